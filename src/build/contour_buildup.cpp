// Contour-buildup: per atom, the exposed arcs of its SAS circles, and from them the SES
// patches. Atoms are independent (that is what makes it parallel): every circle and every
// probe position is a pure function of its sorted atoms (sas_geometry.hpp), so the atoms
// sharing a vertex agree on it bit for bit without sharing state.
#include "build/contour_buildup.hpp"

#include <algorithm>
#include <cmath>
#include <numbers>
#include <stdexcept>

#include <glm/geometric.hpp>
#include <tbb/blocked_range.h>
#include <tbb/enumerable_thread_specific.h>
#include <tbb/parallel_for.h>

#include "build/neighbour_grid.hpp"
#include "build/sas_geometry.hpp"
#include "build/spherical_region.hpp"

namespace surftrace::build {
namespace {

constexpr double kTwoPi = 2.0 * std::numbers::pi;
// Blocks of atoms are the unit of parallel work and of output order; a fixed size (not
// one derived from the thread count) keeps the patch list identical for any thread count.
constexpr std::size_t kBlock = 64;

// Per-block output, concatenated in block order.
struct BlockPatches {
  ConvexSpheres convex;
  Tori tori;
  ConcaveTriangles concave;
};

// One crossing of a circle with a third atom's extended sphere that is an SAS vertex.
struct Crossing {
  double phi;
  bool leaves;  // moving with increasing φ, the circle leaves the sphere here
  std::uint32_t third;
  bool plus;
  glm::dvec3 position;
};

struct Scratch {
  std::vector<std::uint32_t> neighbours, common;
  std::vector<Crossing> crossings;
  std::vector<Cap> caps;
  SphericalRegionScratch region;
};

// Neighbour lists in compressed rows: row i lists, ascending, every j whose extended
// sphere cuts atom i's (|c_i − c_j| < R_i + R_j).
struct NeighbourRows {
  std::vector<std::uint32_t> begin;  // n + 1
  std::vector<std::uint32_t> index;
  std::span<const std::uint32_t> row(std::size_t i) const {
    return {index.data() + begin[i], index.data() + begin[i + 1]};
  }
};

NeighbourRows neighbourRows(const NeighbourGrid& grid, std::size_t n, tbb::enumerable_thread_specific<Scratch>& tls) {
  NeighbourRows rows;
  rows.begin.assign(n + 1, 0);
  tbb::parallel_for(tbb::blocked_range<std::size_t>(0, n, kBlock), [&](const auto& range) {
    auto& s = tls.local();
    for (std::size_t i = range.begin(); i != range.end(); ++i) {
      s.neighbours.clear();
      grid.neighbours(static_cast<std::uint32_t>(i), s.neighbours);
      rows.begin[i + 1] = static_cast<std::uint32_t>(s.neighbours.size());
    }
  });
  for (std::size_t i = 0; i < n; ++i) rows.begin[i + 1] += rows.begin[i];
  rows.index.resize(rows.begin[n]);
  tbb::parallel_for(tbb::blocked_range<std::size_t>(0, n, kBlock), [&](const auto& range) {
    auto& s = tls.local();
    for (std::size_t i = range.begin(); i != range.end(); ++i) {
      s.neighbours.clear();
      grid.neighbours(static_cast<std::uint32_t>(i), s.neighbours);
      std::copy(s.neighbours.begin(), s.neighbours.end(), rows.index.begin() + rows.begin[i]);
    }
  });
  return rows;
}

// An atom whose extended sphere lies inside another's contributes nothing to the SAS or
// the SES. Identical atoms: the lowest index survives (ORACLES E.1, E.2).
bool isBuriedByContainment(std::uint32_t i, std::span<const std::uint32_t> row, std::span<const glm::dvec3> c,
                           std::span<const double> R) {
  for (const std::uint32_t j : row) {
    const double d = glm::distance(c[i], c[j]);
    if (d + R[i] < R[j]) return true;
    if (d + R[i] == R[j] && !(d == 0.0 && j > i)) return true;
  }
  return false;
}

void pushTorus(Tori& t, const SasCircle& circle, double phi0, double extent, std::uint32_t i, std::uint32_t j) {
  t.center.push_back(circle.center);
  t.axis.push_back(circle.axis);
  t.e1.push_back(std::cos(phi0) * circle.e1 + std::sin(phi0) * circle.e2);
  t.bigRadius.push_back(circle.radius);
  t.thetaI.push_back(std::atan2(-circle.t, circle.radius));
  t.thetaJ.push_back(std::atan2(circle.distance - circle.t, circle.radius));
  t.phiExtent.push_back(extent);
  t.atomI.push_back(i);
  t.atomJ.push_back(j);
  t.component.push_back(0);
}

template <class T> void append(std::vector<T>& to, const std::vector<T>& from) {
  to.insert(to.end(), from.begin(), from.end());
}

}  // namespace

PatchList buildSes(std::span<const glm::dvec3> centers, std::span<const double> radii, const SesParams& params) {
  const double rp = params.probeRadius;
  if (!std::isfinite(rp) || !(rp > 0.0))
    throw std::invalid_argument("probe radius must be finite and > 0, got " + std::to_string(rp));
  if (centers.size() != radii.size()) throw std::invalid_argument("centers and radii differ in length");
  const std::size_t n = centers.size();

  PatchList out;
  out.params.surface = SurfaceKind::Ses;
  out.params.probeRadius = rp;
  out.params.atomCount = static_cast<std::uint32_t>(n);
  out.componentCount = n > 0 ? 1 : 0;
  if (n == 0) return out;

  std::vector<double> R(n);
  for (std::size_t i = 0; i < n; ++i) R[i] = radii[i] + rp;

  NeighbourGrid grid(n);
  grid.build(centers, radii, rp);
  tbb::enumerable_thread_specific<Scratch> tls;
  const NeighbourRows rows = neighbourRows(grid, n, tls);

  std::vector<char> buried(n);
  tbb::parallel_for(tbb::blocked_range<std::size_t>(0, n, kBlock), [&](const auto& range) {
    for (std::size_t i = range.begin(); i != range.end(); ++i)
      buried[i] = isBuriedByContainment(static_cast<std::uint32_t>(i), rows.row(i), centers, R);
  });

  const std::size_t blocks = (n + kBlock - 1) / kBlock;
  std::vector<BlockPatches> blockOut(blocks);
  tbb::parallel_for(std::size_t{0}, blocks, [&](std::size_t b) {
    auto& s = tls.local();
    auto& bo = blockOut[b];
    for (std::size_t xi = b * kBlock; xi < std::min(n, (b + 1) * kBlock); ++xi) {
      if (buried[xi]) continue;
      const auto x = static_cast<std::uint32_t>(xi);
      const auto row = rows.row(x);

      // Convex patch: the atom's sphere minus the caps cut by its neighbours.
      s.caps.clear();
      for (const std::uint32_t j : row) {
        if (buried[j]) continue;
        const double d = glm::distance(centers[x], centers[j]);
        const double t = (d * d + R[x] * R[x] - R[j] * R[j]) / (2.0 * d);
        s.caps.push_back({(centers[j] - centers[x]) / d, t / R[x]});
      }
      const SphericalRegion region = sphereMinusCaps(s.caps, s.region);
      if (region.boundaryCycles > 0 || region.area > 0.0) {
        bo.convex.center.push_back(centers[x]);
        bo.convex.radius.push_back(radii[x]);
        bo.convex.atom.push_back(x);
        bo.convex.component.push_back(0);
        bo.convex.area.push_back(radii[x] * radii[x] * region.area);
        bo.convex.vectorArea.push_back(region.vectorArea);
      }

      // Tori and concave triangles of the circles (x, j), j > x.
      for (const std::uint32_t j : row) {
        if (j < x || buried[j]) continue;
        const auto circle = sasCircle(centers[x], R[x], centers[j], R[j]);
        if (!circle) continue;
        const auto rowJ = rows.row(j);
        s.common.clear();
        std::set_intersection(row.begin(), row.end(), rowJ.begin(), rowJ.end(), std::back_inserter(s.common));
        std::erase_if(s.common, [&](std::uint32_t k) { return buried[k] != 0; });

        s.crossings.clear();
        bool circleBuried = false, crossed = false;
        for (const std::uint32_t k : s.common) {
          std::uint32_t t3[3] = {x, j, k};
          std::sort(t3, t3 + 3);
          const auto probes = probePositions(centers[t3[0]], R[t3[0]], centers[t3[1]], R[t3[1]], centers[t3[2]], R[t3[2]]);
          if (!probes) {
            // No crossing: the circle is wholly inside or wholly outside sphere k.
            const glm::dvec3 onCircle = circle->center + circle->radius * circle->e1;
            const glm::dvec3 v = onCircle - centers[k];
            if (glm::dot(v, v) < R[k] * R[k]) {
              circleBuried = true;
              break;
            }
            continue;
          }
          crossed = true;
          const bool plusLeaves = plusLeavesSphere(x, j, k);
          for (const bool plus : {true, false}) {
            const glm::dvec3& p = plus ? probes->plus : probes->minus;
            const bool inside = std::any_of(s.common.begin(), s.common.end(), [&](std::uint32_t m) {
              if (m == k) return false;
              const glm::dvec3 v = p - centers[m];
              return glm::dot(v, v) < R[m] * R[m];
            });
            if (inside) continue;
            const glm::dvec3 w = p - circle->center;
            s.crossings.push_back({std::atan2(glm::dot(w, circle->e2), glm::dot(w, circle->e1)), plus == plusLeaves, k,
                                   plus, p});
          }
        }
        if (circleBuried) continue;
        if (!crossed) {
          pushTorus(bo.tori, *circle, 0.0, kTwoPi, x, j);
          continue;
        }
        std::sort(s.crossings.begin(), s.crossings.end(), [](const Crossing& a, const Crossing& c) {
          if (a.phi != c.phi) return a.phi < c.phi;
          if (a.third != c.third) return a.third < c.third;
          return a.plus > c.plus;
        });

        // Exposed arcs run from a crossing that leaves a sphere to the next that enters one.
        const std::size_t count = s.crossings.size();
        const auto firstLeave = std::find_if(s.crossings.begin(), s.crossings.end(), [](const Crossing& c) { return c.leaves; });
        if (firstLeave != s.crossings.end()) {
          const std::size_t start = static_cast<std::size_t>(firstLeave - s.crossings.begin());
          std::size_t pending = count;  // index of an unmatched leaving crossing
          for (std::size_t step = 0; step <= count; ++step) {
            const std::size_t idx = (start + step) % count;
            const Crossing& c = s.crossings[idx];
            if (c.leaves) {
              if (step < count) pending = idx;
            } else if (pending != count) {
              double extent = c.phi - s.crossings[pending].phi;
              if (extent < 0.0) extent += kTwoPi;
              if (extent > 0.0) pushTorus(bo.tori, *circle, s.crossings[pending].phi, extent, x, j);
              pending = count;
            }
          }
        }

        // Each SAS vertex x < j < k is emitted once, from the circle of its two smallest atoms.
        for (const Crossing& c : s.crossings) {
          if (c.third < j) continue;
          const std::uint32_t k = c.third;
          auto& cv = bo.concave;
          cv.probe.push_back(c.position);
          cv.dirI.push_back(glm::normalize(centers[x] - c.position));
          cv.dirJ.push_back(glm::normalize(centers[j] - c.position));
          cv.dirK.push_back(glm::normalize(centers[k] - c.position));
          cv.atomI.push_back(x);
          cv.atomJ.push_back(j);
          cv.atomK.push_back(k);
          cv.component.push_back(0);
        }
      }
    }
  });

  for (const auto& bo : blockOut) {
    append(out.convex.center, bo.convex.center);
    append(out.convex.radius, bo.convex.radius);
    append(out.convex.atom, bo.convex.atom);
    append(out.convex.component, bo.convex.component);
    append(out.convex.area, bo.convex.area);
    append(out.convex.vectorArea, bo.convex.vectorArea);
    append(out.tori.center, bo.tori.center);
    append(out.tori.axis, bo.tori.axis);
    append(out.tori.e1, bo.tori.e1);
    append(out.tori.bigRadius, bo.tori.bigRadius);
    append(out.tori.thetaI, bo.tori.thetaI);
    append(out.tori.thetaJ, bo.tori.thetaJ);
    append(out.tori.phiExtent, bo.tori.phiExtent);
    append(out.tori.atomI, bo.tori.atomI);
    append(out.tori.atomJ, bo.tori.atomJ);
    append(out.tori.component, bo.tori.component);
    append(out.concave.probe, bo.concave.probe);
    append(out.concave.dirI, bo.concave.dirI);
    append(out.concave.dirJ, bo.concave.dirJ);
    append(out.concave.dirK, bo.concave.dirK);
    append(out.concave.atomI, bo.concave.atomI);
    append(out.concave.atomJ, bo.concave.atomJ);
    append(out.concave.atomK, bo.concave.atomK);
    append(out.concave.component, bo.concave.component);
  }
  blockOut.clear();

  // Self-intersections (ORACLES A.5): every pair of probe positions closer than 2 rp cuts
  // both probe spheres along their bisector plane. The probe positions go into a
  // neighbour grid of their own (radius rp each, no probe), whose neighbour relation is
  // exactly |p − q| < 2 rp. No cap on the number of planes per patch.
  auto& cv = out.concave;
  const std::size_t probes = cv.size();
  if (probes > 0) {
    const std::vector<double> probeRadii(probes, rp);
    NeighbourGrid probeGrid(probes);
    probeGrid.build(cv.probe, probeRadii, 0.0);
    std::vector<std::vector<Plane>> planes(probes);
    tbb::parallel_for(tbb::blocked_range<std::size_t>(0, probes, kBlock), [&](const auto& range) {
      auto& s = tls.local();
      for (std::size_t a = range.begin(); a != range.end(); ++a) {
        s.neighbours.clear();
        probeGrid.neighbours(static_cast<std::uint32_t>(a), s.neighbours);
        for (const std::uint32_t b : s.neighbours) {
          const glm::dvec3 v = cv.probe[b] - cv.probe[a];
          const double len = glm::length(v);
          if (!(len > 0.0)) continue;  // coincident probes (cospherical atoms): no plane
          const glm::dvec3 nrm = v / len;
          const glm::dvec3 mid = 0.5 * (cv.probe[a] + cv.probe[b]);
          planes[a].emplace_back(nrm, -glm::dot(nrm, mid));
        }
      }
    });
    cv.clipBegin.resize(probes);
    cv.clipCount.resize(probes);
    for (std::size_t a = 0; a < probes; ++a) {
      cv.clipBegin[a] = static_cast<std::uint32_t>(out.clipPlanes.size());
      cv.clipCount[a] = static_cast<std::uint32_t>(planes[a].size());
      append(out.clipPlanes, planes[a]);
    }
  }
  return out;
}

}  // namespace surftrace::build

// Which atoms can hide part of a whole convex sphere (sphere_blockers.hpp).
#include "build/sphere_blockers.hpp"

#include <algorithm>
#include <cmath>
#include <limits>
#include <numbers>
#include <optional>
#include <stdexcept>
#include <string>
#include <tuple>
#include <unordered_map>
#include <utility>

#include <tbb/parallel_for.h>

#include <glm/common.hpp>
#include <glm/geometric.hpp>

#include "build/core/vector_math.hpp"

namespace surftrace::build {

SphereBlockers sphereBlockers(const SurfaceParams& params, std::span<const glm::dvec3> centers,
                              std::span<const double> radii, std::span<const std::uint32_t> sphereAtoms,
                              std::span<const glm::dvec4> atoms) {
  const std::size_t n = centers.size();
  if (radii.size() != n || sphereAtoms.size() != n)
    throw std::invalid_argument("sphere blockers: " + std::to_string(n) + " sphere centres but " +
                                std::to_string(radii.size()) + " radii and " + std::to_string(sphereAtoms.size()) + " atoms");
  const double rp = params.probeRadius;
  SphereBlockers out;
  out.grow = params.surface == SurfaceKind::Ses ? rp : 0.0;
  std::vector<std::uint32_t> blockerAtom;  // to skip a sphere's own atom
  if (!atoms.empty()) {
    const double h = params.surface == SurfaceKind::Vdw ? 0.0 : rp;
    for (std::uint32_t k = 0; k < atoms.size(); ++k) {
      out.blockers.push_back(glm::dvec4(glm::dvec3(atoms[k]), atoms[k].w + h));
      blockerAtom.push_back(k);
    }
  } else {
    for (std::uint32_t k = 0; k < n; ++k) {
      out.blockers.push_back(glm::dvec4(centers[k], radii[k] + out.grow));
      blockerAtom.push_back(sphereAtoms[k]);
    }
  }
  double largest = 0.0;
  for (double r : radii) largest = std::max(largest, r + out.grow);
  for (const glm::dvec4& b : out.blockers) largest = std::max(largest, b.w);
  out.begin.assign(n + 1, 0);
  if (n == 0) return out;
  // A grid of cell 2·(largest grown radius): grown spheres that meet lie in adjacent cells. The
  // blockers sorted by cell, each cell's a contiguous run (centre, radius and atom beside it),
  // found by binary search: no hashing, no collisions, and the 27 cells' blockers read in order.
  const double cell = std::max(2.0 * largest, 1e-6);
  auto cellOf = [&](const glm::dvec3& c) { return glm::ivec3(glm::floor(c / cell)); };
  auto cellLess = [](const glm::ivec3& x, const glm::ivec3& y) { return std::tie(x.z, x.y, x.x) < std::tie(y.z, y.y, y.x); };
  struct Slot {
    glm::ivec3 cell;
    std::uint32_t blocker;
  };
  std::vector<Slot> slots(out.blockers.size());
  for (std::uint32_t k = 0; k < out.blockers.size(); ++k) slots[k] = {cellOf(glm::dvec3(out.blockers[k])), k};
  std::sort(slots.begin(), slots.end(), [&](const Slot& x, const Slot& y) {
    return cellLess(x.cell, y.cell) || (x.cell == y.cell && x.blocker < y.blocker);
  });
  std::vector<glm::dvec4> slotBlocker(slots.size());
  std::vector<std::uint32_t> slotAtom(slots.size());
  for (std::size_t s = 0; s < slots.size(); ++s) {
    slotBlocker[s] = out.blockers[slots[s].blocker];
    slotAtom[s] = blockerAtom[slots[s].blocker];
  }
  // Candidates of one sphere: the blocker and its gap (centre distance minus grown radius).
  std::vector<std::pair<double, std::uint32_t>> near;
  for (std::uint32_t i = 0; i < n; ++i) {
    const glm::dvec3 c = centers[i];
    const glm::ivec3 k = cellOf(c);
    near.clear();
    for (int dz = -1; dz <= 1; ++dz)
      for (int dy = -1; dy <= 1; ++dy) {
        // The three cells (x − 1, x, x + 1) of one row are adjacent in the sorted order.
        const glm::ivec3 first = k + glm::ivec3(-1, dy, dz), last = k + glm::ivec3(1, dy, dz);
        auto lo = std::lower_bound(slots.begin(), slots.end(), first,
                                   [&](const Slot& x, const glm::ivec3& y) { return cellLess(x.cell, y); });
        for (auto it = lo; it != slots.end() && !cellLess(last, it->cell); ++it) {
          const std::size_t s = static_cast<std::size_t>(it - slots.begin());
          const glm::dvec3 cj(slotBlocker[s]);
          if (slotAtom[s] == sphereAtoms[i]) continue;  // its own atom
          if (glm::length(cj - c) < radii[i] + out.grow + slotBlocker[s].w)
            near.emplace_back(glm::length(cj - c) - slotBlocker[s].w, it->blocker);
        }
      }
    // Nearest first: the blocker that hides a point is most often a close one, and the test
    // stops at the first. Ties by index keep the order deterministic (whatever the cells' order).
    std::sort(near.begin(), near.end());
    for (const auto& [gap, j] : near) out.list.push_back(j);
    out.begin[i + 1] = static_cast<std::uint32_t>(out.list.size());
  }
  return out;
}

namespace {

// A blocker's circle on the grown sphere (centre c, radius G): the direction n from c towards
// the blocker (centre, grown radius) and h, the cosine of the circle's polar angle about n (law
// of cosines; |h| >= 1 where the spheres do not cross). None when the blocker's centre is c.
struct BlockerCircle {
  glm::dvec3 n;
  double h;
};
std::optional<BlockerCircle> blockerCircle(const glm::dvec4& blocker, const glm::dvec3& c, double G) {
  const glm::dvec3 axis = glm::dvec3(blocker) - c;
  const double D = glm::length(axis);
  if (!(D > 0.0)) return std::nullopt;
  return BlockerCircle{axis / D, (D * D + G * G - blocker.w * blocker.w) / (2.0 * D * G)};
}

// Distance from the point p to the arc a.
double distanceToArc(const SaddleArc& a, const glm::dvec3& p) {
  const glm::dvec3 q = p - a.center;
  double phi = std::atan2(glm::dot(q, a.e2), glm::dot(q, a.e1));
  if (phi < 0.0) phi += 2.0 * std::numbers::pi;
  auto at = [&](double f) { return a.center + a.radius * (std::cos(f) * a.e1 + std::sin(f) * a.e2); };
  if (phi <= a.extent) return glm::length(p - at(phi));
  return std::min(glm::length(p - at(0.0)), glm::length(p - at(a.extent)));
}

// distanceToArc(a, p) < tolerance, skipping the trigonometry where p is farther than that from
// the arc's whole circle: every point of the circle is at least ||p − centre| − radius| from p,
// a bound that is taken as conclusive only when it exceeds the tolerance by far more than the
// rounding of either side.
bool nearArc(const SaddleArc& a, const glm::dvec3& p, double tolerance) {
  if (std::abs(glm::length(p - a.center) - a.radius) > 2.0 * tolerance) return false;
  return distanceToArc(a, p) < tolerance;
}

// Whether every edge of the free part of grown sphere i (centre c, radius G) lies on one of its
// saddle arcs: each blocker's circle minus the other blockers' caps is a set of intervals, the
// edges (an edge of the list is one saddle's whole arc, from one concave triangle to the next),
// and each edge's middle point must be on an arc. A sphere whose atom has no arc counts as
// covered (it is kept whole).
bool edgeCovered(const SphereBlockers& b, std::uint32_t i, const glm::dvec3& c, double G) {
  if (b.arcBegin[i] == b.arcBegin[i + 1]) return true;
  constexpr double kTwoPi = 2.0 * std::numbers::pi;
  // Each blocker's cap on the grown sphere: direction n, cos of its angular radius h.
  std::vector<BlockerCircle> circles;
  for (std::uint32_t k = b.begin[i]; k < b.begin[i + 1]; ++k) {
    const std::optional<BlockerCircle> circle = blockerCircle(b.blockers[b.list[k]], c, G);
    if (!circle) continue;
    if (circle->h <= -1.0) return true;  // a blocker hides the whole sphere: no edge (not drawn)
    if (circle->h < 1.0) circles.push_back(*circle);
  }
  struct Interval {
    double lo, hi;
  };
  std::vector<Interval> covered, gaps;
  // A cap j that cuts circle k: cos(ψ − ψj) > rest/M there, with (A, B) = M/sk (cos ψj, sin ψj).
  struct Cut {
    double A, B, rest, M;
  };
  std::vector<Cut> cuts;
  for (std::size_t k = 0; k < circles.size(); ++k) {
    const glm::dvec3 n = circles[k].n;
    const double h = circles[k].h, sk = std::sqrt(1.0 - h * h);
    const glm::dvec3 u = glm::normalize(glm::cross(n, std::abs(n.x) < 0.9 ? glm::dvec3(1, 0, 0) : glm::dvec3(0, 1, 0)));
    const glm::dvec3 v = glm::cross(n, u);
    // The circle u(ψ) = h n + sk (cos ψ u + sin ψ v) lies in cap j where n_j·u(ψ) > h_j, i.e.
    // where cos(ψ − ψj) > q = (h_j − h n_j·n) / (sk |(n_j·u, n_j·v)|).
    // First, without trigonometry: is the whole circle in one cap (most buried atoms' are)? The
    // same pass keeps the caps that cut the circle, whose arcs the trigonometry below needs.
    bool all = false;
    cuts.clear();
    for (std::size_t j = 0; j < circles.size() && !all; ++j) {
      if (j == k) continue;
      const glm::dvec3 nj = circles[j].n;
      const double A = glm::dot(nj, u), B = glm::dot(nj, v);
      const double rest = circles[j].h - h * glm::dot(nj, n);
      // Most caps lie clear of the circle (rest >= M, below): the square root is needed only
      // where rest² does not exceed M² by far more than the rounding of either side.
      if (rest > 0.0 && rest * rest > (sk * sk) * (A * A + B * B) * (1.0 + 1e-12)) continue;
      const double M = sk * std::sqrt(A * A + B * B);
      if (rest <= -M) all = true;  // q <= -1: the whole circle is in cap j
      else if (rest < M) cuts.push_back({A, B, rest, M});  // else q >= 1: the circle misses cap j (or only touches it)
    }
    if (all) continue;
    covered.clear();
    for (const Cut& cut : cuts) {
      const double A = cut.A, B = cut.B, M = cut.M, rest = cut.rest;
      const double mid = std::atan2(B, A), half = std::acos(rest / M);
      double lo = mid - half;
      lo -= kTwoPi * std::floor(lo / kTwoPi);
      if (lo + 2.0 * half <= kTwoPi) {
        covered.push_back({lo, lo + 2.0 * half});
      } else {
        covered.push_back({lo, kTwoPi});
        covered.push_back({0.0, lo + 2.0 * half - kTwoPi});
      }
    }
    std::sort(covered.begin(), covered.end(), [](const Interval& x, const Interval& y) { return x.lo < y.lo; });
    // The gaps between the merged intervals, around the circle, are the edges on this circle.
    gaps.clear();
    double reach = 0.0;
    for (const Interval& x : covered) {
      if (x.lo > reach) gaps.push_back({reach, x.lo});
      reach = std::max(reach, x.hi);
    }
    if (reach < kTwoPi) gaps.push_back({reach, kTwoPi});
    // A gap at both ends of [0, 2π) is one edge through ψ = 0.
    if (gaps.size() >= 2 && gaps.front().lo == 0.0 && gaps.back().hi == kTwoPi) {
      gaps.front().lo = gaps.back().lo - kTwoPi;
      gaps.pop_back();
    }
    for (const Interval& g : gaps) {
      const double psi = 0.5 * (g.lo + g.hi);
      const glm::dvec3 p = c + G * (h * n + sk * (std::cos(psi) * u + std::sin(psi) * v));
      bool on = false;
      for (std::uint32_t a = b.arcBegin[i]; a < b.arcBegin[i + 1] && !on; ++a) on = nearArc(b.arcs[a], p, 1e-4 * G);
      if (!on) return false;
    }
  }
  return true;
}

}  // namespace

SphereBlockers sphereBlockers(const PatchList& list, std::span<const glm::dvec4> atoms) {
  SphereBlockers b = sphereBlockers(list.params, list.convex.center, list.convex.radius, list.convex.atom, atoms);
  if (list.params.surface != SurfaceKind::Ses || atoms.empty()) return b;
  std::vector<SaddleArc> arcs;
  std::vector<glm::uvec2> arcAtoms;
  for (std::size_t t = 0; t < list.tori.size(); ++t) {
    const glm::dvec3 e1 = list.tori.e1[t];
    arcs.push_back({list.tori.center[t], e1, glm::cross(list.tori.axis[t], e1), list.tori.bigRadius[t], list.tori.phiExtent[t]});
    arcAtoms.push_back({list.tori.atomI[t], list.tori.atomJ[t]});
  }
  addSaddleArcs(b, list.convex.center, list.convex.radius, list.convex.atom, arcs, arcAtoms);
  return b;
}

void attachSaddleArcs(SphereBlockers& b, std::span<const std::uint32_t> sphereAtoms, std::span<const SaddleArc> arcs,
                      std::span<const glm::uvec2> arcAtoms) {
  // Atom -> its sphere (the list has at most one per atom), then a counting sort of the arcs.
  std::unordered_map<std::uint32_t, std::uint32_t> sphereOf;
  for (std::uint32_t i = 0; i < sphereAtoms.size(); ++i) sphereOf.emplace(sphereAtoms[i], i);
  std::vector<std::uint32_t> count(sphereAtoms.size() + 1, 0);
  auto forEachSphere = [&](std::size_t t, auto&& f) {
    for (const std::uint32_t atom : {arcAtoms[t].x, arcAtoms[t].y})
      if (const auto it = sphereOf.find(atom); it != sphereOf.end()) f(it->second);
  };
  for (std::size_t t = 0; t < arcs.size(); ++t) forEachSphere(t, [&](std::uint32_t i) { ++count[i + 1]; });
  b.arcBegin.assign(sphereAtoms.size() + 1, 0);
  for (std::size_t i = 0; i < sphereAtoms.size(); ++i) b.arcBegin[i + 1] = b.arcBegin[i] + count[i + 1];
  b.arcs.resize(b.arcBegin.back());
  std::vector<std::uint32_t> next(b.arcBegin.begin(), b.arcBegin.end() - 1);
  for (std::size_t t = 0; t < arcs.size(); ++t) forEachSphere(t, [&](std::uint32_t i) { b.arcs[next[i]++] = arcs[t]; });
}

bool freeEdgeCovered(const SphereBlockers& b, std::uint32_t i, const glm::dvec3& c, double grown) {
  return edgeCovered(b, i, c, grown);
}

void addSaddleArcs(SphereBlockers& b, std::span<const glm::dvec3> centers, std::span<const double> radii,
                   std::span<const std::uint32_t> sphereAtoms, std::span<const SaddleArc> arcs,
                   std::span<const glm::uvec2> arcAtoms) {
  attachSaddleArcs(b, sphereAtoms, arcs, arcAtoms);
  // The test costs a pass over the blockers per hit: keep the arcs of the spheres whose edge
  // they leave partly open alone (those --drop-cavities cut), none when no sphere has one.
  // The spheres are independent (an O(n²) pass over each one's blockers): in parallel.
  std::vector<char> covered(sphereAtoms.size());
  tbb::parallel_for(std::size_t{0}, sphereAtoms.size(), [&](std::size_t i) {
    covered[i] = edgeCovered(b, static_cast<std::uint32_t>(i), centers[i], radii[i] + b.grow);
  });
  std::vector<SaddleArc> open;
  std::vector<std::uint32_t> openBegin(sphereAtoms.size() + 1, 0);
  for (std::uint32_t i = 0; i < sphereAtoms.size(); ++i) {
    if (!covered[i]) open.insert(open.end(), b.arcs.begin() + b.arcBegin[i], b.arcs.begin() + b.arcBegin[i + 1]);
    openBegin[i + 1] = static_cast<std::uint32_t>(open.size());
  }
  b.arcs = std::move(open);
  b.arcBegin = std::move(openBegin);
  if (b.arcs.empty()) b.arcBegin.clear();
}

namespace {

// Whether the point y of the free part of grown sphere i (centre c, radius G) lies on a part
// that a saddle arc of the list bounds (onConvexPatch).
bool onKeptPart(const SphereBlockers& b, std::uint32_t i, const glm::dvec3& c, double G, const glm::dvec3& y) {
  if (b.arcBegin.empty() || b.arcBegin[i] == b.arcBegin[i + 1]) return true;
  // The nearest blocker circle, by the angle between y's polar angle about the blocker's
  // direction and the circle's.
  const glm::dvec3 u = (y - c) / G;
  double best = std::numeric_limits<double>::infinity();
  glm::dvec3 edge(0.0);
  for (std::uint32_t k = b.begin[i]; k < b.begin[i + 1]; ++k) {
    const std::optional<BlockerCircle> circle = blockerCircle(b.blockers[b.list[k]], c, G);
    if (!circle) continue;
    const glm::dvec3 n = circle->n;
    const double h = circle->h;
    if (!(std::abs(h) < 1.0)) continue;
    const double cosAlpha = glm::clamp(glm::dot(n, u), -1.0, 1.0);
    const double gap = std::abs(std::acos(cosAlpha) - std::acos(h));
    if (!(gap < best)) continue;
    const glm::dvec3 side = u - cosAlpha * n;
    const double s = glm::length(side);
    if (!(s > 1e-12)) return true;  // y on a blocker's axis: every point of its circle is as near
    best = gap;
    edge = c + G * (h * n + std::sqrt(1.0 - h * h) * (side / s));
  }
  if (!std::isfinite(best)) return true;
  // The list's arcs pass through its edge points to rounding; 1e-4 G also covers atoms merged
  // within 1e-5 Å (atom_culling.hpp), whose circles and arcs are that far apart.
  for (std::uint32_t a = b.arcBegin[i]; a < b.arcBegin[i + 1]; ++a)
    if (nearArc(b.arcs[a], edge, 1e-4 * G)) return true;
  return false;
}

}  // namespace

bool onConvexPatch(const SphereBlockers& b, std::uint32_t i, const glm::dvec3& c, double rho, const glm::dvec3& x,
                   double tolerance, bool keptPartTest) {
  if (!(rho > 0.0)) return true;
  const glm::dvec3 y = c + ((rho + b.grow) / rho) * (x - c);
  for (std::uint32_t k = b.begin[i]; k < b.begin[i + 1]; ++k) {
    const glm::dvec4 o = b.blockers[b.list[k]];
    const glm::dvec3 d = y - glm::dvec3(o);
    const double reach = o.w * (1.0 - tolerance);
    // Clear of the blocker by far more than the rounding of either side: no square root.
    if (glm::dot(d, d) > (reach * reach) * (1.0 + 1e-12)) continue;
    if (glm::length(d) < reach) return false;
  }
  return !keptPartTest || onKeptPart(b, i, c, rho + b.grow, y);
}

double convexPatchEdgeDistance(const SphereBlockers& b, std::uint32_t i, const glm::dvec3& c, double rho,
                               const glm::dvec3& x) {
  double d = std::numeric_limits<double>::infinity();
  if (!(rho > 0.0)) return d;
  const double grown = rho + b.grow;
  for (std::uint32_t k = b.begin[i]; k < b.begin[i + 1]; ++k) {
    // The circle of the grown spheres is at polar angle acos(h) about the axis towards the
    // blocker, on sphere i as on the grown sphere (y − c ∥ x − c).
    const std::optional<BlockerCircle> circle = blockerCircle(b.blockers[b.list[k]], c, grown);
    if (circle) d = std::min(d, distanceToSphereCircle(c, rho, x, circle->n, circle->h));
  }
  return d;
}

}  // namespace surftrace::build

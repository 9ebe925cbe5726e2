// MSS patches: feasible power cells (power_cell.hpp), their faces, edges and vertices as
// Delaunay edges, triangles and tetrahedra, and the mixed cells' planes (skin_geometry.hpp).
#include "build/mss/mss_builder.hpp"

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdio>
#include <cstring>
#include <functional>
#include <limits>
#include <stdexcept>
#include <string>
#include <utility>
#include <vector>

#include <glm/geometric.hpp>
#include <tbb/enumerable_thread_specific.h>
#include <tbb/parallel_for.h>

#include "build/mss/power_cell.hpp"
#include "build/mss/skin_geometry.hpp"
#include "build/moved_atoms.hpp"
#include "build/neighbour_grid.hpp"

namespace surftrace::build {
namespace {

using mss::CellPlane;
using mss::kBoxPlane;
using mss::PowerCell;
using mss::Simplex;
using mss::WeightedPoints;

// Atoms per block: the unit of parallel work and of partial updates. Fixed, so the result
// does not depend on the number of threads.
constexpr std::uint32_t kBlockAtoms = 16;
// Relative slack on the feasibility radius and the reach: the neighbourhood stays a superset
// whatever the rounding of the distances that select it.
constexpr double kReachSlack = 1e-9;

// One block's patches of one kind (the MSS arrays of a patch list), with cell-plane indices
// relative to the chunk. The list is the chunks kind by kind, block by block.
using Chunk = PatchList;

bool isMssGroup(const char* group) { return std::strcmp(group, "mss") == 0 || std::strcmp(group, "cellPlanes") == 0; }

// A Delaunay simplex owned by the current atom whose mixed cell holds skin, with the atoms
// a of its cofaces X ∪ {a} (the facets on the Voronoi side) in ups[upBegin, upBegin + upCount).
struct Element {
  Simplex x;
  std::uint32_t upBegin, upCount;
};

// A neighbour whose power plane comes within ρ_i: the plane's distance from the atom and
// its unit normal. Ordered by distance, then atom.
struct Candidate {
  double dist;
  std::uint32_t atom;
  glm::dvec3 unit;

  bool operator<(const Candidate& o) const { return dist < o.dist || (dist == o.dist && atom < o.atom); }
};

struct Scratch {
  PowerCell cell;
  std::vector<std::uint32_t> near;
  std::vector<Candidate> candidates;
  std::vector<Element> elements;
  std::vector<std::uint32_t> ups;
};

struct Geometry {
  WeightedPoints points;
  double wMax = 0.0;
  std::vector<double> rho;    // feasibility radius ρ_i (with slack), times feasibleScale
  std::vector<double> rho2;   // ρ_i² (with slack) without feasibleScale: where skin can be
  std::vector<double> reach;  // neighbour reach ρ_i + √(ρ_i² + w_max − w_i) (with slack)
};

double pointSegmentDistance2(const glm::dvec3& x, const glm::dvec3& a, const glm::dvec3& b) {
  const glm::dvec3 ab = b - a;
  const double len2 = glm::dot(ab, ab);
  const double t = len2 > 0.0 ? std::clamp(glm::dot(x - a, ab) / len2, 0.0, 1.0) : 0.0;
  const glm::dvec3 d = x - (a + t * ab);
  return glm::dot(d, d);
}

// Squared distance from x to the polygon of face k of the cell (local coordinates).
double polygonDistance2(const PowerCell& cell, std::size_t k, const glm::dvec3& x) {
  const std::span<const std::uint16_t> poly = cell.face(k);
  const std::span<const mss::CellVertex> verts = cell.vertices();
  const glm::dvec3 n = glm::normalize(cell.planes()[k].n);
  bool inside = true;
  double best = std::numeric_limits<double>::infinity();
  for (std::size_t q = 0; q < poly.size(); ++q) {
    const glm::dvec3 pa = verts[poly[q]].p, pb = verts[poly[(q + 1) % poly.size()]].p;
    best = std::min(best, pointSegmentDistance2(x, pa, pb));
    if (glm::dot(x - pa, glm::cross(pb - pa, n)) > 0.0) inside = false;
  }
  if (!inside) return best;
  const double h = glm::dot(x - verts[poly[0]].p, n);
  return h * h;
}

// Lower bound on d(z_X, δ_X): the largest distance of z_X beyond one of δ_X's facets
// (exact for a segment; 0 inside).
double distanceToSimplex(const WeightedPoints& p, const Simplex& x, const glm::dvec3& zX) {
  double out = 0.0;
  if (x.size < 2) return 0.0;
  for (int k = 0; k < x.size; ++k) {
    const Simplex facet = x.without(k);
    const glm::dvec3 n = mss::facetNormal(p, facet, x[k]);
    out = std::max(out, -glm::dot(n, zX - p.z[facet[0]]));
  }
  return out;
}

// Whether the skin quadric of X meets μ_X = (1 − s) δ_X + s ν_X: the skin function scaled,
// g = s|v'|² − (1 − s)|u'|² + w_X over u' ∈ δ_X − z_X and v' ∈ ν_X − z_X (independent, the
// two are orthogonal), takes the value 0. distNu and maxNu2 bound |v'| from below and above.
bool holdsSkin(const WeightedPoints& p, const Simplex& x, const mss::Orthocentre& o, double distNu, double maxNu2) {
  double wMax = p.w[x[0]];
  for (int k = 1; k < x.size; ++k) wMax = std::max(wMax, p.w[x[k]]);
  const double s = p.s;
  const double distDelta = distanceToSimplex(p, x, o.z);
  const double minG = s * distNu * distNu - (1.0 - s) * (o.w + wMax) + o.w;
  const double maxG = s * maxNu2 - (1.0 - s) * distDelta * distDelta + o.w;
  const double tol = 1e-9 * (wMax + std::abs(o.w));
  return minG <= tol && maxG >= -tol;
}

void emitPatch(const WeightedPoints& p, const Simplex& x, std::span<const std::uint32_t> ups, Chunk& chunk) {
  MssQuadrics& out = chunk.mss;
  const mss::SkinPatch patch = mss::skinPatch(p, x);
  const mss::SkinQuadric& q = patch.quadric;
  const double bound = patch.boundRadius;
  std::vector<Plane>& planes = chunk.cellPlanes;
  const auto begin = static_cast<std::uint32_t>(planes.size());
  // A plane is kept unless the whole ball of the patch's skin lies on its inner side. Each
  // plane keeps the atom across it, from which the file derives it again (mss::cellPlane).
  const double cull = -(bound * (1.0 + 1e-9) + 1e-12);
  auto keep = [&](std::uint32_t a) {
    const glm::dvec4 plane = mss::cellPlane(p, x, q.center, a);
    if (glm::dot(glm::dvec3(plane), q.center) + plane.w >= cull) {
      planes.push_back(plane);
      chunk.cellPlaneAtom.push_back(a);
    }
  };
  for (int k = 0; x.size >= 2 && k < x.size; ++k) keep(x[k]);
  for (std::uint32_t a : ups) keep(a);
  glm::uvec4 atoms(~0u);
  for (int k = 0; k < x.size; ++k) atoms[k] = x[k];
  out.kind.push_back(static_cast<std::uint32_t>(x.size - 1));
  out.center.push_back(q.center);
  out.axis.push_back(q.axis);
  out.radialCoeff.push_back(q.radial);
  out.axialCoeff.push_back(q.axial);
  out.constant.push_back(q.constant);
  out.boundRadius.push_back(bound);
  out.atoms.push_back(atoms);
  out.cellBegin.push_back(begin);
  out.cellCount.push_back(static_cast<std::uint32_t>(planes.size()) - begin);
}

bool isAtom(const CellPlane& plane) { return plane.atom < kBoxPlane; }

// The patches owned by atom i (every simplex whose lowest atom is i), appended to `out`.
void atomPatches(const Geometry& g, const NeighbourGrid& grid, std::uint32_t i, Scratch& sc, Chunk* byKind) {
  const WeightedPoints& p = g.points;
  const glm::dvec3 zi = p.z[i];
  const double wi = p.w[i];

  // The neighbours whose power plane comes within ρ_i, nearest plane first (sorted below by
  // distance, then atom: the grid's order does not matter).
  sc.near.clear();
  grid.atomsNearUnordered(zi, g.reach[i], sc.near);
  sc.candidates.clear();
  for (std::uint32_t j : sc.near) {
    if (j == i) continue;
    const glm::dvec3 d = p.z[j] - zi;
    const double dd = glm::dot(d, d);
    if (dd == 0.0) {
      // Same centre: the larger weight (then, by the perturbation, the lower index) owns it all.
      if (p.w[j] > wi || (p.w[j] == wi && j < i)) return;
      continue;
    }
    const double dist = (dd - p.w[j] + wi) / (2.0 * std::sqrt(dd));
    if (dist < g.rho[i]) sc.candidates.push_back({dist, j, d / std::sqrt(dd)});
  }
  std::sort(sc.candidates.begin(), sc.candidates.end());

  PowerCell& cell = sc.cell;
  cell.reset(p, i, g.rho[i] * 1.0625);
  for (const Candidate& c : sc.candidates) {
    // Sorted by distance: once a plane lies beyond every vertex, so do the rest.
    if (c.dist > 0.0 && c.dist * c.dist > cell.maxVertexNorm2() * (1.0 + 1e-6)) break;
    if (cell.surelyRedundant(c.unit, c.dist)) continue;
    if (cell.clip(c.atom) == PowerCell::Clip::Empty) return;
  }

  // Only the part of the cell within ρ_i can bound skin (and only it is exact): a coface's
  // facet plane is kept when its Voronoi element comes that close, so a wider neighbourhood
  // (feasibleScale) changes nothing.
  const double rho2 = g.rho2[i];
  const std::span<const CellPlane> planes = cell.planes();
  const std::span<const mss::CellVertex> verts = cell.vertices();
  sc.elements.clear();
  sc.ups.clear();
  auto addElement = [&](const Simplex& x, std::size_t upBegin) {
    sc.elements.push_back({x, static_cast<std::uint32_t>(upBegin), static_cast<std::uint32_t>(sc.ups.size() - upBegin)});
  };

  // The vertex {i}: the sphere of radius r_i in the scaled cell.
  {
    const std::size_t upBegin = sc.ups.size();
    double distNu = 0.0;
    for (std::size_t k = 0; k < planes.size(); ++k) {
      if (!isAtom(planes[k]) || cell.face(k).empty()) continue;
      if (polygonDistance2(cell, k, glm::dvec3(0.0)) <= rho2) sc.ups.push_back(planes[k].atom);
      distNu = std::max(distNu, -planes[k].c / glm::length(planes[k].n));
    }
    Simplex x;
    x.atom[0] = i;
    x.size = 1;
    if (holdsSkin(p, x, {zi, -wi}, distNu, cell.maxVertexNorm2()))
      addElement(x, upBegin);
    else
      sc.ups.resize(upBegin);
  }

  for (std::size_t k = 0; k < planes.size(); ++k) {
    const std::span<const std::uint16_t> poly = cell.face(k);
    if (!isAtom(planes[k]) || poly.empty() || planes[k].atom < i) continue;
    const std::uint32_t j = planes[k].atom;
    const glm::dvec3 t = glm::normalize(planes[k].n);

    // The Delaunay edge {i, j}: the Voronoi face is the polygon.
    {
      Simplex x;
      x.atom[0] = i;
      x.atom[1] = j;
      x.size = 2;
      const mss::Orthocentre o = mss::orthocentre(p, x);
      const glm::dvec3 xo = o.z - zi;
      const std::size_t upBegin = sc.ups.size();
      bool inside = true;
      double dist2 = std::numeric_limits<double>::infinity(), maxNu2 = 0.0;
      for (std::size_t q = 0; q < poly.size(); ++q) {
        const std::uint16_t a = poly[q], b = poly[(q + 1) % poly.size()];
        const glm::dvec3 pa = verts[a].p, pb = verts[b].p;
        maxNu2 = std::max(maxNu2, glm::dot(pa - xo, pa - xo));
        dist2 = std::min(dist2, pointSegmentDistance2(xo, pa, pb));
        if (glm::dot(xo - pa, glm::cross(pb - pa, t)) > 0.0) inside = false;
        const CellPlane& across = planes[cell.edgeNeighbour(static_cast<std::uint16_t>(k), a, b)];
        if (isAtom(across) && pointSegmentDistance2(glm::dvec3(0.0), pa, pb) <= rho2) sc.ups.push_back(across.atom);
      }
      if (holdsSkin(p, x, o, inside ? 0.0 : std::sqrt(dist2), maxNu2))
        addElement(x, upBegin);
      else
        sc.ups.resize(upBegin);
    }

    // The Delaunay triangles {i, j, m}, m > j: the polyhedron's edges between faces j and m.
    for (std::size_t q = 0; q < poly.size(); ++q) {
      const std::uint16_t a = poly[q], b = poly[(q + 1) % poly.size()];
      const std::uint16_t across = cell.edgeNeighbour(static_cast<std::uint16_t>(k), a, b);
      if (!isAtom(planes[across]) || planes[across].atom < j) continue;
      Simplex x;
      x.atom = {i, j, planes[across].atom, 0};
      x.size = 3;
      const mss::Orthocentre o = mss::orthocentre(p, x);
      const glm::dvec3 xo = o.z - zi;
      const std::size_t upBegin = sc.ups.size();
      for (std::uint16_t v : {a, b}) {
        if (glm::dot(verts[v].p, verts[v].p) > rho2) continue;
        for (std::uint16_t pl : verts[v].plane)
          if (pl != k && pl != across && isAtom(planes[pl])) sc.ups.push_back(planes[pl].atom);
      }
      const double dist2 = pointSegmentDistance2(xo, verts[a].p, verts[b].p);
      const double maxNu2 = std::max(glm::dot(verts[a].p - xo, verts[a].p - xo), glm::dot(verts[b].p - xo, verts[b].p - xo));
      if (holdsSkin(p, x, o, std::sqrt(dist2), maxNu2))
        addElement(x, upBegin);
      else
        sc.ups.resize(upBegin);
    }
  }

  // The Delaunay tetrahedra: vertices of three atom planes, all above i.
  for (const mss::CellVertex& v : verts) {
    Simplex x;
    x.atom[0] = i;
    x.size = 1;
    for (std::uint16_t pl : v.plane) {
      if (!isAtom(planes[pl]) || planes[pl].atom < i) {
        x.size = 0;
        break;
      }
      x = x.with(planes[pl].atom);
    }
    if (x.size != 4) continue;
    const mss::Orthocentre o = mss::orthocentre(p, x);
    if (holdsSkin(p, x, o, 0.0, 0.0)) addElement(x, sc.ups.size());
  }

  // Canonical order: by size, then by atoms.
  std::sort(sc.elements.begin(), sc.elements.end(), [](const Element& a, const Element& b) {
    if (a.x.size != b.x.size) return a.x.size < b.x.size;
    return a.x.atom < b.x.atom;
  });
  for (const Element& e : sc.elements) {
    std::uint32_t* up = sc.ups.data() + e.upBegin;
    std::sort(up, up + e.upCount);
    const std::uint32_t count = static_cast<std::uint32_t>(std::unique(up, up + e.upCount) - up);
    emitPatch(p, e.x, {up, count}, byKind[e.x.size - 1]);
  }
}

// The rule of surface_limits.hpp: [kMinShrinkFactor, 1), s = 1 being the vdW spheres.
void checkShrink(double s) {
  if (skinBuiltWithCells(s)) return;
  char text[320];
  if (s > 0.0 && s < kMinShrinkFactor)
    std::snprintf(text, sizeof text,
                  "MSS shrink factor %g is below %g, the smallest this program serves: the atoms' weights "
                  "r^2/s grow as 1/s, and below it double precision no longer carries the skin's areas and "
                  "volume (by then the skin is within 0.1 %% of its s -> 0 limit, the atoms' hull grown by "
                  "their radii)",
                  s, kMinShrinkFactor);
  else
    std::snprintf(text, sizeof text,
                  "MSS shrink factor must lie in [%g, 1), got %g (s = 1 is the union of the van der Waals balls: "
                  "use the vdw surface)",
                  kMinShrinkFactor, s);
  throw std::invalid_argument(text);
}

}  // namespace

struct MssBuilder::State {
  MssParams params;
  std::vector<glm::dvec3> centers;
  std::vector<double> radii, weights;
  Geometry geometry;
  NeighbourGrid grid;
  std::vector<std::array<Chunk, kMssKindCount>> blocks;
  PatchList list;
  MssUpdateStats stats;
  tbb::enumerable_thread_specific<Scratch> scratch;
  std::vector<std::uint8_t> dirty;  // per block
  std::vector<std::size_t> patchOffset, planeOffset;  // per block, into the list
  bool built = false;

  void buildBlocks(std::span<const std::uint32_t> which) {
    tbb::enumerable_thread_specific<std::size_t> exact(0);
    tbb::parallel_for(std::size_t{0}, which.size(), [&](std::size_t n) {
      const std::uint32_t b = which[n];
      std::array<Chunk, kMssKindCount>& chunks = blocks[b];
      for (Chunk& chunk : chunks) chunk.clearKeepingMemory();
      Scratch& sc = scratch.local();
      const auto end = static_cast<std::uint32_t>(std::min<std::size_t>(centers.size(), (b + 1) * std::size_t{kBlockAtoms}));
      for (std::uint32_t i = b * kBlockAtoms; i < end; ++i) {
        atomPatches(geometry, grid, i, sc, chunks.data());
        exact.local() += sc.cell.exactSides();
      }
    });
    stats.exactSides = exact.combine(std::plus<>());
  }

  // The blocks concatenated, in parallel: offsets first, then each block copies itself.
  void assemble() {
    list.params = {};
    list.params.surface = SurfaceKind::Mss;
    list.params.shrinkFactor = params.shrink;
    list.params.atomCount = static_cast<std::uint32_t>(centers.size());
    list.componentCount = 0;
    list.skinAtoms.center.assign(centers.begin(), centers.end());
    list.skinAtoms.weight.assign(weights.begin(), weights.end());
    // Chunk c = kind·blocks + block: the list holds the kinds in order, each by block.
    const std::size_t count = kMssKindCount * blocks.size();
    auto chunk = [&](std::size_t c) -> const Chunk& { return blocks[c % blocks.size()][c / blocks.size()]; };
    patchOffset.assign(count + 1, 0);
    planeOffset.assign(count + 1, 0);
    for (std::size_t c = 0; c < count; ++c) {
      patchOffset[c + 1] = patchOffset[c] + chunk(c).mss.size();
      planeOffset[c + 1] = planeOffset[c] + chunk(c).cellPlanes.size();
    }
    auto offsets = [&](const char* group) -> const std::vector<std::size_t>& {
      return std::strcmp(group, "cellPlanes") == 0 ? planeOffset : patchOffset;
    };
    forEachArray([&](const char* group, const char*, auto& v) {
      if (isMssGroup(group)) v.resize(offsets(group)[count]);
    }, list);
    tbb::parallel_for(std::size_t{0}, count, [&](std::size_t c) {
      forEachArray([&](const char* group, const char*, auto& dst, const auto& src) {
        if (isMssGroup(group))
          std::copy(src.begin(), src.end(), dst.begin() + static_cast<std::ptrdiff_t>(offsets(group)[c]));
      }, list, chunk(c));
      const auto base = static_cast<std::uint32_t>(planeOffset[c]);
      for (std::size_t k = patchOffset[c]; k < patchOffset[c + 1]; ++k) list.mss.cellBegin[k] += base;
    });
  }

  void setGeometry() {
    const double s = params.shrink;
    geometry.points = {centers, weights, s};
    const std::size_t n = centers.size();
    geometry.rho.resize(n);
    geometry.rho2.resize(n);
    geometry.reach.resize(n);
    double reachMax = 0.0;
    for (std::size_t i = 0; i < n; ++i) {
      geometry.rho2[i] = (weights[i] + (1.0 - s) * geometry.wMax / s) * (1.0 + kReachSlack);
      const double rho2 = geometry.rho2[i] * params.feasibleScale * params.feasibleScale;
      geometry.rho[i] = std::sqrt(rho2);
      geometry.reach[i] = (geometry.rho[i] + std::sqrt(rho2 + geometry.wMax - weights[i])) * (1.0 + kReachSlack);
      reachMax = std::max(reachMax, geometry.reach[i]);
    }
    grid.build(centers, radii, 0.5 * reachMax);
  }
};

MssBuilder::MssBuilder() : s_(std::make_unique<State>()) {}
MssBuilder::~MssBuilder() = default;
MssBuilder::MssBuilder(MssBuilder&&) noexcept = default;
MssBuilder& MssBuilder::operator=(MssBuilder&&) noexcept = default;

const PatchList& MssBuilder::build(std::span<const glm::dvec3> centers, std::span<const double> radii,
                                   const MssParams& params) {
  checkShrink(params.shrink);
  if (!(params.feasibleScale >= 1.0)) throw std::invalid_argument("MSS: feasibleScale must be >= 1");
  if (centers.size() != radii.size()) throw std::invalid_argument("MSS: centres and radii differ in length");
  if (centers.size() >= kBoxPlane) throw std::invalid_argument("MSS: too many atoms");
  State& s = *s_;
  s.params = params;
  s.centers.assign(centers.begin(), centers.end());
  s.radii.assign(radii.begin(), radii.end());
  s.weights.resize(radii.size());
  s.geometry.wMax = 0.0;
  for (std::size_t i = 0; i < radii.size(); ++i) {
    const glm::dvec3& c = centers[i];
    if (!std::isfinite(c.x) || !std::isfinite(c.y) || !std::isfinite(c.z) || !std::isfinite(radii[i]) || radii[i] < 0.0)
      throw std::invalid_argument("MSS: atom " + std::to_string(i) + " has a non-finite centre or a bad radius");
    s.weights[i] = mss::skinWeight(radii[i], params.shrink);
    s.geometry.wMax = std::max(s.geometry.wMax, s.weights[i]);
  }
  s.setGeometry();
  const std::size_t blockCount = (centers.size() + kBlockAtoms - 1) / kBlockAtoms;
  s.blocks.resize(blockCount);
  std::vector<std::uint32_t> all(blockCount);
  for (std::uint32_t b = 0; b < blockCount; ++b) all[b] = b;
  s.buildBlocks(all);
  s.assemble();
  s.stats.moved = 0;
  s.stats.recomputed = centers.size();
  s.stats.full = true;
  s.built = true;
  return s.list;
}

const PatchList& MssBuilder::update(std::span<const std::uint32_t> moved, std::span<const glm::dvec3> newCenters) {
  State& s = *s_;
  if (!s.built) throw std::logic_error("MssBuilder::update before build");
  if (moved.size() != newCenters.size()) throw std::invalid_argument("MssBuilder::update: length mismatch");
  const std::size_t n = s.centers.size();
  std::vector<glm::dvec3> oldPlaces;
  oldPlaces.reserve(moved.size());
  for (std::size_t k = 0; k < moved.size(); ++k) {
    const glm::dvec3& c = newCenters[k];
    if (moved[k] >= n) throw std::invalid_argument("MssBuilder::update: atom index " + std::to_string(moved[k]) + " out of range");
    if (!std::isfinite(c.x) || !std::isfinite(c.y) || !std::isfinite(c.z))
      throw std::invalid_argument("MssBuilder::update: atom " + std::to_string(moved[k]) + " moves to a non-finite place");
    oldPlaces.push_back(s.centers[moved[k]]);
    s.centers[moved[k]] = c;
  }
  s.grid.build(s.centers, s.radii, s.grid.probeRadius());
  const std::size_t blockCount = s.blocks.size();
  s.dirty.assign(blockCount, 0);
  std::vector<std::uint32_t> near;
  std::size_t recomputed = 0;
  double reachMax = 0.0;
  for (double r : s.geometry.reach) reachMax = std::max(reachMax, r);
  auto markAround = [&](const glm::dvec3& place) {
    near.clear();
    s.grid.atomsNear(place, reachMax, near);
    for (std::uint32_t j : near) {
      const glm::dvec3 d = s.centers[j] - place;
      if (glm::dot(d, d) < s.geometry.reach[j] * s.geometry.reach[j]) s.dirty[j / kBlockAtoms] = 1;
    }
  };
  // When many atoms move, finding who is near them costs more than rebuilding everything.
  if (moved.size() > n / 8) {
    s.dirty.assign(blockCount, 1);
  } else {
    for (std::size_t k = 0; k < moved.size(); ++k) {
      s.dirty[moved[k] / kBlockAtoms] = 1;
      markAround(oldPlaces[k]);
      markAround(newCenters[k]);
    }
  }
  std::vector<std::uint32_t> which;
  for (std::uint32_t b = 0; b < blockCount; ++b) {
    if (!s.dirty[b]) continue;
    which.push_back(b);
    recomputed += std::min<std::size_t>(kBlockAtoms, n - b * std::size_t{kBlockAtoms});
  }
  s.buildBlocks(which);
  s.assemble();
  s.stats.moved = moved.size();
  s.stats.recomputed = recomputed;
  s.stats.full = which.size() == blockCount;
  return s.list;
}

const PatchList& MssBuilder::update(std::span<const glm::dvec3> centers) {
  if (!s_->built) throw std::logic_error("MssBuilder::update before build");
  if (centers.size() != s_->centers.size()) throw std::invalid_argument("MssBuilder::update: the frame has a different atom count");
  std::vector<std::uint32_t> moved;
  std::vector<glm::dvec3> places;
  movedAtoms(s_->centers, centers, moved, places);
  return update(moved, places);
}

const PatchList& MssBuilder::patches() const { return s_->list; }
PatchList MssBuilder::takePatches() {
  s_->built = false;
  return std::move(s_->list);
}
const MssUpdateStats& MssBuilder::lastUpdate() const { return s_->stats; }

PatchList buildMss(std::span<const glm::dvec3> centers, std::span<const double> radii, const MssParams& params) {
  MssBuilder builder;
  builder.build(centers, radii, params);
  return builder.takePatches();
}

}  // namespace surftrace::build

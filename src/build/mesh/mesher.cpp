// The mesher (mesher.hpp): sparse grid walk, marching tetrahedra, certified refinement.
#include "build/mesh/mesher.hpp"

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdio>
#include <mutex>
#include <optional>
#include <set>
#include <cstdint>
#include <limits>
#include <numeric>
#include <stdexcept>
#include <string>
#include <unordered_map>
#include <unordered_set>
#include <utility>

#include <glm/geometric.hpp>
#include <tbb/parallel_for.h>

#include "build/core/assert.hpp"

namespace surftrace::build::mesh {
namespace {

constexpr double kInf = std::numeric_limits<double>::infinity();
// Samples per triangle edge at most in the certificate: beyond it the triangle is split
// instead, which costs fewer closest() calls than sampling it.
constexpr int kMaxSamplesPerEdge = 32;
// The certificate's sampling radius is this share of ε: √(0.7² + d²) <= 1 leaves d up to ~0.7ε.
constexpr double kSamplingShare = 0.7;
// Root finding on a grid edge: iterations of the safeguarded secant (Illinois) method.
constexpr int kRootIterations = 100;
// Sphere-tracing steps along a split line before falling back to the nearest point: a line
// that meets the surface at 10° still arrives within 1e-3 edge lengths in about 60.
constexpr int kTraceSteps = 100;
// Corner normals of a mesh edge further apart than this (90°) make it an edge across a crease
// of the surface (creasePoint), such as the knife-edge ridge where two concave patches clip
// each other.
constexpr double kCreaseCosine = 0.0;
// The crease search (creasePoint) bisects along the edge this many times at most, until the
// surface points found on its two sides are within this share of the edge's length.
constexpr int kCreaseIterations = 60;
constexpr double kCreaseGap = 1e-6;
// How far the crease search traces from the edge (edge lengths): a crease whose two sides meet
// at an angle α lies up to L / (2 sin(α/2)) beyond an edge of length L across it, and the
// traces need |np + nq| = 2 sin(α/2) > 0.2 (traceToSurface), so 5 edges reach every one.
constexpr double kCreaseReach = 5.0;
// A split point is taken no farther than this many edge lengths from the edge's midpoint along
// the line (the midpoint is within half an edge of the surface; a crossing much farther belongs
// to another part of it, and the triangles made with it would be larger than the ones split).
constexpr double kSplitReach = 1.0;
// Refinement gives up when the mesh has grown this many times over the marching-tetrahedra mesh
// (about 100x is what ε = h²/1000 asks of a smooth surface): past it, splits no longer converge.
constexpr std::size_t kMaxGrowth = 200;
// And whatever the start, at this many triangles (a few GB with their vertices and the
// certificate's work), so that a surface the refinement cannot finish stops with a message
// instead of filling the memory (1AON's SES at 0.1 Å passed 18 GB without finishing).
constexpr std::size_t kMaxTriangles = 20'000'000;

// Grid vertices are (i, j, k) in [0, 2^21)^3 in fine units, kFine to a grid step, packed into
// one key; a cell is keyed by its lowest corner. The fine units are the vertices that bisecting
// tetrahedra adds where the body is thinner than the grid (refineHidden): a midpoint of two
// vertices is a vertex as long as their coordinates differ by even numbers, which allows
// kFineBits halvings of a grid edge.
constexpr int kAxisBits = 21;
constexpr int kFineBits = 8;
constexpr std::int64_t kFine = std::int64_t{1} << kFineBits;
constexpr std::int64_t kAxisLimit = std::int64_t{1} << (kAxisBits - kFineBits);  // grid cells per axis
using Key = std::uint64_t;
Key packKey(std::int64_t i, std::int64_t j, std::int64_t k) {
  return static_cast<Key>(i) | static_cast<Key>(j) << kAxisBits | static_cast<Key>(k) << (2 * kAxisBits);
}
std::array<std::int64_t, 3> unpackKey(Key key) {
  const Key mask = (Key{1} << kAxisBits) - 1;
  return {static_cast<std::int64_t>(key & mask), static_cast<std::int64_t>(key >> kAxisBits & mask),
          static_cast<std::int64_t>(key >> (2 * kAxisBits) & mask)};
}
// Corner c (bits x = 1, y = 2, z = 4) of the cell keyed `cell`.
Key cornerKey(Key cell, int c) {
  return cell + static_cast<Key>((c & 1) * kFine) + (static_cast<Key>((c >> 1 & 1) * kFine) << kAxisBits) +
         (static_cast<Key>((c >> 2 & 1) * kFine) << (2 * kAxisBits));
}
// Kuhn's triangulation of the cube: the six monotone paths from corner 0 to corner 7. Every
// cube is split alike, so each square face is cut along the same diagonal from both sides and
// the tetrahedra of neighbouring cubes share whole faces. Every edge runs from a corner to one
// with more bits set, so an edge is its lower corner and a direction (1..7).
constexpr int kTets[6][4] = {{0, 1, 3, 7}, {0, 1, 5, 7}, {0, 2, 3, 7}, {0, 2, 6, 7}, {0, 4, 5, 7}, {0, 4, 6, 7}};
// The four corners of each face: x = 0, x = 1, y = 0, y = 1, z = 0, z = 1.
constexpr int kFaces[6][4] = {{0, 2, 4, 6}, {1, 3, 5, 7}, {0, 1, 4, 5}, {2, 3, 6, 7}, {0, 1, 2, 3}, {4, 5, 6, 7}};
// Kuhn's edges are the corner pairs (u, v) whose bits u has a strict subset of v's: 19 per cube.
bool kuhnEdge(int u, int v) { return u != v && (u & v) == u; }

// An edge between two vertices, its keys in order.
struct EdgeKey {
  Key a = 0, b = 0;
  EdgeKey() = default;
  EdgeKey(Key p, Key q) : a(std::min(p, q)), b(std::max(p, q)) {}
  bool operator==(const EdgeKey& o) const { return a == o.a && b == o.b; }
  bool operator<(const EdgeKey& o) const { return a != o.a ? a < o.a : b < o.b; }
};
struct EdgeHash {
  std::size_t operator()(const EdgeKey& e) const {
    return static_cast<std::size_t>(e.a * 0x9E3779B97F4A7C15ull ^ (e.b + 0x632BE59BD9B4E019ull + (e.a << 6)));
  }
};

struct Grid {
  glm::dvec3 origin{0.0};
  double h = 0.0;
  // Grid vertices where the field was exactly 0, moved off the surface (see valueAt).
  std::unordered_map<Key, glm::dvec3> moved;
  glm::dvec3 position(Key key) const {
    if (!moved.empty())
      if (const auto it = moved.find(key); it != moved.end()) return it->second;
    const auto [i, j, k] = unpackKey(key);
    return origin + (h / static_cast<double>(kFine)) *
                        glm::dvec3(static_cast<double>(i), static_cast<double>(j), static_cast<double>(k));
  }
};

// Inside the body: strictly negative. A value of exactly 0 counts as outside, so no grid value
// sits on the surface and marching tetrahedra's output is a closed manifold.
bool inside(double value) { return value < 0.0; }

// The value at a grid vertex whose field value came out `value`. A grid vertex on the surface
// would put the crossings of all its edges at one point (zero-area triangles): it is moved off
// the surface by a small step, outwards (0 counts as outside), which keeps every tetrahedron's
// sign pattern and makes the crossings distinct.
double settleZero(const SurfaceDistance& field, Grid& grid, Key key, double value) {
  for (double step = 1e-4; value == 0.0 && step < 0.5; step *= 4.0)
    for (double sign : {1.0, -1.0}) {
      const glm::dvec3 moved = grid.position(key) + sign * step * grid.h / static_cast<double>(kFine) *
                                                        glm::normalize(glm::dvec3(0.53, 0.71, 0.46));
      const double v = field.signedDistance(moved);
      if (v > 0.0 && value == 0.0) grid.moved[key] = moved, value = v;
    }
  return value;
}

// The farthest a point of a Kuhn triangle (half a cube's face, or a diagonal section) lies
// from its nearest corner, in grid steps: half the face diagonal √2 of a right triangle; the
// sections through the cube (sides 1, √2, √3, right-angled) reach √3/2, which is larger.
constexpr double kFaceCover = 0.8660254037844387;

// Whether the field may cross zero between two points more often than their signs require
// (never where they have one sign, once where they differ): by the Lipschitz bound it cannot
// where |f(a)| + |f(b)| >= |a − b| (|f| is at least the distance up to the reach), since the
// balls of radius |f| about the two points then cover the segment and hold no surface.
bool mayCrossAgain(double fa, double fb, double length, double reach) {
  return std::min(std::abs(fa), reach) + std::min(std::abs(fb), reach) < length;
}
// The same for two points of one sign: whether the field may cross zero between them at all.
bool mayHideCrossing(double fa, double fb, double length, double reach) {
  return inside(fa) == inside(fb) && mayCrossAgain(fa, fb, length, reach);
}

// The grid walk: the cells the surface crosses (corners of both signs), reached from the seeds'
// cells across faces whose corners have both signs (the marching-tetrahedra surface leaves a
// cube only through such faces), with the field's value at every corner of them. The walk also
// goes through the cells with an edge that may hide crossings (mayHideCrossing: the body, or
// the solvent, thinner than the grid there) and across their faces that have such an edge, so
// that a wall or gap between two grid vertices of one sign is reached too: those cells are
// `near`, for refineHidden to look into.
struct Walk {
  std::vector<Key> cells;
  std::vector<Key> near;
  std::unordered_map<Key, double> values;
};

Walk walkGrid(const SurfaceDistance& field, Grid& grid, std::span<const glm::dvec3> seeds, std::int64_t limit) {
  Walk w;
  const double reach = field.reach();
  std::unordered_set<Key> visited;
  std::vector<Key> frontier;
  const auto cellOf = [&](const glm::dvec3& p, int di, int dj, int dk, Key& out) {
    const glm::dvec3 g = (p - grid.origin) / grid.h;
    const std::int64_t i = static_cast<std::int64_t>(std::floor(g.x)) + di;
    const std::int64_t j = static_cast<std::int64_t>(std::floor(g.y)) + dj;
    const std::int64_t k = static_cast<std::int64_t>(std::floor(g.z)) + dk;
    if (i < 0 || j < 0 || k < 0 || i + 1 >= limit || j + 1 >= limit || k + 1 >= limit) return false;
    out = packKey(i * kFine, j * kFine, k * kFine);
    return true;
  };
  for (const glm::dvec3& s : seeds)
    for (int di = -1; di <= 1; ++di)
      for (int dj = -1; dj <= 1; ++dj)
        for (int dk = -1; dk <= 1; ++dk) {
          Key cell;
          if (cellOf(s, di, dj, dk, cell) && visited.insert(cell).second) frontier.push_back(cell);
        }
  // The length of the edge between corners u and v of a cell.
  const auto cornerDistance = [&](int u, int v) {
    return grid.h * std::sqrt(static_cast<double>(__builtin_popcount(static_cast<unsigned>(u ^ v))));
  };
  std::vector<Key> need;
  std::vector<double> needValues;
  while (!frontier.empty()) {
    need.clear();
    for (Key cell : frontier)
      for (int c = 0; c < 8; ++c)
        if (!w.values.count(cornerKey(cell, c))) need.push_back(cornerKey(cell, c));
    std::sort(need.begin(), need.end());
    need.erase(std::unique(need.begin(), need.end()), need.end());
    needValues.resize(need.size());
    tbb::parallel_for(std::size_t{0}, need.size(),
                      [&](std::size_t n) { needValues[n] = field.signedDistance(grid.position(need[n])); });
    for (std::size_t n = 0; n < need.size(); ++n)
      w.values.emplace(need[n], settleZero(field, grid, need[n], needValues[n]));
    std::vector<Key> next;
    for (Key cell : frontier) {
      bool in[8];
      double value[8];
      int count = 0;
      for (int c = 0; c < 8; ++c) {
        value[c] = w.values.at(cornerKey(cell, c));
        count += in[c] = inside(value[c]);
      }
      bool hides[8][8] = {};
      bool anyHidden = false;
      for (int u = 0; u < 8; ++u)
        for (int v = 0; v < 8; ++v)
          if (kuhnEdge(u, v) && mayHideCrossing(value[u], value[v], cornerDistance(u, v), reach))
            hides[u][v] = hides[v][u] = anyHidden = true;
      // A corner nearer the surface than a face diagonal's half: a channel thinner than the
      // grid may pierce a face of the cell between its edges (mayHideInFace).
      double nearest = kInf;
      for (int c = 0; c < 8; ++c) nearest = std::min(nearest, std::abs(value[c]));
      anyHidden = anyHidden || nearest < kFaceCover * grid.h;
      const bool crossed = count != 0 && count != 8;
      if (!crossed && !anyHidden) continue;
      (crossed ? w.cells : w.near).push_back(cell);
      const auto [i, j, k] = unpackKey(cell);
      for (int f = 0; f < 6; ++f) {
        const int* q = kFaces[f];
        const int faceIn = in[q[0]] + in[q[1]] + in[q[2]] + in[q[3]];
        bool faceHides = false;
        for (int x = 0; x < 4; ++x) {
          faceHides = faceHides || std::abs(value[q[x]]) < kFaceCover * grid.h;
          for (int y = 0; y < 4; ++y) faceHides = faceHides || hides[q[x]][q[y]];
        }
        if ((faceIn == 0 || faceIn == 4) && !faceHides) continue;
        const int axis = f / 2, step = f % 2 == 0 ? -1 : 1;
        std::int64_t n[3] = {i / kFine, j / kFine, k / kFine};
        n[axis] += step;
        if (n[axis] < 0 || n[axis] + 1 >= limit) continue;
        const Key neighbour = packKey(n[0] * kFine, n[1] * kFine, n[2] * kFine);
        if (visited.insert(neighbour).second) next.push_back(neighbour);
      }
    }
    frontier = std::move(next);
  }
  return w;
}

// A point of the surface with what closest() knows of it.
void storeVertex(TriangleMesh& mesh, std::size_t v, const SurfacePoint& p) {
  mesh.positions[v] = p.point;
  mesh.normals[v] = p.normal;
  mesh.atom[v] = p.atom;
  mesh.kind[v] = p.kind;
  mesh.component[v] = p.component;
}

// The zero of the field on the segment from `a` (inside, fa < 0) to `b` (outside, fb >= 0):
// the Illinois variant of regula falsi, which keeps the bracket and converges superlinearly.
glm::dvec3 edgeRoot(const SurfaceDistance& field, glm::dvec3 a, double fa, glm::dvec3 b, double fb) {
  if (fb == 0.0) return b;
  int side = 0;
  for (int it = 0; it < kRootIterations; ++it) {
    const double t = fa / (fa - fb);
    const glm::dvec3 x = a + t * (b - a);
    const double fx = field.signedDistance(x);
    if (fx == 0.0 || glm::length(b - a) < 1e-13) return x;
    if (inside(fx)) {
      a = x, fa = fx;
      if (side == -1) fb *= 0.5;
      side = -1;
    } else {
      b = x, fb = fx;
      if (side == 1) fa *= 0.5;
      side = 1;
    }
    if (std::abs(fx) < 1e-13) return x;
  }
  return 0.5 * (a + b);
}

// The surface point where the line from m along ±sum (towards the surface: inwards from
// outside, outwards from inside) first meets it within `reach` edge lengths `length`, walked
// by sphere tracing; nothing when it does not or `sum` is too short to give a direction.
std::optional<glm::dvec3> traceToSurface(const SurfaceDistance& field, const glm::dvec3& m, const glm::dvec3& sum,
                                         double length, double reach) {
  const double fm = field.signedDistance(m);
  if (fm == 0.0) return m;
  if (!(glm::length(sum) > 0.2)) return std::nullopt;
  const glm::dvec3 dir = (fm > 0.0 ? -1.0 : 1.0) * glm::normalize(sum);
  const double limit = reach * length;
  // Steps no shorter than this (a bracket this short is left to edgeRoot), nor longer than
  // the reach, beyond which |f| need not be the distance.
  const double minStep = 1e-3 * length, maxStep = field.reach();
  double t = 0.0, ft = fm;
  for (int step = 0; step < kTraceSteps && t <= limit; ++step) {
    const double next = t + std::max(std::min(std::abs(ft), maxStep), minStep);
    const glm::dvec3 x = m + t * dir, y = m + next * dir;
    const double fy = field.signedDistance(y);
    if (inside(fy) != inside(fm)) return inside(fm) ? edgeRoot(field, x, ft, y, fy) : edgeRoot(field, y, fy, x, ft);
    t = next, ft = fy;
  }
  return std::nullopt;
}

}  // namespace

// splitPoint (mesher.hpp). The line is walked by sphere tracing (steps of |f|, which within the
// reach is the distance to the surface, so no step passes a crossing), then the last step's
// bracket goes to edgeRoot. Steps that grow by doubling instead pass over thin fins: on 1AON's
// SES an edge across the ridge of two nearly touching concave caps has a normal sum along the
// ridge, whose line leaves and re-enters the body within 0.01 Å several times; the doubling
// stepped over all of them to a crossing 2 Å away, and the triangles made there were too large
// to certify (the "worst bound inf" of a triangle that needs over kMaxSamplesPerEdge samples).
glm::dvec3 splitPoint(const SurfaceDistance& field, const glm::dvec3& p, const glm::dvec3& q, const glm::dvec3& np,
                      const glm::dvec3& nq) {
  const glm::dvec3 m = 0.5 * (p + q);
  if (const auto hit = traceToSurface(field, m, np + nq, glm::length(q - p), kSplitReach)) return *hit;
  return field.closest(m).point;
}

std::optional<SurfacePoint> creasePoint(const SurfaceDistance& field, const glm::dvec3& p, const glm::dvec3& q,
                                        const glm::dvec3& np, const glm::dvec3& nq) {
  const double length = glm::length(q - p);
  const glm::dvec3 sum = np + nq, away = np - nq;
  // The surface point the trace from the edge's point at s reaches, and whether it is on p's side.
  const auto reach = [&](double s) -> std::optional<std::pair<SurfacePoint, bool>> {
    const auto hit = traceToSurface(field, p + s * (q - p), sum, length, kCreaseReach);
    if (!hit) return std::nullopt;
    const SurfacePoint y = field.closest(*hit);
    return std::make_pair(y, glm::dot(y.normal, away) > 0.0);
  };
  // The ends are on the surface, each on its own side.
  std::optional<std::pair<SurfacePoint, bool>> lo = std::make_pair(field.closest(p), true),
                                               hi = std::make_pair(field.closest(q), false);
  lo->first.normal = np, hi->first.normal = nq;
  double a = 0.0, b = 1.0;
  for (int it = 0; it < kCreaseIterations && glm::length(lo->first.point - hi->first.point) > kCreaseGap * length; ++it) {
    const double s = 0.5 * (a + b);
    const auto mid = reach(s);
    if (!mid) return std::nullopt;
    (mid->second ? lo : hi) = mid, (mid->second ? a : b) = s;
  }
  if (glm::length(lo->first.point - hi->first.point) > kCreaseGap * length) return std::nullopt;
  // A point of the crease whose normal is the mean of the two sides' there, so that the
  // edges from it to either side do not count as crossing the crease again.
  SurfacePoint c = lo->first;
  const glm::dvec3 mean = lo->first.normal + hi->first.normal;
  if (!(glm::length(mean) > 1e-3)) return std::nullopt;  // a fin's two faces: no direction between them
  c.normal = glm::normalize(mean);
  // One that falls on an end of the edge adds nothing (the ordinary split is taken instead).
  if (std::min(glm::length(c.point - p), glm::length(c.point - q)) < kCreaseGap * length) return std::nullopt;
  return c;
}

namespace {

std::string coordinates(const glm::dvec3& p) {
  char text[96];
  std::snprintf(text, sizeof text, "%.4f, %.4f, %.4f", p.x, p.y, p.z);
  return text;
}

// Where the body (or the solvent) is thinner than the grid, a grid edge can cross the surface
// twice or more with both ends on one side, and marching tetrahedra on the grid's values opens a
// hole through a wall or bridges a gap there, which no later split of triangles undoes (the
// triangles spanning the hole stay as wide as the wall is thick). Those edges are found and
// bisected, with every tetrahedron around them, until no edge hides a crossing.

// Whether the field changes sign between a and b more often than their values fa and fb
// require: at all where they have one sign (a wall or gap between them), more than once where
// they differ (an edge that passes through a thin wall or tunnel beside the crossing it was
// marched at: its one vertex then lands on any of the three, and the triangles made from it
// face against the surface). The segment is halved wherever mayCrossAgain leaves room for
// another crossing, down to pieces of `minLength`, with at most `budget` evaluations of the
// field.
// With `again` false only segments of one sign are searched.
bool hiddenCrossing(const SurfaceDistance& field, const glm::dvec3& a, double fa, const glm::dvec3& b, double fb,
                    double minLength, int& budget, bool again) {
  const double length = glm::length(b - a);
  if (!(again ? mayCrossAgain(fa, fb, length, field.reach()) : mayHideCrossing(fa, fb, length, field.reach())) ||
      length < minLength || budget-- <= 0)
    return false;
  const glm::dvec3 m = 0.5 * (a + b);
  const double fm = field.signedDistance(m);
  if (inside(fa) == inside(fb) && inside(fm) != inside(fa)) return true;
  return hiddenCrossing(field, a, fa, m, fm, minLength, budget, again) ||
         hiddenCrossing(field, m, fm, b, fb, minLength, budget, again);
}
// Whether the field changes sign inside the triangle (a, b, c), whose values have one sign: a
// channel thinner than the grid (two probe balls' narrow neck) can pierce a face between its
// edges. Where each corner's |f| covers the triangle (coverRadius) there is no crossing; else
// the triangle is cut into four at its edges' midpoints, down to pieces of `minLength`, with
// at most `budget` evaluations of the field.
double coverRadius(const glm::dvec3& a, const glm::dvec3& b, const glm::dvec3& c);
bool hiddenInFace(const SurfaceDistance& field, const glm::dvec3& a, double fa, const glm::dvec3& b, double fb,
                  const glm::dvec3& c, double fc, double minLength, int& budget) {
  const double reach = field.reach();
  const double cover = coverRadius(a, b, c);
  if (std::min({std::abs(fa), std::abs(fb), std::abs(fc), reach}) >= cover) return false;
  if (glm::length(b - a) + glm::length(c - b) + glm::length(a - c) < 3.0 * minLength || budget <= 0) return false;
  budget -= 3;
  const glm::dvec3 ab = 0.5 * (a + b), bc = 0.5 * (b + c), ca = 0.5 * (c + a);
  const double fab = field.signedDistance(ab), fbc = field.signedDistance(bc), fca = field.signedDistance(ca);
  if (inside(fab) != inside(fa) || inside(fbc) != inside(fa) || inside(fca) != inside(fa)) return true;
  return hiddenInFace(field, a, fa, ab, fab, ca, fca, minLength, budget) ||
         hiddenInFace(field, ab, fab, b, fb, bc, fbc, minLength, budget) ||
         hiddenInFace(field, ca, fca, bc, fbc, c, fc, minLength, budget) ||
         hiddenInFace(field, ab, fab, bc, fbc, ca, fca, minLength, budget);
}

// Field evaluations per edge in hiddenCrossing, and rounds of bisection.
constexpr int kHiddenBudget = 64;
constexpr int kHiddenRounds = 3 * kFineBits;
// Rounds of bisecting the tetrahedra whose triangles fold (meshSurface): each halves their
// edges, from the grid's to the search's shortest.
constexpr int kFoldPasses = kFineBits;
// Rounds of bisecting the tetrahedra that hold a thin feature (MeshParams::features).
constexpr int kFeaturePasses = 3 * kFineBits;
// Features narrower than this many of the hidden-crossing search's shortest pieces are left.
constexpr double kFeatureResolution = 4.0;
// Corner normals further apart than this (60°) make a backward-facing triangle a fold.
constexpr double kFoldCosine = 0.5;

// A tetrahedron of the refined part of the grid: its four vertices' keys.
using Tet = std::array<Key, 4>;
struct Refined {
  std::unordered_set<Key> cells;  // grid cells whose six Kuhn tetrahedra were replaced by `tets`
  std::vector<Tet> tets;
};

// Finds the edges of the walked cells that hide crossings (hiddenCrossing) and bisects them:
// the grid cells around such an edge become tetrahedra (Kuhn's six each), and every
// tetrahedron with bisected edges is split at its greatest one (by length, then keys), its
// halves again at theirs, until none is left; then the new edges are searched likewise. Both
// tetrahedra on either side of a face split it at the same edges in the same order (a face's
// first split is at its greatest bisected edge, whichever tetrahedron splits it), so the
// tetrahedra stay face to face with each other and with the cells left whole: a cell keeps
// its six tetrahedra only while none of its edges is bisected, and every new edge lies inside
// the cells already replaced. The values of the new vertices go into walk.values.
// With `start` empty the search begins at the walked cells' edges and faces; else it begins by
// bisecting the edges `start` (of tetrahedra that r, grown by an earlier call, or the grid
// has): refinement where marching tetrahedra's triangles fold (refineFolds).
void refineHidden(const SurfaceDistance& field, Grid& grid, Walk& walk, double minLength, Refined& r,
                  const std::vector<EdgeKey>& start, bool again) {
  const double reach = field.reach();
  const auto hides = [&](const EdgeKey& e) {
    int budget = kHiddenBudget;
    return hiddenCrossing(field, grid.position(e.a), walk.values.at(e.a), grid.position(e.b), walk.values.at(e.b),
                          minLength, budget, again);
  };
  std::unordered_set<EdgeKey, EdgeHash> tested;
  std::vector<EdgeKey> candidates;
  if (start.empty())
  for (const std::vector<Key>* list : {&walk.cells, &walk.near})
    for (Key cell : *list) {
      Key corner[8];
      double value[8];
      for (int c = 0; c < 8; ++c) corner[c] = cornerKey(cell, c), value[c] = walk.values.at(corner[c]);
      for (int u = 0; u < 8; ++u)
        for (int v = 0; v < 8; ++v)
          if (kuhnEdge(u, v) &&
              (again ? mayCrossAgain : mayHideCrossing)(value[u], value[v],
                              grid.h * std::sqrt(static_cast<double>(__builtin_popcount(static_cast<unsigned>(u ^ v)))),
                              reach))
            candidates.emplace_back(corner[u], corner[v]);
    }
  std::sort(candidates.begin(), candidates.end());
  candidates.erase(std::unique(candidates.begin(), candidates.end()), candidates.end());
  // The faces of the walked cells' tetrahedra, each with its keys in order.
  using Face = std::array<Key, 3>;
  const auto faceOf = [](Key p, Key q, Key s) {
    Face f{p, q, s};
    std::sort(f.begin(), f.end());
    return f;
  };
  const auto facesOf = [&](const Tet& t, std::vector<Face>& out) {
    out.push_back(faceOf(t[0], t[1], t[2])), out.push_back(faceOf(t[0], t[1], t[3]));
    out.push_back(faceOf(t[0], t[2], t[3])), out.push_back(faceOf(t[1], t[2], t[3]));
  };
  std::vector<Face> faces;
  if (start.empty())
  for (const std::vector<Key>* list : {&walk.cells, &walk.near})
    for (Key cell : *list)
      for (const auto& tet : kTets)
        facesOf({cornerKey(cell, tet[0]), cornerKey(cell, tet[1]), cornerKey(cell, tet[2]), cornerKey(cell, tet[3])},
                faces);
  std::sort(faces.begin(), faces.end());
  faces.erase(std::unique(faces.begin(), faces.end()), faces.end());
  const auto faceHides = [&](const Face& f) {
    const double fa = walk.values.at(f[0]), fb = walk.values.at(f[1]), fc = walk.values.at(f[2]);
    if (inside(fa) != inside(fb) || inside(fa) != inside(fc)) return false;
    int budget = kHiddenBudget;
    return hiddenInFace(field, grid.position(f[0]), fa, grid.position(f[1]), fb, grid.position(f[2]), fc, minLength,
                        budget);
  };
  const auto squaredLength = [](const EdgeKey& e) {
    const auto a = unpackKey(e.a), b = unpackKey(e.b);
    return (a[0] - b[0]) * (a[0] - b[0]) + (a[1] - b[1]) * (a[1] - b[1]) + (a[2] - b[2]) * (a[2] - b[2]);
  };
  // The order in which a tetrahedron's bisected edges are taken: longest first, then by keys.
  const auto before = [&](const EdgeKey& x, const EdgeKey& y) {
    const std::int64_t lx = squaredLength(x), ly = squaredLength(y);
    return lx != ly ? lx > ly : y < x;
  };
  std::vector<EdgeKey> marked;
  const auto mark = [&](const EdgeKey& e) {
    const auto a = unpackKey(e.a), b = unpackKey(e.b);
    // An edge whose midpoint is no vertex of the fine lattice is left as it is.
    if ((a[0] + b[0]) % 2 == 0 && (a[1] + b[1]) % 2 == 0 && (a[2] + b[2]) % 2 == 0) marked.push_back(e);
  };
  std::set<Face> testedFaces;
  const auto search = [&](const std::vector<EdgeKey>& edges, const std::vector<Face>& faceList) {
    std::vector<char> hidden(edges.size(), 0), faceHidden(faceList.size(), 0);
    tbb::parallel_for(std::size_t{0}, edges.size(), [&](std::size_t n) { hidden[n] = hides(edges[n]); });
    tbb::parallel_for(std::size_t{0}, faceList.size(), [&](std::size_t n) { faceHidden[n] = faceHides(faceList[n]); });
    marked.clear();
    for (std::size_t n = 0; n < edges.size(); ++n)
      if (hidden[n]) mark(edges[n]);
    // A face that hides a crossing between its edges is bisected at its longest edge: the
    // faces cut from it shrink until the crossing meets an edge.
    for (std::size_t n = 0; n < faceList.size(); ++n) {
      if (!faceHidden[n]) continue;
      const Face& f = faceList[n];
      EdgeKey longest(f[0], f[1]);
      for (const EdgeKey& e : {EdgeKey(f[1], f[2]), EdgeKey(f[0], f[2])})
        if (before(e, longest)) longest = e;
      mark(longest);
    }
    std::sort(marked.begin(), marked.end());
    marked.erase(std::unique(marked.begin(), marked.end()), marked.end());
  };
  if (start.empty()) {
    search(candidates, faces);
    tested.insert(candidates.begin(), candidates.end());
    testedFaces.insert(faces.begin(), faces.end());
  } else {
    marked.clear();
    for (const EdgeKey& e : start) mark(e);
    std::sort(marked.begin(), marked.end());
    marked.erase(std::unique(marked.begin(), marked.end()), marked.end());
  }
  const auto valueOf = [&](Key key) {
    if (const auto it = walk.values.find(key); it != walk.values.end()) return it->second;
    const double v = settleZero(field, grid, key, field.signedDistance(grid.position(key)));
    walk.values.emplace(key, v);
    return v;
  };
  const auto onGrid = [](const std::array<std::int64_t, 3>& p) {
    return p[0] % kFine == 0 && p[1] % kFine == 0 && p[2] % kFine == 0;
  };
  for (int round = 0; !marked.empty() && round < kHiddenRounds; ++round) {
    // The cells around a bisected grid edge: the cells whose lowest corner is its lower end
    // less the corner offsets u that share no axis with the edge's direction.
    for (const EdgeKey& e : marked) {
      const auto a = unpackKey(e.a), b = unpackKey(e.b);
      if (!onGrid(a) || !onGrid(b)) continue;
      int dir = 0;
      for (int axis = 0; axis < 3; ++axis) dir |= (b[axis] != a[axis]) << axis;
      for (int u = 0; u < 8; ++u) {
        if (u & dir) continue;
        std::int64_t c[3];
        for (int axis = 0; axis < 3; ++axis) c[axis] = a[axis] - (u >> axis & 1) * kFine;
        if (c[0] < 0 || c[1] < 0 || c[2] < 0) continue;
        const Key cell = packKey(c[0], c[1], c[2]);
        if (!r.cells.insert(cell).second) continue;
        for (int corner = 0; corner < 8; ++corner) valueOf(cornerKey(cell, corner));
        for (const auto& tet : kTets)
          r.tets.push_back({cornerKey(cell, tet[0]), cornerKey(cell, tet[1]), cornerKey(cell, tet[2]),
                            cornerKey(cell, tet[3])});
      }
    }
    std::sort(marked.begin(), marked.end());
    std::vector<Key> mid(marked.size());
    for (std::size_t n = 0; n < marked.size(); ++n) {
      const auto a = unpackKey(marked[n].a), b = unpackKey(marked[n].b);
      mid[n] = packKey((a[0] + b[0]) / 2, (a[1] + b[1]) / 2, (a[2] + b[2]) / 2);
    }
    std::vector<double> midValue(marked.size());
    tbb::parallel_for(std::size_t{0}, mid.size(),
                      [&](std::size_t n) { midValue[n] = field.signedDistance(grid.position(mid[n])); });
    for (std::size_t n = 0; n < mid.size(); ++n) walk.values.emplace(mid[n], settleZero(field, grid, mid[n], midValue[n]));
    const auto midpointOf = [&](Key p, Key q) -> std::optional<Key> {
      const EdgeKey e(p, q);
      const auto it = std::lower_bound(marked.begin(), marked.end(), e);
      if (it == marked.end() || !(*it == e)) return std::nullopt;
      return mid[static_cast<std::size_t>(it - marked.begin())];
    };
    std::vector<Tet> tets, created, stack;
    tets.reserve(r.tets.size() + 2 * marked.size());
    for (const Tet& t : r.tets) {
      stack.assign(1, t);
      bool split = false;
      while (!stack.empty()) {
        const Tet tet = stack.back();
        stack.pop_back();
        int bestP = -1, bestQ = -1;
        EdgeKey best;
        for (int p = 0; p < 4; ++p)
          for (int q = p + 1; q < 4; ++q) {
            const EdgeKey e(tet[p], tet[q]);
            if (!midpointOf(tet[p], tet[q])) continue;
            if (bestP < 0 || before(e, best)) best = e, bestP = p, bestQ = q;
          }
        if (bestP < 0) {
          tets.push_back(tet);
          if (split) created.push_back(tet);
          continue;
        }
        split = true;
        const Key m = *midpointOf(tet[bestP], tet[bestQ]);
        Tet first = tet, second = tet;
        first[bestP] = m, second[bestQ] = m;
        stack.push_back(first), stack.push_back(second);
      }
    }
    r.tets = std::move(tets);
    // The new tetrahedra's edges not searched yet, and the new cells'.
    std::vector<EdgeKey> fresh;
    std::vector<Face> freshFaces, tetFaces;
    for (const Tet& t : created) {
      for (int p = 0; p < 4; ++p)
        for (int q = p + 1; q < 4; ++q)
          if (tested.insert(EdgeKey(t[p], t[q])).second) fresh.emplace_back(t[p], t[q]);
      tetFaces.clear();
      facesOf(t, tetFaces);
      for (const Face& f : tetFaces)
        if (testedFaces.insert(f).second) freshFaces.push_back(f);
    }
    search(fresh, freshFaces);
  }
}

// Marching tetrahedra over the walked cells and the refined tetrahedra: vertices on the edges
// whose ends have opposite signs (one per edge, shared by every tetrahedron around it),
// triangles oriented from the inside corners towards the outside ones.
// tetOf, when given, receives each triangle's tetrahedron.
TriangleMesh marchTetrahedra(const SurfaceDistance& field, const Grid& grid, const Walk& walk, const Refined& refined,
                             std::vector<Tet>* tetOf = nullptr) {
  std::unordered_map<EdgeKey, std::uint32_t, EdgeHash> edgeVertex;
  edgeVertex.reserve(walk.cells.size() * 4);
  std::vector<EdgeKey> edges;
  TriangleMesh mesh;
  const auto vertexOn = [&](Key p, Key q) {
    const auto [it, added] = edgeVertex.emplace(EdgeKey(p, q), static_cast<std::uint32_t>(edges.size()));
    if (added) edges.push_back(EdgeKey(p, q));
    return it->second;
  };
  const auto march = [&](const Key* corner, const double* value) {
    int in[4], out[4], nIn = 0, nOut = 0;
    for (int v = 0; v < 4; ++v) (inside(value[v]) ? in[nIn++] : out[nOut++]) = v;
    if (nIn == 0 || nOut == 0) return;
    // The cut's vertices; orientation is decided on the edges' midpoints, where the cut
    // separates the tetrahedron's inside corners from its outside ones by construction.
    std::pair<int, int> cut[4];
    std::size_t cuts = 3;
    if (nIn == 1) cut[0] = {in[0], out[0]}, cut[1] = {in[0], out[1]}, cut[2] = {in[0], out[2]};
    else if (nIn == 3) cut[0] = {in[0], out[0]}, cut[1] = {in[1], out[0]}, cut[2] = {in[2], out[0]};
    else cut[0] = {in[0], out[0]}, cut[1] = {in[0], out[1]}, cut[2] = {in[1], out[1]}, cut[3] = {in[1], out[0]}, cuts = 4;
    glm::dvec3 mid[4], inC(0.0), outC(0.0);
    for (std::size_t n = 0; n < cuts; ++n)
      mid[n] = 0.5 * (grid.position(corner[cut[n].first]) + grid.position(corner[cut[n].second]));
    for (int n = 0; n < nIn; ++n) inC += grid.position(corner[in[n]]) / double(nIn);
    for (int n = 0; n < nOut; ++n) outC += grid.position(corner[out[n]]) / double(nOut);
    const bool flip = glm::dot(glm::cross(mid[1] - mid[0], mid[2] - mid[0]), outC - inC) < 0.0;
    std::uint32_t id[4];
    for (std::size_t n = 0; n < cuts; ++n) id[n] = vertexOn(corner[cut[n].first], corner[cut[n].second]);
    const auto emit = [&](std::uint32_t a, std::uint32_t b, std::uint32_t c) {
      mesh.triangles.push_back(flip ? glm::uvec3(a, c, b) : glm::uvec3(a, b, c));
      if (tetOf) tetOf->push_back({corner[0], corner[1], corner[2], corner[3]});
    };
    emit(id[0], id[1], id[2]);
    // The quad's four points are coplanar at the midpoints, so both halves face alike.
    if (cuts == 4) emit(id[0], id[2], id[3]);
  };
  for (Key cell : walk.cells) {
    if (refined.cells.count(cell)) continue;
    Key corner[8];
    double value[8];
    for (int c = 0; c < 8; ++c) corner[c] = cornerKey(cell, c), value[c] = walk.values.at(corner[c]);
    for (const auto& tet : kTets) {
      const Key k[4] = {corner[tet[0]], corner[tet[1]], corner[tet[2]], corner[tet[3]]};
      const double v[4] = {value[tet[0]], value[tet[1]], value[tet[2]], value[tet[3]]};
      march(k, v);
    }
  }
  for (const Tet& t : refined.tets) {
    const double v[4] = {walk.values.at(t[0]), walk.values.at(t[1]), walk.values.at(t[2]), walk.values.at(t[3])};
    march(t.data(), v);
  }
  const std::size_t n = edges.size();
  std::optional<std::string> broken;
  std::mutex brokenMutex;
  mesh.positions.resize(n), mesh.normals.resize(n), mesh.atom.resize(n), mesh.kind.resize(n), mesh.component.resize(n);
  tbb::parallel_for(std::size_t{0}, n, [&](std::size_t v) {
    double fa = walk.values.at(edges[v].a), fb = walk.values.at(edges[v].b);
    glm::dvec3 a = grid.position(edges[v].a), b = grid.position(edges[v].b);
    if (!inside(fa)) std::swap(a, b), std::swap(fa, fb);
    const glm::dvec3 root = edgeRoot(field, a, fa, b, fb);
    // The field is continuous, so the bracket closes on a zero; a value left over means it
    // changes sign without one (a broken field), which would put vertices far apart.
    const double left = field.signedDistance(root);
    if (std::abs(left) > 1e-6 * grid.h) {
      std::lock_guard<std::mutex> lock(brokenMutex);
      if (!broken) broken = "mesh: the surface's distance field changes sign without a zero on the segment from (" +
                            coordinates(a) + ") to (" + coordinates(b) + "): " + std::to_string(fa) + " to " +
                            std::to_string(fb) + ", still " + std::to_string(left) + " at (" + coordinates(root) +
                            "); the field is discontinuous there (a bug in it), so no mesh can follow it";
    }
    storeVertex(mesh, v, field.closest(root));
  });
  if (broken) throw std::runtime_error(*broken);
  return mesh;
}

// The farthest a point of the triangle lies from the nearest of its corners: the circumradius
// for a triangle with no obtuse angle; for an obtuse one the triangle lies in the disc on its
// longest edge L, where every point is within L/√2 of an end of that edge.
double coverRadius(const glm::dvec3& a, const glm::dvec3& b, const glm::dvec3& c) {
  const double ab = glm::length(b - a), bc = glm::length(c - b), ca = glm::length(a - c);
  const double longest = std::max({ab, bc, ca});
  const double others2 = ab * ab + bc * bc + ca * ca - longest * longest;
  if (longest * longest > others2) return longest / std::sqrt(2.0);
  const double area2 = glm::length(glm::cross(b - a, c - a));  // twice the area
  if (area2 <= 0.0) return longest / std::sqrt(2.0);
  return ab * bc * ca / (2.0 * area2);
}

std::uint64_t edgeKey(std::uint32_t a, std::uint32_t b) {
  if (a > b) std::swap(a, b);
  return static_cast<std::uint64_t>(a) << 32 | b;
}

// The longest edge of a triangle, the one a failing triangle splits.
std::uint64_t longestEdgeOf(const TriangleMesh& mesh, const glm::uvec3& tri) {
  int longest = 0;
  double best = -1.0;
  for (int e = 0; e < 3; ++e) {
    const double length = glm::length(mesh.positions[tri[e]] - mesh.positions[tri[(e + 1) % 3]]);
    if (length > best) best = length, longest = e;
  }
  return edgeKey(tri[longest], tri[(longest + 1) % 3]);
}

// No edge (creaseEdgeOf): a key no triangle's edge has, two equal indices.
constexpr std::uint64_t kNoEdge = ~std::uint64_t{0};

// The edge of a triangle whose corner normals are furthest apart, when they are further apart
// than kCreaseCosine allows (an edge across a crease); kNoEdge when none is.
std::uint64_t creaseEdgeOf(const TriangleMesh& mesh, const glm::uvec3& tri) {
  int opposed = -1;
  double least = kCreaseCosine;
  for (int e = 0; e < 3; ++e) {
    const double cosine = glm::dot(mesh.normals[tri[e]], mesh.normals[tri[(e + 1) % 3]]);
    if (cosine < least) least = cosine, opposed = e;
  }
  return opposed < 0 ? kNoEdge : edgeKey(tri[opposed], tri[(opposed + 1) % 3]);
}

// A triangle that faces against the surface's normals at its corners, or has no area: made
// by marching tetrahedra where a crossing lies very near a grid vertex (a sliver), once its
// corners are projected onto the surface.
bool badTriangle(const TriangleMesh& m, const glm::uvec3& t) {
  const glm::dvec3 n = glm::cross(m.positions[t.y] - m.positions[t.x], m.positions[t.z] - m.positions[t.x]);
  return !(glm::dot(n, m.normals[t.x] + m.normals[t.y] + m.normals[t.z]) > 0.0);
}

// Edge collapses on a closed manifold mesh: one vertex of an edge moves onto the other (which
// stays where it is, on the surface), the edge's two triangles go. A collapse is made only
// when the link condition holds (the two vertices share exactly the two opposite vertices:
// the mesh stays a manifold of the same topology), no triangle it changes turns bad, and, when
// asked, every changed triangle keeps a certified bound within ε.
class Collapser {
 public:
  Collapser(const SurfaceDistance& field, TriangleMesh& mesh, std::vector<double>& bound, double samplingTerm)
      : field_(field), m_(mesh), bound_(bound), samplingTerm_(samplingTerm), around_(mesh.positions.size()),
        alive_(mesh.triangles.size(), 1) {
    for (std::size_t t = 0; t < m_.triangles.size(); ++t)
      for (int k = 0; k < 3; ++k) around_[m_.triangles[t][k]].push_back(static_cast<std::uint32_t>(t));
  }

  bool alive(std::size_t t) const { return alive_[t]; }

  // Moves `drop` onto `keep` if allowed; `maxBound` < 0: no bound asked.
  bool collapse(std::uint32_t keep, std::uint32_t drop, double maxBound) {
    std::vector<std::uint32_t> shared, changed;
    for (std::uint32_t t : around_[drop]) {
      if (!alive_[t]) continue;
      const glm::uvec3 tri = m_.triangles[t];
      (tri.x == keep || tri.y == keep || tri.z == keep ? shared : changed).push_back(t);
    }
    if (shared.size() != 2) return false;
    // Link condition: the common neighbours are the shared triangles' third vertices alone.
    std::unordered_set<std::uint32_t> nearKeep;
    for (std::uint32_t t : around_[keep])
      if (alive_[t])
        for (int k = 0; k < 3; ++k) nearKeep.insert(m_.triangles[t][k]);
    std::unordered_set<std::uint32_t> common;
    for (std::uint32_t t : changed)
      for (int k = 0; k < 3; ++k)
        if (m_.triangles[t][k] != drop && nearKeep.count(m_.triangles[t][k])) common.insert(m_.triangles[t][k]);
    for (std::uint32_t t : shared)
      for (int k = 0; k < 3; ++k)
        if (m_.triangles[t][k] != drop && m_.triangles[t][k] != keep) common.erase(m_.triangles[t][k]);
    if (!common.empty()) return false;
    if (nearKeep.size() <= 4) return false;  // a tetrahedron would fold flat
    std::vector<glm::uvec3> replaced(changed.size());
    std::vector<double> bounds(changed.size(), -1.0);
    for (std::size_t n = 0; n < changed.size(); ++n) {
      glm::uvec3 tri = m_.triangles[changed[n]];
      for (int k = 0; k < 3; ++k)
        if (tri[k] == drop) tri[k] = keep;
      if (badTriangle(m_, tri)) return false;
      replaced[n] = tri;
      if (maxBound >= 0.0) {
        bounds[n] = certifiedDeviation(field_, m_.positions[tri.x], m_.positions[tri.y], m_.positions[tri.z],
                                       samplingTerm_, maxBound);
        if (bounds[n] > maxBound) return false;
      }
    }
    for (std::uint32_t t : shared) alive_[t] = 0;
    for (std::size_t n = 0; n < changed.size(); ++n) {
      m_.triangles[changed[n]] = replaced[n];
      bound_[changed[n]] = bounds[n];
      around_[keep].push_back(changed[n]);
    }
    around_[drop].clear();
    return true;
  }

  // Removes the collapsed triangles and the vertices no triangle uses.
  void compact() {
    std::vector<std::uint32_t> index(m_.positions.size(), ~0u);
    TriangleMesh out;
    std::vector<double> bounds;
    for (std::size_t t = 0; t < m_.triangles.size(); ++t) {
      if (!alive_[t]) continue;
      glm::uvec3 tri = m_.triangles[t];
      for (int k = 0; k < 3; ++k) {
        std::uint32_t& i = index[tri[k]];
        if (i == ~0u) {
          i = static_cast<std::uint32_t>(out.positions.size());
          out.positions.push_back(m_.positions[tri[k]]);
          out.normals.push_back(m_.normals[tri[k]]);
          out.atom.push_back(m_.atom[tri[k]]);
          out.kind.push_back(m_.kind[tri[k]]);
          out.component.push_back(m_.component[tri[k]]);
        }
        tri[k] = i;
      }
      out.triangles.push_back(tri);
      bounds.push_back(bound_[t]);
    }
    m_ = std::move(out);
    bound_ = std::move(bounds);
  }

 private:
  const SurfaceDistance& field_;
  TriangleMesh& m_;
  std::vector<double>& bound_;
  double samplingTerm_;
  std::vector<std::vector<std::uint32_t>> around_;
  std::vector<char> alive_;
};

// Collapses away bad triangles (badTriangle): for each, its edges shortest first, each
// direction. Returns how many bad triangles are left.
std::size_t removeBadTriangles(const SurfaceDistance& field, TriangleMesh& mesh, std::vector<double>& bound,
                               double samplingTerm, double maxBound) {
  for (int pass = 0; pass < 8; ++pass) {
    Collapser c(field, mesh, bound, samplingTerm);
    std::size_t bad = 0, fixed = 0;
    for (std::size_t t = 0; t < mesh.triangles.size(); ++t) {
      if (!c.alive(t) || !badTriangle(mesh, mesh.triangles[t])) continue;
      ++bad;
      const glm::uvec3 tri = mesh.triangles[t];
      int order[3] = {0, 1, 2};
      const auto len = [&](int e) { return glm::length(mesh.positions[tri[e]] - mesh.positions[tri[(e + 1) % 3]]); };
      std::sort(order, order + 3, [&](int a, int b) { return len(a) < len(b); });
      for (int e : order) {
        const std::uint32_t p = tri[e], q = tri[(e + 1) % 3];
        if (c.collapse(p, q, maxBound) || c.collapse(q, p, maxBound)) {
          ++fixed;
          break;
        }
      }
    }
    c.compact();
    if (bad == 0 || fixed == 0) return bad - fixed;
  }
  std::size_t bad = 0;
  for (const glm::uvec3& t : mesh.triangles) bad += badTriangle(mesh, t);
  return bad;
}

}  // namespace

double certifiedDeviation(const SurfaceDistance& field, const glm::dvec3& a, const glm::dvec3& b,
                          const glm::dvec3& c, double samplingTerm, double giveUpAbove) {
  // The sub-triangles of an n-fold barycentric split are the triangle (or its point mirror)
  // scaled by 1/n, so each point p lies within r = coverRadius/n of a sample s. With q the
  // surface point closest(s) gives, v = q − s, d = |v| and t = |v's part along the triangle's
  // plane|, and p − s in that plane: dist(p, surface) <= |p − q| = √(r² + d² − 2(p − s)·v)
  // <= √(r² + d² + 2rt). Near the surface v is nearly normal to the triangle (t << d), so
  // this is about √(r² + d²), where the Lipschitz bound d + r would ask for samples about
  // twice as dense (and four times as many).
  // When the field bounds the triangle from its patch's shape (a sphere's or torus's curvature,
  // SurfaceDistance::patchDeviation), that bound needs no sampling. It takes the patch's
  // largest curvature in every direction, so on a torus's sliver it can fail where the samples
  // pass: then they are taken too, and the smaller of the two upper bounds is one.
  const double patch = field.patchDeviation(a, b, c);
  if (patch <= giveUpAbove) return patch;
  const double cover = coverRadius(a, b, c);
  const int n = std::max(1, static_cast<int>(std::ceil(cover / samplingTerm)));
  if (n > kMaxSamplesPerEdge) return patch;
  const double r = cover / double(n);
  const glm::dvec3 cross = glm::cross(b - a, c - a);
  const double crossLength = glm::length(cross);
  const glm::dvec3 normal = crossLength > 0.0 ? cross / crossLength : glm::dvec3(0.0);
  // The corners are on the surface to about 1e-9 Å (projected there): that much is added.
  double d = 1e-9, t = 1e-9;
  const auto bound = [&] { return std::sqrt(r * r + d * d + 2.0 * r * t); };
  const auto sample = [&](int i, int j) {
    const int k = n - i - j;
    const glm::dvec3 s = (double(i) * a + double(j) * b + double(k) * c) / double(n);
    const glm::dvec3 v = field.closest(s).point - s;
    // A closest point that is not a number (a broken field) bounds nothing: d goes to +inf,
    // where std::max would drop the NaN and keep the bound of the other samples.
    d = std::isfinite(glm::length(v)) ? std::max(d, glm::length(v)) : kInf;
    t = std::max(t, crossLength > 0.0 ? glm::length(v - glm::dot(v, normal) * normal) : glm::length(v));
  };
  // A coarse pass first, so that most failing triangles are told after a few samples.
  const int stride = std::max(1, n / 2);
  for (int pass = 0; pass < 2; ++pass)
    for (int i = 0; i <= n; ++i)
      for (int j = 0; i + j <= n; ++j) {
        const bool coarse = i % stride == 0 && j % stride == 0 && (n - i - j) % stride == 0;
        if (coarse != (pass == 0) || i == n || j == n || i + j == 0) continue;  // corners: on the surface
        sample(i, j);
        if (bound() > giveUpAbove) return std::min(patch, bound());
      }
  return std::min(patch, bound());
}

MeshResult meshSurface(const SurfaceDistance& field, std::span<const glm::dvec3> seeds, const MeshParams& params) {
  const double eps = params.maxError, h = params.gridSpacing;
  if (!(eps > 0.0) || !std::isfinite(eps))
    throw std::invalid_argument("mesh: the maximum error must be a positive number of Å, got " + std::to_string(eps));
  if (!(h > 0.0) || !(h < field.reach()))
    throw std::invalid_argument("mesh: the grid spacing " + std::to_string(h) +
                                " Å must be positive and below the field's reach " + std::to_string(field.reach()) +
                                " Å");
  const auto progress = [&](double f) {
    if (params.progress) params.progress(f);
  };
  MeshResult result;
  // The grid: one cell of margin around the surface's box, so every cell the surface crosses
  // has all its corners in the grid.
  Grid grid;
  grid.h = h;
  // An offset that is no round fraction of h, so that symmetric surfaces rarely pass through
  // grid vertices.
  grid.origin = field.boundsMin() - glm::dvec3(2.0 * h) - h * glm::dvec3(0.2718281828, 0.1414213562, 0.1732050808);
  const glm::dvec3 extent = field.boundsMax() - grid.origin + glm::dvec3(2.0 * h);
  const double cellsPerAxis = std::max({extent.x, extent.y, extent.z}) / h + 2.0;
  if (!(cellsPerAxis < static_cast<double>(kAxisLimit - 2)))
    throw std::invalid_argument("mesh: the surface's box spans " + std::to_string(cellsPerAxis) +
                                " grid cells along an axis, more than " + std::to_string(kAxisLimit - 2) +
                                "; use a larger grid spacing");
  const std::int64_t limit = static_cast<std::int64_t>(std::ceil(cellsPerAxis)) + 2;
  Walk walk = walkGrid(field, grid, seeds, limit);
  // Hidden crossings are searched down to pieces that ε-sized triangles would cover anyway.
  const double minLength = std::max(h / static_cast<double>(kFine), std::min(h / 64.0, eps));
  Refined refined;
  refineHidden(field, grid, walk, minLength, refined, {}, params.followFolds);
  progress(0.1);
  TriangleMesh& mesh = result.mesh;
  std::vector<Tet> tetOf;
  mesh = marchTetrahedra(field, grid, walk, refined, &tetOf);
  // The thin features given: the tetrahedra holding each are bisected (all their edges) until
  // no edge is longer than the feature is wide, with the hidden-crossing search on the new edges.
  for (int pass = 0; pass < kFeaturePasses && !params.features.empty(); ++pass) {
    std::vector<EdgeKey> split;
    const auto contains = [&](const Tet& t, const glm::dvec3& x) {
      const glm::dvec3 a = grid.position(t[0]), b = grid.position(t[1]), c = grid.position(t[2]),
                       d = grid.position(t[3]);
      const double volume = glm::dot(b - a, glm::cross(c - a, d - a));
      if (volume == 0.0) return false;
      const double l1 = glm::dot(x - a, glm::cross(c - a, d - a)) / volume;
      const double l2 = glm::dot(b - a, glm::cross(x - a, d - a)) / volume;
      const double l3 = glm::dot(b - a, glm::cross(c - a, x - a)) / volume;
      const double slack = 1e-9;
      return l1 >= -slack && l2 >= -slack && l3 >= -slack && l1 + l2 + l3 <= 1.0 + slack;
    };
    const auto splitIfLong = [&](const Tet& t, double size) {
      double longest = 0.0;
      for (int p = 0; p < 4; ++p)
        for (int q = p + 1; q < 4; ++q)
          longest = std::max(longest, glm::length(grid.position(t[p]) - grid.position(t[q])));
      if (longest <= std::max(size, 2.0 * minLength)) return;
      for (int p = 0; p < 4; ++p)
        for (int q = p + 1; q < 4; ++q) split.emplace_back(t[p], t[q]);
    };
    for (const ThinFeature& f : params.features) {
      // Narrower than a few of the search's shortest pieces, the feature cannot be resolved
      // (the lattice ends at h/256): bisecting there only makes slivers.
      if (f.size < kFeatureResolution * minLength) continue;
      const glm::dvec3 g = (f.point - grid.origin) / grid.h;
      const std::int64_t i = static_cast<std::int64_t>(std::floor(g.x)), j = static_cast<std::int64_t>(std::floor(g.y)),
                         k = static_cast<std::int64_t>(std::floor(g.z));
      if (i < 0 || j < 0 || k < 0 || i + 1 >= limit || j + 1 >= limit || k + 1 >= limit) continue;
      const Key cell = packKey(i * kFine, j * kFine, k * kFine);
      if (!refined.cells.count(cell)) {
        for (const auto& tet : kTets) {
          const Tet t{cornerKey(cell, tet[0]), cornerKey(cell, tet[1]), cornerKey(cell, tet[2]), cornerKey(cell, tet[3])};
          if (contains(t, f.point)) splitIfLong(t, f.size);
        }
      } else {
        for (const Tet& t : refined.tets)
          if (contains(t, f.point)) splitIfLong(t, f.size);
      }
    }
    if (split.empty()) break;
    for (const EdgeKey& e : split)
      for (Key key : {e.a, e.b})
        if (!walk.values.count(key)) walk.values.emplace(key, settleZero(field, grid, key, field.signedDistance(grid.position(key))));
    refineHidden(field, grid, walk, minLength, refined, split, params.followFolds);
    tetOf.clear();
    mesh = marchTetrahedra(field, grid, walk, refined, &tetOf);
  }
  // A triangle of marching tetrahedra that faces against the surface's normals at its corners
  // (badTriangle) while those normals differ by more than 60° (kFoldCosine) is where the surface turns
  // further inside its tetrahedron than one cut can follow: near a change of the skin's
  // topology its necks and saddles curve on a scale of a tenth of an Å, and such a triangle
  // joins points of two sides of a neck. Every edge of its tetrahedron is bisected (with the
  // search for hidden crossings on the new edges) and the tetrahedra are marched again, until
  // no triangle folds or the edges reach minLength. (A bad triangle whose corners' normals
  // agree is a sliver, cut where a crossing lies next to a grid vertex: its facing is
  // rounding, bisecting makes more of them, and removeBadTriangles collapses it.)
  const auto folds = [&](const glm::uvec3& tri) {
    if (!badTriangle(mesh, tri)) return false;
    const glm::dvec3 a = mesh.normals[tri.x], b = mesh.normals[tri.y], c = mesh.normals[tri.z];
    return std::min({glm::dot(a, b), glm::dot(b, c), glm::dot(c, a)}) < kFoldCosine;
  };
  for (int pass = 0; pass < kFoldPasses && params.followFolds; ++pass) {
    std::vector<EdgeKey> folded;
    for (std::size_t t = 0; t < mesh.triangles.size(); ++t) {
      if (!folds(mesh.triangles[t])) continue;
      const Tet& tet = tetOf[t];
      for (int p = 0; p < 4; ++p)
        for (int q = p + 1; q < 4; ++q)
          if (glm::length(grid.position(tet[p]) - grid.position(tet[q])) >= 2.0 * minLength)
            folded.emplace_back(tet[p], tet[q]);
    }
    if (folded.empty()) break;
    refineHidden(field, grid, walk, minLength, refined, folded, params.followFolds);
    tetOf.clear();
    mesh = marchTetrahedra(field, grid, walk, refined, &tetOf);
  }
  result.gridCells = walk.cells.size();
  result.refinedCells = refined.cells.size();
  progress(0.2);

  // Refinement. Each triangle keeps its bound until it is split.
  const double samplingTerm = kSamplingShare * eps;
  std::vector<double> bound(mesh.triangles.size(), -1.0);
  removeBadTriangles(field, mesh, bound, samplingTerm, -1.0);
  const std::size_t initialTriangles = mesh.triangles.size();
  for (int round = 0;; ++round) {
    tbb::parallel_for(std::size_t{0}, mesh.triangles.size(), [&](std::size_t t) {
      if (bound[t] >= 0.0) return;
      const glm::uvec3 tri = mesh.triangles[t];
      bound[t] = certifiedDeviation(field, mesh.positions[tri.x], mesh.positions[tri.y], mesh.positions[tri.z],
                                    samplingTerm, eps);
    });
    // The longest edge of each failing triangle is split.
    std::vector<std::uint64_t> marked;
    std::size_t worstTriangle = 0;
    double worst = 0.0;
    for (std::size_t t = 0; t < mesh.triangles.size(); ++t) {
      if (bound[t] > worst) worst = bound[t], worstTriangle = t;
      if (bound[t] <= eps) continue;
      const glm::uvec3 tri = mesh.triangles[t];
      marked.push_back(longestEdgeOf(mesh, tri));
      // An edge across a crease is split too, on the crease (creasePoint), when it is not the
      // longest: where three concave sheets meet (on 1AON's SES) a triangle's corners can sit
      // on three of them, its longest edge joining two neighbours 72° apart, whose split lands
      // next to an end round after round while the edge 144° across is never split.
      if (const std::uint64_t crease = creaseEdgeOf(mesh, tri); crease != marked.back() && crease != kNoEdge)
        marked.push_back(crease);
    }
    result.certifiedError = worst;
    result.rounds = round;
    if (marked.empty()) break;
    if (round >= params.maxRounds) {
      const glm::dvec3 p = mesh.positions[mesh.triangles[worstTriangle].x];
      throw std::runtime_error("mesh: after " + std::to_string(round) +
                               " rounds of refinement a triangle near (" + std::to_string(p.x) + ", " +
                               std::to_string(p.y) + ", " + std::to_string(p.z) + ") still has a bound of " +
                               std::to_string(worst) + " Å > --max-error " + std::to_string(eps) +
                               " Å (a cusp or a very thin feature there?); ask for a larger --max-error");
    }
    if (mesh.triangles.size() > std::min(kMaxGrowth * initialTriangles + 1000000, kMaxTriangles))
      throw std::runtime_error("mesh: refinement has grown the mesh to " + std::to_string(mesh.triangles.size()) +
                               " triangles from " + std::to_string(initialTriangles) + " without meeting --max-error " +
                               std::to_string(eps) + " Å (worst bound " + std::to_string(worst) +
                               " Å near the triangle it names next): " +
                               coordinates(mesh.positions[mesh.triangles[worstTriangle].x]) +
                               "; a feature the grid does not resolve there? try a smaller --grid or a larger --max-error");
    std::sort(marked.begin(), marked.end());
    marked.erase(std::unique(marked.begin(), marked.end()), marked.end());
    // Midpoints, projected onto the surface.
    const std::size_t first = mesh.positions.size(), added = marked.size();
    const std::size_t total = first + added;
    mesh.positions.resize(total), mesh.normals.resize(total), mesh.atom.resize(total), mesh.kind.resize(total);
    mesh.component.resize(total);
    tbb::parallel_for(std::size_t{0}, added, [&](std::size_t n) {
      const auto p = static_cast<std::uint32_t>(marked[n] >> 32), q = static_cast<std::uint32_t>(marked[n]);
      // An edge across a crease is split on the crease: a split point on either side of it
      // leaves a triangle across it that no later split shrinks (on 1AON's SES the split of
      // such an edge and of the next one's land on each other's ends, round after round).
      if (glm::dot(mesh.normals[p], mesh.normals[q]) < kCreaseCosine)
        if (const auto c = creasePoint(field, mesh.positions[p], mesh.positions[q], mesh.normals[p], mesh.normals[q])) {
          storeVertex(mesh, first + n, *c);
          return;
        }
      storeVertex(mesh, first + n,
                  field.closest(splitPoint(field, mesh.positions[p], mesh.positions[q], mesh.normals[p], mesh.normals[q])));
    });
    const auto midpointOf = [&](std::uint32_t p, std::uint32_t q) -> std::int64_t {
      const auto it = std::lower_bound(marked.begin(), marked.end(), edgeKey(p, q));
      if (it == marked.end() || *it != edgeKey(p, q)) return -1;
      return static_cast<std::int64_t>(first + static_cast<std::size_t>(it - marked.begin()));
    };
    // Each triangle with marked edges is split at its longest marked edge, and its halves
    // again at theirs: every marked edge is split once, at its one midpoint, from both sides.
    std::vector<glm::uvec3> triangles;
    std::vector<double> bounds;
    triangles.reserve(mesh.triangles.size() + 3 * added);
    std::vector<glm::uvec3> stack;
    for (std::size_t t = 0; t < mesh.triangles.size(); ++t) {
      stack.assign(1, mesh.triangles[t]);
      bool split = false;
      while (!stack.empty()) {
        const glm::uvec3 tri = stack.back();
        stack.pop_back();
        int edge = -1;
        double best = -1.0;
        for (int e = 0; e < 3; ++e) {
          const std::uint32_t p = tri[e], q = tri[(e + 1) % 3];
          if (midpointOf(p, q) < 0) continue;
          const double len = glm::length(mesh.positions[p] - mesh.positions[q]);
          if (len > best) best = len, edge = e;
        }
        if (edge < 0) {
          triangles.push_back(tri);
          bounds.push_back(split ? -1.0 : bound[t]);
          continue;
        }
        split = true;
        const std::uint32_t p = tri[edge], q = tri[(edge + 1) % 3], r = tri[(edge + 2) % 3];
        const auto m = static_cast<std::uint32_t>(midpointOf(p, q));
        stack.push_back(glm::uvec3(p, m, r));
        stack.push_back(glm::uvec3(m, q, r));
      }
    }
    mesh.triangles = std::move(triangles);
    bound = std::move(bounds);
    progress(std::min(0.95, 0.2 + 0.06 * (round + 1)));
  }
  // Splitting can leave a bad triangle where a projected midpoint folds a thin one over.
  result.badTriangles = removeBadTriangles(field, mesh, bound, samplingTerm, eps);
  result.certifiedError = bound.empty() ? 0.0 : *std::max_element(bound.begin(), bound.end());
  progress(1.0);
  return result;
}

std::vector<glm::dvec3> surfaceSeeds(const PatchList& p) {
  std::vector<glm::dvec3> seeds;
  static const glm::dvec3 kDirections[] = {{1, 0, 0},  {-1, 0, 0}, {0, 1, 0},
                                           {0, -1, 0}, {0, 0, 1},  {0, 0, -1}};
  for (std::size_t i = 0; i < p.convex.size(); ++i)
    for (const glm::dvec3& d : kDirections) seeds.push_back(p.convex.center[i] + p.convex.radius[i] * d);
  const double rp = p.params.probeRadius;
  for (std::size_t i = 0; i < p.tori.size(); ++i) {
    // The contact circles: θ = θi and θ = θj at φ = 0 and at the middle of the sweep
    // (ORACLES A.3: the probe centre at φ is c + R(cos φ e1 + sin φ axis × e1)).
    const glm::dvec3 a = p.tori.axis[i], e1 = p.tori.e1[i], e2 = glm::cross(a, e1);
    for (double phi : {0.0, 0.5 * p.tori.phiExtent[i]}) {
      const glm::dvec3 radial = std::cos(phi) * e1 + std::sin(phi) * e2;
      const glm::dvec3 probe = p.tori.center[i] + p.tori.bigRadius[i] * radial;
      for (double theta : {p.tori.thetaI[i], p.tori.thetaJ[i]})
        seeds.push_back(probe + rp * (-std::cos(theta) * radial + std::sin(theta) * a));
    }
  }
  for (std::size_t i = 0; i < p.concave.size(); ++i)
    for (const glm::dvec3& d : {p.concave.dirI[i], p.concave.dirJ[i], p.concave.dirK[i]})
      seeds.push_back(p.concave.probe[i] + rp * d);
  // Skin quadrics: along each direction u from the centre, the quadric radial|x − z|² +
  // axial((x − z)·axis)² + constant = 0 has a root at |x − z| = √(−constant / (radial + axial (u·axis)²)).
  const MssQuadrics& q = p.mss;
  for (std::size_t i = 0; i < q.size(); ++i) {
    const glm::dvec3 a = q.axis[i];
    const glm::dvec3 side = glm::normalize(std::abs(a.x) < 0.9 ? glm::cross(a, glm::dvec3(1, 0, 0))
                                                               : glm::cross(a, glm::dvec3(0, 1, 0)));
    for (const glm::dvec3& u : {a, -a, side, -side, glm::cross(a, side), -glm::cross(a, side),
                                glm::normalize(a + side), glm::normalize(-a - side)}) {
      const double k = q.radialCoeff[i] + q.axialCoeff[i] * glm::dot(u, a) * glm::dot(u, a);
      if (k != 0.0 && -q.constant[i] / k > 0.0) seeds.push_back(q.center[i] + std::sqrt(-q.constant[i] / k) * u);
    }
  }
  return seeds;
}

std::vector<ThinFeature> thinFeatures(const PatchList& p, double gridSpacing) {
  std::vector<ThinFeature> out;
  const MssQuadrics& q = p.mss;
  const double s = p.params.shrinkFactor;
  if (q.size() == 0 || !(s > 0.0 && s < 1.0)) return out;
  for (std::size_t k = 0; k < q.size(); ++k) {
    const double w = q.constant[k] / (s * (1.0 - s));
    const int atoms = static_cast<int>(q.kind[k]) + 1;
    double width = kInf;
    if (atoms == 2 || atoms == 3) width = 2.0 * std::sqrt((w < 0.0 ? s : 1.0 - s) * std::abs(w));
    if (atoms == 4 && w > 0.0) width = 2.0 * std::sqrt((1.0 - s) * w);
    if (width < gridSpacing) out.push_back({q.center[k], width});
  }
  return out;
}

namespace {

// For each vertex, a representative of its connected piece of the mesh (vertices joined by
// triangles): union-find with path halving.
std::vector<std::uint32_t> pieceRoots(const TriangleMesh& mesh) {
  std::vector<std::uint32_t> parent(mesh.positions.size());
  std::iota(parent.begin(), parent.end(), 0u);
  const auto find = [&](std::uint32_t v) {
    while (parent[v] != v) v = parent[v] = parent[parent[v]];
    return v;
  };
  for (const glm::uvec3& t : mesh.triangles) {
    parent[find(t.y)] = find(t.x);
    parent[find(t.z)] = find(t.x);
  }
  for (std::uint32_t v = 0; v < parent.size(); ++v) parent[v] = find(v);
  return parent;
}

}  // namespace

std::vector<MeshComponent> meshComponents(const TriangleMesh& mesh) {
  const std::size_t n = mesh.positions.size();
  const std::vector<std::uint32_t> root = pieceRoots(mesh);
  std::unordered_map<std::uint32_t, std::size_t> index;
  std::vector<MeshComponent> out;
  std::vector<std::size_t> ofTriangle(mesh.triangles.size());
  for (std::size_t t = 0; t < mesh.triangles.size(); ++t) {
    const auto [it, added] = index.emplace(root[mesh.triangles[t].x], out.size());
    if (added) {
      out.emplace_back();
      if (!mesh.component.empty()) out.back().surfaceComponent = mesh.component[mesh.triangles[t].x];
    }
    ofTriangle[t] = it->second;
    MeshComponent& c = out[it->second];
    const glm::uvec3 tri = mesh.triangles[t];
    const glm::dvec3 a = mesh.positions[tri.x], b = mesh.positions[tri.y], d = mesh.positions[tri.z];
    c.triangles++;
    c.area += 0.5 * glm::length(glm::cross(b - a, d - a));
    c.volume += glm::dot(a, glm::cross(b, d)) / 6.0;
  }
  // Directed edges: each must meet its reverse exactly once.
  std::unordered_map<std::uint64_t, int> directed;
  directed.reserve(3 * mesh.triangles.size());
  for (const glm::uvec3& t : mesh.triangles)
    for (int e = 0; e < 3; ++e) directed[static_cast<std::uint64_t>(t[e]) << 32 | t[(e + 1) % 3]]++;
  std::vector<char> used(n, 0);
  for (std::size_t t = 0; t < mesh.triangles.size(); ++t) {
    MeshComponent& c = out[ofTriangle[t]];
    const glm::uvec3 tri = mesh.triangles[t];
    for (int e = 0; e < 3; ++e) {
      const std::uint32_t p = tri[e], q = tri[(e + 1) % 3];
      if (!used[p]) used[p] = 1, c.vertices++;
      const auto fwd = directed.find(static_cast<std::uint64_t>(p) << 32 | q);
      const auto back = directed.find(static_cast<std::uint64_t>(q) << 32 | p);
      if (fwd->second != 1 || back == directed.end() || back->second != 1) c.closed = false;
      if (p < q || back == directed.end()) c.edges++;
    }
  }
  for (MeshComponent& c : out)
    c.euler = static_cast<long long>(c.vertices) - static_cast<long long>(c.edges) + static_cast<long long>(c.triangles);
  return out;
}

TriangleMesh keepComponents(const TriangleMesh& mesh, const std::vector<bool>& keep) {
  // Components numbered as meshComponents numbers them: by first triangle.
  const std::size_t n = mesh.positions.size();
  const std::vector<std::uint32_t> root = pieceRoots(mesh);
  std::unordered_map<std::uint32_t, std::size_t> index;
  std::vector<std::uint32_t> newIndex(n, ~0u);
  TriangleMesh out;
  const bool attributes = !mesh.normals.empty();
  for (const glm::uvec3& t : mesh.triangles) {
    const auto [it, added] = index.emplace(root[t.x], index.size());
    if (!keep.at(it->second)) continue;
    glm::uvec3 mapped;
    for (int e = 0; e < 3; ++e) {
      const std::uint32_t v = t[e];
      if (newIndex[v] == ~0u) {
        newIndex[v] = static_cast<std::uint32_t>(out.positions.size());
        out.positions.push_back(mesh.positions[v]);
        if (attributes) {
          out.normals.push_back(mesh.normals[v]);
          out.atom.push_back(mesh.atom[v]);
          out.kind.push_back(mesh.kind[v]);
          out.component.push_back(mesh.component[v]);
        }
      }
      mapped[e] = newIndex[v];
    }
    out.triangles.push_back(mapped);
  }
  return out;
}

}  // namespace surftrace::build::mesh

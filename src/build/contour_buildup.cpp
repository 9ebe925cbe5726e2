// Contour-buildup in two per-atom passes (Lindow et al. 2010, Sect. 4.1).
//
// Vertex pass: every SAS vertex {i < j < k} is computed, tested and emitted once, by its
// owner i (the lowest atom), from circle (i, j). The probe positions are pure functions of
// the sorted triple (sas_geometry.hpp), so they agree bit for bit with what any atom of the
// triple would compute. The owner also finds the free circles (i, j): those no third sphere
// touches.
// Contour pass: each atom gathers the vertices and free circles that touch it, orders the
// vertices along each of its circles and joins them into exposed arcs. The arcs give the
// tori (from the lower atom of the circle) and the convex patch's area by Gauss–Bonnet.
// Because one decision per vertex serves all three atoms, the contours of neighbouring
// atoms cannot disagree.
//
// Most of the work is deciding which neighbour spheres cut, bury or miss a circle, and
// whether a vertex lies inside another sphere. That is done on the owner's unit sphere
// (circle (i, j) and sphere k are the boundary of cap a and the cap b) in single precision,
// four caps at a time, and only taken when clear by a margin far above rounding; the rest
// takes the exact double-precision tests of ORACLES A.2, so the result is that of the
// exact tests alone (the tori, concave patches and planes are bit for bit those of the
// first implementation, which tested every vertex against every common neighbour).
//
// Every output array is a concatenation of per-atom (per-probe for the planes) segments
// in atom order, which is what makes the list independent of the thread count and lets
// SesBuilder::update splice recomputed segments between kept ones. The contour pass also
// splits each atom's exposed region into its connected faces, from which the SES
// components are labelled.
#include "build/contour_buildup.hpp"

#include <algorithm>
#include <array>
#include <bit>
#include <cmath>
#include <cstring>
#include <limits>
#include <numbers>
#include <optional>
#include <stdexcept>
#include <string>

#include <glm/geometric.hpp>
#include <glm/vec2.hpp>
#if defined(__x86_64__)
#include <immintrin.h>
#elif defined(__SSE2__)
#include <emmintrin.h>
#endif
#include <tbb/blocked_range.h>
#include <tbb/enumerable_thread_specific.h>
#include <tbb/parallel_for.h>

#include "build/error.hpp"
#include "build/neighbour_grid.hpp"
#include "build/sas_geometry.hpp"

namespace surftrace::build {
namespace {

constexpr double kPi = std::numbers::pi;
constexpr double kTwoPi = 2.0 * kPi;
// Atoms per unit of parallel work. Output order never depends on it (every array is in
// atom order), only scheduling does.
constexpr std::size_t kBlock = 64;
// Cap-pair decisions on the unit sphere are taken, in single precision, only when
// |M² − Q²| exceeds this; the rounding error of either side is below 1e-6 (all terms are
// O(1)), so a clear decision is the exact one. Pairs within the margin (a circle within
// ~1e-5 of tangency to a sphere) take the exact path.
constexpr float kMargin = 2e-5f;

// What owner i knows about its circle (i, j), j > i.
enum class CircleState : std::uint8_t {
  Open,        // not decided yet
  Buried,      // clearly inside one sphere (so are its vertices)
  BuriedExact, // inside one sphere by the exact test
  NoCircle,    // the extended spheres do not cut (sasCircle gives nothing)
  Free,        // no sphere touches it: a full torus
  Crossed,     // cut by at least one sphere
};

// Sets of neighbours as bit masks, one bit per position in the neighbourhood.
using Word = std::uint64_t;
constexpr std::size_t kWordBits = 64;
inline void setBit(Word* m, std::size_t b) { m[b / kWordBits] |= Word{1} << (b % kWordBits); }
inline void clearBit(Word* m, std::size_t b) { m[b / kWordBits] &= ~(Word{1} << (b % kWordBits)); }

// Atom x's live (not buried) neighbours, largest cap first, with their caps on x's unit
// sphere. The caps are a struct of arrays in single precision, padded to a multiple of four with
// caps that miss everything, so the all-pairs cap test runs four pairs at a time.
constexpr std::size_t kLanes = 4;
// The arrays are padded to a multiple of 8 so that the AVX2 kernels can run 8 at a time.
constexpr std::size_t kPad = 8;
constexpr std::size_t kCapBuckets = 4;
constexpr double kCapBucketBound[kCapBuckets - 1] = {0.35, 0.55, 0.7};
struct Neighbourhood {
  std::vector<std::uint32_t> atom;
  std::vector<std::uint32_t> upper;  // positions of the atoms > x, in increasing atom order
  std::vector<glm::dvec4> sphere;  // centre, R²: the vertex tests read these
  std::vector<float> ux, uy, uz, cosr;
  void clear() {
    atom.clear();
    sphere.clear();
    ux.clear();
    uy.clear();
    uz.clear();
    cosr.clear();
  }
};

struct Vertex {
  double phi;
  std::uint32_t third;
  bool plus;
  glm::dvec3 p;
  std::uint32_t poly = ~0u;  // a merged vertex of cospherical atoms: its polygon in Scratch::polys
};

// A merged SAS vertex of k >= 4 cospherical atoms (ORACLES E.6): one probe position and the
// fan of concave triangles that tiles the convex cone of the contact directions.
struct Polygon {
  glm::dvec3 p;
  std::vector<std::array<std::uint32_t, 3>> tri;  // sorted atoms of each fan triangle
  std::vector<std::uint8_t> edges;                // per triangle: boundary edges IJ (1), JK (2), KI (4)
};

// One incidence of a vertex or free circle on one of atom x's circles.
struct Entry {
  std::uint32_t other;  // the circle is (x, other)
  std::uint32_t third;  // the vertex's third atom
  std::uint32_t vertex; // concave index; ~0u for a free circle
  bool plus;
  bool leaves;          // with increasing φ the circle leaves sphere `third` here
  double phi;
  double cosPhi, sinPhi;
  std::uint32_t slot;   // position in x's incidence list (vertices or free circles)
};

// An exposed arc of one of atom x's circles, in the frame of its cap on x's unit sphere:
// u(φ) = cosA·axis + sinA·(cos φ e1 + sin φ e2), φ from phi0 to phi0 + extent, the
// region on its left. A free circle is one arc with no vertices.
struct Arc {
  std::uint32_t from, to;  // vertices (concave indices); ~0u for a free circle
  std::uint32_t other;     // the circle is (x, other)
  glm::dvec3 axis, e1, e2;
  double cosA, sinA, phi0, extent;
};


// Per-atom state of the convex patch, from the vertex pass.
enum class CapState : std::uint8_t {
  None,     // no neighbour cap: the whole sphere is exposed
  Some,     // caps; the contour decides
  Covered,  // a cap covers the whole sphere
};

// Pass outputs live in per-thread buffers: each parallel chunk appends the output of its
// run of atoms (in order) to its thread's buffer and records where it starts and ends
// (a Piece); assembly then copies the pieces in chunk order. The buffers are reused from
// pass to pass and build to build, so the per-atom path does not allocate once warm.
// Each buffer has three field groups whose fields grow together.

// Vertex pass. Group 0: concave patches; 1: free circles; 2: per-owner counts.
struct VertexBuf {
  std::vector<glm::dvec3> probe, dirI, dirJ, dirK;
  std::vector<std::uint32_t> atomI, atomJ, atomK;
  std::vector<std::uint8_t> plus;
  std::vector<std::uint8_t> edges;     // boundary edges of the triangle (7 unless merged)
  std::vector<std::uint32_t> group;    // distance back to the first triangle of its merged vertex
  std::vector<std::uint32_t> freeOther;
  std::vector<std::uint32_t> concaveCount, freeCount;
  std::size_t size(int g) const { return g == 0 ? probe.size() : g == 1 ? freeOther.size() : concaveCount.size(); }
  // Room for a pass over `atoms` atoms (about 1.5 concave patches per atom in proteins).
  // Reserving does not touch memory, so generous capacity costs nothing but saves the
  // copies and page faults of growth.
  void reserve(std::size_t atoms) {
    for (auto* v : {&probe, &dirI, &dirJ, &dirK}) v->reserve(4 * atoms);
    for (auto* v : {&atomI, &atomJ, &atomK}) v->reserve(4 * atoms);
    plus.reserve(4 * atoms);
    edges.reserve(4 * atoms);
    group.reserve(4 * atoms);
    freeOther.reserve(atoms / 4 + 64);
    concaveCount.reserve(atoms);
    freeCount.reserve(atoms);
  }
  void clear() {
    for (auto* v : {&probe, &dirI, &dirJ, &dirK}) v->clear();
    for (auto* v : {&atomI, &atomJ, &atomK, &freeOther, &concaveCount, &freeCount, &group}) v->clear();
    plus.clear();
    edges.clear();
  }
};

// Contour pass. Group 0: convex patches; 1: tori; 2: per-atom counts.
struct ContourBuf {
  std::vector<glm::dvec3> convexCenter, convexVectorArea;
  std::vector<double> convexRadius, convexArea;
  std::vector<std::uint32_t> convexAtom;
  std::vector<glm::dvec3> torusCenter, torusAxis, torusE1;
  std::vector<double> bigRadius, thetaI, thetaJ, phiExtent;
  std::vector<std::uint32_t> torusI, torusJ, torusFace;
  std::vector<std::uint32_t> convexCount, toriCount;
  std::size_t size(int g) const { return g == 0 ? convexAtom.size() : g == 1 ? torusI.size() : convexCount.size(); }
  void reserve(std::size_t atoms) {  // about 2.5 tori per atom in proteins
    for (auto* v : {&convexCenter, &convexVectorArea}) v->reserve(atoms);
    for (auto* v : {&convexRadius, &convexArea}) v->reserve(atoms);
    convexAtom.reserve(atoms);
    for (auto* v : {&torusCenter, &torusAxis, &torusE1}) v->reserve(6 * atoms);
    for (auto* v : {&bigRadius, &thetaI, &thetaJ, &phiExtent}) v->reserve(6 * atoms);
    for (auto* v : {&torusI, &torusJ, &torusFace}) v->reserve(6 * atoms);
    convexCount.reserve(atoms);
    toriCount.reserve(atoms);
  }
  void clear() {
    for (auto* v : {&convexCenter, &convexVectorArea, &torusCenter, &torusAxis, &torusE1}) v->clear();
    for (auto* v : {&convexRadius, &convexArea, &bigRadius, &thetaI, &thetaJ, &phiExtent}) v->clear();
    for (auto* v : {&convexAtom, &torusI, &torusJ, &torusFace, &convexCount, &toriCount}) v->clear();
  }
};

// Clipping planes: the partner of each plane, found with the probe grid (group 0), and
// per-probe counts (group 2; group 1 is unused). The planes themselves are computed
// afterwards straight into their final place.
struct PlaneBuf {
  std::vector<std::uint32_t> partner;
  std::vector<std::uint32_t> count;
  std::size_t size(int g) const { return g == 0 ? partner.size() : g == 1 ? 0 : count.size(); }
  void reserve(std::size_t probes) {  // about 10 planes per probe at rp = 1.4
    partner.reserve(32 * probes);
    count.reserve(probes);
  }
  void clear() {
    partner.clear();
    count.clear();
  }
};

template <class Buf> struct Piece {
  const Buf* buf = nullptr;
  std::array<std::size_t, 3> begin{}, end{};
};

struct Scratch {
  struct Order {
    float ux, uy, uz, cosr;
    std::uint32_t atom, bucket;
  };
  std::vector<Order> order;
  std::vector<std::uint32_t> row;
  Neighbourhood nb;
  std::vector<CircleState> state;
  // Per circle (x, atom[a]), a > x: the spheres that may meet it (cand), those that
  // clearly or exactly cross it (cross); `words` words each.
  std::vector<Word> cand, cross;
  std::vector<SasCircle> circle;
  std::vector<std::uint8_t> hasCircle;
  std::vector<Word> buriedMask, above;
  std::vector<Vertex> verts;
  std::vector<Polygon> polys;
  std::vector<std::uint32_t> tied;
  std::vector<Entry> entries;
  std::vector<Arc> arcs;
  std::vector<int> parent;
  std::vector<int> cycleOf, cycleFace;  // per arc; per cycle
  std::vector<std::uint8_t> leftOf;     // cycles × cycles: cycle i lies left of cycle j
  std::vector<std::uint32_t> torusArc;  // per torus of this atom: its arc
  VertexBuf vertexOut;
  ContourBuf contourOut;
  PlaneBuf planeOut;
};

// The atoms as every pass sees them.
struct Atoms {
  std::span<const glm::dvec3> c;
  std::span<const double> r;  // vdW radii
  std::span<const double> R;  // extended radii r + rp
  std::span<const char> buried;
  double rp;
};

// The neighbour relation of NeighbourGrid, evaluated exactly as the grid does, so that a
// pair is a neighbour here iff the grid lists it.
bool gridNeighbours(const Atoms& a, std::uint32_t i, std::uint32_t j) {
  const glm::dvec3& ci = a.c[i];
  const glm::dvec3& cj = a.c[j];
  const double dx = ci.x - cj.x;
  const double dy = ci.y - cj.y;
  const double dz = ci.z - cj.z;
  const double sum = (a.r[i] + a.r[j]) + 2.0 * a.rp;
  return dx * dx + dy * dy + dz * dz < sum * sum;
}

// An atom whose extended sphere lies inside another's contributes nothing to the SAS or
// the SES. Identical atoms: the lowest index survives (ORACLES E.1, E.2).
bool isBuriedByContainment(std::uint32_t i, std::span<const std::uint32_t> row, std::span<const glm::dvec3> c,
                           std::span<const double> R) {
  for (const std::uint32_t j : row) {
    if (R[j] < R[i]) continue;  // d + R_i >= R_i > R_j: j cannot contain i
    // Clearly farther apart than R_j − R_i (the usual case): no square root needed.
    const glm::dvec3 v = c[j] - c[i];
    const double reach = (R[j] - R[i]) + 1e-9;
    if (glm::dot(v, v) > reach * reach * (1.0 + 1e-12)) continue;
    const double d = glm::distance(c[i], c[j]);
    if (d + R[i] < R[j]) return true;
    if (d + R[i] == R[j] && !(d == 0.0 && j > i)) return true;
  }
  return false;
}

std::optional<ProbePair> sortedProbes(const Atoms& a, std::uint32_t x, std::uint32_t y, std::uint32_t z) {
  std::uint32_t t[3] = {x, y, z};
  if (t[0] > t[1]) std::swap(t[0], t[1]);
  if (t[1] > t[2]) std::swap(t[1], t[2]);
  if (t[0] > t[1]) std::swap(t[0], t[1]);
  return probePositions(a.c[t[0]], a.R[t[0]], a.c[t[1]], a.R[t[1]], a.c[t[2]], a.R[t[2]]);
}

// ---------------------------------------------------------------------------------------
// Vertex pass

// Fills s.nb with x's live neighbours and their caps; returns the convex patch's cap state.
CapState gatherNeighbourhood(const Atoms& a, std::uint32_t x, std::span<const std::uint32_t> row, Scratch& s) {
  auto& nb = s.nb;
  nb.clear();
  const glm::dvec3 cx = a.c[x];
  const double Rx = a.R[x];
  bool some = false, covered = false;
  // Larger caps first: they bury most circles and contain most vertices, so the tests
  // that stop at the first such cap stop early. A bucket sort by cap size is enough for
  // that (bonded neighbours have cos ≈ 0.25, the others 0.5 to 1).
  auto& order = s.order;
  order.clear();
  std::uint32_t bucketStart[kCapBuckets + 1] = {};
  const double RxRx = Rx * Rx, invRx = 1.0 / Rx;
  for (const std::uint32_t j : row) {
    if (a.buried[j]) continue;
    const glm::dvec3 v = a.c[j] - cx;
    const double d = std::sqrt(glm::dot(v, v));  // glm::distance(cx, c_j)
    const double inv = 1.0 / d;
    double cosr = (d * d + RxRx - a.R[j] * a.R[j]) * (0.5 * inv) * invRx;
    // The convex patch's fate hangs on cos ≤ −1 (covered) and cos < 1 (a cap at all); near
    // those, the cap's cosine exactly as the contour has always computed it.
    if (!(std::abs(std::abs(cosr) - 1.0) > 1e-9)) cosr = ((d * d + Rx * Rx - a.R[j] * a.R[j]) / (2.0 * d)) / Rx;
    covered = covered || cosr <= -1.0;
    some = some || cosr < 1.0;
    const auto bucket = static_cast<std::uint32_t>(cosr >= kCapBucketBound[0]) +
                        static_cast<std::uint32_t>(cosr >= kCapBucketBound[1]) +
                        static_cast<std::uint32_t>(cosr >= kCapBucketBound[2]);
    // Caps far outside [−1, 1] decide the same way clamped; the clamp keeps floats tame.
    order.push_back({static_cast<float>(v.x * inv), static_cast<float>(v.y * inv), static_cast<float>(v.z * inv),
                     static_cast<float>(std::clamp(cosr, -4.0, 4.0)), j, bucket});
    ++bucketStart[bucket + 1];
  }
  for (std::size_t b = 0; b < kCapBuckets; ++b) bucketStart[b + 1] += bucketStart[b];
  const std::size_t count = order.size();
  nb.atom.resize(count);
  nb.sphere.resize(count);
  nb.ux.resize(count);
  nb.uy.resize(count);
  nb.uz.resize(count);
  nb.cosr.resize(count);
  nb.upper.clear();
  for (const auto& o : order) {
    const std::uint32_t l = bucketStart[o.bucket]++;
    const std::uint32_t j = o.atom;
    nb.atom[l] = j;
    nb.sphere[l] = glm::dvec4(a.c[j], a.R[j] * a.R[j]);
    nb.ux[l] = o.ux;
    nb.uy[l] = o.uy;
    nb.uz[l] = o.uz;
    nb.cosr[l] = o.cosr;
    // The circles (x, j > x) in increasing j (the row is ascending): the output order.
    if (j > x) nb.upper.push_back(l);
  }
  while (nb.ux.size() % kPad != 0) {
    nb.ux.push_back(0.0f);
    nb.uy.push_back(0.0f);
    nb.uz.push_back(0.0f);
    nb.cosr.push_back(2.0f);  // misses every circle: q = 2, d < 0
  }
  return covered ? CapState::Covered : some ? CapState::Some : CapState::None;
}

// Which neighbour caps may meet the boundary of cap `a` (circle (x, atom[a])): sets their
// bits in `cand`, and in `clear` those that clearly cross it. Returns false, early, if one
// clearly contains the whole circle.
//
// On the unit sphere, circle a is u = cos_a a + sin_a (cos φ e1 + sin φ e2), and
// u·b − cos_b = M cos(φ − ψ) − Q with M = sin_a |b − (a·b) a|, Q = cos_b − cos_a (a·b).
// The circle crosses cap b iff M > |Q|, lies inside it iff Q < −M, misses it iff Q > M;
// d = M² − Q² up to rounding (M² = sin²_a (1 − (a·b)²) for unit a, b).
bool classifyCircleSse(const Neighbourhood& nb, std::size_t a, Word* cand, Word* clear, std::size_t words) {
  const std::size_t n = nb.ux.size();  // a multiple of kPad
  const float ax = nb.ux[a], ay = nb.uy[a], az = nb.uz[a], ca = nb.cosr[a];
  const float sa2 = 1.0f - ca * ca;
#if defined(__SSE2__)
  const __m128 vax = _mm_set1_ps(ax), vay = _mm_set1_ps(ay), vaz = _mm_set1_ps(az), vca = _mm_set1_ps(ca);
  const __m128 vsa2 = _mm_set1_ps(sa2), one = _mm_set1_ps(1.0f), zero = _mm_setzero_ps();
  const __m128 lo = _mm_set1_ps(-kMargin), hi = _mm_set1_ps(kMargin);
#endif
  for (std::size_t w = 0; w < words; ++w) {
    Word candBits = 0, clearBits = 0;
    const std::size_t end = std::min(n, (w + 1) * kWordBits);
    for (std::size_t b = w * kWordBits; b < end; b += kLanes) {
      const auto shift = b % kWordBits;  // b is a multiple of kLanes: all bits land in word w
#if defined(__SSE2__)
      const __m128 ab = _mm_add_ps(_mm_add_ps(_mm_mul_ps(vax, _mm_loadu_ps(&nb.ux[b])), _mm_mul_ps(vay, _mm_loadu_ps(&nb.uy[b]))),
                                   _mm_mul_ps(vaz, _mm_loadu_ps(&nb.uz[b])));
      const __m128 q = _mm_sub_ps(_mm_loadu_ps(&nb.cosr[b]), _mm_mul_ps(vca, ab));
      const __m128 d = _mm_sub_ps(_mm_mul_ps(vsa2, _mm_sub_ps(one, _mm_mul_ps(ab, ab))), _mm_mul_ps(q, q));
      // b = a gives d ≈ 0: never a burial.
      if (_mm_movemask_ps(_mm_and_ps(_mm_cmplt_ps(d, lo), _mm_cmplt_ps(q, zero)))) return false;
      candBits |= static_cast<Word>(_mm_movemask_ps(_mm_cmpge_ps(d, lo))) << shift;
      clearBits |= static_cast<Word>(_mm_movemask_ps(_mm_cmpgt_ps(d, hi))) << shift;
#else
      for (std::size_t l = 0; l < kLanes; ++l) {
        const float ab = ax * nb.ux[b + l] + ay * nb.uy[b + l] + az * nb.uz[b + l];
        const float q = nb.cosr[b + l] - ca * ab;
        const float d = sa2 * (1.0f - ab * ab) - q * q;
        if (d < -kMargin && q < 0.0f) return false;
        candBits |= static_cast<Word>(d >= -kMargin) << (shift + l);
        clearBits |= static_cast<Word>(d > kMargin) << (shift + l);
      }
#endif
    }
    cand[w] = candBits;
    clear[w] = clearBits;
  }
  clearBit(cand, a);
  clearBit(clear, a);
  return true;
}

// Whether some cap contains w + n and some cap w − n by kVertexMargin (the loop of
// clearlyInsideBoth).
constexpr float kVertexMargin = 1e-4f;
bool bothInsideSse(const Neighbourhood& nb, float wx, float wy, float wz, float nx, float ny, float nz) {
  const std::size_t n = nb.ux.size();  // a multiple of kPad, padded with caps that contain nothing
#if defined(__SSE2__)
  const __m128 vwx = _mm_set1_ps(wx), vwy = _mm_set1_ps(wy), vwz = _mm_set1_ps(wz);
  const __m128 vnx = _mm_set1_ps(nx), vny = _mm_set1_ps(ny), vnz = _mm_set1_ps(nz);
  const __m128 margin = _mm_set1_ps(kVertexMargin);
  __m128 plusIn = _mm_setzero_ps(), minusIn = _mm_setzero_ps();
  for (std::size_t m = 0; m < n; m += kLanes) {
    const __m128 mx = _mm_loadu_ps(&nb.ux[m]), my = _mm_loadu_ps(&nb.uy[m]), mz = _mm_loadu_ps(&nb.uz[m]);
    const __m128 mw = _mm_sub_ps(_mm_add_ps(_mm_add_ps(_mm_mul_ps(mx, vwx), _mm_mul_ps(my, vwy)), _mm_mul_ps(mz, vwz)),
                                 _mm_loadu_ps(&nb.cosr[m]));
    const __m128 mn = _mm_add_ps(_mm_add_ps(_mm_mul_ps(mx, vnx), _mm_mul_ps(my, vny)), _mm_mul_ps(mz, vnz));
    plusIn = _mm_or_ps(plusIn, _mm_cmpgt_ps(_mm_add_ps(mw, mn), margin));
    minusIn = _mm_or_ps(minusIn, _mm_cmpgt_ps(_mm_sub_ps(mw, mn), margin));
    if (_mm_movemask_ps(plusIn) && _mm_movemask_ps(minusIn)) return true;
  }
#else
  bool plusIn = false, minusIn = false;
  for (std::size_t m = 0; m < n; ++m) {
    const float mw = nb.ux[m] * wx + nb.uy[m] * wy + nb.uz[m] * wz - nb.cosr[m];
    const float mn = nb.ux[m] * nx + nb.uy[m] * ny + nb.uz[m] * nz;
    plusIn = plusIn || mw + mn > kVertexMargin;
    minusIn = minusIn || mw - mn > kVertexMargin;
    if (plusIn && minusIn) return true;
  }
#endif
  return false;
}

#if defined(__x86_64__) && (defined(__GNUC__) || defined(__clang__))
// The same two kernels eight lanes at a time, for CPUs with AVX2 (picked at run time).
// Each lane does the same IEEE single-precision operations in the same order as in the
// SSE2 kernels (no fused multiply-add: the target enables AVX2 alone), so both give the
// same decisions, and the output does not depend on the CPU.
#define SURFTRACE_AVX2_KERNELS 1
__attribute__((target("avx2"))) bool classifyCircleAvx2(const Neighbourhood& nb, std::size_t a, Word* cand, Word* clear,
                                                        std::size_t words) {
  const std::size_t n = nb.ux.size();  // a multiple of kPad
  const float ca = nb.cosr[a];
  const __m256 vax = _mm256_set1_ps(nb.ux[a]), vay = _mm256_set1_ps(nb.uy[a]), vaz = _mm256_set1_ps(nb.uz[a]);
  const __m256 vca = _mm256_set1_ps(ca), vsa2 = _mm256_set1_ps(1.0f - ca * ca), one = _mm256_set1_ps(1.0f);
  const __m256 zero = _mm256_setzero_ps(), lo = _mm256_set1_ps(-kMargin), hi = _mm256_set1_ps(kMargin);
  for (std::size_t w = 0; w < words; ++w) {
    Word candBits = 0, clearBits = 0;
    const std::size_t end = std::min(n, (w + 1) * kWordBits);
    for (std::size_t b = w * kWordBits; b < end; b += kPad) {
      const auto shift = b % kWordBits;  // b is a multiple of kPad: all bits land in word w
      const __m256 ab = _mm256_add_ps(
          _mm256_add_ps(_mm256_mul_ps(vax, _mm256_loadu_ps(&nb.ux[b])), _mm256_mul_ps(vay, _mm256_loadu_ps(&nb.uy[b]))),
          _mm256_mul_ps(vaz, _mm256_loadu_ps(&nb.uz[b])));
      const __m256 q = _mm256_sub_ps(_mm256_loadu_ps(&nb.cosr[b]), _mm256_mul_ps(vca, ab));
      const __m256 d = _mm256_sub_ps(_mm256_mul_ps(vsa2, _mm256_sub_ps(one, _mm256_mul_ps(ab, ab))), _mm256_mul_ps(q, q));
      if (_mm256_movemask_ps(_mm256_and_ps(_mm256_cmp_ps(d, lo, _CMP_LT_OQ), _mm256_cmp_ps(q, zero, _CMP_LT_OQ)))) return false;
      candBits |= static_cast<Word>(_mm256_movemask_ps(_mm256_cmp_ps(d, lo, _CMP_GE_OQ))) << shift;
      clearBits |= static_cast<Word>(_mm256_movemask_ps(_mm256_cmp_ps(d, hi, _CMP_GT_OQ))) << shift;
    }
    cand[w] = candBits;
    clear[w] = clearBits;
  }
  clearBit(cand, a);
  clearBit(clear, a);
  return true;
}

__attribute__((target("avx2"))) bool bothInsideAvx2(const Neighbourhood& nb, float wx, float wy, float wz, float nx, float ny,
                                                    float nz) {
  const std::size_t n = nb.ux.size();
  const __m256 vwx = _mm256_set1_ps(wx), vwy = _mm256_set1_ps(wy), vwz = _mm256_set1_ps(wz);
  const __m256 vnx = _mm256_set1_ps(nx), vny = _mm256_set1_ps(ny), vnz = _mm256_set1_ps(nz);
  const __m256 margin = _mm256_set1_ps(kVertexMargin);
  __m256 plusIn = _mm256_setzero_ps(), minusIn = _mm256_setzero_ps();
  for (std::size_t m = 0; m < n; m += kPad) {
    const __m256 mx = _mm256_loadu_ps(&nb.ux[m]), my = _mm256_loadu_ps(&nb.uy[m]), mz = _mm256_loadu_ps(&nb.uz[m]);
    const __m256 mw = _mm256_sub_ps(
        _mm256_add_ps(_mm256_add_ps(_mm256_mul_ps(mx, vwx), _mm256_mul_ps(my, vwy)), _mm256_mul_ps(mz, vwz)),
        _mm256_loadu_ps(&nb.cosr[m]));
    const __m256 mn = _mm256_add_ps(_mm256_add_ps(_mm256_mul_ps(mx, vnx), _mm256_mul_ps(my, vny)), _mm256_mul_ps(mz, vnz));
    plusIn = _mm256_or_ps(plusIn, _mm256_cmp_ps(_mm256_add_ps(mw, mn), margin, _CMP_GT_OQ));
    minusIn = _mm256_or_ps(minusIn, _mm256_cmp_ps(_mm256_sub_ps(mw, mn), margin, _CMP_GT_OQ));
    if (_mm256_movemask_ps(plusIn) && _mm256_movemask_ps(minusIn)) return true;
  }
  return false;
}

bool hasAvx2() {
  static const bool avx2 = __builtin_cpu_supports("avx2");
  return avx2;
}
#endif

// Which neighbour caps may meet circle a, and whether one clearly buries it (above).
bool classifyCircle(const Neighbourhood& nb, std::size_t a, Word* cand, Word* clear, std::size_t words) {
#if defined(SURFTRACE_AVX2_KERNELS)
  if (hasAvx2()) return classifyCircleAvx2(nb, a, cand, clear, words);
#endif
  return classifyCircleSse(nb, a, cand, clear, words);
}

// Whether both vertices of circles a and b (caps on x's unit sphere, a·u = cos_a,
// b·u = cos_b, |u| = 1) lie inside some neighbour cap by a margin that single precision
// cannot get wrong; then the exact test agrees (|p − c_m| < R_m iff u·m > cos_m for
// p = c_x + R_x u). Any cap may be tried: one that clearly contains a vertex of circles a
// and b is a candidate of both, and a and b themselves pass through the vertices, so they
// never clearly contain them. Unsure (near-tangent circles, a vertex near a rim) is false.
bool clearlyInsideBoth(const Neighbourhood& nb, std::size_t a, std::size_t b) {
  const float ax = nb.ux[a], ay = nb.uy[a], az = nb.uz[a], ca = nb.cosr[a];
  const float bx = nb.ux[b], by = nb.uy[b], bz = nb.uz[b], cb = nb.cosr[b];
  const float g = ax * bx + ay * by + az * bz;
  const float den = 1.0f - g * g;
  if (!(den > 1e-3f)) return false;
  const float inv = 1.0f / den;
  const float alpha = (ca - cb * g) * inv, beta = (cb - ca * g) * inv;
  const float t2 = 1.0f - (alpha * ca + beta * cb);
  if (!(t2 > 1e-3f)) return false;
  const float gamma = std::sqrt(t2 * inv);
  // Vertices w ± n.
  const float wx = alpha * ax + beta * bx, wy = alpha * ay + beta * by, wz = alpha * az + beta * bz;
  const float nx = (ay * bz - az * by) * gamma, ny = (az * bx - ax * bz) * gamma, nz = (ax * by - ay * bx) * gamma;
#if defined(SURFTRACE_AVX2_KERNELS)
  if (hasAvx2()) return bothInsideAvx2(nb, wx, wy, wz, nx, ny, nz);
#endif
  return bothInsideSse(nb, wx, wy, wz, nx, ny, nz);
}

// Cospherical atoms (ORACLES E.6): a probe position p lies on sphere m, a tie, when
// |p − c_m|² = R_m² to a relative kTie, i.e. |p − c_m| = R_m to 1e-10 relative: the tolerance
// of ORACLES A.2 and of the test oracle. A probe position is exact to ~1e-15 relative
// (1e-12 Å even 1e4 Å from the origin, ORACLES E.14), far inside it; and atoms placed with
// the 1e-3 Å resolution of PDB files meet a fourth sphere within 3e-10 Å only by symmetry.
constexpr double kTie = 2e-10;

// Which of p (bit 0) and q (bit 1) lie inside a sphere of (m1 & m2) other than skip1, skip2
// beyond the tie tolerance, |p − c|² < R²(1 − kTie) (computed as glm::dot(p − c, p − c));
// bits 2 and 3: which lie within the tolerance of such a sphere's surface or inside it,
// |p − c|² < R²(1 + kTie). Stops once both are inside.
int insideMask(const Neighbourhood& nb, const Word* m1, const Word* m2, std::size_t words, std::size_t skip1,
               std::size_t skip2, const glm::dvec3& p, const glm::dvec3& q) {
  int inside = 0;
#if defined(__SSE2__)
  const __m128d px = _mm_set_pd(q.x, p.x), py = _mm_set_pd(q.y, p.y), pz = _mm_set_pd(q.z, p.z);
#endif
  for (std::size_t w = 0; w < words; ++w) {
    Word bits = m1[w] & m2[w];
    while (bits) {
      const std::size_t b = w * kWordBits + static_cast<std::size_t>(std::countr_zero(bits));
      bits &= bits - 1;
      if (b == skip1 || b == skip2) continue;
      const glm::dvec4& c = nb.sphere[b];
#if defined(__SSE2__)
      const __m128d dx = _mm_sub_pd(px, _mm_set1_pd(c.x));
      const __m128d dy = _mm_sub_pd(py, _mm_set1_pd(c.y));
      const __m128d dz = _mm_sub_pd(pz, _mm_set1_pd(c.z));
      const __m128d d2 = _mm_add_pd(_mm_add_pd(_mm_mul_pd(dx, dx), _mm_mul_pd(dy, dy)), _mm_mul_pd(dz, dz));
      inside |= _mm_movemask_pd(_mm_cmplt_pd(d2, _mm_set1_pd(c.w * (1.0 - kTie)))) |
                (_mm_movemask_pd(_mm_cmplt_pd(d2, _mm_set1_pd(c.w * (1.0 + kTie)))) << 2);
#else
      const glm::dvec3 c3(c);
      const glm::dvec3 u = p - c3, v = q - c3;
      const double lo = c.w * (1.0 - kTie), hi = c.w * (1.0 + kTie);
      const double du = glm::dot(u, u), dv = glm::dot(v, v);
      inside |= (du < lo ? 1 : 0) | (dv < lo ? 2 : 0) | (du < hi ? 4 : 0) | (dv < hi ? 8 : 0);
#endif
      if ((inside & 3) == 3) return inside;
    }
  }
  return inside;
}

// |p − c|² against R² of neighbourhood sphere b: −1 inside beyond the tie tolerance, 0 a tie,
// 1 outside beyond it.
int sideOf(const Neighbourhood& nb, std::size_t b, const glm::dvec3& p) {
  const glm::dvec4& c = nb.sphere[b];
  const glm::dvec3 u = p - glm::dvec3(c);
  const double d2 = glm::dot(u, u);
  return d2 < c.w * (1.0 - kTie) ? -1 : d2 < c.w * (1.0 + kTie) ? 0 : 1;
}

// The atoms whose spheres pass through p (x and every live neighbour that ties), ascending;
// false if p lies strictly inside a neighbour sphere. A sphere through p meets x's sphere,
// so it is a neighbour of x.
bool tiesAt(const Neighbourhood& nb, std::uint32_t x, const glm::dvec3& p, std::vector<std::uint32_t>& tied) {
  tied.clear();
  tied.push_back(x);
  for (std::size_t b = 0; b < nb.atom.size(); ++b) {
    const int side = sideOf(nb, b, p);
    if (side < 0) return false;
    if (side == 0) tied.push_back(nb.atom[b]);
  }
  std::sort(tied.begin(), tied.end());
  return true;
}

bool plusSideOf(const Atoms& a, std::uint32_t i, std::uint32_t j, std::uint32_t k, const glm::dvec3& p) {
  const glm::dvec3 ci = a.c[i];
  return glm::dot(p - ci, glm::cross(a.c[j] - ci, a.c[k] - ci)) > 0.0;
}

// The merged vertex of the cospherical atoms `atoms` (ascending, k >= 4) near p: the probe
// position of their first triple (in lexicographic order) that has one, on p's side. A
// pure function of the atoms (and the side), so every owner computes the same bits.
std::optional<glm::dvec3> mergedProbe(const Atoms& a, std::span<const std::uint32_t> atoms, const glm::dvec3& p) {
  const std::size_t k = atoms.size();
  for (std::size_t i = 0; i < k; ++i)
    for (std::size_t j = i + 1; j < k; ++j)
      for (std::size_t l = j + 1; l < k; ++l) {
        const std::uint32_t u = atoms[i], v = atoms[j], w = atoms[l];
        const auto probes = probePositions(a.c[u], a.R[u], a.c[v], a.R[v], a.c[w], a.R[w]);
        if (!probes) continue;
        const glm::dvec3 dp = probes->plus - p, dm = probes->minus - p;
        return glm::dot(dp, dp) <= glm::dot(dm, dm) ? probes->plus : probes->minus;
      }
  return std::nullopt;
}

// The concave polygon of a merged vertex: the probe sphere inside the convex cone of the
// contact directions u_m = (c_m − p)/|c_m − p|, triangulated. Its faces are the faces of the
// convex hull of {u_m} ∪ {0} that miss 0 (a pointed cone: one face, or several when the
// directions are not coplanar; all hull faces of {u_m} when the cone is all of space, a
// probe trapped at the centre of a cube). Each face is fanned from its lowest atom over its
// extreme directions in order; an edge is a boundary edge (where the torus of the pair ends)
// when no other triangle of the polygon has it. Directions lying within kFlat of a great
// circle through 0 give no face: a probe that just fits through a ring (E.7b) bounds no area.
void buildPolygon(const Atoms& a, std::span<const std::uint32_t> atoms, Polygon& poly) {
  constexpr double kFlat = 1e-12;
  const std::size_t k = atoms.size();
  std::vector<glm::dvec3> u(k);
  for (std::size_t m = 0; m < k; ++m) u[m] = glm::normalize(a.c[atoms[m]] - poly.p);
  poly.tri.clear();
  poly.edges.clear();
  std::vector<std::size_t> face;
  std::vector<std::pair<double, std::size_t>> ring;
  for (std::size_t i = 0; i < k; ++i)
    for (std::size_t j = i + 1; j < k; ++j)
      for (std::size_t l = j + 1; l < k; ++l) {
        glm::dvec3 nrm = glm::cross(u[j] - u[i], u[l] - u[i]);
        const double len = glm::length(nrm);
        if (!(len > 1e-9)) continue;
        nrm /= len;
        double off = glm::dot(nrm, u[i]);
        if (off < 0.0) nrm = -nrm, off = -off;  // 0 on the inner side
        if (!(off > kFlat)) continue;           // a plane through the probe: no face
        face.clear();
        bool hull = true;
        for (std::size_t m = 0; m < k && hull; ++m) {
          const double dm = glm::dot(nrm, u[m]) - off;
          if (dm > 1e-9) hull = false;
          else if (dm >= -1e-9) face.push_back(m);
        }
        if (!hull || face[0] != i || face[1] != j || face[2] != l) continue;  // each face once
        // Extreme directions of the face in order about its normal (convex position).
        const glm::dvec3 e1 = perpendicularTo(nrm), e2 = glm::cross(nrm, e1);
        glm::dvec3 g(0.0);
        for (const std::size_t m : face) g += u[m];
        g /= static_cast<double>(face.size());
        ring.clear();
        for (const std::size_t m : face) ring.push_back({std::atan2(glm::dot(u[m] - g, e2), glm::dot(u[m] - g, e1)), m});
        std::sort(ring.begin(), ring.end());
        // Drop directions on the segment between their neighbours (not extreme).
        for (bool dropped = true; dropped && ring.size() > 3;) {
          dropped = false;
          for (std::size_t r = 0; r < ring.size(); ++r) {
            const glm::dvec3& p0 = u[ring[(r + ring.size() - 1) % ring.size()].second];
            const glm::dvec3& p1 = u[ring[r].second];
            const glm::dvec3& p2 = u[ring[(r + 1) % ring.size()].second];
            if (glm::dot(glm::cross(p1 - p0, p2 - p1), nrm) <= 1e-12) {
              ring.erase(ring.begin() + static_cast<std::ptrdiff_t>(r));
              dropped = true;
              break;
            }
          }
        }
        // Fan from the lowest atom (the face's first direction in atom order).
        std::size_t start = 0;
        for (std::size_t r = 1; r < ring.size(); ++r)
          if (ring[r].second < ring[start].second) start = r;
        for (std::size_t r = 1; r + 1 < ring.size(); ++r) {
          std::array<std::uint32_t, 3> t = {atoms[ring[start].second], atoms[ring[(start + r) % ring.size()].second],
                                            atoms[ring[(start + r + 1) % ring.size()].second]};
          std::sort(t.begin(), t.end());
          poly.tri.push_back(t);
        }
      }
  // Boundary edges: those of one triangle only.
  auto count = [&](std::uint32_t p, std::uint32_t q) {
    int c = 0;
    for (const auto& t : poly.tri)
      c += ((t[0] == p || t[1] == p || t[2] == p) && (t[0] == q || t[1] == q || t[2] == q)) ? 1 : 0;
    return c;
  };
  for (const auto& t : poly.tri)
    poly.edges.push_back(static_cast<std::uint8_t>((count(t[0], t[1]) == 1 ? 1 : 0) | (count(t[1], t[2]) == 1 ? 2 : 0) |
                                                   (count(t[2], t[0]) == 1 ? 4 : 0)));
}

void vertexPass(const Atoms& a, std::uint32_t x, std::span<const std::uint32_t> row, Scratch& s, VertexBuf& out,
                CapState& capState) {
  std::uint32_t concaveCount = 0, freeCount = 0;
  capState = gatherNeighbourhood(a, x, row, s);
  const auto& nb = s.nb;
  const std::size_t n = nb.atom.size();
  const std::size_t words = (n + kWordBits - 1) / kWordBits;
  const glm::dvec3 cx = a.c[x];
  const double Rx = a.R[x];

  s.state.assign(n, CircleState::Open);
  s.cand.resize(n * words);
  s.cross.resize(n * words);
  s.circle.resize(n);
  s.hasCircle.assign(n, 0);
  // The circle (x, j) of a neighbourhood position, computed when first needed; nothing
  // when the extended spheres do not cut (then the circle contributes nothing).
  auto circleOf = [&](std::size_t ai) -> const SasCircle* {
    if (!s.hasCircle[ai]) {
      const std::uint32_t j = nb.atom[ai];
      const auto circle = sasCircle(cx, Rx, a.c[j], a.R[j]);
      if (!circle) {
        s.state[ai] = CircleState::NoCircle;
        return nullptr;
      }
      s.circle[ai] = *circle;
      s.hasCircle[ai] = 1;
    }
    return &s.circle[ai];
  };
  // Every circle (x, j > x) first, so that the vertex step below knows which circles are
  // clearly buried.
  s.buriedMask.assign(words, 0);
  for (const std::size_t ai : nb.upper) {
    if (!classifyCircle(nb, ai, &s.cand[ai * words], &s.cross[ai * words], words)) {
      s.state[ai] = CircleState::Buried;
      setBit(s.buriedMask.data(), ai);
    }
  }
  // above[t]: the positions of the atoms after upper[t] in atom order (k > j).
  const std::size_t uppers = nb.upper.size();
  s.polys.clear();
  s.above.assign((uppers + 1) * words, 0);
  for (std::size_t t = uppers; t-- > 0;) {
    std::copy_n(&s.above[(t + 1) * words], words, &s.above[t * words]);
    if (t + 1 < uppers) setBit(&s.above[t * words], nb.upper[t + 1]);
  }

  for (const std::size_t ai : nb.upper) {
    if (s.state[ai] != CircleState::Open) continue;
    const std::uint32_t j = nb.atom[ai];
    Word* cand = &s.cand[ai * words];
    Word* cross = &s.cross[ai * words];
    // Undecided spheres (within the margin of tangency) take the exact tests, as for any
    // sphere k of the circle's neighbourhood.
    bool buried = false;
    for (std::size_t w = 0; w < words && !buried; ++w) {
      Word undecided = cand[w] & ~cross[w];
      while (undecided) {
        const std::size_t b = w * kWordBits + static_cast<std::size_t>(std::countr_zero(undecided));
        undecided &= undecided - 1;
        const std::uint32_t k = nb.atom[b];
        const SasCircle* circle = circleOf(ai);
        if (!circle) break;
        if (!gridNeighbours(a, j, k)) {
          clearBit(cand, b);
        } else if (sortedProbes(a, x, j, k)) {
          setBit(cross, b);
        } else {
          // No crossing: the circle is wholly inside or wholly outside sphere k.
          const glm::dvec3 onCircle = circle->center + circle->radius * circle->e1;
          const glm::dvec3 v = onCircle - a.c[k];
          if (glm::dot(v, v) < a.R[k] * a.R[k]) {
            buried = true;
            break;
          }
        }
      }
    }
    if (s.state[ai] == CircleState::NoCircle) continue;
    bool crossed = false;
    for (std::size_t w = 0; w < words; ++w) crossed = crossed || cross[w] != 0;
    if (buried) {
      s.state[ai] = CircleState::BuriedExact;
    } else if (crossed) {
      s.state[ai] = CircleState::Crossed;
    } else if (circleOf(ai)) {
      s.state[ai] = CircleState::Free;
      out.freeOther.push_back(j);
      ++freeCount;
    }
  }

  // The vertices x < j < k on each crossed circle (x, j): valid iff inside no other sphere.
  // A sphere that contains a vertex meets both its circles (x, j) and (x, k), so it is a
  // candidate of both; the others clearly miss one of the circles.
  for (std::size_t t = 0; t < uppers; ++t) {
    const std::size_t ai = nb.upper[t];
    if (s.state[ai] != CircleState::Crossed) continue;
    const std::uint32_t j = nb.atom[ai];
    const Word* candA = &s.cand[ai * words];
    const Word* crossA = &s.cross[ai * words];
    const Word* above = &s.above[t * words];
    s.verts.clear();
    for (std::size_t w = 0; w < words; ++w) {
      // Circles (x, k), k > j, not clearly buried (or so would be the vertex); a vertex
      // {x, k, j} with k < j is emitted from circle (x, k).
      Word bits = crossA[w] & above[w] & ~s.buriedMask[w];
      while (bits) {
        const std::size_t bi = w * kWordBits + static_cast<std::size_t>(std::countr_zero(bits));
        bits &= bits - 1;
        const std::uint32_t k = nb.atom[bi];
        const Word* candB = &s.cand[bi * words];
        // Most vertices lie deep inside some other sphere: a single-precision look first,
        // then the exact probe positions and tests for what it cannot settle.
        if (clearlyInsideBoth(nb, ai, bi)) continue;
        const auto probes = probePositions(cx, Rx, a.c[j], a.R[j], a.c[k], a.R[k]);
        if (!probes) continue;
        // Both probe positions against each sphere at once: bit 0 plus, bit 1 minus.
        const int inside = insideMask(nb, candA, candB, words, ai, bi, probes->plus, probes->minus);
        for (const bool plus : {true, false}) {
          const glm::dvec3 p = plus ? probes->plus : probes->minus;
          if (inside & (plus ? 1 : 2)) continue;
          if (inside & (plus ? 4 : 8)) {
            // Further spheres pass through p (cospherical atoms, ORACLES E.6): one merged
            // vertex, emitted by the lowest of its atoms from the first triple that finds it.
            if (!tiesAt(nb, x, p, s.tied) || s.tied.size() < 4) continue;
            const auto merged = mergedProbe(a, s.tied, p);
            if (!merged || !tiesAt(nb, x, *merged, s.tied) || s.tied.size() < 4 || s.tied[0] != x) continue;
            bool seen = false;
            for (const Polygon& poly : s.polys) seen = seen || std::memcmp(&poly.p, &*merged, sizeof(glm::dvec3)) == 0;
            if (seen) continue;
            s.polys.emplace_back();
            s.polys.back().p = *merged;
            buildPolygon(a, s.tied, s.polys.back());
            s.verts.push_back({0.0, k, plus, *merged, static_cast<std::uint32_t>(s.polys.size() - 1)});
            continue;
          }
          s.verts.push_back({0.0, k, plus, p});
        }
      }
    }
    if (s.verts.empty()) continue;
    const SasCircle* circle = circleOf(ai);
    if (!circle) continue;
    for (Vertex& v : s.verts) {
      const glm::dvec3 wv = v.p - circle->center;
      v.phi = std::atan2(glm::dot(wv, circle->e2), glm::dot(wv, circle->e1));
    }
    if (s.verts.size() > 1) {
      std::sort(s.verts.begin(), s.verts.end(), [](const Vertex& u, const Vertex& v) {
        if (u.phi != v.phi) return u.phi < v.phi;
        if (u.third != v.third) return u.third < v.third;
        return u.plus > v.plus;
      });
    }
    for (const Vertex& v : s.verts) {
      if (v.poly != ~0u) {
        const Polygon& poly = s.polys[v.poly];
        for (std::size_t f = 0; f < poly.tri.size(); ++f) {
          const auto& tri = poly.tri[f];
          out.probe.push_back(poly.p);
          out.dirI.push_back(glm::normalize(a.c[tri[0]] - poly.p));
          out.dirJ.push_back(glm::normalize(a.c[tri[1]] - poly.p));
          out.dirK.push_back(glm::normalize(a.c[tri[2]] - poly.p));
          out.atomI.push_back(tri[0]);
          out.atomJ.push_back(tri[1]);
          out.atomK.push_back(tri[2]);
          out.plus.push_back(plusSideOf(a, tri[0], tri[1], tri[2], poly.p) ? 1 : 0);
          out.edges.push_back(poly.edges[f]);
          out.group.push_back(static_cast<std::uint32_t>(f));
          ++concaveCount;
        }
        continue;
      }
      out.probe.push_back(v.p);
      out.dirI.push_back(glm::normalize(cx - v.p));
      out.dirJ.push_back(glm::normalize(a.c[j] - v.p));
      out.dirK.push_back(glm::normalize(a.c[v.third] - v.p));
      out.atomI.push_back(x);
      out.atomJ.push_back(j);
      out.atomK.push_back(v.third);
      out.plus.push_back(v.plus ? 1 : 0);
      out.edges.push_back(7);
      out.group.push_back(0);
      ++concaveCount;
    }
  }
  out.concaveCount.push_back(concaveCount);
  out.freeCount.push_back(freeCount);
}

// ---------------------------------------------------------------------------------------
// Contour pass

// What the contour pass reads: the vertices and free circles, and who touches them.
struct Incidence {
  std::span<const glm::dvec3> probe;
  std::span<const std::uint32_t> atomI, atomJ, atomK;
  std::span<const std::uint8_t> plus;
  std::span<const std::uint8_t> edges;    // per concave patch: its boundary edges (merged vertices)
  std::span<const std::uint32_t> group;   // per concave patch: distance back to its merged vertex's first
  std::span<const std::uint32_t> vertexBegin, vertex;  // per atom: concave indices
  std::span<const std::uint32_t> freeBegin, free;      // per atom: other atom of free circles
  std::span<const CapState> capState;
  // Written by each atom's contour pass at its own places: the face (of its exposed
  // region, see contourPass) that each incident vertex and free circle bounds, the
  // number of faces, and for the atom `extremeAtom` the face facing +x.
  std::span<std::uint32_t> vertexFace, freeFace, faceCount;
  std::uint32_t extremeAtom;
  std::uint32_t* extremeFace;
};

void pushTorus(ContourBuf& t, const SasCircle& circle, double phi0, double extent, std::uint32_t i, std::uint32_t j) {
  t.torusCenter.push_back(circle.center);
  t.torusAxis.push_back(circle.axis);
  t.torusE1.push_back(std::cos(phi0) * circle.e1 + std::sin(phi0) * circle.e2);
  t.bigRadius.push_back(circle.radius);
  t.thetaI.push_back(std::atan2(-circle.t, circle.radius));
  t.thetaJ.push_back(std::atan2(circle.distance - circle.t, circle.radius));
  t.phiExtent.push_back(extent);
  t.torusI.push_back(i);
  t.torusJ.push_back(j);
}

// Exterior angle of the region's boundary at u, between circles a and b: the angle between
// their axes projected into the tangent plane at u (ORACLES D.2).
double exteriorAngle(const glm::dvec3& axisA, const glm::dvec3& axisB, const glm::dvec3& u) {
  const glm::dvec3 ma = axisA - glm::dot(axisA, u) * u;
  const glm::dvec3 mb = axisB - glm::dot(axisB, u) * u;
  const double la = glm::length(ma), lb = glm::length(mb);
  if (la == 0.0 || lb == 0.0) return 0.0;
  return std::acos(std::clamp(glm::dot(ma, mb) / (la * lb), -1.0, 1.0));
}

int findRoot(std::vector<int>& parent, int v) {
  while (parent[static_cast<std::size_t>(v)] != v) {
    parent[static_cast<std::size_t>(v)] = parent[static_cast<std::size_t>(parent[static_cast<std::size_t>(v)])];
    v = parent[static_cast<std::size_t>(v)];
  }
  return v;
}

// The exposed arcs of one circle from its valid vertices, ordered along it: an arc runs
// from a vertex where the circle leaves a sphere to the next where it enters one.
template <class Emit> void sweepArcs(std::span<const Entry> list, Emit&& emit) {
  const std::size_t count = list.size();
  const auto firstLeave = std::find_if(list.begin(), list.end(), [](const Entry& e) { return e.leaves; });
  if (firstLeave == list.end()) return;
  const std::size_t start = static_cast<std::size_t>(firstLeave - list.begin());
  std::size_t pending = count;  // index of an unmatched leaving vertex
  for (std::size_t step = 0; step <= count; ++step) {
    const std::size_t idx = (start + step) % count;
    const Entry& e = list[idx];
    if (e.leaves) {
      if (step < count) pending = idx;
    } else if (pending != count) {
      double extent = e.phi - list[pending].phi;
      if (extent < 0.0) extent += kTwoPi;
      if (extent > 0.0) emit(list[pending], e, extent);
      pending = count;
    }
  }
}

void sortAlongCircle(std::span<Entry> list) {
  std::sort(list.begin(), list.end(), [](const Entry& u, const Entry& v) {
    if (u.phi != v.phi) return u.phi < v.phi;
    if (u.third != v.third) return u.third < v.third;
    return u.plus > v.plus;
  });
}

// The winding number of cycle `cycle` of s.arcs around q, seen in the stereographic
// projection from p0 (a point off the cycle): ±1 if q and p0 lie on opposite sides of it,
// 0 if on the same side. Counted as signed crossings of a ray from q by the projected
// arcs, sampled finely (every π/16 of each circle) so that the polygon winds like the arcs
// unless q all but touches the cycle.
int windingNumber(const Scratch& s, int cycle, const glm::dvec3& p0, const glm::dvec3& q) {
  // The ray leaves q in a direction no symmetry of the input favours (the plane's axes
  // rotated by 1 radian), so it does not run through vertices of symmetric inputs.
  const glm::dvec3 g1 = perpendicularTo(p0), g2 = glm::cross(p0, g1);
  const glm::dvec3 f1 = std::cos(1.0) * g1 + std::sin(1.0) * g2, f2 = glm::cross(p0, f1);
  auto project = [&](const glm::dvec3& u) {
    const double w = 1.0 / (1.0 - glm::dot(u, p0));
    return glm::dvec2(glm::dot(u, f1) * w, glm::dot(u, f2) * w);
  };
  const glm::dvec2 at = project(q);
  int winding = 0;
  for (std::size_t k = 0; k < s.arcs.size(); ++k) {
    if (s.cycleOf[k] != cycle) continue;
    const Arc& arc = s.arcs[k];
    const int steps = std::max(4, static_cast<int>(std::ceil(arc.extent * (16.0 / kPi))));
    const double step = arc.extent / steps, cosStep = std::cos(step), sinStep = std::sin(step);
    double c = std::cos(arc.phi0), sn = std::sin(arc.phi0);
    glm::dvec2 prev = project(arc.cosA * arc.axis + arc.sinA * (c * arc.e1 + sn * arc.e2)) - at;
    for (int i = 1; i <= steps; ++i) {
      const double c2 = c * cosStep - sn * sinStep;
      sn = sn * cosStep + c * sinStep;
      c = c2;
      const glm::dvec2 cur = project(arc.cosA * arc.axis + arc.sinA * (c * arc.e1 + sn * arc.e2)) - at;
      if ((prev.y < 0.0) != (cur.y < 0.0)) {
        // Where the segment crosses y = 0: on the ray (x > 0) it counts, upward +1.
        const double cross = prev.x * cur.y - prev.y * cur.x;  // sign of x at the crossing, times dy
        if ((cross > 0.0) == (cur.y > prev.y)) winding += cur.y > prev.y ? 1 : -1;
      }
      prev = cur;
    }
  }
  return winding;
}

// A point of cycle `cycle` (the start of its first arc) and one certainly on its right (the
// centre of that arc's cap: the open cap lies wholly right of the cycle).
glm::dvec3 pointOn(const Scratch& s, int cycle) {
  for (std::size_t k = 0; k < s.arcs.size(); ++k) {
    if (s.cycleOf[k] != cycle) continue;
    const Arc& arc = s.arcs[k];
    return arc.cosA * arc.axis + arc.sinA * (std::cos(arc.phi0) * arc.e1 + std::sin(arc.phi0) * arc.e2);
  }
  return glm::dvec3(0.0);
}
glm::dvec3 pointRightOf(const Scratch& s, int cycle) {
  for (std::size_t k = 0; k < s.arcs.size(); ++k)
    if (s.cycleOf[k] == cycle) return s.arcs[k].axis;
  return glm::dvec3(0.0);
}
bool leftOfCycle(const Scratch& s, int cycle, const glm::dvec3& q) {
  return windingNumber(s, cycle, pointRightOf(s, cycle), q) != 0;
}

// The faces of atom x's exposed region (sphere minus caps): its connected components. A
// face with several boundary cycles (a band between two caps) is one piece of surface; two
// faces (a thin wall, exposed on both sides) can belong to different SES components. The
// cycles are disjoint closed curves with the region on their left, so two cycles bound the
// same face iff each lies left of the other and every other cycle sees them on one side.
// Fills s.cycleFace (face of each cycle, numbered in cycle order); returns the face count.
int groupCyclesIntoFaces(Scratch& s, int cycles) {
  const auto n = static_cast<std::size_t>(std::max(cycles, 0));
  s.cycleFace.assign(n, 0);
  if (cycles <= 1) return 1;
  s.leftOf.assign(n * n, 1);
  for (int i = 0; i < cycles; ++i) {
    const glm::dvec3 q = pointOn(s, i);
    for (int j = 0; j < cycles; ++j)
      if (i != j) s.leftOf[static_cast<std::size_t>(i) * n + static_cast<std::size_t>(j)] = leftOfCycle(s, j, q) ? 1 : 0;
  }
  auto left = [&](std::size_t i, std::size_t j) { return s.leftOf[i * n + j] != 0; };
  s.parent.resize(n);
  for (std::size_t i = 0; i < n; ++i) s.parent[i] = static_cast<int>(i);
  for (std::size_t i = 0; i < n; ++i) {
    for (std::size_t j = i + 1; j < n; ++j) {
      bool same = left(i, j) && left(j, i);
      for (std::size_t k = 0; k < n && same; ++k)
        if (k != i && k != j) same = left(i, k) == left(j, k);
      if (same) s.parent[static_cast<std::size_t>(findRoot(s.parent, static_cast<int>(j)))] = findRoot(s.parent, static_cast<int>(i));
    }
  }
  int faces = 0;
  for (std::size_t i = 0; i < n; ++i) {
    const auto root = static_cast<std::size_t>(findRoot(s.parent, static_cast<int>(i)));
    s.cycleFace[i] = root == i ? faces++ : s.cycleFace[root];
  }
  return faces;
}

// The face that contains the region point u (after groupCyclesIntoFaces): the face whose
// cycles all have u on their left and whose other cycles see u on the face's side.
std::uint32_t faceContaining(Scratch& s, int cycles, const glm::dvec3& u) {
  if (cycles <= 1) return 0;
  const auto n = static_cast<std::size_t>(cycles);
  for (std::size_t i = 0; i < n; ++i) {
    bool inside = leftOfCycle(s, static_cast<int>(i), u);
    for (std::size_t j = 0; j < n && inside; ++j)
      if (j != i) inside = leftOfCycle(s, static_cast<int>(j), u) == (s.leftOf[i * n + j] != 0);
    if (inside) return static_cast<std::uint32_t>(s.cycleFace[i]);
  }
  return 0;
}

void contourPass(const Atoms& a, const Incidence& inc, std::uint32_t x, Scratch& s, ContourBuf& out) {
  std::uint32_t toriCount = 0, convexCount = 0;
  const glm::dvec3 cx = a.c[x];
  const double Rx = a.R[x];

  // Each vertex {x, o1, o2} lies on circles (x, o1) and (x, o2).
  auto& entries = s.entries;
  entries.clear();
  bool anyMerged = false;
  for (std::uint32_t k = inc.vertexBegin[x]; k < inc.vertexBegin[x + 1]; ++k) {
    const std::uint32_t v = inc.vertex[k];
    const std::uint32_t i = inc.atomI[v], j = inc.atomJ[v], l = inc.atomK[v];
    if (inc.edges[v] != 7 || inc.group[v] != 0 || (v + 1 < inc.group.size() && inc.group[v + 1] == 1)) {
      // A triangle of a merged vertex (ORACLES E.6): x's arcs end there on the circles of
      // its two boundary edges; the sphere entered is the other boundary neighbour. Once
      // per merged vertex, at its first triangle that has x.
      anyMerged = true;
      const std::uint32_t first = v - inc.group[v];
      std::uint32_t end = first + 1;
      while (end < inc.group.size() && inc.group[end] == end - first) ++end;
      bool earlier = false;
      for (std::uint32_t t = first; t < v && !earlier; ++t)
        earlier = inc.atomI[t] == x || inc.atomJ[t] == x || inc.atomK[t] == x;
      if (earlier) continue;
      std::uint32_t nbr[2] = {~0u, ~0u};
      int found = 0;
      for (std::uint32_t t = first; t < end; ++t) {
        const std::uint32_t tri[3] = {inc.atomI[t], inc.atomJ[t], inc.atomK[t]};
        for (int e = 0; e < 3; ++e) {
          if (!(inc.edges[t] & (1u << e))) continue;
          const std::uint32_t p0 = tri[e], p1 = tri[(e + 1) % 3];
          if (p0 != x && p1 != x) continue;
          if (found < 2) nbr[found] = p0 == x ? p1 : p0;
          ++found;
        }
      }
      if (found != 2) continue;  // no boundary at x (a probe enclosed by the atoms)
      auto sidePlus = [&](std::uint32_t o, std::uint32_t w) {
        std::uint32_t t3[3] = {x, o, w};
        std::sort(t3, t3 + 3);
        const glm::dvec3 c0 = a.c[t3[0]];
        return glm::dot(inc.probe[first] - c0, glm::cross(a.c[t3[1]] - c0, a.c[t3[2]] - c0)) > 0.0;
      };
      entries.push_back({nbr[0], nbr[1], first, sidePlus(nbr[0], nbr[1]), false, 0.0, 0.0, 0.0, k});
      entries.push_back({nbr[1], nbr[0], first, sidePlus(nbr[1], nbr[0]), false, 0.0, 0.0, 0.0, k});
      continue;
    }
    const std::uint32_t o1 = x == i ? j : i;
    const std::uint32_t o2 = x == l ? j : l;
    const bool plus = inc.plus[v] != 0;
    entries.push_back({o1, o2, v, plus, false, 0.0, 0.0, 0.0, k});
    entries.push_back({o2, o1, v, plus, false, 0.0, 0.0, 0.0, k});
  }
  for (std::uint32_t k = inc.freeBegin[x]; k < inc.freeBegin[x + 1]; ++k)
    entries.push_back({inc.free[k], ~0u, ~0u, false, false, 0.0, 0.0, 0.0, k});
  std::sort(entries.begin(), entries.end(), [](const Entry& u, const Entry& v) {
    return u.other < v.other || (u.other == v.other && u.vertex < v.vertex);
  });

  double turning = 0.0;  // Σ geodesic-curvature terms − Σ exterior angles
  glm::dvec3 vectorArea(0.0);
  double maxCapArea = 0.0;
  s.arcs.clear();
  s.torusArc.clear();

  for (std::size_t g = 0; g < entries.size();) {
    std::size_t end = g;
    while (end < entries.size() && entries[end].other == entries[g].other) ++end;
    std::span<Entry> list(entries.data() + g, entries.data() + end);
    g = end;
    const std::uint32_t o = list[0].other;
    // Free-circle entries sort last; beside vertices (only conceivable at exact tangency)
    // the vertices win.
    while (list.size() > 1 && list.back().vertex == ~0u && list.front().vertex != ~0u) list = list.first(list.size() - 1);

    // The cap of o on x's unit sphere, as the convex patch sees it.
    const double d = glm::distance(cx, a.c[o]);
    const double t = (d * d + Rx * Rx - a.R[o] * a.R[o]) / (2.0 * d);
    const glm::dvec3 axis = (a.c[o] - cx) / d;
    const double cosA = t / Rx;
    const double sinA = std::sqrt(std::max(0.0, 1.0 - cosA * cosA));
    maxCapArea = std::max(maxCapArea, kTwoPi * (1.0 - cosA));

    // For x < o the cap's frame is the circle's own (same axis and e1, bit for bit).
    std::optional<SasCircle> circle;
    glm::dvec3 e1, e2;
    if (x < o) {
      circle = sasCircle(cx, Rx, a.c[o], a.R[o]);
      if (!circle) continue;
      e1 = circle->e1;
      e2 = circle->e2;
    } else {
      e1 = perpendicularTo(axis);
      e2 = glm::cross(axis, e1);
    }
    // The region lies outside the cap, so its boundary runs with decreasing φ about the
    // axis; with the region on the left, an arc φ0→φ1 adds −½[...] to W (ORACLES D.2).
    // (The sines and cosines of the ends are the vertices' own, so no trigonometry.)
    auto addArc = [&](double extent, double cos0, double sin0, double cos1, double sin1) {
      turning += cosA * extent;
      vectorArea -= 0.5 * (sinA * sinA * extent * axis - cosA * sinA * ((sin1 - sin0) * e1 + (cos0 - cos1) * e2));
    };

    if (list[0].vertex == ~0u) {  // a free circle
      addArc(kTwoPi, 1.0, 0.0, 1.0, 0.0);
      s.arcs.push_back({~0u, ~0u, o, axis, e1, e2, cosA, sinA, 0.0, kTwoPi});
      if (circle) {
        pushTorus(out, *circle, 0.0, kTwoPi, x, o);
        s.torusArc.push_back(static_cast<std::uint32_t>(s.arcs.size() - 1));
        ++toriCount;
      }
      continue;
    }

    for (Entry& e : list) {
      const glm::dvec3 p = inc.probe[e.vertex];
      double px, py;
      if (circle) {
        const glm::dvec3 w = p - circle->center;
        px = glm::dot(w, circle->e1);
        py = glm::dot(w, circle->e2);
        e.leaves = e.plus == plusLeavesSphere(x, o, e.third);
      } else {
        // Seen from x > o the circle of (o, x) runs backwards (axis −n, e1 −e1, e2 e2).
        const glm::dvec3 u = p - cx;
        px = glm::dot(u, e1);
        py = glm::dot(u, e2);
        e.leaves = e.plus != plusLeavesSphere(o, x, e.third);
      }
      e.phi = std::atan2(py, px);
      const double len = std::sqrt(px * px + py * py);
      e.cosPhi = len > 0.0 ? px / len : 1.0;
      e.sinPhi = len > 0.0 ? py / len : 0.0;
    }
    sortAlongCircle(list);
    sweepArcs(list, [&](const Entry& from, const Entry& to, double extent) {
      s.arcs.push_back({from.vertex, to.vertex, o, axis, e1, e2, cosA, sinA, from.phi, extent});
      if (circle) {
        pushTorus(out, *circle, from.phi, extent, x, o);
        s.torusArc.push_back(static_cast<std::uint32_t>(s.arcs.size() - 1));
        ++toriCount;
      }
      addArc(extent, from.cosPhi, from.sinPhi, to.cosPhi, to.sinPhi);
      const glm::dvec3 u1 = (inc.probe[to.vertex] - cx) / Rx;
      const glm::dvec3 entered = glm::normalize(a.c[to.third] - cx);
      turning -= exteriorAngle(axis, entered, u1);
    });
  }

  // Boundary cycles: the arc that ends at a vertex continues, on the other circle through
  // it, with the arc that starts there. A free circle is a cycle of its own.
  const std::size_t arcs = s.arcs.size();
  s.parent.resize(arcs);
  for (std::size_t k = 0; k < arcs; ++k) s.parent[k] = static_cast<int>(k);
  for (std::size_t e = 0; e < arcs; ++e) {
    if (s.arcs[e].to == ~0u) continue;
    for (std::size_t st = 0; st < arcs; ++st) {
      if (s.arcs[st].from == s.arcs[e].to) {
        s.parent[static_cast<std::size_t>(findRoot(s.parent, static_cast<int>(e)))] = findRoot(s.parent, static_cast<int>(st));
        break;
      }
    }
  }
  s.cycleOf.resize(arcs);
  int cycles = 0;
  for (std::size_t k = 0; k < arcs; ++k) {
    if (findRoot(s.parent, static_cast<int>(k)) == static_cast<int>(k)) s.cycleOf[k] = cycles++;
  }
  for (std::size_t k = 0; k < arcs; ++k) s.cycleOf[k] = s.cycleOf[static_cast<std::size_t>(findRoot(s.parent, static_cast<int>(k)))];

  // Faces (connected components of the exposed region), for the SES components.
  const int faces = groupCyclesIntoFaces(s, cycles);
  for (std::size_t k = 0; k < s.torusArc.size(); ++k)
    out.torusFace.push_back(static_cast<std::uint32_t>(s.cycleFace[static_cast<std::size_t>(s.cycleOf[s.torusArc[k]])]));
  inc.faceCount[x] = static_cast<std::uint32_t>(faces);
  for (const Entry& e : entries) {
    std::uint32_t face = 0;
    for (std::size_t k = 0; k < arcs; ++k) {
      const Arc& arc = s.arcs[k];
      const bool mine = e.vertex == ~0u ? arc.from == ~0u && arc.other == e.other : arc.from == e.vertex || arc.to == e.vertex;
      if (mine) {
        face = static_cast<std::uint32_t>(s.cycleFace[static_cast<std::size_t>(s.cycleOf[k])]);
        break;
      }
    }
    if (e.vertex == ~0u) inc.freeFace[e.slot] = face;
    else inc.vertexFace[e.slot] = face;
  }
  if (anyMerged) {
    // Every triangle of a merged vertex takes the face of the arcs that end there; none
    // (~0u) where x has no arc there.
    for (std::uint32_t k = inc.vertexBegin[x]; k < inc.vertexBegin[x + 1]; ++k) {
      const std::uint32_t v = inc.vertex[k];
      if (inc.edges[v] == 7 && inc.group[v] == 0 && !(v + 1 < inc.group.size() && inc.group[v + 1] == 1)) continue;
      const std::uint32_t first = v - inc.group[v];
      std::uint32_t face = ~0u;
      for (std::size_t m = 0; m < arcs; ++m) {
        const Arc& arc = s.arcs[m];
        if (arc.from == first || arc.to == first) {
          face = static_cast<std::uint32_t>(s.cycleFace[static_cast<std::size_t>(s.cycleOf[m])]);
          break;
        }
      }
      inc.vertexFace[k] = face;
    }
  }
  if (x == inc.extremeAtom) *inc.extremeFace = faceContaining(s, cycles, glm::dvec3(1.0, 0.0, 0.0));

  double area = 0.0;
  const CapState caps = inc.capState[x];
  if (caps == CapState::None) {
    area = 4.0 * kPi;
    cycles = 0;
    vectorArea = glm::dvec3(0.0);
  } else if (caps == CapState::Covered || cycles == 0) {
    cycles = 0;
  } else {
    // Gauss–Bonnet fixes the area modulo 4π (2πχ ≡ −2π·cycles). The area is at most 4π
    // minus any cap, so a value above 4π minus half the largest bounding cap is a tiny
    // area that wrapped around.
    area = std::fmod(turning - kTwoPi * cycles, 2.0 * kTwoPi);
    if (area < 0.0) area += 2.0 * kTwoPi;
    if (area > 2.0 * kTwoPi - 0.5 * maxCapArea) area -= 2.0 * kTwoPi;
    area = std::max(area, 0.0);
  }
  if (cycles > 0 || area > 0.0) {
    out.convexCenter.push_back(cx);
    out.convexRadius.push_back(a.r[x]);
    out.convexAtom.push_back(x);
    out.convexArea.push_back(a.r[x] * a.r[x] * area);
    out.convexVectorArea.push_back(vectorArea);
    ++convexCount;
  }
  out.convexCount.push_back(convexCount);
  out.toriCount.push_back(toriCount);
}

// ---------------------------------------------------------------------------------------
// Assembly: every array is a concatenation of per-atom segments in atom order (per probe
// for the clipping planes), so a full build concatenates the pieces and a partial update
// splices fresh segments between the old ones.

// Runs body(k, scratch, buffer) for k in [0, count) in parallel chunks of kBlock, recording
// where each chunk's output lies.
template <class Buf, class BufOf, class Body>
void runChunks(tbb::enumerable_thread_specific<Scratch>& tls, std::size_t count, std::vector<Piece<Buf>>& pieces,
               BufOf bufOf, Body body) {
  for (Scratch& s : tls) bufOf(s).clear();
  const std::size_t chunks = (count + kBlock - 1) / kBlock;
  pieces.assign(chunks, Piece<Buf>{});
  tbb::parallel_for(std::size_t{0}, chunks, [&](std::size_t c) {
    Scratch& s = tls.local();
    Buf& buf = bufOf(s);
    if (buf.size(2) == 0) buf.reserve(count);  // this thread's first chunk of the pass
    Piece<Buf>& piece = pieces[c];
    piece.buf = &buf;
    for (int g = 0; g < 3; ++g) piece.begin[static_cast<std::size_t>(g)] = buf.size(g);
    for (std::size_t k = c * kBlock; k < std::min(count, (c + 1) * kBlock); ++k) body(k, s, buf);
    for (int g = 0; g < 3; ++g) piece.end[static_cast<std::size_t>(g)] = buf.size(g);
  });
}

// Where each piece's group g goes in the concatenation; returns the total.
template <class Buf>
std::size_t pieceOffsets(const std::vector<Piece<Buf>>& pieces, std::size_t g, std::vector<std::size_t>& offset) {
  offset.resize(pieces.size() + 1);
  offset[0] = 0;
  for (std::size_t c = 0; c < pieces.size(); ++c) offset[c + 1] = offset[c] + (pieces[c].end[g] - pieces[c].begin[g]);
  return offset.back();
}

// One field of a pass buffer and where its concatenation goes.
template <class Buf, class T> struct Field {
  std::vector<T> Buf::*member;
  std::vector<T>* to;
  std::size_t group;
};

// Concatenates the fields of the pieces, in chunk order, in one parallel pass.
template <class Buf, class... T>
void gatherPieces(const std::vector<Piece<Buf>>& pieces, std::array<std::vector<std::size_t>, 3>& offset,
                  const Field<Buf, T>&... fields) {
  for (std::size_t g = 0; g < 3; ++g) pieceOffsets(pieces, g, offset[g]);
  (fields.to->resize(offset[fields.group].back()), ...);
  tbb::parallel_for(std::size_t{0}, pieces.size(), [&](std::size_t c) {
    const Piece<Buf>& piece = pieces[c];
    auto copy = [&](const auto& field) {
      const auto& from = (*piece.buf).*(field.member);
      const std::size_t g = field.group;
      std::copy(from.begin() + static_cast<std::ptrdiff_t>(piece.begin[g]),
                from.begin() + static_cast<std::ptrdiff_t>(piece.end[g]),
                field.to->begin() + static_cast<std::ptrdiff_t>(offset[g][c]));
    };
    (copy(fields), ...);
  });
}

// Segment starts from per-item lengths: begin[0] = 0, begin[i + 1] = begin[i] + len[i].
void prefix(std::span<const std::uint32_t> len, std::vector<std::uint32_t>& begin) {
  begin.resize(len.size() + 1);
  begin[0] = 0;
  for (std::size_t i = 0; i < len.size(); ++i) begin[i + 1] = begin[i] + len[i];
}

// The arrays after replacing the segments of the atoms in `changed` (ascending): old
// segments at oldBegin, fresh ones (one per changed atom, in order) at freshBegin, new
// starts at newBegin (see newStarts). Unchanged runs move in one copy each.
struct Splice {
  std::span<const std::uint32_t> oldBegin, newBegin, changed, freshBegin;

  template <class T> void operator()(std::vector<T>& arr, const std::vector<T>& fresh, std::vector<T>& tmp) const {
    const std::size_t n = oldBegin.size() - 1;
    tmp.resize(newBegin[n]);
    tbb::parallel_for(tbb::blocked_range<std::size_t>(0, changed.size() + 1, 32), [&](const auto& range) {
      for (std::size_t c = range.begin(); c != range.end(); ++c) {
        const std::size_t runBegin = c == 0 ? 0 : changed[c - 1] + 1;
        const std::size_t runEnd = c == changed.size() ? n : changed[c];
        if (runEnd > runBegin)
          std::copy(arr.begin() + oldBegin[runBegin], arr.begin() + oldBegin[runEnd], tmp.begin() + newBegin[runBegin]);
        if (c < changed.size())
          std::copy(fresh.begin() + freshBegin[c], fresh.begin() + freshBegin[c + 1], tmp.begin() + newBegin[changed[c]]);
      }
    });
    arr.swap(tmp);
  }
};

// New segment starts: old lengths for unchanged atoms, fresh lengths for changed ones.
void newStarts(std::span<const std::uint32_t> oldBegin, std::span<const std::uint32_t> changed,
               std::span<const std::uint32_t> freshBegin, std::vector<std::uint32_t>& newBegin) {
  const std::size_t n = oldBegin.size() - 1;
  newBegin.resize(n + 1);
  newBegin[0] = 0;
  std::size_t c = 0;
  for (std::size_t x = 0; x < n; ++x) {
    std::uint32_t len;
    if (c < changed.size() && changed[c] == x) {
      len = freshBegin[c + 1] - freshBegin[c];
      ++c;
    } else {
      len = oldBegin[x + 1] - oldBegin[x];
    }
    newBegin[x + 1] = newBegin[x] + len;
  }
}

template <class T> bool sameBits(std::span<const T> a, std::span<const T> b) {
  return a.size() == b.size() && (a.empty() || std::memcmp(a.data(), b.data(), a.size() * sizeof(T)) == 0);
}

}  // namespace

// ---------------------------------------------------------------------------------------

struct SesBuilder::State {
  SesParams params;
  std::vector<glm::dvec3> centers;
  std::vector<double> radii, R;
  std::vector<char> buried;
  std::vector<CapState> capState;
  NeighbourGrid grid;
  NeighbourGrid probeGrid;
  std::vector<double> probeRadii;
  tbb::enumerable_thread_specific<Scratch> tls;


  // Vertex pass: the concave arrays of `out` in owner segments, and beside them.
  std::vector<std::uint32_t> concaveBegin;  // per owner, n + 1
  std::vector<std::uint8_t> vertexPlus;     // per concave patch: probe is p+ of its triple
  std::vector<std::uint8_t> vertexEdges;    // per concave patch: boundary edges (merged vertices)
  std::vector<std::uint32_t> vertexGroup;   // per concave patch: distance back to its merged vertex's first
  std::vector<std::uint32_t> freeBegin;     // per owner, n + 1
  std::vector<std::uint32_t> freeOther;     // free circles (owner, other > owner)
  // Contour pass: the convex and tori arrays of `out` in atom segments.
  std::vector<std::uint32_t> convexBegin, toriBegin;
  // Who touches what: per atom, its concave patches and the other atoms of its free circles.
  std::vector<std::uint32_t> incVertexBegin, incVertex, incFreeBegin, incFree;
  // Faces of each atom's exposed region (contourPass), for the components: per atom the
  // count, per incidence the face it bounds, per torus its face on atom i; and the face of
  // the atom reaching furthest in +x (on the outer surface).
  std::vector<std::uint32_t> faceCount, incVertexFace, incFreeFace, torusFace;
  std::uint32_t extremeAtom = 0, extremeFace = 0;

  PatchList out;
  SesUpdateStats stats;
  bool built = false;

  // Pieces and fresh arrays of the passes (reused).
  std::vector<Piece<VertexBuf>> vertexPieces;
  std::vector<Piece<ContourBuf>> contourPieces;
  std::vector<Piece<PlaneBuf>> planePieces;
  std::array<std::vector<std::size_t>, 3> offsets;
  VertexBuf fv;   // fresh vertex-pass output of the atoms listed
  ContourBuf fc;  // fresh contour-pass output
  // Fresh planes of the probes listed: partners, counts, starts, planes.
  std::vector<std::uint32_t> fpPartner, fpCount, fpBegin;
  std::vector<Plane> fpPlanes;
  std::vector<std::uint32_t> list, list2, freshBegin, freshFreeBegin, newBegin, tmpIndex;
  std::vector<std::uint8_t> mark;
  // Scratch of partialUpdate, kept so that a trajectory does not allocate per frame.
  struct UpdateTmp {
    std::vector<glm::dvec3> v3, removed;
    std::vector<double> f64;
    std::vector<std::uint32_t> u32, oldConcaveBegin, oldClipBegin, oldClipCount, clipCount, clipBegin;
    std::vector<std::uint8_t> u8, dirty;
    std::vector<Plane> planes;
    std::vector<std::uint32_t> faceBegin, faceParent, faceLabel, vertexNode;
    std::vector<std::uint32_t> oldIncVertexBegin, oldIncVertexFace, oldIncFreeBegin, oldIncFreeFace;
  } tmp;

  Atoms atoms() const { return {centers, radii, R, buried, params.probeRadius}; }
  Incidence incidence() {
    return {out.concave.probe, out.concave.atomI, out.concave.atomJ, out.concave.atomK, vertexPlus, vertexEdges, vertexGroup, incVertexBegin,
            incVertex,         incFreeBegin,      incFree,           capState,          incVertexFace, incFreeFace,
            faceCount,         extremeAtom,       &extremeFace};
  }
  void findExtremeAtom();
  // Whether atom i's extended sphere lies inside another's: only atoms closer than the
  // difference of the radii can contain it, a small search (a superset, then the exact test).
  bool buriedByContainment(std::uint32_t i, std::vector<std::uint32_t>& near) const {
    near.clear();
    grid.atomsNear(centers[i], 1e-6 - radii[i], near);
    std::erase(near, i);
    return isBuriedByContainment(i, near, centers, R);
  }

  void fullBuild();
  void partialUpdate(std::span<const std::uint32_t> moved, std::span<const glm::dvec3> newCenters);
  void vertexPassOf(std::span<const std::uint32_t> owners);
  void contourPassOf(std::span<const std::uint32_t> atoms);
  void planesOf(std::span<const std::uint32_t> probes);
  void buildIncidence();
  void labelComponents();
};

// The vertex pass for `owners` (ascending) into fv (owner counts in fv.concaveCount,
// fv.freeCount, one per owner).
void SesBuilder::State::vertexPassOf(std::span<const std::uint32_t> owners) {
  const Atoms a = atoms();
  runChunks(tls, owners.size(), vertexPieces, [](Scratch& s) -> VertexBuf& { return s.vertexOut; },
            [&](std::size_t k, Scratch& s, VertexBuf& buf) {
              const std::uint32_t x = owners[k];
              if (buried[x]) {
                buf.concaveCount.push_back(0);
                buf.freeCount.push_back(0);
                capState[x] = CapState::Covered;
                return;
              }
              s.row.clear();
              grid.neighbours(x, s.row);
              vertexPass(a, x, s.row, s, buf, capState[x]);
            });
  gatherPieces(vertexPieces, offsets, Field{&VertexBuf::probe, &fv.probe, 0}, Field{&VertexBuf::dirI, &fv.dirI, 0},
               Field{&VertexBuf::dirJ, &fv.dirJ, 0}, Field{&VertexBuf::dirK, &fv.dirK, 0},
               Field{&VertexBuf::atomI, &fv.atomI, 0}, Field{&VertexBuf::atomJ, &fv.atomJ, 0},
               Field{&VertexBuf::atomK, &fv.atomK, 0}, Field{&VertexBuf::plus, &fv.plus, 0},
               Field{&VertexBuf::edges, &fv.edges, 0}, Field{&VertexBuf::group, &fv.group, 0},
               Field{&VertexBuf::freeOther, &fv.freeOther, 1}, Field{&VertexBuf::concaveCount, &fv.concaveCount, 2},
               Field{&VertexBuf::freeCount, &fv.freeCount, 2});
}

void SesBuilder::State::contourPassOf(std::span<const std::uint32_t> list_) {
  const Atoms a = atoms();
  const Incidence inc = incidence();
  runChunks(tls, list_.size(), contourPieces, [](Scratch& s) -> ContourBuf& { return s.contourOut; },
            [&](std::size_t k, Scratch& s, ContourBuf& buf) {
              const std::uint32_t x = list_[k];
              if (buried[x]) {
                buf.convexCount.push_back(0);
                buf.toriCount.push_back(0);
                faceCount[x] = 0;
                return;
              }
              contourPass(a, inc, x, s, buf);
            });
  using B = ContourBuf;
  gatherPieces(contourPieces, offsets, Field{&B::convexCenter, &fc.convexCenter, 0}, Field{&B::convexRadius, &fc.convexRadius, 0},
               Field{&B::convexAtom, &fc.convexAtom, 0}, Field{&B::convexArea, &fc.convexArea, 0},
               Field{&B::convexVectorArea, &fc.convexVectorArea, 0}, Field{&B::torusCenter, &fc.torusCenter, 1},
               Field{&B::torusAxis, &fc.torusAxis, 1}, Field{&B::torusE1, &fc.torusE1, 1},
               Field{&B::bigRadius, &fc.bigRadius, 1}, Field{&B::thetaI, &fc.thetaI, 1}, Field{&B::thetaJ, &fc.thetaJ, 1},
               Field{&B::phiExtent, &fc.phiExtent, 1}, Field{&B::torusI, &fc.torusI, 1}, Field{&B::torusJ, &fc.torusJ, 1},
               Field{&B::torusFace, &fc.torusFace, 1}, Field{&B::convexCount, &fc.convexCount, 2},
               Field{&B::toriCount, &fc.toriCount, 2});
}

// Self-intersections (ORACLES A.5): every pair of probe positions closer than 2 rp cuts
// both probe spheres along their bisector plane. The probe positions sit in a neighbour
// grid of their own (probeGrid: radius rp each, no probe), whose neighbour relation is
// exactly |p − q| < 2 rp. No cap on the number of planes per patch. Fills fp with the
// planes of the probes listed (ascending).
void SesBuilder::State::planesOf(std::span<const std::uint32_t> probes) {
  const auto& probe = out.concave.probe;
  runChunks(tls, probes.size(), planePieces, [](Scratch& s) -> PlaneBuf& { return s.planeOut; },
            [&](std::size_t k, Scratch& s, PlaneBuf& buf) {
              const std::uint32_t a = probes[k];
              s.row.clear();
              probeGrid.neighbours(a, s.row);
              std::uint32_t count = 0;
              for (const std::uint32_t b : s.row) {
                const glm::dvec3 v = probe[b] - probe[a];
                if (!(glm::dot(v, v) > 0.0)) continue;  // coincident probes (cospherical atoms): no plane
                buf.partner.push_back(b);
                ++count;
              }
              buf.count.push_back(count);
            });
  gatherPieces(planePieces, offsets, Field{&PlaneBuf::partner, &fpPartner, 0}, Field{&PlaneBuf::count, &fpCount, 2});
  prefix(fpCount, fpBegin);
  fpPlanes.resize(fpPartner.size());
  tbb::parallel_for(tbb::blocked_range<std::size_t>(0, probes.size(), kBlock), [&](const auto& range) {
    for (std::size_t k = range.begin(); k != range.end(); ++k) {
      const glm::dvec3& pa = probe[probes[k]];
      for (std::uint32_t i = fpBegin[k]; i < fpBegin[k + 1]; ++i) {
        const glm::dvec3& pb = probe[fpPartner[i]];
        const glm::dvec3 v = pb - pa;
        const double len = glm::length(v);
        const glm::dvec3 nrm = v / len;
        const glm::dvec3 mid = 0.5 * (pa + pb);
        fpPlanes[i] = Plane(nrm, -glm::dot(nrm, mid));
      }
    }
  });
}

// Per atom, the concave patches and free circles it belongs to (a counting sort, so each
// list is in patch order).
void SesBuilder::State::buildIncidence() {
  const std::size_t n = centers.size();
  const auto& cv = out.concave;
  const std::size_t v = cv.size();
  incVertexBegin.assign(n + 2, 0);
  for (std::size_t k = 0; k < v; ++k) {
    ++incVertexBegin[cv.atomI[k] + 2];
    ++incVertexBegin[cv.atomJ[k] + 2];
    ++incVertexBegin[cv.atomK[k] + 2];
  }
  for (std::size_t i = 0; i < n; ++i) incVertexBegin[i + 2] += incVertexBegin[i + 1];
  incVertex.resize(incVertexBegin[n + 1]);
  // incVertexBegin[i + 1] is atom i's cursor; afterwards it is atom i's end = i + 1's start.
  for (std::size_t k = 0; k < v; ++k) {
    const auto id = static_cast<std::uint32_t>(k);
    incVertex[incVertexBegin[cv.atomI[k] + 1]++] = id;
    incVertex[incVertexBegin[cv.atomJ[k] + 1]++] = id;
    incVertex[incVertexBegin[cv.atomK[k] + 1]++] = id;
  }
  incVertexBegin.pop_back();
  incFreeBegin.assign(n + 2, 0);
  for (std::size_t x = 0; x < n; ++x) {
    for (std::uint32_t f = freeBegin[x]; f < freeBegin[x + 1]; ++f) {
      ++incFreeBegin[x + 2];
      ++incFreeBegin[freeOther[f] + 2];
    }
  }
  for (std::size_t i = 0; i < n; ++i) incFreeBegin[i + 2] += incFreeBegin[i + 1];
  incFree.resize(incFreeBegin[n + 1]);
  for (std::size_t x = 0; x < n; ++x) {
    for (std::uint32_t f = freeBegin[x]; f < freeBegin[x + 1]; ++f) {
      const std::uint32_t o = freeOther[f];
      incFree[incFreeBegin[x + 1]++] = o;
      incFree[incFreeBegin[o + 1]++] = static_cast<std::uint32_t>(x);
    }
  }
  incFreeBegin.pop_back();
}

// The atom whose extended sphere reaches furthest in +x: the SAS point there is exposed,
// so the SES patch of that atom facing +x is on the outer surface.
void SesBuilder::State::findExtremeAtom() {
  double best = -std::numeric_limits<double>::infinity();
  extremeAtom = 0;
  for (std::size_t i = 0; i < centers.size(); ++i) {
    if (buried[i]) continue;
    const double reach = centers[i].x + R[i];
    if (reach > best) best = reach, extremeAtom = static_cast<std::uint32_t>(i);
  }
  extremeFace = 0;
}

// SES components: the faces of all atoms (nodes), joined where they share a vertex (its
// three atoms' faces) or a free circle (its two atoms' faces); tori and concave patches
// take their faces' component. The outer component, 0, is the extreme atom's face facing
// +x; the others are numbered in order of their first patch (convex, tori, concave). An
// atom exposed to two components (a one-atom wall around a cavity) has one convex patch;
// it takes the lower number.
void SesBuilder::State::labelComponents() {
  const std::size_t n = centers.size();
  auto& cv = out.concave;
  std::vector<std::uint32_t>& faceBegin = tmp.faceBegin;
  prefix(std::span<const std::uint32_t>(faceCount.data(), n), faceBegin);
  const std::size_t faces = n == 0 ? 0 : faceBegin[n];
  std::vector<std::uint32_t>& parent = tmp.faceParent;
  parent.resize(faces);
  for (std::size_t f = 0; f < faces; ++f) parent[f] = static_cast<std::uint32_t>(f);
  auto find = [&](std::uint32_t f) {
    while (parent[f] != f) f = parent[f] = parent[parent[f]];
    return f;
  };
  auto unite = [&](std::uint32_t f, std::uint32_t g) {
    f = find(f);
    g = find(g);
    if (f != g) parent[std::max(f, g)] = std::min(f, g);
  };
  std::vector<std::uint32_t>& vertexFace = tmp.vertexNode;
  vertexFace.assign(cv.size(), ~0u);
  for (std::size_t x = 0; x < n; ++x) {
    if (faceCount[x] == 0) continue;
    for (std::uint32_t k = incVertexBegin[x]; k < incVertexBegin[x + 1]; ++k) {
      if (incVertexFace[k] == ~0u) continue;  // a merged vertex with no arc of x
      const std::uint32_t f = faceBegin[x] + incVertexFace[k];
      std::uint32_t& v = vertexFace[incVertex[k]];
      if (v == ~0u) v = f;
      else unite(v, f);
    }
    for (std::uint32_t k = incFreeBegin[x]; k < incFreeBegin[x + 1]; ++k) {
      const std::uint32_t o = incFree[k];
      if (o < x || faceCount[o] == 0) continue;
      for (std::uint32_t m = incFreeBegin[o]; m < incFreeBegin[o + 1]; ++m)
        if (incFree[m] == x) unite(faceBegin[x] + incFreeFace[k], faceBegin[o] + incFreeFace[m]);
    }
  }
  // The triangles of a merged vertex are one patch.
  for (std::size_t v = 0; v < cv.size(); ++v) {
    if (vertexGroup[v] == 0) continue;
    std::uint32_t& first = vertexFace[v - vertexGroup[v]];
    if (vertexFace[v] == ~0u) continue;
    if (first == ~0u) first = vertexFace[v];
    else unite(first, vertexFace[v]);
  }
  for (std::size_t v = 0; v < cv.size(); ++v)
    if (vertexGroup[v] != 0) vertexFace[v] = vertexFace[v - vertexGroup[v]];
  std::vector<std::uint32_t>& label = tmp.faceLabel;
  label.assign(faces, ~0u);
  std::uint32_t components = 0;
  auto labelOf = [&](std::uint32_t f) {
    std::uint32_t& l = label[find(f)];
    if (l == ~0u) l = components++;
    return l;
  };
  if (n > 0 && extremeAtom < n && faceCount[extremeAtom] > 0)
    labelOf(faceBegin[extremeAtom] + std::min(extremeFace, faceCount[extremeAtom] - 1));
  out.convex.component.resize(out.convex.size());
  for (std::size_t k = 0; k < out.convex.size(); ++k) {
    const std::uint32_t x = out.convex.atom[k];
    std::uint32_t lowest = ~0u;
    for (std::uint32_t f = faceBegin[x]; f < faceBegin[x + 1]; ++f) lowest = std::min(lowest, labelOf(f));
    out.convex.component[k] = lowest == ~0u ? 0 : lowest;
  }
  out.tori.component.resize(out.tori.size());
  for (std::size_t t = 0; t < out.tori.size(); ++t) out.tori.component[t] = labelOf(faceBegin[out.tori.atomI[t]] + torusFace[t]);
  cv.component.resize(cv.size());
  for (std::size_t v = 0; v < cv.size(); ++v) {
    if (vertexFace[v] != ~0u) {
      cv.component[v] = labelOf(vertexFace[v]);
    } else if (vertexGroup[v] != 0) {
      cv.component[v] = cv.component[v - vertexGroup[v]];
    } else {
      // A merged vertex with no arc at all (a probe trapped where it touches all its atoms,
      // the centre of a cube) is a component of its own; any other vertex without a face, 0.
      const bool merged = vertexEdges[v] != 7 || (v + 1 < cv.size() && vertexGroup[v + 1] == 1);
      cv.component[v] = merged ? components++ : 0;
    }
  }
  out.componentCount = components;
}

void SesBuilder::State::fullBuild() {
  const std::size_t n = centers.size();
  const double rp = params.probeRadius;
  out = PatchList();
  out.params.surface = SurfaceKind::Ses;
  out.params.probeRadius = rp;
  out.params.atomCount = static_cast<std::uint32_t>(n);
  R.resize(n);
  for (std::size_t i = 0; i < n; ++i) R[i] = radii[i] + rp;
  buried.assign(n, 0);
  capState.assign(n, CapState::None);

  grid.build(centers, radii, rp);
  // Burial by containment first: every pass after reads it for all neighbours.
  tbb::parallel_for(tbb::blocked_range<std::size_t>(0, n, kBlock), [&](const auto& range) {
    auto& near = tls.local().row;
    for (std::size_t i = range.begin(); i != range.end(); ++i) buried[i] = buriedByContainment(static_cast<std::uint32_t>(i), near);
  });

  list.resize(n);
  for (std::size_t i = 0; i < n; ++i) list[i] = static_cast<std::uint32_t>(i);

  // Vertex pass over every atom: the fresh arrays are the patch list's.
  vertexPassOf(list);
  auto& cv = out.concave;
  cv.probe.swap(fv.probe);
  cv.dirI.swap(fv.dirI);
  cv.dirJ.swap(fv.dirJ);
  cv.dirK.swap(fv.dirK);
  cv.atomI.swap(fv.atomI);
  cv.atomJ.swap(fv.atomJ);
  cv.atomK.swap(fv.atomK);
  vertexPlus.swap(fv.plus);
  vertexEdges.swap(fv.edges);
  vertexGroup.swap(fv.group);
  freeOther.swap(fv.freeOther);
  prefix(fv.concaveCount, concaveBegin);
  prefix(fv.freeCount, freeBegin);

  buildIncidence();
  incVertexFace.assign(incVertex.size(), 0);
  incFreeFace.assign(incFree.size(), 0);
  faceCount.assign(n, 0);
  findExtremeAtom();

  contourPassOf(list);
  auto& cx = out.convex;
  auto& tr = out.tori;
  cx.center.swap(fc.convexCenter);
  cx.radius.swap(fc.convexRadius);
  cx.atom.swap(fc.convexAtom);
  cx.area.swap(fc.convexArea);
  cx.vectorArea.swap(fc.convexVectorArea);
  tr.center.swap(fc.torusCenter);
  tr.axis.swap(fc.torusAxis);
  tr.e1.swap(fc.torusE1);
  tr.bigRadius.swap(fc.bigRadius);
  tr.thetaI.swap(fc.thetaI);
  tr.thetaJ.swap(fc.thetaJ);
  tr.phiExtent.swap(fc.phiExtent);
  tr.atomI.swap(fc.torusI);
  tr.atomJ.swap(fc.torusJ);
  torusFace.swap(fc.torusFace);
  prefix(fc.convexCount, convexBegin);
  prefix(fc.toriCount, toriBegin);

  // Clipping planes of every probe.
  const std::size_t probes = cv.size();
  probeRadii.assign(probes, rp);
  probeGrid.build(cv.probe, probeRadii, 0.0);
  list.resize(probes);
  for (std::size_t i = 0; i < probes; ++i) list[i] = static_cast<std::uint32_t>(i);
  planesOf(list);
  out.clipPlanes.swap(fpPlanes);
  cv.clipCount.swap(fpCount);
  cv.clipBegin.resize(probes);
  std::uint32_t at = 0;
  for (std::size_t k = 0; k < probes; ++k) {
    cv.clipBegin[k] = at;
    at += cv.clipCount[k];
  }

  labelComponents();
}

// Lindow et al. 2010, end of Sect. 4.1: only atoms within reach of a moved atom's old or
// new position can change. An owner's vertices depend on its neighbours and their burial;
// an atom's contour on the vertices and free circles that touch it; a probe's planes on
// the probes within 2 rp. Each is recomputed exactly as a full build would, and the fresh
// segments are spliced between the old ones, so the arrays equal a full build's.
void SesBuilder::State::partialUpdate(std::span<const std::uint32_t> moved, std::span<const glm::dvec3> newCenters) {
  const std::size_t n = centers.size();
  stats = SesUpdateStats{};
  stats.moved = moved.size();
  if (moved.empty()) return;
  // Past a fraction of the atoms the bookkeeping costs more than it saves.
  if (moved.size() * 8 > n) {
    for (std::size_t k = 0; k < moved.size(); ++k) centers[moved[k]] = newCenters[k];
    fullBuild();
    stats.owners = stats.contours = n;
    stats.probes = out.concave.size();
    stats.full = true;
    return;
  }
  constexpr std::uint8_t kNear = 1, kOwner = 2, kContour = 4;
  mark.assign(n, 0);
  auto& rowBuf = tls.local().row;
  // Near: the moved atoms and their neighbours at the old positions (the grid still holds
  // them) and, after the move, at the new ones.
  for (const std::uint32_t m : moved) {
    mark[m] |= kNear;
    rowBuf.clear();
    grid.neighbours(m, rowBuf);
    for (const std::uint32_t j : rowBuf) mark[j] |= kNear;
  }
  for (std::size_t k = 0; k < moved.size(); ++k) centers[moved[k]] = newCenters[k];
  grid.build(centers, radii, params.probeRadius);
  for (const std::uint32_t m : moved) {
    rowBuf.clear();
    grid.neighbours(m, rowBuf);
    for (const std::uint32_t j : rowBuf) mark[j] |= kNear;
  }
  // Burial can change only near the move; where it does, the neighbours' vertices change.
  for (std::size_t i = 0; i < n; ++i) {
    if (!(mark[i] & kNear)) continue;
    mark[i] |= kOwner;
    const auto x = static_cast<std::uint32_t>(i);
    const char now = buriedByContainment(x, rowBuf) ? 1 : 0;
    if (now != buried[i]) {
      buried[i] = now;
      rowBuf.clear();
      grid.neighbours(x, rowBuf);
      for (const std::uint32_t j : rowBuf) mark[j] |= kOwner;
    }
  }
  list.clear();
  for (std::size_t i = 0; i < n; ++i)
    if (mark[i] & kOwner) list.push_back(static_cast<std::uint32_t>(i));
  stats.owners = list.size();

  // Vertex pass of those owners; an owner whose output differs changes the contours of
  // every atom its old and new vertices and free circles touch, and the planes near them.
  vertexPassOf(list);
  prefix(fv.concaveCount, freshBegin);
  prefix(fv.freeCount, freshFreeBegin);
  auto& cv = out.concave;
  list2.clear();  // owners whose vertices changed
  for (std::size_t t = 0; t < list.size(); ++t) {
    const std::uint32_t x = list[t];
    mark[x] |= kContour;
    const std::size_t o0 = concaveBegin[x], o1 = concaveBegin[x + 1], f0 = freshBegin[t], f1 = freshBegin[t + 1];
    const std::size_t g0 = freeBegin[x], g1 = freeBegin[x + 1], h0 = freshFreeBegin[t], h1 = freshFreeBegin[t + 1];
    auto same = [&](const auto& oldField, const auto& freshField) {
      using T = typename std::remove_cvref_t<decltype(oldField)>::value_type;
      return sameBits<T>(std::span<const T>(oldField).subspan(o0, o1 - o0),
                         std::span<const T>(freshField).subspan(f0, f1 - f0));
    };
    const bool unchanged =
        same(cv.probe, fv.probe) && same(cv.dirI, fv.dirI) && same(cv.dirJ, fv.dirJ) && same(cv.dirK, fv.dirK) &&
        same(cv.atomI, fv.atomI) && same(cv.atomJ, fv.atomJ) && same(cv.atomK, fv.atomK) && same(vertexPlus, fv.plus) &&
        same(vertexEdges, fv.edges) && same(vertexGroup, fv.group) &&
        sameBits<std::uint32_t>(std::span<const std::uint32_t>(freeOther).subspan(g0, g1 - g0),
                                std::span<const std::uint32_t>(fv.freeOther).subspan(h0, h1 - h0));
    if (unchanged) continue;
    list2.push_back(x);
    // (The triangles of a merged vertex need not have their owner as atom I.)
    for (std::size_t v = o0; v < o1; ++v)
      mark[cv.atomI[v]] |= kContour, mark[cv.atomJ[v]] |= kContour, mark[cv.atomK[v]] |= kContour;
    for (std::size_t v = f0; v < f1; ++v)
      mark[fv.atomI[v]] |= kContour, mark[fv.atomJ[v]] |= kContour, mark[fv.atomK[v]] |= kContour;
    for (std::size_t f = g0; f < g1; ++f) mark[freeOther[f]] |= kContour;
    for (std::size_t f = h0; f < h1; ++f) mark[fv.freeOther[f]] |= kContour;
  }

  // Old probes of changed owners, before the splice: their planes' partners need updates.
  auto& removed = tmp.removed;
  removed.clear();
  for (const std::uint32_t x : list2)
    removed.insert(removed.end(), cv.probe.begin() + concaveBegin[x], cv.probe.begin() + concaveBegin[x + 1]);
  const auto& oldConcaveBegin = tmp.oldConcaveBegin = concaveBegin;
  const auto& oldClipBegin = tmp.oldClipBegin = cv.clipBegin;
  const auto& oldClipCount = tmp.oldClipCount = cv.clipCount;

  // Splice the vertex-pass arrays.
  {
    newStarts(concaveBegin, list, freshBegin, newBegin);
    const Splice splice{concaveBegin, newBegin, list, freshBegin};
    auto& t3 = tmp.v3;
    auto& tu = tmp.u32;
    auto& t8 = tmp.u8;
    splice(cv.probe, fv.probe, t3);
    splice(cv.dirI, fv.dirI, t3);
    splice(cv.dirJ, fv.dirJ, t3);
    splice(cv.dirK, fv.dirK, t3);
    splice(cv.atomI, fv.atomI, tu);
    splice(cv.atomJ, fv.atomJ, tu);
    splice(cv.atomK, fv.atomK, tu);
    splice(vertexPlus, fv.plus, t8);
    splice(vertexEdges, fv.edges, t8);
    splice(vertexGroup, fv.group, tu);
    concaveBegin.swap(newBegin);
    newStarts(freeBegin, list, freshFreeBegin, newBegin);
    const Splice spliceFree{freeBegin, newBegin, list, freshFreeBegin};
    spliceFree(freeOther, fv.freeOther, tu);
    freeBegin.swap(newBegin);
  }
  tmp.oldIncVertexBegin.swap(incVertexBegin);
  tmp.oldIncVertexFace.swap(incVertexFace);
  tmp.oldIncFreeBegin.swap(incFreeBegin);
  tmp.oldIncFreeFace.swap(incFreeFace);
  buildIncidence();
  // The extreme atom's contour gives the outer face: recompute it too.
  findExtremeAtom();
  if (n > 0) mark[extremeAtom] |= kContour;

  // Contours of the atoms touched. The others keep their faces; their incidence lists hold
  // the same vertices in the same order, only moved.
  list.clear();
  for (std::size_t i = 0; i < n; ++i)
    if (mark[i] & kContour) list.push_back(static_cast<std::uint32_t>(i));
  stats.contours = list.size();
  incVertexFace.resize(incVertex.size());
  incFreeFace.resize(incFree.size());
  tbb::parallel_for(tbb::blocked_range<std::size_t>(0, n, 1024), [&](const auto& range) {
    for (std::size_t i = range.begin(); i != range.end(); ++i) {
      if (mark[i] & kContour) continue;
      const auto& ob = tmp.oldIncVertexBegin;
      const auto& fb = tmp.oldIncFreeBegin;
      SURFTRACE_ASSERT(ob[i + 1] - ob[i] == incVertexBegin[i + 1] - incVertexBegin[i]);
      SURFTRACE_ASSERT(fb[i + 1] - fb[i] == incFreeBegin[i + 1] - incFreeBegin[i]);
      std::copy(tmp.oldIncVertexFace.begin() + ob[i], tmp.oldIncVertexFace.begin() + ob[i + 1],
                incVertexFace.begin() + incVertexBegin[i]);
      std::copy(tmp.oldIncFreeFace.begin() + fb[i], tmp.oldIncFreeFace.begin() + fb[i + 1], incFreeFace.begin() + incFreeBegin[i]);
    }
  });
  contourPassOf(list);
  {
    auto& cx = out.convex;
    auto& tr = out.tori;
    auto& t3 = tmp.v3;
    auto& td = tmp.f64;
    auto& tu = tmp.u32;
    prefix(fc.convexCount, freshBegin);
    newStarts(convexBegin, list, freshBegin, newBegin);
    const Splice sc{convexBegin, newBegin, list, freshBegin};
    sc(cx.center, fc.convexCenter, t3);
    sc(cx.radius, fc.convexRadius, td);
    sc(cx.atom, fc.convexAtom, tu);
    sc(cx.area, fc.convexArea, td);
    sc(cx.vectorArea, fc.convexVectorArea, t3);
    convexBegin.swap(newBegin);
    prefix(fc.toriCount, freshBegin);
    newStarts(toriBegin, list, freshBegin, newBegin);
    const Splice st{toriBegin, newBegin, list, freshBegin};
    st(tr.center, fc.torusCenter, t3);
    st(tr.axis, fc.torusAxis, t3);
    st(tr.e1, fc.torusE1, t3);
    st(tr.bigRadius, fc.bigRadius, td);
    st(tr.thetaI, fc.thetaI, td);
    st(tr.thetaJ, fc.thetaJ, td);
    st(tr.phiExtent, fc.phiExtent, td);
    st(tr.atomI, fc.torusI, tu);
    st(tr.atomJ, fc.torusJ, tu);
    st(torusFace, fc.torusFace, tu);
    toriBegin.swap(newBegin);
  }

  // Clipping planes: those of the changed owners' new probes, and of every probe within
  // 2 rp of a removed or added probe; the others keep their lists (their neighbours kept
  // their relative order).
  const std::size_t probes = cv.size();
  probeRadii.assign(probes, params.probeRadius);
  probeGrid.build(cv.probe, probeRadii, 0.0);
  auto& dirty = tmp.dirty;
  dirty.assign(probes, 0);
  for (const std::uint32_t x : list2)
    for (std::uint32_t v = concaveBegin[x]; v < concaveBegin[x + 1]; ++v) dirty[v] = 1;
  auto markNear = [&](const glm::dvec3& p) {
    rowBuf.clear();
    probeGrid.atomsNear(p, params.probeRadius, rowBuf);
    for (const std::uint32_t v : rowBuf) dirty[v] = 1;
  };
  for (const glm::dvec3& p : removed) markNear(p);
  for (const std::uint32_t x : list2)
    for (std::uint32_t v = concaveBegin[x]; v < concaveBegin[x + 1]; ++v) markNear(cv.probe[v]);
  list.clear();
  for (std::size_t v = 0; v < probes; ++v)
    if (dirty[v]) list.push_back(static_cast<std::uint32_t>(v));
  stats.probes = list.size();
  planesOf(list);
  // Old index of each new probe of an unchanged owner: same place within the owner.
  tmpIndex.assign(probes, ~0u);
  for (std::size_t x = 0; x < n; ++x) {
    const std::uint32_t len = concaveBegin[x + 1] - concaveBegin[x];
    if (len == 0 || len != oldConcaveBegin[x + 1] - oldConcaveBegin[x]) continue;
    for (std::uint32_t k = 0; k < len; ++k) tmpIndex[concaveBegin[x] + k] = oldConcaveBegin[x] + k;
  }
  auto& clipCount = tmp.clipCount;
  auto& clipBegin = tmp.clipBegin;
  clipCount.resize(probes);
  clipBegin.resize(probes);
  std::size_t d = 0;
  std::uint32_t at = 0;
  for (std::size_t v = 0; v < probes; ++v) {
    clipBegin[v] = at;
    if (dirty[v]) {
      clipCount[v] = fpCount[d++];
    } else {
      SURFTRACE_ASSERT(tmpIndex[v] != ~0u);
      clipCount[v] = oldClipCount[tmpIndex[v]];
    }
    at += clipCount[v];
  }
  auto& planes = tmp.planes;
  planes.resize(at);
  tbb::parallel_for(tbb::blocked_range<std::size_t>(0, probes, 256), [&](const auto& range) {
    // Dirty probes before this range, to find their fresh planes.
    std::size_t dd = static_cast<std::size_t>(std::lower_bound(list.begin(), list.end(), range.begin()) - list.begin());
    for (std::size_t v = range.begin(); v != range.end(); ++v) {
      const Plane* from = dirty[v] ? fpPlanes.data() + fpBegin[dd++] : out.clipPlanes.data() + oldClipBegin[tmpIndex[v]];
      std::copy(from, from + clipCount[v], planes.begin() + clipBegin[v]);
    }
  });
  out.clipPlanes.swap(planes);
  cv.clipBegin.swap(clipBegin);
  cv.clipCount.swap(clipCount);

  labelComponents();
}

SesBuilder::SesBuilder() : s_(std::make_unique<State>()) {}
SesBuilder::~SesBuilder() = default;
SesBuilder::SesBuilder(SesBuilder&&) noexcept = default;
SesBuilder& SesBuilder::operator=(SesBuilder&&) noexcept = default;

const PatchList& SesBuilder::build(std::span<const glm::dvec3> centers, std::span<const double> radii,
                                   const SesParams& params) {
  const double rp = params.probeRadius;
  if (!std::isfinite(rp) || !(rp > 0.0))
    throw std::invalid_argument("probe radius must be finite and > 0, got " + std::to_string(rp));
  if (centers.size() != radii.size()) throw std::invalid_argument("centers and radii differ in length");
  if (centers.size() >= std::numeric_limits<std::uint32_t>::max())
    throw std::invalid_argument("too many atoms: " + std::to_string(centers.size()));
  s_->params = params;
  s_->centers.assign(centers.begin(), centers.end());
  s_->radii.assign(radii.begin(), radii.end());
  s_->fullBuild();
  s_->built = true;
  s_->stats = SesUpdateStats{};
  s_->stats.moved = s_->stats.owners = s_->stats.contours = centers.size();
  s_->stats.probes = s_->out.concave.size();
  s_->stats.full = true;
  return s_->out;
}

const PatchList& SesBuilder::update(std::span<const std::uint32_t> moved, std::span<const glm::dvec3> newCenters) {
  if (!s_->built) throw std::logic_error("SesBuilder::update before build");
  if (moved.size() != newCenters.size()) throw std::invalid_argument("moved and newCenters differ in length");
  const std::size_t n = s_->centers.size();
  for (std::size_t k = 0; k < moved.size(); ++k) {
    if (moved[k] >= n) throw std::invalid_argument("moved atom " + std::to_string(moved[k]) + " out of range");
    const glm::dvec3& c = newCenters[k];
    if (!std::isfinite(c.x) || !std::isfinite(c.y) || !std::isfinite(c.z))
      throw std::invalid_argument("non-finite centre for atom " + std::to_string(moved[k]));
  }
  // The atoms that really move (a repeated index takes its last position), ascending.
  std::vector<std::uint32_t> order(moved.size());
  for (std::size_t k = 0; k < moved.size(); ++k) order[k] = static_cast<std::uint32_t>(k);
  std::stable_sort(order.begin(), order.end(), [&](std::uint32_t u, std::uint32_t v) { return moved[u] < moved[v]; });
  std::vector<std::uint32_t> atoms;
  std::vector<glm::dvec3> where;
  for (std::size_t k = 0; k < order.size(); ++k) {
    const std::uint32_t i = moved[order[k]];
    if (k + 1 < order.size() && moved[order[k + 1]] == i) continue;  // a later entry wins
    const glm::dvec3& c = newCenters[order[k]];
    if (std::memcmp(&c, &s_->centers[i], sizeof(glm::dvec3)) == 0) continue;
    atoms.push_back(i);
    where.push_back(c);
  }
  s_->partialUpdate(atoms, where);
  return s_->out;
}

const PatchList& SesBuilder::update(std::span<const glm::dvec3> centers) {
  if (!s_->built) throw std::logic_error("SesBuilder::update before build");
  if (centers.size() != s_->centers.size()) throw std::invalid_argument("frame has a different atom count");
  std::vector<std::uint32_t> moved;
  std::vector<glm::dvec3> where;
  for (std::size_t i = 0; i < centers.size(); ++i) {
    if (std::memcmp(&centers[i], &s_->centers[i], sizeof(glm::dvec3)) != 0) {
      moved.push_back(static_cast<std::uint32_t>(i));
      where.push_back(centers[i]);
    }
  }
  return update(moved, where);
}

const PatchList& SesBuilder::patches() const { return s_->out; }
const SesUpdateStats& SesBuilder::lastUpdate() const { return s_->stats; }
PatchList SesBuilder::takePatches() {
  s_->built = false;
  return std::move(s_->out);
}

PatchList buildSes(std::span<const glm::dvec3> centers, std::span<const double> radii, const SesParams& params) {
  SesBuilder builder;
  builder.build(centers, radii, params);
  return builder.takePatches();
}

}  // namespace surftrace::build

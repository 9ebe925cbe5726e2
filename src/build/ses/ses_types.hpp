// SES contour-buildup internals: the types the passes share (neighbourhoods, vertices, arcs, pass buffers).
#pragma once

#include <array>
#include <cstddef>
#include <cstdint>
#include <numbers>
#include <span>
#include <vector>

#include <glm/vec3.hpp>
#include <glm/vec4.hpp>

#include "build/ses/sas_geometry.hpp"

namespace surftrace::build::detail {

constexpr double kPi = std::numbers::pi;
constexpr double kTwoPi = 2.0 * kPi;
// Atoms per unit of parallel work. Output order never depends on it (every array is in
// atom order), only scheduling does.
constexpr std::size_t kBlock = 64;

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
  double maxRadius = 0.0;  // largest R of the spheres
  void clear() {
    maxRadius = 0.0;
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

// Clipping planes: the planes of each probe (group 0) and per-probe counts (group 2;
// group 1 is unused).
struct PlaneBuf {
  std::vector<glm::dvec4> plane;
  std::vector<std::uint32_t> count;
  std::size_t size(int g) const { return g == 0 ? plane.size() : g == 1 ? 0 : count.size(); }
  void reserve(std::size_t probes) {  // about 0.5 planes per probe cut their patch at rp = 1.4
    plane.reserve(2 * probes);
    count.reserve(probes);
  }
  void clear() {
    plane.clear();
    count.clear();
  }
};

template <class Buf> struct Piece {
  Buf* buf = nullptr;  // a thread's buffer: gatherPieces may free its large fields
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

}  // namespace surftrace::build::detail

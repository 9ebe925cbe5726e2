// One atom's feasible power cell (Lindow et al. 2010, Sect. 4.2): a box about the atom cut by
// the power half-spaces π_i(x) <= π_j(x) of its neighbours, as a convex polyhedron whose every
// combinatorial decision is exact.
//
// Decisions. A vertex is the meet of three planes, kept in homogeneous form H (the 4D cross
// product of the planes' rows (n, −c)), so the side of a plane m is sign(P_m·H)·sign(H_w):
// a 4×4 determinant evaluated as four products with a proven error bound, and in rational
// arithmetic (GMP) from the input doubles when the bound cannot decide. Exact ties (five
// cospherical weighted points, a vertex on a box plane) are broken by simulation of
// simplicity on the weights: w_k + ε_k with ε_0 ≫ ε_1 ≫ … by atom index (box planes after
// every atom). The perturbed points are a real weighted point set, so every cell takes the
// same decision about a shared Voronoi vertex and the cells fit together: every vertex has
// exactly three planes, Voronoi vertices of five cospherical points split into tetrahedra
// with zero-volume mixed cells, and nothing is left out or counted twice.
//
// Coordinates are local (x − z_i). Plane j: n = 2(z_j − z_i), c = |z_j − z_i|² − w_j + w_i,
// n·x <= c is π_i(x) <= π_j(x). The box is an artefact of the cell: callers drop every
// element that touches a box plane (atom() >= kBoxPlane).
#pragma once

#include <array>
#include <cmath>
#include <cstdint>
#include <limits>
#include <span>
#include <utility>
#include <vector>

#include <glm/vec3.hpp>
#include <glm/vec4.hpp>

#include "build/mss/skin_geometry.hpp"

namespace surftrace::build::mss {

inline constexpr std::uint32_t kBoxPlane = 0xFFFFFFF0u;  // box planes are kBoxPlane + 0..5

struct CellPlane {
  glm::dvec3 n;
  double c;
  double mag;          // |z_j − z_i|² + |w_j| + |w_i|: bounds |c| and its rounding error
  std::uint32_t atom;  // the neighbour j, or kBoxPlane + k
};

struct CellVertex {
  glm::dvec4 h;                          // homogeneous position: x = h.xyz / h.w
  glm::dvec4 hMag;                       // the same cofactors over magnitudes (error bounds)
  int wSign;                             // exact sign of h.w
  std::array<std::uint16_t, 3> plane;    // indices into planes()
  glm::dvec3 p;                          // h.xyz / h.w, local coordinates
};

class PowerCell {
 public:
  enum class Clip { Redundant, Cut, Empty };

  // Starts from the box |x_k| <= half about atom `atom` of `points`.
  void reset(const WeightedPoints& points, std::uint32_t atom, double half);
  // Cuts by the power plane of neighbour j (j != atom, centres distinct).
  Clip clip(std::uint32_t j);

  bool empty() const { return empty_; }
  std::uint32_t atom() const { return atom_; }
  std::span<const CellPlane> planes() const { return planes_; }
  std::span<const CellVertex> vertices() const { return vertices_; }
  // The polygon of plane k, counter-clockwise seen from outside; empty if the plane is not a
  // face. Consecutive vertices q, q+1 share plane k and one other, the neighbour across
  // that edge.
  std::span<const std::uint16_t> face(std::size_t k) const {
    return {faceVerts_.data() + faceStart_[k], faceVerts_.data() + faceStart_[k + 1]};
  }
  // The plane other than k that vertices a and b share.
  std::uint16_t edgeNeighbour(std::uint16_t k, std::uint16_t a, std::uint16_t b) const;
  double maxVertexNorm2() const { return maxNorm2_; }
  // Whether the plane at signed distance `dist` from the atom along the unit normal `unit`
  // surely leaves every vertex inside, with a margin far above the vertices' rounding (each
  // within 1e-12 of the box of its exact place, makeVertex) and the plane's: clip() would
  // answer Redundant. Three bounds on the cell's reach along `unit`, cheapest first: a ball
  // about the vertices' mean, their bounding box, and the largest unit·p over the vertices.
  // On 1AON at s = 0.5 three in five planes that reach the clipping are redundant, and the
  // ball alone caught one in six of them: the others cost a side() test a vertex each.
  bool surelyRedundant(const glm::dvec3& unit, double dist) const {
    const double reach = unit.x * ballCentre_.x + unit.y * ballCentre_.y + unit.z * ballCentre_.z;
    const double margin = ballRadius_ * (1.0 + 1e-6) + 1e-9 * (std::abs(reach) + ballRadius_) + 1e-12;
    if (dist - reach > margin) return true;
    const double slack = 1e-9 * (std::abs(dist) + ballRadius_ + std::sqrt(maxNorm2_)) + 1e-11 * boxHalf_ + 1e-12;
    double box = 0.0;
    for (int k = 0; k < 3; ++k) box += std::max(unit[k] * boxLo_[k], unit[k] * boxHi_[k]);
    if (dist - box > slack) return true;
    double support = -std::numeric_limits<double>::infinity();
    for (const CellVertex& v : vertices_) support = std::max(support, unit.x * v.p.x + unit.y * v.p.y + unit.z * v.p.z);
    return dist - support > slack;
  }
  // Counters for tests and benchmarks: sides decided exactly (GMP) since the last reset.
  std::size_t exactSides() const { return exactSides_; }

 private:
  CellPlane planeOf(std::uint32_t j) const;
  CellVertex makeVertex(std::uint16_t a, std::uint16_t b, std::uint16_t c);
  int side(const CellVertex& v, std::uint16_t m);
  [[gnu::noinline]] int exactSideCounted(const CellVertex& v, std::uint16_t m);
  int exactSide(const CellVertex& v, std::uint16_t m) const;
  int exactWSign(const CellVertex& v) const;
  glm::dvec3 exactPosition(const CellVertex& v) const;

  WeightedPoints points_;
  std::uint32_t atom_ = 0;
  bool empty_ = false;
  double maxNorm2_ = 0.0;
  glm::dvec3 ballCentre_{0.0};
  double ballRadius_ = 0.0;
  glm::dvec3 boxLo_{0.0}, boxHi_{0.0};  // the vertices' bounding box
  double boxHalf_ = 0.0;                // the half-width of the starting box
  std::size_t exactSides_ = 0;

  std::vector<CellPlane> planes_;
  std::vector<CellVertex> vertices_, nextVertices_;
  std::vector<std::uint32_t> faceStart_, nextFaceStart_;  // planes_.size() + 1 prefix sums
  std::vector<std::uint16_t> faceVerts_, nextFaceVerts_;
  std::vector<int> sides_, remap_;
  std::vector<std::pair<std::uint32_t, std::uint16_t>> crossings_;  // (edge key, new vertex)
  std::vector<std::uint16_t> newFaceNext_;
  std::vector<std::uint16_t> newFaceFirst_;
};

}  // namespace surftrace::build::mss

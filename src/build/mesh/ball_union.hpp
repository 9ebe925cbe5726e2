// The union of balls U = ∪ B(c_k, R_k) and the nearest point of its boundary from inside: the
// SAS field that the SES, SAS and vdW distances are made of (ORACLES D.1).
#pragma once

#include <cstdint>
#include <span>
#include <vector>

#include <glm/vec3.hpp>
#include <glm/vec4.hpp>

namespace surftrace::build::mesh {

// Boxes binned into a uniform grid of cubic cells (CSR): a cell lists every item whose box,
// grown by `margin`, meets it. A point query then needs the one cell it falls in for every item
// within `margin` of it, and the cells of the box x ± (r − margin) for those within r > margin.
class BoxGrid {
 public:
  BoxGrid() = default;
  BoxGrid(std::span<const glm::dvec3> lower, std::span<const glm::dvec3> upper, double cellSize, double margin);

  // The items of the cell holding x (empty outside the grid).
  std::span<const std::uint32_t> cellAt(const glm::dvec3& x) const;
  // f(item) for the items of every cell meeting the box x ± halfWidth (items repeat).
  template <class F>
  void forEachInBox(const glm::dvec3& x, double halfWidth, F&& f) const;
  double margin() const { return margin_; }
  // The grid's box (the grown item boxes), and its diagonal.
  double diagonal() const;

 private:
  bool cellRange(const glm::dvec3& lo, const glm::dvec3& hi, glm::ivec3& c0, glm::ivec3& c1) const;

  glm::dvec3 origin_{0.0};
  double cellSize_ = 1.0, inverse_ = 1.0, margin_ = 0.0;
  glm::ivec3 dims_{0, 0, 0};
  std::vector<std::uint32_t> start_;  // cells + 1
  std::vector<std::uint32_t> items_;
};

// An SAS arc: the circle (centre, unit axis, radius) swept from e1 towards e2 = axis × e1 by
// phiExtent, where the spheres of balls[0] and balls[1] meet.
struct BallArc {
  glm::dvec3 center, axis, e1, e2;
  double radius, phiExtent;
  std::uint32_t balls[2];
};

// An SAS vertex: where the spheres of three balls meet.
struct BallVertex {
  glm::dvec3 point;
  std::uint32_t balls[3];
};

// Which feature of ∂U is nearest to a point.
enum class UnionFeature : std::uint8_t { Outside, Sphere, Arc, Vertex };

struct UnionNearest {
  UnionFeature feature = UnionFeature::Outside;
  std::uint32_t index = 0;  // ball (Sphere, Outside), arc or vertex index
  double distance = 0.0;    // inside U: to ∂U; Outside: to U (min_k |x − c_k| − R_k), both exact
  glm::dvec3 point{0.0};    // the nearest point of ∂U
};

// The balls, with the arcs and vertices of their union's boundary given by the caller (an SES
// builder knows them: its tori's probe circles and its concave triangles' probes).
class BallUnion {
 public:
  // `featureReach` T (Å): points up to T inside U find their nearest point among the arcs and
  // vertices listed in their grid cell (those whose normal sector, truncated at T, meets the
  // cell), and points up to T outside find the nearest ball in their cell; farther ones search
  // boxes of cells.
  BallUnion(std::vector<glm::dvec3> centers, std::vector<double> radii, std::vector<BallArc> arcs,
            std::vector<BallVertex> vertices, double featureReach);

  // The nearest point of ∂U from x. Inside U (x in some open ball) it is the nearest of the
  // candidates of ORACLES D.1: the radial projection onto a sphere that lies in no other ball
  // (relative tolerance 1e-10), the nearest point of an arc within its φ range, a vertex; the
  // minimum is exact because the nearest point always is one of them. Outside U, the nearest
  // ball's radial projection. Cost: the balls of one cell, and when the deepest sphere's
  // projection is covered, the arcs and vertices of one cell whose normal sectors may hold x.
  UnionNearest nearest(const glm::dvec3& x) const;

  std::size_t size() const { return centers_.size(); }
  const glm::dvec3& center(std::size_t k) const { return centers_[k]; }
  double radius(std::size_t k) const { return radii_[k]; }
  const BallArc& arc(std::size_t k) const { return arcs_[k]; }
  const BallVertex& vertex(std::size_t k) const { return vertices_[k]; }
  // The balls that overlap ball k (|c_j − c_k| < R_j + R_k): the only ones whose caps cover
  // part of its sphere.
  std::span<const std::uint32_t> neighbours(std::size_t k) const {
    return {neighbours_.data() + neighbourStart_[k], neighbours_.data() + neighbourStart_[k + 1]};
  }

 private:
  UnionNearest nearestOutside(const glm::dvec3& x) const;
  bool exposed(std::uint32_t ball, const glm::dvec3& y) const;
  // The squared distance from x to feature k (arcs, then vertices) and its nearest point, when
  // below best2 (which it then lowers).
  void consider(std::uint32_t k, const glm::dvec3& x, double& best2, UnionNearest& best) const;

  std::vector<glm::dvec3> centers_;
  std::vector<double> radii_;
  std::vector<glm::dvec4> balls_;  // (centre, radius) together: one cache line per ball in the hot loops
  std::vector<BallArc> arcs_;
  std::vector<glm::dvec3> arcEnd_;  // cos(phiExtent) e1 + sin(phiExtent) e2
  std::vector<BallVertex> vertices_;
  std::vector<std::uint32_t> neighbourStart_, neighbours_;  // CSR: balls that overlap ball k
  double reach_ = 0.0;
  BoxGrid ballGrid_;     // balls, margin 0: those that may hold a point
  BoxGrid outsideGrid_;  // balls grown by reach_: the nearest ball of a point up to reach_ outside
  BoxGrid sectorGrid_;   // features (arcs [0, arcs), then vertices) by their normal sectors
  BoxGrid featureGrid_;  // features by their own boxes, for points deep inside
};

template <class F>
void BoxGrid::forEachInBox(const glm::dvec3& x, double halfWidth, F&& f) const {
  glm::ivec3 c0, c1;
  if (!cellRange(x - halfWidth, x + halfWidth, c0, c1)) return;
  for (int iz = c0.z; iz <= c1.z; ++iz)
    for (int iy = c0.y; iy <= c1.y; ++iy) {
      const std::size_t row = (static_cast<std::size_t>(iz) * dims_.y + iy) * dims_.x;
      for (std::uint32_t k = start_[row + c0.x]; k < start_[row + c1.x + 1]; ++k) f(items_[k]);
    }
}

}  // namespace surftrace::build::mesh

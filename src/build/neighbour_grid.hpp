// The flexible neighbour grid of Lindow et al. 2010 (Sect. 4.1, 4.3): atoms binned into at
// most 2n cells over their bounding box, rebuilt in place for every new frame.
#pragma once

#include <cstdint>
#include <span>
#include <vector>

#include <glm/vec3.hpp>
#include <glm/vec4.hpp>

namespace surftrace::build {

// Queries are const and touch no shared mutable state, so any number of threads may query
// one grid at once (but not while build() runs). The grid keeps its own copy of the atoms:
// the spans passed to build() need not outlive it.
//
// Both predicates are evaluated in double exactly as written here, so that callers testing
// the same pair with the same expression agree with the grid even at the boundary
// (d2 = dx*dx + dy*dy + dz*dz, summed left to right):
//   neighbours: d2 < s * s           with d = c_i - c_j, s = (r_i + r_j) + 2 * rp
//   atomsNear:  s > 0 && d2 < s * s  with d = p - c_j,   s = r_j + reach
//
// Cells: Lindow et al.'s at most 2n cubic cells over the atoms' bounding box, of edge
// 2 r_max + 2 rp where the cap allows. When a few far outliers would force much coarser
// cells, the grid covers the bulk of the atoms instead and the outliers sit in its border
// cells; results are exact either way.
class NeighbourGrid {
 public:
  // Reserves room for up to `capacity` atoms (and 2*capacity cells). build() with at most
  // that many atoms never allocates.
  explicit NeighbourGrid(std::size_t capacity = 0);

  // Bins the atoms. `probeRadius` >= 0 sets the query reach: atoms i and j are neighbours
  // iff |c_i - c_j| < r_i + r_j + 2 rp. Grows capacity if needed (allocating only then).
  void build(std::span<const glm::dvec3> centers, std::span<const double> radii,
             double probeRadius);

  // Appends to `out` every j != i that is a neighbour of atom i, in increasing index order.
  void neighbours(std::uint32_t i, std::vector<std::uint32_t>& out) const;

  // Appends every atom j whose reach sphere may contain point p within `reach`:
  // all j with |p - c_j| < r_j + reach (in increasing index order).
  void atomsNear(const glm::dvec3& p, double reach, std::vector<std::uint32_t>& out) const;
  // The same atoms in the grid's own order (cell by cell), for callers that order them
  // themselves: sorting a query of the skin's reach (~150 atoms, far from sorted in cell
  // order) took 3% of the skin's build.
  void atomsNearUnordered(const glm::dvec3& p, double reach, std::vector<std::uint32_t>& out) const;

  std::size_t atomCount() const { return n_; }
  std::size_t cellCount() const;
  std::size_t capacity() const { return capacity_; }
  double probeRadius() const { return probeRadius_; }
  double maxRadius() const { return maxRadius_; }
  double cellSize() const { return cellSize_; }          // edge of the cubic cells, Å
  glm::ivec3 cellDims() const { return dims_; }          // cells along x, y, z

 private:
  void reserve(std::size_t capacity);
  void chooseCells(const glm::dvec3& lo, const glm::dvec3& hi);
  void bulkBounds(std::span<const glm::dvec3> centers, glm::dvec3& lo, glm::dvec3& hi);
  glm::ivec3 cellOf(const glm::dvec3& p) const;
  // Appends, in increasing order (in cell order unless `ordered`), the atom of every sorted
  // slot s in the cells overlapping the box [lo, hi] for which accept(s) holds.
  template <class Accept>
  void collect(const glm::dvec3& lo, const glm::dvec3& hi, Accept&& accept,
               std::vector<std::uint32_t>& out, bool ordered = true) const;
  void near(const glm::dvec3& p, double reach, std::vector<std::uint32_t>& out, bool ordered) const;

  std::size_t capacity_ = 0;
  std::size_t n_ = 0;
  double probeRadius_ = 0.0;
  double maxRadius_ = 0.0;
  glm::dvec3 origin_{0.0};
  double cellSize_ = 1.0;
  double cellFromWorld_ = 1.0;             // 1 / cellSize_
  glm::ivec3 dims_{1, 1, 1};
  // Sized once by reserve() and never resized by build(), so a rebuild cannot allocate;
  // n_ and cellCount() say how much of each is in use.
  std::vector<std::uint32_t> cellStart_;  // cells+1 prefix sums into the sorted arrays
  std::vector<std::uint32_t> cellAtoms_;  // atom index of each sorted slot, ascending per cell
  std::vector<glm::dvec4> sorted_;        // (centre, radius) of each sorted slot
  std::vector<std::uint32_t> atomSlot_;   // sorted slot of each atom
  std::vector<double> scratch_;           // one coordinate per atom, for bulkBounds()
};

}  // namespace surftrace::build

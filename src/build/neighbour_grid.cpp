// The flexible neighbour grid of Lindow et al. 2010 (Sect. 4.1, 4.3): a counting sort of the
// atoms into at most 2n cubic cells over their bounding box (or over the bulk of the atoms
// when a few outliers stretch the box).
#include "build/neighbour_grid.hpp"

#include <algorithm>
#include <cmath>
#include <cstddef>
#include <limits>

#include <glm/common.hpp>

#include "build/core/assert.hpp"

namespace surftrace::build {
namespace {

// Lindow et al. bound the cell count by M = 2n so that memory stays linear in n.
constexpr std::size_t kCellsPerAtom = 2;

// The cell edge we aim for is (2 r_max + 2 rp) / kCellsPerReach, the largest neighbour
// reach divided by this. See chooseCells() for the measurements behind the value.
constexpr double kCellsPerReach = 1.0;

// When the 2n cap makes cells this much coarser than aimed for, the bounding box is
// probably stretched by a few outliers, and the grid is laid over the bulk instead:
// per axis, from the k-th smallest to the k-th largest coordinate, k = n / kBulkTrim.
constexpr double kCoarseCells = 2.0;
constexpr std::size_t kBulkTrim = 1000;

double aimedCellSize(double maxRadius, double probeRadius) {
  return (2.0 * maxRadius + 2.0 * probeRadius) / kCellsPerReach;
}

// Sorts a query's result in place. The candidates come out cell by cell, each cell in
// increasing index, and atoms close in space tend to be close in index (residues along a
// chain), so the list is nearly sorted: insertion sort made the all-neighbours query of
// 1AF6 20% faster than std::sort at rp = 1.4 and still 7% at rp = 3 (~140 neighbours). Its
// cost is the length plus the inversions, so past a budget std::sort takes over (a big
// atomsNear reach).
void sortNearlySorted(std::uint32_t* first, std::uint32_t* last) {
  const std::ptrdiff_t budget = 64 * (last - first) + 4096;
  std::ptrdiff_t moves = 0;
  for (std::uint32_t* p = first + (first != last ? 1 : 0); p < last; ++p) {
    const std::uint32_t v = *p;
    std::uint32_t* q = p;
    for (; q > first && q[-1] > v; --q) *q = q[-1];
    *q = v;
    moves += p - q;
    if (moves > budget) {
      std::sort(first, last);
      return;
    }
  }
}

// The cell of coordinate x along one axis. Every step (subtraction, scaling, clamping,
// truncation) is monotone in x, so a box [lo, hi] covers exactly the cells from
// axisCell(lo) to axisCell(hi) of every atom inside it, however the arithmetic rounds.
// The clamp runs in double before the conversion, so far-away query points (or a box that
// overflowed to infinity) cannot overflow the int; !(t > 0) also catches NaN.
//
// Nor does the query box need slack. With half-width R >= s (both doubles) and
// lo = fl(c - R), an atom j is missed only if c_j < lo; lo is the double nearest to c - R,
// so c_j < c - R exactly, hence fl(c - c_j) >= s, and since every rounding is monotone the
// computed dx*dx + dy*dy + dz*dz >= fl(s * s) (fused multiply-adds included): the
// predicate rejects j anyway. Likewise for hi and per axis. R >= s holds because R is
// computed like s with r_max in place of r_j.
int axisCell(double x, double origin, double cellFromWorld, int dim) {
  double t = (x - origin) * cellFromWorld;
  if (!(t > 0.0)) return 0;
  const double last = static_cast<double>(dim - 1);
  if (t > last) t = last;
  return static_cast<int>(t);
}

double cellProduct(const glm::dvec3& extent, double h) {
  double p = 1.0;
  for (int a = 0; a < 3; ++a) p *= std::max(1.0, std::ceil(extent[a] / h));
  return p;
}

}  // namespace

NeighbourGrid::NeighbourGrid(std::size_t capacity) {
  reserve(capacity);
}

void NeighbourGrid::reserve(std::size_t capacity) {
  // Atom indices and cell starts are uint32 and cell dims int; 2n cells must fit both.
  SURFTRACE_ASSERT(capacity <= std::size_t{std::numeric_limits<std::int32_t>::max()} / kCellsPerAtom);
  capacity_ = capacity;
  cellStart_.assign(std::max<std::size_t>(kCellsPerAtom * capacity, 1) + 1, 0);
  cellAtoms_.assign(capacity, 0);
  sorted_.assign(capacity, glm::dvec4(0.0));
  atomSlot_.assign(capacity, 0);
  scratch_.assign(capacity, 0.0);
}

std::size_t NeighbourGrid::cellCount() const {
  return static_cast<std::size_t>(dims_.x) * static_cast<std::size_t>(dims_.y) *
         static_cast<std::size_t>(dims_.z);
}

// Cell size. With edge h, a query of reach R scans on average about (2R + h)^3 of space in
// (2R/h + 1)^2 rows of cells, so smaller cells scan fewer atoms but pay more per row; the
// 2n cap alone stops edges below ~3.3 Å on 1AON and 1VIS. All-neighbours query time in ms
// (min of 4 interleaved runs, one core of a shared 2-core machine, noise ~3%), for
// h = R_max * (4/3, 1, 2/3, 1/2, 1/3) where R_max = 2 r_max + 2 rp:
//   1AF6 rp = 0:     2.5,   2.4,   2.8,   2.8,   2.8
//        rp = 1.4:   8.7,   8.2,   8.5,   9.0,   9.6
//        rp = 3:    29.3,  29.8,  29.5,  31.4,  32.1
//   1AON rp = 0:    14.2,  13.9,  14.6,  14.8,  14.6
//        rp = 1.4:  45.7,  43.6,  45.7,  50.6,  49.2   (the last two both hit the cap)
//        rp = 3:   148.5, 148.2, 151.8, 162.3, 174.4
// Cells of edge R_max (at most 3 x 3 x 3 per query) win or tie everywhere, and the curve
// is flat enough that no cleverer rule would pay.
void NeighbourGrid::chooseCells(const glm::dvec3& lo, const glm::dvec3& hi) {
  const glm::dvec3 extent = hi - lo;
  const double maxExtent = std::max({extent.x, extent.y, extent.z});
  origin_ = lo;
  if (!std::isfinite(maxExtent)) {
    // Coordinates near ±DBL_MAX: the extent overflowed. One cell is correct and the only
    // grid that cannot overflow; nobody has real molecules like that.
    dims_ = glm::ivec3(1);
    cellSize_ = std::numeric_limits<double>::max();
    cellFromWorld_ = 0.0;
    return;
  }
  const double maxCells = static_cast<double>(std::max<std::size_t>(kCellsPerAtom * n_, 1));
  double h = aimedCellSize(maxRadius_, probeRadius_);
  if (cellProduct(extent, h) > maxCells) {
    // The product only decreases as h grows and is 1 at h = maxExtent (> h here, or the
    // product would be 1), so bisect for the smallest h that satisfies the cap.
    double feasible = maxExtent;
    double infeasible = h;
    for (int iter = 0; iter < 200 && feasible > infeasible * (1.0 + 1e-9); ++iter) {
      const double mid = 0.5 * (feasible + infeasible);
      if (cellProduct(extent, mid) > maxCells) infeasible = mid;
      else feasible = mid;
    }
    h = feasible;
  }
  for (int a = 0; a < 3; ++a) dims_[a] = static_cast<int>(std::max(1.0, std::ceil(extent[a] / h)));
  cellSize_ = h;
  cellFromWorld_ = 1.0 / h;
}

void NeighbourGrid::bulkBounds(std::span<const glm::dvec3> centers, glm::dvec3& lo, glm::dvec3& hi) {
  const std::size_t n = centers.size();
  const std::size_t k = n / kBulkTrim;
  if (k == 0) return;  // fewer than kBulkTrim atoms: keep the full bounds
  const auto first = scratch_.begin();
  const auto last = first + static_cast<std::ptrdiff_t>(n);
  const auto kth = first + static_cast<std::ptrdiff_t>(k);
  const auto kthLargest = first + static_cast<std::ptrdiff_t>(n - 1 - k);
  for (int a = 0; a < 3; ++a) {
    for (std::size_t i = 0; i < n; ++i) scratch_[i] = centers[i][a];
    std::nth_element(first, kth, last);
    lo[a] = *kth;
    std::nth_element(kth, kthLargest, last);  // everything before kth is <= *kth
    hi[a] = *kthLargest;
  }
}

glm::ivec3 NeighbourGrid::cellOf(const glm::dvec3& p) const {
  return {axisCell(p.x, origin_.x, cellFromWorld_, dims_.x),
          axisCell(p.y, origin_.y, cellFromWorld_, dims_.y),
          axisCell(p.z, origin_.z, cellFromWorld_, dims_.z)};
}

void NeighbourGrid::build(std::span<const glm::dvec3> centers, std::span<const double> radii,
                          double probeRadius) {
  SURFTRACE_ASSERT(centers.size() == radii.size());
  SURFTRACE_ASSERT(std::isfinite(probeRadius) && probeRadius >= 0.0);
  const std::size_t n = centers.size();
  if (n > capacity_) reserve(n);
  n_ = n;
  probeRadius_ = probeRadius;
  maxRadius_ = 0.0;
  if (n == 0) {
    origin_ = glm::dvec3(0.0);
    dims_ = glm::ivec3(1);
    cellSize_ = cellFromWorld_ = 1.0;
    cellStart_[0] = cellStart_[1] = 0;
    return;
  }

  glm::dvec3 lo = centers[0];
  glm::dvec3 hi = centers[0];
  for (std::size_t i = 0; i < n; ++i) {
    lo = glm::min(lo, centers[i]);
    hi = glm::max(hi, centers[i]);
    maxRadius_ = std::max(maxRadius_, radii[i]);
  }
  chooseCells(lo, hi);
  if (cellSize_ > kCoarseCells * aimedCellSize(maxRadius_, probeRadius_)) {
    // One atom 1e6 Å away would otherwise put all others into one cell and make every
    // query O(n). Atoms outside the bulk box are clamped into its border cells, which is
    // still exact (see axisCell) and leaves those cells only a few extra atoms.
    bulkBounds(centers, lo, hi);
    chooseCells(lo, hi);
  }

  // Counting sort (Lindow et al. Sect. 4.3): count per cell, prefix-sum into cellStart_,
  // scatter in increasing atom order so each cell lists its atoms in increasing index.
  // atomSlot_ holds each atom's cell until the scatter overwrites it with the slot.
  const std::size_t cells = cellCount();
  SURFTRACE_ASSERT(cells < cellStart_.size());
  std::fill_n(cellStart_.begin(), cells + 1, 0u);
  for (std::size_t i = 0; i < n; ++i) {
    const glm::ivec3 c = cellOf(centers[i]);
    // Each partial sum is below the cell count (<= 2n), so int cannot overflow.
    const auto cell = static_cast<std::uint32_t>((c.z * dims_.y + c.y) * dims_.x + c.x);
    atomSlot_[i] = cell;
    ++cellStart_[cell + 1];
  }
  for (std::size_t c = 0; c < cells; ++c) cellStart_[c + 1] += cellStart_[c];
  // Scatter with cellStart_[c] as the cursor of cell c; afterwards it holds the end of c,
  // which is the start of c + 1, so shifting by one restores the starts.
  for (std::size_t i = 0; i < n; ++i) {
    const std::uint32_t slot = cellStart_[atomSlot_[i]]++;
    atomSlot_[i] = slot;
    cellAtoms_[slot] = static_cast<std::uint32_t>(i);
    sorted_[slot] = glm::dvec4(centers[i], radii[i]);
  }
  for (std::size_t c = cells; c > 0; --c) cellStart_[c] = cellStart_[c - 1];
  cellStart_[0] = 0;
}

template <class Accept>
void NeighbourGrid::collect(const glm::dvec3& lo, const glm::dvec3& hi, Accept&& accept,
                            std::vector<std::uint32_t>& out, bool ordered) const {
  const glm::ivec3 a = cellOf(lo);
  const glm::ivec3 b = cellOf(hi);
  // Cells consecutive in x are consecutive in the sorted arrays: one run per (y, z) row.
  const auto forEachRun = [&](auto&& visitRun) {
    for (int z = a.z; z <= b.z; ++z) {
      for (int y = a.y; y <= b.y; ++y) {
        const std::size_t row = (static_cast<std::size_t>(z) * static_cast<std::size_t>(dims_.y) +
                                 static_cast<std::size_t>(y)) * static_cast<std::size_t>(dims_.x);
        visitRun(cellStart_[row + static_cast<std::size_t>(a.x)],
                 cellStart_[row + static_cast<std::size_t>(b.x) + 1]);
      }
    }
  };
  // Writing every candidate and advancing the cursor only past accepted ones avoids a
  // branch that mispredicts on most of the ~20% of candidates accepted: all-neighbours of
  // 1VIS went from 3.4 to 2.5 ms against push_back behind an if.
  std::size_t candidates = 0;
  forEachRun([&](std::uint32_t begin, std::uint32_t end) { candidates += end - begin; });
  const std::size_t first = out.size();
  out.resize(first + candidates);
  std::uint32_t* const start = out.data() + first;
  std::uint32_t* cursor = start;
  forEachRun([&](std::uint32_t begin, std::uint32_t end) {
    for (std::uint32_t s = begin; s < end; ++s) {
      *cursor = cellAtoms_[s];
      cursor += static_cast<std::ptrdiff_t>(accept(s));
    }
  });
  if (ordered) sortNearlySorted(start, cursor);
  out.resize(first + static_cast<std::size_t>(cursor - start));
}

void NeighbourGrid::neighbours(std::uint32_t i, std::vector<std::uint32_t>& out) const {
  SURFTRACE_ASSERT(i < n_);
  const glm::dvec4 ci = sorted_[atomSlot_[i]];
  const std::size_t first = out.size();
  const double twoRp = 2.0 * probeRadius_;
  const double reach = (ci.w + maxRadius_) + twoRp;
  const glm::dvec3 lo(ci.x - reach, ci.y - reach, ci.z - reach);
  const glm::dvec3 hi(ci.x + reach, ci.y + reach, ci.z + reach);
  collect(lo, hi, [&](std::uint32_t s) {
    const glm::dvec4& cj = sorted_[s];
    const double dx = ci.x - cj.x;
    const double dy = ci.y - cj.y;
    const double dz = ci.z - cj.z;
    const double sum = (ci.w + cj.w) + twoRp;
    return dx * dx + dy * dy + dz * dz < sum * sum;
  }, out);
  // Atom i accepted itself (distance 0), unless sum * sum underflowed for absurdly small
  // radii; dropping it afterwards keeps the test out of the loop.
  const auto self = std::lower_bound(out.begin() + static_cast<std::ptrdiff_t>(first), out.end(), i);
  if (self != out.end() && *self == i) out.erase(self);
}

void NeighbourGrid::atomsNear(const glm::dvec3& p, double reach, std::vector<std::uint32_t>& out) const {
  near(p, reach, out, true);
}

void NeighbourGrid::atomsNearUnordered(const glm::dvec3& p, double reach, std::vector<std::uint32_t>& out) const {
  near(p, reach, out, false);
}

void NeighbourGrid::near(const glm::dvec3& p, double reach, std::vector<std::uint32_t>& out, bool ordered) const {
  SURFTRACE_ASSERT(std::isfinite(reach));
  // r_j + reach <= maxRadius_ + reach for every j (rounding is monotone), so nothing can
  // be near when the latter is not positive, and the box below is not empty.
  const double boxReach = maxRadius_ + reach;
  if (n_ == 0 || !(boxReach > 0.0)) return;
  collect(p - boxReach, p + boxReach, [&](std::uint32_t s) {
    const glm::dvec4& cj = sorted_[s];
    const double dx = p.x - cj.x;
    const double dy = p.y - cj.y;
    const double dz = p.z - cj.z;
    // max(.., 0) makes a non-positive r_j + reach reject (d^2 >= 0) without a branch.
    const double sum = std::max(cj.w + reach, 0.0);
    return dx * dx + dy * dy + dz * dz < sum * sum;
  }, out, ordered);
}

}  // namespace surftrace::build

// The nearest boundary point of a union of balls (ORACLES D.1), with grids that make a query
// touch one cell of balls and, at most, one cell of arcs and vertices.
#include "build/mesh/ball_union.hpp"

#include <algorithm>
#include <cmath>
#include <limits>
#include <numbers>

#include <glm/common.hpp>
#include <glm/geometric.hpp>

#include "build/core/assert.hpp"
#include "build/neighbour_grid.hpp"

namespace surftrace::build::mesh {

namespace {

constexpr double kInf = std::numeric_limits<double>::infinity();
// A projection onto sphere k lies in A unless it is this far (relative) inside another ball:
// ORACLES D.1's tolerance. Where it errs, the point is within 1e-10 R of an arc, whose own
// candidate is as near.
constexpr double kCoveredTolerance = 1e-10;
// Grids hold at most this many cells per item (and this many in all): a few far outliers make
// coarser cells rather than a grid of empty ones.
constexpr double kMaxCellsPerItem = 64.0;
constexpr double kMaxCells = 1 << 26;

}  // namespace

BoxGrid::BoxGrid(std::span<const glm::dvec3> lower, std::span<const glm::dvec3> upper, double cellSize,
                 double margin)
    : margin_(margin) {
  SURFTRACE_ASSERT(lower.size() == upper.size() && cellSize > 0.0);
  if (lower.empty()) return;
  glm::dvec3 lo(kInf), hi(-kInf);
  for (std::size_t k = 0; k < lower.size(); ++k) lo = glm::min(lo, lower[k] - margin), hi = glm::max(hi, upper[k] + margin);
  const glm::dvec3 extent = hi - lo;
  const double budget = std::min(kMaxCells, kMaxCellsPerItem * static_cast<double>(lower.size()) + 64.0);
  // Grow the cells until the grid fits its budget.
  for (;;) {
    const glm::dvec3 n = glm::floor(extent / cellSize) + 1.0;
    if (n.x * n.y * n.z <= budget) {
      dims_ = glm::ivec3(n);
      break;
    }
    cellSize *= 1.25;
  }
  origin_ = lo;
  cellSize_ = cellSize;
  inverse_ = 1.0 / cellSize;
  const std::size_t cells = static_cast<std::size_t>(dims_.x) * dims_.y * dims_.z;
  start_.assign(cells + 1, 0);
  // Two passes over the items' cells: count, then place (CSR).
  auto visit = [&](std::size_t k, auto&& f) {
    glm::ivec3 c0, c1;
    if (!cellRange(lower[k] - margin, upper[k] + margin, c0, c1)) return;
    for (int iz = c0.z; iz <= c1.z; ++iz)
      for (int iy = c0.y; iy <= c1.y; ++iy)
        for (int ix = c0.x; ix <= c1.x; ++ix) f((static_cast<std::size_t>(iz) * dims_.y + iy) * dims_.x + ix);
  };
  for (std::size_t k = 0; k < lower.size(); ++k) visit(k, [&](std::size_t c) { ++start_[c + 1]; });
  for (std::size_t c = 0; c < cells; ++c) start_[c + 1] += start_[c];
  items_.resize(start_[cells]);
  std::vector<std::uint32_t> fill(start_.begin(), start_.end() - 1);
  for (std::size_t k = 0; k < lower.size(); ++k)
    visit(k, [&](std::size_t c) { items_[fill[c]++] = static_cast<std::uint32_t>(k); });
}

bool BoxGrid::cellRange(const glm::dvec3& lo, const glm::dvec3& hi, glm::ivec3& c0, glm::ivec3& c1) const {
  if (start_.empty()) return false;
  for (int a = 0; a < 3; ++a) {
    // Clamped in double before the conversion, so that far points cannot overflow it.
    const double l = (lo[a] - origin_[a]) * inverse_, h = (hi[a] - origin_[a]) * inverse_;
    if (!(h >= 0.0) || !(l < dims_[a])) return false;  // also NaN
    c0[a] = l <= 0.0 ? 0 : static_cast<int>(l);
    c1[a] = h >= dims_[a] - 1 ? dims_[a] - 1 : static_cast<int>(h);
  }
  return true;
}

std::span<const std::uint32_t> BoxGrid::cellAt(const glm::dvec3& x) const {
  glm::ivec3 c0, c1;
  if (!cellRange(x, x, c0, c1)) return {};
  const std::size_t c = (static_cast<std::size_t>(c0.z) * dims_.y + c0.y) * dims_.x + c0.x;
  return {items_.data() + start_[c], items_.data() + start_[c + 1]};
}

double BoxGrid::diagonal() const { return cellSize_ * glm::length(glm::dvec3(dims_)); }

BallUnion::BallUnion(std::vector<glm::dvec3> centers, std::vector<double> radii, std::vector<BallArc> arcs,
                     std::vector<glm::dvec3> vertices, double featureReach)
    : centers_(std::move(centers)), radii_(std::move(radii)), arcs_(std::move(arcs)), vertices_(std::move(vertices)) {
  SURFTRACE_ASSERT(centers_.size() == radii_.size());
  const std::size_t n = centers_.size();
  double maxRadius = 0.0;
  for (double r : radii_) maxRadius = std::max(maxRadius, r);

  // Overlapping balls: only they can cover a point of ball k's sphere.
  NeighbourGrid grid(n);
  grid.build(centers_, radii_, 0.0);
  neighbourStart_.assign(n + 1, 0);
  std::vector<std::uint32_t> near;
  for (std::size_t k = 0; k < n; ++k) {
    near.clear();
    grid.neighbours(static_cast<std::uint32_t>(k), near);
    neighbours_.insert(neighbours_.end(), near.begin(), near.end());
    neighbourStart_[k + 1] = static_cast<std::uint32_t>(neighbours_.size());
  }

  std::vector<glm::dvec3> lo(n), hi(n);
  for (std::size_t k = 0; k < n; ++k) lo[k] = centers_[k] - radii_[k], hi[k] = centers_[k] + radii_[k];
  // Cells of about two thirds of the largest radius: a ball covers a few cells each way, and a
  // cell lists the balls near it without many that are not.
  ballGrid_ = BoxGrid(lo, hi, std::max(0.67 * maxRadius, 0.5), 0.0);

  // Each arc's own box (its endpoints and the extremes of each coordinate inside its φ range).
  std::vector<glm::dvec3> flo, fhi;
  flo.reserve(arcs_.size() + vertices_.size());
  fhi.reserve(arcs_.size() + vertices_.size());
  for (const BallArc& a : arcs_) {
    glm::dvec3 l = a.center + a.radius * a.e1, h = l;
    const glm::dvec3 end = a.center + a.radius * (std::cos(a.phiExtent) * a.e1 + std::sin(a.phiExtent) * a.e2);
    l = glm::min(l, end), h = glm::max(h, end);
    for (int c = 0; c < 3; ++c) {
      // Coordinate c along the circle is center_c + R (cos φ e1_c + sin φ e2_c) = center_c + R A cos(φ − ψ).
      const double amp = std::hypot(a.e1[c], a.e2[c]);
      const double psi = std::atan2(a.e2[c], a.e1[c]);
      for (double phi : {psi, psi + std::numbers::pi}) {
        double p = std::fmod(phi, 2.0 * std::numbers::pi);
        if (p < 0) p += 2.0 * std::numbers::pi;
        if (p <= a.phiExtent) {
          const double v = a.center[c] + a.radius * amp * std::cos(p - psi);
          l[c] = std::min(l[c], v), h[c] = std::max(h[c], v);
        }
      }
    }
    // Rounding: grow by a hair so that an arc's own points are always inside its box.
    const double pad = 1e-9 * (a.radius + 1.0);
    flo.push_back(l - pad), fhi.push_back(h + pad);
  }
  for (const glm::dvec3& v : vertices_) flo.push_back(v), fhi.push_back(v);
  featureGrid_ = BoxGrid(flo, fhi, std::max(featureReach, 0.5), featureReach);
}

bool BallUnion::exposed(std::uint32_t ball, const glm::dvec3& y) const {
  for (std::uint32_t k = neighbourStart_[ball]; k < neighbourStart_[ball + 1]; ++k) {
    const std::uint32_t o = neighbours_[k];
    const double limit = radii_[o] * (1.0 - kCoveredTolerance);
    const glm::dvec3 d = y - centers_[o];
    if (glm::dot(d, d) < limit * limit) return false;
  }
  return true;
}

UnionNearest BallUnion::nearestOutside(const glm::dvec3& x) const {
  UnionNearest best;
  best.distance = kInf;
  // Any ball within r of x meets the box x ± r, so a box search that finds one within r is final.
  const double diag = ballGrid_.diagonal();
  double r = 1.0;
  auto scan = [&](std::uint32_t k) {
    const double d = glm::length(x - centers_[k]) - radii_[k];
    if (d < best.distance) best.distance = d, best.index = k;
  };
  for (;;) {
    ballGrid_.forEachInBox(x, r, scan);
    if (best.distance <= r) break;
    if (r > diag) {
      // Far from the grid: every ball is a candidate.
      for (std::uint32_t k = 0; k < centers_.size(); ++k) scan(k);
      break;
    }
    r *= 2.0;
  }
  best.feature = UnionFeature::Outside;
  if (best.distance < kInf) {
    const glm::dvec3 d = x - centers_[best.index];
    const double len = glm::length(d);
    best.point = centers_[best.index] + radii_[best.index] * (len > 0.0 ? d / len : glm::dvec3(0, 0, 1));
    best.distance = std::max(best.distance, 0.0);
  }
  return best;
}

UnionNearest BallUnion::nearest(const glm::dvec3& x) const {
  // Every point of A lies outside every ball that holds x, so at least the largest depth
  // R − |x − c| away: only that deepest ball's sphere can hold the nearest point, and when its
  // radial projection lies in no other ball, that is the answer.
  double lower = -1.0;
  std::uint32_t deepest = 0;
  for (std::uint32_t k : ballGrid_.cellAt(x)) {
    const glm::dvec3 d = x - centers_[k];
    const double q = glm::dot(d, d);
    if (q >= radii_[k] * radii_[k]) continue;
    const double depth = radii_[k] - std::sqrt(q);
    if (depth > lower) lower = depth, deepest = k;
  }
  if (lower < 0.0) return nearestOutside(x);
  UnionNearest best;
  best.distance = kInf;
  {
    const glm::dvec3 d = x - centers_[deepest];
    const double len = glm::length(d);
    const glm::dvec3 y = centers_[deepest] + radii_[deepest] * (len > 0.0 ? d / len : glm::dvec3(0, 0, 1));
    if (exposed(deepest, y)) return {UnionFeature::Sphere, deepest, lower, y};
  }

  // Arcs and vertices within the best distance so far; wider boxes until one is found.
  const double margin = featureGrid_.margin();
  double reach = std::max(1.5 * lower, margin);
  const std::uint32_t arcCount = static_cast<std::uint32_t>(arcs_.size());
  double best2 = best.distance * best.distance;
  auto consider = [&](std::uint32_t k) {
    if (k >= arcCount) {
      const glm::dvec3 v = vertices_[k - arcCount];
      const glm::dvec3 d = x - v;
      const double q = glm::dot(d, d);
      if (q < best2) best2 = q, best = {UnionFeature::Vertex, k - arcCount, 0.0, v};
      return;
    }
    const BallArc& a = arcs_[k];
    const glm::dvec3 w = x - a.center;
    const double h = glm::dot(w, a.axis);
    const glm::dvec3 radial = w - h * a.axis;
    const double rho = glm::length(radial);
    const double q = h * h + (rho - a.radius) * (rho - a.radius);
    if (q >= best2) return;
    // On the axis every circle point is as near: the arc's ends (vertices) stand for them,
    // and a whole ring has no ends, so its φ = 0 point does.
    glm::dvec3 u = a.e1;
    if (rho > 1e-12 * a.radius) {
      u = radial / rho;
      double phi = std::atan2(glm::dot(u, a.e2), glm::dot(u, a.e1));
      if (phi < 0.0) phi += 2.0 * std::numbers::pi;
      if (phi > a.phiExtent) return;
    } else if (a.phiExtent < 2.0 * std::numbers::pi) {
      return;
    }
    best2 = q, best = {UnionFeature::Arc, k, 0.0, a.center + a.radius * u};
  };
  const double diag = featureGrid_.diagonal();
  for (;;) {
    if (reach <= margin)
      for (std::uint32_t k : featureGrid_.cellAt(x)) consider(k);
    else
      featureGrid_.forEachInBox(x, reach - margin, consider);
    if (best2 <= reach * reach || reach > diag) break;
    reach *= 2.0;
  }
  if (best2 == kInf) {
    // No point of ∂U found at all (a list whose arcs or vertices were left out): the deepest
    // sphere stands for it, at the lower bound.
    const glm::dvec3 d = x - centers_[deepest];
    const double len = glm::length(d);
    return {UnionFeature::Sphere, deepest, lower,
            centers_[deepest] + radii_[deepest] * (len > 0.0 ? d / len : glm::dvec3(0, 0, 1))};
  }
  best.distance = std::sqrt(best2);
  return best;
}

}  // namespace surftrace::build::mesh

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

// Grows [lo, hi] by the arc center + radius (cos φ e1 + sin φ e2), φ in [0, extent] (a negative
// radius is the arc mirrored through its centre): its ends and, per coordinate, the extremes
// R A cos(φ − ψ) that fall inside the range; padded by a hair for rounding.
void arcBox(const glm::dvec3& center, const glm::dvec3& e1, const glm::dvec3& e2, double radius, double extent,
            glm::dvec3& lo, glm::dvec3& hi) {
  const glm::dvec3 start = center + radius * e1;
  const glm::dvec3 end = center + radius * (std::cos(extent) * e1 + std::sin(extent) * e2);
  lo = glm::min(lo, glm::min(start, end)), hi = glm::max(hi, glm::max(start, end));
  for (int c = 0; c < 3; ++c) {
    const double amp = std::hypot(e1[c], e2[c]);
    const double psi = std::atan2(e2[c], e1[c]);
    for (double phi : {psi, psi + std::numbers::pi}) {
      double p = std::fmod(phi, 2.0 * std::numbers::pi);
      if (p < 0) p += 2.0 * std::numbers::pi;
      if (p <= extent) {
        const double v = center[c] + radius * amp * std::cos(p - psi);
        lo[c] = std::min(lo[c], v), hi[c] = std::max(hi[c], v);
      }
    }
  }
  const double pad = 1e-9 * (std::abs(radius) + glm::length(center) + 1.0);
  lo -= pad, hi += pad;
}

// The largest e·u over unit u on the great-circle arc from a to b (unit, not antipodal).
double maxOnArc(const glm::dvec3& e, const glm::dvec3& a, const glm::dvec3& b) {
  double best = std::max(glm::dot(e, a), glm::dot(e, b));
  const glm::dvec3 n = glm::cross(a, b);
  const double nn = glm::dot(n, n);
  if (nn <= 0.0) return best;
  // e's projection onto the arc's plane, where e·u peaks on the whole great circle.
  const glm::dvec3 q = e - (glm::dot(e, n) / nn) * n;
  const double ql = glm::length(q);
  if (ql <= 0.0) return best;
  const glm::dvec3 u = q / ql;
  // u lies between a and b when it is on a's side of b and on b's side of a within the plane.
  if (glm::dot(glm::cross(a, u), n) >= 0.0 && glm::dot(glm::cross(u, b), n) >= 0.0) best = std::max(best, ql);
  return best;
}

// The largest e·u over unit u in the spherical triangle (cone) of d[0], d[1], d[2]: 1 where e
// is inside the cone, else the largest over its edges.
double maxOnTriangle(const glm::dvec3& e, const glm::dvec3 (&d)[3]) {
  const double det = glm::dot(d[0], glm::cross(d[1], d[2]));
  if (det != 0.0) {
    const double a = glm::dot(e, glm::cross(d[1], d[2])) / det, b = glm::dot(d[0], glm::cross(e, d[2])) / det,
                 c = glm::dot(d[0], glm::cross(d[1], e)) / det;
    if (a >= 0.0 && b >= 0.0 && c >= 0.0) return 1.0;
  }
  return std::max({maxOnArc(e, d[0], d[1]), maxOnArc(e, d[1], d[2]), maxOnArc(e, d[2], d[0])});
}

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
                     std::vector<BallVertex> vertices, double featureReach)
    : centers_(std::move(centers)),
      radii_(std::move(radii)),
      arcs_(std::move(arcs)),
      vertices_(std::move(vertices)),
      reach_(featureReach) {
  SURFTRACE_ASSERT(centers_.size() == radii_.size());
  const std::size_t n = centers_.size();
  double maxRadius = 0.0;
  for (double r : radii_) maxRadius = std::max(maxRadius, r);
  for (std::size_t k = 0; k < n; ++k) balls_.emplace_back(centers_[k], radii_[k]);

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
  // Cells of about a third of the largest radius: a cell lists the few balls that hold its
  // points, and little else.
  ballGrid_ = BoxGrid(lo, hi, std::max(0.33 * maxRadius, 0.5), 0.0);
  outsideGrid_ = BoxGrid(lo, hi, std::max(0.67 * maxRadius, 0.5), reach_);

  // Each arc's own box (its endpoints and the extremes of each coordinate inside its φ range),
  // for points deep inside, whose nearest feature may lie on a sphere beyond the reach.
  std::vector<glm::dvec3> flo, fhi;
  flo.reserve(arcs_.size() + vertices_.size());
  fhi.reserve(arcs_.size() + vertices_.size());
  for (const BallArc& a : arcs_) {
    arcEnd_.push_back(std::cos(a.phiExtent) * a.e1 + std::sin(a.phiExtent) * a.e2);
    glm::dvec3 l(kInf), h(-kInf);
    arcBox(a.center, a.e1, a.e2, a.radius, a.phiExtent, l, h);
    flo.push_back(l), fhi.push_back(h);
  }
  for (const BallVertex& v : vertices_) flo.push_back(v.point), fhi.push_back(v.point);
  featureGrid_ = BoxGrid(flo, fhi, std::max(2.0 * reach_, 1.0), 0.0);

  // The normal sectors, truncated at T = reach_: a point x whose nearest point of ∂U is the
  // feature's point c lies at c + t u with u in the cone of the inward normals there (towards
  // the centres of the feature's balls) and t = |x − c|. For a vertex the cone is spanned by its
  // three contact directions; for an arc, at each φ, by the two, so the sector lies in the hull
  // of the arc and of the arcs it makes moved by T towards each centre (homotheties about them).
  std::vector<glm::dvec3> slo, shi;
  for (const BallArc& a : arcs_) {
    glm::dvec3 l(kInf), h(-kInf);
    arcBox(a.center, a.e1, a.e2, a.radius, a.phiExtent, l, h);
    for (std::uint32_t b : a.balls) {
      const double s = 1.0 - reach_ / radii_[b];
      arcBox(centers_[b] + s * (a.center - centers_[b]), a.e1, a.e2, s * a.radius, a.phiExtent, l, h);
    }
    slo.push_back(l), shi.push_back(h);
  }
  for (const BallVertex& v : vertices_) {
    glm::dvec3 d[3];
    for (int m = 0; m < 3; ++m) d[m] = glm::normalize(centers_[v.balls[m]] - v.point);
    glm::dvec3 l = v.point, h = v.point;
    for (int c = 0; c < 3; ++c) {
      glm::dvec3 e(0.0);
      e[c] = 1.0;
      const double pad = 1e-9 * (reach_ + 1.0);
      h[c] += reach_ * std::max(0.0, maxOnTriangle(e, d)) + pad;
      l[c] -= reach_ * std::max(0.0, maxOnTriangle(-e, d)) + pad;
    }
    slo.push_back(l), shi.push_back(h);
  }
  sectorGrid_ = BoxGrid(slo, shi, std::max(0.33 * reach_, 0.4), 0.0);
}

bool BallUnion::exposed(std::uint32_t ball, const glm::dvec3& y) const {
  for (std::uint32_t k = neighbourStart_[ball]; k < neighbourStart_[ball + 1]; ++k) {
    const glm::dvec4& b = balls_[neighbours_[k]];
    const double limit = b.w * (1.0 - kCoveredTolerance);
    const glm::dvec3 d = y - glm::dvec3(b);
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

void BallUnion::consider(std::uint32_t k, const glm::dvec3& x, double& best2, UnionNearest& best) const {
  const std::uint32_t arcCount = static_cast<std::uint32_t>(arcs_.size());
  if (k >= arcCount) {
    const glm::dvec3 v = vertices_[k - arcCount].point;
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
  // On the axis every circle point is as near: the arc's ends (vertices) stand for them, and a
  // whole ring has no ends, so its φ = 0 point does.
  glm::dvec3 u = a.e1;
  if (rho > 1e-12 * a.radius) {
    u = radial / rho;
    // φ in [0, phiExtent] without atan2, from sin φ = u·e2 and sin(phiExtent − φ) = (u × end)·axis.
    const double sinPhi = glm::dot(u, a.e2);
    const double sinRest = glm::dot(glm::cross(u, arcEnd_[k]), a.axis);
    const bool inside = a.phiExtent <= std::numbers::pi ? sinPhi >= 0.0 && sinRest >= 0.0 : !(sinPhi < 0.0 && sinRest < 0.0);
    if (!inside) return;
  } else if (a.phiExtent < 2.0 * std::numbers::pi) {
    return;
  }
  best2 = q, best = {UnionFeature::Arc, k, 0.0, a.center + a.radius * u};
}

UnionNearest BallUnion::nearest(const glm::dvec3& x) const {
  // Every point of A lies outside every ball that holds x, so at least the largest depth
  // R − |x − c| away: only that deepest ball's sphere can hold the nearest point, and when its
  // radial projection lies in no other ball, that is the answer.
  double lower = 0.0;
  std::uint32_t deepest = 0;
  for (std::uint32_t k : ballGrid_.cellAt(x)) {
    const glm::dvec4& b = balls_[k];
    const glm::dvec3 d = x - glm::dvec3(b);
    const double q = glm::dot(d, d);
    if (q >= b.w * b.w) continue;
    const double depth = b.w - std::sqrt(q);
    if (depth > lower) lower = depth, deepest = k;
  }
  if (!(lower > 0.0)) {
    // Outside every ball (x is in A): the cell lists every ball within the reach.
    UnionNearest best;
    best.distance = kInf;
    for (std::uint32_t k : outsideGrid_.cellAt(x)) {
      const double gap = glm::length(x - glm::dvec3(balls_[k])) - balls_[k].w;
      if (gap < best.distance) best.distance = gap, best.index = k;
    }
    if (!(best.distance <= reach_)) return nearestOutside(x);
    const glm::dvec3 d = x - centers_[best.index];
    const double len = glm::length(d);
    best.point = centers_[best.index] + radii_[best.index] * (len > 0.0 ? d / len : glm::dvec3(0, 0, 1));
    best.distance = std::max(best.distance, 0.0);
    return best;
  }
  {
    const glm::dvec3 d = x - centers_[deepest];
    const double len = glm::length(d);
    const glm::dvec3 y = centers_[deepest] + radii_[deepest] * (len > 0.0 ? d / len : glm::dvec3(0, 0, 1));
    if (exposed(deepest, y)) return {UnionFeature::Sphere, deepest, lower, y};
  }
  // An arc or a vertex: the nearest one's normal sector holds x, so when it is within the
  // reach it is among the features listed in x's cell.
  UnionNearest best;
  double best2 = kInf;
  for (std::uint32_t k : sectorGrid_.cellAt(x)) consider(k, x, best2, best);
  if (best2 > reach_ * reach_) {
    // Deep inside: search boxes of features until one lies within the box.
    const double diag = featureGrid_.diagonal();
    for (double r = std::max(lower, reach_);; r *= 2.0) {
      featureGrid_.forEachInBox(x, r, [&](std::uint32_t k) { consider(k, x, best2, best); });
      if (best2 <= r * r || r > diag) break;
    }
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

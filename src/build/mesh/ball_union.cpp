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

  // The features on each ball's sphere (CSR).
  const std::uint32_t arcCount = static_cast<std::uint32_t>(arcs_.size());
  featureStart_.assign(n + 1, 0);
  for (const BallArc& a : arcs_) ++featureStart_[a.balls[0] + 1], ++featureStart_[a.balls[1] + 1];
  for (const BallVertex& v : vertices_)
    for (std::uint32_t b : v.balls) ++featureStart_[b + 1];
  for (std::size_t k = 0; k < n; ++k) featureStart_[k + 1] += featureStart_[k];
  features_.resize(featureStart_[n]);
  std::vector<std::uint32_t> fill(featureStart_.begin(), featureStart_.end() - 1);
  for (std::uint32_t k = 0; k < arcCount; ++k) {
    const auto& b = arcs_[k].balls;
    features_[fill[b[0]]++] = {k, {b[1], ~0u}};
    features_[fill[b[1]]++] = {k, {b[0], ~0u}};
  }
  for (std::uint32_t k = 0; k < vertices_.size(); ++k) {
    const auto& b = vertices_[k].balls;
    for (int m = 0; m < 3; ++m) features_[fill[b[m]]++] = {arcCount + k, {b[(m + 1) % 3], b[(m + 2) % 3]}};
  }

  std::vector<glm::dvec3> lo(n), hi(n);
  for (std::size_t k = 0; k < n; ++k) lo[k] = centers_[k] - radii_[k], hi[k] = centers_[k] + radii_[k];
  // Cells of about two thirds of the largest radius: a ball covers a few cells each way, and a
  // cell lists the balls near it without many that are not.
  ballGrid_ = BoxGrid(lo, hi, std::max(0.67 * maxRadius, 0.5), reach_);

  // Each arc's own box (its endpoints and the extremes of each coordinate inside its φ range),
  // for points deep inside, whose nearest feature may lie on a sphere beyond the reach.
  std::vector<glm::dvec3> flo, fhi;
  flo.reserve(arcs_.size() + vertices_.size());
  fhi.reserve(arcs_.size() + vertices_.size());
  for (const BallArc& a : arcs_) {
    const glm::dvec3 end = std::cos(a.phiExtent) * a.e1 + std::sin(a.phiExtent) * a.e2;
    arcEnd_.push_back(end);
    glm::dvec3 l = a.center + a.radius * a.e1, h = l;
    l = glm::min(l, a.center + a.radius * end), h = glm::max(h, a.center + a.radius * end);
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
  for (const BallVertex& v : vertices_) flo.push_back(v.point), fhi.push_back(v.point);
  featureGrid_ = BoxGrid(flo, fhi, std::max(2.0 * reach_, 1.0), 0.0);
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
  // The spheres that pass within the reach of x, with their signed gaps |x − c| − R.
  struct Near {
    double gap;
    std::uint32_t ball;
  };
  constexpr std::size_t kLocal = 256;
  Near local[kLocal];
  std::size_t count = 0;
  thread_local std::vector<Near> spillStore;
  std::vector<Near>& spill = spillStore;
  spill.clear();
  double lower = -kInf;
  std::uint32_t deepest = 0;
  for (std::uint32_t k : ballGrid_.cellAt(x)) {
    const glm::dvec3 d = x - centers_[k];
    const double q = glm::dot(d, d), outer = radii_[k] + reach_;
    if (q >= outer * outer) continue;
    const Near nk{std::sqrt(q) - radii_[k], k};
    if (count < kLocal)
      local[count++] = nk;
    else
      spill.push_back(nk);
    if (-nk.gap > lower) lower = -nk.gap, deepest = k;
  }
  // Outside every ball (x is in A): the cell lists every ball within the reach, so the smallest
  // gap among them is the distance to U unless there is none.
  if (lower <= 0.0) {
    if (count == 0) return nearestOutside(x);
    const glm::dvec3 d = x - centers_[deepest];
    const double len = glm::length(d);
    return {UnionFeature::Outside, deepest, std::max(-lower, 0.0),
            centers_[deepest] + radii_[deepest] * (len > 0.0 ? d / len : glm::dvec3(0, 0, 1))};
  }
  // Every point of A lies outside every ball that holds x, so at least the largest depth
  // R − |x − c| away: only that deepest ball's sphere can hold the nearest point, and when its
  // radial projection lies in no other ball, that is the answer.
  {
    const glm::dvec3 d = x - centers_[deepest];
    const double len = glm::length(d);
    const glm::dvec3 y = centers_[deepest] + radii_[deepest] * (len > 0.0 ? d / len : glm::dvec3(0, 0, 1));
    if (exposed(deepest, y)) return {UnionFeature::Sphere, deepest, lower, y};
  }
  // An arc or a vertex: a feature on sphere m is at least |gap_m| = ||x − c_m| − R_m| from x,
  // so a feature whose spheres all pass within the best distance so far is a candidate, and
  // once every such one is seen the best is final. The deepest sphere's own features first:
  // they usually hold the answer, and then few spheres pass nearer than it.
  struct Gap {
    double gap;
    std::uint64_t stamp;
  };
  thread_local std::vector<Gap> gapStore;
  thread_local std::uint64_t stamp = 0;
  if (gapStore.size() < centers_.size()) gapStore.resize(centers_.size(), Gap{0.0, 0});
  // Plain pointers: thread-local storage costs a look-up at every use.
  Gap* const gaps = gapStore.data();
  const std::uint64_t now = ++stamp;
  for (std::size_t k = 0; k < count; ++k) gaps[local[k].ball] = {std::abs(local[k].gap), now};
  for (const Near& nk : spill) gaps[nk.ball] = {std::abs(nk.gap), now};
  // A sphere outside the cell's list passes farther than the reach from x.
  const double reach = reach_;
  auto gap = [gaps, now, reach](std::uint32_t b) { return gaps[b].stamp == now ? gaps[b].gap : reach; };
  UnionNearest best;
  double best2 = kInf;
  // Each feature once, from the sphere of its largest gap (ties: the higher index), and only
  // when that gap is below the best distance.
  auto last = [&](std::uint32_t b, double gb, std::uint32_t o) {
    if (o == ~0u) return true;
    const double go = gap(o);
    return go < gb || (go == gb && o <= b);
  };
  auto scanBall = [&](std::uint32_t b, bool all) {
    const double gb = gap(b);
    for (std::uint32_t k = featureStart_[b]; k < featureStart_[b + 1]; ++k) {
      const BallFeature& f = features_[k];
      if (all || (last(b, gb, f.other[0]) && last(b, gb, f.other[1]))) consider(f.feature, x, best2, best);
    }
  };
  scanBall(deepest, true);
  auto scanNear = [&](const Near* begin, const Near* end) {
    for (const Near* n = begin; n != end; ++n)
      if (n->gap * n->gap < best2) scanBall(n->ball, false);
  };
  scanNear(local, local + count);
  scanNear(spill.data(), spill.data() + spill.size());
  if (best2 > reach_ * reach_) {
    // Deep inside: spheres beyond the reach may hold nearer features; search boxes of them.
    const double diag = featureGrid_.diagonal();
    for (double r = std::sqrt(best2) < kInf ? std::sqrt(best2) : 2.0 * std::max(lower, reach_);; r *= 2.0) {
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

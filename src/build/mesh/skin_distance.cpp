// The skin's field: G(x) by a primal active-set method over the atoms near x (its minimiser's
// support is the Delaunay simplex of x's mixed cell, ORACLES D.3), certified against every atom
// farther away; closest points by exact projection onto that cell's quadric.
#include "build/mesh/skin_distance.hpp"

#include <algorithm>
#include <cmath>
#include <limits>
#include <numbers>
#include <optional>
#include <vector>

#include <glm/geometric.hpp>

#include "build/mesh/ball_union.hpp"
#include "build/mss/skin_geometry.hpp"

namespace surftrace::build::mesh {

namespace {

constexpr double kInf = std::numeric_limits<double>::infinity();
// Active-set steps before the method gives up and keeps its best point (degenerate pivots).
constexpr int kMaxActiveSetSteps = 100;
// Projections onto a cell's quadric that land in another cell, before falling back to steps
// along the gradient.
constexpr int kMaxCellMoves = 8;
// A point is on the skin when G(p)/|∇G(p)| is below this (Å): the first-order distance.
constexpr double kOnSkin = 1e-10;
constexpr std::uint8_t kFirstSkinCode = 4;  // view::PatchKind::SkinConvex; + MssKind

struct Candidate {
  glm::dvec3 y;  // c_j − x
  double b;      // s π_j(x) = s|y|² − r²
  std::uint32_t atom;
};

// Solves the symmetric m×m system (m <= 3) G a = r; false when it is singular.
bool solveSmall(int m, const double (&g)[3][3], const double (&r)[3], double (&a)[3]) {
  if (m == 1) {
    if (!(g[0][0] > 0.0)) return false;
    a[0] = r[0] / g[0][0];
    return true;
  }
  if (m == 2) {
    const double det = g[0][0] * g[1][1] - g[0][1] * g[1][0];
    if (!(std::abs(det) > 1e-14 * g[0][0] * g[1][1])) return false;
    a[0] = (r[0] * g[1][1] - r[1] * g[0][1]) / det;
    a[1] = (g[0][0] * r[1] - g[1][0] * r[0]) / det;
    return true;
  }
  const glm::dvec3 c0(g[0][0], g[1][0], g[2][0]), c1(g[0][1], g[1][1], g[2][1]), c2(g[0][2], g[1][2], g[2][2]);
  const double det = glm::dot(c0, glm::cross(c1, c2));
  if (!(std::abs(det) > 1e-14 * g[0][0] * g[1][1] * g[2][2])) return false;
  const glm::dvec3 rv(r[0], r[1], r[2]);
  a[0] = glm::dot(rv, glm::cross(c1, c2)) / det;
  a[1] = glm::dot(c0, glm::cross(rv, c2)) / det;
  a[2] = glm::dot(c0, glm::cross(c1, rv)) / det;
  return true;
}

class SkinDistance final : public SurfaceDistance {
 public:
  SkinDistance(const PatchList& list, std::span<const glm::dvec3> centers, std::span<const double> radii)
      : centers_(centers.begin(), centers.end()),
        radii_(radii.begin(), radii.end()),
        s_(list.params.shrinkFactor),
        mss_(list.mss),
        cellPlanes_(list.cellPlanes) {
    weights_.resize(radii_.size());
    for (std::size_t k = 0; k < radii_.size(); ++k) {
      weights_[k] = mss::skinWeight(radii_[k], s_);
      rMax_ = std::max(rMax_, radii_[k]);
      rMin_ = std::min(rMin_, radii_[k]);
      // The skin lies in the centres' hull grown by r_max (build/surface.hpp).
      lo_ = glm::min(lo_, centers_[k] - rMax_), hi_ = glm::max(hi_, centers_[k] + rMax_);
    }
    for (std::size_t k = 0; k < radii_.size(); ++k) lo_ = glm::min(lo_, centers_[k] - rMax_), hi_ = glm::max(hi_, centers_[k] + rMax_);
    grid_ = BoxGrid(centers_, centers_, 2.5, 0.0);
    std::vector<glm::dvec3> lo(mss_.size()), hi(mss_.size());
    for (std::size_t k = 0; k < mss_.size(); ++k)
      lo[k] = mss_.center[k] - mss_.boundRadius[k], hi[k] = mss_.center[k] + mss_.boundRadius[k];
    patchGrid_ = BoxGrid(lo, hi, 2.0, 0.0);
  }

  double signedDistance(const glm::dvec3& x) const override {
    if (centers_.empty()) return kInf;
    const SkinValue v = evaluate(x);
    if (v.value == 0.0) return 0.0;
    const mss::SkinQuadric q = quadricOf(v);
    const double gl = glm::length(v.gradient);
    const glm::dvec3 g = gl > 0.0 ? v.gradient / gl : glm::dvec3(0, 0, 1);
    // f = (1 − s) G is this cell's quadric: exact along the line x + t g while it stays in the
    // cell, so its nearest root is the distance along the gradient (exact for the spheres).
    const double f0 = (1.0 - s_) * v.value, f1 = (1.0 - s_) * gl;
    const double f2 = q.radial + q.axial * glm::dot(g, q.axis) * glm::dot(g, q.axis);
    const double t = nearestRoot(f2, f1, f0);
    double d = std::isfinite(t) ? std::abs(t) : (gl > 0.0 ? std::abs(v.value) / gl : std::sqrt(std::abs(v.value)));
    // Near the skin the distance itself, to the closest point (exact), so that the mesher's
    // samples and its certificate see the true distance; farther, the estimate.
    if (d <= reach()) d = glm::length(project(x, v).point - x);
    return v.value < 0.0 ? -d : d;
  }

  SurfacePoint closest(const glm::dvec3& x) const override {
    if (centers_.empty()) return SurfacePoint{};
    return project(x, evaluate(x));
  }

  double reach() const override { return 0.5 * rMin_; }
  glm::dvec3 boundsMin() const override { return lo_; }
  glm::dvec3 boundsMax() const override { return hi_; }

  SkinValue evaluate(const glm::dvec3& x) const;

 private:
  // closest(x) from G at x, v0 = evaluate(x), which signedDistance has already (evaluate is
  // most of the skin mesher's time: a second one at the same point cost a fifth of it).
  SurfacePoint project(const glm::dvec3& x, const SkinValue& v0) const {
    SurfacePoint out;
    // Onto the skin first, along the gradient: each step to the nearest root of the current
    // cell's quadric on the line.
    glm::dvec3 p = x;
    SkinValue v = v0;
    for (int step = 0; step < 64 && !onSkin(v); ++step) {
      const mss::SkinQuadric q = quadricOf(v);
      const double gl = glm::length(v.gradient);
      const glm::dvec3 g = gl > 0.0 ? v.gradient / gl : glm::dvec3(0, 0, 1);
      const double t = nearestRoot(q.radial + q.axial * glm::dot(g, q.axis) * glm::dot(g, q.axis),
                                   (1.0 - s_) * gl, (1.0 - s_) * v.value);
      p += (std::isfinite(t) ? t : -v.value / std::max(gl, 1e-300)) * g;
      v = evaluate(p);
    }
    // The skin point nearest to x is a foot point of x on the quadric of a patch whose cell
    // holds it (on a facet between cells too: the skin is C¹ there, so it is a foot point of
    // both quadrics). Every patch that may come nearer than the point found so far offers all
    // of its foot points that lie in its cell.
    if (onSkin(v)) {
      // Boxes growing from the first-order distance up to |p − x|: once the best foot point is
      // within the box, every patch whose ball comes nearer has been seen.
      double best = glm::length(p - x);
      thread_local std::vector<std::uint64_t> seenStore;
      thread_local std::uint64_t seenStamp = 0;
      if (seenStore.size() < mss_.size()) seenStore.resize(mss_.size(), 0);
      std::uint64_t* const seen = seenStore.data();
      const std::uint64_t now = ++seenStamp;
      bool moved = false;
      auto visit = [&](std::uint32_t k) {
        if (seen[k] == now) return;
        seen[k] = now;
        if (glm::length(x - mss_.center[k]) - mss_.boundRadius[k] > best) return;
        // The patch lies in its cell, at least as far from x as x is beyond any cell plane.
        for (std::uint32_t c = mss_.cellBegin[k]; c < mss_.cellBegin[k] + mss_.cellCount[k]; ++c)
          if (glm::dot(glm::dvec3(cellPlanes_[c]), x) + cellPlanes_[c].w > best) return;
        forEachFootPoint(k, x, [&](const glm::dvec3& q) {
          const double d = glm::length(q - x);
          if (d < best && inPatch(k, q)) best = d, p = q, moved = true;
        });
      };
      const double gl0 = glm::length(v0.gradient);
      double r = std::min(best, std::max(gl0 > 0.0 ? 1.5 * std::abs(v0.value) / gl0 : best, 0.05));
      for (;;) {
        patchGrid_.forEachInBox(x, r, visit);
        if (best <= r) break;
        r = std::min(2.0 * r, best);
      }
      if (moved) v = evaluate(p);
    }
    out.point = p;
    const double gl = glm::length(v.gradient);
    out.normal = gl > 0.0 ? v.gradient / gl : glm::dvec3(0, 0, 1);
    // The owner: the simplex's atom of smallest power distance |p − c|² − r².
    double best = kInf;
    for (int k = 0; k < v.size; ++k) {
      const std::uint32_t a = v.atoms[k];
      const glm::dvec3 d = p - centers_[a];
      const double power = glm::dot(d, d) - radii_[a] * radii_[a];
      if (power < best) best = power, out.atom = a;
    }
    out.kind = static_cast<std::uint8_t>(kFirstSkinCode + v.size - 1);
    out.component = 0;
    return out;
  }

  static bool sameSupport(const SkinValue& a, const SkinValue& b) {
    if (a.size != b.size) return false;
    for (int k = 0; k < a.size; ++k)
      if (a.atoms[k] != b.atoms[k]) return false;
    return true;
  }
  static bool onSkin(const SkinValue& v) { return std::abs(v.value) <= kOnSkin * glm::length(v.gradient); }

  // The root of f2 t² + f1 t + f0 nearest to 0 (∞ when there is none).
  static double nearestRoot(double f2, double f1, double f0) {
    if (std::abs(f2) < 1e-300) return f1 != 0.0 ? -f0 / f1 : kInf;
    const double disc = f1 * f1 - 4.0 * f2 * f0;
    if (disc < 0.0) return kInf;
    const double qq = -0.5 * (f1 + std::copysign(std::sqrt(disc), f1));
    const double t1 = qq / f2, t2 = qq != 0.0 ? f0 / qq : kInf;
    return std::abs(t1) < std::abs(t2) ? t1 : t2;
  }

  mss::SkinQuadric quadricOf(const SkinValue& v) const {
    mss::Simplex x;
    x.size = v.size;
    for (int k = 0; k < v.size; ++k) x.atom[k] = v.atoms[k];
    const mss::WeightedPoints wp{centers_, weights_, s_};
    return mss::skinQuadric(wp, x, mss::orthocentre(wp, x));
  }

  // The patch's own membership test (trace/mss_patch.cpp insideCell): within its bounding ball
  // and on the kept side of its cell planes, with a slack relative to its size.
  bool inPatch(std::size_t k, const glm::dvec3& q) const {
    const glm::dvec3 d = q - mss_.center[k];
    const double slack = 1e-9 * (mss_.boundRadius[k] + 1.0);
    const double ball = mss_.boundRadius[k] + slack;
    if (glm::dot(d, d) > ball * ball) return false;
    for (std::uint32_t c = mss_.cellBegin[k]; c < mss_.cellBegin[k] + mss_.cellCount[k]; ++c) {
      const Plane& plane = cellPlanes_[c];
      const glm::dvec3 n(plane);
      if (glm::dot(n, d) + (glm::dot(n, mss_.center[k]) + plane.w) > slack) return false;
    }
    return true;
  }

  // f(q) for every foot point q of x on patch k's quadric (q − x ∥ ∇f(q)): with d = q − z,
  // h = d·a and v the rest, q − x = μ ∇f(q) gives h = h_x/(1 − 2μ k1), v = v_x/(1 − 2μ k2)
  // (k1 = radial + axial, k2 = radial), and f(q(μ)) = φ(μ) = 0. φ is smooth between its poles
  // 1/(2k): each interval is sampled densely towards its ends and every sign change bisected.
  // Where x lies on the axis or on the plane h = 0 the foot points at a pole form a circle or
  // a pair; they are added from the quadric's own equation.
  template <class F>
  void forEachFootPoint(std::size_t k, const glm::dvec3& x, F&& f) const {
    const glm::dvec3 z = mss_.center[k], a = mss_.axis[k];
    const double k1 = mss_.radialCoeff[k] + mss_.axialCoeff[k], k2 = mss_.radialCoeff[k], c = mss_.constant[k];
    const glm::dvec3 w = x - z;
    const double hx = glm::dot(w, a);
    const glm::dvec3 vx = w - hx * a;
    const double A = hx * hx, B = glm::dot(vx, vx);
    auto phi = [&](double mu) {
      const double p1 = 1.0 - 2.0 * mu * k1, p2 = 1.0 - 2.0 * mu * k2;
      return (A > 0.0 ? k1 * A / (p1 * p1) : 0.0) + (B > 0.0 ? k2 * B / (p2 * p2) : 0.0) + c;
    };
    auto emit = [&](double mu) {
      const double p1 = 1.0 - 2.0 * mu * k1, p2 = 1.0 - 2.0 * mu * k2;
      if (p1 == 0.0 || p2 == 0.0) return;
      const glm::dvec3 q = z + (hx / p1) * a + vx / p2;
      if (std::isfinite(q.x + q.y + q.z)) f(q);
    };
    // φ'(μ) = 4 k1² A/(1 − 2μk1)³ + 4 k2² B/(1 − 2μk2)³: of one sign where both factors are,
    // and zero only where (1 − 2μk2)/(1 − 2μk1) = −t with t = ∛(k2² B / (k1² A)), a single μ_E.
    // So the poles and μ_E cut the line into monotone pieces,
    // each with at most one root, bracketed and polished by safeguarded Newton–bisection.
    auto dphi = [&](double mu) {
      const double p1 = 1.0 - 2.0 * mu * k1, p2 = 1.0 - 2.0 * mu * k2;
      return 4.0 * ((A > 0.0 ? k1 * k1 * A / (p1 * p1 * p1) : 0.0) + (B > 0.0 ? k2 * k2 * B / (p2 * p2 * p2) : 0.0));
    };
    double cuts[3];
    int cutCount = 0;
    if (k1 != 0.0 && A > 0.0) cuts[cutCount++] = 0.5 / k1;
    if (k2 != 0.0 && B > 0.0 && (cutCount == 0 || k2 != k1)) cuts[cutCount++] = 0.5 / k2;
    if (cutCount == 2) {
      // φ' vanishes at most once, at μ_E (where the factors have opposite signs: between the
      // poles, or beyond them when k1 and k2 differ in sign): a cut wherever it falls.
      const double t = std::cbrt(k2 * k2 * B / (k1 * k1 * A));
      const double muE = (1.0 + t) / (2.0 * (k2 + t * k1));
      if (std::isfinite(muE) && muE != cuts[0] && muE != cuts[1]) cuts[cutCount++] = muE;
      std::sort(cuts, cuts + cutCount);
    }
    const double scale = 0.5 / std::max({std::abs(k1), std::abs(k2), 1e-6});
    // The sign φ takes near a cut from inside a piece: ±∞ at a pole (the sign of its term's
    // coefficient), the value itself at the extremum, c at ±∞.
    auto isPole = [&](double mu) { return (A > 0.0 && mu == 0.5 / k1) || (B > 0.0 && mu == 0.5 / k2); };
    for (int piece = 0; piece <= cutCount; ++piece) {
      const double lo = piece == 0 ? -kInf : cuts[piece - 1];
      const double hi = piece == cutCount ? kInf : cuts[piece];
      if (!std::isfinite(lo) && !std::isfinite(hi)) break;  // no cut: A = B = 0, x at the centre
      // A finite point inside the piece, then one near each end with the end's sign.
      auto inside = [&](double end, double from) {
        // From `from` towards `end` (a cut or ±∞) until φ takes the end's limiting sign.
        double mu = from;
        for (int halving = 1; halving <= 80; ++halving) {
          mu = std::isfinite(end) ? end + (from - end) * std::ldexp(1.0, -halving)
                                  : from + (end > 0 ? 1.0 : -1.0) * scale * std::ldexp(1.0, halving);
          const double v = phi(mu);
          const double limit = std::isfinite(end) ? (isPole(end) ? (end == 0.5 / k1 && A > 0.0 ? k1 : k2) : phi(end)) : c;
          if (limit == 0.0 || (v < 0.0) == (limit < 0.0)) return mu;
        }
        return mu;
      };
      const double mid = std::isfinite(lo) && std::isfinite(hi) ? 0.5 * (lo + hi)
                         : std::isfinite(lo)                   ? lo + scale
                                                               : hi - scale;
      const double l = std::isfinite(lo) && !isPole(lo) ? lo : inside(lo, mid);
      const double h = std::isfinite(hi) && !isPole(hi) ? hi : inside(hi, mid);
      double fl = phi(l), fh = phi(h);
      if (fl == 0.0) { emit(l); continue; }
      if (fh == 0.0) { emit(h); continue; }
      if ((fl < 0.0) == (fh < 0.0)) continue;
      // Safeguarded Newton–bisection on [left, right] with φ of opposite signs at the ends.
      double left = l, right = h, mu = 0.5 * (l + h);
      for (int it = 0; it < 100; ++it) {
        const double v = phi(mu);
        if (v == 0.0) break;
        if ((v < 0.0) == (fl < 0.0))
          left = mu, fl = v;
        else
          right = mu;
        const double d = dphi(mu);
        double next = d != 0.0 ? mu - v / d : 0.5 * (left + right);
        if (!(next > std::min(left, right) && next < std::max(left, right))) next = 0.5 * (left + right);
        if (next == mu || std::abs(right - left) <= 4.0 * std::numeric_limits<double>::epsilon() * std::abs(mu)) {
          mu = next;
          break;
        }
        mu = next;
      }
      emit(mu);
    }
    // x on the plane h = 0 (A = 0): at μ = 1/(2k1) h is free; x on the axis (B = 0): v is.
    if (A == 0.0 && k1 != 0.0 && k1 != k2) {
      const glm::dvec3 v = vx / (1.0 - k2 / k1);
      const double h2 = -(k2 * glm::dot(v, v) + c) / k1;
      if (h2 >= 0.0) f(z + std::sqrt(h2) * a + v), f(z - std::sqrt(h2) * a + v);
    }
    if (B == 0.0 && k2 != 0.0) {
      const double h = k1 != k2 ? hx / (1.0 - k1 / k2) : 0.0;
      const double v2 = -(k1 * h * h + c) / k2 - (k1 == k2 ? A : 0.0);
      glm::dvec3 perp = glm::cross(a, glm::dvec3(1, 0, 0));
      if (glm::dot(perp, perp) < 0.1) perp = glm::cross(a, glm::dvec3(0, 1, 0));
      if (v2 >= 0.0) f(z + (k1 != k2 ? h : hx) * a + std::sqrt(v2) * glm::normalize(perp));
    }
  }

  // The nearest point to x of the quadric f = radial|d|² + axial (d·a)² + constant (d = p − z),
  // on the branch of the foot-point equation through x: p − x = μ ∇f(p) splits into the axial
  // part h = h_x / (1 − 2μ k1) and the radial part v = v_x / (1 − 2μ k2) (k1 = radial + axial,
  // k2 = radial), and f(p(μ)) is increasing in μ between the poles around 0.
  static std::optional<glm::dvec3> footPoint(const mss::SkinQuadric& q, const glm::dvec3& x) {
    const glm::dvec3 w = x - q.center;
    const double hx = glm::dot(w, q.axis);
    const glm::dvec3 vx = w - hx * q.axis;
    const double k1 = q.radial + q.axial, k2 = q.radial, A = hx * hx, B = glm::dot(vx, vx);
    auto phi = [&](double mu) {
      const double a = 1.0 - 2.0 * mu * k1, b = 1.0 - 2.0 * mu * k2;
      return (A > 0.0 ? k1 * A / (a * a) : 0.0) + (B > 0.0 ? k2 * B / (b * b) : 0.0) + q.constant;
    };
    double lo = -kInf, hi = kInf;
    for (const auto& [k, coef] : {std::pair{k1, A}, std::pair{k2, B}}) {
      if (!(coef > 0.0) || k == 0.0) continue;
      if (k > 0.0)
        hi = std::min(hi, 0.5 / k);
      else
        lo = std::max(lo, 0.5 / k);
    }
    const double f0 = phi(0.0);
    if (f0 == 0.0) return x;
    double a = 0.0, b = 0.0;  // φ(a) < 0 < φ(b)
    const double step = 0.5 / std::max({std::abs(k1), std::abs(k2), 1e-3});
    if (f0 > 0.0) {
      b = 0.0;
      if (std::isfinite(lo)) {
        a = lo;
      } else {
        a = -step;
        for (int k = 0; k < 200 && phi(a) >= 0.0; ++k) a *= 2.0;
        if (phi(a) >= 0.0) return std::nullopt;
      }
    } else {
      a = 0.0;
      if (std::isfinite(hi)) {
        b = hi;
      } else {
        b = step;
        for (int k = 0; k < 200 && phi(b) <= 0.0; ++k) b *= 2.0;
        if (phi(b) <= 0.0) return std::nullopt;
      }
    }
    for (int k = 0; k < 400; ++k) {
      const double mid = 0.5 * (a + b);
      if (mid <= a || mid >= b) break;
      (phi(mid) < 0.0 ? a : b) = mid;
    }
    // The end nearer the root: where the factors are finite.
    const double mu = std::abs(phi(a)) < std::abs(phi(b)) ? a : b;
    const double fa = 1.0 - 2.0 * mu * k1, fb = 1.0 - 2.0 * mu * k2;
    if (fa == 0.0 || fb == 0.0) return std::nullopt;
    const glm::dvec3 p = q.center + (hx / fa) * q.axis + vx / fb;
    if (!std::isfinite(p.x + p.y + p.z)) return std::nullopt;
    return p;
  }

  std::vector<glm::dvec3> centers_;
  std::vector<double> radii_, weights_;
  double s_ = 0.5, rMax_ = 0.0, rMin_ = kInf;
  BoxGrid grid_;
  MssQuadrics mss_;                // the patches: quadric, cell and bounding ball
  std::vector<Plane> cellPlanes_;
  BoxGrid patchGrid_;
  glm::dvec3 lo_{kInf}, hi_{-kInf};
};

SkinValue SkinDistance::evaluate(const glm::dvec3& x) const {
  thread_local std::vector<Candidate> cand;
  const double s = s_, t = 1.0 - s_;
  double gather = rMax_ / s + 1.0;
  for (int round = 0;; ++round) {
    cand.clear();
    grid_.forEachInBox(x, gather, [&](std::uint32_t k) {
      const glm::dvec3 y = centers_[k] - x;
      const double q = glm::dot(y, y);
      if (q <= gather * gather) cand.push_back({y, s * q - radii_[k] * radii_[k], k});
    });
    if (cand.empty()) {
      if (gather > 4.0 * grid_.diagonal() + 1e3) {
        for (std::uint32_t k = 0; k < centers_.size(); ++k) {
          const glm::dvec3 y = centers_[k] - x;
          cand.push_back({y, s * glm::dot(y, y) - radii_[k] * radii_[k], k});
        }
      } else {
        gather *= 2.0;
        continue;
      }
    }
    const std::size_t m = cand.size();
    // Start at the vertex of smallest F(e_j) = |y_j|² − r_j².
    int support[4];
    double lambda[4];
    int size = 1;
    {
      std::size_t best = 0;
      double bestF = kInf;
      for (std::size_t j = 0; j < m; ++j) {
        const double f = t * glm::dot(cand[j].y, cand[j].y) + cand[j].b;
        if (f < bestF) bestF = f, best = j;
      }
      support[0] = static_cast<int>(best), lambda[0] = 1.0;
    }
    glm::dvec3 v(0.0);
    double nu = 0.0;
    for (int iter = 0; iter < kMaxActiveSetSteps; ++iter) {
      // The minimiser on the affine hull of the support: μ_0 = 1 − Σμ_k, E μ' the offsets.
      double mu[4] = {1.0, 0.0, 0.0, 0.0};
      if (size > 1) {
        const glm::dvec3 y0 = cand[support[0]].y;
        glm::dvec3 e[3];
        double g[3][3], r[3], a[3];
        for (int k = 1; k < size; ++k) e[k - 1] = cand[support[k]].y - y0;
        for (int i = 0; i < size - 1; ++i) {
          for (int j = 0; j < size - 1; ++j) g[i][j] = glm::dot(e[i], e[j]);
          r[i] = -glm::dot(e[i], y0) - (cand[support[i + 1]].b - cand[support[0]].b) / (2.0 * t);
        }
        if (!solveSmall(size - 1, g, r, a)) {
          // A flat support: drop its newest atom (the others were a regular support).
          --size;
          continue;
        }
        double sum = 0.0;
        for (int k = 1; k < size; ++k) mu[k] = a[k - 1], sum += a[k - 1];
        mu[0] = 1.0 - sum;
      }
      // Infeasible: step towards μ until a weight reaches 0, and drop that atom.
      double step = 1.0;
      int blocking = -1;
      for (int k = 0; k < size; ++k)
        if (mu[k] < 0.0) {
          const double tk = lambda[k] / (lambda[k] - mu[k]);
          if (tk < step) step = tk, blocking = k;
        }
      for (int k = 0; k < size; ++k) lambda[k] += step * (mu[k] - lambda[k]);
      if (blocking >= 0) {
        for (int k = blocking; k + 1 < size; ++k) support[k] = support[k + 1], lambda[k] = lambda[k + 1];
        --size;
        continue;
      }
      // Optimal on the support: check every candidate's reduced gradient.
      v = glm::dvec3(0.0);
      for (int k = 0; k < size; ++k) v += lambda[k] * cand[support[k]].y;
      nu = 0.0;
      for (int k = 0; k < size; ++k) nu += lambda[k] * (2.0 * t * glm::dot(cand[support[k]].y, v) + cand[support[k]].b);
      double worst = 0.0;
      int enter = -1;
      const double tolerance = 1e-13 * (rMax_ * rMax_ + glm::dot(v, v));
      for (std::size_t j = 0; j < m; ++j) {
        const double reduced = 2.0 * t * glm::dot(cand[j].y, v) + cand[j].b - nu;
        if (reduced < worst - tolerance) {
          bool in = false;
          for (int k = 0; k < size; ++k) in = in || support[k] == static_cast<int>(j);
          if (!in) worst = reduced, enter = static_cast<int>(j);
        }
      }
      if (enter < 0) break;
      if (size == 4) {
        // Five points in space are affinely dependent: along the dependency α (α_enter = 1,
        // Σα = 0, Σα z = 0) v stays and F falls by α·b < 0, until a weight reaches 0.
        const glm::dvec3 y0 = cand[support[0]].y;
        const glm::dvec3 e0 = cand[support[1]].y - y0, e1 = cand[support[2]].y - y0, e2 = cand[support[3]].y - y0;
        const glm::dvec3 target = cand[enter].y - y0;
        const double det = glm::dot(e0, glm::cross(e1, e2));
        if (det == 0.0) break;
        const double gamma[3] = {glm::dot(target, glm::cross(e1, e2)) / det, glm::dot(e0, glm::cross(target, e2)) / det,
                                 glm::dot(e0, glm::cross(e1, target)) / det};
        const double alpha[4] = {-(1.0 - gamma[0] - gamma[1] - gamma[2]), -gamma[0], -gamma[1], -gamma[2]};
        double move = kInf;
        int out = -1;
        for (int k = 0; k < 4; ++k)
          if (alpha[k] < 0.0 && lambda[k] / -alpha[k] < move) move = lambda[k] / -alpha[k], out = k;
        if (out < 0) break;
        for (int k = 0; k < 4; ++k) lambda[k] += move * alpha[k];
        support[out] = enter, lambda[out] = move;
        continue;
      }
      support[size] = enter, lambda[size] = 0.0;
      ++size;
    }
    // Every atom farther than `need` has a reduced gradient >= 0 (see the header's bound), so
    // the minimum over the candidates is the global one.
    const double vl = glm::length(v);
    const double need = (t * vl + std::sqrt(t * t * vl * vl + s * std::max(0.0, rMax_ * rMax_ + nu))) / s;
    if (need > gather && round < 8 && m < centers_.size()) {
      gather = need * 1.01;
      continue;
    }
    SkinValue out;
    double value = t * glm::dot(v, v);
    for (int k = 0; k < size; ++k) value += lambda[k] * cand[support[k]].b;
    out.value = value;
    out.gradient = -2.0 * v;
    out.size = size;
    for (int k = 0; k < size; ++k) out.atoms[k] = cand[support[k]].atom;
    std::sort(out.atoms, out.atoms + size);
    return out;
  }
}

}  // namespace

std::unique_ptr<SurfaceDistance> makeSkinDistance(const PatchList& patches, std::span<const glm::dvec3> centers,
                                                  std::span<const double> radii) {
  return std::make_unique<SkinDistance>(patches, centers, radii);
}

}  // namespace surftrace::build::mesh

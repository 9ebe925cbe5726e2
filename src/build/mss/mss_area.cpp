// MSS areas and volumes: spheres in closed form, hyperboloids of revolution by boundary integrals
// (and, as the test oracle, by quadrature along their axis). For a patch about z with axis a write x = z + h a + ρ e(φ); in every mixed cell of
// an edge or a triangle the lateral planes contain a, so the cross-section is one polygon for
// all h and the circle of radius ρ(h) meets it in arcs whose length Φ and moment E = ∫ e dφ are
// closed form. With f = B ρ² + A h² + c (B = radial, A = radial + axial) the surface is
// ρ² = α h² + β (α = −A/B > 0, β = −c/B), dA = J dh dφ with J = √(ρ² + α² h²), and
//   area = ∫ J Φ dh,  ∫ n dA = ∫ (sign(B) ρ E + (A/|B|) h Φ a) dh,  ∫ (x − z)·n dA = ∫ (−c/|B|) Φ dh.
// computeMssAreas turns these into integrals over the patch's boundary (hyperboloidMomentsBoundary).
#include "build/mss/mss_area.hpp"

#include <algorithm>
#include <array>
#include <cmath>
#include <limits>
#include <tuple>
#include <numbers>

#include <boost/math/quadrature/gauss.hpp>
#include <boost/math/quadrature/gauss_kronrod.hpp>
#include <glm/geometric.hpp>
#include <glm/vec2.hpp>
#include <tbb/enumerable_thread_specific.h>
#include <tbb/parallel_for.h>

#include "build/core/vector_math.hpp"
#include "build/neighbour_grid.hpp"
#include "build/spherical_region.hpp"

namespace surftrace::build {
namespace {

constexpr double kTwoPi = 2.0 * std::numbers::pi;

// ∫ over the patch of 1, (x − z)·n, n and x − z.
struct Moments {
  double area = 0.0, flux = 0.0;
  glm::dvec3 normal{0.0}, first{0.0};

  Moments& operator+=(const Moments& o) {
    area += o.area;
    flux += o.flux;
    normal += o.normal;
    first += o.first;
    return *this;
  }
  friend Moments operator*(double k, const Moments& m) { return {k * m.area, k * m.flux, k * m.normal, k * m.first}; }
};

struct Lateral {
  double angle;   // direction of the plane normal's part across the axis, in the (e1, e2) frame
  double length;  // |that part|
  double offset;  // −(n·z + d)
  double along;   // n·a
  double nx, ny;  // the unit normal of the side in the cross-section, (cos, sin)(angle)
  double dist;    // its signed distance from the axis, offset/length
};

struct Revolution {
  glm::dvec3 z, a, e1, e2;
  double A, B, c, alpha, beta;
  std::vector<Lateral> laterals;
};

// An arc of the circle outside one lateral side: its angles and the unit vectors at its ends.
struct ExcludedArc {
  double lo, hi;
  glm::dvec2 eLo, eHi;
};

struct Scratch {
  SphericalRegionScratch sphere;
  std::vector<Cap> caps;
  std::vector<std::array<double, 2>> arcs, merged, pieces;
  std::vector<ExcludedArc> excluded, excludedMerged;
  std::vector<double> breaks, tail;
  Revolution rev;
};

// Length Φ and ∫ e dφ (in the e1, e2 frame) of the part of the circle of radius ρ at height h
// inside every lateral half-plane.
void circleInPolygon(const Revolution& r, double h, double rho, Scratch& sc, double& phi, glm::dvec2& moment) {
  sc.arcs.clear();
  for (const Lateral& l : r.laterals) {
    const double kappa = (l.offset - h * l.along) / (rho * l.length);
    if (kappa >= 1.0) continue;
    if (kappa <= -1.0) {
      phi = 0.0;
      moment = glm::dvec2(0.0);
      return;
    }
    const double half = std::acos(kappa);
    double lo = std::fmod(l.angle - half, kTwoPi);
    if (lo < 0.0) lo += kTwoPi;
    sc.arcs.push_back({lo, lo + 2.0 * half});
  }
  std::sort(sc.arcs.begin(), sc.arcs.end());
  sc.merged.clear();
  for (const auto& arc : sc.arcs) {
    if (!sc.merged.empty() && arc[0] <= sc.merged.back()[1])
      sc.merged.back()[1] = std::max(sc.merged.back()[1], arc[1]);
    else
      sc.merged.push_back(arc);
  }
  // The last arc may run past 2π over the first ones.
  std::size_t first = 0;
  while (sc.merged.size() - first > 1 && sc.merged.back()[1] - kTwoPi >= sc.merged[first][0]) {
    sc.merged.back()[1] = std::max(sc.merged.back()[1], sc.merged[first][1] + kTwoPi);
    ++first;
  }
  double excluded = 0.0;
  glm::dvec2 excludedMoment(0.0);
  for (std::size_t k = first; k < sc.merged.size(); ++k) {
    const auto& [lo, hi] = sc.merged[k];
    excluded += hi - lo;
    excludedMoment += glm::dvec2(std::sin(hi) - std::sin(lo), std::cos(lo) - std::cos(hi));
  }
  if (excluded >= kTwoPi) {
    phi = 0.0;
    moment = glm::dvec2(0.0);
    return;
  }
  phi = kTwoPi - excluded;
  moment = -excludedMoment;  // ∫ e over the whole circle is 0
}

// circleInPolygon without trigonometry beyond one acos a side: the ends of the arc cut off by
// a side are (κ n ∓ √(1 − κ²) n⊥) for its unit normal n, so ∫ e dφ needs no sin or cos, and
// the angles need no fmod (angle − acos κ lies in (−2π, π]).
void circleInPolygonFast(const Revolution& r, double h, double rho, Scratch& sc, double& phi, glm::dvec2& moment) {
  sc.excluded.clear();
  for (const Lateral& l : r.laterals) {
    const double kappa = (l.offset - h * l.along) / (rho * l.length);
    if (kappa >= 1.0) continue;
    if (kappa <= -1.0) {
      phi = 0.0;
      moment = glm::dvec2(0.0);
      return;
    }
    const double half = std::acos(kappa), sine = std::sqrt((1.0 - kappa) * (1.0 + kappa));
    double lo = l.angle - half;
    if (lo < 0.0) lo += kTwoPi;
    sc.excluded.push_back({lo, lo + 2.0 * half, {kappa * l.nx + sine * l.ny, kappa * l.ny - sine * l.nx},
                           {kappa * l.nx - sine * l.ny, kappa * l.ny + sine * l.nx}});
  }
  std::sort(sc.excluded.begin(), sc.excluded.end(), [](const ExcludedArc& a, const ExcludedArc& b) { return a.lo < b.lo; });
  auto& merged = sc.excludedMerged;
  merged.clear();
  for (const ExcludedArc& arc : sc.excluded) {
    if (!merged.empty() && arc.lo <= merged.back().hi) {
      if (arc.hi > merged.back().hi) {
        merged.back().hi = arc.hi;
        merged.back().eHi = arc.eHi;
      }
    } else {
      merged.push_back(arc);
    }
  }
  // The last arc may run past 2π over the first ones.
  std::size_t first = 0;
  while (merged.size() - first > 1 && merged.back().hi - kTwoPi >= merged[first].lo) {
    if (merged[first].hi + kTwoPi > merged.back().hi) {
      merged.back().hi = merged[first].hi + kTwoPi;
      merged.back().eHi = merged[first].eHi;
    }
    ++first;
  }
  double excluded = 0.0;
  glm::dvec2 excludedMoment(0.0);
  for (std::size_t k = first; k < merged.size(); ++k) {
    const ExcludedArc& arc = merged[k];
    excluded += arc.hi - arc.lo;
    excludedMoment += glm::dvec2(arc.eHi.y - arc.eLo.y, arc.eLo.x - arc.eHi.x);
  }
  if (excluded >= kTwoPi) {
    phi = 0.0;
    moment = glm::dvec2(0.0);
    return;
  }
  phi = kTwoPi - excluded;
  moment = -excludedMoment;  // ∫ e over the whole circle is 0
}

Moments revolutionIntegrand(const Revolution& r, double h, Scratch& sc) {
  const double rho2 = r.alpha * h * h + r.beta;
  if (!(rho2 > 0.0)) return {};
  const double rho = std::sqrt(rho2);
  double phi;
  glm::dvec2 e;
  circleInPolygon(r, h, rho, sc, phi, e);
  if (phi == 0.0) return {};
  const double J = std::sqrt(rho2 + r.alpha * r.alpha * h * h);
  const glm::dvec3 E = e.x * r.e1 + e.y * r.e2;
  const double absB = std::abs(r.B);
  return {J * phi, -r.c / absB * phi, (r.B > 0 ? 1.0 : -1.0) * rho * E + (r.A / absB) * h * phi * r.a,
          J * (h * phi * r.a + rho * E)};
}

// Adaptive Gauss–Kronrod (7/15 points, nodes and weights from Boost.Math) of the vector of
// moments; the area component steers the subdivision. Returns the error estimate.
double integrate(const Revolution& r, double lo, double hi, double tol, int depth, Scratch& sc, Moments& out) {
  using Kronrod = boost::math::quadrature::gauss_kronrod<double, 15>;
  using Gauss = boost::math::quadrature::gauss<double, 7>;
  const auto& x = Kronrod::abscissa();
  const auto& wk = Kronrod::weights();
  const auto& wg = Gauss::weights();
  const double mid = 0.5 * (lo + hi), half = 0.5 * (hi - lo);
  Moments kronrod, gauss;
  for (std::size_t k = 0; k < x.size(); ++k) {
    Moments f = revolutionIntegrand(r, mid + half * x[k], sc);
    if (k > 0) f += revolutionIntegrand(r, mid - half * x[k], sc);
    kronrod += wk[k] * f;
    if (k % 2 == 0) gauss += wg[k / 2] * f;
  }
  const double error = half * std::abs(kronrod.area - gauss.area);
  if (error <= tol || depth >= 40 || half < 1e-13 * (1.0 + std::abs(mid))) {
    out += half * kronrod;
    return error;
  }
  return integrate(r, lo, mid, 0.5 * tol, depth + 1, sc, out) + integrate(r, mid, hi, 0.5 * tol, depth + 1, sc, out);
}

// Frame, cap heights [lo, hi] and lateral sides of hyperboloid patch k; false for an empty cell.
bool setUpRevolution(const PatchList& p, std::size_t k, Revolution& r, double& lo, double& hi) {
  const MssQuadrics& q = p.mss;
  r.z = q.center[k];
  r.a = q.axis[k];
  r.e1 = perpendicularTo(r.a);
  r.e2 = glm::cross(r.a, r.e1);
  r.B = q.radialCoeff[k];
  r.A = q.radialCoeff[k] + q.axialCoeff[k];
  r.c = q.constant[k];
  r.alpha = -r.A / r.B;
  r.beta = -r.c / r.B;
  const double bound = q.boundRadius[k];
  lo = -bound;
  hi = bound;
  r.laterals.clear();
  for (std::uint32_t c = 0; c < q.cellCount[k]; ++c) {
    const Plane& plane = p.cellPlanes[q.cellBegin[k] + c];
    const glm::dvec3 n(plane);
    const double along = glm::dot(n, r.a), offset = -(glm::dot(n, r.z) + plane.w);
    if (std::abs(along) > 0.5) {
      (along > 0 ? hi : lo) = along > 0 ? std::min(hi, offset / along) : std::max(lo, offset / along);
    } else {
      const double x = glm::dot(n, r.e1), y = glm::dot(n, r.e2);
      const double length = std::sqrt(x * x + y * y);  // |along| <= 0.5: no overflow, and no hypot call
      r.laterals.push_back({std::atan2(y, x), length, offset, along, x / length, y / length, offset / length});
    }
  }
  return lo < hi;
}

// The reference integration, kept as the test oracle (issue 22): adaptive Gauss–Kronrod in h
// between every candidate breakpoint (every pair of lateral lines, met or not), each piece to
// relTol·2π·bound². The square-root ends of Φ (acos near ±1) make it subdivide ~30 times a patch.
double hyperboloidMomentsAdaptive(const PatchList& p, std::size_t k, double relTol, Scratch& sc, Moments& m) {
  Revolution& r = sc.rev;
  double lo, hi;
  if (!setUpRevolution(p, k, r, lo, hi)) return 0.0;
  const double bound = p.mss.boundRadius[k];

  // Breakpoints: where ρ(h) vanishes, h = 0, and where the circle touches a lateral line or
  // passes a corner of the cross-section.
  sc.breaks.assign({lo, hi, 0.0});
  auto addRadius = [&](double rho) {
    const double h2 = (rho * rho - r.beta) / r.alpha;
    if (h2 >= 0.0) {
      sc.breaks.push_back(std::sqrt(h2));
      sc.breaks.push_back(-std::sqrt(h2));
    }
  };
  addRadius(0.0);
  for (std::size_t u = 0; u < r.laterals.size(); ++u) {
    const Lateral& lu = r.laterals[u];
    addRadius(std::abs(lu.offset) / lu.length);
    for (std::size_t v = u + 1; v < r.laterals.size(); ++v) {
      const Lateral& lv = r.laterals[v];
      // Corner: (cos, sin)(angle)·x = offset/length for both lines.
      const double a1 = std::cos(lu.angle), b1 = std::sin(lu.angle), c1 = lu.offset / lu.length;
      const double a2 = std::cos(lv.angle), b2 = std::sin(lv.angle), c2 = lv.offset / lv.length;
      const double det = a1 * b2 - a2 * b1;
      if (std::abs(det) < 1e-12) continue;
      addRadius(std::hypot((c1 * b2 - c2 * b1) / det, (a1 * c2 - a2 * c1) / det));
    }
  }
  std::sort(sc.breaks.begin(), sc.breaks.end());
  const double tol = relTol * kTwoPi * bound * bound;
  double error = 0.0;
  for (std::size_t b = 0; b + 1 < sc.breaks.size(); ++b) {
    const double x0 = std::max(lo, sc.breaks[b]), x1 = std::min(hi, sc.breaks[b + 1]);
    if (x1 > x0) error += integrate(r, x0, x1, tol, 0, sc, m);
  }
  return error;
}

// The boundary integral (issue 22). Over the patch dA = J dh dφ on the region
// R = {(h, φ): h ∈ [lo, hi], ρ(h) e(φ) ∈ P} of the (h, φ) cylinder, P the cross-section polygon.
// Green's theorem on the cylinder turns each moment ∫∫_R f dh dφ into ∮_∂R (L dh + M dφ) with
// ∂M/∂h − ∂L/∂φ = f: the parts of f constant in φ take M = ∫ f dh, closed form (area: ∫ J dh
// with J = √(γh² + β), γ = α(1 + α)), and the parts ∝ e(φ) take L = F(h) e⊥(φ) with F = the
// coefficient, which needs no antiderivative at all. ∂R is made of the caps (h = lo, hi, where
// ∮ = ±M(h) Φ(h), closed form), the tips (ρ = 0: ±M·2π when the axis lies in P) and, on each
// side of P, the conic where the side's plane cuts the hyperboloid: α h² − t² = dist² − β for
// the coordinate t along the side. Parametrised by σ with cosh and sinh, each conic branch is
// an entire function of σ but for poles and branch points ~π/2 off the real axis (or ~dist/√k
// beside a tip), so Gauss–Kronrod converges geometrically on a handful of pieces where the
// integration in h needed ~16 pieces between every corner's and foot's height.

// M for the φ-constant parts of area, flux, normal·a and first moment·a, and J.
struct Potentials {
  double area = 0.0, flux = 0.0, axial = 0.0, firstAxial = 0.0, J = 0.0;
};

// The patch's constants of the potentials, with the quotients that do not depend on h formed
// once (the same roundings as forming them at every h: each is the leftmost operation of its
// expression there).
struct BoundaryFrame {
  double gamma, sqrtGamma, absB, signB, sqrtBeta;
  double betaOverSqrtGamma, fluxPerH, axialPerH2, inverseThreeGamma;  // β/√γ, −c/|B|, ½A/|B|, 1/(3γ)
  double inverseSqrtBeta;  // 1/√β (0 for β <= 0, where it is not used): two divisions an evaluation fewer

  explicit BoundaryFrame(const Revolution& r)
      : gamma(r.alpha * (1.0 + r.alpha)), sqrtGamma(std::sqrt(gamma)), absB(std::abs(r.B)), signB(r.B > 0.0 ? 1.0 : -1.0),
        sqrtBeta(std::sqrt(std::max(0.0, r.beta))), betaOverSqrtGamma(r.beta / sqrtGamma), fluxPerH(-r.c / absB),
        axialPerH2(0.5 * r.A / absB), inverseThreeGamma(1.0 / (3.0 * gamma)),
        inverseSqrtBeta(sqrtBeta > 0.0 ? 1.0 / sqrtBeta : 0.0) {}
};

Potentials potentials(const Revolution& r, const BoundaryFrame& f, double h) {
  Potentials m;
  const double a = std::abs(h), h2 = h * h;
  m.J = std::sqrt(std::max(0.0, f.gamma * h2 + r.beta));
  // ∫ √(γh² + β) dh = ½(hJ + β/√γ · ln(√γ h + J)), odd in h: for β > 0 the log of
  // (√γ|h| + J)/√β = 1 + (√γ|h| + γh²/(J + √β))/√β, so that it vanishes at h = 0 (asinh without
  // its overhead); for β < 0 (two sheets, |h| beyond the tips) any constant does (anchors).
  // From x = 1 on, rounding 1 + x costs at most an ulp of log(1 + x) >= ln 2, and glibc's log is
  // cheaper than its log1p (~3 % of the skin's areas on 1AON).
  double log = 0.0;
  if (r.beta > 0.0) {
    const double x = (f.sqrtGamma * a + f.gamma * h2 / (m.J + f.sqrtBeta)) * f.inverseSqrtBeta;
    log = x >= 1.0 ? std::log(1.0 + x) : std::log1p(x);
  } else if (r.beta < 0.0)
    log = std::log(f.sqrtGamma * a + m.J);
  const double half = 0.5 * (a * m.J + f.betaOverSqrtGamma * log);
  m.area = h < 0.0 ? -half : half;
  m.flux = f.fluxPerH * h;
  m.axial = f.axialPerH2 * h2;
  m.firstAxial = m.J * m.J * m.J * f.inverseThreeGamma;
  return m;
}

// One branch of a side's conic: x = foot + t·along in the (e1, e2) frame, and either
// t = tScale sinh σ, h = hScale cosh σ (k > 0) or t = tScale cosh σ, h = hScale sinh σ (k < 0,
// the branch crosses the waist). `orientation` makes increasing σ run anticlockwise about R.
struct ConicBranch {
  bool crossesWaist;
  double tScale, hScale, orientation, dist;
  glm::dvec2 foot, along;
  Potentials ref;  // M is taken relative to the sheet's anchor (∮ dφ = 0), against cancellation
  double orientedDist, dist2;  // orientation·dist and dist², formed once
};

// sinh and cosh from expm1: (e − 1/e)/2 loses all but a few digits at |σ| ~ 1e-5, where a side
// passing close to a tip puts a peak.
struct Hyperbolic {
  double sh, ch;
  explicit Hyperbolic(double sigma) {
    const double em1 = std::expm1(sigma), ie = 1.0 / (1.0 + em1);
    sh = 0.5 * em1 * (1.0 + ie);
    ch = 1.0 + 0.5 * em1 * em1 * ie;
  }
  Hyperbolic(double s, double c) : sh(s), ch(c) {}
};

// The integrand at σ with sinh σ and cosh σ given.
Moments conicAt(const Revolution& r, const BoundaryFrame& f, const ConicBranch& q, Hyperbolic hyp) {
  const double sh = hyp.sh, ch = hyp.ch;
  double t, dt, h, dh;
  if (q.crossesWaist) {
    t = q.tScale * ch, dt = q.tScale * sh, h = q.hScale * sh, dh = q.hScale * ch;
  } else {
    t = q.tScale * sh, dt = q.tScale * ch, h = q.hScale * ch, dh = q.hScale * sh;
  }
  const double dphi = q.orientedDist * dt / (q.dist2 + t * t);
  const glm::dvec2 x = q.foot + t * q.along;
  const glm::dvec3 perp = q.orientation * dh * (-x.y * r.e1 + x.x * r.e2);  // ρ e⊥(φ) dh
  const Potentials m = potentials(r, f, h);
  Moments out;
  out.area = (m.area - q.ref.area) * dphi;
  out.flux = (m.flux - q.ref.flux) * dphi;
  out.normal = (m.axial - q.ref.axial) * dphi * r.a + f.signB * perp;
  out.first = (m.firstAxial - q.ref.firstAxial) * dphi * r.a + m.J * perp;
  return out;
}

Moments conicIntegrand(const Revolution& r, const BoundaryFrame& f, const ConicBranch& q, double sigma) {
  return conicAt(r, f, q, Hyperbolic(sigma));
}

// The conic integrand as a Kronrod rule wants it: the nodes come in pairs mid ± d, whose sinh
// and cosh follow from those of mid and d by the addition theorems, one expm1 a pair instead of
// two (expm1 was a sixth of the boundary integral's time on 1AON). The sum sinh mid cosh d −
// cosh mid sinh d loses relative digits where mid ≈ d, but keeps the absolute error within a
// few ulps of the piece's ends: this integrand has no peak narrower than its piece (the peaks
// beside a tip go through the sinh substitution, which evaluates σ on its own).
struct ConicIntegrand {
  const Revolution& r;
  const BoundaryFrame& f;
  const ConicBranch& q;
  Moments operator()(double sigma) const { return conicIntegrand(r, f, q, sigma); }
  template <std::size_t N>
  void rule(double mid, double half, const std::array<double, N>& x, std::array<Moments, 2 * N - 1>& values) const {
    const Hyperbolic m(mid);
    values[0] = conicAt(r, f, q, m);
    for (std::size_t k = 1; k < N; ++k) {
      const Hyperbolic d(half * x[k]);
      const double a = m.sh * d.ch, b = m.ch * d.sh, c = m.ch * d.ch, e = m.sh * d.sh;
      values[2 * k] = conicAt(r, f, q, Hyperbolic(a + b, c + e));
      values[2 * k - 1] = conicAt(r, f, q, Hyperbolic(a - b, c - e));
    }
  }
};

// The conic integrand after σ = ε sinh τ (hyperboloidMomentsBoundary), with e^τ and e^−τ at the
// nodes mid ± d of a rule from e^mid and e^d: one exp and one division a pair instead of two.
// Only the weights and the σ move, by an ulp or two of e^τ, as (e − 1/e)/2 already rounds.
struct SinhSubstituted {
  const ConicIntegrand& inner;
  double eps;
  Moments at(double e, double ie) const { return (eps * 0.5 * (e + ie)) * inner(eps * 0.5 * (e - ie)); }
  Moments operator()(double tau) const {
    const double e = std::exp(tau);
    return at(e, 1.0 / e);
  }
  template <std::size_t N>
  void rule(double mid, double half, const std::array<double, N>& x, std::array<Moments, 2 * N - 1>& values) const {
    const double e = std::exp(mid), ie = 1.0 / e;
    values[0] = at(e, ie);
    for (std::size_t k = 1; k < N; ++k) {
      const double d = std::exp(half * x[k]), id = 1.0 / d;
      values[2 * k] = at(e * d, ie * id);
      values[2 * k - 1] = at(e * id, ie * d);
    }
  }
};

// Adaptive Gauss–Kronrod (7/15 points, Boost.Math's nodes) of the moments; the area component
// steers the subdivision. The error of the 15-point result is estimated as QUADPACK's QK15 does
// (Piessens, de Doncker-Kapenga, Überhuber, Kahaner, QUADPACK, 1983): with e = |K15 − G7| and
// I = ∫|f − mean f|, e' = I·min(1, (200 e/I)^1.5), at least 50 ulps of ∫|f|. |K15 − G7| itself
// bounds the 7-point rule's error, and on these analytic integrands (K15's error falls like the
// square of G7's) overstates the 15-point result's by orders of magnitude: with it as the
// criterion half the pieces were split for accuracy they already had. Returns the summed estimate.
template <class F>
double kronrodMoments(const F& fn, double lo, double hi, double tol, int depth, Moments& out);

// The conic integrands are analytic in a strip of half-width ~π/2 about the real σ axis (τ
// beside a tip), so a 15-point piece longer than ~2 is split for accuracy anyway: cut it first,
// rather than spend a rule on the whole (measured on 1AON: 12% fewer evaluations).
constexpr double kMaxPiece = 2.0;

template <class F>
double kronrodPieces(const F& fn, double lo, double hi, double tol, Moments& out) {
  const double n = std::ceil((hi - lo) / kMaxPiece);
  if (!(n > 1.0)) return kronrodMoments(fn, lo, hi, tol, 0, out);
  double error = 0.0;
  const int count = n < 64.0 ? static_cast<int>(n) : 64;
  for (int i = 0; i < count; ++i)
    error += kronrodMoments(fn, lo + (hi - lo) * i / count, i + 1 == count ? hi : lo + (hi - lo) * (i + 1) / count, tol / count, 0, out);
  return error;
}

template <class F>
double kronrodMoments(const F& fn, double lo, double hi, double tol, int depth, Moments& out) {
  using Kronrod = boost::math::quadrature::gauss_kronrod<double, 15>;
  using Gauss = boost::math::quadrature::gauss<double, 7>;
  const auto& x = Kronrod::abscissa();
  const auto& wk = Kronrod::weights();
  const auto& wg = Gauss::weights();
  const double mid = 0.5 * (lo + hi), half = 0.5 * (hi - lo);
  Moments kronrod, gauss;
  // values[2k] at mid + half·x[k], values[2k − 1] at mid − half·x[k].
  std::array<Moments, 15> values;
  if constexpr (requires { fn.rule(mid, half, x, values); }) {
    fn.rule(mid, half, x, values);
  } else {
    for (std::size_t k = 0; k < x.size(); ++k) {
      values[2 * k] = fn(mid + half * x[k]);
      if (k > 0) values[2 * k - 1] = fn(mid - half * x[k]);
    }
  }
  std::array<double, 15> area;
  for (std::size_t k = 0; k < values.size(); ++k) area[k] = values[k].area;
  for (std::size_t k = 0; k < x.size(); ++k) {
    Moments v = values[2 * k];
    if (k > 0) v += values[2 * k - 1];
    kronrod += wk[k] * v;
    if (k % 2 == 0) gauss += wg[k / 2] * v;
  }
  const double mean = 0.5 * kronrod.area;
  double absolute = 0.0, spread = 0.0;  // ∫|f| and ∫|f − mean f| over [−1, 1]
  for (std::size_t k = 0; k < x.size(); ++k) {
    const double a0 = area[2 * k], a1 = k > 0 ? area[2 * k - 1] : 0.0;
    absolute += wk[k] * (std::abs(a0) + (k > 0 ? std::abs(a1) : 0.0));
    spread += wk[k] * (std::abs(a0 - mean) + (k > 0 ? std::abs(a1 - mean) : 0.0));
  }
  constexpr double kEpsilon = std::numeric_limits<double>::epsilon();
  double error = half * std::abs(kronrod.area - gauss.area);
  if (spread > 0.0 && error > 0.0) {
    const double ratio = 200.0 * error / (half * spread);  // ratio^1.5 without pow
    error = half * spread * std::min(1.0, ratio * std::sqrt(ratio));
  }
  error = std::max(error, 50.0 * kEpsilon * half * absolute);
  // Below ~1000 ulps of ∫|f| the difference is rounding, not truncation: the halved tolerance
  // of a deep piece beside a peak (a side passing 1e-5 Å from a tip) would never be met.
  if (error <= std::max(tol, 1000.0 * kEpsilon * half * absolute) || depth >= 40 ||
      half < 1e-13 * (1.0 + std::abs(mid))) {
    out += half * kronrod;
    return error;
  }
  return kronrodMoments(fn, lo, mid, 0.5 * tol, depth + 1, out) + kronrodMoments(fn, mid, hi, 0.5 * tol, depth + 1, out);
}

// σ with cosh σ ∈ [a, b] and σ ∈ [s0, s1]: up to two intervals.
void coshInterval(double a, double b, double s0, double s1, std::vector<std::array<double, 2>>& out) {
  if (!(b >= 1.0) || !(b >= a)) return;
  const double inner = a > 1.0 ? std::acosh(a) : 0.0, outer = std::acosh(b);
  auto add = [&](double x0, double x1) {
    x0 = std::max(x0, s0);
    x1 = std::min(x1, s1);
    if (x1 > x0) out.push_back({x0, x1});
  };
  if (inner == 0.0) {
    add(-outer, outer);
  } else {
    add(-outer, -inner);
    add(inner, outer);
  }
}

// The part [t0, t1] of side l's line that bounds P; false when the side does not (redundant,
// or a duplicate of an earlier side, or P empty).
bool sideExtent(const Revolution& r, std::size_t l, double& t0, double& t1) {
  constexpr double kInfinity = std::numeric_limits<double>::infinity();
  const Lateral& s = r.laterals[l];
  t0 = -kInfinity;
  t1 = kInfinity;
  for (std::size_t m = 0; m < r.laterals.size(); ++m) {
    if (m == l) continue;
    const Lateral& o = r.laterals[m];
    const double slope = s.nx * o.ny - s.ny * o.nx, rhs = o.dist - s.dist * (s.nx * o.nx + s.ny * o.ny);
    if (std::abs(slope) < 1e-12) {  // parallel: this side lies outside the other, or on it
      const double scale = 1e-12 * (1.0 + std::abs(s.dist) + std::abs(o.dist));
      if (rhs < -scale || (std::abs(rhs) <= scale && s.nx * o.nx + s.ny * o.ny > 0.0 && m < l)) return false;
      continue;
    }
    if (slope > 0.0)
      t1 = std::min(t1, rhs / slope);
    else
      t0 = std::max(t0, rhs / slope);
  }
  return t1 > t0;
}

double hyperboloidMomentsBoundary(const PatchList& p, std::size_t k, double relTol, Scratch& sc, Moments& m) {
  Revolution& r = sc.rev;
  double lo, hi;
  if (!setUpRevolution(p, k, r, lo, hi)) return 0.0;
  const double bound = p.mss.boundRadius[k];
  const double tol = relTol * kTwoPi * bound * bound;
  const BoundaryFrame f(r);
  auto addM = [&](double weight, const Potentials& at, const Potentials& ref) {
    m.area += weight * (at.area - ref.area);
    m.flux += weight * (at.flux - ref.flux);
    m.normal += weight * (at.axial - ref.axial) * r.a;
    m.first += weight * (at.firstAxial - ref.firstAxial) * r.a;
  };

  // Sheets: [lo, hi] for β >= 0; for β < 0 its parts beyond the tips ±hTip, [1] above, [0] below.
  bool axisInside = true;
  for (const Lateral& l : r.laterals) axisInside = axisInside && l.dist >= 0.0;
  const double hTip = r.beta < 0.0 ? std::sqrt(-r.beta / r.alpha) : 0.0;
  std::array<Potentials, 2> anchors;
  auto sheet = [&](int index, double from, double to, bool tipFrom, bool tipTo) {
    if (!(to > from)) return;
    // At a tip the anchor is the tip itself, so the tip's term vanishes: a side passing a
    // distance d ~ 1e-13 from the tip turns Φ from 2π to π within ρ ~ d, a peak of dφ/dσ of that
    // width that no quadrature resolves, but which M − M(tip) ~ d² then weighs to nothing.
    anchors[index] = potentials(r, f, tipFrom ? from : tipTo ? to : 0.5 * (from + to));
    for (const auto& [h, side, tip] : {std::tuple{from, -1.0, tipFrom}, std::tuple{to, 1.0, tipTo}}) {
      double phi = tip && axisInside ? kTwoPi : 0.0;
      if (!tip) {
        glm::dvec2 unused;
        circleInPolygonFast(r, h, std::sqrt(std::max(0.0, r.alpha * h * h + r.beta)), sc, phi, unused);
      }
      if (phi > 0.0) addM(side * phi, potentials(r, f, h), anchors[index]);
    }
  };
  if (r.beta >= 0.0) {
    sheet(0, lo, hi, false, false);
    anchors[1] = anchors[0];
  } else {
    sheet(0, lo, std::min(hi, -hTip), false, -hTip < hi);
    sheet(1, std::max(lo, hTip), hi, hTip > lo, false);
  }

  double error = 0.0;
  auto& pieces = sc.pieces;
  for (std::size_t l = 0; l < r.laterals.size(); ++l) {
    double t0, t1;
    if (!sideExtent(r, l, t0, t1)) continue;
    const Lateral& s = r.laterals[l];
    double kk = s.dist * s.dist - r.beta;
    // k = 0: the side touches the waist circle and the conic is two lines; any k of the order of
    // rounding describes the same curve to rounding.
    if (kk == 0.0) kk = 1e-30 * (s.dist * s.dist + std::abs(r.beta));
    for (const double branch : {-1.0, 1.0}) {
      ConicBranch q{kk < 0.0, 0.0, 0.0, branch, s.dist, s.dist * glm::dvec2(s.nx, s.ny), glm::dvec2(-s.ny, s.nx), {},
                    branch * s.dist, s.dist * s.dist};
      pieces.clear();
      if (kk > 0.0) {  // branch = the sign of h
        const double c = std::sqrt(kk / r.alpha), sk = std::sqrt(kk);
        q.tScale = sk;
        q.hScale = branch * c;
        q.ref = anchors[r.beta < 0.0 && branch > 0.0 ? 1 : 0];
        const double a = branch > 0.0 ? lo / c : -hi / c, b = branch > 0.0 ? hi / c : -lo / c;
        coshInterval(a, b, std::asinh(t0 / sk), std::asinh(t1 / sk), pieces);
      } else {  // branch = the sign of t
        const double c = std::sqrt(-kk / r.alpha), sk = std::sqrt(-kk);
        q.tScale = branch * sk;
        q.hScale = c;
        q.ref = anchors[0];
        const double a = branch > 0.0 ? t0 / sk : -t1 / sk, b = branch > 0.0 ? t1 / sk : -t0 / sk;
        coshInterval(a, b, std::asinh(lo / c), std::asinh(hi / c), pieces);
      }
      const ConicIntegrand fn{r, f, q};
      for (const auto& [x0, x1] : pieces) {
        // Beside a tip (k > dist², two sheets) dφ/dσ peaks at σ = 0 with width ε = asin(dist/√k)
        // (its poles are at ±iε): σ = ε sinh τ moves them to ±iπ/2 (the sinh transformation of
        // Johnston and Elliott, for nearly singular integrands), so the peak needs no bisection.
        if (!q.crossesWaist && kk > s.dist * s.dist) {
          const double eps = std::asin(std::abs(s.dist) / std::sqrt(kk));
          if (eps > 0.0) {
            const SinhSubstituted g{fn, eps};
            error += kronrodPieces(g, std::asinh(x0 / eps), std::asinh(x1 / eps), tol, m);
          } else {
            error += kronrodPieces(fn, x0, x1, tol, m);
          }
        } else {
          error += kronrodPieces(fn, x0, x1, tol, m);
        }
      }
    }
  }
  return error;
}

void sphereMoments(const PatchList& p, std::size_t k, Scratch& sc, Moments& m) {
  const MssQuadrics& q = p.mss;
  const double R = std::sqrt(std::max(0.0, -q.constant[k] / q.radialCoeff[k]));
  const glm::dvec3 z = q.center[k];
  sc.caps.clear();
  for (std::uint32_t c = 0; c < q.cellCount[k]; ++c) {
    const Plane& plane = p.cellPlanes[q.cellBegin[k] + c];
    const glm::dvec3 n(plane);
    sc.caps.push_back({n, R > 0 ? -(glm::dot(n, z) + plane.w) / R : -1.0});
  }
  const SphericalRegion region = sphereMinusCaps(sc.caps, sc.sphere);
  const double side = q.radialCoeff[k] > 0 ? 1.0 : -1.0;  // convex: outward normal u; concave: −u
  m.area = R * R * region.area;
  m.flux = side * R * R * R * region.area;
  m.normal = side * R * R * region.vectorArea;
  m.first = R * R * R * region.vectorArea;
}

// Barycentric coordinates of y in the simplex of `atoms` (count entries).
std::array<double, 4> barycentric(std::span<const glm::dvec3> centers, const glm::uvec4& atoms, int count,
                                  const glm::dvec3& y) {
  std::array<double, 4> l{1.0, 0.0, 0.0, 0.0};
  if (count == 1) return l;
  const glm::dvec3 z0 = centers[atoms[0]];
  std::array<glm::dvec3, 3> e;
  for (int k = 1; k < count; ++k) e[k - 1] = centers[atoms[k]] - z0;
  const glm::dvec3 v = y - z0;
  if (count == 2) {
    l[1] = glm::dot(v, e[0]) / glm::dot(e[0], e[0]);
  } else if (count == 3) {
    const double g00 = glm::dot(e[0], e[0]), g01 = glm::dot(e[0], e[1]), g11 = glm::dot(e[1], e[1]);
    const double b0 = glm::dot(v, e[0]), b1 = glm::dot(v, e[1]), det = g00 * g11 - g01 * g01;
    l[1] = (b0 * g11 - b1 * g01) / det;
    l[2] = (g00 * b1 - g01 * b0) / det;
  } else {
    const double det = glm::dot(e[0], glm::cross(e[1], e[2]));
    l[1] = glm::dot(v, glm::cross(e[1], e[2])) / det;
    l[2] = glm::dot(e[0], glm::cross(v, e[2])) / det;
    l[3] = glm::dot(e[0], glm::cross(e[1], v)) / det;
  }
  l[0] = 1.0;
  for (int k = 1; k < count; ++k) l[0] -= l[k];
  // y lies in δ_X, so λ lies in [0, 1]: outside means rounding on a nearly flat simplex (the
  // determinant ~ the jitter of near-degenerate input) blew it up. Clamp and renormalise.
  double sum = 0.0;
  for (int k = 0; k < count; ++k) {
    l[k] = std::isfinite(l[k]) ? std::clamp(l[k], 0.0, 1.0) : 0.0;
    sum += l[k];
  }
  for (int k = 0; k < count; ++k) l[k] = sum > 0.0 ? l[k] / sum : 1.0 / count;
  return l;
}

}  // namespace

double mssThinPatchAreaBound(const PatchList& p, std::size_t k) {
  const MssQuadrics& q = p.mss;
  const auto kind = static_cast<MssKind>(q.kind[k]);
  constexpr double kInfinity = std::numeric_limits<double>::infinity();
  if (kind != MssKind::Convex && kind != MssKind::Concave) return kInfinity;
  const double R = std::sqrt(std::max(0.0, -q.constant[k] / q.radialCoeff[k]));
  const glm::dvec3 z = q.center[k];
  const std::span<const Plane> planes(p.cellPlanes.data() + q.cellBegin[k], q.cellCount[k]);
  double width = kInfinity;
  for (std::size_t i = 0; i < planes.size(); ++i) {
    const glm::dvec3 ni(planes[i]);
    const double di = glm::dot(ni, z) + planes[i].w;
    for (std::size_t j = i + 1; j < planes.size(); ++j) {
      const glm::dvec3 nj(planes[j]);
      if (glm::dot(ni, nj) >= -0.5) continue;
      const double dj = glm::dot(nj, z) + planes[j].w;
      // x − z = u on the patch, |u| = R: n_i·u <= −d_i and n_i·u >= d_j − (n_i + n_j)·u. The
      // last term bounds the rounding of d_i + d_j (a few ulps of the terms summed).
      const double rounding = 8.0 * std::numeric_limits<double>::epsilon() *
                              (std::abs(glm::dot(ni, z)) + std::abs(planes[i].w) + std::abs(glm::dot(nj, z)) +
                               std::abs(planes[j].w));
      width = std::min(width, -di - dj + glm::length(ni + nj) * R + rounding);
    }
  }
  if (width == kInfinity) return kInfinity;
  return 2.0 * std::numbers::pi * R * std::max(0.0, width);
}

bool mssPatchIsNegligible(const PatchList& p, std::size_t k) {
  const double bound = mssThinPatchAreaBound(p, k);
  if (bound == std::numeric_limits<double>::infinity()) return false;
  const double R2 = std::max(0.0, -p.mss.constant[k] / p.mss.radialCoeff[k]);
  return bound <= 1e-7 * 2.0 * kTwoPi * R2;
}

namespace {

using HyperboloidMoments = double (*)(const PatchList&, std::size_t, double, Scratch&, Moments&);

MssAreas mssAreas(const PatchList& p, std::span<const glm::dvec3> centers, HyperboloidMoments hyperboloidMoments,
                  double relTol) {
  const MssQuadrics& q = p.mss;
  const std::size_t n = q.size();
  std::vector<Moments> moments(n);
  std::vector<double> errors(n, 0.0);
  tbb::enumerable_thread_specific<Scratch> scratch;
  tbb::parallel_for(std::size_t{0}, n, [&](std::size_t k) {
    Scratch& sc = scratch.local();
    const auto kind = static_cast<MssKind>(q.kind[k]);
    if (mssPatchIsNegligible(p, k)) {
      // Zero in the limit of the symbolic perturbation; what it may hold is reported as error.
      errors[k] = mssThinPatchAreaBound(p, k);
    } else if (kind == MssKind::Convex || kind == MssKind::Concave)
      sphereMoments(p, k, sc, moments[k]);
    else
      errors[k] = hyperboloidMoments(p, k, relTol, sc, moments[k]);
  });

  MssAreas out;
  out.perPatch.resize(n);
  out.perAtom.assign(p.params.atomCount, 0.0);
  // Volume about a point near the molecule, so the terms do not cancel from afar.
  glm::dvec3 origin(0.0);
  for (std::size_t k = 0; k < n; ++k) origin += q.center[k] / static_cast<double>(n);
  const double s = p.params.shrinkFactor;
  double volume = 0.0, volumeError = 0.0;
  glm::dvec3 normalSum(0.0);
  for (std::size_t k = 0; k < n; ++k) {
    const Moments& m = moments[k];
    const std::uint32_t kind = q.kind[k];
    out.perPatch[k] = m.area;
    out.byKind[kind] += m.area;
    out.areaErrorEstimate += errors[k];
    normalSum += m.normal;
    volume += m.flux + glm::dot(q.center[k] - origin, m.normal);
    // The flux integrand is bounded by |x − origin|; its error scales like the area's (and the
    // whole of a negligible sphere patch lies within its radius, <= boundRadius, of its centre).
    volumeError += errors[k] * (q.boundRadius[k] + glm::length(q.center[k] - origin));
    if (m.area <= 0.0) continue;
    // Per atom: λ of the area centroid's point y (λ is affine in x over μ_X).
    const glm::dvec3 d = m.first / m.area;
    glm::dvec3 inLine = d;
    if (kind == static_cast<std::uint32_t>(MssKind::Edge)) inLine = glm::dot(d, q.axis[k]) * q.axis[k];
    if (kind == static_cast<std::uint32_t>(MssKind::Face)) inLine = d - glm::dot(d, q.axis[k]) * q.axis[k];
    const glm::dvec3 y = q.center[k] + inLine / (1.0 - s);
    const std::array<double, 4> l = barycentric(centers, q.atoms[k], static_cast<int>(kind) + 1, y);
    for (std::uint32_t a = 0; a <= kind; ++a) out.perAtom[q.atoms[k][a]] += l[a] * m.area;
  }
  out.closure = glm::length(normalSum);
  out.volume = volume / 3.0;
  out.volumeErrorEstimate = volumeError / 3.0;
  return out;
}

}  // namespace

MssAreas computeMssAreas(const PatchList& p, std::span<const glm::dvec3> centers) {
  return mssAreas(p, centers, hyperboloidMomentsBoundary, 1e-10);
}

MssAreas computeMssAreasAdaptive(const PatchList& p, std::span<const glm::dvec3> centers, double relTol) {
  return mssAreas(p, centers, hyperboloidMomentsAdaptive, relTol);
}

MssAreas unionOfBallsAreas(std::span<const glm::dvec3> centers, std::span<const double> radii) {
  const std::size_t n = centers.size();
  NeighbourGrid grid;
  grid.build(centers, radii, 0.0);
  std::vector<SphericalRegion> regions(n);
  tbb::enumerable_thread_specific<Scratch> scratch;
  tbb::enumerable_thread_specific<std::vector<std::uint32_t>> near;
  tbb::parallel_for(std::size_t{0}, n, [&](std::size_t i) {
    Scratch& sc = scratch.local();
    std::vector<std::uint32_t>& nb = near.local();
    nb.clear();
    grid.neighbours(static_cast<std::uint32_t>(i), nb);
    sc.caps.clear();
    for (std::uint32_t j : nb) {
      const glm::dvec3 d = centers[j] - centers[i];
      const double dist = glm::length(d);
      // Coincident equal balls: the lower index keeps the sphere.
      if (dist == 0.0) {
        if (radii[j] > radii[i] || (radii[j] == radii[i] && j < i)) sc.caps.push_back({glm::dvec3(0, 0, 1), -1.0});
        continue;
      }
      const double cosRadius = (dist * dist + radii[i] * radii[i] - radii[j] * radii[j]) / (2.0 * dist * radii[i]);
      sc.caps.push_back({d / dist, std::clamp(cosRadius, -1.0, 1.0)});
    }
    regions[i] = sphereMinusCaps(sc.caps, sc.sphere);
  });
  MssAreas out;
  out.perAtom.resize(n);
  glm::dvec3 origin(0.0);
  for (const glm::dvec3& c : centers) origin += c / static_cast<double>(n);
  for (std::size_t i = 0; i < n; ++i) {
    const double r = radii[i];
    out.perAtom[i] = r * r * regions[i].area;
    out.byKind[0] += out.perAtom[i];
    out.volume += r * r * (glm::dot(centers[i] - origin, regions[i].vectorArea) + r * regions[i].area) / 3.0;
  }
  return out;
}

MssAreas unionOfBallsAreas(const PatchList& vdwSpheres) {
  const ConvexSpheres& balls = vdwSpheres.convex;
  MssAreas out = unionOfBallsAreas(balls.center, balls.radius);
  const std::vector<double> perBall = std::move(out.perAtom);
  out.perAtom.assign(vdwSpheres.params.atomCount, 0.0);
  for (std::size_t k = 0; k < balls.size(); ++k) out.perAtom[balls.atom[k]] += perBall[k];
  return out;
}

}  // namespace surftrace::build

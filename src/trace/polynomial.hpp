// Real roots of small polynomials (degree <= 4) in an interval: the root isolation under the
// ray–torus intersector (ORACLES B.4).
#pragma once

#include <array>
#include <cstdint>
#include <span>
#include <type_traits>

namespace surftrace::trace {

inline constexpr int kMaxPolynomialDegree = 4;

// Default tolerance for tangential (double) roots: a local extremum t* of p with
// |p(t*)| <= τ is reported as a root (ORACLES B.4: τ ≈ 1e-14 in normalised units). τ is
// absolute because what it must absorb is mostly the rounding of the coefficients
// themselves, which the caller knows and the polynomial does not: the torus quartic's c0 is
// K² + 4R²(z² − r²), a difference of O(1) terms that is ~1e-16 for a ray tangent at the
// origin of the shifted frame. Callers with other scales pass ~45 ε times their scale of p.
inline constexpr double kTangencyTolerance = 1e-14;

// Up to kMaxPolynomialDegree roots in ascending order. No heap: this runs once per ray and
// candidate patch in the renderer's hot path.
struct PolynomialRoots {
  std::array<double, kMaxPolynomialDegree> value{};
  // Bit k set: value[k] is a critical point reported as a tangential double root (no sign
  // change around it) or an exact zero of p that is also a critical point.
  std::uint32_t tangentMask = 0;
  int count = 0;

  bool tangent(int k) const { return ((tangentMask >> k) & 1u) != 0; }
  const double* begin() const { return value.data(); }
  const double* end() const { return value.data() + count; }
};

// p(t) = c[0] + c[1] t + … + c[n] t^n by Horner's rule; n = c.size() − 1 <= 4.
double evaluatePolynomial(std::span<const double> c, double t);

// All real roots of p in the closed interval [lo, hi], sorted (ORACLES B.4 (ii)):
//  - trailing zero coefficients lower the degree; the zero polynomial has no roots;
//  - degree 1 and 2: closed form, the quadratic in the stable form q = −(b + sign(b)√Δ)/2,
//    roots q/a and c/q, with Δ = b² − 4ac from a fused difference of products;
//  - degree 3 and 4: the roots of p' in [lo, hi] (recursively) split the interval into
//    monotone pieces; each piece with a sign change holds exactly one root, found by
//    bracketed Newton (bisect whenever Newton leaves the bracket or stalls) to ~4 ulp, or
//    until |p| is below Horner's rounding bound, whichever comes first;
//  - at an interior critical point that is a local extremum of |p| towards zero with no
//    sign change on either side, |p(t*)| <= τ reports t* as a tangential double
//    root (once, with its bit set in tangentMask). A near-double root is thus reported
//    either as two simple roots or as one tangential root, never as three.
// Exact zeros of p at a split point are reported once. A double root is reported once.
// More than 5 coefficients, non-finite bounds or lo > hi give no roots. (Also see the
// tangency tolerance above: it is absolute.)
PolynomialRoots realRoots(std::span<const double> c, double lo, double hi,
                          double tangencyTolerance = kTangencyTolerance);

// Whether |p(t)| > floor for every t in [lo, hi] (and so p keeps one sign there), proved by
// Taylor bounds: on a piece with centre m and half-width h, |p − b0| <= Σ_{k>=1} |b_k| h^k with
// b_k = p^(k)(m)/k!; a piece whose bound fails is halved, down to 2^maxHalvings pieces.
// False when no proof is found (not a claim that p comes near zero). With floor well above
// the rounding of Horner's rule on [lo, hi] and above the tangency tolerance, a yes means
// realRoots(c, lo, hi) reports no root: every value it computes there has p's one sign and
// is above the tolerance in size.
bool provablyAwayFromZero(std::span<const double> c, double lo, double hi, double floor, int maxHalvings);

// Hands the roots realRoots(c, lo, hi, tangencyTolerance) reports, the same values in the same
// ascending order, to `accept(context, root, tangent)` one at a time, and stops at the first
// it accepts (returns true), leaving the monotone pieces beyond that root, and the critical
// points among them, unsolved: an any-hit query (the scene's occlusion rays) and a nearest
// hit on a patch need only the first root that passes their tests. Returns whether a root
// was accepted.
struct RootVisitor {
  bool (*accept)(void* context, double root, bool tangent);
  void* context;
};
bool firstRoot(std::span<const double> c, double lo, double hi, const RootVisitor& visit,
               double tangencyTolerance = kTangencyTolerance);
// The same with any callable bool(double root, bool tangent).
template <class Accept>
bool firstRoot(std::span<const double> c, double lo, double hi, Accept&& accept,
               double tangencyTolerance = kTangencyTolerance) {
  using F = std::remove_reference_t<Accept>;
  const RootVisitor visit{[](void* f, double root, bool tangent) { return (*static_cast<F*>(f))(root, tangent); },
                          const_cast<void*>(static_cast<const void*>(&accept))};
  return firstRoot(c, lo, hi, visit, tangencyTolerance);
}

}  // namespace surftrace::trace

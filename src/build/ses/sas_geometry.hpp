// Canonical SAS circles and probe positions (ORACLES A.1, A.2).
//
// Every function takes its atoms in ascending index order and is a pure function of the
// atoms' centres and radii, so each of the atoms that share a circle or a probe position
// computes the very same bits: their contours agree exactly, with no shared mutable table.
#pragma once

#include <algorithm>
#include <cmath>
#include <optional>

#include <glm/common.hpp>
#include <glm/geometric.hpp>
#include <glm/vec3.hpp>

#include "build/core/vector_math.hpp"
#include "build/ses/exact_predicates.hpp"

namespace surftrace::build {

// The circle where the extended spheres (radius R = r + rp) of atoms x < y meet.
struct SasCircle {
  glm::dvec3 center;  // c_xy
  glm::dvec3 axis;    // unit, from x to y
  glm::dvec3 e1, e2;  // frame: e2 = axis × e1, φ = 0 along e1
  double t;           // signed distance from c_x to the circle plane along axis
  double radius;      // ρ_xy, the torus big radius
  double distance;    // |c_y − c_x|
};

// The unit roundoff of double precision.
inline constexpr double kUnitRoundoff = 0x1p-53;

// Sign of |cb − ca|² − (Ra + sign·Rb)² (sign = ±1) for the real numbers the doubles denote:
// the double value when it clears its error bound (each of the squares is within 6u of its
// exact value), the rational one otherwise (a near-tangency: ORACLES E.3, E.4).
inline int distanceSign(const glm::dvec3& ca, const glm::dvec3& cb, double Ra, double Rb, int sign) {
  const glm::dvec3 v = cb - ca;
  const double d2 = glm::dot(v, v);
  const double s = sign > 0 ? Ra + Rb : Ra - Rb;
  const double m = std::abs(Ra) + std::abs(Rb);
  const double diff = d2 - s * s, bound = 16.0 * kUnitRoundoff * (d2 + m * m);
  if (diff > bound) return 1;
  if (diff < -bound) return -1;
  return exactDistanceSign(ca, cb, Ra, Rb, sign);
}

// Whether two spheres cut in a circle: |Rx − Ry| < d < Rx + Ry, exactly. Spheres that touch
// share a point, which bounds no patch.
inline bool spheresCut(const glm::dvec3& cx, double Rx, const glm::dvec3& cy, double Ry) {
  return distanceSign(cx, cy, Rx, Ry, 1) < 0 && distanceSign(cx, cy, Rx, Ry, -1) > 0;
}

// Whether the sphere (ci, Ri) lies inside (cj, Rj), touching allowed: d ≤ Rj − Ri, exactly.
inline bool sphereInside(const glm::dvec3& ci, double Ri, const glm::dvec3& cj, double Rj) {
  return Rj >= Ri && distanceSign(ci, cj, Rj, Ri, -1) <= 0;
}

// For a circle (x, y) that no point of crosses sphere k: the sign of the mean of
// |p − ck|² − Rk² over its points p, which is the side of sphere k the whole circle lies on
// (< 0 inside, > 0 outside; a circle touching the sphere at one point still has its other
// points strictly on one side, so only a circle lying on the sphere gives 0). Double with
// an error bound, exact when unsure (exactCircleSphereSign has the formula).
inline int circleSphereSign(const glm::dvec3& cx, double Rx, const glm::dvec3& cy, double Ry, const glm::dvec3& ck,
                            double Rk) {
  const glm::dvec3 vy = cy - cx, vk = cx - ck;
  const double d2 = glm::dot(vy, vy), kk = glm::dot(vk, vk), yk = glm::dot(vy, vk);
  const double Rx2 = Rx * Rx, Ry2 = Ry * Ry, Rk2 = Rk * Rk;
  const double value = d2 * (kk + Rx2 - Rk2) + (d2 + Rx2 - Ry2) * yk;
  // |yk| <= (d2 + kk) / 2; every product of the formula is rounded a few times.
  const double bound = 32.0 * kUnitRoundoff * (d2 * (kk + Rx2 + Rk2) + (d2 + Rx2 + Ry2) * 0.5 * (d2 + kk));
  if (value > bound) return 1;
  if (value < -bound) return -1;
  return exactCircleSphereSign(cx, Rx, cy, Ry, ck, Rk);
}

// Whether sphere k buries the circle (x, y) when no point of the circle crosses it: the
// circle lies inside (circleSphereSign < 0), touching at one point at most. A circle lying
// on sphere k (only possible with the three centres on one line: a pencil of spheres through
// one circle) is covered near each of its points by the two spheres of the pencil whose
// centres are outermost on the line, so it is buried unless k's centre lies strictly
// between x's and y's; then (x, y) are the outer pair and the circle is theirs.
inline bool circleBuriedBy(const glm::dvec3& cx, double Rx, const glm::dvec3& cy, double Ry, const glm::dvec3& ck,
                           double Rk) {
  const int side = circleSphereSign(cx, Rx, cy, Ry, ck, Rk);
  if (side != 0) return side < 0;
  return exactDotSign(ck, cx, cy) >= 0;
}

// The SAS circle of x < y, or nothing when the extended spheres do not cut each other
// (apart, touching, or one inside the other: decided exactly by spheresCut). Radius by
// Connolly's cancellation-safe product form.
inline std::optional<SasCircle> sasCircle(const glm::dvec3& cx, double Rx, const glm::dvec3& cy, double Ry) {
  if (!spheresCut(cx, Rx, cy, Ry)) return std::nullopt;
  const glm::dvec3 v = cy - cx;
  const double d2 = glm::dot(v, v);
  const double d = std::sqrt(d2);
  SasCircle c;
  c.distance = d;
  c.axis = v / d;
  c.t = (d2 + Rx * Rx - Ry * Ry) / (2.0 * d);
  c.center = cx + c.t * c.axis;
  const double s = Rx + Ry, m = Rx - Ry;
  c.radius = std::sqrt(std::max(0.0, (s * s - d2) * (d2 - m * m))) / (2.0 * d);
  c.e1 = perpendicularTo(c.axis);
  c.e2 = glm::cross(c.axis, c.e1);
  return c;
}

// The two probe positions touching the extended spheres of atoms a < b < c.
struct ProbePair {
  glm::dvec3 plus, minus;  // c_a + q ± h m, m = unit normal of the centre plane
  double h;                // height above the centre plane (> 0)
  double error;            // bound on the distance of either from the exact position
};

// Bounds on the rounding of probePositions: of h² and of the positions. The rounding of
// each step (u = 2⁻⁵³) carried through a first-order error analysis and inflated eightfold.
// κ = a·a b·b / det amplifies the solve for q, and h² near 0 (a probe that just fits) the
// square root; tests check both against 50-digit arithmetic on near-collinear and
// just-fitting triples (exact_predicates_test).
struct ProbeErrorBound {
  double h2;        // of h² = Ra² − q·q
  double position;  // of either position, Å
};
inline ProbeErrorBound probeError(const glm::dvec3& ca, double Ra, double Rb, double Rc, double aa, double bb,
                                  double det, double qq, double h2) {
  constexpr double u = kUnitRoundoff;
  const double kappa = aa * bb / det;
  const double la = std::sqrt(aa), lb = std::sqrt(bb);
  const double scale = aa + bb + Ra * Ra + Rb * Rb + Rc * Rc;
  const double q = std::sqrt(qq);
  const double eq = 16.0 * u * kappa * scale * (1.0 / la + 1.0 / lb);  // the solve for q
  const double eh2 = 2.0 * q * eq + 4.0 * u * (Ra * Ra + qq);
  const double h = std::sqrt(std::max(h2, 0.0));
  const double eh = h > 0.0 ? std::min(eh2 / h, std::sqrt(eh2)) : std::sqrt(eh2);
  const double em = 8.0 * u * std::sqrt(kappa) * h;  // the direction m
  const double coords = std::max({std::abs(ca.x), std::abs(ca.y), std::abs(ca.z)});
  return {8.0 * eh2, 8.0 * (4.0 * u * (coords + q + h) + eq + eh + em)};
}

// The probe positions from preciseProbePositions, for triples the double computation cannot
// place well. Two positions that round to the same double are one tangential position to
// every later test (they would be two vertices at one point), so they give nothing.
inline std::optional<ProbePair> preciseProbePair(const glm::dvec3& ca, double Ra, const glm::dvec3& cb, double Rb,
                                                 const glm::dvec3& cc, double Rc) {
  const auto p = preciseProbePositions({ca, cb, cc, Ra, Rb, Rc});
  if (!p || p->plus == p->minus) return std::nullopt;
  // Each coordinate is within one ulp (<= 2u |x|) of the exact one.
  const glm::dvec3 m = glm::max(glm::abs(p->plus), glm::abs(p->minus));
  return ProbePair{p->plus, p->minus, p->h, 4.0 * kUnitRoundoff * std::max({m.x, m.y, m.z}) + 0x1p-1000};
}

// Centres with sin² of their angle below this take the precise path without trying double:
// κ = 1 / sin² would make the double solve meaningless, and probeError's first-order
// analysis is checked only down to sin = 1e-7 (exact_predicates_test).
inline constexpr double kNearlyCollinear = 1e-14;
// The double path is taken only when probeError bounds its error by this many Å per Å of Ra
// (beyond the rounding of the coordinates themselves, which no computation avoids). The
// bound is pessimistic: errors measured against 50 digits stay below 1/18 of it, ~2e-10 Å,
// under the 1e-9 Å of the SES oracle. Ordinary triples pass; the precise path takes the
// few whose probe barely fits (h ~ 1e-4 Å), where h = √h² amplifies the rounding of h².
// (Vertices that must be ordered against a neighbour closer than this are placed to an
// ulp by the vertex pass.)
inline constexpr double kMaxProbeError = 1e-9;

// The probe positions of a sorted triple, or nothing when the three extended spheres share
// no point (h² < 0), one point (h² = 0, a tangential "vertex", which bounds no patch), or
// their centres are collinear (no isolated vertex). All three are decided for the real
// numbers the doubles denote: the double h² when it clears its error bound, exact integer
// arithmetic otherwise. Well-conditioned triples (the bulk) are placed in double; nearly
// collinear centres and probes that just fit (|h²| within its error bound) are placed by
// preciseProbePositions, so every position returned is within `error` of the exact one and
// that error is small.
inline std::optional<ProbePair> probePositions(const glm::dvec3& ca, double Ra, const glm::dvec3& cb, double Rb,
                                               const glm::dvec3& cc, double Rc) {
  const glm::dvec3 a = cb - ca, b = cc - ca;
  const glm::dvec3 cross = glm::cross(a, b);
  const double aa = glm::dot(a, a), bb = glm::dot(b, b), ab = glm::dot(a, b);
  const double det = glm::dot(cross, cross);  // = aa·bb − ab², without the cancellation
  if (!(det > kNearlyCollinear * aa * bb)) return preciseProbePair(ca, Ra, cb, Rb, cc, Rc);
  const double ra = 0.5 * (aa + Ra * Ra - Rb * Rb);
  const double rb = 0.5 * (bb + Ra * Ra - Rc * Rc);
  const double alpha = (ra * bb - rb * ab) / det;
  const double beta = (rb * aa - ra * ab) / det;
  const glm::dvec3 q = alpha * a + beta * b;
  const double qq = glm::dot(q, q);
  const double h2 = Ra * Ra - qq;
  const ProbeErrorBound error = probeError(ca, Ra, Rb, Rc, aa, bb, det, qq, h2);
  if (h2 < -error.h2) return std::nullopt;  // clearly no common point: the usual rejection
  const double coords = std::max({std::abs(ca.x), std::abs(ca.y), std::abs(ca.z)});
  if (!(h2 > error.h2) || !(error.position <= kMaxProbeError * Ra + 64.0 * kUnitRoundoff * coords))
    return preciseProbePair(ca, Ra, cb, Rb, cc, Rc);
  const double h = std::sqrt(h2);
  const glm::dvec3 m = cross / std::sqrt(det);
  return ProbePair{ca + q + h * m, ca + q - h * m, h, error.position};
}

// On the circle of (x < y), moving with increasing φ, does the probe position `plus` of the
// sorted triple {x, y, z} leave sphere z (and so start an exposed arc)? The answer is the
// parity of the permutation (x, y, z) of the sorted triple: s(p±) = ±h·m·(n × (c_z − c_x))
// and m ∝ (c_b − c_a) × (c_c − c_a), so the sign needs no arithmetic at all.
inline bool plusLeavesSphere(unsigned x, unsigned y, unsigned z) {
  // x < y always. Even permutations of (a, b, c): z > y (identity) or z < x (cyclic).
  return z > y || z < x;
}

}  // namespace surftrace::build

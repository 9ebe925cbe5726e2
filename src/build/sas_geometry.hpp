// Canonical SAS circles and probe positions (ORACLES A.1, A.2).
//
// Every function takes its atoms in ascending index order and is a pure function of the
// atoms' centres and radii, so each of the atoms that share a circle or a probe position
// computes the very same bits: their contours agree exactly, with no shared mutable table.
#pragma once

#include <algorithm>
#include <cmath>
#include <optional>

#include <glm/geometric.hpp>
#include <glm/vec3.hpp>

#include "build/exact_predicates.hpp"

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

// A unit vector perpendicular to n, chosen by n alone (so it is canonical).
inline glm::dvec3 perpendicularTo(const glm::dvec3& n) {
  const glm::dvec3 a = glm::abs(n);
  const glm::dvec3 helper = (a.x <= a.y && a.x <= a.z) ? glm::dvec3(1, 0, 0)
                            : (a.y <= a.z)               ? glm::dvec3(0, 1, 0)
                                                         : glm::dvec3(0, 0, 1);
  return glm::normalize(glm::cross(n, helper));
}

// The SAS circle of x < y, or nothing when the extended spheres do not cut each other
// (apart, or one inside the other). Radius by Connolly's cancellation-safe product form.
inline std::optional<SasCircle> sasCircle(const glm::dvec3& cx, double Rx, const glm::dvec3& cy, double Ry) {
  const glm::dvec3 v = cy - cx;
  const double d2 = glm::dot(v, v);
  const double d = std::sqrt(d2);
  if (!(d < Rx + Ry) || !(d > std::abs(Rx - Ry))) return std::nullopt;
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

// A bound on how far the rounded probe positions of probePositions lie from the exact ones:
// the rounding of each step (u = 2⁻⁵³) carried through a first-order error analysis and
// inflated eightfold. κ = a·a b·b / det amplifies the solve for q, and h² near 0 (a probe
// that just fits) the square root; tests check it against 50-digit arithmetic on
// near-collinear and just-fitting triples (exact_predicates_test).
inline double probeError(const glm::dvec3& ca, double Ra, double Rb, double Rc, double aa, double bb, double det,
                         double qq, double h2) {
  constexpr double u = 0x1p-53;
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
  return 8.0 * (4.0 * u * (coords + q + h) + eq + eh + em);
}

// Collinear centres (no isolated vertex) and triples whose spheres share no point give
// nothing; a tangential triple (h = 0) gives nothing as well: its "vertex" is a single
// point where two circles touch, which bounds no patch. A positive double h² within its
// error bound of 0 is confirmed in rational arithmetic (a rounding-positive h² of a
// tangential or separate triple gives nothing). Centres with sin² of their angle below
// 1e-24 count as collinear: no double could place a probe from them.
inline std::optional<ProbePair> probePositions(const glm::dvec3& ca, double Ra, const glm::dvec3& cb, double Rb,
                                               const glm::dvec3& cc, double Rc) {
  const glm::dvec3 a = cb - ca, b = cc - ca;
  const glm::dvec3 cross = glm::cross(a, b);
  const double aa = glm::dot(a, a), bb = glm::dot(b, b), ab = glm::dot(a, b);
  const double det = glm::dot(cross, cross);  // = aa·bb − ab², without the cancellation
  if (!(det > 1e-24 * aa * bb)) return std::nullopt;
  const double ra = 0.5 * (aa + Ra * Ra - Rb * Rb);
  const double rb = 0.5 * (bb + Ra * Ra - Rc * Rc);
  const double alpha = (ra * bb - rb * ab) / det;
  const double beta = (rb * aa - ra * ab) / det;
  const glm::dvec3 q = alpha * a + beta * b;
  const double qq = glm::dot(q, q);
  const double h2 = Ra * Ra - qq;
  const double error = probeError(ca, Ra, Rb, Rc, aa, bb, det, qq, h2);
  // A positive h² that rounding made 0 or negative leaves p+ = p−: no double can tell the
  // two positions apart, so that triple counts as tangential as well.
  if (!(h2 > 0.0)) return std::nullopt;
  const double eh2 = 2.0 * std::sqrt(qq) * error + 4.0 * 0x1p-53 * (Ra * Ra + qq);  // bound on h2's error
  if (h2 <= eh2 && exactProbeHeightSign({ca, cb, cc, Ra, Rb, Rc}) <= 0) return std::nullopt;
  const double h = std::sqrt(h2);
  const glm::dvec3 m = cross / std::sqrt(det);
  return ProbePair{ca + q + h * m, ca + q - h * m, h, error};
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

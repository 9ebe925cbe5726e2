// 50-digit floating point (Boost.Multiprecision) versions of the SES formulas of ORACLES
// A.1 and A.2, for tests that check the double and exact predicates of src/build against
// arithmetic that cannot round the same way. Uses nothing from src/build.
#pragma once

#include <boost/multiprecision/cpp_bin_float.hpp>
#include <glm/vec3.hpp>

namespace surftrace::testing_big {

using Big = boost::multiprecision::cpp_bin_float_50;

struct BigVec {
  Big x, y, z;
};
inline BigVec big(const glm::dvec3& v) { return {Big(v.x), Big(v.y), Big(v.z)}; }
inline BigVec operator-(const BigVec& a, const BigVec& b) { return {a.x - b.x, a.y - b.y, a.z - b.z}; }
inline BigVec operator+(const BigVec& a, const BigVec& b) { return {a.x + b.x, a.y + b.y, a.z + b.z}; }
inline BigVec operator*(const Big& s, const BigVec& a) { return {s * a.x, s * a.y, s * a.z}; }
inline Big dot(const BigVec& a, const BigVec& b) { return a.x * b.x + a.y * b.y + a.z * b.z; }
inline BigVec cross(const BigVec& a, const BigVec& b) {
  return {a.y * b.z - a.z * b.y, a.z * b.x - a.x * b.z, a.x * b.y - a.y * b.x};
}
inline glm::dvec3 toDouble(const BigVec& v) {
  return {static_cast<double>(v.x), static_cast<double>(v.y), static_cast<double>(v.z)};
}
inline double distance(const glm::dvec3& p, const BigVec& q) {
  const BigVec d = big(p) - q;
  return static_cast<double>(sqrt(dot(d, d)));
}

// The probe positions of the spheres (ca, Ra), (cb, Rb), (cc, Rc) (ORACLES A.2); h² beside.
struct BigProbes {
  BigVec plus, minus;  // ca + q ± h m, m = unit (cb − ca) × (cc − ca)
  Big h2;
};
inline BigProbes bigProbes(const glm::dvec3& pa, double Ra_, const glm::dvec3& pb, double Rb_, const glm::dvec3& pc,
                           double Rc_) {
  const BigVec ca = big(pa), a = big(pb) - ca, b = big(pc) - ca;
  const Big aa = dot(a, a), bb = dot(b, b), ab = dot(a, b), det = aa * bb - ab * ab;
  const Big Ra2 = Big(Ra_) * Big(Ra_);
  const Big ra = (aa + Ra2 - Big(Rb_) * Big(Rb_)) / 2, rb = (bb + Ra2 - Big(Rc_) * Big(Rc_)) / 2;
  const BigVec q = ((ra * bb - rb * ab) / det) * a + ((rb * aa - ra * ab) / det) * b;
  const Big h2 = Ra2 - dot(q, q);
  const BigVec n = cross(a, b);
  const BigVec hm = (sqrt(h2 > 0 ? h2 : Big(0)) / sqrt(dot(n, n))) * n;
  return {ca + q + hm, ca + q - hm, h2};
}

// The circle where the spheres (cx, Rx) and (cy, Ry) cut (ORACLES A.1): centre, unit axis
// from x to y, radius² (negative when they do not cut).
struct BigCircle {
  BigVec center, axis;
  Big radius2;
};
inline BigCircle bigCircle(const glm::dvec3& px, double Rx, const glm::dvec3& py, double Ry) {
  const BigVec cx = big(px), v = big(py) - cx;
  const Big d2 = dot(v, v), d = sqrt(d2);
  const Big t = (d2 + Big(Rx) * Big(Rx) - Big(Ry) * Big(Ry)) / (2 * d);
  const BigVec axis = (1 / d) * v;
  return {cx + t * axis, axis, Big(Rx) * Big(Rx) - t * t};
}

// Over the points p of circle c, the smallest and largest |p − ck|² − Rk²: a² + (ρ ∓ w)² − Rk²
// with a and w the axial and radial offsets of ck from the circle's centre. Both < 0: the
// circle is inside the sphere; both > 0: outside; otherwise it crosses (or touches) it.
struct BigSpread {
  Big nearest, farthest;
};
inline BigSpread circleSphereSpread(const BigCircle& c, const glm::dvec3& ck, double Rk) {
  const BigVec w = big(ck) - c.center;
  const Big a = dot(w, c.axis);
  const BigVec radial = w - a * c.axis;
  const Big rw = sqrt(dot(radial, radial)), r = sqrt(c.radius2), Rk2 = Big(Rk) * Big(Rk);
  return {a * a + (r - rw) * (r - rw) - Rk2, a * a + (r + rw) * (r + rw) - Rk2};
}

// The centre of a sphere of radius Rk that touches circle c (radius rho, rounded) at its
// point in direction `out` (unit, in the circle's plane), from inside (the circle inside the
// sphere) or from outside; rounded to double, so a touch up to rounding.
inline glm::dvec3 touchingCentre(const BigCircle& c, double rho, const glm::dvec3& out, double Rk, bool inside) {
  return toDouble(c.center) + (inside ? rho - Rk : rho + Rk) * out;
}

}  // namespace surftrace::testing_big

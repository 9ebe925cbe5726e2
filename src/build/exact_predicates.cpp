// Exact probe-position predicates in rational arithmetic (GMP's mpq_class).
//
// With a = cb − ca, b = cc − ca, n = a × b, det = n·n, the probe positions are
// p = ca + q ± h n/|n|, q = (α a + β b)/det, α = ra·bb − rb·ab, β = rb·aa − ra·ab,
// ra = (aa + Ra² − Rb²)/2, rb = (bb + Ra² − Rc²)/2, h² = Ra² − q·q. With H = h²/det (a
// rational), h n/|n| = √H n, so |p − c|² − T = A ± B √H with rationals
// A = |u|² + H det − T, B = 2 u·n, u = ca + q − c; its sign needs one comparison of A²
// with B² H. Every double is a rational, so nothing here rounds.
#include "build/exact_predicates.hpp"

#include <gmpxx.h>

#include "build/error.hpp"

namespace surftrace::build {
namespace {

struct QVec {
  mpq_class x, y, z;
};

QVec q(const glm::dvec3& v) { return {mpq_class(v.x), mpq_class(v.y), mpq_class(v.z)}; }
QVec sub(const QVec& u, const QVec& v) { return {u.x - v.x, u.y - v.y, u.z - v.z}; }
QVec add(const QVec& u, const QVec& v) { return {u.x + v.x, u.y + v.y, u.z + v.z}; }
QVec scale(const QVec& u, const mpq_class& s) { return {u.x * s, u.y * s, u.z * s}; }
mpq_class dot(const QVec& u, const QVec& v) { return u.x * v.x + u.y * v.y + u.z * v.z; }
QVec cross(const QVec& u, const QVec& v) {
  return {u.y * v.z - u.z * v.y, u.z * v.x - u.x * v.z, u.x * v.y - u.y * v.x};
}

struct Exact {
  QVec ca, a, b, n, qv;  // qv = q·det (α a + β b)
  mpq_class det, Ra2;
};

Exact setUp(const ProbeTriple& t) {
  Exact e;
  e.ca = q(t.ca);
  e.a = sub(q(t.cb), e.ca);
  e.b = sub(q(t.cc), e.ca);
  e.n = cross(e.a, e.b);
  e.det = dot(e.n, e.n);
  const mpq_class aa = dot(e.a, e.a), bb = dot(e.b, e.b), ab = dot(e.a, e.b);
  e.Ra2 = mpq_class(t.Ra) * mpq_class(t.Ra);
  const mpq_class Rb2 = mpq_class(t.Rb) * mpq_class(t.Rb), Rc2 = mpq_class(t.Rc) * mpq_class(t.Rc);
  const mpq_class ra = (aa + e.Ra2 - Rb2) / 2, rb = (bb + e.Ra2 - Rc2) / 2;
  const mpq_class alpha = ra * bb - rb * ab, beta = rb * aa - ra * ab;
  e.qv = add(scale(e.a, alpha), scale(e.b, beta));
  return e;
}

}  // namespace

int exactProbeHeightSign(const ProbeTriple& t) {
  const Exact e = setUp(t);
  if (sgn(e.det) == 0) return 0;
  // h² det² = Ra² det² − |α a + β b|².
  return sgn(e.Ra2 * e.det * e.det - dot(e.qv, e.qv));
}

int exactProbeSide(const ProbeTriple& t, bool plus, const glm::dvec3& c, double threshold) {
  const Exact e = setUp(t);
  // Collinear centres have no probe position (and GMP would abort on the division).
  SURFTRACE_ASSERT(sgn(e.det) > 0);
  const QVec qq = scale(e.qv, 1 / e.det);
  const mpq_class H = (e.Ra2 - dot(qq, qq)) / e.det;
  const QVec u = sub(add(e.ca, qq), q(c));
  const mpq_class A = dot(u, u) + H * e.det - mpq_class(threshold);
  const mpq_class B = (plus ? 2 : -2) * dot(u, e.n);
  const int sa = sgn(A), sb = sgn(B);
  if (sgn(H) <= 0 || sb == 0) return sa;
  if (sa == 0 || sa == sb) return sb;
  // Opposite signs: the larger of |A| and |B| √H wins.
  const int cmpSquares = cmp(A * A, B * B * H);
  return cmpSquares > 0 ? sa : cmpSquares < 0 ? sb : 0;
}

std::optional<PreciseProbes> preciseProbePositions(const ProbeTriple& t) {
  const Exact e = setUp(t);
  if (sgn(e.det) == 0) return std::nullopt;
  const QVec qq = scale(e.qv, 1 / e.det);
  const mpq_class H = (e.Ra2 - dot(qq, qq)) / e.det;
  if (sgn(H) <= 0) return std::nullopt;
  // 256 bits: the rounding of the square root and the products is ~2^-250 relative, far
  // below the last bit of a double, so each coordinate is the exact one truncated to double.
  constexpr mp_bitcnt_t kBits = 256;
  const mpf_class h2(H, kBits);
  const mpf_class root(sqrt(h2), kBits);
  const auto coord = [&](const mpq_class& base, const mpq_class& n, int sign) {
    const mpf_class offset(root * mpf_class(n, kBits), kBits);
    mpf_class v(base, kBits);
    if (sign > 0) v += offset;
    else v -= offset;
    return v.get_d();
  };
  const QVec p = add(e.ca, qq);
  PreciseProbes out;
  out.plus = {coord(p.x, e.n.x, 1), coord(p.y, e.n.y, 1), coord(p.z, e.n.z, 1)};
  out.minus = {coord(p.x, e.n.x, -1), coord(p.y, e.n.y, -1), coord(p.z, e.n.z, -1)};
  const mpf_class det(e.det, kBits);
  out.h = mpf_class(root * sqrt(det), kBits).get_d();
  return out;
}

int exactDistanceSign(const glm::dvec3& ca, const glm::dvec3& cb, double Ra, double Rb, int sign) {
  const QVec v = sub(q(cb), q(ca));
  const mpq_class s = sign > 0 ? mpq_class(mpq_class(Ra) + mpq_class(Rb)) : mpq_class(mpq_class(Ra) - mpq_class(Rb));
  return sgn(dot(v, v) - s * s);
}

int exactCircleSphereSign(const glm::dvec3& cx, double Rx, const glm::dvec3& cy, double Ry, const glm::dvec3& ck,
                          double Rk) {
  const QVec x = q(cx), vy = sub(q(cy), x), vk = sub(x, q(ck));
  const mpq_class d2 = dot(vy, vy), Rx2 = mpq_class(Rx) * mpq_class(Rx);
  const mpq_class Ry2 = mpq_class(Ry) * mpq_class(Ry), Rk2 = mpq_class(Rk) * mpq_class(Rk);
  return sgn(d2 * (dot(vk, vk) + Rx2 - Rk2) + (d2 + Rx2 - Ry2) * dot(vy, vk));
}

int exactDotSign(const glm::dvec3& o, const glm::dvec3& a, const glm::dvec3& b) {
  const QVec qo = q(o);
  return sgn(dot(sub(q(a), qo), sub(q(b), qo)));
}

}  // namespace surftrace::build

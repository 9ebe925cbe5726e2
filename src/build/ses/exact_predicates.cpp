// Exact SES predicates in rational arithmetic (GMP's mpq_class), and probe positions to an
// ulp from exact integer arithmetic (mpz_class) and 256-bit floating point (mpf_class).
//
// With a = cb − ca, b = cc − ca, n = a × b, det = n·n, the probe positions are
// p = ca + q ± h n/|n|, q = (α a + β b)/det, α = ra·bb − rb·ab, β = rb·aa − ra·ab,
// ra = (aa + Ra² − Rb²)/2, rb = (bb + Ra² − Rc²)/2, h² = Ra² − q·q. With H = h²/det (a
// rational), h n/|n| = √H n, so |p − c|² − T = A ± B √H with rationals
// A = |u|² + H det − T, B = 2 u·n, u = ca + q − c; its sign needs one comparison of A²
// with B² H. Every double is a rational, so nothing here rounds.
#include "build/ses/exact_predicates.hpp"

#include <algorithm>
#include <cmath>
#include <limits>

#include <gmpxx.h>

#include "build/core/assert.hpp"
#include "build/core/rational_vector.hpp"

namespace surftrace::build {
namespace {

using exact::QVec, exact::q, exact::sub, exact::add, exact::scale, exact::dot, exact::cross;

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

// Integer arithmetic for preciseProbePositions: every input double times 2^S is an integer
// for one common S, and all the formulas are then polynomials in integers (no gcd as with
// rationals, which made the rational version ~6× slower).
namespace {

struct ZVec {
  mpz_class x, y, z;
};
ZVec sub(const ZVec& u, const ZVec& v) { return {u.x - v.x, u.y - v.y, u.z - v.z}; }
mpz_class dot(const ZVec& u, const ZVec& v) { return u.x * v.x + u.y * v.y + u.z * v.z; }
ZVec cross(const ZVec& u, const ZVec& v) {
  return {u.y * v.z - u.z * v.y, u.z * v.x - u.x * v.z, u.x * v.y - u.y * v.x};
}

// The exponent that makes x · 2^S an integer (x = m · 2^(e − 53) with an integer |m| < 2^53).
int integerScale(double x) {
  if (x == 0.0) return std::numeric_limits<int>::min();
  int e = 0;
  std::frexp(x, &e);
  return 53 - e;
}

mpz_class scaled(double x, int S) {
  if (x == 0.0) return 0;
  int e = 0;
  const double m = std::ldexp(std::frexp(x, &e), 53);  // an integer, exactly
  mpz_class z(m);
  mpz_mul_2exp(z.get_mpz_t(), z.get_mpz_t(), static_cast<mp_bitcnt_t>(e - 53 + S));
  return z;
}

ZVec scaled(const glm::dvec3& v, int S) { return {scaled(v.x, S), scaled(v.y, S), scaled(v.z, S)}; }

}  // namespace

std::optional<PreciseProbes> preciseProbePositions(const ProbeTriple& t) {
  int S = 0;
  for (const double x : {t.ca.x, t.ca.y, t.ca.z, t.cb.x, t.cb.y, t.cb.z, t.cc.x, t.cc.y, t.cc.z, t.Ra, t.Rb, t.Rc})
    S = std::max(S, integerScale(x));
  // In units of 2^-S (capitals): A = a·2^S, N = n·2^2S, DET = det·2^4S, QV = 2 qv·2^5S
  // with qv = α a + β b, and K = Ra²(2 DET)² − QV² = 4 h² det² 2^10S. Then, scaled by 2^S,
  // p = CA + (QV ± N √(K / DET)) / (2 DET) and h = √K / (2 DET 2^S).
  const ZVec CA = scaled(t.ca, S);
  const ZVec A = sub(scaled(t.cb, S), CA), B = sub(scaled(t.cc, S), CA);
  const ZVec N = cross(A, B);
  const mpz_class DET = dot(N, N);
  if (sgn(DET) == 0) return std::nullopt;
  const mpz_class AA = dot(A, A), BB = dot(B, B), AB = dot(A, B);
  const mpz_class RA = scaled(t.Ra, S), RB = scaled(t.Rb, S), RC = scaled(t.Rc, S);
  const mpz_class RA2 = RA * RA;
  const mpz_class ra = AA + RA2 - RB * RB, rb = BB + RA2 - RC * RC;  // 2 ra, 2 rb
  const mpz_class alpha = ra * BB - rb * AB, beta = rb * AA - ra * AB;
  const ZVec QV{alpha * A.x + beta * B.x, alpha * A.y + beta * B.y, alpha * A.z + beta * B.z};
  const mpz_class twoDet = 2 * DET;
  const mpz_class K = RA2 * twoDet * twoDet - dot(QV, QV);
  if (sgn(K) <= 0) return std::nullopt;
  // 256-bit floating point from here: each step rounds by ~2^-256 of quantities no larger
  // than |ca| + Ra (times the common scale), far below the last bit of a double, so each
  // coordinate is the exact one truncated to double.
  constexpr mp_bitcnt_t kBits = 256;
  mpf_class root(0, kBits), det(DET, kBits), k(K, kBits), inv(0, kBits), scale(1, kBits);
  mpf_div(root.get_mpf_t(), k.get_mpf_t(), det.get_mpf_t());
  mpf_sqrt(root.get_mpf_t(), root.get_mpf_t());
  mpf_mul_2exp(scale.get_mpf_t(), scale.get_mpf_t(), static_cast<mp_bitcnt_t>(S) + 1);  // 2 · 2^S
  mpf_mul(inv.get_mpf_t(), det.get_mpf_t(), scale.get_mpf_t());                         // 2 DET 2^S
  const auto coord = [&](const mpz_class& ca, const mpz_class& qv, const mpz_class& n, int sign) {
    mpf_class v(ca * twoDet + qv, kBits), offset(n, kBits);
    offset *= root;
    if (sign > 0) v += offset;
    else v -= offset;
    v /= inv;
    return v.get_d();
  };
  PreciseProbes out;
  out.plus = {coord(CA.x, QV.x, N.x, 1), coord(CA.y, QV.y, N.y, 1), coord(CA.z, QV.z, N.z, 1)};
  out.minus = {coord(CA.x, QV.x, N.x, -1), coord(CA.y, QV.y, N.y, -1), coord(CA.z, QV.z, N.z, -1)};
  mpf_class h(K, kBits);
  mpf_sqrt(h.get_mpf_t(), h.get_mpf_t());
  h /= inv;
  out.h = h.get_d();
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

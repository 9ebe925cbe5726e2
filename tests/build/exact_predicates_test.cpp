// The exact SES predicates and the error bound of the double probe positions, against an
// independent evaluation in 50-digit floating point (Boost.Multiprecision) of the same
// formulas (ORACLES A.2) from the same double inputs.
#include <algorithm>
#include <cmath>
#include <cstdio>
#include <optional>
#include <random>

#include <boost/multiprecision/cpp_bin_float.hpp>
#include <glm/geometric.hpp>
#include <gtest/gtest.h>

#include "build/exact_predicates.hpp"
#include "build/sas_geometry.hpp"

namespace surftrace::build {
namespace {

using Big = boost::multiprecision::cpp_bin_float_50;

struct BigVec {
  Big x, y, z;
};
BigVec big(const glm::dvec3& v) { return {Big(v.x), Big(v.y), Big(v.z)}; }
BigVec operator-(const BigVec& a, const BigVec& b) { return {a.x - b.x, a.y - b.y, a.z - b.z}; }
BigVec operator+(const BigVec& a, const BigVec& b) { return {a.x + b.x, a.y + b.y, a.z + b.z}; }
BigVec operator*(const Big& s, const BigVec& a) { return {s * a.x, s * a.y, s * a.z}; }
Big dot(const BigVec& a, const BigVec& b) { return a.x * b.x + a.y * b.y + a.z * b.z; }
BigVec cross(const BigVec& a, const BigVec& b) { return {a.y * b.z - a.z * b.y, a.z * b.x - a.x * b.z, a.x * b.y - a.y * b.x}; }

// The probe positions of ORACLES A.2 in 50 digits; h² alongside.
struct BigProbes {
  BigVec plus, minus;
  Big h2;
};
BigProbes bigProbes(const ProbeTriple& t) {
  const BigVec ca = big(t.ca), a = big(t.cb) - ca, b = big(t.cc) - ca;
  const Big aa = dot(a, a), bb = dot(b, b), ab = dot(a, b), det = aa * bb - ab * ab;
  const Big Ra2 = Big(t.Ra) * Big(t.Ra);
  const Big ra = (aa + Ra2 - Big(t.Rb) * Big(t.Rb)) / 2, rb = (bb + Ra2 - Big(t.Rc) * Big(t.Rc)) / 2;
  const BigVec q = ((ra * bb - rb * ab) / det) * a + ((rb * aa - ra * ab) / det) * b;
  const Big h2 = Ra2 - dot(q, q);
  const BigVec n = cross(a, b);
  const BigVec hm = (sqrt(h2 > 0 ? h2 : Big(0)) / sqrt(dot(n, n))) * n;
  return {ca + q + hm, ca + q - hm, h2};
}

glm::dvec3 randomUnit(std::mt19937_64& rng) {
  std::normal_distribution<double> g;
  return glm::normalize(glm::dvec3(g(rng), g(rng), g(rng)));
}

// A triple of extended spheres with probe positions, of a chosen difficulty: 0 ordinary,
// 1 nearly collinear centres, 2 a probe that just fits (h → 0); far from the origin.
ProbeTriple randomTriple(std::mt19937_64& rng, int kind) {
  std::uniform_real_distribution<double> uni(0.0, 1.0);
  const double rp = 1.4;
  const double Ra = 1.2 + rp + uni(rng), Rb = 1.2 + rp + uni(rng), Rc = 1.2 + rp + uni(rng);
  const glm::dvec3 origin = randomUnit(rng) * std::pow(10.0, 4.0 * uni(rng));
  const glm::dvec3 e = randomUnit(rng), f = glm::normalize(glm::cross(e, randomUnit(rng)));
  double angle = 0.3 + 2.5 * uni(rng);
  if (kind == 1) angle = std::pow(10.0, -2.0 - 5.0 * uni(rng));  // b almost along a
  const double la = 1.5 + 3.0 * uni(rng), lb = 1.5 + 3.0 * uni(rng);
  const glm::dvec3 ca = origin;
  const glm::dvec3 cb = origin + la * e;
  glm::dvec3 cc = origin + lb * (std::cos(angle) * e + std::sin(angle) * f);
  ProbeTriple t{ca, cb, cc, Ra, Rb, Rc};
  if (kind == 2) {
    // Scale the radii so that h² ≈ 0: the probe circle of (a, b) just reaches sphere c.
    const BigProbes p = bigProbes(t);
    const double h2 = static_cast<double>(p.h2);
    const double target = std::pow(10.0, -16.0 + 14.0 * uni(rng)) * (uni(rng) < 0.5 ? -1.0 : 1.0);
    // Ra² − |q|² shifts by dR² when all R² shift alike (q is unchanged): R² += target − h2.
    const double shift = target - h2;
    t.Ra = std::sqrt(Ra * Ra + shift);
    t.Rb = std::sqrt(Rb * Rb + shift);
    t.Rc = std::sqrt(Rc * Rc + shift);
  }
  return t;
}

double distance(const glm::dvec3& p, const BigVec& q) {
  const BigVec d = big(p) - q;
  return static_cast<double>(sqrt(dot(d, d)));
}

// The double probe positions lie within their error bound of the exact ones, and their
// existence (sign of h²) is the exact one.
TEST(ExactPredicates, ProbeErrorBoundHoldsOnHardTriples) {
  std::mt19937_64 rng(424242);
  double worstRatio[3] = {0, 0, 0};
  int present = 0, signChecks = 0, roundedAway = 0;
  for (int trial = 0; trial < 30000; ++trial) {
    const int kind = trial % 3;
    const ProbeTriple t = randomTriple(rng, kind);
    const BigProbes ref = bigProbes(t);
    const auto p = probePositions(t.ca, t.Ra, t.cb, t.Rb, t.cc, t.Rc);
    const int exactSign = exactProbeHeightSign(t);
    if (kind == 2 || abs(ref.h2) < 1e-6) {
      ++signChecks;
      ASSERT_EQ(exactSign, ref.h2 > 0 ? 1 : ref.h2 < 0 ? -1 : 0) << "trial " << trial;
    }
    // Probe positions only when h² > 0 exactly; none for h² > 0 only when rounding made it
    // 0 or negative (then p+ = p− in double: tangential).
    if (!p) {
      if (exactSign > 0) ++roundedAway;
      ASSERT_TRUE(exactSign <= 0 || ref.h2 < 1e-12) << "trial " << trial << " h2 " << static_cast<double>(ref.h2);
      continue;
    }
    ASSERT_GT(exactSign, 0) << "trial " << trial << " h2 " << static_cast<double>(ref.h2);
    ++present;
    const double e = std::max(distance(p->plus, ref.plus), distance(p->minus, ref.minus));
    ASSERT_LE(e, p->error) << "trial " << trial << " kind " << kind;
    worstRatio[kind] = std::max(worstRatio[kind], e / p->error);
  }
  std::printf("probe error / bound, worst: ordinary %.3g, near-collinear %.3g, just fitting %.3g (%d triples, %d signs, "
              "%d positive h² rounded to tangential)\n",
              worstRatio[0], worstRatio[1], worstRatio[2], present, signChecks, roundedAway);
  EXPECT_GT(present, 10000);
}

// |p − c|² against a threshold for a sphere placed so that the probe lies on it up to
// ~1e-16 relative: the exact sign agrees with 50 digits, where the double test often does not.
TEST(ExactPredicates, ProbeSideOnSpheresThroughTheProbe) {
  std::mt19937_64 rng(77);
  std::uniform_real_distribution<double> uni(0.0, 1.0);
  int checked = 0, doubleWrong = 0;
  for (int trial = 0; trial < 4000; ++trial) {
    const ProbeTriple t = randomTriple(rng, trial % 2);
    const auto p = probePositions(t.ca, t.Ra, t.cb, t.Rb, t.cc, t.Rc);
    if (!p) continue;
    const BigProbes ref = bigProbes(t);
    const bool plus = trial % 4 < 2;
    const BigVec& exact = plus ? ref.plus : ref.minus;
    // A fourth sphere of radius R through the exact probe position, rounded to doubles.
    const double R = 2.6 + uni(rng);
    const glm::dvec3 dir = randomUnit(rng);
    const BigVec cBig = exact - Big(R) * big(dir);
    const glm::dvec3 c(static_cast<double>(cBig.x), static_cast<double>(cBig.y), static_cast<double>(cBig.z));
    const double threshold = R * R;
    const BigVec d = exact - big(c);
    const Big value = dot(d, d) - Big(threshold);
    const int want = value > 0 ? 1 : value < 0 ? -1 : 0;
    ASSERT_EQ(exactProbeSide(t, plus, c, threshold), want) << "trial " << trial;
    const glm::dvec3 pd = (plus ? p->plus : p->minus) - c;
    const double d2 = glm::dot(pd, pd);
    doubleWrong += (d2 < threshold) != (want < 0) ? 1 : 0;
    ++checked;
  }
  std::printf("spheres through the probe: %d checked, the plain double test wrong on %d\n", checked, doubleWrong);
  EXPECT_GT(checked, 1000);
  EXPECT_GT(doubleWrong, 100);  // the fallback is needed: rounding alone decides these
}

}  // namespace
}  // namespace surftrace::build

// The exact SES predicates and the error bound of the double probe positions, against an
// independent evaluation in 50-digit floating point (Boost.Multiprecision) of the same
// formulas (ORACLES A.2) from the same double inputs.
#include <algorithm>
#include <cmath>
#include <cstdio>
#include <optional>
#include <random>

#include <glm/geometric.hpp>
#include <gtest/gtest.h>

#include "build/ses/exact_predicates.hpp"
#include "build/ses/sas_geometry.hpp"
#include "big_geometry.hpp"

namespace surftrace::build {
namespace {

using namespace testing_big;

BigProbes bigProbes(const ProbeTriple& t) { return testing_big::bigProbes(t.ca, t.Ra, t.cb, t.Rb, t.cc, t.Rc); }

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
  if (kind == 1) angle = std::pow(10.0, -2.0 - 10.0 * uni(rng));  // b almost along a
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

// The probe positions lie within their error bound of the exact ones, that bound is small
// (kMaxProbeError; ill-conditioned triples take the precise path), and their existence
// (sign of h²) is the exact one.
TEST(ExactPredicates, ProbeErrorBoundHoldsOnHardTriples) {
  std::mt19937_64 rng(424242);
  double worstRatio[3] = {0, 0, 0}, worstError[3] = {0, 0, 0};
  int present = 0, signChecks = 0, oneDouble = 0;
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
    const double coords = std::max({std::abs(t.ca.x), std::abs(t.ca.y), std::abs(t.ca.z)}) + 2.0 * t.Ra;
    // Probe positions exactly when h² > 0, except two positions closer than the spacing of
    // doubles there, which are one tangential position.
    if (!p) {
      const bool apartInDouble = distance(toDouble(ref.plus), ref.minus) > 8.0 * kUnitRoundoff * coords;
      ASSERT_TRUE(exactSign <= 0 || !apartInDouble) << "trial " << trial << " h2 " << static_cast<double>(ref.h2);
      oneDouble += exactSign > 0 ? 1 : 0;
      continue;
    }
    ASSERT_GT(exactSign, 0) << "trial " << trial << " h2 " << static_cast<double>(ref.h2);
    ++present;
    const double e = std::max(distance(p->plus, ref.plus), distance(p->minus, ref.minus));
    ASSERT_LE(e, p->error) << "trial " << trial << " kind " << kind;
    ASSERT_LE(p->error, kMaxProbeError * t.Ra + 64.0 * kUnitRoundoff * coords) << "trial " << trial << " kind " << kind;
    worstRatio[kind] = std::max(worstRatio[kind], e / p->error);
    worstError[kind] = std::max(worstError[kind], e);
  }
  std::printf("probe error / bound, worst: ordinary %.3g, near-collinear %.3g, just fitting %.3g; worst error %.2g / %.2g / "
              "%.2g Å (%d triples, %d signs, %d positive h² with p+ = p- in double)\n",
              worstRatio[0], worstRatio[1], worstRatio[2], worstError[0], worstError[1], worstError[2], present, signChecks,
              oneDouble);
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

// Two spheres a few ulps from touching, outside (d ≈ Ra + Rb) or inside (d ≈ |Ra − Rb|):
// distanceSign, spheresCut and sphereInside agree with 50 digits; a plain double test on
// the rounded distance does not always.
TEST(ExactPredicates, NearTangentSpheres) {
  std::mt19937_64 rng(5150);
  std::uniform_real_distribution<double> uni(0.0, 1.0);
  int checked = 0, plainWrong = 0, ties = 0;
  for (int trial = 0; trial < 6000; ++trial) {
    const double Ra = 2.6 + uni(rng), Rb = 2.6 + uni(rng) + (trial % 2 ? 2.0 : 0.0);
    const int sign = trial % 2 ? -1 : 1;  // odd: b around a, nearly touching it from outside
    const glm::dvec3 ca = randomUnit(rng) * std::pow(10.0, 3.0 * uni(rng));
    const double target = std::abs(Ra + sign * Rb) * (1.0 + (uni(rng) - 0.5) * std::pow(10.0, -10.0 - 6.0 * uni(rng)));
    const glm::dvec3 cb = ca + target * randomUnit(rng);
    const Big gap = dot(big(cb) - big(ca), big(cb) - big(ca)) - (Big(Ra) + sign * Big(Rb)) * (Big(Ra) + sign * Big(Rb));
    const int want = gap > 0 ? 1 : gap < 0 ? -1 : 0;
    ASSERT_EQ(distanceSign(ca, cb, Ra, Rb, sign), want) << "trial " << trial;
    ASSERT_EQ(exactDistanceSign(ca, cb, Ra, Rb, sign), want) << "trial " << trial;
    if (sign > 0) {
      ASSERT_EQ(spheresCut(ca, Ra, cb, Rb), want < 0) << "trial " << trial;
    } else {
      ASSERT_EQ(spheresCut(ca, Ra, cb, Rb), want > 0) << "trial " << trial;
      ASSERT_EQ(sphereInside(ca, Ra, cb, Rb), want <= 0) << "trial " << trial;  // Rb > Ra here
    }
    const double d = glm::distance(ca, cb);
    plainWrong += (d < std::abs(Ra + sign * Rb)) != (want < 0) ? 1 : 0;
    ties += want == 0 ? 1 : 0;
    ++checked;
  }
  std::printf("near-tangent sphere pairs: %d checked, the plain double test wrong on %d\n", checked, plainWrong);
  EXPECT_GT(plainWrong, 100);  // rounding alone decides these
}

// A circle (x, y) that touches a sphere k at one point, from inside or outside, with k's
// radius moved a few ulps either way: when no point of the circle crosses k, circleSphereSign
// says which side the circle lies on, by the circle's nearest and farthest points from k's
// centre in 50 digits (an independent formula: circleSphereSpread).
TEST(ExactPredicates, CircleTouchingASphere) {
  std::mt19937_64 rng(2718);
  std::uniform_real_distribution<double> uni(0.0, 1.0);
  int checked = 0, plainWrong = 0;
  for (int trial = 0; trial < 6000; ++trial) {
    const double Rx = 2.6 + uni(rng), Ry = 2.6 + uni(rng);
    const glm::dvec3 cx = randomUnit(rng) * std::pow(10.0, 3.0 * uni(rng));
    const glm::dvec3 axis = randomUnit(rng);
    const glm::dvec3 cy = cx + (0.5 + 4.0 * uni(rng)) * axis;
    const BigCircle c = bigCircle(cx, Rx, cy, Ry);
    if (!(c.radius2 > 0.1)) continue;
    const double rho = static_cast<double>(sqrt(c.radius2));
    // The touching point: half the trials where the plain test below looks (φ = 0).
    const glm::dvec3 e1 = perpendicularTo(axis), e2 = glm::cross(axis, e1);
    const double phi = trial % 2 ? 0.0 : 6.283185307179586 * uni(rng);
    const glm::dvec3 out = std::cos(phi) * e1 + std::sin(phi) * e2;
    const bool inside = trial % 4 < 2;
    const double Rk = 2.0 + uni(rng) + (inside ? rho : 0.0);
    const glm::dvec3 ck = touchingCentre(c, rho, out, Rk, inside);
    const double RkMoved = Rk * (1.0 + (uni(rng) - 0.5) * std::pow(10.0, -10.0 - 6.0 * uni(rng)));
    const BigSpread spread = circleSphereSpread(c, ck, RkMoved);
    if (spread.nearest < 0 && spread.farthest > 0) continue;  // the circle crosses k: not this predicate's case
    const int want = spread.farthest <= 0 ? -1 : 1;           // inside (touching allowed), or outside
    ASSERT_EQ(circleSphereSign(cx, Rx, cy, Ry, ck, RkMoved), want) << "trial " << trial;
    ASSERT_EQ(circleBuriedBy(cx, Rx, cy, Ry, ck, RkMoved), want < 0) << "trial " << trial;
    // The plain test of a single point of the circle, the one at φ = 0 (as the builder
    // tested before its exact predicate).
    const auto sc = sasCircle(cx, Rx, cy, Ry);
    ASSERT_TRUE(sc.has_value());
    const glm::dvec3 v = sc->center + sc->radius * sc->e1 - ck;
    plainWrong += (glm::dot(v, v) < RkMoved * RkMoved) != (want < 0) ? 1 : 0;
    ++checked;
  }
  std::printf("circles touching a sphere: %d checked, a point test at φ = 0 wrong on %d\n", checked, plainWrong);
  EXPECT_GT(checked, 2000);
  EXPECT_GT(plainWrong, 50);
}

}  // namespace
}  // namespace surftrace::build

// The SES builder's decisions at the boundary cases that rounding alone would decide
// (ORACLES A.1, A.2, E.3–E.5): extended spheres a few ulps from touching, a circle a few
// ulps from touching a third sphere, nearly collinear triples, and three spheres through one
// circle. Each case is built by buildSes and checked against 50-digit arithmetic on the same
// double inputs (big_geometry.hpp) or against the independent SES oracle's Monte Carlo
// volume. Probe radius 1.5 and radii r = R − 1.5 chosen so that r + 1.5 = R exactly: the
// extended radii are the doubles the oracle sees.
#include <algorithm>
#include <array>
#include <cmath>
#include <cstdio>
#include <numbers>
#include <random>
#include <vector>

#include <glm/geometric.hpp>
#include <gtest/gtest.h>

#include "build/ses/contour_buildup.hpp"
#include "build/ses/sas_geometry.hpp"
#include "build/ses/surface_area.hpp"
#include "big_geometry.hpp"
#include "oracles/ses_oracle.hpp"

namespace surftrace::build {
namespace {

using namespace testing_big;

constexpr double kRp = 1.5;

glm::dvec3 randomUnit(std::mt19937_64& rng) {
  std::normal_distribution<double> g;
  return glm::normalize(glm::dvec3(g(rng), g(rng), g(rng)));
}

// The vdW radius whose extended radius is exactly R (asserted).
double vdwFor(double R) {
  const double r = R - kRp;
  EXPECT_EQ(r + kRp, R);
  return r;
}

// R times (1 + δ), |δ| log-uniform in [1e-16, 10^-largest], either sign.
double nudged(double R, std::mt19937_64& rng, double largest = 10.0) {
  std::uniform_real_distribution<double> uni(0.0, 1.0);
  return R * (1.0 + (uni(rng) < 0.5 ? -1.0 : 1.0) * std::pow(10.0, -largest - (16.0 - largest) * uni(rng)));
}

bool hasTorus(const PatchList& p, std::uint32_t i, std::uint32_t j, double* extent = nullptr) {
  for (std::size_t t = 0; t < p.tori.size(); ++t)
    if (std::min(p.tori.atomI[t], p.tori.atomJ[t]) == std::min(i, j) &&
        std::max(p.tori.atomI[t], p.tori.atomJ[t]) == std::max(i, j)) {
      if (extent) *extent = p.tori.phiExtent[t];
      return true;
    }
  return false;
}

bool hasConvex(const PatchList& p, std::uint32_t i) {
  return std::find(p.convex.atom.begin(), p.convex.atom.end(), i) != p.convex.atom.end();
}

// Two atoms whose extended spheres are a few ulps from touching, from outside (d ≈ Ra + Rb)
// or with the smaller inside the larger (d ≈ Rb − Ra). A torus exactly when the spheres cut;
// the inner atom is buried exactly when its sphere lies inside, touching allowed.
TEST(ExactDecisions, NearlyTouchingPairs) {
  std::mt19937_64 rng(31337);
  std::uniform_real_distribution<double> uni(0.0, 1.0);
  int plainWrong = 0, cut = 0, trials = 0;
  for (int trial = 0; trial < 4000; ++trial) {
    const bool inside = trial % 2 == 1;
    const double Ra = std::ldexp(std::round(std::ldexp(2.2 + uni(rng), 40)), -40);
    const double Rb = std::ldexp(std::round(std::ldexp(2.2 + uni(rng) + (inside ? 1.5 : 0.0), 40)), -40);
    const glm::dvec3 ca = randomUnit(rng) * std::pow(10.0, 3.0 * uni(rng));
    const double target = nudged(inside ? Rb - Ra : Ra + Rb, rng, 13.0);
    const glm::dvec3 cb = ca + target * randomUnit(rng);
    const Big d2 = dot(big(cb) - big(ca), big(cb) - big(ca));
    const Big s = inside ? Big(Rb) - Big(Ra) : Big(Ra) + Big(Rb);
    const bool cuts = inside ? d2 > s * s : d2 < s * s;
    const PatchList p = buildSes(std::vector<glm::dvec3>{ca, cb}, std::vector<double>{vdwFor(Ra), vdwFor(Rb)}, SesParams{kRp});
    ASSERT_EQ(hasTorus(p, 0, 1), cuts) << "trial " << trial;
    ASSERT_EQ(hasConvex(p, 0), !inside || cuts) << "trial " << trial;
    ASSERT_TRUE(hasConvex(p, 1)) << "trial " << trial;
    const double d = glm::distance(ca, cb);
    plainWrong += (inside ? d > Rb - Ra : d < Ra + Rb) != cuts ? 1 : 0;
    cut += cuts ? 1 : 0;
    ++trials;
  }
  std::printf("nearly touching pairs: %d built, %d cut; a plain double test of d wrong on %d\n", trials, cut, plainWrong);
  EXPECT_GT(plainWrong, 20);
  EXPECT_GT(cut, trials / 5);
  EXPECT_LT(cut, trials * 4 / 5);
}

// Atoms 0 and 1 cut in a circle that sphere 2 touches at one point, from inside or from
// outside, its radius nudged by a few ulps. By the circle's farthest and nearest points from
// c_2 (50 digits): inside k (touching allowed) the circle is buried and has no torus; crossing
// it, the circle has a torus and two concave triangles (0, 1, 2) bound its arcs; outside k
// (touching allowed) it is a free circle, a full torus.
TEST(ExactDecisions, CircleNearlyTouchingASphere) {
  std::mt19937_64 rng(4711);
  std::uniform_real_distribution<double> uni(0.0, 1.0);
  int trials = 0, buried = 0, crossing = 0, free = 0;
  for (int trial = 0; trial < 600 && trials < 300; ++trial) {
    const double Rx = 2.5 + uni(rng), Ry = 2.5 + uni(rng);
    const glm::dvec3 cx = randomUnit(rng) * std::pow(10.0, 2.0 * uni(rng));
    const glm::dvec3 axis = randomUnit(rng);
    const glm::dvec3 cy = cx + (1.0 + 3.0 * uni(rng)) * axis;
    const BigCircle c = bigCircle(cx, Rx, cy, Ry);
    if (!(c.radius2 > 1.0)) continue;
    const double rho = static_cast<double>(sqrt(c.radius2));
    // Half the trials touch at the circle's φ = 0, where a single-point test would look.
    const auto sc = sasCircle(cx, Rx, cy, Ry);
    const double phi = trial % 2 ? 0.0 : 2.0 * std::numbers::pi * uni(rng);
    const glm::dvec3 out = std::cos(phi) * sc->e1 + std::sin(phi) * sc->e2;
    const bool inside = trial % 4 < 2;
    const double Rk = inside ? rho + 0.5 + uni(rng) : 2.5 + uni(rng);
    const glm::dvec3 ck = touchingCentre(c, rho, out, Rk, inside);
    const double RkNudged = std::max(nudged(Rk, rng), 1.6);
    const std::vector<glm::dvec3> centers{cx, cy, ck};
    const std::vector<double> R{Rx, Ry, RkNudged};
    // Skip the few draws where some extended sphere contains another: the circle's fate is
    // then decided by burial, not by the tangency tested here.
    bool contained = false;
    for (int i = 0; i < 3; ++i)
      for (int j = 0; j < 3; ++j)
        if (i != j) {
          const Big dd = dot(big(centers[j]) - big(centers[i]), big(centers[j]) - big(centers[i]));
          contained = contained || (R[j] >= R[i] && dd <= (Big(R[j]) - Big(R[i])) * (Big(R[j]) - Big(R[i])));
        }
    if (contained) continue;
    const BigSpread spread = circleSphereSpread(c, ck, RkNudged);
    std::vector<double> radii;
    for (const double Ri : R) radii.push_back(Ri - kRp);
    const PatchList p = buildSes(centers, radii, SesParams{kRp});
    std::size_t triangles = 0;
    for (std::size_t v = 0; v < p.concave.size(); ++v) {
      std::array<std::uint32_t, 3> t{p.concave.atomI[v], p.concave.atomJ[v], p.concave.atomK[v]};
      std::sort(t.begin(), t.end());
      triangles += t == std::array<std::uint32_t, 3>{0, 1, 2} ? 1 : 0;
    }
    double extent = 0.0;
    const bool torus = hasTorus(p, 0, 1, &extent);
    if (spread.farthest <= 0) {
      ASSERT_FALSE(torus) << "trial " << trial << ": the circle lies inside sphere 2";
      ++buried;
    } else if (spread.nearest >= 0) {
      ASSERT_TRUE(torus) << "trial " << trial << ": the circle lies outside sphere 2";
      ASSERT_EQ(extent, 2.0 * std::numbers::pi) << "trial " << trial;
      ++free;
    } else {
      ASSERT_TRUE(torus) << "trial " << trial << ": the circle crosses sphere 2";
      ASSERT_LT(extent, 2.0 * std::numbers::pi) << "trial " << trial;
      ASSERT_EQ(triangles, 2u) << "trial " << trial;
      ++crossing;
    }
    ++trials;
  }
  std::printf("circles nearly touching a sphere: %d built: %d buried, %d crossing, %d free\n", trials, buried, crossing,
              free);
  EXPECT_GT(buried, 30);
  EXPECT_GT(crossing, 30);
  EXPECT_GT(free, 30);
}

// Three atoms whose centres are collinear up to an angle ω from 1e-4 down to 1e-14 rad, the
// third sphere passing through two points of the circle of the first two. Both probe
// positions exist and lie within 1e-9 Å of the 50-digit ones (the double solve alone would
// be off by up to ~u/ω² Å; the builder used to drop triples below ω = 1e-12).
TEST(ExactDecisions, NearlyCollinearTriples) {
  std::mt19937_64 rng(1618);
  std::uniform_real_distribution<double> uni(0.0, 1.0);
  double worst = 0.0;
  int built = 0;
  for (int trial = 0; trial < 200; ++trial) {
    const double omega = std::pow(10.0, -4.0 - 10.0 * uni(rng));
    const double Rx = 3.0 + 0.5 * uni(rng), Ry = 3.0 + 0.5 * uni(rng);  // in [2, 4): R − 1.5 + 1.5 = R
    const glm::dvec3 cx = randomUnit(rng) * (10.0 * uni(rng));
    const glm::dvec3 e = randomUnit(rng), f = glm::normalize(glm::cross(e, randomUnit(rng))), g = glm::cross(e, f);
    const glm::dvec3 cy = cx + 3.0 * e;
    const glm::dvec3 ck = cx + 5.0 * (std::cos(omega) * e + std::sin(omega) * f);
    const BigCircle c = bigCircle(cx, Rx, cy, Ry);
    const double psi = 0.3 + 2.5 * uni(rng);
    const BigVec point = c.center + sqrt(c.radius2) * (Big(std::cos(psi)) * big(f) + Big(std::sin(psi)) * big(g));
    const BigVec toK = point - big(ck);
    // The extended radius the builder will see: (Rk − 1.5) + 1.5, rounded twice.
    const double rk = static_cast<double>(sqrt(dot(toK, toK))) - kRp, Rk = rk + kRp;
    const BigProbes ref = bigProbes(cx, Rx, cy, Ry, ck, Rk);
    ASSERT_GT(ref.h2, 0) << "trial " << trial;
    const PatchList p = buildSes(std::vector<glm::dvec3>{cx, cy, ck}, std::vector<double>{vdwFor(Rx), vdwFor(Ry), rk},
                                 SesParams{kRp});
    ASSERT_EQ(p.concave.size(), 2u) << "trial " << trial << " ω " << omega;
    for (std::size_t v = 0; v < 2; ++v) {
      const double e0 = std::min(distance(p.concave.probe[v], ref.plus), distance(p.concave.probe[v], ref.minus));
      ASSERT_LT(e0, 1e-9) << "trial " << trial << " ω " << omega;
      worst = std::max(worst, e0);
    }
    ++built;
  }
  std::printf("nearly collinear triples: %d built, worst probe position error %.2g Å\n", built, worst);
  EXPECT_GT(built, 50);
}

// A pencil of spheres: three extended spheres through one circle, centres on one line
// (R = 5, 5, 8.5 at x = 0, 6, 10.5; the circle x = 3, ρ = 4; all exact in double). Near the
// circle the union is bounded by the two outer spheres, so the middle atom is wholly covered
// and the only torus is the outer pair's. In every index order, against the independent
// oracle's Monte Carlo volume and area sanity.
TEST(ExactDecisions, ThreeSpheresThroughOneCircle) {
  const std::array<glm::dvec3, 3> c{glm::dvec3(0, 0, 0), glm::dvec3(6, 0, 0), glm::dvec3(10.5, 0, 0)};
  const std::array<double, 3> R{5.0, 5.0, 8.5};
  std::array<int, 3> order{0, 1, 2};
  double mcVolume = 0.0, mcError = 0.0;
  {
    std::vector<oracle::Sphere> atoms;
    for (int i = 0; i < 3; ++i) atoms.push_back({c[static_cast<std::size_t>(i)], R[static_cast<std::size_t>(i)] - kRp});
    const oracle::SesOracle oracle(atoms, kRp);
    const auto mc = oracle::sesVolumeMonteCarlo(oracle, 400000, 3);
    mcVolume = mc.volume;
    mcError = mc.stderr_;
  }
  do {
    std::vector<glm::dvec3> centers;
    std::vector<double> radii;
    for (const int o : order) centers.push_back(c[static_cast<std::size_t>(o)]), radii.push_back(R[static_cast<std::size_t>(o)] - kRp);
    const auto at = [&](int o) { return static_cast<std::uint32_t>(std::find(order.begin(), order.end(), o) - order.begin()); };
    const PatchList p = buildSes(centers, radii, SesParams{kRp});
    EXPECT_FALSE(hasConvex(p, at(1))) << "order " << order[0] << order[1] << order[2];
    EXPECT_TRUE(hasConvex(p, at(0)));
    EXPECT_TRUE(hasConvex(p, at(2)));
    double extent = 0.0;
    EXPECT_TRUE(hasTorus(p, at(0), at(2), &extent));
    EXPECT_EQ(extent, 2.0 * std::numbers::pi);
    EXPECT_EQ(p.tori.size(), 1u);
    EXPECT_EQ(p.concave.size(), 0u);
    const SurfaceAreas areas = computeAreas(p);
    EXPECT_NEAR(areas.sesVolume, mcVolume, 4.0 * mcError) << "order " << order[0] << order[1] << order[2];
  } while (std::next_permutation(order.begin(), order.end()));
  std::printf("pencil of three spheres: Monte Carlo volume %.3f ± %.3f Å³\n", mcVolume, mcError);
}

}  // namespace
}  // namespace surftrace::build

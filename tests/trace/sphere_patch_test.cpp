// Whole-sphere intersector against the brute-force ray oracle (STYLE §4, ORACLES B.5).
#include "trace/sphere_patch.hpp"

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <cstdlib>
#include <iostream>
#include <limits>
#include <random>
#include <vector>

#include <gtest/gtest.h>
#include <glm/common.hpp>
#include <glm/geometric.hpp>

#include "oracles/ray_march.hpp"
#include "trace/random_geometry.hpp"
#include "trace/sphere_oracle.hpp"

namespace surftrace::trace {
namespace {

using namespace testing_random;
using namespace sphere_oracle;

using Rng = std::mt19937_64;

constexpr int kTrials = 4000;
// Steps across the oracle's window (2ρ wide): two roots of a non-grazing ray
// (|n·d| >= kGrazingCosine) are at least 2e-3·ρ apart, four steps or more.
constexpr int kMarchSteps = 4000;
constexpr double kHitTolerance = 1e-9;  // Å, ORACLES D.1
constexpr double kInf = std::numeric_limits<double>::infinity();

// Trial i uses seed base + i; SURFTRACE_TEST_SEED overrides the base to explore other seeds.
std::uint64_t seedBase() {
  const char* s = std::getenv("SURFTRACE_TEST_SEED");
  return s != nullptr ? std::strtoull(s, nullptr, 10) : 0;
}



struct Trial {
  SpherePatch sphere;
  Ray ray;
  double tMin = 0.0, tMax = kInf;
};

// Log-uniform scales: radius 0.1..10 Å, centre up to 1e3 Å from the origin, cameras from
// inside the sphere to 2e3 Å away, direction lengths 1e-3..1e3, tMin/tMax now and then.
Trial randomTrial(Rng& rng) {
  Trial tr;
  tr.sphere.radius = logUniform(rng, 0.1, 10.0);
  tr.sphere.center = randomUnit(rng) * logUniform(rng, 1e-3, 1e3);
  const double rho = tr.sphere.radius;
  const double camera = uniform(rng, 0, 1) < 0.2 ? rho * uniform(rng, 0.0, 0.99) : rho + logUniform(rng, 1e-3, 2e3);
  tr.ray.org = tr.sphere.center + camera * randomUnit(rng);
  glm::dvec3 target = tr.sphere.center + randomUnit(rng) * rho * uniform(rng, 0.0, 1.3);
  if (camera > rho && uniform(rng, 0, 1) < 0.1) {
    // Near-tangent rays on purpose: perpendicular distance ρ(1 ± δ), δ down to 1e-12, so
    // both sides of the grazing threshold are exercised.
    const glm::dvec3 axis = glm::normalize(tr.sphere.center - tr.ray.org);
    glm::dvec3 perp = randomUnit(rng);
    perp = glm::normalize(perp - glm::dot(perp, axis) * axis);
    const double delta = logUniform(rng, 1e-12, 1e-2) * (uniform(rng, 0, 1) < 0.5 ? -1.0 : 1.0);
    target = tr.sphere.center + perp * rho * (1.0 + delta);
  }
  const glm::dvec3 toTarget = target - tr.ray.org;
  tr.ray.dir = glm::normalize(toTarget) * logUniform(rng, 1e-3, 1e3);
  const double tTarget = glm::length(toTarget) / glm::length(tr.ray.dir);
  if (uniform(rng, 0, 1) < 0.3) tr.tMin = uniform(rng, -0.5, 1.5) * tTarget;
  if (uniform(rng, 0, 1) < 0.3) tr.tMax = tr.tMin + uniform(rng, 0.0, 2.0) * tTarget;
  return tr;
}

std::vector<Real> oracleRoots(const SpherePatch& s, const Ray& r, double tMin, double tMax) {
  return sphereRoots(s.center, s.radius, r, tMin, tMax, kMarchSteps);
}
Real grazingCosine(const SpherePatch& s, const Ray& r) { return sphereGrazingCosine(s.center, s.radius, r); }

TEST(SpherePatch, MatchesBruteForceOracle) {
  const std::uint64_t base = seedBase();
  int hits = 0, misses = 0, grazing = 0;
  double worstT = 0.0, worstNormal = 0.0, worstImplicit = 0.0;
  for (int i = 0; i < kTrials; ++i) {
    Rng rng(base + static_cast<std::uint64_t>(i));
    const Trial tr = randomTrial(rng);
    const SpherePatch& s = tr.sphere;
    const Bounds3d box = bounds(s);
    ASSERT_TRUE(finite(box) && !box.empty()) << "trial " << i << " seed " << base + i;

    const std::vector<Real> roots = oracleRoots(s, tr.ray, tr.tMin, tr.tMax);
    const SphereImplicit f(s.center, s.radius, tr.ray);
    for (Real t : roots) EXPECT_TRUE(containsL(box, s.center, f.local(t))) << "trial " << i << " seed " << base + i;

    const std::optional<PatchHit> got = intersect(s, tr.ray, tr.tMin, tr.tMax);
    const Real cosine = grazingCosine(s, tr.ray);
    if (cosine < kGrazingCosine) {
      ++grazing;
      if (got) {
        EXPECT_TRUE(got->flags & kHitGrazing) << "trial " << i << " seed " << base + i;
      }
      continue;
    }
    ASSERT_EQ(got.has_value(), !roots.empty()) << "trial " << i << " seed " << base + i;
    if (!got) {
      ++misses;
      continue;
    }
    ++hits;
    const Real len = std::sqrt(dotL(f.d, f.d));
    const double errT = static_cast<double>(std::abs(got->t - roots.front()) * len);  // Å
    EXPECT_LE(errT, kHitTolerance) << "trial " << i << " seed " << base + i;
    // Properties of the returned hit itself: on the sphere, unit outward normal.
    const Vec3L x = f.local(got->t);
    const double implicit = static_cast<double>(std::abs(std::sqrt(dotL(x, x)) - static_cast<Real>(s.radius)));
    EXPECT_LE(implicit, kHitTolerance) << "trial " << i << " seed " << base + i;
    const Vec3L xw = f.local(roots.front());
    const Real rho = s.radius;
    const glm::dvec3 want(static_cast<double>(xw.x / rho), static_cast<double>(xw.y / rho),
                          static_cast<double>(xw.z / rho));
    const double errN = glm::length(got->normal - want);
    EXPECT_LE(errN, 1e-9) << "trial " << i << " seed " << base + i;
    EXPECT_NEAR(glm::length(got->normal), 1.0, 1e-14) << "trial " << i << " seed " << base + i;
    if (cosine > 1.01 * kGrazingCosine) {
      EXPECT_FALSE(got->flags & kHitGrazing) << "trial " << i;
    }
    worstT = std::max(worstT, errT);
    worstNormal = std::max(worstNormal, errN);
    worstImplicit = std::max(worstImplicit, implicit);
  }
  std::cout << "[ stats    ] " << kTrials << " trials: " << hits << " hits, " << misses << " misses, " << grazing
            << " grazing skipped; worst |Δt| " << worstT << " Å, |x−c|−ρ " << worstImplicit << " Å, normal "
            << worstNormal << "\n";
  EXPECT_GT(hits, kTrials / 4);
  EXPECT_GT(misses, kTrials / 10);
}

// allHits() solves once and gives every root the brute-force march finds in (tMin, tMax], and the
// very hits (t, normal, flags, bit for bit) that intersect() gives when called again from each
// hit's t, as transparency did before (three solves for two roots).
TEST(SpherePatch, AllHitsFromOneSolveAreTheRepeatedHits) {
  const std::uint64_t base = seedBase();
  int twoRoots = 0, oneRoot = 0;
  for (int i = 0; i < kTrials; ++i) {
    Rng rng(base + static_cast<std::uint64_t>(i) + 7000000);
    const Trial tr = randomTrial(rng);
    const UnitRay ray(tr.ray);
    std::vector<PatchHit> repeated;
    for (double tMin = tr.tMin; repeated.size() < 4;) {
      const std::optional<PatchHit> h = intersect(tr.sphere, ray, tMin, tr.tMax);
      if (!h || !(h->t > tMin)) break;
      repeated.push_back(*h);
      tMin = h->t;
    }
    PatchHit all[2];
    const int count = allHits(tr.sphere, ray, tr.tMin, tr.tMax, all);
    ASSERT_EQ(static_cast<std::size_t>(count), repeated.size()) << "trial " << i;
    for (int k = 0; k < count; ++k) {
      EXPECT_EQ(all[k].t, repeated[k].t) << "trial " << i << " root " << k;
      EXPECT_EQ(all[k].normal, repeated[k].normal) << "trial " << i << " root " << k;
      EXPECT_EQ(all[k].flags, repeated[k].flags) << "trial " << i << " root " << k;
    }
    if (grazingCosine(tr.sphere, tr.ray) < kGrazingCosine) continue;
    const std::vector<Real> roots = oracleRoots(tr.sphere, tr.ray, tr.tMin, tr.tMax);
    ASSERT_EQ(static_cast<std::size_t>(count), roots.size()) << "trial " << i;
    const Real len = std::sqrt(dotL(SphereImplicit(tr.sphere.center, tr.sphere.radius, tr.ray).d,
                                    SphereImplicit(tr.sphere.center, tr.sphere.radius, tr.ray).d));
    for (int k = 0; k < count; ++k)
      EXPECT_LE(static_cast<double>(std::abs(all[k].t - roots[static_cast<std::size_t>(k)]) * len), kHitTolerance)
          << "trial " << i << " root " << k;
    (count == 2 ? twoRoots : oneRoot) += count > 0;
  }
  EXPECT_GT(twoRoots, kTrials / 10);
  EXPECT_GT(oneRoot, kTrials / 20);
}

// From inside, the near root is behind the origin: the hit is the far side, leaving.
TEST(SpherePatch, RayFromInsideHitsFarSide) {
  for (int i = 0; i < 1000; ++i) {
    Rng rng(seedBase() + static_cast<std::uint64_t>(i));
    SpherePatch s{randomUnit(rng) * logUniform(rng, 1e-3, 1e3), logUniform(rng, 0.1, 10.0)};
    const Ray r{s.center + randomUnit(rng) * s.radius * uniform(rng, 0.0, 0.999),
                randomUnit(rng) * logUniform(rng, 1e-3, 1e3)};
    const std::optional<PatchHit> h = intersect(s, r, 0.0, kInf);
    ASSERT_TRUE(h.has_value()) << "trial " << i;
    EXPECT_GT(h->t, 0.0) << "trial " << i;
    EXPECT_GT(glm::dot(h->normal, r.dir), 0.0) << "trial " << i;
    EXPECT_LE(h->t * glm::length(r.dir), 2 * s.radius * (1 + 1e-12)) << "trial " << i;
    const glm::dvec3 x = r.org + h->t * r.dir;
    EXPECT_NEAR(glm::length(x - s.center), s.radius, 1e-9) << "trial " << i;
  }
}

// (tMin, tMax] is half-open: a root at tMin is excluded, a root at tMax included.
TEST(SpherePatch, RespectsTminTmax) {
  for (int i = 0; i < 200; ++i) {
    Rng rng(seedBase() + static_cast<std::uint64_t>(i));
    const SpherePatch s{randomUnit(rng) * logUniform(rng, 1e-3, 1e3), logUniform(rng, 0.1, 10.0)};
    const glm::dvec3 u = randomUnit(rng);
    const Ray r{s.center - u * (s.radius + logUniform(rng, 1e-2, 1e3)), u * logUniform(rng, 1e-2, 1e2)};
    const std::optional<PatchHit> t0 = intersect(s, r, 0.0, kInf);
    ASSERT_TRUE(t0.has_value()) << "trial " << i;
    const std::optional<PatchHit> t1 = intersect(s, r, t0->t, kInf);
    ASSERT_TRUE(t1.has_value()) << "trial " << i;
    EXPECT_GT(t1->t, t0->t) << "trial " << i;
    EXPECT_NEAR((t1->t - t0->t) * glm::length(r.dir), 2 * s.radius, 1e-9) << "trial " << i;
    EXPECT_LT(glm::dot(t0->normal, r.dir), 0.0) << "trial " << i;  // entering
    EXPECT_GT(glm::dot(t1->normal, r.dir), 0.0) << "trial " << i;  // leaving

    const std::optional<PatchHit> atTmax = intersect(s, r, 0.0, t0->t);
    ASSERT_TRUE(atTmax.has_value()) << "trial " << i;
    EXPECT_EQ(atTmax->t, t0->t) << "trial " << i;
    EXPECT_FALSE(intersect(s, r, 0.0, std::nextafter(t0->t, 0.0)).has_value()) << "trial " << i;
    EXPECT_FALSE(intersect(s, r, t1->t, kInf).has_value()) << "trial " << i;
    const double mid = 0.5 * (t0->t + t1->t);
    EXPECT_FALSE(intersect(s, r, mid - 1e-3 * (t1->t - t0->t), mid).has_value()) << "trial " << i;
    // A negative tMin admits the root behind the origin: only (tMin, tMax] decides.
    const Ray back{r.org + (t1->t + 1.0) * r.dir, r.dir};
    EXPECT_FALSE(intersect(s, back, 0.0, kInf).has_value()) << "trial " << i;
    const std::optional<PatchHit> behind = intersect(s, back, -kInf, kInf);
    ASSERT_TRUE(behind.has_value()) << "trial " << i;
    EXPECT_NEAR(behind->t * glm::length(r.dir), (t0->t - t1->t - 1.0) * glm::length(r.dir), 1e-9) << "trial " << i;
  }
}

// Non-unit directions report t in the caller's parametrisation.
TEST(SpherePatch, TScalesWithDirectionLength) {
  const SpherePatch s{{10, -20, 30}, 1.7};
  const Ray unit{{0, 0, 0}, glm::normalize(s.center + glm::dvec3(0.3, 0.2, -0.1))};
  const std::optional<PatchHit> h = intersect(s, unit, 0.0, kInf);
  ASSERT_TRUE(h.has_value());
  for (double k : {1e-6, 1e-3, 0.5, 3.0, 1e4, 1e8}) {
    const std::optional<PatchHit> hk = intersect(s, Ray{unit.org, unit.dir * k}, 0.0, kInf);
    ASSERT_TRUE(hk.has_value()) << k;
    EXPECT_NEAR(hk->t * k, h->t, 1e-12 * h->t) << k;
    EXPECT_NEAR(glm::length(hk->normal - h->normal), 0.0, 1e-14) << k;
  }
  EXPECT_FALSE(intersect(s, Ray{unit.org, glm::dvec3(0.0)}, 0.0, kInf).has_value());
}

// A tangent ray is flagged grazing when it hits; a steep one is not.
TEST(SpherePatch, FlagsGrazingRays) {
  const SpherePatch s{{1, 2, 3}, 2.0};
  for (double offset : {0.0, 1e-12, 1e-8, 1e-7}) {
    const Ray r{s.center + glm::dvec3(-50, s.radius * (1 - offset), 0), {1, 0, 0}};
    const std::optional<PatchHit> h = intersect(s, r, 0.0, kInf);
    if (offset >= 1e-8) {
      ASSERT_TRUE(h.has_value()) << offset;
    }
    if (h) {
      EXPECT_TRUE(h->flags & kHitGrazing) << offset;
      EXPECT_NEAR(h->t, 50.0, 1e-2) << offset;
    }
  }
  const Ray miss{s.center + glm::dvec3(-50, s.radius * (1 + 1e-7), 0), {1, 0, 0}};
  EXPECT_FALSE(intersect(s, miss, 0.0, kInf).has_value());
  const Ray steep{s.center + glm::dvec3(-50, s.radius * 0.5, 0), {1, 0, 0}};
  const std::optional<PatchHit> h = intersect(s, steep, 0.0, kInf);
  ASSERT_TRUE(h.has_value());
  EXPECT_EQ(h->flags, 0u);
}

}  // namespace
}  // namespace surftrace::trace

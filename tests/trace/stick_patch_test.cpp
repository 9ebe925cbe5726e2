// The ball-and-stick model's stick (capped cylinder) intersector against the brute-force ray
// oracle (STYLE §4): march F(x) = max(|x⊥| − ρ, −h, h − L) in long double along the ray.
#include "trace/stick_patch.hpp"

#include <algorithm>
#include <cmath>
#include <cstdlib>
#include <iostream>
#include <limits>
#include <random>

#include <gtest/gtest.h>
#include <glm/geometric.hpp>

#include "oracles/ray_march.hpp"
#include "trace/random_geometry.hpp"

namespace surftrace::trace {
namespace {

using namespace testing_random;
using Rng = std::mt19937_64;
using Real = long double;

constexpr int kTrials = 4000;
constexpr int kMarchSteps = 4000;
constexpr double kInf = std::numeric_limits<double>::infinity();

std::uint64_t seedBase() {
  const char* s = std::getenv("SURFTRACE_TEST_SEED");
  return s != nullptr ? std::strtoull(s, nullptr, 10) : 0;
}

struct Trial {
  StickPatch stick;
  Ray ray;
  double tMin = 0.0, tMax = kInf;
};

// Log-uniform scales: radius 0.01..1 Å, length 0.1..10 Å, the stick up to 1e3 Å from the origin,
// cameras from inside to 2e3 Å away, direction lengths 1e-3..1e3, aimed near the stick.
Trial randomTrial(Rng& rng) {
  Trial tr;
  tr.stick.radius = logUniform(rng, 0.01, 1.0);
  tr.stick.a = randomUnit(rng) * logUniform(rng, 1e-3, 1e3);
  tr.stick.b = tr.stick.a + randomUnit(rng) * logUniform(rng, 0.1, 10.0);
  const glm::dvec3 mid = 0.5 * (tr.stick.a + tr.stick.b);
  const double L = glm::length(tr.stick.b - tr.stick.a);
  const double u = uniform(rng, 0, 1);
  const glm::dvec3 axis = (tr.stick.b - tr.stick.a) / L;
  if (u < 0.1) {  // from inside
    glm::dvec3 side = randomUnit(rng);
    side = glm::normalize(side - glm::dot(side, axis) * axis);
    tr.ray.org = tr.stick.a + uniform(rng, 0.01, 0.99) * L * axis + uniform(rng, 0, 0.99) * tr.stick.radius * side;
  } else {
    tr.ray.org = mid + randomUnit(rng) * (0.5 * L + tr.stick.radius + logUniform(rng, 1e-3, 2e3));
  }
  glm::dvec3 target = tr.stick.a + uniform(rng, -0.2, 1.2) * (tr.stick.b - tr.stick.a) +
                      randomUnit(rng) * tr.stick.radius * uniform(rng, 0.0, 1.5);
  if (u > 0.9) target = tr.ray.org + (uniform(rng, 0, 1) < 0.5 ? 1.0 : -1.0) * L * axis;  // along the axis
  tr.ray.dir = glm::normalize(target - tr.ray.org) * logUniform(rng, 1e-3, 1e3);
  const double tTarget = glm::length(target - tr.ray.org) / glm::length(tr.ray.dir);
  if (uniform(rng, 0, 1) < 0.3) tr.tMin = uniform(rng, -0.5, 1.5) * tTarget;
  if (uniform(rng, 0, 1) < 0.3) tr.tMax = tr.tMin + uniform(rng, 0.0, 2.0) * tTarget;
  return tr;
}

struct Local {
  Real x, y, z;
};
// The ray's point at t relative to a, in long double.
Local pointAt(const StickPatch& s, const Ray& r, Real t) {
  return {static_cast<Real>(r.org.x) - s.a.x + t * r.dir.x, static_cast<Real>(r.org.y) - s.a.y + t * r.dir.y,
          static_cast<Real>(r.org.z) - s.a.z + t * r.dir.z};
}
struct Cylindrical {
  Real h, radial;  // along the axis from a; distance from the axis
};
Cylindrical cylindrical(const StickPatch& s, const Local& p) {
  const Real ax = static_cast<Real>(s.b.x) - s.a.x, ay = static_cast<Real>(s.b.y) - s.a.y,
             az = static_cast<Real>(s.b.z) - s.a.z;
  const Real L = std::sqrt(ax * ax + ay * ay + az * az);
  const Real h = (p.x * ax + p.y * ay + p.z * az) / L;
  const Real r2 = p.x * p.x + p.y * p.y + p.z * p.z - h * h;
  return {h, std::sqrt(std::max(r2, Real(0)))};
}
Real implicitF(const StickPatch& s, const Ray& r, Real t) {
  const Cylindrical c = cylindrical(s, pointAt(s, r, t));
  const Real L = glm::length(s.b - s.a);
  return std::max({c.radial - static_cast<Real>(s.radius), -c.h, c.h - L});
}
// Within a small distance of the rim circles (edges: a ray there may cross both faces at once)
// or of the side's silhouette.
bool nearRim(const StickPatch& s, const Ray& r, Real t) {
  const Cylindrical c = cylindrical(s, pointAt(s, r, t));
  const Real L = glm::length(s.b - s.a);
  const Real eps = 1e-7L * (s.radius + L);
  return std::abs(c.radial - s.radius) < eps && (std::abs(c.h) < eps || std::abs(c.h - L) < eps);
}

TEST(StickPatch, MatchesBruteForceOracle) {
  const std::uint64_t base = seedBase();
  int hits = 0, misses = 0, skipped = 0;
  double worstT = 0.0;
  for (int i = 0; i < kTrials; ++i) {
    Rng rng(base + static_cast<std::uint64_t>(i));
    const Trial tr = randomTrial(rng);
    const StickPatch& s = tr.stick;
    const Bounds3d box = bounds(s);
    // March over the ray's part inside the stick's bounding ball, clipped to (tMin, tMax].
    const double len = glm::length(tr.ray.dir);
    const glm::dvec3 mid = 0.5 * (s.a + s.b);
    const double R = std::hypot(0.5 * glm::length(s.b - s.a), s.radius) * 1.01;
    const double tc = glm::dot(mid - tr.ray.org, tr.ray.dir) / (len * len);
    const double half = R / len;
    const double lo = std::max(tr.tMin, tc - half), hi = std::min(tr.tMax, tc + half);
    std::optional<Real> want;
    if (lo < hi) {
      auto f = [&](Real t) { return implicitF(s, tr.ray, t); };
      for (Real t : oracles::marchRoots(f, lo, hi, kMarchSteps))
        if (t > tr.tMin) {
          want = t;
          break;
        }
    }
    const std::optional<PatchHit> got = intersect(s, tr.ray, tr.tMin, tr.tMax);
    const std::string where = "trial " + std::to_string(i) + " seed " + std::to_string(base + i);
    if ((got && (got->flags & kHitGrazing || nearRim(s, tr.ray, got->t))) || (want && nearRim(s, tr.ray, *want))) {
      ++skipped;
      continue;
    }
    ASSERT_EQ(got.has_value(), want.has_value()) << where;
    if (!got) {
      ++misses;
      continue;
    }
    ++hits;
    const double errT = static_cast<double>(std::abs(got->t - *want) * len);
    EXPECT_LE(errT, 1e-9 * (1.0 + glm::length(tr.ray.org - mid))) << where;
    worstT = std::max(worstT, errT);
    const glm::dvec3 x = tr.ray.org + got->t * tr.ray.dir;
    EXPECT_TRUE(box.contains(x, 1e-9 * (1.0 + glm::length(x)))) << where;
    EXPECT_NEAR(glm::length(got->normal), 1.0, 1e-12) << where;
    // The normal is F's gradient: a step along it leaves the solid, one against it enters it.
    const Real step = 1e-6L * s.radius;
    auto fAt = [&](const glm::dvec3& n, int k) {
      Ray probe{tr.ray.org + (static_cast<double>(k) * static_cast<double>(step)) * n, tr.ray.dir};
      return implicitF(s, probe, got->t);
    };
    EXPECT_GT(fAt(got->normal, 1), 0.0L) << where;
    EXPECT_LT(fAt(got->normal, -1), 0.0L) << where;
  }
  std::cout << "[ stats    ] " << kTrials << " trials: " << hits << " hits, " << misses << " misses, " << skipped
            << " at a rim or grazing skipped; worst |Δt| " << worstT << " Å\n";
  EXPECT_GT(hits, kTrials / 4);
  EXPECT_GT(misses, kTrials / 10);
  EXPECT_LT(skipped, kTrials / 50);
}

TEST(StickPatch, EachHalfBelongsToItsAtom) {
  const StickPatch s{{0, 0, 0}, {2, 0, 0}, 0.2};
  const glm::uvec2 atoms{7, 9};
  const auto near = intersect(s, Ray{{0.5, 0, 5}, {0, 0, -1}}, 0.0, kInf);
  const auto far = intersect(s, Ray{{1.5, 0, 5}, {0, 0, -1}}, 0.0, kInf);
  ASSERT_TRUE(near && far);
  EXPECT_NEAR(near->t, 4.8, 1e-12);
  EXPECT_EQ(atomOf(s, atoms, glm::dvec3(0.5, 0, 0.2)), 7u);
  EXPECT_EQ(atomOf(s, atoms, glm::dvec3(1.5, 0, 0.2)), 9u);
  // Along the axis the cap is hit, with the normal −u.
  const auto cap = intersect(s, Ray{{-3, 0.1, 0}, {1, 0, 0}}, 0.0, kInf);
  ASSERT_TRUE(cap);
  EXPECT_NEAR(cap->t, 3.0, 1e-12);
  EXPECT_NEAR(cap->normal.x, -1.0, 1e-15);
}

}  // namespace
}  // namespace surftrace::trace

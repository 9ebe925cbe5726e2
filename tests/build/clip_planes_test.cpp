// TriangleCone (which clipping planes can cut a concave patch) against brute force: the
// largest u·w over a dense sampling of the spherical triangle.
#include <algorithm>
#include <cmath>
#include <cstdint>
#include <random>

#include <glm/geometric.hpp>
#include <gtest/gtest.h>

#include "build/core/vector_math.hpp"
#include "build/ses/clip_planes.hpp"

namespace surftrace::build {
namespace {

// max u·w over the triangle, sampled on a barycentric grid (corners and edges included).
// The sampling error is below (π/2)²/n² ≈ 1e-4 in cosine for n = 200 and small triangles.
double sampledMax(const glm::dvec3 (&d)[3], const glm::dvec3& u, int n = 200) {
  double best = -2.0;
  for (int i = 0; i <= n; ++i)
    for (int j = 0; i + j <= n; ++j) {
      const int k = n - i - j;
      const glm::dvec3 w = glm::normalize(double(i) * d[0] + double(j) * d[1] + double(k) * d[2]);
      best = std::max(best, glm::dot(u, w));
    }
  return best;
}

glm::dvec3 randomUnit(std::mt19937_64& rng) {
  std::normal_distribution<double> g;
  return glm::normalize(glm::dvec3(g(rng), g(rng), g(rng)));
}

// A random direction within `angle` of `axis`.
glm::dvec3 within(const glm::dvec3& axis, double angle, std::mt19937_64& rng) {
  std::uniform_real_distribution<double> uni(0.0, 1.0);
  const double c = 1.0 - uni(rng) * (1.0 - std::cos(angle));
  const double phi = 2.0 * 3.141592653589793 * uni(rng);
  const glm::dvec3 e1 = perpendicularTo(axis), e2 = glm::cross(axis, e1);
  const double s = std::sqrt(1.0 - c * c);
  return c * axis + s * (std::cos(phi) * e1 + std::sin(phi) * e2);
}

TEST(TriangleCone, AgreesWithSampledTriangle) {
  std::mt19937_64 rng(20261121);
  std::uniform_real_distribution<double> uni(0.0, 1.0);
  int culled = 0, kept = 0, nearBoundary = 0;
  for (int trial = 0; trial < 3000; ++trial) {
    const glm::dvec3 axis = randomUnit(rng);
    const double spread = 0.05 + 1.2 * uni(rng);  // triangles from 3° to ~70° across
    const glm::dvec3 d[3] = {within(axis, spread, rng), within(axis, spread, rng), within(axis, spread, rng)};
    const TriangleCone cone(d);
    const glm::dvec3 u = randomUnit(rng);
    const double best = sampledMax(d, u, 120);
    // Caps whose rim passes near the triangle, and random ones.
    const double cosAlpha = trial % 2 == 0 ? std::clamp(best + 0.05 * (uni(rng) - 0.5), 0.0, 0.999) : uni(rng);
    const bool meets = cone.capMeets(u, cosAlpha);
    const double fine = sampledMax(d, u, 400);
    if (std::abs(fine - cosAlpha) < 1e-3) ++nearBoundary;
    if (!meets) {
      ++culled;
      // A dropped plane must clip nothing: no sample of the triangle inside the cap.
      ASSERT_LE(fine, cosAlpha) << "trial " << trial;
    } else {
      ++kept;
      // Kept only when the cap reaches the triangle (to the sampling error).
      ASSERT_GT(fine, cosAlpha - 2e-4) << "trial " << trial;
    }
  }
  EXPECT_GT(culled, 500);
  EXPECT_GT(kept, 500);
  EXPECT_GT(nearBoundary, 20);
}

// The cap's centre inside the triangle, far from every corner and edge: met.
TEST(TriangleCone, CapInsideTriangleIsMet) {
  const glm::dvec3 d[3] = {glm::normalize(glm::dvec3(1, 0, 1)), glm::normalize(glm::dvec3(-0.5, 0.87, 1)),
                           glm::normalize(glm::dvec3(-0.5, -0.87, 1))};
  const TriangleCone cone(d);
  EXPECT_TRUE(cone.capMeets({0, 0, 1}, 0.9999));
  EXPECT_FALSE(cone.capMeets({0, 0, -1}, 0.5));
}

// A flat cone (coplanar directions) is always met: nothing is dropped for it.
TEST(TriangleCone, FlatConeKeepsEveryPlane) {
  const glm::dvec3 d[3] = {{1, 0, 0}, {0, 1, 0}, glm::normalize(glm::dvec3(1, 1, 0))};
  const TriangleCone cone(d);
  EXPECT_TRUE(cone.capMeets({0, 0, -1}, 0.99));
}

}  // namespace
}  // namespace surftrace::build

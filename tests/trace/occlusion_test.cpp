// Occlusion (any-hit) queries against the nearest-hit ones, by brute force: a ray is occluded
// within (0, tMax] exactly when the nearest-hit query finds a hit there, for the scene
// (PatchScene::occluded against intersect1) and for each patch (occludes() against
// intersect()), on crambin's SES and gramicidin's skin.
#include <algorithm>
#include <cmath>
#include <cstdio>
#include <limits>
#include <random>
#include <string>
#include <type_traits>

#include <glm/geometric.hpp>
#include <gtest/gtest.h>

#include "build/io/molecule.hpp"
#include "build/mss/mss_builder.hpp"
#include "build/ses/contour_buildup.hpp"
#include "random_geometry.hpp"
#include "trace/patch_scene.hpp"

namespace surftrace::trace {
namespace {

using testing_random::logUniform;
using testing_random::randomUnit;
using testing_random::uniform;

constexpr double kInf = std::numeric_limits<double>::infinity();

struct OcclusionCase {
  const char* name;
  const char* file;
  bool skin;  // the molecular skin at s = 0.5, else the SES with rp = 1.4 Å
};

build::PatchList patchList(const OcclusionCase& c) {
  const build::Molecule m = build::readMolecule(std::string(SURFTRACE_TEST_DATA) + "/" + c.file);
  return c.skin ? build::buildMss(m.centers, m.radii, {0.5}) : build::buildSes(m.centers, m.radii, build::SesParams{1.4});
}

glm::dvec3 pointIn(std::mt19937_64& rng, const Bounds3d& b) {
  return {uniform(rng, b.lower.x, b.upper.x), uniform(rng, b.lower.y, b.upper.y), uniform(rng, b.lower.z, b.upper.z)};
}

// The end of a ray's range: unbounded (a shadow ray), an occlusion distance, or at and a
// double step either side of the nearest hit `t` (where a range rounded to float would
// reach past the query's own end).
double rangeEnd(std::mt19937_64& rng, double t) {
  switch (std::uniform_int_distribution<int>(0, std::isfinite(t) ? 4 : 1)(rng)) {
    case 0: return kInf;
    case 1: return logUniform(rng, 0.05, 20.0);
    case 2: return t;
    case 3: return std::nextafter(t, 0.0);
    default: return std::nextafter(t, kInf);
  }
}

// A point of the torus of p at (θ, φ) (ORACLES A.3: θ = 0 towards the axis, φ from e1 to e2).
glm::dvec3 torusPoint(const TorusPatch& p, double theta, double phi) {
  const glm::dvec3 radial = std::cos(phi) * p.e1 + std::sin(phi) * p.e2;
  return p.center + (p.bigRadius - p.probeRadius * std::cos(theta)) * radial + p.probeRadius * std::sin(theta) * p.axis;
}

// A ray that crosses the torus first near the patch's edge (on either side of it), then on the
// patch: the case where the first root fails the clip test and a later one passes, which an
// early exit must not cut short.
Ray throughTwoTorusPoints(std::mt19937_64& rng, const TorusPatch& p) {
  const glm::dvec3 on = torusPoint(p, uniform(rng, p.thetaI, p.thetaJ), uniform(rng, 0.0, p.phiExtent));
  const glm::dvec3 edge =
      torusPoint(p, uniform(rng, p.thetaI - 0.3, p.thetaJ + 0.3), uniform(rng, -0.5, p.phiExtent + 0.5));
  return Ray{edge - 0.1 * (on - edge), on - edge};
}

class Occlusion : public testing::TestWithParam<OcclusionCase> {};

// Rays like the renderer's shadow and occlusion rays (from just above a visible hit, in any
// direction) and rays from anywhere in the scene's box: occluded() == intersect1() has a hit.
TEST_P(Occlusion, SceneIsOccludedExactlyWhenTheNearestHitIsInRange) {
  const build::PatchList list = patchList(GetParam());
  const PatchScene scene(ScenePatches::fromPatchList(list));
  const Bounds3d box = scene.patches().bounds();
  const double size = glm::length(box.upper - box.lower);
  std::mt19937_64 rng(35);
  int rays = 0, occluded = 0, mismatches = 0;
  for (int k = 0; k < 20000; ++k) {
    Ray ray;
    if (k % 2 == 0) {
      const glm::dvec3 target = pointIn(rng, box);
      const Ray view{target - size * randomUnit(rng), randomUnit(rng)};
      const SceneHit first = scene.intersect1(Ray{view.org, target - view.org}, 0.0, kInf);
      if (!first.valid()) continue;
      const glm::dvec3 x = view.org + first.hit.t * (target - view.org);
      ray = Ray{x + 1e-6 * size * first.hit.normal, randomUnit(rng) * logUniform(rng, 0.1, 10.0)};
    } else {
      ray = Ray{pointIn(rng, box), randomUnit(rng) * logUniform(rng, 0.1, 10.0)};
    }
    const SceneHit nearest = scene.intersect1(ray, 0.0, kInf);
    const double tMax = rangeEnd(rng, nearest.valid() ? nearest.hit.t : kInf);
    const bool expected = scene.intersect1(ray, 0.0, tMax).valid();
    const bool got = scene.occluded(ray, 0.0, tMax);
    ++rays;
    occluded += got ? 1 : 0;
    if (got != expected) {
      ++mismatches;
      if (mismatches <= 5)
        ADD_FAILURE() << GetParam().name << ": ray " << k << " occluded " << got << ", nearest hit in (0, " << tMax
                      << "] " << expected << " (nearest t " << nearest.hit.t << ")";
    }
  }
  std::printf("[ stats    ] %s: %d rays, %d occluded, %d mismatches\n", GetParam().name, rays, occluded, mismatches);
  EXPECT_EQ(mismatches, 0);
  // Both answers are common, or the comparison says little.
  EXPECT_GT(occluded, rays / 5);
  EXPECT_LT(occluded, rays * 4 / 5);
}

// The box a scene keeps (its frames' ray offsets scale with it): the lowest and highest
// coordinate of every patch's own box, gathered here patch by patch.
TEST_P(Occlusion, SceneBoundsAreTheSpanOfEveryPatchsBox) {
  const build::PatchList list = patchList(GetParam());
  const PatchScene scene(ScenePatches::fromPatchList(list));
  glm::dvec3 lower(kInf), upper(-kInf);
  std::size_t boxes = 0;
  scene.patches().forEachKind([&](const auto& k) {
    for (const auto& p : k.patches) {
      const Bounds3d b = bounds(p);
      for (int c = 0; c < 3; ++c) {
        lower[c] = std::min(lower[c], b.lower[c]);
        upper[c] = std::max(upper[c], b.upper[c]);
      }
      ++boxes;
    }
  });
  ASSERT_GT(boxes, 100u);
  for (int c = 0; c < 3; ++c) {
    EXPECT_EQ(scene.bounds().lower[c], lower[c]) << GetParam().name << " axis " << c;
    EXPECT_EQ(scene.bounds().upper[c], upper[c]) << GetParam().name << " axis " << c;
  }
}

// Every patch's any-hit test against its own intersector, for rays aimed into the patch's
// box, with ranges that end before, at, just short of and past its roots.
TEST_P(Occlusion, EachPatchOccludesExactlyWhenItsIntersectorHits) {
  const build::PatchList list = patchList(GetParam());
  const ScenePatches patches = ScenePatches::fromPatchList(list);
  std::mt19937_64 rng(36);
  int tests = 0, hits = 0, mismatches = 0;
  patches.forEachKind([&](const auto& k) {
    using Row = typename std::remove_reference_t<decltype(k)>::Row;
    using Patch = typename Row::Patch;
    if constexpr (requires(const Patch& p, const UnitRay& r) { occludes(p, r, 0.0, 1.0); }) {
      for (std::size_t i = 0; i < k.patches.size(); ++i) {
        const Patch& p = k.patches[i];
        // The skin's patches fill little of their plain box: aim at the cell's.
        Bounds3d b;
        if constexpr (std::is_same_v<Patch, MssPatch>)
          b = cellBounds(p);
        else
          b = bounds(p);
        const double size = glm::length(b.upper - b.lower);
        for (int n = 0; n < 48; ++n) {
          const glm::dvec3 target = pointIn(rng, b);
          const glm::dvec3 dir = randomUnit(rng) * logUniform(rng, 0.1, 10.0);
          UnitRay ray(Ray{target - uniform(rng, 0.0, 2.0) * size * dir / glm::length(dir), dir});
          if constexpr (std::is_same_v<Patch, TorusPatch>)
            if (n % 2 == 0) ray = UnitRay(throughTwoTorusPoints(rng, p));
          const auto nearest = intersect(p, ray, 0.0, kInf);
          const double tMin = n % 3 == 0 && nearest ? uniform(rng, 0.0, nearest->t * 1.01) : 0.0;
          const double tMax = n % 4 == 1 && nearest ? uniform(rng, tMin, nearest->t * 1.5) : rangeEnd(rng, nearest ? nearest->t : kInf);
          const bool expected = intersect(p, ray, tMin, tMax).has_value();
          const bool got = occludes(p, ray, tMin, tMax);
          ++tests;
          hits += expected ? 1 : 0;
          if (got != expected && ++mismatches <= 5)
            ADD_FAILURE() << GetParam().name << ": kind " << static_cast<int>(Row::kind) << " patch " << i
                          << " occludes " << got << ", intersect in (" << tMin << ", " << tMax << "] " << expected;
        }
      }
    }
  });
  std::printf("[ stats    ] %s: %d patch rays, %d hits, %d mismatches\n", GetParam().name, tests, hits, mismatches);
  EXPECT_EQ(mismatches, 0);
  EXPECT_GT(hits, 1000);  // enough hits (and misses) that the comparison says something
}

INSTANTIATE_TEST_SUITE_P(Surfaces, Occlusion,
                         testing::Values(OcclusionCase{"crambin_ses", "structures/1crn.pdb", false},
                                         OcclusionCase{"gramicidin_skin", "paper/1grm.pdb.gz", true}),
                         [](const testing::TestParamInfo<OcclusionCase>& p) { return std::string(p.param.name); });

}  // namespace
}  // namespace surftrace::trace

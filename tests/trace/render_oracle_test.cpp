// Rendered SES images against independent oracles: the per-point SES oracle (ORACLES D.1),
// a plain loop over every patch (no BVH), and watertightness on closed molecules.
#include <cmath>
#include <cstdio>
#include <map>
#include <random>
#include <string>

#include <glm/geometric.hpp>
#include <gtest/gtest.h>
#include <tbb/global_control.h>

#include "build/ses/contour_buildup.hpp"
#include "build/io/molecule.hpp"
#include "build/ses/surface_area.hpp"
#include "build/surface_components.hpp"
#include "oracles/ses_oracle.hpp"
#include "trace/render.hpp"

namespace surftrace::trace {
namespace {

using view::Camera;
using view::FrameBuffers;
using view::Projection;
using view::RenderOptions;

constexpr double kRp = 1.4;

struct Case {
  build::Molecule molecule;
  build::PatchList patches;
};

const Case& loadCase(const std::string& file) {
  static std::map<std::string, Case> cache;
  auto it = cache.find(file);
  if (it == cache.end()) {
    Case c;
    c.molecule = build::readMolecule(std::string(SURFTRACE_TEST_DATA) + "/" + file);
    c.patches = build::buildSes(c.molecule.centers, c.molecule.radii, build::SesParams{kRp});
    it = cache.emplace(file, std::move(c)).first;
  }
  return it->second;
}

std::vector<oracle::Sphere> oracleAtoms(const build::Molecule& m) {
  std::vector<oracle::Sphere> atoms;
  for (std::size_t i = 0; i < m.size(); ++i) atoms.push_back({m.centers[i], m.radii[i]});
  return atoms;
}

Camera framed(const build::Molecule& m, const glm::dvec3& direction, int size, Projection projection) {
  Camera c;
  c.width = c.height = size;
  c.projection = projection;
  std::vector<double> reach(m.radii);
  for (double& r : reach) r += kRp;
  return frameSpheres(c, m.centers, reach, direction);
}

glm::dvec3 randomDirection(std::mt19937_64& rng) {
  std::normal_distribution<double> n(0.0, 1.0);
  glm::dvec3 d;
  do d = {n(rng), n(rng), n(rng)};
  while (glm::length(d) < 1e-3);
  return glm::normalize(d);
}

// Every hit pixel lies on the SES (dist to the accessible region = rp to 1e-6 Å), the ray
// passes no part of the SES body before it, and every missed ray misses the body: sampled
// along the ray every 0.1 Å across the molecule's box.
class RenderOnSes : public testing::TestWithParam<std::string> {};

TEST_P(RenderOnSes, HitsLieOnTheSesAndMissesMiss) {
  const Case& c = loadCase(GetParam());
  const oracle::SesOracle oracle(oracleAtoms(c.molecule), kRp);
  const PatchScene scene(ScenePatches::fromPatchList(c.patches));
  std::mt19937_64 rng(7);
  const glm::dvec3 lo = oracle.boxLo() - 0.1, hi = oracle.boxHi() + 0.1;
  int hits = 0, misses = 0;
  double worst = 0.0;
  for (int view = 0; view < 2; ++view) {
    RenderOptions o;
    o.camera = framed(c.molecule, randomDirection(rng), 64, view == 0 ? Projection::Perspective : Projection::Orthographic);
    const FrameBuffers f = render(scene, o, {});
    for (int y = 0; y < f.height; ++y)
      for (int x = 0; x < f.width; ++x) {
        const std::size_t p = static_cast<std::size_t>(y) * f.width + x;
        const Ray ray = o.camera.ray(x + 0.5, y + 0.5);
        const glm::dvec3 d = glm::normalize(ray.dir);
        // Where the ray is inside the box: slab test.
        double t0 = 0.0, t1 = std::numeric_limits<double>::infinity();
        for (int k = 0; k < 3; ++k) {
          const double a = (lo[k] - ray.org[k]) / d[k], b = (hi[k] - ray.org[k]) / d[k];
          t0 = std::max(t0, std::min(a, b));
          t1 = std::min(t1, std::max(a, b));
        }
        double tEnd = t1;
        if (f.kind[p] != 0) {
          ++hits;
          // Depth in the buffer is float; recompute the double hit from the scene for the oracle.
          const SceneHit h = scene.intersect1(ray, 0.0, std::numeric_limits<double>::infinity());
          ASSERT_TRUE(h.valid()) << "pixel " << x << "," << y;
          const glm::dvec3 hitPoint = ray.org + h.hit.t * ray.dir;
          const auto r = oracle.distanceToAccessible(hitPoint);
          const double err = std::abs(r.dist - kRp);
          worst = std::max(worst, err);
          EXPECT_LT(err, 1e-6) << GetParam() << " view " << view << " pixel " << x << "," << y << " kind " << f.kind[p];
          tEnd = h.hit.t * glm::length(ray.dir) - 1e-4;
        } else {
          ++misses;
        }
        for (double t = t0; t < tEnd; t += 0.1) {
          const glm::dvec3 q = ray.org + t * d;
          if (oracle.distanceToAccessible(q).dist > kRp + 1e-9) {
            ADD_FAILURE() << GetParam() << " view " << view << " pixel " << x << "," << y << ": the ray enters the SES body at t="
                          << t << (f.kind[p] ? " before its hit" : " but the pixel is a miss");
            break;
          }
        }
      }
  }
  EXPECT_GT(hits, 500);
  EXPECT_GT(misses, 200);
  char text[32];
  std::snprintf(text, sizeof text, "%.3g", worst);
  RecordProperty("worst_distance_error_angstrom", text);
}

INSTANTIATE_TEST_SUITE_P(Molecules, RenderOnSes, testing::Values("structures/1crn.pdb", "small/1grm_single.pdb"),
                         [](const testing::TestParamInfo<std::string>& p) { return p.param.find("1crn") != std::string::npos ? "1crn" : "1grm"; });

// The BVH finds what a plain loop over every patch finds: same patch (or a tie within
// 1e-9 Å), same depth.
TEST(PatchScene, MatchesAPlainLoopOverAllPatches) {
  const Case& c = loadCase("structures/1crn.pdb");
  const PatchScene scene(ScenePatches::fromPatchList(c.patches));
  const ScenePatches& patches = scene.patches();
  std::mt19937_64 rng(11);
  int compared = 0, hits = 0;
  for (int view = 0; view < 3; ++view) {
    const Camera cam = framed(c.molecule, randomDirection(rng), 40, Projection::Perspective);
    for (int y = 0; y < cam.height; ++y)
      for (int x = 0; x < cam.width; x += 4) {
        Ray rays[16];
        bool valid[16];
        for (int j = 0; j < 16; ++j) {
          valid[j] = x + j % 4 < cam.width && j / 4 == 0;
          rays[j] = cam.ray(x + j % 4 + 0.5, y + 0.5);
        }
        SceneHit packet[16];
        scene.intersect16(rays, valid, 0.0, packet);
        for (int j = 0; j < 4 && x + j < cam.width; ++j) {
          const SceneHit loop = patches.intersectAll(rays[j], 0.0, std::numeric_limits<double>::infinity());
          const SceneHit single = scene.intersect1(rays[j], 0.0, std::numeric_limits<double>::infinity());
          ++compared;
          ASSERT_EQ(loop.valid(), packet[j].valid()) << "view " << view << " pixel " << x + j << "," << y;
          ASSERT_EQ(loop.valid(), single.valid()) << "view " << view << " pixel " << x + j << "," << y;
          if (!loop.valid()) continue;
          ++hits;
          const double scale = glm::length(rays[j].dir);
          EXPECT_NEAR(loop.hit.t * scale, packet[j].hit.t * scale, 1e-9)
              << "view " << view << " pixel " << x + j << "," << y << ": loop " << patchKindName(loop.kind) << " " << loop.patch
              << ", Embree " << patchKindName(packet[j].kind) << " " << packet[j].patch;
          EXPECT_NEAR(loop.hit.t * scale, single.hit.t * scale, 1e-9);
          if (loop.kind != packet[j].kind || loop.patch != packet[j].patch) {
            // A different patch is acceptable only at a seam: both report the same depth.
            const SceneHit other = patches.intersectPatch(packet[j].kind, packet[j].patch, rays[j], 0.0,
                                                          std::numeric_limits<double>::infinity());
            EXPECT_NEAR(other.hit.t * scale, loop.hit.t * scale, 1e-9);
          }
        }
      }
  }
  EXPECT_GT(hits, 1000);
  EXPECT_GT(compared, hits);
}

// On a closed surface seen from outside, the first hit always faces the viewer: a hit whose
// normal faces away from the ray means the ray slipped through a crack.
TEST(Watertight, NoRayEscapesThroughTheSurface) {
  std::mt19937_64 rng(3);
  for (const char* file : {"structures/1crn.pdb", "small/1grm_single.pdb"}) {
    const Case& c = loadCase(file);
    const PatchScene scene(ScenePatches::fromPatchList(c.patches));
    std::size_t hits = 0, escaped = 0;
    for (int view = 0; view < 6; ++view) {
      RenderOptions o;
      o.camera = framed(c.molecule, randomDirection(rng), 256, Projection::Perspective);
      const FrameBuffers f = render(scene, o, {});
      for (int y = 0; y < f.height; ++y)
        for (int x = 0; x < f.width; ++x) {
          const std::size_t p = static_cast<std::size_t>(y) * f.width + x;
          if (f.kind[p] == 0) continue;
          ++hits;
          const glm::dvec3 d = o.camera.ray(x + 0.5, y + 0.5).dir;
          const glm::dvec3 n(f.normal[3 * p], f.normal[3 * p + 1], f.normal[3 * p + 2]);
          if (glm::dot(n, d) > kGrazingCosine) {
            ++escaped;
            if (escaped <= 5)
              ADD_FAILURE() << file << " view " << view << " pixel " << x << "," << y << " kind " << f.kind[p] << " patch "
                            << f.patchId[p] << " faces away (n·d = " << glm::dot(n, d) << ")";
          }
        }
    }
    EXPECT_EQ(escaped, 0u) << file << ": " << escaped << " of " << hits << " hit pixels escaped";
    EXPECT_GT(hits, 50000u);
  }
}

// Tiles are independent: 1 and 2 threads give the same bits in every buffer.
TEST(Render, IdenticalForAnyThreadCount) {
  const Case& c = loadCase("structures/1crn.pdb");
  const PatchScene scene(ScenePatches::fromPatchList(c.patches));
  RenderOptions o;
  o.camera = framed(c.molecule, {0.3, -0.5, -1.0}, 97, Projection::Perspective);
  o.samplesPerPixel = 4;
  o.aoSamples = 4;
  o.shadows = true;
  FrameBuffers a, b;
  {
    tbb::global_control one(tbb::global_control::max_allowed_parallelism, 1);
    a = render(scene, o, {});
  }
  {
    tbb::global_control two(tbb::global_control::max_allowed_parallelism, 2);
    b = render(scene, o, {});
  }
  EXPECT_EQ(a.rgba, b.rgba);
  EXPECT_EQ(a.depth, b.depth);
  EXPECT_EQ(a.normal, b.normal);
  EXPECT_EQ(a.patchId, b.patchId);
  EXPECT_EQ(a.atomId, b.atomId);
  EXPECT_EQ(a.flags, b.flags);
}

}  // namespace
}  // namespace surftrace::trace

namespace surftrace::trace {
namespace {

// Buried cavities are closed inner components: dropping them (build::outerComponent)
// changes no pixel seen from outside, and their areas and volumes add up.
TEST(Components, DroppingCavitiesChangesNothingSeenFromOutside) {
  const Case& c = loadCase("structures/1crn.pdb");
  ASSERT_GE(c.patches.componentCount, 2u) << "1CRN has a buried cavity a 1.4 Å probe fits in";
  const build::PatchList outer = build::outerComponent(c.patches);
  outer.validate();
  EXPECT_LT(outer.patchCount(), c.patches.patchCount());
  const build::SurfaceAreas all = build::computeAreas(c.patches), kept = build::computeAreas(outer);
  double area = 0.0, volume = 0.0;
  for (const auto& comp : all.components) area += comp.area, volume += comp.volume;
  EXPECT_NEAR(area, all.sesTotal(), 1e-9 * all.sesTotal());
  EXPECT_NEAR(volume, all.sesVolume, 1e-9 * all.sesVolume);
  EXPECT_NEAR(kept.sesTotal(), all.components[0].area, 1e-9 * all.sesTotal());
  EXPECT_NEAR(kept.sesVolume, all.components[0].volume, 1e-9 * all.sesVolume);
  for (std::size_t k = 1; k < all.components.size(); ++k) EXPECT_LT(all.components[k].volume, 0.0) << "cavity " << k;

  const PatchScene full(ScenePatches::fromPatchList(c.patches)), pruned(ScenePatches::fromPatchList(outer));
  std::mt19937_64 rng(21);
  for (int view = 0; view < 3; ++view) {
    RenderOptions o;
    o.camera = framed(c.molecule, randomDirection(rng), 96, Projection::Perspective);
    const FrameBuffers a = render(full, o, {}), b = render(pruned, o, {});
    EXPECT_EQ(a.depth, b.depth) << "view " << view;
    EXPECT_EQ(a.kind, b.kind) << "view " << view;
    EXPECT_EQ(a.atomId, b.atomId) << "view " << view;
  }
}

}  // namespace
}  // namespace surftrace::trace

namespace surftrace::trace {
namespace {

// ORACLES D.4/E.14: moving the molecule and the camera 1e4 Å away changes nothing but
// rounding. Embree traverses float rays, so this holds only because the callbacks work on
// the double rays and the float rays start at the scene's box.
TEST(PatchScene, TranslationInvariantFarFromTheOrigin) {
  const Case& c = loadCase("structures/1crn.pdb");
  const glm::dvec3 offset(1e4, 1e4, 1e4);
  std::vector<glm::dvec3> moved(c.molecule.centers);
  for (auto& x : moved) x += offset;
  const build::PatchList far = build::buildSes(moved, c.molecule.radii, build::SesParams{kRp});
  ASSERT_EQ(far.patchCount(), c.patches.patchCount());
  const PatchScene near(ScenePatches::fromPatchList(c.patches)), away(ScenePatches::fromPatchList(far));
  const Camera cam = framed(c.molecule, {0.4, -0.3, -1.0}, 64, Projection::Perspective);
  Camera camFar = cam;
  camFar.eye += offset;
  camFar.lookAt += offset;
  double worst = 0.0;
  int hits = 0, kindChanges = 0;
  for (int y = 0; y < cam.height; ++y)
    for (int x = 0; x < cam.width; ++x) {
      const SceneHit a = near.intersect1(cam.ray(x + 0.5, y + 0.5), 0.0, std::numeric_limits<double>::infinity());
      const SceneHit b = away.intersect1(camFar.ray(x + 0.5, y + 0.5), 0.0, std::numeric_limits<double>::infinity());
      ASSERT_EQ(a.valid(), b.valid()) << "pixel " << x << "," << y;
      if (!a.valid()) continue;
      ++hits;
      worst = std::max(worst, std::abs(a.hit.t - b.hit.t));
      kindChanges += a.kind != b.kind && ((a.hit.flags | b.hit.flags) & kHitNearBoundary) == 0;
    }
  EXPECT_GT(hits, 1000);
  EXPECT_LT(worst, 1e-6) << "worst depth change " << worst << " Å";
  EXPECT_EQ(kindChanges, 0);
  char text[32];
  std::snprintf(text, sizeof text, "%.3g", worst);
  RecordProperty("worst_depth_change_angstrom", text);
}

}  // namespace
}  // namespace surftrace::trace

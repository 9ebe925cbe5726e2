// The lighting presets (view::lightingFor) rendered by Embree, against the key-fill formula
// evaluated here from the normal buffer, on a concave bowl (a pocket must not read as a
// bump), and for the noise and determinism of their shadow and occlusion rays.
#include <cmath>
#include <cstdio>
#include <numeric>
#include <vector>

#include <glm/geometric.hpp>
#include <glm/vec2.hpp>
#include <gtest/gtest.h>
#include <tbb/global_control.h>

#include "build/atom_spheres.hpp"
#include "build/io/molecule.hpp"
#include "build/ses/contour_buildup.hpp"
#include "oracles/floor_noise.hpp"
#include "trace/render.hpp"
#include "view/shading.hpp"

namespace surftrace::trace {
namespace {

using view::Camera;
using view::FrameBuffers;
using view::LightingPreset;
using view::RenderOptions;

constexpr double kRp = 1.4;

// Pearson's correlation of two equally long series.
double correlation(const std::vector<double>& a, const std::vector<double>& b) {
  const double n = static_cast<double>(a.size());
  const double ma = std::accumulate(a.begin(), a.end(), 0.0) / n, mb = std::accumulate(b.begin(), b.end(), 0.0) / n;
  double sab = 0.0, saa = 0.0, sbb = 0.0;
  for (std::size_t i = 0; i < a.size(); ++i) {
    sab += (a[i] - ma) * (b[i] - mb);
    saa += (a[i] - ma) * (a[i] - ma);
    sbb += (b[i] - mb) * (b[i] - mb);
  }
  return sab / std::sqrt(saa * sbb);
}

// Towards the key light: 45° off the view axis, above left.
glm::dvec3 keyLight(const Camera& cam) {
  return glm::normalize(-cam.right() + cam.trueUp() - std::sqrt(2.0) * cam.forward());
}

// The `simple` preset as the README states it, with its numbers written out here: a key light
// from (−1, 1, √2) (45° off the view axis) and a fill light from (1, −0.2, 1) in the camera's (right, up, towards
// the eye) frame, c = base·(0.3 + 0.65·max(0, n·k) + 0.25·max(0, n·f)) + 0.2·[n·k > 0]·max(0, n·h)^32,
// h = normalize(k + e), clamped to 1.
glm::dvec3 simpleFormula(const glm::dvec3& base, const glm::dvec3& n, const glm::dvec3& e, const Camera& cam) {
  const glm::dvec3 k = keyLight(cam);
  const glm::dvec3 f = glm::normalize(cam.right() - 0.2 * cam.trueUp() - cam.forward());
  const double nk = glm::dot(n, k);
  const double spec = nk > 0.0 ? 0.2 * std::pow(std::max(0.0, glm::dot(n, glm::normalize(k + e))), 32.0) : 0.0;
  return glm::min(base * (0.3 + 0.65 * std::max(0.0, nk) + 0.25 * std::max(0.0, glm::dot(n, f))) + spec, glm::dvec3(1.0));
}

TEST(LightingSimple, EveryPixelIsTheKeyFillFormulaOfItsNormal) {
  const build::Molecule m = build::readMolecule(std::string(SURFTRACE_TEST_DATA) + "/structures/1crn.pdb");
  const build::PatchList list = build::buildSes(m.centers, m.radii, build::SesParams{kRp});
  const PatchScene scene(ScenePatches::fromPatchList(list));
  for (const view::Projection projection : {view::Projection::Perspective, view::Projection::Orthographic}) {
    RenderOptions o;
    o.camera.width = o.camera.height = 64;
    o.camera.projection = projection;
    std::vector<double> reach(m.radii);
    for (double& r : reach) r += kRp;
    o.camera = view::frameSpheres(o.camera, m.centers, reach, glm::normalize(glm::dvec3(0.3, -0.4, 0.8)));
    o.lighting = view::lightingFor(LightingPreset::Simple);
    const FrameBuffers fb = render(scene, o, {});
    int checked = 0, litByKeyOnly = 0;
    double worst = 0.0;
    for (int y = 0; y < fb.height; ++y)
      for (int x = 0; x < fb.width; ++x) {
        const std::size_t p = static_cast<std::size_t>(y) * fb.width + x;
        if (fb.kind[p] == 0) continue;
        const glm::dvec3 n(fb.normal[3 * p], fb.normal[3 * p + 1], fb.normal[3 * p + 2]);
        const glm::dvec3 e = -glm::normalize(o.camera.ray(x + 0.5, y + 0.5).dir);
        const glm::dvec3 base(view::kindColor(static_cast<view::PatchKind>(fb.kind[p])));
        const glm::dvec3 want = simpleFormula(base, glm::normalize(n), e, o.camera);
        for (int c = 0; c < 3; ++c) worst = std::max(worst, std::abs(fb.rgba[4 * p + c] - want[c]));
        // Pixels the headlight would light fully but the key light does not: the model differs.
        if (glm::dot(n, e) > 0.95 && glm::dot(n, keyLight(o.camera)) < 0.7)
          ++litByKeyOnly;
        ++checked;
      }
    EXPECT_GT(checked, 64 * 64 / 5);
    EXPECT_LT(worst, 1e-4) << "largest |Δ| of a channel from the formula";
    EXPECT_GT(litByKeyOnly, 0);
  }
}

// A pit: 1.8 Å atoms on a tube of radius 7 Å from z = 0.5 down to z = −12 and on the half
// sphere that closes it below, about 2.4 Å apart (too tight for the probe), looked into from +z
// (orthographic). Its inner SES is a pocket 19 Å deep whose floor faces the eye.
struct Pit {
  std::vector<glm::dvec3> centers;
  std::vector<double> radii;
  build::PatchList patches;
};

constexpr double kPitRadius = 7.0, kPitDepth = 12.0;

const Pit& pit() {
  static const Pit made = [] {
    Pit b;
    const int perRing = 18;
    for (int ring = 0; 0.5 - 2.1 * ring >= -kPitDepth; ++ring)
      for (int i = 0; i < perRing; ++i) {
        const double phi = 2.0 * 3.14159265358979323846 * (i + 0.5 * (ring % 2)) / perRing;
        b.centers.push_back({kPitRadius * std::cos(phi), kPitRadius * std::sin(phi), 0.5 - 2.1 * ring});
        b.radii.push_back(1.8);
      }
    const int n = 110;
    for (int i = 0; i < n; ++i) {
      const double z = 1.0 - (2.0 * i + 1.0) / n, r = std::sqrt(1.0 - z * z), phi = 2.399963229728653 * i;
      if (z < -0.15) {
        b.centers.push_back(kPitRadius * glm::dvec3(r * std::cos(phi), r * std::sin(phi), z) - glm::dvec3(0.0, 0.0, kPitDepth));
        b.radii.push_back(1.8);
      }
    }
    b.patches = build::buildSes(b.centers, b.radii, build::SesParams{kRp});
    return b;
  }();
  return made;
}

RenderOptions pitView(int size) {
  RenderOptions o;
  o.camera.projection = view::Projection::Orthographic;
  o.camera.eye = {0.0, 0.0, 40.0};
  o.camera.lookAt = {0.0, 0.0, 0.0};
  o.camera.up = {0.0, 1.0, 0.0};
  o.camera.orthoHeight = 22.0;
  o.camera.width = o.camera.height = size;
  o.color = view::ColorMode::Uniform;
  return o;
}

// The correlation of brightness with depth over the pocket's pixels (hits inside the tube below its rim).
double pocketCorrelation(const RenderOptions& o) {
  const Pit& b = pit();
  const PatchScene scene(ScenePatches::fromPatchList(b.patches));
  const std::vector<glm::vec3> grey(b.centers.size(), glm::vec3(0.8f));
  const FrameBuffers fb = render(scene, o, grey);
  std::vector<double> depth, brightness;
  for (int y = 0; y < fb.height; ++y)
    for (int x = 0; x < fb.width; ++x) {
      const std::size_t p = static_cast<std::size_t>(y) * fb.width + x;
      if (fb.kind[p] == 0) continue;
      const Ray ray = o.camera.ray(x + 0.5, y + 0.5);
      const glm::dvec3 hit = ray.org + static_cast<double>(fb.depth[p]) * ray.dir;
      if (glm::length(glm::dvec2(hit.x, hit.y)) > kPitRadius || hit.z > -1.0) continue;
      depth.push_back(fb.viewZ[p]);
      brightness.push_back((fb.rgba[4 * p] + fb.rgba[4 * p + 1] + fb.rgba[4 * p + 2]) / 3.0);
    }
  EXPECT_GT(depth.size(), static_cast<std::size_t>(fb.pixels() / 8));
  return correlation(depth, brightness);
}

TEST(LightingPocket, ThePocketDoesNotBrightenWithDepth) {
  RenderOptions o = pitView(96);
  const double headlight = pocketCorrelation(o);
  o.lighting = view::lightingFor(LightingPreset::Simple);
  const double simple = pocketCorrelation(o);
  o.lighting = view::lightingFor(LightingPreset::Soft);
  const double soft = pocketCorrelation(o);
  std::printf("brightness-depth correlation in the pit: headlight %+.3f, simple %+.3f, soft %+.3f\n", headlight, simple,
              soft);
  // Measured +0.647, +0.370, −0.493. Without shadows the floor, which faces the eye, still
  // gets cos 45° of the key light where the walls get less: `simple` halves the correlation;
  // only the key light's shadow and the occlusion of `soft` make the pocket darken with depth.
  EXPECT_GT(headlight, 0.5) << "the scene is not the pocket the headlight lights as a bump";
  EXPECT_LT(simple, 0.45);
  EXPECT_LT(soft, -0.3);
}

using test::floorNoise;

// A flat region: a sphere of radius 100 Å (its top at z = 0) with a ball of 4 Å hovering 0.5 Å
// above it, seen from above (orthographic). The floor's ambient visibility and the ball's
// penumbra vary smoothly; what a pixel adds to its neighbours' mean is the sampling noise.
struct Floor {
  PatchScene scene;
  RenderOptions o;
  std::vector<glm::vec3> white;
};

Floor floorScene() {
  const std::vector<glm::dvec3> centers{{0.0, 0.0, -100.0}, {0.0, 0.0, 4.5}};
  const std::vector<double> radii{100.0, 4.0};
  RenderOptions o;
  o.camera.projection = view::Projection::Orthographic;
  o.camera.eye = {0.0, 0.0, 50.0};
  o.camera.lookAt = {0.0, 0.0, 0.0};
  o.camera.orthoHeight = 30.0;
  o.camera.width = o.camera.height = 128;
  o.color = view::ColorMode::Uniform;
  return {PatchScene(ScenePatches::fromPatchList(build::atomSpheres(centers, radii, 0.0, build::SurfaceKind::Vdw))), o,
          std::vector<glm::vec3>(2, glm::vec3(1.0f))};
}

// Ambient occlusion alone (ambient 1, no other term), white: the colour is the ambient visibility A.
TEST(LightingSoft, OcclusionNoiseOnAFlatFloorIsSmallAtTheDefaultRays) {
  Floor f = floorScene();
  for (const LightingPreset preset : {LightingPreset::Soft, LightingPreset::Full}) {
    view::Lighting l = view::lightingFor(preset);
    l.ambient = 1.0f;
    l.diffuse = l.fill = l.specular = 0.0f;
    l.shadowRays = 0;
    f.o.lighting = l;
    const FrameBuffers fb = render(f.scene, f.o, f.white);
    std::vector<double> a(fb.pixels());
    for (std::size_t p = 0; p < a.size(); ++p) a[p] = fb.rgba[4 * p];
    const test::FloorNoise n = floorNoise(fb, a, 0.02, 0.98);
    std::printf("%s: %d occlusion rays, noise σ = %.4f over %zu partly occluded floor pixels\n",
                view::lightingPresetName(preset), l.occlusionRays, n.sigma, n.pixels);
    EXPECT_GT(n.pixels, 500u);
    EXPECT_LT(n.sigma, preset == LightingPreset::Soft ? 0.01 : 0.005);
  }
}

// The key light alone (diffuse 1, no other term), white: the colour over max(0, n·k) is the key
// light's visibility S; its noise over the ball's penumbra on the floor.
TEST(LightingSoft, PenumbraNoiseOnAFlatFloorIsSmallAtTheDefaultRays) {
  Floor f = floorScene();
  for (const LightingPreset preset : {LightingPreset::Soft, LightingPreset::Full}) {
    view::Lighting l = view::lightingFor(preset);
    l.ambient = l.fill = l.specular = 0.0f;
    l.diffuse = 1.0f;
    l.occlusionRays = 0;
    f.o.lighting = l;
    const FrameBuffers fb = render(f.scene, f.o, f.white);
    const glm::dvec3 k = keyLight(f.o.camera);
    std::vector<double> s(fb.pixels(), 0.0);
    for (std::size_t p = 0; p < s.size(); ++p) {
      const double nk = glm::dot(glm::dvec3(fb.normal[3 * p], fb.normal[3 * p + 1], fb.normal[3 * p + 2]), k);
      if (fb.kind[p] != 0 && nk > 0.1) s[p] = fb.rgba[4 * p] / nk;
    }
    const test::FloorNoise n = floorNoise(fb, s, 0.02, 0.98);
    std::printf("%s: %d shadow rays, penumbra noise σ = %.4f over %zu floor pixels\n", view::lightingPresetName(preset),
                l.shadowRays, n.sigma, n.pixels);
    EXPECT_GT(n.pixels, 100u);
    EXPECT_LT(n.sigma, preset == LightingPreset::Soft ? 0.02 : 0.012);
  }
}

// 1CRN's SES, the middle quarter of a `size`² framing (fovY narrowed to a quarter's tangent):
// pixels as fine as a 1024² frame of a 60 Å protein, where the filter is meant to work.
struct Crambin {
  PatchScene scene;
  RenderOptions o;
};

Crambin crambin(int size) {
  const build::Molecule m = build::readMolecule(std::string(SURFTRACE_TEST_DATA) + "/structures/1crn.pdb");
  RenderOptions o;
  o.camera.width = o.camera.height = 4 * size;
  std::vector<double> reach(m.radii);
  for (double& r : reach) r += kRp;
  o.camera = view::frameSpheres(o.camera, m.centers, reach, glm::normalize(glm::dvec3(0.3, -0.4, 0.8)));
  o.camera.width = o.camera.height = size;
  constexpr double kDegree = 3.14159265358979323846 / 180.0;
  o.camera.fovY = 2.0 * std::atan(0.25 * std::tan(0.5 * o.camera.fovY * kDegree)) / kDegree;
  return {PatchScene(ScenePatches::fromPatchList(build::buildSes(m.centers, m.radii, build::SesParams{kRp}))), o};
}

// The mean |Δ| of the red channel from the oracle's over the pixels both hit, and over those
// of them next to a depth jump (a 4-neighbour more than 2 Å nearer or farther, or a miss).
struct Error {
  double all = 0.0, silhouette = 0.0, silhouetteWorst = 0.0;
  std::size_t silhouettePixels = 0;
};
Error errorFrom(const FrameBuffers& fb, const FrameBuffers& truth) {
  Error e;
  std::size_t n = 0;
  for (int y = 0; y < fb.height; ++y)
    for (int x = 0; x < fb.width; ++x) {
      const std::size_t p = static_cast<std::size_t>(y) * fb.width + x;
      if (fb.kind[p] == 0 || truth.kind[p] == 0) continue;
      const double d = std::abs(fb.rgba[4 * p] - truth.rgba[4 * p]);
      e.all += d;
      ++n;
      bool edge = false;
      for (const auto& [dx, dy] : {std::pair{1, 0}, std::pair{-1, 0}, std::pair{0, 1}, std::pair{0, -1}}) {
        if (x + dx < 0 || x + dx >= fb.width || y + dy < 0 || y + dy >= fb.height) continue;
        const std::size_t q = static_cast<std::size_t>(y + dy) * fb.width + (x + dx);
        edge = edge || fb.kind[q] == 0 || std::abs(fb.viewZ[q] - fb.viewZ[p]) > 2.0f;
      }
      if (!edge) continue;
      e.silhouette += d;
      e.silhouetteWorst = std::max(e.silhouetteWorst, d);
      ++e.silhouettePixels;
    }
  e.all /= static_cast<double>(std::max<std::size_t>(n, 1));
  e.silhouette /= static_cast<double>(std::max<std::size_t>(e.silhouettePixels, 1));
  return e;
}

// Each preset's image of 1CRN (white) against a brute-force oracle: 1024 rays for S and for A
// at every pixel, no filter, the same lights, disc and occlusion distance (both presets'), so
// the estimators' common mean to about ±0.003. The preset has a smaller mean error than the
// same lights traced per pixel with the former ray counts (32 and 128 each for S and A, no
// filter), and carries no value across a silhouette: the pixels next to a depth jump are as
// near the oracle on average, none farther than 0.1.
TEST(LightingSoft, FilteredImageIsNearerTheBruteForceOracleThanTheFormerRays) {
  Crambin c = crambin(96);
  const std::vector<glm::vec3> white(400, glm::vec3(1.0f));
  c.o.color = view::ColorMode::Uniform;
  c.o.lighting = view::lightingFor(LightingPreset::Soft);
  c.o.lighting.shadowRays = c.o.lighting.occlusionRays = 1024;
  c.o.lighting.filterPasses = 0;
  const FrameBuffers truth = render(c.scene, c.o, white);
  for (const LightingPreset preset : {LightingPreset::Soft, LightingPreset::Full}) {
    c.o.lighting = view::lightingFor(preset);
    c.o.lighting.shadowRays = c.o.lighting.occlusionRays = preset == LightingPreset::Soft ? 32 : 128;
    c.o.lighting.filterPasses = 0;
    const Error before = errorFrom(render(c.scene, c.o, white), truth);
    c.o.lighting = view::lightingFor(preset);
    const Error now = errorFrom(render(c.scene, c.o, white), truth);
    std::printf("%s: mean |error| from the oracle %.4f (former rays %.4f); at %zu silhouette pixels %.4f (%.4f), "
                "worst %.3f (%.3f)\n",
                view::lightingPresetName(preset), now.all, before.all, now.silhouettePixels, now.silhouette,
                before.silhouette, now.silhouetteWorst, before.silhouetteWorst);
    EXPECT_GT(now.silhouettePixels, 30u);
    EXPECT_LT(now.all, before.all);
    EXPECT_LT(now.silhouette, before.silhouette);
    EXPECT_LT(now.silhouetteWorst, 0.1);
  }
}

// Shadow and occlusion rays depend on the pixel alone: two renders, and a render on one thread,
// are bit-identical (so a still image is reproducible and a trajectory's pattern does not move).
TEST(LightingSoft, RendersAreIdenticalRunToRunAndForAnyThreadCount) {
  const build::Molecule m = build::readMolecule(std::string(SURFTRACE_TEST_DATA) + "/structures/1crn.pdb");
  const PatchScene scene(ScenePatches::fromPatchList(build::buildSes(m.centers, m.radii, build::SesParams{kRp})));
  RenderOptions o;
  o.camera.width = o.camera.height = 48;
  std::vector<double> reach(m.radii);
  for (double& r : reach) r += kRp;
  o.camera = view::frameSpheres(o.camera, m.centers, reach, glm::dvec3(0.0, 0.0, -1.0));
  o.lighting = view::lightingFor(LightingPreset::Soft);
  const FrameBuffers a = render(scene, o, {}), b = render(scene, o, {});
  FrameBuffers c;
  {
    const tbb::global_control one(tbb::global_control::max_allowed_parallelism, 1);
    c = render(scene, o, {});
  }
  EXPECT_EQ(a.rgba, b.rgba);
  EXPECT_EQ(a.rgba, c.rgba);
  // Not trivially so: the soft preset does darken some pixels below the simple preset.
  o.lighting = view::lightingFor(LightingPreset::Simple);
  const FrameBuffers plain = render(scene, o, {});
  int darker = 0;
  for (std::size_t p = 0; p < plain.pixels(); ++p) darker += a.rgba[4 * p] < plain.rgba[4 * p] - 0.05f;
  EXPECT_GT(darker, 48 * 48 / 20);
}

}  // namespace
}  // namespace surftrace::trace

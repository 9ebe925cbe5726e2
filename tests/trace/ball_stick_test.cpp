// The ball-and-stick model in the Embree scene: nearest hits against a plain loop over the
// balls and sticks, and a transparent surface over the opaque model: each pixel composites
// exactly the surface's crossings in front of the model's nearest hit (from separate queries
// of a surface-only scene and a model-only loop), by the compositing formula.
#include <cmath>
#include <random>
#include <string>
#include <vector>

#include <glm/geometric.hpp>
#include <gtest/gtest.h>

#include "build/bonds.hpp"
#include "build/io/molecule.hpp"
#include "build/ses/contour_buildup.hpp"
#include "trace/layers.hpp"
#include "trace/render.hpp"
#include "view/camera.hpp"
#include "view/shading.hpp"

namespace surftrace::trace {
namespace {

constexpr double kRp = 1.4;

struct Crambin {
  build::Molecule molecule;
  build::PatchList ses;
  build::BallStickModel model;
};
const Crambin& crambin() {
  static const Crambin loaded = [] {
    Crambin c;
    c.molecule = build::readMolecule(std::string(SURFTRACE_TEST_DATA) + "/structures/1crn.pdb");
    c.ses = build::buildSes(c.molecule.centers, c.molecule.radii, build::SesParams{kRp});
    c.model = build::ballStickModel(c.molecule.centers, c.molecule.radii, build::moleculeBonds(c.molecule), 0.25, 0.15);
    return c;
  }();
  return loaded;
}

view::RenderOptions framed(int size) {
  const Crambin& c = crambin();
  view::RenderOptions o;
  o.camera.width = o.camera.height = size;
  std::vector<double> reach(c.molecule.radii);
  for (double& r : reach) r += kRp;
  o.camera = view::frameSpheres(o.camera, c.molecule.centers, reach, {0, 0, -1});
  o.color = view::ColorMode::Element;
  o.background = {0.2f, 0.3f, 0.9f};
  return o;
}

TEST(BallAndStickScene, NearestHitsMatchAPlainLoop) {
  const Crambin& c = crambin();
  ASSERT_EQ(c.model.bonds.size(), 337u);  // MDAnalysis's count (reader_tests: Bonds.*)
  const PatchScene scene(ScenePatches::fromPatchList(build::PatchList(), {}, {}, &c.model));
  EXPECT_EQ(scene.patches().of<BallKind>().patches.size(), c.molecule.size());
  EXPECT_EQ(scene.patches().of<StickKind>().patches.size(), 337u);
  const view::RenderOptions o = framed(48);
  const view::Camera::Frame frame = o.camera.frame();
  int balls = 0, sticks = 0;
  for (int y = 0; y < 48; ++y)
    for (int x = 0; x < 48; ++x) {
      const Ray ray = frame.ray(x + 0.5, y + 0.5);
      const SceneHit got = scene.intersect1(ray, 0.0, std::numeric_limits<double>::infinity());
      const SceneHit want = scene.patches().intersectAll(ray, 0.0, std::numeric_limits<double>::infinity());
      ASSERT_EQ(got.kind, want.kind) << x << "," << y;
      if (!want.valid()) continue;
      EXPECT_EQ(got.patch, want.patch) << x << "," << y;
      EXPECT_NEAR(got.hit.t, want.hit.t, 1e-9) << x << "," << y;
      balls += want.kind == PatchKind::Ball;
      sticks += want.kind == PatchKind::Stick;
    }
  EXPECT_GT(balls, 100);
  EXPECT_GT(sticks, 20);
}

TEST(BallAndStickScene, TransparentSurfaceCompositesTheLayersInFrontOfTheModel) {
  const Crambin& c = crambin();
  const PatchScene both(ScenePatches::fromPatchList(c.ses, c.molecule.centers, c.molecule.radii, &c.model));
  const PatchScene surface(ScenePatches::fromPatchList(c.ses, c.molecule.centers, c.molecule.radii));
  const ScenePatches model = ScenePatches::fromPatchList(build::PatchList(), {}, {}, &c.model);
  view::RenderOptions o = framed(40);
  o.opacity = 0.4;
  o.maxLayers = 64;
  std::vector<glm::vec3> colors(c.molecule.size());
  std::mt19937_64 rng(5);
  std::uniform_real_distribution<float> u(0.1f, 0.9f);
  for (glm::vec3& col : colors) col = {u(rng), u(rng), u(rng)};
  const view::FrameBuffers fb = render(both, o, colors);
  const view::Camera::Frame frame = o.camera.frame();
  const float a = 0.4f;
  int throughModel = 0, withLayersInFront = 0;
  for (int y = 0; y < 40; ++y)
    for (int x = 0; x < 40; ++x) {
      const std::size_t p = static_cast<std::size_t>(y) * 40 + x;
      const Ray ray = frame.ray(x + 0.5, y + 0.5);
      const glm::dvec3 d = glm::normalize(ray.dir);
      const SceneHit m = model.intersectAll(ray, 0.0, std::numeric_limits<double>::infinity());
      const std::vector<SceneHit> layers = surface.intersectLayers1(ray, 64);
      glm::vec3 want(0.0f);
      float through = 1.0f;
      std::uint32_t front = 0;
      for (const SceneHit& h : layers) {
        if (m.valid() && h.hit.t >= m.hit.t) break;  // behind the model: dropped
        const std::uint32_t atom = surface.patches().atomOf(h, ray.org + h.hit.t * ray.dir);
        want += through * a * view::shade(colors[atom], h.hit.normal, -d, o.lighting);
        through *= 1.0f - a;
        ++front;
      }
      if (m.valid()) {
        const std::uint32_t atom = model.atomOf(m, ray.org + m.hit.t * ray.dir);
        want += through * view::shade(colors[atom], m.hit.normal, -d, o.lighting);
        through = 0.0f;
        ++throughModel;
        withLayersInFront += front > 0;
      }
      want += through * o.background;
      EXPECT_EQ(fb.layers[p], front) << x << "," << y;
      for (int ch = 0; ch < 3; ++ch) EXPECT_NEAR(fb.rgba[4 * p + ch], want[ch], 2e-5) << x << "," << y << " channel " << ch;
      EXPECT_NEAR(fb.rgba[4 * p + 3], 1.0f - through, 1e-6) << x << "," << y;
    }
  EXPECT_GT(throughModel, 150);
  EXPECT_GT(withLayersInFront, 150);
}

}  // namespace
}  // namespace surftrace::trace

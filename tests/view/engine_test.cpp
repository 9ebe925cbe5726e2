// The rules every engine follows, which Engine::render holds (view/engine.hpp), seen through an
// engine that records the frame it is asked to draw.
#include <gtest/gtest.h>

#include <stdexcept>
#include <string>
#include <vector>

#include "build/atom_spheres.hpp"
#include "view/engine.hpp"

namespace surftrace::view {
namespace {

// Draws one pixel, a hit at view depth kViewZ in colour kColor, and records what it was given.
constexpr float kViewZ = 15.0f;
constexpr float kColor[3] = {0.2f, 0.4f, 0.6f};

class RecordingEngine final : public Engine {
 public:
  EngineDescription describe() const override { return {"recording", "", "recording", {}}; }
  const char* name() const override { return "recording"; }

  int draws = 0;
  std::size_t patches = 0;
  build::SurfaceParams params;
  double opacity = -1.0;
  const build::BallStickModel* model = nullptr;

 protected:
  FrameBuffers draw(const Frame& frame) override {
    ++draws;
    patches = frame.surface->patchCount();
    params = frame.surface->params;
    opacity = frame.options.opacity;
    model = frame.model;
    FrameBuffers b;
    b.reset(1, 1);
    b.kind[0] = 1;
    b.viewZ[0] = kViewZ;
    b.rgba = {kColor[0], kColor[1], kColor[2], 1.0f};
    return b;
  }
};

// Three vdW balls of 1CRN-like size, their own surface (the list's params say how many atoms).
build::PatchList threeBalls(std::vector<glm::dvec3>& centers, std::vector<double>& radii) {
  centers = {{0, 0, 0}, {3, 0, 0}, {0, 3, 0}};
  radii = {1.7, 1.5, 1.6};
  return build::atomSpheres(centers, radii, 0.0, build::SurfaceKind::Vdw);
}

TEST(Engine, OpacityZeroDrawsAnEmptyListOfTheSameSurfaceAtOpacityOne) {
  std::vector<glm::dvec3> centers;
  std::vector<double> radii;
  const build::PatchList list = threeBalls(centers, radii);
  ASSERT_EQ(list.patchCount(), 3u);
  build::BallStickModel model;
  model.centers = centers;
  model.ballRadii = {0.4, 0.4, 0.4};
  RecordingEngine engine;
  Frame frame{&list, centers, radii, {}, &model, {}};
  frame.options.opacity = 0.0;
  engine.render(frame);
  EXPECT_EQ(engine.draws, 1);
  EXPECT_EQ(engine.patches, 0u);
  EXPECT_EQ(engine.params.surface, build::SurfaceKind::Vdw);
  EXPECT_EQ(engine.params.atomCount, 3u);
  EXPECT_EQ(engine.opacity, 1.0);
  EXPECT_EQ(engine.model, &model);  // the model alone, drawn opaque
  // Any other opacity reaches the engine as it is, with the whole list.
  frame.options.opacity = 0.5;
  engine.render(frame);
  EXPECT_EQ(engine.patches, 3u);
  EXPECT_EQ(engine.opacity, 0.5);
}

TEST(Engine, AnEmptyModelIsNoModel) {
  std::vector<glm::dvec3> centers;
  std::vector<double> radii;
  const build::PatchList list = threeBalls(centers, radii);
  const build::BallStickModel empty;
  RecordingEngine engine;
  engine.render({&list, {}, {}, {}, &empty, {}});
  EXPECT_EQ(engine.model, nullptr);
}

// Depth cueing, linear fog: colour c at view depth z in [start, end] becomes
// (1 − f)·c + f·background with f = strength·(z − start)/(end − start), applied once.
TEST(Engine, ImageEffectsRunOnceAfterTheEngine) {
  std::vector<glm::dvec3> centers;
  std::vector<double> radii;
  const build::PatchList list = threeBalls(centers, radii);
  RecordingEngine engine;
  Frame frame{&list, {}, {}, {}, nullptr, {}};
  frame.options.background = {1.0f, 1.0f, 1.0f};
  frame.options.effects.depthCue = true;
  frame.options.effects.depthCueStrength = 0.5;
  frame.options.effects.depthCueStart = 10.0;
  frame.options.effects.depthCueEnd = 20.0;
  const FrameBuffers b = engine.render(frame);
  const double f = 0.5 * (kViewZ - 10.0) / 10.0;  // 0.25
  for (int c = 0; c < 3; ++c) EXPECT_NEAR(b.rgba[c], (1.0 - f) * kColor[c] + f * 1.0, 1e-6) << "channel " << c;
}

TEST(Engine, AFrameWithoutASurfaceOrWithUnpairedAtomsIsRefused) {
  RecordingEngine engine;
  EXPECT_THROW(engine.render(Frame{}), std::invalid_argument);
  std::vector<glm::dvec3> centers;
  std::vector<double> radii;
  const build::PatchList list = threeBalls(centers, radii);
  radii.pop_back();
  try {
    engine.render({&list, centers, radii, {}, nullptr, {}});
    FAIL() << "unpaired centres and radii accepted";
  } catch (const std::invalid_argument& e) {
    EXPECT_NE(std::string(e.what()).find("3 atom centres but 2 radii"), std::string::npos) << e.what();
  }
  EXPECT_EQ(engine.draws, 0);
}

TEST(Engine, KindsParseByNameAndAnUnknownOneNamesTheChoices) {
  EXPECT_EQ(parseEngineKind("embree"), EngineKind::Embree);
  EXPECT_EQ(parseEngineKind("gl"), EngineKind::Gl);
  EXPECT_STREQ(engineKindName(EngineKind::Gl), "gl");
  EXPECT_STREQ(engineKindName(EngineKind::Embree), "embree");
  try {
    parseEngineKind("vulkan");
    FAIL();
  } catch (const std::invalid_argument& e) {
    EXPECT_NE(std::string(e.what()).find("'vulkan': use embree or gl"), std::string::npos) << e.what();
  }
}

TEST(Engine, GlCannotDrawSamplesShadowsOrOcclusionEmbreeCan) {
  EngineOptions gl;
  gl.kind = EngineKind::Gl;
  RenderOptions options;
  EXPECT_NO_THROW(checkEngineCanDraw(gl, options));
  for (int what = 0; what < 3; ++what) {
    RenderOptions asked;
    if (what == 0) asked.samplesPerPixel = 4;
    if (what == 1) asked.shadows = true;
    if (what == 2) asked.aoSamples = 8;
    EXPECT_THROW(checkEngineCanDraw(gl, asked), std::invalid_argument) << what;
    EXPECT_NO_THROW(checkEngineCanDraw(EngineOptions{}, asked)) << what;
  }
}

}  // namespace
}  // namespace surftrace::view

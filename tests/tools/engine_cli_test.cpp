// `trajectory --engine gl`: the GL engine through the same pipeline as Embree, on three frames
// of AdK (3341 atoms, CHARMM DCD). Oracles: the Embree frames of the same run under `compare`'s
// GL presets, and independent `render --engine gl` processes of each frame (which draw on
// the main thread, not in the trajectory's TBB pipeline).
#include <gtest/gtest.h>

#include <cstdio>
#include <filesystem>
#include <sstream>
#include <string>

#include "frame_buffers_equal.hpp"
#include "run_tool.hpp"
#include "temp_dir.hpp"
#include "view/camera.hpp"
#include "view/image_io.hpp"

namespace surftrace::tools::test {
namespace {

namespace fs = std::filesystem;

const std::string kData = SURFTRACE_TEST_DATA;
const std::string kPsf = kData + "/trajectories/adk_dims/adk.psf.gz";
const std::string kDcd = kData + "/trajectories/adk_dims/adk_dims.dcd";
const std::string kFrames = " --frames 0:98:40";  // frames 0, 40 and 80
constexpr std::size_t kFrameNumbers[] = {0, 40, 80};

// An empty folder in the test's own (temp_dir.hpp).
struct TempDir {
  fs::path path = ::surftrace::test::freshTempDir("frames");
};

std::string frameFile(const fs::path& dir, std::size_t k) {
  char name[32];
  std::snprintf(name, sizeof name, "%05zu.exr", k);
  return (dir / name).string();
}

std::string vec(const glm::dvec3& v) {
  std::ostringstream out;
  out.precision(17);
  out << v.x << ',' << v.y << ',' << v.z;
  return out.str();
}

// Renders the three frames with `engine` and `options` into dir/<engine>/; each frame's
// metadata names the engine that drew it.
void renderFrames(const fs::path& dir, const std::string& engine, const std::string& options, const std::string& size) {
  const Result r = runTool("trajectory " + kPsf + " " + kDcd + kFrames + " --size " + size + " --quiet --engine " +
                           engine + " " + options + " --exr " + (dir / engine / "%05d.exr").string());
  ASSERT_EQ(r.status, 0) << r.output;
  for (std::size_t k : kFrameNumbers) {
    view::ImageMetadata meta;
    view::readExr(frameFile(dir / engine, k), &meta);
    EXPECT_EQ(meta.at("surftrace:engine"), engine);
    EXPECT_EQ(meta.at("surftrace:frame"), std::to_string(k));
    if (engine == "gl") {
      // GL's context opens with the first frame; every frame records it.
      EXPECT_NE(meta.at("surftrace:renderer").find(" gl: "), std::string::npos) << meta.at("surftrace:renderer");
      EXPECT_EQ(meta.at("surftrace:gl_torus_method"), "quartic");
    }
  }
}

// GL's frames pass `compare` with `preset` against Embree's frames of the same run.
void expectGlPassesAgainstEmbree(const std::string& options, const std::string& preset) {
  const TempDir dir;
  // 160x120: trajectory EXRs record no seam distances, so `compare` masks seams by the 3x3
  // neighbourhood rule, which leaves too few pixels to judge in a smaller frame.
  renderFrames(dir.path, "embree", options, "160x120");
  renderFrames(dir.path, "gl", options, "160x120");
  for (std::size_t k : kFrameNumbers) {
    const Result c = runTool("compare " + frameFile(dir.path / "gl", k) + " " + frameFile(dir.path / "embree", k) +
                             " --preset " + preset);
    EXPECT_EQ(c.status, 0) << "frame " << k << ", " << options << ":\n" << c.output;
    EXPECT_NE(c.output.find("PASS (" + preset + ")"), std::string::npos) << c.output;
  }
}

TEST(EngineCli, TrajectoryGlFramesPassCompareAgainstEmbreeFrames) {
  expectGlPassesAgainstEmbree("", "gl-vs-embree");
}

TEST(EngineCli, TransparentTrajectoryGlFramesPassCompareAgainstEmbreeFrames) {
  expectGlPassesAgainstEmbree("--opacity 0.5", "transparency");
}

// Every GL frame of a trajectory equals, buffer for buffer, `render --engine gl` of that frame
// alone with the trajectory's camera: the frames do not depend on the thread that asks for
// them (a TBB worker in the trajectory's pipeline, the main thread in `render`), nor on the
// frames drawn before them in the same context.
TEST(EngineCli, TrajectoryGlFramesEqualIndependentGlRenders) {
  for (const std::string options : {"", "--opacity 0.5 --ball-and-stick"}) {
    const TempDir dir;
    renderFrames(dir.path, "gl", options, "40x32");
    for (std::size_t k : kFrameNumbers) {
      view::ImageMetadata meta;
      const view::FrameBuffers frame = view::readExr(frameFile(dir.path / "gl", k), &meta);
      const view::Camera camera = view::cameraFromJson(meta.at("surftrace:camera"));
      std::ostringstream fov;
      fov.precision(17);
      fov << camera.fovY;
      const std::string alone = (dir.path / ("alone_" + std::to_string(k) + ".exr")).string();
      const Result r = runTool("render " + kPsf + " --trajectory " + kDcd + " --frame " + std::to_string(k) +
                               " --size 40x32 --quiet --engine gl --eye " + vec(camera.eye) + " --look-at " +
                               vec(camera.lookAt) + " --up " + vec(camera.up) + " --fov " + fov.str() + " --exr " +
                               alone + " " + options);
      ASSERT_EQ(r.status, 0) << r.output;
      const view::FrameBuffers b = view::readExr(alone);
      ::surftrace::test::expectSameBuffers(frame, b, "frame " + std::to_string(k) + " " + options);
    }
  }
}

// GL's limits hold for `trajectory` as for `render`, before any frame is read.
TEST(EngineCli, TrajectoryGlRefusesWhatGlCannotDraw) {
  const TempDir dir;
  const Result r = runTool("trajectory " + kPsf + " " + kDcd + kFrames + " --size 40x32 --quiet --engine gl --spp 4 " +
                           "--exr " + (dir.path / "%05d.exr").string());
  EXPECT_EQ(r.status, 1) << r.output;
  EXPECT_NE(r.output.find("--engine gl draws one sample per pixel"), std::string::npos) << r.output;
  EXPECT_FALSE(fs::exists(frameFile(dir.path, 0)));
}

// GL's light maps count occluders at any distance: an occlusion reach is refused with the value
// and what to do, not ignored (render and trajectory alike); Embree takes it; without occlusion
// (simple) the reach is moot and GL draws.
TEST(EngineCli, GlRefusesAnOcclusionDistance) {
  const TempDir dir;
  const std::string mol = kData + "/structures/1crn.pdb", png = (dir.path / "x.png").string();
  for (const std::string& command :
       {"render " + mol + " -o " + png, "trajectory " + kPsf + " " + kDcd + kFrames + " -o " + (dir.path / "%05d.png").string()}) {
    const Result r = runTool(command + " --size 16x16 --quiet --engine gl --lighting soft --ao-distance 4");
    EXPECT_EQ(r.status, 1) << command << "\n" << r.output;
    EXPECT_NE(r.output.find("--ao-distance 4: --engine gl's light maps count occluders at any distance"),
              std::string::npos)
        << r.output;
  }
  EXPECT_FALSE(fs::exists(png));
  EXPECT_EQ(runTool("render " + mol + " -o " + png + " --size 16x16 --quiet --lighting soft --ao-distance 4").status, 0);
  EXPECT_EQ(runTool("render " + mol + " -o " + png + " --size 16x16 --quiet --engine gl --lighting simple --ao-distance 4")
                .status,
            0);
}

}  // namespace
}  // namespace surftrace::tools::test

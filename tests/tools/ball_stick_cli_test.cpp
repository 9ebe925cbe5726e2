// --ball-and-stick through `surftrace render` and `trajectory`: GL against Embree with `compare
// --preset gl-vs-embree` on 1CRN (the model alone at --opacity 0, and under the opaque SES), the
// metadata, the model's kinds in the EXR, and the options' errors.
#include <cstdio>
#include <filesystem>
#include <string>
#include <vector>

#include <gtest/gtest.h>

#include "run_tool.hpp"
#include "temp_dir.hpp"
#include "view/image_io.hpp"
#include "view/patch_kind.hpp"

namespace surftrace::tools::test {
namespace {

namespace fs = std::filesystem;

const std::string kData = SURFTRACE_TEST_DATA;
const std::string kCrambin = kData + "/structures/1crn.pdb";

fs::path scratch(const std::string& name) {
  return ::surftrace::test::freshTempDir(name);
}

void render(const std::string& args, const fs::path& exr) {
  const Result r = runTool("render " + kCrambin + " --size 128x128 --quiet --color element " + args + " --exr " +
                           exr.string());
  EXPECT_EQ(r.status, 0) << args << ":\n" << r.output;
}

std::size_t countKind(const view::FrameBuffers& f, view::PatchKind kind) {
  std::size_t n = 0;
  for (std::uint32_t k : f.kind) n += k == static_cast<std::uint32_t>(kind);
  return n;
}

TEST(BallStickCli, GlMatchesEmbreeAloneAndUnderTheSurface) {
  const fs::path dir = scratch("engines");
  for (const std::string& surface : {std::string("--opacity 0"), std::string("--surface vdw"), std::string("")}) {
    const fs::path embree = dir / "embree.exr", gl = dir / "gl.exr";
    render("--ball-and-stick " + surface, embree);
    render("--ball-and-stick --engine gl " + surface, gl);
    const Result c = runTool("compare " + gl.string() + " " + embree.string() + " --preset gl-vs-embree");
    EXPECT_EQ(c.status, 0) << "'" << surface << "':\n" << c.output;
    std::printf("ball-and-stick '%s', GL vs Embree:\n%s", surface.c_str(), c.output.c_str());
    view::ImageMetadata meta;
    const view::FrameBuffers f = view::readExr(embree.string(), &meta);
    ASSERT_EQ(meta.count("surftrace:ball_and_stick"), 1u);
    EXPECT_EQ(meta.at("surftrace:ball_and_stick"), "{\"ball_scale\": 0.25, \"stick_radius\": 0.15, \"bonds\": 337}");
    if (surface == "--opacity 0") {
      EXPECT_GT(countKind(f, view::PatchKind::Ball), 1000u);
      EXPECT_GT(countKind(f, view::PatchKind::Stick), 200u);
      EXPECT_EQ(countKind(f, view::PatchKind::Convex), 0u) << "no surface at opacity 0";
    }
  }
}

TEST(BallStickCli, UnderATransparentSurfaceTheModelShows) {
  const fs::path dir = scratch("transparent");
  const fs::path plain = dir / "plain.exr", model = dir / "model.exr";
  render("--opacity 0.4", plain);
  render("--opacity 0.4 --ball-and-stick", model);
  const view::FrameBuffers a = view::readExr(plain.string()), b = view::readExr(model.string());
  // The buffers are the nearest crossing's, the surface's, wherever the surface covers the model.
  EXPECT_EQ(a.kind, b.kind);
  EXPECT_NE(a.rgba, b.rgba);
}

// GL peels the transparent surface over the model (its opaque layer) as Embree composites it:
// the colours agree (compare --preset transparency), and the model shows through in both.
TEST(BallStickCli, GlMatchesEmbreeUnderATransparentSurface) {
  const fs::path dir = scratch("transparent_engines");
  for (const std::string& surface : {std::string(""), std::string("--surface mss")}) {
    const fs::path embree = dir / "embree.exr", gl = dir / "gl.exr", plain = dir / "plain.exr";
    render("--ball-and-stick --opacity 0.4 " + surface, embree);
    render("--ball-and-stick --opacity 0.4 --engine gl " + surface, gl);
    render("--opacity 0.4 --engine gl " + surface, plain);
    const Result c = runTool("compare " + gl.string() + " " + embree.string() + " --preset transparency");
    EXPECT_EQ(c.status, 0) << "'" << surface << "':\n" << c.output;
    std::printf("ball-and-stick under '%s' at opacity 0.4, GL vs Embree:\n%s", surface.c_str(), c.output.c_str());
    // The comparison can fail: GL without the model is another picture, refused for its
    // settings, and judged on its colour when they are set aside.
    const Result without = runTool("compare " + plain.string() + " " + embree.string() + " --preset transparency");
    EXPECT_EQ(without.status, 1) << without.output;
    EXPECT_NE(without.output.find("ball and stick: test none, reference {"), std::string::npos) << without.output;
    const Result ignored = runTool("compare " + plain.string() + " " + embree.string() +
                                   " --preset transparency --ignore-settings --max-color-p99 1e-3");
    EXPECT_EQ(ignored.status, 2) << ignored.output;
  }
}

TEST(BallStickCli, TrajectoryFramesGetTheModel) {
  const fs::path dir = scratch("trajectory");
  const std::string psf = kData + "/trajectories/adk_dims/adk.psf.gz", dcd = kData + "/trajectories/adk_dims/adk_dims.dcd";
  const Result r = runTool("trajectory " + psf + " " + dcd + " --frames 0:2 --size 32x32 --quiet --ball-and-stick "
                           "--opacity 0 --exr " + (dir / "%03d.exr").string());
  ASSERT_EQ(r.status, 0) << r.output;
  view::ImageMetadata meta;
  const view::FrameBuffers f = view::readExr((dir / "000.exr").string(), &meta);
  EXPECT_EQ(meta.count("surftrace:ball_and_stick"), 1u);
  EXPECT_GT(countKind(f, view::PatchKind::Ball), 50u);
}

TEST(BallStickCli, BadOptionsAreRefusedNamingThem) {
  const fs::path out = scratch("bad") / "x.png";
  const std::vector<std::pair<std::string, std::string>> cases = {
      {"--opacity 0", "--ball-and-stick"},
      {"--ball-and-stick --ball-scale 0", "--ball-scale"},
      {"--ball-and-stick --stick-radius -1", "--stick-radius"},
      {"--opacity -0.5", "--opacity"},
  };
  for (const auto& [args, named] : cases) {
    const Result r = runTool("render " + kCrambin + " --size 8x8 --quiet " + args + " -o " + out.string());
    EXPECT_NE(r.status, 0) << args << ":\n" << r.output;
    EXPECT_NE(r.output.find(named), std::string::npos) << args << ":\n" << r.output;
  }
}

}  // namespace
}  // namespace surftrace::tools::test

// The image-space effects through `surftrace render` and `trajectory`: the silhouettes against
// a numpy recomputation from the EXR's own depth buffer, GL against Embree with each effect on
// (compare --preset effects), the metadata, and every effect off leaving the image as it was.
#include <cstdio>
#include <algorithm>
#include <filesystem>
#include <numeric>
#include <string>
#include <vector>

#include <gtest/gtest.h>

#include "oracles/python_oracle.hpp"
#include "run_tool.hpp"
#include "temp_dir.hpp"
#include "view/image_io.hpp"

namespace surftrace::tools::test {
namespace {

namespace fs = std::filesystem;

const std::string kData = SURFTRACE_TEST_DATA;
const std::string kCrambin = kData + "/structures/1crn.pdb";

fs::path scratch(const std::string& name) {
  return ::surftrace::test::freshTempDir(name);
}

std::string render(const std::string& args, const fs::path& exr) {
  const Result r = runTool("render " + kCrambin + " --size 96x96 --quiet " + args + " --exr " + exr.string());
  EXPECT_EQ(r.status, 0) << args << ":\n" << r.output;
  return r.output;
}

TEST(EffectsCli, SilhouettesLieAlongTheDepthJumpsInTheExr) {
  const fs::path dir = scratch("numpy");
  const fs::path plain = dir / "plain.exr";
  render("--color uniform", plain);
  // Widths as fractions of the 96-px height: 1.06, 2.02 and 3.07 px.
  for (const auto& [width, jump] : std::vector<std::pair<std::string, std::string>>{{"0.011", "2"}, {"0.021", "2"}, {"0.032", "0.75"}}) {
    const fs::path exr = dir / ("w" + width + ".exr");
    render("--color uniform --silhouettes --silhouette-width " + width + " --silhouette-depth-jump " + jump +
               " --silhouette-color 1,0,1", exr);
    const auto run = surftrace::test::runOracleScript("exr_silhouettes.py", {exr.string(), plain.string(), width, jump, "1,0,1"}, dir);
    EXPECT_TRUE(run.ok()) << run.describe() << run.out;
    EXPECT_NE(run.out.find("mismatches 0"), std::string::npos) << run.out;
    std::printf("width %s, jump %s: %s", width.c_str(), jump.c_str(), run.out.c_str());
    // The oracle can fail: lines at jumps below a larger threshold lie far from its edges.
    const auto other = surftrace::test::runOracleScript("exr_silhouettes.py", {exr.string(), plain.string(), width, "25", "1,0,1"}, dir);
    EXPECT_EQ(other.exitCode, 1) << other.out << other.err;
  }
}

// Creases on the SES of 1VIS at 512² and 50°: where the smooth surface curves fast they used to
// break into specks (175 pieces, median 3 px, 134 of them under 10 px; now 25 pieces, 6 under
// 10 px). Hysteresis and the minimum length leave long pieces. The line pixels (coverage >= ½)
// are recovered from the colour against the same render without lines, and their 8-connected
// pieces counted.
TEST(EffectsCli, CreasesOnTheSesLeaveNoSpecks) {
  const fs::path dir = scratch("specks");
  const fs::path plain = dir / "plain.exr", lined = dir / "lined.exr";
  const std::string base = "render " + kData + "/paper/1vis.pdb.gz --size 512x512 --quiet --color uniform ";
  ASSERT_EQ(runTool(base + "--exr " + plain.string()).status, 0);
  ASSERT_EQ(runTool(base + "--crease-angle 50 --silhouette-color 1,0,1 --exr " + lined.string()).status, 0);
  const view::FrameBuffers a = view::readExr(plain.string()), b = view::readExr(lined.string());
  ASSERT_EQ(a.pixels(), b.pixels());
  const int w = a.width, h = a.height;
  // Line colour 1,0,1 over grey: the green channel keeps (1 − coverage) of the plain one.
  std::vector<unsigned char> line(a.pixels(), 0);
  for (std::size_t p = 0; p < a.pixels(); ++p) {
    const float g = a.rgba[4 * p + 1];
    line[p] = g > 0.05f && 1.0f - b.rgba[4 * p + 1] / g >= 0.5f;
  }
  std::vector<int> sizes;
  std::vector<unsigned char> seen(line.size(), 0);
  for (std::size_t start = 0; start < line.size(); ++start) {
    if (!line[start] || seen[start]) continue;
    std::vector<std::size_t> stack{start};
    seen[start] = 1;
    int size = 0;
    while (!stack.empty()) {
      const std::size_t p = stack.back();
      stack.pop_back();
      ++size;
      const int x = static_cast<int>(p % static_cast<std::size_t>(w)), y = static_cast<int>(p / static_cast<std::size_t>(w));
      for (int qy = std::max(0, y - 1); qy <= std::min(h - 1, y + 1); ++qy)
        for (int qx = std::max(0, x - 1); qx <= std::min(w - 1, x + 1); ++qx) {
          const std::size_t q = static_cast<std::size_t>(qy) * static_cast<std::size_t>(w) + static_cast<std::size_t>(qx);
          if (line[q] && !seen[q]) seen[q] = 1, stack.push_back(q);
        }
    }
    sizes.push_back(size);
  }
  const auto small = std::count_if(sizes.begin(), sizes.end(), [](int s) { return s < 10; });
  const auto pixels = std::accumulate(sizes.begin(), sizes.end(), 0);
  std::printf("1VIS SES creases at 50°: %d line pixels in %zu pieces, %td under 10 px\n", pixels, sizes.size(), small);
  EXPECT_GT(pixels, 300) << "the creases are gone, not just their specks";
  EXPECT_LE(small, 8) << "pieces under 10 px";
}

// Each technique, and all together, drawn by both engines from their own buffers: the colours
// agree outside the silhouette band and the seams (compare --preset effects: colour p99 < 0.02).
TEST(EffectsCli, GlAgreesWithEmbreeForEachEffect) {
  const fs::path dir = scratch("engines");
  // The SES is smooth away from its seams: creases are shown on the vdW surface, where spheres meet.
  const std::vector<std::pair<std::string, std::string>> techniques = {
      {"silhouettes", "--silhouettes"},
      {"creases", "--surface vdw --crease-angle 50 --silhouette-width 0.0105"},
      {"darkening", "--depth-darkening --depth-darkening-sigma 0.04 --depth-darkening-strength 3"},
      {"cue", "--depth-cue"},
      {"all", "--silhouettes --crease-angle 60 --depth-darkening --depth-cue"}};
  const fs::path plainGl = dir / "plain_gl.exr", plainVdwGl = dir / "plain_vdw_gl.exr";
  render("--engine gl", plainGl);
  render("--engine gl --surface vdw", plainVdwGl);
  for (const auto& [name, args] : techniques) {
    const fs::path& plain = name == "creases" ? plainVdwGl : plainGl;
    const fs::path embree = dir / (name + "_embree.exr"), gl = dir / (name + "_gl.exr");
    render(args, embree);
    render(args + " --engine gl", gl);
    const Result c = runTool("compare " + gl.string() + " " + embree.string() + " --preset effects");
    EXPECT_EQ(c.status, 0) << name << ":\n" << c.output;
    std::printf("%s, GL vs Embree:\n%s", name.c_str(), c.output.c_str());
    // The check can fail: GL without the effect against Embree with it is refused for its
    // settings, and judged on its colour when they are set aside.
    const Result missing = runTool("compare " + plain.string() + " " + embree.string() + " --preset effects");
    EXPECT_EQ(missing.status, 1) << name << " (GL without the effect passed):\n" << missing.output;
    EXPECT_NE(missing.output.find("effects: test none, reference {"), std::string::npos) << missing.output;
    const Result ignored = runTool("compare " + plain.string() + " " + embree.string() +
                                   " --preset effects --ignore-settings --max-color-p99 0.02");
    EXPECT_EQ(ignored.status, 2) << name << " (GL without the effect passed):\n" << ignored.output;
    EXPECT_NE(ignored.output.find("colour p99"), std::string::npos) << ignored.output;
  }
}

// Transparency: GL's depth peeling against Embree's exact layers (compare --preset transparency:
// colour p99 < 1e-3) on the SES, the skin and the vdW balls at two opacities; an image with the
// wrong opacity fails the same check.
TEST(EffectsCli, GlPeelsTheLayersEmbreeComposites) {
  const fs::path dir = scratch("transparency");
  const std::vector<std::pair<std::string, std::string>> surfaces = {
      {"ses", kCrambin},
      {"skin", kData + "/small/1grm_single.pdb --surface mss --shrink 0.5"},
      {"vdw", kCrambin + " --surface vdw"}};
  for (const auto& [name, input] : surfaces)
    for (const std::string opacity : {"0.4", "0.7"}) {
      const fs::path embree = dir / (name + opacity + "_embree.exr"), gl = dir / (name + opacity + "_gl.exr");
      const std::string args = " --size 96x96 --quiet --opacity " + opacity;
      ASSERT_EQ(runTool("render " + input + args + " --exr " + embree.string()).status, 0);
      const Result r = runTool("render " + input + args + " --engine gl --exr " + gl.string());
      ASSERT_EQ(r.status, 0) << r.output;
      const Result c = runTool("compare " + gl.string() + " " + embree.string() + " --preset transparency");
      EXPECT_EQ(c.status, 0) << name << " " << opacity << ":\n" << c.output;
      std::printf("%s at opacity %s, GL vs Embree:\n%s", name.c_str(), opacity.c_str(), c.output.c_str());
    }
  const fs::path other = dir / "ses0.4_other_gl.exr";
  ASSERT_EQ(runTool("render " + kCrambin + " --size 96x96 --quiet --opacity 0.5 --engine gl --exr " + other.string()).status, 0);
  const std::string embree = (dir / "ses0.4_embree.exr").string();
  const Result wrong = runTool("compare " + other.string() + " " + embree + " --preset transparency");
  EXPECT_EQ(wrong.status, 1) << wrong.output;
  EXPECT_NE(wrong.output.find("opacity: test 0.5 (16 layers), reference 0.4 (16 layers)"), std::string::npos) << wrong.output;
  const Result ignored = runTool("compare " + other.string() + " " + embree + " --preset transparency --ignore-settings "
                                 "--max-color-p99 1e-3");
  EXPECT_EQ(ignored.status, 2) << ignored.output;
  EXPECT_NE(ignored.output.find("colour p99"), std::string::npos) << ignored.output;
}

TEST(EffectsCli, EffectsAreRecordedAndOffMeansTheImageAsItWas) {
  const fs::path dir = scratch("off");
  const fs::path plain = dir / "plain.exr", tuned = dir / "tuned.exr", on = dir / "on.exr";
  render("", plain);
  // Every parameter changed, no effect switched on.
  render("--silhouette-width 0.04 --silhouette-color 1,0,0 --silhouette-depth-jump 0.5 --depth-darkening-sigma 0.02 "
         "--depth-darkening-strength 2 --depth-cue-strength 0.9 --depth-cue-start 1 --depth-cue-end 2",
         tuned);
  render("--silhouettes --depth-darkening --depth-cue --crease-angle 45", on);
  view::ImageMetadata plainMeta, tunedMeta, onMeta;
  const view::FrameBuffers a = view::readExr(plain.string(), &plainMeta);
  const view::FrameBuffers b = view::readExr(tuned.string(), &tunedMeta);
  const view::FrameBuffers c = view::readExr(on.string(), &onMeta);
  EXPECT_EQ(a.rgba, b.rgba);
  EXPECT_EQ(a.depth, b.depth);
  EXPECT_NE(a.rgba, c.rgba);
  EXPECT_EQ(a.depth, c.depth) << "effects change colour only";
  EXPECT_EQ(plainMeta.count("surftrace:effects"), 0u);
  EXPECT_EQ(tunedMeta.count("surftrace:effects"), 0u);
  ASSERT_EQ(onMeta.count("surftrace:effects"), 1u);
  const std::string& json = onMeta.at("surftrace:effects");
  for (const char* key : {"\"silhouettes\"", "\"depth_darkening\"", "\"sigma_image_height\":0.015", "\"depth_cue\"", "\"start\"",
                          "\"crease_angle_degrees\":45.0"})
    EXPECT_NE(json.find(key), std::string::npos) << key << " not in " << json;
}

TEST(EffectsCli, TrajectoryFramesGetTheEffects) {
  const fs::path dir = scratch("trajectory");
  const std::string psf = kData + "/trajectories/adk_dims/adk.psf.gz", dcd = kData + "/trajectories/adk_dims/adk_dims.dcd";
  const Result r = runTool("trajectory " + psf + " " + dcd + " --frames 0:1 --size 24x24 --quiet --silhouettes --silhouette-width 0.1 "
                           "--silhouette-color 1,0,1 --exr " + (dir / "%03d.exr").string());
  ASSERT_EQ(r.status, 0) << r.output;
  view::ImageMetadata meta;
  const view::FrameBuffers f = view::readExr((dir / "000.exr").string(), &meta);
  EXPECT_EQ(meta.count("surftrace:effects"), 1u);
  std::size_t lines = 0;
  for (std::size_t p = 0; p < f.pixels(); ++p) lines += f.rgba[4 * p] == 1.0f && f.rgba[4 * p + 1] == 0.0f && f.rgba[4 * p + 2] == 1.0f;
  EXPECT_GT(lines, 10u);
}

TEST(EffectsCli, BadEffectOptionsAreRefused) {
  const fs::path out = scratch("bad") / "x.png";
  for (const std::string args : {"--silhouette-width 0", "--silhouette-width 2", "--silhouette-color 2,0,0", "--depth-darkening-sigma 0",
                                 "--depth-cue-strength 1.5", "--depth-cue-start 10 --depth-cue-end 5",
                                 "--crease-angle 180"}) {
    const Result r = runTool("render " + kCrambin + " --size 8x8 --quiet " + args + " -o " + out.string());
    EXPECT_NE(r.status, 0) << args << ":\n" << r.output;
  }
}

}  // namespace
}  // namespace surftrace::tools::test

// Depth darkening and depth cueing sized in the image's terms, through `surftrace render` and
// `trajectory`: the same view at 512² and 2048² looks the same, 1AON's halo is grey as 1VIS's
// is, and every trajectory frame darkens against the camera's fixed far plane and depth range
// (recovered from each frame's own buffers). Oracles: box averages, luminance and a brute-force
// Gaussian over the EXR's buffers, written here without the filter's code.
#include <algorithm>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <string>
#include <vector>

#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

#include "run_tool.hpp"
#include "temp_dir.hpp"
#include "view/image_io.hpp"

namespace surftrace::tools::test {
namespace {

namespace fs = std::filesystem;

const std::string kData = SURFTRACE_TEST_DATA;

view::FrameBuffers render(const std::string& input, const std::string& args, const fs::path& exr,
                          view::ImageMetadata* meta = nullptr) {
  const Result r = runTool("render " + input + " --quiet " + args + " --exr " + exr.string());
  EXPECT_EQ(r.status, 0) << args << ":\n" << r.output;
  return view::readExr(exr.string(), meta);
}

std::size_t at(const view::FrameBuffers& f, int x, int y) {
  return static_cast<std::size_t>(y) * static_cast<std::size_t>(f.width) + static_cast<std::size_t>(x);
}

// Rec. 709 luminance of the linear colour.
double luminance(const view::FrameBuffers& f, std::size_t p) {
  return 0.2126 * f.rgba[4 * p] + 0.7152 * f.rgba[4 * p + 1] + 0.0722 * f.rgba[4 * p + 2];
}

// (a) The same view of 1CRN at 512² and at 2048², both with depth darkening and depth cueing,
// the 2048² box-averaged 4×4 to 512². Background pixels (all 16 samples and the 512² centre
// miss) hold the halo: max |Δ| over channels below 0.03 (measured 0.008; with σ in pixels and
// strength per Å as they once were, 0.21), mean below 0.001 (measured 0.0001; once 0.0056).
// Hit pixels differ by the renderer's own sampling (mean 0.014 with no effect at all), so they
// are held by their mean colour: within 0.001 per channel (measured 0.0002, as with no effect;
// once 0.0023).
TEST(DepthEffectsCli, APreviewAndAFigureOfTheSameViewAgree) {
  const fs::path dir = ::surftrace::test::freshTempDir("depth_sizes");
  const std::string input = kData + "/structures/1crn.pdb", effects = "--depth-darkening --depth-cue --background 1,1,1";
  const view::FrameBuffers small = render(input, "--size 512x512 " + effects, dir / "512.exr");
  const view::FrameBuffers large = render(input, "--size 2048x2048 " + effects, dir / "2048.exr");
  ASSERT_EQ(small.width, 512);
  ASSERT_EQ(large.width, 2048);
  double worst = 0, sum = 0;
  std::size_t background = 0, hitsSmall = 0, hitsLarge = 0;
  double meanSmall[3] = {0, 0, 0}, meanLarge[3] = {0, 0, 0};
  for (int y = 0; y < 512; ++y)
    for (int x = 0; x < 512; ++x) {
      const std::size_t p = at(small, x, y);
      bool allMiss = small.kind[p] == 0;
      double box[3] = {0, 0, 0};
      for (int j = 0; j < 4; ++j)
        for (int i = 0; i < 4; ++i) {
          const std::size_t q = at(large, 4 * x + i, 4 * y + j);
          allMiss = allMiss && large.kind[q] == 0;
          for (int c = 0; c < 3; ++c) box[c] += large.rgba[4 * q + c] / 16.0;
        }
      if (!allMiss) continue;
      double d = 0;
      for (int c = 0; c < 3; ++c) d = std::max(d, std::abs(box[c] - small.rgba[4 * p + c]));
      worst = std::max(worst, d);
      sum += d;
      ++background;
    }
  for (std::size_t p = 0; p < small.pixels(); ++p)
    if (small.kind[p] != 0) {
      ++hitsSmall;
      for (int c = 0; c < 3; ++c) meanSmall[c] += small.rgba[4 * p + c];
    }
  for (std::size_t p = 0; p < large.pixels(); ++p)
    if (large.kind[p] != 0) {
      ++hitsLarge;
      for (int c = 0; c < 3; ++c) meanLarge[c] += large.rgba[4 * p + c];
    }
  ASSERT_GT(background, 100000u);
  std::printf("background: max %.4f mean %.5f over %zu pixels\n", worst, sum / background, background);
  EXPECT_LT(worst, 0.03);
  EXPECT_LT(sum / background, 0.001);
  for (int c = 0; c < 3; ++c) {
    const double a = meanSmall[c] / hitsSmall, b = meanLarge[c] / hitsLarge;
    std::printf("hits, channel %d: mean %.5f at 512², %.5f at 2048²\n", c, a, b);
    EXPECT_LT(std::abs(a - b), 0.001) << "channel " << c;
  }
}

// The background pixels within 4 px (Euclidean, pixel centres) of a hit, and their luminance.
struct Halo {
  std::size_t pixels = 0, dark = 0;  // dark: luminance < 0.2
  double meanLuminance = 0;
};
Halo halo(const view::FrameBuffers& f) {
  Halo h;
  for (int y = 0; y < f.height; ++y)
    for (int x = 0; x < f.width; ++x) {
      const std::size_t p = at(f, x, y);
      if (f.kind[p] != 0) continue;
      bool near = false;
      for (int dy = -4; dy <= 4 && !near; ++dy)
        for (int dx = -4; dx <= 4 && !near; ++dx) {
          const int qx = x + dx, qy = y + dy;
          near = dx * dx + dy * dy <= 16 && qx >= 0 && qy >= 0 && qx < f.width && qy < f.height && f.kind[at(f, qx, qy)] != 0;
        }
      if (!near) continue;
      const double l = luminance(f, p);
      ++h.pixels;
      h.dark += l < 0.2;
      h.meanLuminance += l;
    }
  h.meanLuminance /= static_cast<double>(std::max<std::size_t>(1, h.pixels));
  return h;
}

// (b) 1AON's halo is not solid black: of the background within 4 px of the molecule, below 5 %
// has luminance < 0.2 (measured 0 %; with the strength once in colour per Å, 97.5 %), and it
// looks as 1VIS's: mean luminance within 0.15 of each other (measured 0.654 and 0.731; once 0.023
// and 0.608), on a white background at 512².
TEST(DepthEffectsCli, TheHaloOfALargeMoleculeIsGreyAsASmallOnes) {
  const fs::path dir = ::surftrace::test::freshTempDir("depth_halo");
  const std::string args = "--size 512x512 --depth-darkening --background 1,1,1";
  const Halo big = halo(render(kData + "/paper/1aon.pdb.gz", args, dir / "1aon.exr"));
  const Halo small = halo(render(kData + "/paper/1vis.pdb.gz", args, dir / "1vis.exr"));
  std::printf("1AON: %zu halo pixels, %.4f dark, mean luminance %.3f; 1VIS: %zu, %.4f, %.3f\n", big.pixels,
              static_cast<double>(big.dark) / big.pixels, big.meanLuminance, small.pixels,
              static_cast<double>(small.dark) / small.pixels, small.meanLuminance);
  ASSERT_GT(big.pixels, 1000u);
  ASSERT_GT(small.pixels, 1000u);
  EXPECT_LT(static_cast<double>(big.dark) / big.pixels, 0.05);
  EXPECT_LT(std::abs(big.meanLuminance - small.meanLuminance), 0.15);
  EXPECT_LT(big.meanLuminance, 0.9) << "the halo must show";
}

// (c) Frames 47 and 48 of AdK, the pair whose halo flickered most when the background followed
// each frame's farthest hit. A missed pixel p is darkened to 1 + λ/R·ΔD with
// ΔD = S1 − B·S0 (S0: the Gaussian weight of the hits in its window, S1: their weighted depth,
// both over the weight inside the image), so the background depth B it was darkened against
// is (S1 − (colour − 1)·R/λ)/S0. Recovered from each frame's own buffers at every halo pixel
// with S0 >= 0.1, B is the camera's far plane in both frames (within 0.01 Å, measured 1.2e-4;
// the frames' farthest hits differ: once B, they moved the halo by up to 0.065), with R its
// near-to-far range, as the metadata says; depth cueing takes the same range.
TEST(DepthEffectsCli, TrajectoryFramesDarkenAgainstTheCamerasFixedFarPlane) {
  const fs::path dir = ::surftrace::test::freshTempDir("depth_trajectory");
  const std::string psf = kData + "/trajectories/adk_dims/adk.psf.gz", dcd = kData + "/trajectories/adk_dims/adk_dims.dcd";
  const Result r = runTool("trajectory " + psf + " " + dcd + " --frames 47:49 --size 256x256 --quiet --depth-darkening "
                           "--depth-cue --background 1,1,1 --exr " + (dir / "%03d.exr").string());
  ASSERT_EQ(r.status, 0) << r.output;
  double farthestHit[2] = {0, 0};
  for (int k = 0; k < 2; ++k) {
    view::ImageMetadata meta;
    const view::FrameBuffers f = view::readExr((dir / (k == 0 ? "047.exr" : "048.exr")).string(), &meta);
    const auto camera = nlohmann::json::parse(meta.at("surftrace:camera"));
    const auto dark = nlohmann::json::parse(meta.at("surftrace:effects")).at("depth_darkening");
    const double zNear = camera.at("near"), zFar = camera.at("far"), range = zFar - zNear;
    EXPECT_EQ(dark.value("background_depth", 0.0), zFar);
    EXPECT_EQ(dark.value("range", 0.0), range);
    // Depth cueing fades hits only, over the same fixed range.
    const auto cue = nlohmann::json::parse(meta.at("surftrace:effects")).at("depth_cue");
    EXPECT_EQ(cue.at("start").get<double>(), zNear);
    EXPECT_EQ(cue.at("end").get<double>(), zFar);
    const double lambda = dark.at("strength"), sigma = 0.015 * f.height;
    const int radius = static_cast<int>(std::ceil(3.0 * sigma));
    std::vector<double> g(static_cast<std::size_t>(radius) + 1);
    for (int i = 0; i <= radius; ++i) g[static_cast<std::size_t>(i)] = std::exp(-0.5 * i * i / (sigma * sigma));
    std::size_t used = 0;
    double worst = 0;
    for (std::size_t p = 0; p < f.pixels(); ++p)
      if (f.kind[p] != 0) farthestHit[k] = std::max(farthestHit[k], double{f.viewZ[p]});
    for (int y = 0; y < f.height; ++y)
      for (int x = 0; x < f.width; ++x) {
        const std::size_t p = at(f, x, y);
        if (f.kind[p] != 0 || f.rgba[4 * p] <= 0.0f) continue;
        double all = 0, s0 = 0, s1 = 0;
        for (int qy = std::max(0, y - radius); qy <= std::min(f.height - 1, y + radius); ++qy)
          for (int qx = std::max(0, x - radius); qx <= std::min(f.width - 1, x + radius); ++qx) {
            const double w = g[static_cast<std::size_t>(std::abs(qx - x))] * g[static_cast<std::size_t>(std::abs(qy - y))];
            all += w;
            if (f.kind[at(f, qx, qy)] != 0) s0 += w, s1 += w * f.viewZ[at(f, qx, qy)];
          }
        s0 /= all, s1 /= all;
        if (s0 < 0.1) continue;
        const double b = (s1 - (f.rgba[4 * p] - 1.0) * range / lambda) / s0;
        worst = std::max(worst, std::abs(b - zFar));
        ++used;
      }
    std::printf("frame %d: background depth recovered at %zu pixels, at most %.2e Å from the far plane %.3f "
                "(farthest hit %.3f)\n", 47 + k, used, worst, zFar, farthestHit[k]);
    EXPECT_GT(used, 200u);
    EXPECT_LT(worst, 0.01);
  }
  EXPECT_NE(farthestHit[0], farthestHit[1]) << "the frames must differ where the old background depth came from";
}

// σ was once given in pixels: such a value is refused and the error names the option that
// takes pixels now; that option and an explicit range work.
TEST(DepthEffectsCli, SigmaInPixelsIsRefusedWithTheOptionThatTakesIt) {
  const fs::path dir = ::surftrace::test::freshTempDir("depth_options");
  const std::string crambin = kData + "/structures/1crn.pdb --size 32x32 --quiet --depth-darkening ";
  const Result old = runTool("render " + crambin + "--depth-darkening-sigma 8 -o " + (dir / "a.png").string());
  EXPECT_NE(old.status, 0);
  EXPECT_NE(old.output.find("--depth-darkening-sigma-px 8"), std::string::npos) << old.output;
  EXPECT_FALSE(fs::exists(dir / "a.png"));
  const Result both = runTool("render " + crambin + "--depth-darkening-sigma 0.02 --depth-darkening-sigma-px 3 -o " +
                              (dir / "b.png").string());
  EXPECT_NE(both.status, 0) << both.output;
  view::ImageMetadata meta;
  render(kData + "/structures/1crn.pdb", "--size 32x32 --depth-darkening --depth-darkening-sigma-px 3 "
         "--depth-darkening-range 5", dir / "c.exr", &meta);
  const auto dark = nlohmann::json::parse(meta.at("surftrace:effects")).at("depth_darkening");
  EXPECT_EQ(dark.at("sigma_px").get<double>(), 3.0);
  EXPECT_EQ(dark.at("range").get<double>(), 5.0);
  EXPECT_FALSE(dark.contains("sigma_image_height"));
}

}  // namespace
}  // namespace surftrace::tools::test

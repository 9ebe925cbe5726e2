// The image-space effects on synthetic buffers against their definitions evaluated by brute force.
#include "view/image_effects.hpp"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <random>

#include <gtest/gtest.h>

namespace surftrace::view {
namespace {

constexpr double kPi = 3.14159265358979323846;

std::size_t at(const FrameBuffers& f, int x, int y) {
  return static_cast<std::size_t>(y) * static_cast<std::size_t>(f.width) + static_cast<std::size_t>(x);
}

// An orthographic view of spheres (one pixel = 1 Å): the nearest sphere's depth and normal,
// misses elsewhere; colour a flat grey.
struct Ball {
  double cx, cy, cz, r;
};
FrameBuffers ballsFrame(int w, int h, const std::vector<Ball>& balls) {
  FrameBuffers f;
  f.reset(w, h);
  for (int y = 0; y < h; ++y)
    for (int x = 0; x < w; ++x) {
      const std::size_t p = at(f, x, y);
      for (int c = 0; c < 3; ++c) f.rgba[4 * p + c] = 0.7f;
      f.rgba[4 * p + 3] = 1.0f;
      for (const Ball& b : balls) {
        const double dx = x + 0.5 - b.cx, dy = y + 0.5 - b.cy, d2 = b.r * b.r - dx * dx - dy * dy;
        if (d2 < 0) continue;
        const double z = b.cz - std::sqrt(d2);
        if (f.kind[p] != 0 && f.viewZ[p] <= z) continue;
        f.kind[p] = 1;
        f.viewZ[p] = f.depth[p] = static_cast<float>(z);
        f.normal[3 * p] = static_cast<float>(dx / b.r);
        f.normal[3 * p + 1] = static_cast<float>(dy / b.r);
        f.normal[3 * p + 2] = static_cast<float>((z - b.cz) / b.r);
      }
      if (f.kind[p] == 0)
        for (int c = 0; c < 3; ++c) f.rgba[4 * p + c] = 1.0f;
    }
  return f;
}

// Two overlapping spheres: an outline against the background and a depth jump between them.
FrameBuffers twoBalls() { return ballsFrame(64, 48, {{24, 24, 100, 14}, {40, 22, 80, 11}}); }

// The definition, pixel by pixel over the whole window.
bool bruteSilhouette(const FrameBuffers& f, int x, int y, int width, double jump) {
  const std::size_t p = at(f, x, y);
  if (f.kind[p] == 0) return false;
  for (int qy = y - width; qy <= y + width; ++qy)
    for (int qx = x - width; qx <= x + width; ++qx) {
      if (qx < 0 || qy < 0 || qx >= f.width || qy >= f.height) continue;
      const std::size_t q = at(f, qx, qy);
      if (f.kind[q] == 0 || static_cast<double>(f.viewZ[q]) - static_cast<double>(f.viewZ[p]) > jump) return true;
    }
  return false;
}

TEST(ImageEffects, SilhouettesAreTheDepthJumpsOfTheDefinition) {
  const FrameBuffers f = twoBalls();
  for (int width : {1, 2, 3})
    for (double jump : {0.5, 2.0, 8.0}) {
      const auto mask = silhouetteMask(f, width, jump);
      std::size_t lines = 0, inner = 0;
      for (int y = 0; y < f.height; ++y)
        for (int x = 0; x < f.width; ++x) {
          const bool want = bruteSilhouette(f, x, y, width, jump);
          ASSERT_EQ(mask[at(f, x, y)] != 0, want) << "pixel " << x << "," << y << " width " << width << " jump " << jump;
          lines += want;
          // A line between the balls, not at the outline: the near ball's pixels over the far one.
          bool nearMiss = false;
          for (int qy = std::max(0, y - width); qy <= std::min(f.height - 1, y + width); ++qy)
            for (int qx = std::max(0, x - width); qx <= std::min(f.width - 1, x + width); ++qx)
              nearMiss = nearMiss || f.kind[at(f, qx, qy)] == 0;
          inner += want && !nearMiss;
        }
      EXPECT_GT(lines, 0u);
      EXPECT_GT(inner, 0u) << "no silhouette where the near ball covers the far one (width " << width << ")";
    }
}

TEST(ImageEffects, ASmoothSurfaceHasNoInnerSilhouetteOrCrease) {
  const FrameBuffers f = ballsFrame(48, 48, {{24, 24, 100, 30}});  // the ball fills the image
  const auto s = silhouetteMask(f, 2, 2.0);
  const auto c = creaseMask(f, 2, 2.0, 60.0);
  // Near the ball's rim the depth changes by more than the jump within 2 px: those pixels are
  // silhouettes; away from it nothing is.
  for (int y = 0; y < f.height; ++y)
    for (int x = 0; x < f.width; ++x) {
      const double dx = x + 0.5 - 24, dy = y + 0.5 - 24;
      if (dx * dx + dy * dy < 16 * 16) {  // slope below 0.7: under 2 Å within 2 px
        EXPECT_EQ(s[at(f, x, y)], 0) << x << "," << y;
        EXPECT_EQ(c[at(f, x, y)], 0) << x << "," << y;
      }
    }
}

// Where two balls of equal depth intersect, their normals meet at an angle: a crease.
TEST(ImageEffects, CreasesAreWhereNormalsTurnOnOneSurface) {
  const FrameBuffers f = ballsFrame(64, 48, {{24, 24, 100, 14}, {40, 24, 100, 14}});
  const double angle = 40.0;
  const auto c = creaseMask(f, 1, 2.0, angle);
  const double cosLimit = std::cos(angle * kPi / 180.0);
  std::size_t creases = 0;
  for (int y = 0; y < f.height; ++y)
    for (int x = 0; x < f.width; ++x) {
      const std::size_t p = at(f, x, y);
      bool want = false, nearLimit = false;
      if (f.kind[p] != 0)
        for (int qy = std::max(0, y - 1); qy <= std::min(f.height - 1, y + 1); ++qy)
          for (int qx = std::max(0, x - 1); qx <= std::min(f.width - 1, x + 1); ++qx) {
            const std::size_t q = at(f, qx, qy);
            if (f.kind[q] == 0 || std::abs(static_cast<double>(f.viewZ[q]) - f.viewZ[p]) > 2.0) continue;
            double dot = 0;
            for (int k = 0; k < 3; ++k) dot += static_cast<double>(f.normal[3 * p + k]) * f.normal[3 * q + k];
            want = want || dot < cosLimit;
            nearLimit = nearLimit || std::abs(dot - cosLimit) < 1e-5;
          }
      // float against double dot products: skip the pixels within rounding of the limit.
      if (!nearLimit) {
        EXPECT_EQ(c[p] != 0, want) << x << "," << y;
      }
      creases += want;
      if (want) {
        EXPECT_NEAR(x + 0.5, 32.0, 3.0) << "crease away from the seam at x = 32";
      }
    }
  EXPECT_GT(creases, 0u);
  // Angle 0 draws none.
  const auto none = creaseMask(f, 1, 2.0, 0.0);
  EXPECT_EQ(std::count(none.begin(), none.end(), 1), 0);
}

// ΔD = G∗D − D by the 2-D definition, O(N·k²): the Gaussian over the (2r+1)² window, averaged
// over the pixels in the image, misses at depth `far`.
double bruteDelta(const FrameBuffers& f, int x, int y, double sigma, double far) {
  auto depth = [&](int px, int py) { return f.kind[at(f, px, py)] != 0 ? static_cast<double>(f.viewZ[at(f, px, py)]) : far; };
  const int r = std::max(1, static_cast<int>(std::ceil(3.0 * sigma)));
  double num = 0, den = 0;
  for (int qy = y - r; qy <= y + r; ++qy)
    for (int qx = x - r; qx <= x + r; ++qx) {
      if (qx < 0 || qy < 0 || qx >= f.width || qy >= f.height) continue;
      const double g = std::exp(-((qx - x) * (qx - x) + (qy - y) * (qy - y)) / (2 * sigma * sigma));
      num += g * depth(qx, qy);
      den += g;
    }
  return num / den - depth(x, y);
}

TEST(ImageEffects, DepthUnsharpMaskMatchesTheTwoDimensionalConvolution) {
  const FrameBuffers f = twoBalls();
  for (double sigma : {0.7, 2.0, 4.5}) {
    const std::vector<float> delta = depthUnsharpMask(f, sigma, 120.0);
    double worst = 0;
    std::size_t negative = 0;
    for (int y = 0; y < f.height; ++y)
      for (int x = 0; x < f.width; ++x) {
        const std::size_t p = at(f, x, y);
        const double want = bruteDelta(f, x, y, sigma, 120.0);
        worst = std::max(worst, std::abs(delta[p] - want));
        negative += f.kind[p] != 0 && want < -0.1;
      }
    EXPECT_LT(worst, 1e-4) << "sigma " << sigma << " (depths up to 100 Å, float accumulation)";
    EXPECT_GT(negative, 0u) << "the far ball next to the near one must lie behind its surroundings";
  }
}

// The nearest and farthest hits of a frame, by a plain loop.
void hitRange(const FrameBuffers& f, double& nearest, double& farthest) {
  nearest = HUGE_VAL, farthest = -HUGE_VAL;
  for (std::size_t p = 0; p < f.pixels(); ++p)
    if (f.kind[p] != 0) nearest = std::min(nearest, double{f.viewZ[p]}), farthest = std::max(farthest, double{f.viewZ[p]});
}

// colour + λ·ΔD/R where ΔD < 0, ΔD by the 2-D definition with misses at `far`.
void expectDarkening(const FrameBuffers& before, const FrameBuffers& after, double sigma, double far, double lambda,
                     double range) {
  std::size_t darkened = 0;
  for (int y = 0; y < before.height; ++y)
    for (int x = 0; x < before.width; ++x) {
      const std::size_t p = at(before, x, y);
      const double want = bruteDelta(before, x, y, sigma, far);
      for (int c = 0; c < 4; ++c) {
        const double expected =
            c < 3 && want < 0 ? std::max(0.0, before.rgba[4 * p + c] + lambda * want / range) : before.rgba[4 * p + c];
        ASSERT_NEAR(after.rgba[4 * p + c], expected, 1e-5) << x << "," << y << " channel " << c << " ΔD " << want;
        if (want >= 1e-4) {
          ASSERT_EQ(after.rgba[4 * p + c], before.rgba[4 * p + c]) << "brightened or darkened at ΔD > 0";
        }
      }
      darkened += after.rgba[4 * p] < before.rgba[4 * p];
    }
  EXPECT_GT(darkened, 20u);
}

// Without a camera depth range: misses at the farthest hit, ΔD over the hits' depth range.
TEST(ImageEffects, DepthDarkeningDarkensOnlyWhereTheMaskIsNegative) {
  FrameBuffers f = twoBalls();
  const FrameBuffers before = f;
  ImageEffects e;
  e.depthDarkening = true;
  e.darkeningSigmaPx = 3.0;
  e.darkeningStrength = 2.0;
  applyImageEffects(f, e, Camera{}, glm::vec3(1.0f));
  double nearest = 0, farthest = 0;
  hitRange(before, nearest, farthest);
  expectDarkening(before, f, 3.0, farthest, 2.0, farthest - nearest);
  // An explicit range R in Å in place of the hits'.
  f = before;
  e.darkeningRange = 1.0;
  e.darkeningStrength = 0.05;
  applyImageEffects(f, e, Camera{}, glm::vec3(1.0f));
  expectDarkening(before, f, 3.0, farthest, 0.05, 1.0);
}

// With a camera depth range (a trajectory's, fixed for every frame): misses at its far plane,
// ΔD over zFar − zNear, and σ a fraction of the image height; a ball that comes or goes far
// from a pixel leaves that pixel's darkening as it was (it moved the farthest hit before).
TEST(ImageEffects, DepthDarkeningTakesTheCamerasDepthRangeNotTheFramesHits) {
  Camera camera;
  camera.width = 64, camera.height = 48;
  camera.zNear = 60.0, camera.zFar = 140.0;
  FrameBuffers f = twoBalls();
  const FrameBuffers before = f;
  ImageEffects e;
  e.depthDarkening = true;
  e.darkeningSigma = 0.0625;  // 3 px of 48
  applyImageEffects(f, e, camera, glm::vec3(1.0f));
  expectDarkening(before, f, 3.0, 140.0, 1.0, 80.0);
  // The same balls and one more, deep, in the corner (the farthest hit moves from 100 to 130 Å).
  FrameBuffers more = ballsFrame(64, 48, {{24, 24, 100, 14}, {40, 22, 80, 11}, {60, 44, 133, 3}});
  applyImageEffects(more, e, camera, glm::vec3(1.0f));
  std::size_t compared = 0;
  for (int y = 0; y < f.height; ++y)
    for (int x = 0; x < f.width; ++x) {
      // The ball and the Gaussian's square window of half-width 3σ.
      if (std::max(std::abs(x + 0.5 - 60), std::abs(y + 0.5 - 44)) < 3 + 9 + 1) continue;
      const std::size_t p = at(f, x, y);
      for (int c = 0; c < 3; ++c) ASSERT_EQ(more.rgba[4 * p + c], f.rgba[4 * p + c]) << x << "," << y;
      compared += f.kind[p] == 0 && f.rgba[4 * p] < 1.0f;
    }
  EXPECT_GT(compared, 100u) << "halo pixels compared";
}

// The same scene drawn at 1× and 4× the pixels (one pixel = 1 Å at 1×, 1/4 Å at 4×): with σ a
// fraction of the image height and ΔD over the depth range, the 4× image box-averaged to 1×
// is the 1× image but for sampling: mean |Δcolour| below 0.004 (measured 0.0014; with σ in
// pixels and λ per Å as they once were, 2.4 px and 0.03/Å, 0.035).
TEST(ImageEffects, DepthDarkeningLooksTheSameAtAnyImageSize) {
  auto render = [](int scale) {
    const double s = scale;
    FrameBuffers f = ballsFrame(64 * scale, 48 * scale, {{24 * s, 24 * s, 100 * s, 14 * s}, {40 * s, 22 * s, 80 * s, 11 * s},
                                                         {10 * s, 38 * s, 95 * s, 6 * s}});
    Camera camera;
    camera.width = f.width, camera.height = f.height;
    camera.zNear = 60.0 * s, camera.zFar = 120.0 * s;
    ImageEffects e;
    e.depthDarkening = true;
    e.darkeningSigma = 0.05;  // 2.4 px at 1×, 9.6 px at 4×
    applyImageEffects(f, e, camera, glm::vec3(1.0f));
    return f;
  };
  const FrameBuffers small = render(1), large = render(4);
  double sum = 0, darkest = 1;
  for (int y = 0; y < small.height; ++y)
    for (int x = 0; x < small.width; ++x) {
      double mean = 0;
      for (int j = 0; j < 4; ++j)
        for (int i = 0; i < 4; ++i) mean += large.rgba[4 * at(large, 4 * x + i, 4 * y + j)] / 16.0;
      sum += std::abs(mean - small.rgba[4 * at(small, x, y)]);
      darkest = std::min(darkest, double{small.rgba[4 * at(small, x, y)]});
    }
  const double meanDifference = sum / static_cast<double>(small.pixels());
  std::printf("mean |colour(1x) - box(colour(4x))| = %.5f, darkest %.3f\n", meanDifference, darkest);
  EXPECT_LT(meanDifference, 0.004);
  EXPECT_LT(darkest, 0.6) << "the darkening must show";
}

TEST(ImageEffects, DepthDarkeningLeavesAFlatBufferAlone) {
  FrameBuffers f = ballsFrame(40, 30, {});
  for (std::size_t p = 0; p < f.pixels(); ++p) {
    f.kind[p] = 1;
    f.viewZ[p] = f.depth[p] = 37.25f;
    f.normal[3 * p + 2] = -1.0f;
  }
  const FrameBuffers before = f;
  ImageEffects e;
  e.depthDarkening = true;
  e.darkeningStrength = 10.0;
  applyImageEffects(f, e, Camera{}, glm::vec3(1.0f));
  const std::vector<float> delta = depthUnsharpMask(before, e.darkeningSigmaPixels(f.height), 50.0);
  for (float d : delta) ASSERT_EQ(d, 0.0f);
  EXPECT_EQ(f.rgba, before.rgba);
}

TEST(ImageEffects, DepthCueBlendsTowardsTheBackgroundWithDepth) {
  FrameBuffers f = twoBalls();
  const FrameBuffers before = f;
  ImageEffects e;
  e.depthCue = true;
  e.depthCueStrength = 0.5;
  e.depthCueStart = 80.0;
  e.depthCueEnd = 100.0;
  const glm::vec3 background(0.0f, 0.0f, 1.0f);
  applyImageEffects(f, e, Camera{}, background);
  for (std::size_t p = 0; p < f.pixels(); ++p) {
    const double fog = f.kind[p] != 0 ? 0.5 * std::clamp((f.viewZ[p] - 80.0) / 20.0, 0.0, 1.0) : 0.0;
    for (int c = 0; c < 3; ++c)
      ASSERT_NEAR(f.rgba[4 * p + c], (1 - fog) * before.rgba[4 * p + c] + fog * background[c], 1e-6) << p;
  }
}

TEST(ImageEffects, LinesTakeTheirColourAndNoEffectLeavesTheFrameAlone) {
  FrameBuffers f = twoBalls();
  const FrameBuffers before = f;
  applyImageEffects(f, ImageEffects{}, Camera{}, glm::vec3(1.0f));
  EXPECT_EQ(f.rgba, before.rgba);
  ImageEffects e;
  e.silhouettes = true;
  e.lineColor = {0.2f, 0.4f, 0.6f};
  applyImageEffects(f, e, Camera{}, glm::vec3(1.0f));
  const auto mask = silhouetteMask(before, e.lineWidth, e.silhouetteJump);
  for (std::size_t p = 0; p < f.pixels(); ++p) {
    const bool line = f.rgba[4 * p] == 0.2f && f.rgba[4 * p + 1] == 0.4f && f.rgba[4 * p + 2] == 0.6f;
    ASSERT_EQ(line, mask[p] != 0) << p;
    if (!line) {
      for (int c = 0; c < 4; ++c) ASSERT_EQ(f.rgba[4 * p + c], before.rgba[4 * p + c]);
    }
  }
}

TEST(ImageEffects, ValidateNamesTheBadParameter) {
  ImageEffects e;
  e.lineWidth = 0;
  EXPECT_THROW(e.validate(), std::invalid_argument);
  e = {};
  e.darkeningSigma = 0;
  EXPECT_THROW(e.validate(), std::invalid_argument);
  e = {};
  e.darkeningSigma = 8;  // pixels, as σ once was: refused, not read as 8 image heights
  EXPECT_THROW(e.validate(), std::invalid_argument);
  e = {};
  e.darkeningSigmaPx = 0;
  EXPECT_THROW(e.validate(), std::invalid_argument);
  e = {};
  e.darkeningRange = 0;
  EXPECT_THROW(e.validate(), std::invalid_argument);
  e = {};
  e.depthCueStart = 5.0;
  e.depthCueEnd = 5.0;
  EXPECT_THROW(e.validate(), std::invalid_argument);
  EXPECT_NO_THROW(ImageEffects{}.validate());
}

}  // namespace
}  // namespace surftrace::view

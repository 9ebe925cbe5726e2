// The image-space effects on synthetic buffers against their definitions evaluated by brute force.
#include "view/image_effects.hpp"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <random>

#include <glm/geometric.hpp>
#include <gtest/gtest.h>

#include "oracles/srgb.hpp"

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

// A plane facing the eye at view depth z covering the whole image (colour that of ballsFrame's
// misses).
FrameBuffers flatFrame(int w, int h, float z) {
  FrameBuffers f = ballsFrame(w, h, {});
  for (std::size_t p = 0; p < f.pixels(); ++p) {
    f.kind[p] = 1;
    f.viewZ[p] = f.depth[p] = z;
    f.normal[3 * p + 2] = -1.0f;
  }
  return f;
}

// Two overlapping spheres: an outline against the background and a depth jump between them.
FrameBuffers twoBalls() { return ballsFrame(64, 48, {{24, 24, 100, 14}, {40, 22, 80, 11}}); }

// Balls seen through a real camera: each pixel-centre ray against every ball exactly (the
// nearest root), so that depth, normal and ray agree as an engine's buffers do.
FrameBuffers cameraFrame(const Camera& camera, const std::vector<Ball>& balls) {
  FrameBuffers f;
  f.reset(camera.width, camera.height);
  const glm::dvec3 forward = camera.forward();
  for (int y = 0; y < f.height; ++y)
    for (int x = 0; x < f.width; ++x) {
      const std::size_t p = at(f, x, y);
      for (int c = 0; c < 3; ++c) f.rgba[4 * p + c] = 1.0f;
      f.rgba[4 * p + 3] = 1.0f;
      const Ray ray = camera.ray(x + 0.5, y + 0.5);
      double best = HUGE_VAL;
      for (std::size_t i = 0; i < balls.size(); ++i) {
        const Ball& b = balls[i];
        const glm::dvec3 c(b.cx, b.cy, b.cz), oc = c - ray.org;
        const double along = glm::dot(oc, ray.dir), h2 = glm::dot(oc, oc) - along * along, d2 = b.r * b.r - h2;
        if (d2 < 0) continue;
        const double t = along - std::sqrt(d2);
        if (t <= 0 || t >= best) continue;
        best = t;
        const glm::dvec3 n = (ray.org + t * ray.dir - c) / b.r;
        f.kind[p] = 1;
        f.patchId[p] = static_cast<std::uint32_t>(i);
        f.depth[p] = static_cast<float>(t);
        f.viewZ[p] = static_cast<float>(t * glm::dot(ray.dir, forward));
        for (int k = 0; k < 3; ++k) f.normal[3 * p + k] = static_cast<float>(n[k]);
        for (int k = 0; k < 3; ++k) f.rgba[4 * p + k] = 0.7f;
      }
    }
  return f;
}

// An orthographic camera looking down −z with `span` Å over the image height; the image
// centre at world (cx, cy), image x = world x, image y = −world y.
Camera orthoCamera(int width, int height, double span, double cx = 0.0, double cy = 0.0) {
  Camera c;
  c.projection = Projection::Orthographic;
  c.eye = {cx, cy, 100.0};
  c.lookAt = {cx, cy, 0.0};
  c.up = {0.0, 1.0, 0.0};
  c.orthoHeight = span;
  c.width = width;
  c.height = height;
  return c;
}

// The exact coverage of a pixel by the band of width w (px) inside the outline of one disc of
// radius R (px) centred at image point (cx, cy): the share of a 32 × 32 grid of points in the
// pixel with R − w <= |point − centre| <= R.
double bandCoverage(int x, int y, double cx, double cy, double R, double w) {
  constexpr int kGrid = 32;
  int in = 0;
  for (int j = 0; j < kGrid; ++j)
    for (int i = 0; i < kGrid; ++i) {
      const double rho = std::hypot(x + (i + 0.5) / kGrid - cx, y + (j + 0.5) / kGrid - cy);
      in += rho <= R && rho >= R - w;
    }
  return static_cast<double>(in) / (kGrid * kGrid);
}

// Every hit pixel next to a depth jump (among its 8 neighbours a miss, or a pixel of another
// ball deeper by more than `jump`): the definition's edge pixels, by brute force from which
// ball each pixel sees (patchId), so that a ball's own steep rim is no jump.
std::vector<unsigned char> edgePixels(const FrameBuffers& f, double jump) {
  std::vector<unsigned char> edge(f.pixels(), 0);
  for (int y = 0; y < f.height; ++y)
    for (int x = 0; x < f.width; ++x) {
      const std::size_t p = at(f, x, y);
      if (f.kind[p] == 0) continue;
      for (int qy = std::max(0, y - 1); qy <= std::min(f.height - 1, y + 1); ++qy)
        for (int qx = std::max(0, x - 1); qx <= std::min(f.width - 1, x + 1); ++qx) {
          const std::size_t q = at(f, qx, qy);
          if (f.kind[q] == 0 ||
              (f.patchId[q] != f.patchId[p] && static_cast<double>(f.viewZ[q]) - static_cast<double>(f.viewZ[p]) > jump))
            edge[p] = 1;
        }
    }
  return edge;
}

// Two overlapping balls, the near one in front of the far one, seen in perspective and
// orthographically: every edge pixel of the definition is covered, at least half when the band
// is 2 px wide or more (the jump lies within √2 px of the edge pixel's centre), and no pixel
// farther than the band and 1.5 px from an edge pixel is covered at all.
TEST(ImageEffects, SilhouettesCoverEveryDepthJumpAndNothingFarFromOne) {
  Camera perspective;
  perspective.eye = {0.0, 0.0, 60.0};
  perspective.width = 96;
  perspective.height = 72;
  for (const Camera& camera : {perspective, orthoCamera(96, 72, 36.0)}) {
    const FrameBuffers f = cameraFrame(camera, {{-4, 0, 0, 10}, {7, 2, 6, 7}});
    for (double width : {1.0, 2.5, 4.0})
      for (double jump : {0.5, 2.0}) {
        const std::vector<float> cover = silhouetteCoverage(f, camera, width, jump);
        const std::vector<unsigned char> edge = edgePixels(f, jump);
        std::size_t edges = 0, inner = 0;
        for (int y = 0; y < f.height; ++y)
          for (int x = 0; x < f.width; ++x) {
            const std::size_t p = at(f, x, y);
            ASSERT_GE(cover[p], 0.0f);
            ASSERT_LE(cover[p], 1.0f);
            if (edge[p]) {
              ++edges;
              EXPECT_GE(cover[p], width >= 2.0 ? 0.5f : 0.01f) << "edge pixel " << x << "," << y << " width " << width << " jump " << jump;
              bool nearMiss = false;
              for (int qy = std::max(0, y - 1); qy <= std::min(f.height - 1, y + 1); ++qy)
                for (int qx = std::max(0, x - 1); qx <= std::min(f.width - 1, x + 1); ++qx) nearMiss |= f.kind[at(f, qx, qy)] == 0;
              inner += !nearMiss;
            }
            if (cover[p] > 0.0f) {
              double nearest = HUGE_VAL;
              for (int qy = 0; qy < f.height; ++qy)
                for (int qx = 0; qx < f.width; ++qx)
                  if (edge[at(f, qx, qy)]) nearest = std::min(nearest, std::hypot(qx - x, qy - y));
              EXPECT_LE(nearest, width + 1.5) << "line at " << x << "," << y << " far from every jump";
            }
          }
        EXPECT_GT(edges, 50u);
        EXPECT_GT(inner, 5u) << "no jump where the near ball covers the far one";
      }
  }
}

// One ball seen orthographically, its rim a circle of radius R px: each pixel's line coverage
// against the exact share of the pixel inside the band of width w along the rim (a 32 × 32 grid
// per pixel). The pixels along the rim take intermediate values, as the geometry does.
TEST(ImageEffects, SilhouetteCoverageIsThePixelsShareOfTheBand) {
  const double R = 23.3;  // px, 1 Å a pixel
  for (double w : {1.0, 1.7, 3.0})
    for (double shift : {0.3, 0.0}) {
      const Camera camera = orthoCamera(64, 64, 64.0);
      // Image point (32 + shift, 32) is world (shift, 0).
      const FrameBuffers f = cameraFrame(camera, {{shift, 0.0, 0.0, R}});
      const std::vector<float> cover = silhouetteCoverage(f, camera, w, 2.0);
      double sumError = 0, worst = 0;
      std::size_t counted = 0, intermediate = 0, wantIntermediate = 0;
      for (int y = 0; y < f.height; ++y)
        for (int x = 0; x < f.width; ++x) {
          const double want = bandCoverage(x, y, 32.0 + shift, 32.0, R, w), got = cover[at(f, x, y)];
          if (want == 0.0 && got == 0.0) continue;
          ++counted;
          sumError += std::abs(got - want);
          worst = std::max(worst, std::abs(got - want));
          intermediate += got > 0.05 && got < 0.95;
          wantIntermediate += want > 0.05 && want < 0.95;
        }
      std::printf("w %.1f shift %.1f: mean |error| %.4f, worst %.4f over %zu pixels; %zu partly covered (exact: %zu)\n",
                  w, shift, sumError / counted, worst, counted, intermediate, wantIntermediate);
      // The coverage treats the pixel as 1 px across the rim whatever the rim's slope: off by up
      // to ~0.2 where the rim runs diagonally through a pixel's corner.
      EXPECT_LT(sumError / counted, 0.06) << "w " << w << " shift " << shift;
      EXPECT_LT(worst, 0.3) << "w " << w << " shift " << shift;
      EXPECT_GT(intermediate, wantIntermediate / 2) << "w " << w << ": too few pixels partly covered";
    }
}

// A sub-pixel move of the camera moves the line by as much: along every row that crosses the
// ball's left rim steeply, the coverage-weighted centroid of the line moves as that of the exact
// coverage of the band does (itself the shift, give or take the box filter's ripple), not by 0
// or 1 px as a line of whole pixels does.
TEST(ImageEffects, SilhouetteMovesWithASubPixelShiftOfTheCamera) {
  const double R = 20.0, w = 2.0;
  auto rowCentroids = [&](double shift, bool exact) {
    // The camera moves left by `shift` Å = px: the ball moves right in the image.
    const Camera camera = orthoCamera(64, 64, 64.0, -shift, 0.0);
    const FrameBuffers f = cameraFrame(camera, {{0.0, 0.0, 0.0, R}});
    const std::vector<float> cover = silhouetteCoverage(f, camera, w, 2.0);
    std::vector<double> centroid;
    for (int y = 32 - 5; y < 32 + 5; ++y) {  // |dy| < R/4: the rim within 15° of vertical
      double sum = 0, moment = 0;
      for (int x = 0; x < 32; ++x) {
        const double c = exact ? bandCoverage(x, y, 32.0 + shift, 32.0, R, w) : cover[at(f, x, y)];
        sum += c, moment += (x + 0.5) * c;
      }
      centroid.push_back(moment / sum);
    }
    return centroid;
  };
  const std::vector<double> base = rowCentroids(0.0, false), exactBase = rowCentroids(0.0, true);
  for (double shift : {0.1, 0.25, 0.5, 0.75}) {
    const std::vector<double> moved = rowCentroids(shift, false), exactMoved = rowCentroids(shift, true);
    double worst = 0, worstFromShift = 0;
    for (std::size_t k = 0; k < base.size(); ++k) {
      worst = std::max(worst, std::abs((moved[k] - base[k]) - (exactMoved[k] - exactBase[k])));
      worstFromShift = std::max(worstFromShift, std::abs(moved[k] - base[k] - shift));
    }
    std::printf("shift %.2f px: row centroids move by the exact coverage's within %.4f px, by the shift within %.4f px\n",
                shift, worst, worstFromShift);
    EXPECT_LT(worst, 0.05) << "shift " << shift << " px: a row's line moved by another amount than the exact band";
    EXPECT_LT(worstFromShift, 0.1) << "shift " << shift << " px";
  }
}

// The same view at 512² and 2048², the larger box-downsampled by 4: the lines agree, because
// their width is a fraction of the image height.
TEST(ImageEffects, LinesLookTheSameAtEverySize) {
  const std::vector<Ball> balls = {{-30, 5, 0, 40}, {25, -20, 30, 28}, {35, 40, 10, 15}, {-20, -45, 0, 18}, {-2, -45, 0, 18}};
  ImageEffects e;
  e.lineWidth = 0.005;
  auto lines = [&](int size) {
    const Camera camera = orthoCamera(size, size, 200.0);
    const FrameBuffers f = cameraFrame(camera, balls);
    const double widthPx = lineWidthPixels(e, size);
    std::vector<float> s = silhouetteCoverage(f, camera, widthPx, e.silhouetteJump);
    std::vector<float> c = creaseCoverage(f, widthPx, e.silhouetteJump, 50.0, creaseMinLengthPixels(e, size));
    return std::pair(s, c);
  };
  const auto [small, smallCrease] = lines(512);
  const auto [large, largeCrease] = lines(2048);
  auto compare = [&](const std::vector<float>& a, const std::vector<float>& b, const char* what, double inkTolerance,
                     double tolerance) {
    double ink = 0, inkLarge = 0, sumError = 0;
    std::size_t counted = 0;
    for (int y = 0; y < 512; ++y)
      for (int x = 0; x < 512; ++x) {
        double down = 0;
        for (int j = 0; j < 4; ++j)
          for (int i = 0; i < 4; ++i) down += b[static_cast<std::size_t>(4 * y + j) * 2048 + static_cast<std::size_t>(4 * x + i)];
        down /= 16;
        const double here = a[static_cast<std::size_t>(y) * 512 + static_cast<std::size_t>(x)];
        ink += here, inkLarge += down;
        if (here > 0 || down > 0) ++counted, sumError += std::abs(here - down);
      }
    std::printf("%s: coverage sum 512² %.1f, 2048²/16 %.1f; mean |difference| %.4f over %zu pixels\n", what, ink,
                inkLarge, sumError / counted, counted);
    ASSERT_GT(ink, 100.0) << what;
    EXPECT_NEAR(inkLarge / ink, 1.0, inkTolerance) << what << ": total line coverage at 2048² / 512²";
    EXPECT_LT(sumError / counted, tolerance) << what << ": mean |difference| over the line pixels";
  };
  compare(small, large, "silhouettes", 0.05, 0.05);
  // A crease's band is whole pixels on either side of it (the window), so it is coarser at 512².
  compare(smallCrease, largeCrease, "creases", 0.3, 0.2);
}

TEST(ImageEffects, ASmoothSurfaceHasNoInnerSilhouetteOrCrease) {
  const Camera camera = orthoCamera(48, 48, 48.0);
  const FrameBuffers f = cameraFrame(camera, {{0, 0, 0, 40}});  // the ball fills the image
  const auto s = silhouetteCoverage(f, camera, 2.0, 2.0);
  const auto c = creaseCoverage(f, 2.0, 2.0, 60.0, 4.0);
  for (int y = 0; y < f.height; ++y)
    for (int x = 0; x < f.width; ++x) {
      EXPECT_EQ(s[at(f, x, y)], 0.0f) << x << "," << y;
      EXPECT_EQ(c[at(f, x, y)], 0.0f) << x << "," << y;
    }
}

// Where two balls of equal depth intersect, their normals meet at an angle: a crease along the
// seam, drawn in full where the turn within the window passes the angle.
TEST(ImageEffects, CreasesAreWhereNormalsTurnOnOneSurface) {
  const FrameBuffers f = ballsFrame(64, 48, {{24, 24, 100, 14}, {40, 24, 100, 14}});
  const double angle = 40.0;
  const auto c = creaseCoverage(f, 2.0, 2.0, angle, 4.0);
  const double cosLimit = std::cos(angle * kPi / 180.0);
  std::size_t creases = 0;
  for (int y = 0; y < f.height; ++y)
    for (int x = 0; x < f.width; ++x) {
      const std::size_t p = at(f, x, y);
      bool want = false, nearLimit = false;
      if (f.kind[p] != 0)
        for (int qy = std::max(0, y - 1); qy <= std::min(f.height - 1, y + 1); ++qy)  // radius round(2 / 2)
          for (int qx = std::max(0, x - 1); qx <= std::min(f.width - 1, x + 1); ++qx) {
            const std::size_t q = at(f, qx, qy);
            if (f.kind[q] == 0 || std::abs(static_cast<double>(f.viewZ[q]) - f.viewZ[p]) > 2.0) continue;
            double dot = 0;
            for (int k = 0; k < 3; ++k) dot += static_cast<double>(f.normal[3 * p + k]) * f.normal[3 * q + k];
            want = want || dot < cosLimit;
            nearLimit = nearLimit || std::abs(dot - cosLimit) < 1e-5;
          }
      // float against double dot products: skip the pixels within rounding of the limit.
      if (!nearLimit && want) {
        EXPECT_EQ(c[p], 1.0f) << x << "," << y;
      }
      creases += want;
      if (c[p] > 0.0f) {
        EXPECT_NEAR(x + 0.5, 32.0, 3.0) << "crease away from the seam at x = 32";
      }
    }
  EXPECT_GT(creases, 0u);
  // Angle 0 draws none.
  const auto none = creaseCoverage(f, 2.0, 2.0, 0.0, 4.0);
  EXPECT_EQ(std::count(none.begin(), none.end(), 1.0f), 0);
}

// A flat surface with one long crease and a speck: the speck is dropped (shorter than the
// minimum length), and a stretch of the long crease that turns by less than the angle but more
// than the weak one (hysteresis) still joins its ends.
TEST(ImageEffects, CreasesKeepLongPiecesAndDropSpecks) {
  FrameBuffers f = flatFrame(64, 32, 50.0f);
  auto tilt = [&](int x, int y, double degrees) {
    const std::size_t p = at(f, x, y);
    f.normal[3 * p] = static_cast<float>(std::sin(degrees * kPi / 180.0));
    f.normal[3 * p + 2] = static_cast<float>(-std::cos(degrees * kPi / 180.0));
  };
  // The long crease: row 8, x 4..59, turned by 60° except x 28..35, turned by 45° (above the weak
  // angle 0.75 × 50° = 37.5°, below 50°); the speck: one pixel turned by 60° at (40, 24).
  for (int x = 4; x < 60; ++x) tilt(x, 8, x >= 28 && x <= 35 ? 45.0 : 60.0);
  tilt(40, 24, 60.0);
  const auto c = creaseCoverage(f, 1.0, 2.0, 50.0, 8.0);
  EXPECT_EQ(c[at(f, 40, 24)], 0.0f) << "the speck is drawn";
  EXPECT_EQ(c[at(f, 40, 23)], 0.0f) << "the speck is drawn";
  EXPECT_EQ(c[at(f, 10, 8)], 1.0f);
  EXPECT_EQ(c[at(f, 50, 8)], 1.0f);
  EXPECT_GT(c[at(f, 31, 8)], 0.0f) << "the weaker stretch does not join the crease's ends";
  EXPECT_LT(c[at(f, 31, 8)], 1.0f) << "the weaker stretch is drawn in full";
  // Without the weak stretch's neighbours the two halves (24 px each) are still long enough.
  const auto strongOnly = creaseCoverage(f, 1.0, 2.0, 50.0, 30.0);
  EXPECT_EQ(strongOnly[at(f, 10, 8)], 1.0f) << "the joined crease (56 px) is shorter than 30 px";
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
  FrameBuffers f = flatFrame(40, 30, 37.25f);
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
  e.lineWidth = 2.5 / f.height;
  e.lineColor = {0.2f, 0.4f, 0.6f};
  applyImageEffects(f, e, Camera{}, glm::vec3(1.0f));
  const std::vector<float> cover = silhouetteCoverage(before, Camera{}, 2.5, e.silhouetteJump);
  // The line colour is given in sRGB, as every colour; the frame holds its linear value.
  double line[3];
  for (int k = 0; k < 3; ++k) line[k] = ::surftrace::test::linearFromSrgb(e.lineColor[k]);
  std::size_t full = 0;
  for (std::size_t p = 0; p < f.pixels(); ++p) {
    const float c = cover[p];
    full += c == 1.0f;
    for (int k = 0; k < 3; ++k)
      ASSERT_NEAR(f.rgba[4 * p + k], c * line[k] + (1 - c) * before.rgba[4 * p + k], 1e-6) << p;
    ASSERT_NEAR(f.rgba[4 * p + 3], c + (1 - c) * before.rgba[4 * p + 3], 1e-6) << p;
  }
  EXPECT_GT(full, 20u);
}

TEST(ImageEffects, ValidateNamesTheBadParameter) {
  ImageEffects e;
  e.lineWidth = 0;
  EXPECT_THROW(e.validate(), std::invalid_argument);
  e.lineWidth = 2;  // pixels, as the width once was: refused, not a line as wide as the image
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

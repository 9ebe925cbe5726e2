// The difference image's colours (view/image_compare.hpp, difference_colors): quiet within the
// preset's depth limit, loud beyond it, colour differences shown when colour is judged.
#include <cmath>
#include <limits>

#include <gtest/gtest.h>

#include "view/camera.hpp"
#include "view/image_compare.hpp"

namespace surftrace::view {
namespace {

constexpr int kSize = 16;

// A flat reference facing the camera, every pixel a convex hit at t = 100 (so the scene size
// is 10 Å, a tenth of the nearest depth), coloured mid grey.
FrameBuffers flatReference() {
  FrameBuffers f;
  f.reset(kSize, kSize);
  for (std::size_t p = 0; p < f.pixels(); ++p) {
    f.depth[p] = f.viewZ[p] = 100.0f;
    f.normal[3 * p + 2] = 1.0f;
    f.kind[p] = 1u;
    f.patchId[p] = 0u;
    for (int k = 0; k < 3; ++k) f.rgba[4 * p + k] = 0.5f;
    f.rgba[4 * p + 3] = 1.0f;
  }
  return f;
}

glm::vec3 pixel(const std::vector<float>& rgb, std::size_t p) { return {rgb[3 * p], rgb[3 * p + 1], rgb[3 * p + 2]}; }
glm::vec3 named(const float (&c)[3]) { return {c[0], c[1], c[2]}; }

TEST(DifferenceImage, AnImageWithinTheDepthLimitLooksQuiet) {
  namespace dc = difference_colors;
  const FrameBuffers ref = flatReference();
  const FrameComparison c = compareFrames(ref, ref);
  const DifferenceScale scale = DifferenceScale::of(CompareThresholds::preset("gl-vs-embree"), c);
  EXPECT_DOUBLE_EQ(scale.depthLimit, 1e-3 * 10.0);  // 1e-3 of the 10 Å scene
  FrameBuffers test = ref;
  // Float rounding of a depth near 100 Å (a few 1e-6 Å) everywhere, and in three pixels
  // errors at half the limit, just over it and at a thousand times it.
  for (float& t : test.depth) t = std::nextafter(std::nextafter(t, 1e9f), 1e9f);
  test.depth[1] = 100.0f + 0.5f * 0.01f;
  test.depth[2] = 100.0f + 1.5f * 0.01f;
  test.depth[3] = 100.0f + 1000.0f * 0.01f;
  const std::vector<float> rgb = differenceImage(test, ref, {}, nullptr, scale);
  for (std::size_t p = 4; p < ref.pixels(); ++p) EXPECT_EQ(pixel(rgb, p), named(dc::kQuiet)) << p;
  // Half the limit: on the way from quiet to yellow, log10(0.5) + 1 = 70% of it.
  const glm::vec3 half = pixel(rgb, 1), want = glm::mix(named(dc::kQuiet), named(dc::kWithin), 0.69897f);
  for (int k = 0; k < 3; ++k) EXPECT_NEAR(half[k], want[k], 2e-3f) << k;
  // Over the limit: orange towards magenta; a thousand times: magenta.
  EXPECT_EQ(pixel(rgb, 2).x, 1.0f);
  EXPECT_LT(pixel(rgb, 2).z, 0.2f);
  EXPECT_GT(pixel(rgb, 2).z, 0.0f);
  EXPECT_EQ(pixel(rgb, 3), named(dc::kFarOver));
}

TEST(DifferenceImage, ColourDifferencesShowWhenColourIsJudged) {
  namespace dc = difference_colors;
  const FrameBuffers ref = flatReference();
  FrameBuffers test = ref;
  test.rgba[4 * 7] += 0.1f;                // a pixel 0.1 off in red
  test.rgba[4 * 8 + 2] += 0.01f;           // one within the effects limit (0.02)
  const FrameComparison c = compareFrames(test, ref);
  const DifferenceScale judged = DifferenceScale::of(CompareThresholds::preset("effects"), c);
  ASSERT_TRUE(judged.colorLimit.has_value());
  EXPECT_DOUBLE_EQ(*judged.colorLimit, 0.02);
  const std::vector<float> rgb = differenceImage(test, ref, {}, nullptr, judged);
  EXPECT_EQ(pixel(rgb, 7), named(dc::kColor));
  EXPECT_EQ(pixel(rgb, 8), named(dc::kQuiet));
  // Colour not judged (the foreign preset sets no colour limit), or not carried by the test: not shown.
  const DifferenceScale geometry = DifferenceScale::of(CompareThresholds::preset("foreign"), c);
  EXPECT_FALSE(geometry.colorLimit.has_value());
  EXPECT_EQ(pixel(differenceImage(test, ref, {}, nullptr, geometry), 7), named(dc::kQuiet));
  TestChannels noColour;
  noColour.color = false;
  EXPECT_EQ(pixel(differenceImage(test, ref, noColour, nullptr, judged), 7), named(dc::kQuiet));
}

TEST(DifferenceImage, CoverageAndKindErrorsAndTheBandKeepTheirColours) {
  namespace dc = difference_colors;
  FrameBuffers ref = flatReference();
  // The last row misses: rows 14 and 15 are the 3×3 rule's silhouette band.
  for (int x = 0; x < kSize; ++x) {
    const std::size_t p = static_cast<std::size_t>((kSize - 1) * kSize + x);
    ref.kind[p] = 0, ref.patchId[p] = ~0u, ref.depth[p] = ref.viewZ[p] = std::numeric_limits<float>::infinity();
  }
  FrameBuffers test = ref;
  test.kind[20] = 0, test.depth[20] = std::numeric_limits<float>::infinity();  // coverage
  test.kind[40] = 2;                                                           // kind
  const std::vector<float> rgb = differenceImage(test, ref);
  EXPECT_EQ(pixel(rgb, 20), named(dc::kCoverage));
  EXPECT_EQ(pixel(rgb, 40), named(dc::kKind));
  EXPECT_EQ(pixel(rgb, (kSize - 1) * kSize + 3), named(dc::kBand));
  EXPECT_EQ(pixel(rgb, (kSize - 2) * kSize + 3), named(dc::kBand));
  EXPECT_EQ(pixel(rgb, 60), named(dc::kQuiet));
}

}  // namespace
}  // namespace surftrace::view

// Which pixels compareFrames leaves out: from the reference's exact seam distances and edge
// flags when it records them, else from its 3×3 neighbourhood (view/image_compare.hpp).
#include <cmath>
#include <limits>

#include <gtest/gtest.h>

#include "view/camera.hpp"
#include "view/image_compare.hpp"

namespace surftrace::view {
namespace {

constexpr int kSize = 32;

// An orthographic camera whose pixels are 1 Å wide, looking down −z from z = 100.
Camera unitPixelCamera() {
  Camera c;
  c.projection = Projection::Orthographic;
  c.eye = {0, 0, 100};
  c.lookAt = {0, 0, 0};
  c.orthoHeight = kSize;
  c.width = c.height = kSize;
  return c;
}

// A flat reference facing the camera, every pixel a hit at t = 100: kind 1 (convex) left of
// x = 16 Å from the image's left edge, kind 3 (concave) right of it, and each pixel's seam
// distance that of its centre from x = 16.
FrameBuffers twoPatches() {
  FrameBuffers f;
  f.reset(kSize, kSize);
  f.seamDistance.assign(f.pixels(), 0.0f);
  for (int y = 0; y < kSize; ++y)
    for (int x = 0; x < kSize; ++x) {
      const std::size_t p = static_cast<std::size_t>(y) * kSize + static_cast<std::size_t>(x);
      f.depth[p] = f.viewZ[p] = 100.0f;
      f.normal[3 * p + 2] = 1.0f;
      f.kind[p] = x < 16 ? 1u : 3u;
      f.patchId[p] = f.kind[p];
      f.atomId[p] = 0;
      f.seamDistance[p] = std::abs(static_cast<float>(x) + 0.5f - 16.0f);
    }
  return f;
}

std::size_t at(int x, int y) { return static_cast<std::size_t>(y) * kSize + static_cast<std::size_t>(x); }

TEST(CompareMasks, ExactMasksJudgeKindsUpToTheSeam) {
  const Camera camera = unitPixelCamera();
  const FrameBuffers ref = twoPatches();
  FrameBuffers test = ref;
  test.kind[at(15, 5)] = 3u;  // half a pixel (0.5 Å) from the seam: far beyond float rounding
  const FrameComparison c = compareFrames(test, ref, &camera);
  EXPECT_TRUE(c.exactMasks);
  EXPECT_EQ(c.referenceHits, ref.pixels());
  EXPECT_EQ(c.kindSamples, ref.pixels());
  EXPECT_DOUBLE_EQ(c.kindAgreement, 1.0 - 1.0 / static_cast<double>(ref.pixels()));
  // The 3×3 rule masks the two columns beside the seam, the wrong pixel with them.
  FrameBuffers old = ref;
  old.seamDistance.clear();
  const FrameComparison n = compareFrames(test, old, &camera);
  EXPECT_FALSE(n.exactMasks);
  EXPECT_NE(n.masksNote.find("3x3 neighbourhood rule"), std::string::npos) << n.masksNote;
  EXPECT_NE(n.summary().find("3x3 neighbourhood rule"), std::string::npos) << n.summary();
  EXPECT_EQ(n.kindSamples, ref.pixels() - 2 * kSize);
  EXPECT_DOUBLE_EQ(n.kindAgreement, 1.0);
  // Without a camera the footprint is unknown: the 3×3 rule too.
  EXPECT_FALSE(compareFrames(test, ref).exactMasks);
}

TEST(CompareMasks, ASeamIsWhereFloatRoundingCanCrossTheEdge) {
  const Camera camera = unitPixelCamera();
  FrameBuffers ref = twoPatches();
  // The tolerance at t = 100 for a convex hit (a tangent seam with its torus) and a concave one.
  const double convex = seamTolerance(1.0, 100.0, PatchKind::Convex), concave = seamTolerance(1.0, 100.0, PatchKind::Concave);
  EXPECT_NEAR(concave, kSeamFootprints + 100.0 * kSeamRelative, 1e-15);
  EXPECT_NEAR(convex, concave + std::sqrt(100.0 * kSeamTangency), 1e-15);
  ref.seamDistance[at(15, 1)] = static_cast<float>(0.9 * convex);    // masked
  ref.seamDistance[at(15, 2)] = static_cast<float>(1.1 * convex);    // judged
  ref.seamDistance[at(16, 1)] = static_cast<float>(0.9 * concave);   // masked
  ref.seamDistance[at(16, 2)] = static_cast<float>(1.1 * concave);   // judged
  // Seen at a grazing angle (|n·dir| = 0.1), 5 tolerances along the surface are half of one across it.
  const std::size_t grazing = at(16, 3);
  ref.normal[3 * grazing] = static_cast<float>(std::sqrt(1.0 - 0.01));
  ref.normal[3 * grazing + 2] = 0.1f;
  ref.seamDistance[grazing] = static_cast<float>(5.0 * concave);
  // A flagged hit and one whose distance is unknown (the 3×3 rule: by the seam, so masked).
  ref.flags[at(3, 3)] = kHitGrazing;
  ref.seamDistance[at(16, 4)] = std::numeric_limits<float>::quiet_NaN();
  ref.seamDistance[at(20, 4)] = std::numeric_limits<float>::quiet_NaN();
  const ReferenceMasks masks = referenceMasks(ref, &camera);
  ASSERT_TRUE(masks.exact);
  EXPECT_TRUE(masks.mask[at(15, 1)].kindSeam);
  EXPECT_FALSE(masks.mask[at(15, 2)].kindSeam);
  EXPECT_TRUE(masks.mask[at(16, 1)].kindSeam);
  EXPECT_FALSE(masks.mask[at(16, 2)].kindSeam);
  EXPECT_TRUE(masks.mask[grazing].kindSeam);
  EXPECT_TRUE(masks.mask[at(3, 3)].kindSeam);
  EXPECT_TRUE(masks.mask[at(16, 4)].kindSeam);
  EXPECT_FALSE(masks.mask[at(20, 4)].kindSeam);
  std::size_t masked = 0;
  for (const PixelMask& m : masks.mask) masked += m.kindSeam;
  EXPECT_EQ(masked, 5u);
  EXPECT_EQ(compareFrames(ref, ref, &camera).kindSamples, ref.pixels() - 5);
}

TEST(CompareMasks, TheSilhouetteBandIsThePixelsTheOutlineCrosses) {
  const Camera camera = unitPixelCamera();
  FrameBuffers ref = twoPatches();
  // The right half misses; the reference records the outline on the pixels right of it (its
  // corner rays at x = 16 hit), where the 3×3 rule masks the columns on both sides.
  for (int y = 0; y < kSize; ++y)
    for (int x = 16; x < kSize; ++x) {
      const std::size_t p = at(x, y);
      ref.kind[p] = 0, ref.patchId[p] = ~0u, ref.depth[p] = ref.viewZ[p] = std::numeric_limits<float>::infinity();
      ref.normal[3 * p + 2] = 0.0f, ref.seamDistance[p] = std::numeric_limits<float>::infinity();
    }
  for (int y = 0; y < kSize; ++y) ref.flags[at(16, y)] |= kPixelSilhouette;
  ref.flags[at(4, 4)] |= kPixelOcclusion;
  FrameBuffers test = ref;
  test.kind[at(15, 7)] = 0;  // a coverage error beside the band: the 3×3 rule masks it
  test.depth[at(15, 7)] = std::numeric_limits<float>::infinity();
  const FrameComparison c = compareFrames(test, ref, &camera);
  EXPECT_EQ(c.silhouette, static_cast<std::size_t>(kSize));
  EXPECT_EQ(c.coverageMismatch, 1u);
  const ReferenceMasks masks = referenceMasks(ref, &camera);
  EXPECT_TRUE(masks.mask[at(4, 4)].occlusion);
  EXPECT_FALSE(masks.mask[at(4, 4)].band);
  FrameBuffers old = ref;
  old.seamDistance.clear();
  const FrameComparison n = compareFrames(test, old, &camera);
  EXPECT_EQ(n.silhouette, 2u * kSize);
  EXPECT_EQ(n.coverageMismatch, 0u);
}

}  // namespace
}  // namespace surftrace::view

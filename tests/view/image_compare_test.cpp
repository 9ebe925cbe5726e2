// compareFrames' masks and figures on frames ray-cast here from spheres (the oracle knows which
// sphere each pixel sees): occlusion edges, NaN, statistics over no samples.
#include <cmath>
#include <limits>
#include <vector>

#include <glm/geometric.hpp>
#include <glm/vec4.hpp>
#include <gtest/gtest.h>

#include "view/camera.hpp"
#include "view/image_compare.hpp"

namespace surftrace::view {
namespace {

constexpr double kInf = std::numeric_limits<double>::infinity();

Camera camera(int width, int height) {
  Camera c;
  c.eye = {0.0, 0.0, 30.0};
  c.lookAt = {1.0, 0.0, -4.0};
  c.width = width, c.height = height;
  c.fovY = 30.0;
  return c;
}

// Each pixel's nearest sphere along the camera's ray: depth, view z, normal, kind 1 and the
// sphere's index as patch id.
FrameBuffers castSpheres(const Camera& cam, const std::vector<glm::dvec4>& spheres) {
  FrameBuffers f;
  f.reset(cam.width, cam.height);
  const Camera::Frame frame = cam.frame();
  for (int y = 0; y < cam.height; ++y)
    for (int x = 0; x < cam.width; ++x) {
      const Ray r = frame.ray(x + 0.5, y + 0.5);
      double best = kInf;
      std::size_t id = 0;
      for (std::size_t i = 0; i < spheres.size(); ++i) {
        const glm::dvec3 oc = glm::dvec3(spheres[i]) - r.org;
        const double along = glm::dot(oc, r.dir), perp2 = glm::dot(oc, oc) - along * along;
        if (perp2 > spheres[i].w * spheres[i].w) continue;
        const double t = along - std::sqrt(spheres[i].w * spheres[i].w - perp2);
        if (t > 0.0 && t < best) best = t, id = i;
      }
      if (!std::isfinite(best)) continue;
      const std::size_t p = static_cast<std::size_t>(y * cam.width + x);
      const glm::dvec3 hit = r.org + best * r.dir, n = (hit - glm::dvec3(spheres[id])) / spheres[id].w;
      f.depth[p] = static_cast<float>(best);
      f.viewZ[p] = static_cast<float>(glm::dot(hit - cam.eye, frame.forward));
      for (int k = 0; k < 3; ++k) f.normal[3 * p + static_cast<std::size_t>(k)] = static_cast<float>(n[k]);
      f.kind[p] = 1;
      f.patchId[p] = static_cast<std::uint32_t>(id);
      f.rgba[4 * p + 3] = 1.0f;
    }
  return f;
}

// Disjoint spheres, the first partly in front of the second: the edges are exactly the hit pixels
// with a neighbour (3×3) on the other sphere, and a sphere alone has none, its limb included.
TEST(OcclusionEdges, AreThePixelsBesideAnotherSphere) {
  const Camera cam = camera(120, 90);
  const std::vector<glm::dvec4> spheres = {{0.0, 0.0, 0.0, 3.0}, {3.0, 1.0, -9.0, 3.0}};
  const FrameBuffers f = castSpheres(cam, spheres);
  const std::vector<std::uint8_t> edges = occlusionEdges(f, cam);
  std::size_t oracle = 0, found = 0, missed = 0;
  for (int y = 0; y < f.height; ++y)
    for (int x = 0; x < f.width; ++x) {
      const std::size_t p = static_cast<std::size_t>(y * f.width + x);
      bool beside = false;
      for (int dy = -1; dy <= 1; ++dy)
        for (int dx = -1; dx <= 1; ++dx) {
          const int qx = x + dx, qy = y + dy;
          if (qx < 0 || qy < 0 || qx >= f.width || qy >= f.height) continue;
          const std::size_t q = static_cast<std::size_t>(qy * f.width + qx);
          beside = beside || (f.kind[p] != 0 && f.kind[q] != 0 && f.patchId[q] != f.patchId[p]);
        }
      oracle += beside;
      found += edges[p];
      missed += beside && !edges[p];
      EXPECT_FALSE(edges[p] && !beside) << "pixel " << x << ", " << y << " flagged away from the occlusion";
    }
  EXPECT_GT(oracle, 40u);
  EXPECT_EQ(missed, 0u) << found << " of " << oracle;

  const FrameBuffers alone = castSpheres(cam, {spheres[0]});
  std::size_t flagged = 0;
  for (std::uint8_t e : occlusionEdges(alone, cam)) flagged += e;
  EXPECT_EQ(flagged, 0u);
}

// The edge pixels' depth error is reported apart; the depth figures hold the rest.
TEST(OcclusionEdges, TheirDepthErrorIsReportedApart) {
  const Camera cam = camera(120, 90);
  const FrameBuffers ref = castSpheres(cam, {{0.0, 0.0, 0.0, 3.0}, {3.0, 1.0, -9.0, 3.0}});
  FrameBuffers test = ref;
  const std::vector<std::uint8_t> edges = occlusionEdges(ref, cam);
  std::size_t moved = 0;
  for (std::size_t p = 0; p < ref.pixels(); ++p)
    if (edges[p] && ref.patchId[p] == 0) test.depth[p] += 5.0f, ++moved;
  const FrameComparison c = compareFrames(test, ref, &cam);
  EXPECT_GT(moved, 10u);
  EXPECT_GE(c.occlusionEdge, moved);
  EXPECT_NEAR(c.occlusionDepthMax, 5.0, 1e-5);
  EXPECT_EQ(c.depthMax, 0.0);
  EXPECT_TRUE(CompareThresholds::preset("exact").violations(c).empty());
}

// NaN is counted per buffer and per pixel, kept out of every figure, and fails every preset.
TEST(CompareFrames, NanIsCountedAndFails) {
  const Camera cam = camera(64, 48);
  const FrameBuffers ref = castSpheres(cam, {{0.0, 0.0, 0.0, 4.0}});
  FrameBuffers test = ref;
  const float nan = std::numeric_limits<float>::quiet_NaN();
  const std::size_t centre = static_cast<std::size_t>(24 * 64 + 30);
  test.depth[centre] = nan;
  test.normal[3 * (centre + 1)] = nan;
  test.rgba[4 * (centre + 2)] = nan, test.depth[centre + 2] = nan;
  const FrameComparison c = compareFrames(test, ref, &cam);
  EXPECT_EQ(c.nanTest.pixels, 3u);
  EXPECT_EQ(c.nanTest.depth, 2u);
  EXPECT_EQ(c.nanTest.normal, 1u);
  EXPECT_EQ(c.nanTest.color, 1u);
  EXPECT_EQ(c.nanReference.pixels, 0u);
  EXPECT_FALSE(std::isnan(c.depthMax) || std::isnan(c.normalMaxDegrees) || std::isnan(c.colorMax));
  EXPECT_EQ(c.depthMax, 0.0);
  for (const char* preset : {"exact", "gl-vs-embree", "foreign", "effects", "transparency"}) {
    const auto v = CompareThresholds::preset(preset).violations(c);
    ASSERT_EQ(v.size(), 1u) << preset;
    EXPECT_EQ(v[0], "NaN in 3 px of the test (depth 2, normal 1, colour 1) > 0") << preset;
  }
  EXPECT_TRUE(CompareThresholds{}.violations(c).empty());
}

// A limit over no samples fails as "none compared"; with nothing set there is nothing to fail.
TEST(CompareFrames, NothingComparedFails) {
  const Camera cam = camera(32, 24);
  const FrameBuffers empty = castSpheres(cam, {});
  const FrameComparison c = compareFrames(empty, empty, &cam);
  EXPECT_EQ(c.depthSamples, 0u);
  const auto v = CompareThresholds::preset("exact").violations(c);
  ASSERT_FALSE(v.empty());
  EXPECT_EQ(v[0], "depth: none compared (no pixel where both images hit, outside the masks)");
  EXPECT_NE(c.summary().find("depth error      none compared (0 px)"), std::string::npos) << c.summary();
  EXPECT_TRUE(CompareThresholds{}.violations(c).empty());
}

}  // namespace
}  // namespace surftrace::view

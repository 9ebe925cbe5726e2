// `compare` as a library call (surftrace/compare.hpp) with another renderer's buffers held in
// memory, as a program (or the Python module) hands them over: no test file is written. The
// reference is a stored reference image; the buffers under test are made from its own depth.
#include <algorithm>
#include <cmath>
#include <limits>
#include <stdexcept>
#include <string>
#include <vector>

#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

#include "surftrace/compare.hpp"

namespace surftrace {
namespace {

constexpr float kInf = std::numeric_limits<float>::infinity();

// A perspective reference of 1CRN (30° field of view, its camera unrotated).
const CompareReference& reference() {
  static const CompareReference r =
      readCompareReference(std::string(SURFTRACE_SOURCE_DIR) + "/reference/crambin-front/image.exr");
  return r;
}

// One buffer of the reference (view z or ray distance), +inf at misses, plus `shift` Å on the
// hits, rows stored from `origin`.
ImageChannels depthBuffer(const std::vector<float>& source, float shift, RowOrigin origin) {
  const FrameBuffers& f = reference().frame;
  std::vector<float> values(f.pixels(), kInf);
  for (int y = 0; y < f.height; ++y) {
    const int stored = origin == RowOrigin::TopLeft ? y : f.height - 1 - y;
    for (int x = 0; x < f.width; ++x) {
      const std::size_t p = static_cast<std::size_t>(y) * f.width + x;
      if (f.kind[p] != 0) values[static_cast<std::size_t>(stored) * f.width + x] = source[p] + shift;
    }
  }
  return memoryChannels("depth", f.width, f.height, {"Z"}, std::move(values));
}

CompareTest foreignTest(ImageChannels depth, DepthConvention convention, RowOrigin origin) {
  ForeignBufferOptions options;
  options.depthConvention = convention;
  options.origin = origin;
  return CompareTest{"depth", {}, {}, ForeignBuffers{std::move(depth), std::nullopt, options}, std::nullopt};
}

TEST(Comparison, ReferencesOwnViewDepthFromMemoryPasses) {
  const FrameBuffers& f = reference().frame;
  for (const RowOrigin origin : {RowOrigin::TopLeft, RowOrigin::BottomLeft}) {
    const CompareResult r = compare(foreignTest(depthBuffer(f.viewZ, 0.0f, origin), DepthConvention::ViewZ, origin), reference());
    EXPECT_TRUE(r.passed()) << r.verdict();
    EXPECT_TRUE(r.foreign);
    EXPECT_EQ(r.preset, "foreign");  // chosen for another renderer's buffers
    EXPECT_EQ(r.figures.coverageMismatch, 0u);
    EXPECT_GT(r.figures.depthSamples, f.pixels() / 5);
    EXPECT_LT(r.figures.depthP99, 1e-4);  // float view z turned back into a float ray distance
    EXPECT_NE(r.verdict().find("PASS (foreign, on what the test carries)"), std::string::npos) << r.verdict();
    const nlohmann::json report = nlohmann::json::parse(r.json());
    EXPECT_TRUE(report.contains("worst_pixels"));
  }
}

// View z shifted by 0.2 Å moves each hit 0.2/cos θ along its ray, θ the ray's angle to the view
// direction: for a pinhole with tan(fov/2) = h, pixel centre (sx, sy) of W×H,
// 1/cos θ = sqrt(1 + a² + b²), a = (2 sx/W − 1)·h·W/H, b = (2 sy/H − 1)·h.
TEST(Comparison, ViewDepthShiftedByAFifthOfAnAngstromFails) {
  const FrameBuffers& f = reference().frame;
  const CompareResult r =
      compare(foreignTest(depthBuffer(f.viewZ, 0.2f, RowOrigin::TopLeft), DepthConvention::ViewZ, RowOrigin::TopLeft), reference());
  const double h = std::tan(15.0 * M_PI / 180.0);  // the reference's 30° field of view
  std::vector<double> expected;
  for (int y = 0; y < f.height; ++y)
    for (int x = 0; x < f.width; ++x)
      if (f.kind[static_cast<std::size_t>(y) * f.width + x] != 0) {
        const double a = (2.0 * (x + 0.5) / f.width - 1.0) * h * f.width / f.height, b = (2.0 * (y + 0.5) / f.height - 1.0) * h;
        expected.push_back(0.2 * std::sqrt(1.0 + a * a + b * b));
      }
  std::sort(expected.begin(), expected.end());
  const double p99 = expected[static_cast<std::size_t>(0.99 * (expected.size() - 1))];
  // The silhouette band the comparison leaves out holds the outermost hits: its p99 lies between
  // the median's and the p99's of every hit (float view z adds ±2e-5 Å).
  EXPECT_GE(r.figures.depthP99, expected[expected.size() / 2] - 1e-4);
  EXPECT_LE(r.figures.depthP99, p99 + 1e-4);
  EXPECT_NEAR(r.figures.depthP99, 0.2, 0.01);
  EXPECT_FALSE(r.passed());
  ASSERT_EQ(r.violations.size(), 1u) << r.verdict();
  EXPECT_NE(r.violations[0].find("depth p99"), std::string::npos) << r.violations[0];
  EXPECT_NE(r.verdict().find("\nFAIL (foreign, on what the test carries):\n  depth p99 "), std::string::npos) << r.verdict();
}

// Ray distances declared as view z: compare says which convention fits, with the figures.
TEST(Comparison, WrongDepthConventionGetsTheHint) {
  const FrameBuffers& f = reference().frame;
  const ImageChannels rays = depthBuffer(f.depth, 0.0f, RowOrigin::TopLeft);
  EXPECT_TRUE(compare(foreignTest(rays, DepthConvention::Ray, RowOrigin::TopLeft), reference()).passed());
  const CompareResult r = compare(foreignTest(rays, DepthConvention::ViewZ, RowOrigin::TopLeft), reference());
  EXPECT_FALSE(r.passed());
  ASSERT_EQ(r.hints.size(), 1u) << r.verdict();
  EXPECT_EQ(r.hints[0].rfind("hint: with --depth-convention ray the depth p99 would be ", 0), 0u) << r.hints[0];
  EXPECT_NE(r.verdict().find("\n  " + r.hints[0]), std::string::npos);
  // The rows read upside down: the hint is the row origin.
  const CompareResult flipped = compare(foreignTest(rays, DepthConvention::Ray, RowOrigin::BottomLeft), reference());
  EXPECT_FALSE(flipped.passed());
  ASSERT_FALSE(flipped.hints.empty()) << flipped.verdict();
  EXPECT_EQ(flipped.hints[0].rfind("hint: with --test-origin top-left", 0), 0u) << flipped.hints[0];
}

TEST(Comparison, SurfTraceBuffersInMemoryAgainstThemselvesPassExact) {
  const CompareTest same{"same", reference().frame, reference().metadata, std::nullopt, std::nullopt};
  const CompareResult r = compare(same, reference());
  EXPECT_TRUE(r.passed()) << r.verdict();
  EXPECT_EQ(r.preset, "exact");  // both record the engine embree
  EXPECT_NE(r.presetChoice.find("--preset exact (engines: test embree, reference embree"), std::string::npos) << r.presetChoice;
  EXPECT_EQ(r.figures.depthMax, 0.0);
  EXPECT_EQ(r.figures.kindAgreement, 1.0);
  // Handed over as a temporary, the buffers move into the result.
  const CompareResult moved = compare(CompareTest{same}, reference());
  EXPECT_TRUE(moved.passed()) << moved.verdict();
  EXPECT_EQ(moved.testFrame.depth, reference().frame.depth);
  // A limit given replaces the preset's: an impossible one fails.
  CompareSettings strict;
  strict.limits.minPatchAgreement = 1.5;
  EXPECT_FALSE(compare(same, reference(), strict).passed());
}

// The conventions by the names the command line's flags and the Python module's keywords take.
TEST(Comparison, ConventionsByName) {
  EXPECT_EQ(depthConventionNamed("window"), DepthConvention::Window);
  EXPECT_EQ(depthConventionNamed("view-z"), DepthConvention::ViewZ);
  EXPECT_EQ(depthConventionNamed("ray"), DepthConvention::Ray);
  EXPECT_EQ(rowOriginNamed("bottom-left"), RowOrigin::BottomLeft);
  EXPECT_EQ(rowOriginNamed("top-left"), RowOrigin::TopLeft);
  EXPECT_EQ(normalSpaceNamed("view"), NormalSpace::View);
  EXPECT_EQ(normalSpaceNamed("world"), NormalSpace::World);
  EXPECT_EQ(normalEncodingNamed("signed"), NormalEncoding::Signed);
  EXPECT_EQ(normalEncodingNamed("snorm"), NormalEncoding::Signed);
  EXPECT_EQ(normalEncodingNamed("unorm"), NormalEncoding::Unorm);
  try {
    depthConventionNamed("viewz");
    FAIL() << "no error for an unknown name";
  } catch (const std::invalid_argument& e) {
    EXPECT_STREQ(e.what(), "unknown depth convention 'viewz': expected one of window, view-z, ray");
  }
  EXPECT_THROW(rowOriginNamed("top"), std::invalid_argument);
}

TEST(Comparison, BuffersThatDoNotFitAreErrorsNamingThem) {
  EXPECT_THROW(memoryChannels("depth", 4, 4, {"Z"}, std::vector<float>(15)), std::invalid_argument);
  const FrameBuffers& f = reference().frame;
  const CompareTest small = foreignTest(memoryChannels("my depth", f.width - 1, f.height, {"Z"},
                                                       std::vector<float>(static_cast<std::size_t>(f.width - 1) * f.height, kInf)),
                                        DepthConvention::ViewZ, RowOrigin::TopLeft);
  try {
    compare(small, reference());
    FAIL() << "no error for a buffer of another size";
  } catch (const std::invalid_argument& e) {
    EXPECT_NE(std::string(e.what()).find("my depth is 159x160 but "), std::string::npos) << e.what();
  }
  CompareReference noCamera = compareReference("no camera", f, {});
  EXPECT_THROW(compare(foreignTest(depthBuffer(f.viewZ, 0.0f, RowOrigin::TopLeft), DepthConvention::ViewZ, RowOrigin::TopLeft),
                       noCamera),
               std::invalid_argument);
}

}  // namespace
}  // namespace surftrace

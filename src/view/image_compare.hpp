// Pixel-by-pixel comparison of two renderings of the same view (ORACLES D.4): the metrics
// `surftrace compare` reports and the GL tests assert.
#pragma once

#include <cstdint>
#include <optional>
#include <string>
#include <vector>

#include "view/camera.hpp"
#include "view/frame_buffers.hpp"

namespace surftrace::view {

// What the image under test carries. SurfTrace's own images carry every buffer; another
// renderer's (view/foreign_buffers.hpp) carry coverage and depth, normals when it wrote them,
// and no patch kinds or ids. A metric of a buffer not carried is "not compared": neither
// passed nor failed. Without kinds, coverage is "the depth is finite".
struct TestChannels {
  bool normal = true;
  bool kind = true;
  bool patchId = true;
  bool color = true;
};

// Pixels whose buffer holds NaN (a compared buffer: depth, normal, colour): each is a mismatch,
// kept out of the statistics and counted here.
struct NanCounts {
  std::size_t depth = 0, normal = 0, color = 0;
  std::size_t pixels = 0;  // pixels with NaN in any of them
};

// The errors over the depth samples of one patch kind of the reference (its `patch.kind`).
struct KindErrors {
  std::uint32_t kind = 0;
  std::size_t pixels = 0;                               // depth samples of this kind
  double depthMedian = 0.0, depthP1 = 0.0, depthP99 = 0.0;  // signed t_test − t_ref (Å): < 0 in front
  std::size_t inFront = 0, behind = 0;                  // test nearer than the reference, farther
  std::size_t normalSamples = 0;
  double normalMedianDegrees = 0.0, normalP99Degrees = 0.0;
};

struct FrameComparison {
  std::size_t pixels = 0;
  std::size_t silhouette = 0;         // reference hit/miss changes within the 3×3 neighbourhood: masked
  // Both hit beside a depth discontinuity of the reference inside its covered region (one part
  // of the surface hides another: occlusionEdges): masked like the silhouette band, the depth
  // error there reported on its own.
  std::size_t occlusionEdge = 0;
  double occlusionDepthMedian = 0.0, occlusionDepthP99 = 0.0, occlusionDepthMax = 0.0;
  std::size_t coverageMismatch = 0;   // hit/miss differs, outside the silhouette band
  double coverageFraction = 0.0;      // of the pixels outside the band
  std::size_t depthSamples = 0;       // both hit, outside the band
  double depthMedian = 0.0, depthP99 = 0.0, depthMax = 0.0;  // |t_test − t_ref|, Å
  double depthP99Pixels = 0.0;        // p99 of the depth error in units of the pixel footprint at t_ref
  std::size_t kindSamples = 0;        // both hit, reference kind constant over 3×3, not flagged
  std::size_t patchSamples = 0;       // both hit, reference patch id constant over 3×3, not flagged
  double kindAgreement = 1.0, patchAgreement = 1.0;
  std::size_t normalSamples = 0;
  double normalMedianDegrees = 0.0, normalP99Degrees = 0.0, normalMaxDegrees = 0.0;
  // Colour: the largest |ΔR|, |ΔG|, |ΔB| of a pixel, over the pixels outside the silhouette band
  // and off patch-kind seams and flagged pixels (where the two may see different patches: the
  // patch colouring changes there): over the covered pixels (both hit), and apart from them over
  // the background (both miss), so that a large background does not dilute the surface's p99.
  std::size_t colorSamples = 0;
  double colorMedian = 0.0, colorP99 = 0.0, colorMax = 0.0;
  std::size_t backgroundSamples = 0;
  double backgroundMedian = 0.0, backgroundP99 = 0.0, backgroundMax = 0.0;
  NanCounts nanTest, nanReference;
  std::vector<KindErrors> perKind;    // the reference's kinds with depth samples, in kind order
  double sceneSize = 0.0;             // depth range of the reference's hits (Å), for relative depth
  TestChannels compared;              // the metrics measured; the others are "not compared"

  std::string summary() const;
  std::string json() const;
};

// `camera` gives the pixel footprint at ray distance t (Camera::pixelFootprint) and the rays
// that find occlusion edges; pass nothing to skip the footprint-relative figure and those edges. `carried` says which of the test's buffers hold
// anything. Throws std::invalid_argument if the sizes differ.
FrameComparison compareFrames(const FrameBuffers& test, const FrameBuffers& reference,
                              const Camera* camera = nullptr, const TestChannels& carried = {});

// Pass/fail limits; an unset limit is not checked.
struct CompareThresholds {
  std::optional<double> maxCoverageFraction;     // coverage mismatch outside silhouettes
  std::optional<double> maxDepthP99Relative;     // depth p99 / scene size
  std::optional<double> minKindAgreement;
  std::optional<double> minPatchAgreement;
  std::optional<double> maxNormalP99Degrees;
  std::optional<double> maxColorP99;            // colour difference p99, in [0, 1] display units,
                                                // over the covered pixels and over the background
  std::optional<std::size_t> maxNanPixels;      // pixels with NaN in a compared buffer (either image)

  // "gl-vs-embree": the agreement issue 5 requires of the GL path (coverage < 0.1%,
  // depth p99 < 1e-3 of the scene, kind agreement > 99.9%); "exact": a re-render of a
  // reference by the same engine (coverage 0, depth p99 < 1e-6 of the scene, kinds and ids
  // identical); "foreign": another renderer's buffers (coverage < 0.1%, depth p99 < 1e-3 of
  // the scene, normal p99 < 1°, which an 8-bit normal buffer meets); "effects": gl-vs-embree
  // and the colour p99 within 0.02 (the image-space effects, view/image_effects.hpp, on two
  // engines' buffers); "transparency": gl-vs-embree and the colour p99 within 1e-3 (the two
  // engines' layers at opacity < 1, GL peeling them). Throws std::invalid_argument naming the
  // known presets.
  static CompareThresholds preset(const std::string& name);
  // Empty when every set limit on a compared metric holds; otherwise one line per violated limit.
  // A limit on a compared metric with no samples is violated ("none compared"): nothing measured
  // is not a pass.
  std::vector<std::string> violations(const FrameComparison& c) const;
  // One line per set limit on a metric that was not compared (the test does not carry it),
  // saying which buffer is missing.
  std::vector<std::string> notCompared(const FrameComparison& c) const;
};

// Occlusion edges of the reference (1 = edge, per pixel): hit pixels with a hit neighbour (3×3)
// whose view depth differs by more than the two surfaces' slopes can explain, i.e. where one part
// of the surface hides another. Between neighbours p and q the smooth surface under the nearer
// slope changes view depth by at most about footprint·d·tan θ (θ the angle between the normal
// and the ray); an edge is a step larger than 2·footprint·d·min(tan θp, tan θq) + footprint·d
// (d = 1 or √2). At an occlusion edge the front sheet is seen edge-on (its tangent holds the
// ray), so the back sheet's slope is the one that bounds a continuous surface.
std::vector<std::uint8_t> occlusionEdges(const FrameBuffers& reference, const Camera& camera);

// NaN per compared buffer of `frame` (colour when `carried.color`, normals when `carried.normal`),
// and per pixel in `mask` (1 = some NaN) when given.
NanCounts countNan(const FrameBuffers& frame, const TestChannels& carried, std::vector<std::uint8_t>* mask = nullptr);

// A false-colour difference image (RGB, row 0 at the top): grey = agree, red = coverage
// mismatch, blue = silhouette band (masked), yellow→magenta = depth error on a log scale
// from 1e-6 Å to 1 Å, green = patch kind differs (when the test carries kinds).
std::vector<float> differenceImage(const FrameBuffers& test, const FrameBuffers& reference,
                                   const TestChannels& carried = {});

}  // namespace surftrace::view

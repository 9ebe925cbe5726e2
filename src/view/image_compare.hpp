// Pixel-by-pixel comparison of two renderings of the same view (ORACLES D.4): the metrics
// `surftrace compare` reports and the GL tests assert.
#pragma once

#include <cstdint>
#include <optional>
#include <span>
#include <string>
#include <vector>

#include "view/camera.hpp"
#include "view/frame_buffers.hpp"
#include "view/patch_kind.hpp"

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

// The errors of one patch kind of the reference (its `patch.kind`), over the pixels whose depth
// compareFrames measures (both hit, off the masks, no NaN).
struct KindErrors {
  std::uint32_t kind = 0;
  std::size_t pixels = 0;                                   // the reference's hits of this kind
  std::size_t samples = 0;                                  // depth samples of this kind
  double depthMedian = 0.0, depthP1 = 0.0, depthP99 = 0.0;  // signed t_test − t_ref (Å): < 0 in front
  std::size_t inFront = 0, behind = 0;                      // test nearer than the reference, farther
  std::size_t normalSamples = 0;
  double normalMedianDegrees = 0.0, normalP99Degrees = 0.0;
  // The signed depth error's histogram: kHistogramBins equal bins of [−histogramRange,
  // histogramRange] (1.25 times the larger of |p1| and |p99|); errors beyond it fall into the
  // end bins.
  double histogramRange = 0.0;
  std::vector<std::size_t> histogram;
};
inline constexpr int kHistogramBins = 41;

// Which parts of a pixel's comparison are left out, because the two renderings may honestly
// disagree there (ReferenceMasks).
struct PixelMask {
  bool band = false;       // hit/miss may differ (the outline passes the pixel): nothing compared
  bool occlusion = false;  // the depth jumps inside the pixel (exact masks only; see compareFrames)
  bool kindSeam = false;   // the patch kind may differ: kind not compared
  bool seam = false;       // the patch may differ: patch id and normal not compared
};

// The masks of every pixel of a reference, as compareFrames and differenceImage apply them.
//   exact: the reference records what its exact tracer knew (RenderOptions::referenceMasks:
//     FrameBuffers::seamDistance and the kPixelSilhouette / kPixelOcclusion flags) and the
//     camera is known. A hit is on a seam only where a float renderer can put the pixel's
//     centre on the other side of its patch's edge: where its distance d to the edge, seen
//     along the ray (d·|n·dir|), is below seamTolerance(), or where the hit is flagged grazing
//     or cusp. Hits whose distance the tracer does not know (NaN) fall back to the 3×3 rule.
//   3×3 neighbourhood (an older reference, or no camera): the band where hit/miss changes within
//     a pixel's 3×3 neighbourhood, seams where the kind or patch changes there or the reference
//     flags the hit. `note` then says why.
//
// The tolerance at ray distance t: a share of the pixel footprint, which keeps a margin at
// every image size; float rounding of the ray, the hit and the trimming test, relative to t
// (GL's skin cells: its kind mismatches lie within 4e-6·t of the edge, 1AON at 256²); and where
// two patches meet tangentially and one is drawn beyond the seam (an SES sphere drawn whole,
// against its torus: kinds convex and toroidal), the width within which a depth off by ε·t
// lets the wrong one win, s = sqrt(2εRt) for surfaces that part by s²/2R (ε = 2⁻²¹, eight times
// float's unit rounding 2⁻²⁴, and R = 1 Å > 1/(1/r + 1/rp)). Measured: GL's
// kind mismatches lie within 6.2e-4·sqrt(t) Å of the edge (1AON, 1VIS, 1CRN, SES and skin,
// 128² to 256²), a third of the sum.
inline constexpr double kSeamFootprints = 0.01;
inline constexpr double kSeamRelative = 0x1.0p-15;
inline constexpr double kSeamTangency = 0x1.0p-20;  // 2εR, Å
double seamTolerance(double footprint, double t, PatchKind kind);
struct ReferenceMasks {
  bool exact = false;
  std::string note;             // why the 3×3 rule applies, when it does
  std::vector<PixelMask> mask;  // per pixel, row by row
};
ReferenceMasks referenceMasks(const FrameBuffers& reference, const Camera* camera);

struct FrameComparison {
  std::size_t pixels = 0;
  std::size_t referenceHits = 0;      // pixels the reference covers
  bool exactMasks = false;            // ReferenceMasks::exact
  std::string masksNote;              // ReferenceMasks::note
  std::size_t silhouette = 0;         // in the silhouette band (ReferenceMasks): masked
  // Both hit at an occlusion edge of the reference inside its covered region (one part of the
  // surface hides another): occlusionEdges, and PixelMask::occlusion with exact masks. Left out
  // of the depth figures (and the per-kind table), the depth error there reported on its own;
  // kind, id, normal and colour are judged there as the seams allow.
  std::size_t occlusionEdge = 0;
  double occlusionDepthMedian = 0.0, occlusionDepthP99 = 0.0, occlusionDepthMax = 0.0;
  std::size_t coverageMismatch = 0;   // hit/miss differs, outside the silhouette band
  double coverageFraction = 0.0;      // of the pixels outside the band
  std::size_t depthSamples = 0;       // both hit, outside the band
  double depthMedian = 0.0, depthP99 = 0.0, depthMax = 0.0;  // |t_test − t_ref|, Å
  double depthP99Pixels = 0.0;        // p99 of the depth error in units of the pixel footprint at t_ref
  std::size_t kindSamples = 0;        // both hit, off kind seams (ReferenceMasks)
  std::size_t patchSamples = 0;       // both hit, off seams
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
  std::vector<KindErrors> perKind;    // every kind the reference shows, in kind order
  double sceneSize = 0.0;             // depth range of the reference's hits (Å), for relative depth
  TestChannels compared;              // the metrics measured; the others are "not compared"

  std::string summary() const;
  std::string json() const;
};

// What compareFrames measured, pixel by pixel, for a caller that pools several views
// (`compare --views`): the pixels whose depth it judged (both hit, off the band and occlusion
// edges, no NaN), with the signed error t_test − t_ref (Å), and the pixels whose coverage
// differs outside the silhouette band.
struct FrameSamples {
  struct Depth {
    std::size_t pixel;
    double signedError;
  };
  std::vector<Depth> depth;
  std::vector<Depth> normal;  // the angle (°) between the normals, off seams, when normals are carried
  std::vector<std::size_t> coverage;
};

// A value of one of the reference's patch kinds: a signed depth error (Å) or a normal angle (°).
struct KindValue {
  std::uint32_t kind;
  double value;
};
// The per-kind table (FrameComparison::perKind) of pooled samples: a row for every kind k with
// pixelsPerKind[k] > 0 (the reference's hits of that kind), in kind order.
std::vector<KindErrors> kindErrors(std::span<const std::size_t> pixelsPerKind, const std::vector<KindValue>& depth,
                                   const std::vector<KindValue>& normal);

// The per-kind table as `compare` prints it (FrameComparison::summary's last lines, no final
// newline), headed "per patch kind of the <referenceName> (depth error signed, <difference>, ...)",
// and as the report's "per_kind" JSON array (a string of it).
std::string kindTableText(const std::vector<KindErrors>& perKind, bool normalsCompared, const std::string& referenceName,
                          const std::string& difference);
std::string kindTableJson(const std::vector<KindErrors>& perKind, bool normalsCompared, const std::string& difference);

// `camera` gives the pixel footprint at ray distance t (Camera::pixelFootprint) and the rays
// that find occlusion edges; pass nothing to skip the footprint-relative figure and those edges. `carried` says which of the test's buffers hold
// anything. Throws std::invalid_argument if the sizes differ.
FrameComparison compareFrames(const FrameBuffers& test, const FrameBuffers& reference,
                              const Camera* camera = nullptr, const TestChannels& carried = {},
                              FrameSamples* samples = nullptr);

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

// Occlusion edges of the reference from its buffers alone (1 = edge, per pixel): hit pixels with a hit neighbour (3×3)
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

// What the difference image's colours are relative to: the limits the comparison is judged by.
struct DifferenceScale {
  double depthLimit = 0.0;           // Å; 0: 1e-3 of the scene size (the gl-vs-embree limit)
  std::optional<double> colorLimit;  // set when colour is judged: its p99 limit
  // The limits `limits` sets on a comparison `c` (the depth p99 limit times the scene size).
  static DifferenceScale of(const CompareThresholds& limits, const FrameComparison& c);
};

// The difference image's colours (RGB, in [0, 1]); kDifferenceLegend says the same in words.
namespace difference_colors {
inline constexpr float kBackground[3] = {0.15f, 0.15f, 0.15f};  // both miss, colour agrees
inline constexpr float kQuiet[3] = {0.5f, 0.5f, 0.5f};          // both hit, depth error < 1/10 of the limit
inline constexpr float kWithin[3] = {0.85f, 0.85f, 0.2f};       // depth error at the limit (from kQuiet at 1/10)
inline constexpr float kOver[3] = {1.0f, 0.55f, 0.0f};          // depth error just over the limit
inline constexpr float kFarOver[3] = {1.0f, 0.0f, 1.0f};        // 100 times the limit and more (from kOver)
inline constexpr float kCoverage[3] = {1.0f, 0.0f, 0.0f};       // hit/miss differs outside the band
inline constexpr float kKind[3] = {0.0f, 1.0f, 0.0f};           // patch kind differs off the seams
inline constexpr float kColor[3] = {0.0f, 0.9f, 0.9f};          // colour differs by more than its limit
inline constexpr float kBand[3] = {0.2f, 0.3f, 0.8f};           // silhouette band: masked
}  // namespace difference_colors
inline constexpr const char* kDifferenceLegend =
    "dark grey: both miss; grey: depth error below 1/10 of the limit; grey to yellow: 1/10 of the limit to the limit "
    "(log scale); orange to magenta: the limit to 100 times it (log scale); red: coverage differs; green: patch kind "
    "differs; cyan: colour differs by more than its limit (when colour is judged); blue: silhouette band (masked)";

// A false-colour difference image (RGB, row 0 at the top, the reference's size), coloured as
// difference_colors says, in that order of precedence from the band up. Masks as in
// compareFrames (`camera`: exact masks when the reference records them).
std::vector<float> differenceImage(const FrameBuffers& test, const FrameBuffers& reference,
                                   const TestChannels& carried = {}, const Camera* camera = nullptr,
                                   const DifferenceScale& scale = {});

}  // namespace surftrace::view

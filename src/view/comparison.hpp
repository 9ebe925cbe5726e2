// `compare` as one call: a rendering under test (SurfTrace's buffers, or another renderer's depth
// and normal buffers, from files or held in memory) against a SurfTrace reference of the same
// view, judged by a preset's limits: the figures, the verdict and its hints, the JSON report, the
// difference image and the HTML page. `surftrace compare` is argv parsing over it.
#pragma once

#include <optional>
#include <string>
#include <vector>

#include "view/camera.hpp"
#include "view/compare_report.hpp"
#include "view/foreign_buffers.hpp"
#include "view/frame_buffers.hpp"
#include "view/image_compare.hpp"
#include "view/image_io.hpp"

namespace surftrace::view {

// Another renderer's buffers as it wrote them (rows in the order stored: options.origin says
// which row comes first), and how to read them.
struct ForeignBuffers {
  ImageChannels depth;
  std::optional<ImageChannels> normals;  // none: normals are not compared
  ForeignBufferOptions options;

  const ImageChannels* normalImage() const { return normals ? &*normals : nullptr; }
};

// A buffer held in memory (e.g. glReadPixels' result), as readImageChannels gives a file of
// float channels: `values` holds channels.size() floats per pixel, rows in stored order. `name`
// stands for the file in messages (e.g. "depth"). Throws std::invalid_argument when the sizes
// do not agree.
ImageChannels memoryChannels(std::string name, int width, int height, std::vector<std::string> channels,
                             std::vector<float> values);

// A test the caller has already drawn along the reference camera's rays: a mesh
// (surftrace::readMeshTest, trace::drawMesh). Judged as another renderer's buffers are.
struct DrawnTest {
  FrameBuffers frame;     // depth (Å along the reference's rays), viewZ, world normals
  TestChannels carried{true, false, false, false};  // normals; no patch kinds, ids or colour
  std::string description;  // what was drawn, for the "test" line
  std::string details;      // lines under "test", each ending in a newline
};

// The rendering under test: SurfTrace's own buffers and metadata, or (when `foreign` is set)
// another renderer's buffers, read along the reference camera's rays, or (when `drawn` is set)
// a mesh drawn along them.
struct CompareTest {
  std::string name;  // its file, or what messages call it
  FrameBuffers frame;  // SurfTrace's buffers (unused when foreign or drawn)
  ImageMetadata metadata;
  std::optional<ForeignBuffers> foreign;
  std::optional<DrawnTest> drawn;
};

// The reference: SurfTrace's buffers with their metadata. Its masks come from the buffers; its
// camera (needed for exact masks and for another renderer's buffers) from the metadata.
struct CompareReference {
  std::string name;  // its file, or what messages call it
  FrameBuffers frame;
  ImageMetadata metadata;
  std::optional<Camera> camera;  // from surftrace:camera, when recorded
};
// A reference from buffers and metadata held in memory (the camera read from the metadata).
CompareReference compareReference(std::string name, FrameBuffers frame, ImageMetadata metadata);

// From files. Each throws std::runtime_error naming the file when it cannot be read.
CompareReference readCompareReference(const std::string& path);  // a SurfTrace EXR
CompareTest readSurfTraceTest(const std::string& path);          // a SurfTrace EXR
// Another renderer's depth buffer and, unless `normalPath` is empty, its normal buffer: any
// format OpenImageIO reads.
CompareTest readForeignTest(const std::string& depthPath, const std::string& normalPath, const ForeignBufferOptions& options);
// A SurfTrace EXR, or another renderer's buffers when `foreign` is given or the file lacks
// SurfTrace's channels (then read with `foreign`'s options, or the defaults).
CompareTest readCompareTest(const std::string& path, const std::optional<ForeignBufferOptions>& foreign = std::nullopt,
                            const std::string& normalPath = "");

// The presets CompareThresholds::preset knows, and "none" (no limits).
inline constexpr const char* kComparePresets[] = {"gl-vs-embree", "exact", "foreign", "effects", "transparency", "none"};

struct CompareSettings {
  // Empty: chosen from the images (CompareResult::presetChoice says which and why): foreign for
  // another renderer's buffers, exact when both images' metadata name one engine, else effects
  // or transparency when the reference has effects or a transparent surface, else gl-vs-embree.
  std::string preset;
  CompareThresholds limits;    // each limit set here replaces the preset's
  bool ignoreCamera = false;   // compare even if the recorded cameras differ
  bool ignoreSettings = false; // compare even if the recorded render settings differ (then the
                               // preset's colour limit is not applied)
  // The worst pixels and the JSON report (they need the reference's masks, which take time);
  // false leaves them out.
  bool report = true;
};

struct CompareResult {
  std::string testName, referenceName;
  bool foreign = false;               // the test is another renderer's buffers (or a mesh drawn)
  std::string testDescription;        // its renderer, or what was compared
  std::string testDetails;            // lines under "test" (each ending in a newline), or ""
  std::string referenceDescription;   // the reference's renderer, "?" when not recorded
  std::string settingsLines;          // render settings that differ or were not recorded (lines)
  FrameComparison figures;
  std::string preset;                 // the limits judged by ("none": no limits)
  std::string presetChoice;           // the line saying why, when the preset was not given
  CompareThresholds limits;           // as applied: the preset's, with CompareSettings::limits
  std::string notes;                  // lines printed before the verdict
  std::vector<std::string> notCompared;  // limits on buffers the test does not carry
  std::vector<std::string> violations;   // limits exceeded: empty is a pass
  std::vector<std::string> hints;        // on a failure with another renderer's buffers: a
                                         // reading of them that fits ("hint: ..."); with a mesh:
                                         // that it looks to be in another frame
  std::vector<WorstPixel> worstPixels;   // with CompareSettings::report
  // What the difference image and the page draw.
  FrameBuffers testFrame;              // the test as compared (another renderer's: along the reference's rays)
  TestChannels carried;                // the buffers the test carries
  std::optional<Camera> camera;        // the reference's

  bool passed() const { return violations.empty(); }
  // The lines `surftrace compare` prints last: notes, limits not compared, then PASS (preset) or
  // FAIL (preset): with one line per violation and hint. No final newline.
  std::string verdict() const;
  // The report (`compare --report`): the figures, the signed depth error per patch kind and the
  // worst pixels. Needs CompareSettings::report.
  std::string json() const;
};

// Compares `test` with `reference`. Throws std::invalid_argument, naming the test or the
// reference, when they cannot be compared: their sizes differ, their recorded cameras or
// render settings differ (unless ignored), the reference records no camera for another
// renderer's buffers, or a depth value is impossible in its declared convention (with a hint
// at the convention that reads it).
CompareResult compare(const CompareTest& test, const CompareReference& reference, const CompareSettings& settings = {});
// The same, moving the test's SurfTrace buffers into the result rather than copying them.
CompareResult compare(CompareTest&& test, const CompareReference& reference, const CompareSettings& settings = {});

// The difference image (RGB, row 0 at the top, the reference's size; colours as
// kDifferenceLegend says), scaled to the limits the result was judged by.
std::vector<float> differenceImage(const CompareResult& result, const CompareReference& reference);
// kDifferenceLegend with the limits its colours are scaled to.
std::string differenceLegend(const CompareResult& result);
// The difference image as a PNG (or another 8-bit format, by `path`'s extension), its legend
// in the surftrace:legend attribute: encoded in memory, or written to `path` ("-": the standard
// output).
EncodedImage encodeDifference(const std::string& path, const CompareResult& result, const std::vector<float>& rgb);
void writeDifference(const std::string& path, const CompareResult& result, const std::vector<float>& rgb);
// The self-contained HTML page (`compare --html`): test, reference and `rgb` (differenceImage)
// side by side, the verdict, the per-kind table and the worst pixels. Needs CompareSettings::report.
std::string comparisonPage(const CompareResult& result, const CompareReference& reference, const std::vector<float>& rgb);

}  // namespace surftrace::view

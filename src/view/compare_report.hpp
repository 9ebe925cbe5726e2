// What `surftrace compare` shows beside its verdict: the signed depth error per patch kind, the
// worst pixels, and the self-contained HTML page (`compare --html`) that puts them next to the
// two images and their difference.
#pragma once

#include <cstddef>
#include <cstdint>
#include <string>
#include <vector>

#include <glm/vec3.hpp>
#include <nlohmann/json_fwd.hpp>

#include "view/camera.hpp"
#include "view/frame_buffers.hpp"
#include "view/image_compare.hpp"
#include "view/image_io.hpp"
#include "view/patch_kind.hpp"

namespace surftrace::view {

// The signed depth error (test − reference, Å: > 0 behind the reference) of one patch kind,
// over the pixels whose depth compareFrames measures (both hit, outside the silhouette band),
// the kind being the reference's; `pixels` counts the reference's hits of the kind.
struct KindDepthErrors {
  PatchKind kind = PatchKind::None;
  std::size_t pixels = 0, samples = 0;
  double median = 0.0, p1 = 0.0, p99 = 0.0;
  // Counts over kHistogramBins equal bins of [−histogramRange, histogramRange]; errors beyond
  // it fall into the end bins.
  double histogramRange = 0.0;
  std::vector<std::size_t> histogram;
};
inline constexpr int kHistogramBins = 41;

// One row per kind the reference shows, in kind order.
std::vector<KindDepthErrors> kindDepthErrors(const FrameBuffers& test, const FrameBuffers& reference,
                                             const ReferenceMasks& masks, const TestChannels& carried = {});

// A pixel worth a look: coverage differs, or the patch kind differs off the seams, or a large
// depth error; `point` is the reference's hit (the test's where only the test hits; needs a
// camera, else NaN) and `atom` its atom (~0u when not known).
struct WorstPixel {
  int x = 0, y = 0;
  std::string what;  // "coverage", "kind" or "depth"
  double depthError = 0.0;  // signed, Å (NaN for coverage)
  glm::dvec3 point{0.0};
  std::uint32_t atom = ~0u;
  PatchKind kind = PatchKind::None, testKind = PatchKind::None;
};

// The `count` worst pixels: coverage mismatches first, then kind mismatches, then by |depth error|.
std::vector<WorstPixel> worstPixels(const FrameBuffers& test, const FrameBuffers& reference, const ReferenceMasks& masks,
                                    const TestChannels& carried, const Camera* camera, std::size_t count = 20);

// The report's "per_kind" and "worst_pixels" entries.
nlohmann::json kindDepthErrorsJson(const std::vector<KindDepthErrors>& rows);
nlohmann::json worstPixelsJson(const std::vector<WorstPixel>& pixels);

// What the HTML page shows.
struct HtmlReport {
  std::string title;                  // e.g. "gl.exr vs reference.exr"
  std::string verdict;                // the lines `compare` prints
  std::string legend;                 // the difference image's colours in words
  EncodedImage test, reference, diff;  // PNGs
  int width = 0, height = 0;           // theirs
  std::string reportJson;             // the JSON report, with per_kind and worst_pixels
};

// One self-contained HTML page: the three images inlined as data: URIs side by side, zoomed and
// panned together (wheel and drag), the per-kind table and signed-error histograms (inline SVG)
// and the worst pixels, all drawn by the page's script from the JSON report it embeds.
std::string comparisonHtml(const HtmlReport& report);

// An 8-bit PNG of a frame's colour, or, for a frame without colour (another renderer's
// buffers), of its depth in grey (near light, far dark, misses black).
EncodedImage displayPng(const FrameBuffers& frame, bool hasColor);
// An 8-bit PNG of an RGB float image (differenceImage).
EncodedImage rgbPng(const std::vector<float>& rgb, int width, int height);

}  // namespace surftrace::view

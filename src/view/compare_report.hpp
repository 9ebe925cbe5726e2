// What `surftrace compare` shows beside its verdict: the worst pixels, and the self-contained
// HTML page (`compare --html`) that puts them next to the two images and their difference.
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

// The report's "worst_pixels" entry ("per_kind" is FrameComparison::json's).
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

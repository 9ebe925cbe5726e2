// Pixel-by-pixel comparison of two renderings of the same view (ORACLES D.4).
#include "view/image_compare.hpp"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <limits>
#include <optional>
#include <stdexcept>

#include <glm/common.hpp>
#include <glm/geometric.hpp>
#include <nlohmann/json.hpp>

#include "view/ray.hpp"

namespace surftrace::view {
namespace {

constexpr double kDegrees = 180.0 / 3.14159265358979323846;

double percentile(std::vector<double> v, double q) {
  if (v.empty()) return 0.0;
  const std::size_t i = std::min(v.size() - 1, static_cast<std::size_t>(q * static_cast<double>(v.size() - 1) + 0.5));
  std::nth_element(v.begin(), v.begin() + static_cast<std::ptrdiff_t>(i), v.end());
  return v[i];
}

// The reference's 3×3 neighbourhood decides which pixels are genuinely ambiguous.
PixelMask neighbourhood(const FrameBuffers& ref, int x, int y) {
  const int w = ref.width, h = ref.height;
  auto at = [w](int px, int py) { return static_cast<std::size_t>(py) * static_cast<std::size_t>(w) + static_cast<std::size_t>(px); };
  const std::size_t p = at(x, y);
  const bool hit = ref.kind[p] != 0;
  PixelMask n;
  for (int dy = -1; dy <= 1; ++dy)
    for (int dx = -1; dx <= 1; ++dx) {
      const std::size_t q = at(std::clamp(x + dx, 0, w - 1), std::clamp(y + dy, 0, h - 1));
      n.band = n.band || (ref.kind[q] != 0) != hit;
      n.kindSeam = n.kindSeam || ref.kind[q] != ref.kind[p];
      n.seam = n.seam || ref.patchId[q] != ref.patchId[p];
    }
  const bool flagged = (ref.flags[p] & (kHitGrazing | kHitCusp | kHitNearBoundary)) != 0;
  n.kindSeam = n.kindSeam || flagged;
  n.seam = n.seam || flagged;
  return n;
}

// The exact masks of pixel (x, y) (ReferenceMasks): the reference's edge flags, and its seam
// distance against what float rounding and the pixel's footprint allow.
PixelMask exactMask(const FrameBuffers& ref, const Camera& camera, const Camera::Frame& frame, int x, int y) {
  const std::size_t p = static_cast<std::size_t>(y) * static_cast<std::size_t>(ref.width) + static_cast<std::size_t>(x);
  PixelMask m;
  m.band = (ref.flags[p] & kPixelSilhouette) != 0;
  m.occlusion = (ref.flags[p] & kPixelOcclusion) != 0;
  if (ref.kind[p] == 0) return m;
  const double d = ref.seamDistance[p];
  if (std::isnan(d)) {
    const PixelMask n = neighbourhood(ref, x, y);
    m.kindSeam = n.kindSeam;
    m.seam = n.seam;
    return m;
  }
  const double t = ref.depth[p];
  const glm::dvec3 dir = glm::normalize(frame.ray(x + 0.5, y + 0.5).dir);
  const glm::dvec3 n(ref.normal[3 * p], ref.normal[3 * p + 1], ref.normal[3 * p + 2]);
  const double tolerance = seamTolerance(camera.pixelFootprint(t), t, static_cast<PatchKind>(ref.kind[p]));
  m.kindSeam = !(d * std::abs(glm::dot(n, dir)) >= tolerance) || (ref.flags[p] & (kHitGrazing | kHitCusp)) != 0;
  m.seam = m.kindSeam;
  return m;
}

// Whether the test image hits at pixel p: its patch kind when it carries kinds, else a finite depth.
bool testHits(const FrameBuffers& test, std::size_t p, const TestChannels& carried) {
  return carried.kind ? test.kind[p] != 0 : std::isfinite(test.depth[p]);
}

void checkSameSize(const FrameBuffers& a, const FrameBuffers& b) {
  if (a.width != b.width || a.height != b.height)
    throw std::invalid_argument("images differ in size: " + std::to_string(a.width) + "x" + std::to_string(a.height) +
                                " vs " + std::to_string(b.width) + "x" + std::to_string(b.height));
}

}  // namespace

double seamTolerance(double footprint, double t, PatchKind kind) {
  const double tangent = kind == PatchKind::Convex || kind == PatchKind::Toroidal ? std::sqrt(kSeamTangency * std::abs(t)) : 0.0;
  return kSeamFootprints * footprint + kSeamRelative * std::abs(t) + tangent;
}

ReferenceMasks referenceMasks(const FrameBuffers& ref, const Camera* camera) {
  ReferenceMasks masks;
  masks.exact = !ref.seamDistance.empty() && camera && camera->width == ref.width && camera->height == ref.height;
  if (!masks.exact)
    masks.note = ref.seamDistance.empty()
                     ? "the reference records no seam distances (an EXR from before they existed, or not from Embree): "
                       "seams and silhouettes masked by the 3x3 neighbourhood rule; re-render it with surftrace "
                       "render --exr to judge more pixels"
                     : "no camera: seams and silhouettes masked by the 3x3 neighbourhood rule";
  masks.mask.resize(ref.pixels());
  const std::optional<Camera::Frame> frame = masks.exact ? std::optional(camera->frame()) : std::nullopt;
  for (int y = 0; y < ref.height; ++y)
    for (int x = 0; x < ref.width; ++x)
      masks.mask[static_cast<std::size_t>(y) * static_cast<std::size_t>(ref.width) + static_cast<std::size_t>(x)] =
          masks.exact ? exactMask(ref, *camera, *frame, x, y) : neighbourhood(ref, x, y);
  return masks;
}

FrameComparison compareFrames(const FrameBuffers& test, const FrameBuffers& ref, const Camera* camera,
                              const TestChannels& carried) {
  checkSameSize(test, ref);
  FrameComparison c;
  c.pixels = ref.pixels();
  c.compared = carried;
  const ReferenceMasks masks = referenceMasks(ref, camera);
  c.exactMasks = masks.exact;
  c.masksNote = masks.note;
  std::vector<double> depth, depthPixels, angle, color;
  std::size_t kindSame = 0, patchSame = 0;
  double tMin = std::numeric_limits<double>::infinity(), tMax = 0.0;
  for (int y = 0; y < ref.height; ++y)
    for (int x = 0; x < ref.width; ++x) {
      const std::size_t p = static_cast<std::size_t>(y) * static_cast<std::size_t>(ref.width) + static_cast<std::size_t>(x);
      const bool refHit = ref.kind[p] != 0;
      if (refHit) tMin = std::min(tMin, static_cast<double>(ref.depth[p])), tMax = std::max(tMax, static_cast<double>(ref.depth[p]));
      c.referenceHits += refHit;
      const PixelMask& n = masks.mask[p];
      if (n.band) {
        ++c.silhouette;
        continue;
      }
      if (testHits(test, p, carried) != refHit) {
        ++c.coverageMismatch;
        continue;
      }
      if (carried.color && !n.kindSeam && test.rgba.size() == 4 * c.pixels && ref.rgba.size() == 4 * c.pixels) {
        double d = 0.0;
        for (int k = 0; k < 3; ++k) d = std::max(d, std::abs(static_cast<double>(test.rgba[4 * p + k]) - ref.rgba[4 * p + k]));
        color.push_back(d);
      }
      if (!refHit) continue;
      const double dt = std::abs(static_cast<double>(test.depth[p]) - static_cast<double>(ref.depth[p]));
      depth.push_back(dt);
      if (camera) depthPixels.push_back(dt / camera->pixelFootprint(ref.depth[p]));
      if (!n.kindSeam && carried.kind) {
        ++c.kindSamples;
        kindSame += test.kind[p] == ref.kind[p];
      }
      if (n.seam) continue;
      if (carried.normal) {
        const glm::dvec3 nt(test.normal[3 * p], test.normal[3 * p + 1], test.normal[3 * p + 2]);
        const glm::dvec3 nr(ref.normal[3 * p], ref.normal[3 * p + 1], ref.normal[3 * p + 2]);
        const double lt = glm::length(nt), lr = glm::length(nr);
        angle.push_back(lt > 0.0 && lr > 0.0 ? std::acos(std::clamp(glm::dot(nt / lt, nr / lr), -1.0, 1.0)) * kDegrees : 180.0);
      }
      if (carried.patchId) {
        ++c.patchSamples;
        patchSame += test.patchId[p] == ref.patchId[p];
      }
    }
  c.coverageFraction = static_cast<double>(c.coverageMismatch) / static_cast<double>(std::max<std::size_t>(1, c.pixels - c.silhouette));
  c.depthSamples = depth.size();
  c.depthMedian = percentile(depth, 0.5);
  c.depthP99 = percentile(depth, 0.99);
  c.depthMax = depth.empty() ? 0.0 : *std::max_element(depth.begin(), depth.end());
  c.depthP99Pixels = percentile(depthPixels, 0.99);
  if (c.kindSamples > 0) c.kindAgreement = static_cast<double>(kindSame) / static_cast<double>(c.kindSamples);
  if (c.patchSamples > 0) c.patchAgreement = static_cast<double>(patchSame) / static_cast<double>(c.patchSamples);
  c.normalMedianDegrees = percentile(angle, 0.5);
  c.normalP99Degrees = percentile(angle, 0.99);
  c.normalMaxDegrees = angle.empty() ? 0.0 : *std::max_element(angle.begin(), angle.end());
  c.colorSamples = color.size();
  c.colorMedian = percentile(color, 0.5);
  c.colorP99 = percentile(color, 0.99);
  c.colorMax = color.empty() ? 0.0 : *std::max_element(color.begin(), color.end());
  // The scene size is the reference's depth range, at least its nearest depth's tenth, so that
  // a flat close-up does not make every error look huge.
  c.sceneSize = tMax >= tMin ? std::max(tMax - tMin, 0.1 * tMin) : 0.0;
  return c;
}

std::string FrameComparison::summary() const {
  char text[640];
  std::snprintf(text, sizeof text,
                "coverage mismatch %zu of %zu px (%.4f%%; silhouette band %zu px masked)\n"
                "depth error      median %.3g  p99 %.3g  max %.3g Å  (p99 = %.3g of the scene size %.1f Å, %.3g px)\n",
                coverageMismatch, pixels - silhouette, 100.0 * coverageFraction, silhouette, depthMedian, depthP99, depthMax,
                sceneSize > 0 ? depthP99 / sceneSize : 0.0, sceneSize, depthP99Pixels);
  std::string out = text;
  if (compared.normal)
    std::snprintf(text, sizeof text, "normal error     median %.3g°  p99 %.3g°  max %.3g°\n", normalMedianDegrees,
                  normalP99Degrees, normalMaxDegrees);
  else
    std::snprintf(text, sizeof text, "normal error     not compared (the test image carries no normals)\n");
  out += text;
  if (compared.kind)
    std::snprintf(text, sizeof text, "patch kind       %.4f%% agree (%zu px, %.1f%% of the reference's %zu hits)\n",
                  100.0 * kindAgreement, kindSamples,
                  100.0 * static_cast<double>(kindSamples) / static_cast<double>(std::max<std::size_t>(1, referenceHits)),
                  referenceHits);
  else
    std::snprintf(text, sizeof text, "patch kind       not compared (the test image carries no patch kinds)\n");
  out += text;
  if (compared.patchId)
    std::snprintf(text, sizeof text, "patch id         %.4f%% agree (%zu px)", 100.0 * patchAgreement, patchSamples);
  else
    std::snprintf(text, sizeof text, "patch id         not compared (the test image carries no patch ids)");
  out += text;
  if (compared.color) {
    std::snprintf(text, sizeof text, "\ncolour error     median %.3g  p99 %.3g  max %.3g (largest of |dR|, |dG|, |dB|; %zu px)",
                  colorMedian, colorP99, colorMax, colorSamples);
    out += text;
  }
  if (!exactMasks) out += "\nmasks            " + masksNote;
  return out;
}

std::string FrameComparison::json() const {
  nlohmann::json j;
  j["pixels"] = pixels;
  j["reference_hits"] = referenceHits;
  j["masks"] = exactMasks ? nlohmann::json{{"exact", true}} : nlohmann::json{{"exact", false}, {"note", masksNote}};
  j["silhouette_band"] = silhouette;
  j["coverage"] = {{"mismatch", coverageMismatch}, {"fraction", coverageFraction}};
  j["depth"] = {{"samples", depthSamples},  {"median", depthMedian}, {"p99", depthP99}, {"max", depthMax},
                {"p99_relative", sceneSize > 0 ? depthP99 / sceneSize : 0.0}, {"p99_pixels", depthP99Pixels},
                {"scene_size", sceneSize}, {"unit", "Å"}};
  // A metric not compared keeps its key, with "compared": false and no figures to misread.
  j["normal_degrees"] = compared.normal ? nlohmann::json{{"compared", true}, {"median", normalMedianDegrees},
                                                         {"p99", normalP99Degrees}, {"max", normalMaxDegrees}}
                                        : nlohmann::json{{"compared", false}};
  j["patch_kind"] = compared.kind ? nlohmann::json{{"compared", true}, {"samples", kindSamples}, {"agreement", kindAgreement}}
                                  : nlohmann::json{{"compared", false}};
  j["patch_id"] = compared.patchId
                      ? nlohmann::json{{"compared", true}, {"samples", patchSamples}, {"agreement", patchAgreement}}
                      : nlohmann::json{{"compared", false}};
  if (compared.color)
    j["color"] = {{"compared", true}, {"samples", colorSamples}, {"median", colorMedian}, {"p99", colorP99}, {"max", colorMax}};
  else
    j["color"] = {{"compared", false}};
  return j.dump(1);
}

CompareThresholds CompareThresholds::preset(const std::string& name) {
  CompareThresholds t;
  if (name == "gl-vs-embree") {
    t.maxCoverageFraction = 1e-3;
    t.maxDepthP99Relative = 1e-3;
    t.minKindAgreement = 0.999;
  } else if (name == "exact") {
    t.maxCoverageFraction = 0.0;
    t.maxDepthP99Relative = 1e-6;
    t.minKindAgreement = 1.0;
    t.minPatchAgreement = 1.0;
    t.maxNormalP99Degrees = 1e-3;
  } else if (name == "foreign") {
    t.maxCoverageFraction = 1e-3;
    t.maxDepthP99Relative = 1e-3;
    t.maxNormalP99Degrees = 1.0;
  } else if (name == "effects") {
    t = preset("gl-vs-embree");
    t.maxColorP99 = 0.02;
  } else if (name == "transparency") {
    // GL's depth peeling against Embree's exact layers at --opacity < 1: measured p99 <= 2.6e-6
    // (1CRN SES, 1GRM skin s = 0.5, 1CRN vdW, opacity 0.4 and 0.7, 256²); a layer missed or
    // doubled in 1% of the pixels would cost α·|Δc| ~ 0.05 there.
    t = preset("gl-vs-embree");
    t.maxColorP99 = 1e-3;
  } else {
    throw std::invalid_argument("unknown preset '" + name + "': use gl-vs-embree, exact, foreign, effects or transparency");
  }
  return t;
}

std::vector<std::string> CompareThresholds::violations(const FrameComparison& c) const {
  std::vector<std::string> v;
  char line[256];
  const double relative = c.sceneSize > 0 ? c.depthP99 / c.sceneSize : 0.0;
  if (maxCoverageFraction && c.coverageFraction > *maxCoverageFraction)
    std::snprintf(line, sizeof line, "coverage mismatch %.4g%% > %.4g%%", 100 * c.coverageFraction, 100 * *maxCoverageFraction), v.emplace_back(line);
  if (maxDepthP99Relative && relative > *maxDepthP99Relative)
    std::snprintf(line, sizeof line, "depth p99 %.3g of the scene (%.3g Å) > %.3g", relative, c.depthP99, *maxDepthP99Relative), v.emplace_back(line);
  if (minKindAgreement && c.compared.kind && c.kindAgreement < *minKindAgreement)
    std::snprintf(line, sizeof line, "patch-kind agreement %.4f%% < %.4f%%", 100 * c.kindAgreement, 100 * *minKindAgreement), v.emplace_back(line);
  if (minPatchAgreement && c.compared.patchId && c.patchAgreement < *minPatchAgreement)
    std::snprintf(line, sizeof line, "patch-id agreement %.4f%% < %.4f%%", 100 * c.patchAgreement, 100 * *minPatchAgreement), v.emplace_back(line);
  if (maxNormalP99Degrees && c.compared.normal && c.normalP99Degrees > *maxNormalP99Degrees)
    std::snprintf(line, sizeof line, "normal p99 %.3g° > %.3g°", c.normalP99Degrees, *maxNormalP99Degrees), v.emplace_back(line);
  if (maxColorP99 && c.compared.color && c.colorP99 > *maxColorP99)
    std::snprintf(line, sizeof line, "colour p99 %.3g > %.3g", c.colorP99, *maxColorP99), v.emplace_back(line);
  return v;
}

std::vector<std::string> CompareThresholds::notCompared(const FrameComparison& c) const {
  std::vector<std::string> v;
  char line[256];
  if (maxNormalP99Degrees && !c.compared.normal)
    std::snprintf(line, sizeof line, "normal p99 < %.3g° (the test image carries no normals)", *maxNormalP99Degrees),
        v.emplace_back(line);
  if (minKindAgreement && !c.compared.kind)
    std::snprintf(line, sizeof line, "patch-kind agreement > %.4g%% (the test image carries no patch kinds)",
                  100 * *minKindAgreement),
        v.emplace_back(line);
  if (minPatchAgreement && !c.compared.patchId)
    std::snprintf(line, sizeof line, "patch-id agreement > %.4g%% (the test image carries no patch ids)",
                  100 * *minPatchAgreement),
        v.emplace_back(line);
  if (maxColorP99 && !c.compared.color)
    std::snprintf(line, sizeof line, "colour p99 < %.3g (the test image carries no colour)", *maxColorP99), v.emplace_back(line);
  return v;
}

DifferenceScale DifferenceScale::of(const CompareThresholds& limits, const FrameComparison& c) {
  DifferenceScale scale;
  if (limits.maxDepthP99Relative) scale.depthLimit = *limits.maxDepthP99Relative * c.sceneSize;
  if (c.compared.color) scale.colorLimit = limits.maxColorP99;
  return scale;
}

namespace {

glm::vec3 color(const float (&c)[3]) { return {c[0], c[1], c[2]}; }

// The depth error's colour: quiet below a tenth of the limit, towards yellow up to it, then
// orange to magenta up to 100 times it, each on a log scale.
glm::vec3 depthColor(double error, double limit) {
  namespace dc = difference_colors;
  const double r = error / limit;
  if (!(r >= 0.1)) return color(dc::kQuiet);
  if (r <= 1.0) return glm::mix(color(dc::kQuiet), color(dc::kWithin), static_cast<float>(std::log10(r) + 1.0));
  return glm::mix(color(dc::kOver), color(dc::kFarOver), static_cast<float>(std::min(1.0, std::log10(r) / 2.0)));
}

}  // namespace

std::vector<float> differenceImage(const FrameBuffers& test, const FrameBuffers& ref, const TestChannels& carried,
                                   const Camera* camera, const DifferenceScale& scale) {
  namespace dc = difference_colors;
  checkSameSize(test, ref);
  const ReferenceMasks masks = referenceMasks(ref, camera);
  double depthLimit = scale.depthLimit;
  if (!(depthLimit > 0.0)) {
    double tMin = std::numeric_limits<double>::infinity(), tMax = 0.0;
    for (std::size_t p = 0; p < ref.pixels(); ++p)
      if (ref.kind[p] != 0) tMin = std::min(tMin, static_cast<double>(ref.depth[p])), tMax = std::max(tMax, static_cast<double>(ref.depth[p]));
    depthLimit = tMax >= tMin ? 1e-3 * std::max(tMax - tMin, 0.1 * tMin) : 1e-3;
    if (!(depthLimit > 0.0)) depthLimit = 1e-3;
  }
  const bool colors = scale.colorLimit && carried.color && test.rgba.size() == 4 * ref.pixels() &&
                      ref.rgba.size() == 4 * ref.pixels();
  std::vector<float> rgb(3 * ref.pixels(), 0.0f);
  for (std::size_t p = 0; p < ref.pixels(); ++p) {
    const PixelMask& m = masks.mask[p];
    const bool refHit = ref.kind[p] != 0, testHit = testHits(test, p, carried);
    double colorError = 0.0;
    if (colors)
      for (int k = 0; k < 3; ++k)
        colorError = std::max(colorError, std::abs(static_cast<double>(test.rgba[4 * p + k]) - ref.rgba[4 * p + k]));
    glm::vec3 c = color(dc::kBackground);
    if (m.band)
      c = color(dc::kBand);
    else if (refHit != testHit)
      c = color(dc::kCoverage);
    else if (refHit && carried.kind && !m.kindSeam && test.kind[p] != ref.kind[p])
      c = color(dc::kKind);
    else if (colors && !m.kindSeam && colorError > *scale.colorLimit)
      c = color(dc::kColor);
    else if (refHit)
      c = depthColor(std::abs(static_cast<double>(test.depth[p]) - static_cast<double>(ref.depth[p])), depthLimit);
    rgb[3 * p] = c.x, rgb[3 * p + 1] = c.y, rgb[3 * p + 2] = c.z;
  }
  return rgb;
}

}  // namespace surftrace::view

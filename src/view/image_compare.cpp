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

#include "view/patch_kind.hpp"
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

double largest(const std::vector<double>& v) { return v.empty() ? 0.0 : *std::max_element(v.begin(), v.end()); }

std::size_t index(const FrameBuffers& f, int x, int y) {
  return static_cast<std::size_t>(y) * static_cast<std::size_t>(f.width) + static_cast<std::size_t>(x);
}

glm::dvec3 normalAt(const FrameBuffers& f, std::size_t p) {
  return {f.normal[3 * p], f.normal[3 * p + 1], f.normal[3 * p + 2]};
}

// The angle (degrees) between two normals; 180 when either is zero.
double normalAngle(const glm::dvec3& a, const glm::dvec3& b) {
  const double la = glm::length(a), lb = glm::length(b);
  return la > 0.0 && lb > 0.0 ? std::acos(std::clamp(glm::dot(a / la, b / lb), -1.0, 1.0)) * kDegrees : 180.0;
}

// The per-kind table from the depth (and normal) samples: pixel p, signed error t_test − t_ref.
struct KindSample {
  std::size_t pixel;
  double value;
};
std::vector<KindErrors> kindTable(const FrameBuffers& ref, const std::vector<KindSample>& depth,
                                  const std::vector<KindSample>& normal) {
  std::vector<std::size_t> pixels(kPatchKindCount + 1, 0);
  for (std::uint32_t k : ref.kind)
    if (k != 0 && k <= kPatchKindCount) ++pixels[k];
  auto kindOf = [&](const std::vector<KindSample>& samples) {
    std::vector<KindValue> out;
    out.reserve(samples.size());
    for (const KindSample& s : samples) out.push_back({ref.kind[s.pixel], s.value});
    return out;
  };
  return kindErrors(pixels, kindOf(depth), kindOf(normal));
}

// "none compared" for a statistic without samples, else the figures.
std::string figures(std::size_t samples, const char* format, double a, double b, double c) {
  if (samples == 0) return "none compared (0 px)";
  char text[160];
  std::snprintf(text, sizeof text, format, a, b, c);
  return text;
}

}  // namespace

std::vector<KindErrors> kindErrors(std::span<const std::size_t> pixelsPerKind, const std::vector<KindValue>& depth,
                                   const std::vector<KindValue>& normal) {
  std::vector<KindErrors> rows;
  std::vector<std::vector<double>> signedError(kPatchKindCount + 1), angle(kPatchKindCount + 1);
  auto row = [](std::uint32_t kind) { return std::min<std::size_t>(kind, kPatchKindCount); };
  for (const KindValue& s : depth) signedError[row(s.kind)].push_back(s.value);
  for (const KindValue& s : normal) angle[row(s.kind)].push_back(s.value);
  for (std::size_t k = 1; k <= kPatchKindCount; ++k) {
    if (k >= pixelsPerKind.size() || pixelsPerKind[k] == 0) continue;
    KindErrors e;
    e.kind = static_cast<std::uint32_t>(k);
    e.pixels = pixelsPerKind[k];
    e.samples = signedError[k].size();
    e.depthMedian = percentile(signedError[k], 0.5);
    e.depthP1 = percentile(signedError[k], 0.01);
    e.depthP99 = percentile(signedError[k], 0.99);
    for (double v : signedError[k]) e.inFront += v < 0.0, e.behind += v > 0.0;
    e.normalSamples = angle[k].size();
    e.normalMedianDegrees = percentile(angle[k], 0.5);
    e.normalP99Degrees = percentile(angle[k], 0.99);
    e.histogramRange = 1.25 * std::max(std::abs(e.depthP1), std::abs(e.depthP99));
    if (!(e.histogramRange > 0.0)) e.histogramRange = 1e-6;
    e.histogram.assign(kHistogramBins, 0);
    for (const double v : signedError[k]) {
      const double at = (v + e.histogramRange) / (2.0 * e.histogramRange) * kHistogramBins;
      e.histogram[static_cast<std::size_t>(std::clamp(std::floor(at), 0.0, kHistogramBins - 1.0))]++;
    }
    rows.push_back(std::move(e));
  }
  return rows;
}

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

std::vector<std::uint8_t> occlusionEdges(const FrameBuffers& ref, const Camera& camera) {
  const int w = ref.width, h = ref.height;
  std::vector<std::uint8_t> edge(ref.pixels(), 0);
  if (camera.width != w || camera.height != h) return edge;
  const Camera::Frame frame = camera.frame();
  // tan θ between each hit's normal and its ray (∞ edge-on or without a normal).
  std::vector<double> slope(ref.pixels(), std::numeric_limits<double>::infinity());
  for (int y = 0; y < h; ++y)
    for (int x = 0; x < w; ++x) {
      const std::size_t p = index(ref, x, y);
      if (ref.kind[p] == 0) continue;
      const glm::dvec3 n = normalAt(ref, p);
      const double len = glm::length(n);
      if (!(len > 0.0)) continue;
      const double c = std::abs(glm::dot(n / len, frame.ray(x + 0.5, y + 0.5).dir));
      if (c > 0.0) slope[p] = std::sqrt(std::max(0.0, 1.0 - c * c)) / c;
    }
  for (int y = 0; y < h; ++y)
    for (int x = 0; x < w; ++x) {
      const std::size_t p = index(ref, x, y);
      if (ref.kind[p] == 0 || !std::isfinite(ref.depth[p])) continue;
      for (int dy = -1; dy <= 1 && !edge[p]; ++dy)
        for (int dx = -1; dx <= 1; ++dx) {
          const int qx = x + dx, qy = y + dy;
          if ((dx == 0 && dy == 0) || qx < 0 || qy < 0 || qx >= w || qy >= h) continue;
          const std::size_t q = index(ref, qx, qy);
          if (ref.kind[q] == 0 || !std::isfinite(ref.depth[q])) continue;
          const double step = std::abs(static_cast<double>(ref.depth[q]) - ref.depth[p]);
          const double reach = camera.pixelFootprint(std::min(ref.depth[p], ref.depth[q])) * std::hypot(dx, dy);
          if (step > reach * (2.0 * std::min(slope[p], slope[q]) + 1.0)) {
            edge[p] = 1;
            break;
          }
        }
    }
  return edge;
}

NanCounts countNan(const FrameBuffers& f, const TestChannels& carried, std::vector<std::uint8_t>* mask) {
  NanCounts n;
  if (mask) mask->assign(f.pixels(), 0);
  for (std::size_t p = 0; p < f.pixels(); ++p) {
    const bool depth = std::isnan(f.depth[p]);
    const bool normal = carried.normal && f.normal.size() == 3 * f.pixels() &&
                        (std::isnan(f.normal[3 * p]) || std::isnan(f.normal[3 * p + 1]) || std::isnan(f.normal[3 * p + 2]));
    bool color = false;
    if (carried.color && f.rgba.size() == 4 * f.pixels())
      for (int k = 0; k < 4; ++k) color = color || std::isnan(f.rgba[4 * p + static_cast<std::size_t>(k)]);
    n.depth += depth, n.normal += normal, n.color += color;
    if (depth || normal || color) {
      ++n.pixels;
      if (mask) (*mask)[p] = 1;
    }
  }
  return n;
}

FrameComparison compareFrames(const FrameBuffers& test, const FrameBuffers& ref, const Camera* camera,
                              const TestChannels& carried, FrameSamples* samples) {
  checkSameSize(test, ref);
  FrameComparison c;
  c.pixels = ref.pixels();
  c.compared = carried;
  const ReferenceMasks masks = referenceMasks(ref, camera);
  c.exactMasks = masks.exact;
  c.masksNote = masks.note;
  std::vector<double> depth, depthPixels, angle, color, background, occludedDepth;
  std::vector<KindSample> signedDepth, kindAngle;
  std::vector<std::uint8_t> nanTest, nanRef;
  c.nanTest = countNan(test, carried, &nanTest);
  c.nanReference = countNan(ref, TestChannels{}, &nanRef);
  // Occlusion edges: what the exact tracer recorded and what the reference's buffers show. The
  // tracer's flag (a chord between the centre's and a corner's hit that leaves a tangent plane
  // by more than 30°) misses a jump between two sheets both seen obliquely: 9 Å across a 0.16 Å
  // pixel between two atoms seen 70° off their normals reads as smooth to it, not to the steps.
  std::vector<std::uint8_t> occluded(ref.pixels(), 0);
  if (camera) occluded = occlusionEdges(ref, *camera);
  if (masks.exact)
    for (std::size_t p = 0; p < ref.pixels(); ++p) occluded[p] = occluded[p] || masks.mask[p].occlusion;
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
      if (nanTest[p] || nanRef[p]) continue;  // counted in nanTest / nanReference, judged there
      if (testHits(test, p, carried) != refHit) {
        ++c.coverageMismatch;
        continue;
      }
      const double signedDt = static_cast<double>(test.depth[p]) - static_cast<double>(ref.depth[p]);
      // At an occlusion edge the depth error is kept apart; kind, id, normal and colour are
      // judged there as the seam masks allow (the centre's hit is as definite as anywhere).
      const bool occlusion = refHit && occluded[p];
      if (occlusion) {
        ++c.occlusionEdge;
        occludedDepth.push_back(std::abs(signedDt));
      }
      if (carried.color && !n.kindSeam && test.rgba.size() == 4 * c.pixels && ref.rgba.size() == 4 * c.pixels) {
        double d = 0.0;
        for (int k = 0; k < 3; ++k) d = std::max(d, std::abs(static_cast<double>(test.rgba[4 * p + k]) - ref.rgba[4 * p + k]));
        (refHit ? color : background).push_back(d);
      }
      if (!refHit) continue;
      if (!occlusion) {
        const double dt = std::abs(signedDt);
        depth.push_back(dt);
        signedDepth.push_back({p, signedDt});
        if (camera) depthPixels.push_back(dt / camera->pixelFootprint(ref.depth[p]));
      }
      if (!n.kindSeam && carried.kind) {
        ++c.kindSamples;
        kindSame += test.kind[p] == ref.kind[p];
      }
      if (n.seam) continue;
      if (carried.normal) {
        angle.push_back(normalAngle(normalAt(test, p), normalAt(ref, p)));
        kindAngle.push_back({p, angle.back()});
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
  c.depthMax = largest(depth);
  c.depthP99Pixels = percentile(depthPixels, 0.99);
  if (c.kindSamples > 0) c.kindAgreement = static_cast<double>(kindSame) / static_cast<double>(c.kindSamples);
  if (c.patchSamples > 0) c.patchAgreement = static_cast<double>(patchSame) / static_cast<double>(c.patchSamples);
  c.normalSamples = angle.size();
  c.normalMedianDegrees = percentile(angle, 0.5);
  c.normalP99Degrees = percentile(angle, 0.99);
  c.normalMaxDegrees = largest(angle);
  c.colorSamples = color.size();
  c.colorMedian = percentile(color, 0.5);
  c.colorP99 = percentile(color, 0.99);
  c.colorMax = largest(color);
  c.backgroundSamples = background.size();
  c.backgroundMedian = percentile(background, 0.5);
  c.backgroundP99 = percentile(background, 0.99);
  c.backgroundMax = largest(background);
  c.occlusionDepthMedian = percentile(occludedDepth, 0.5);
  c.occlusionDepthP99 = percentile(occludedDepth, 0.99);
  c.occlusionDepthMax = largest(occludedDepth);
  c.perKind = kindTable(ref, signedDepth, kindAngle);
  if (samples) {
    samples->depth.clear();
    samples->depth.reserve(signedDepth.size());
    for (const KindSample& d : signedDepth) samples->depth.push_back({d.pixel, d.value});
    samples->normal.clear();
    for (const KindSample& a : kindAngle) samples->normal.push_back({a.pixel, a.value});
    samples->coverage.clear();
    for (std::size_t p = 0; p < ref.pixels(); ++p)
      if (!masks.mask[p].band && !nanTest[p] && !nanRef[p] && testHits(test, p, carried) != (ref.kind[p] != 0))
        samples->coverage.push_back(p);
  }
  // The scene size is the reference's depth range, at least its nearest depth's tenth, so that
  // a flat close-up does not make every error look huge.
  c.sceneSize = tMax >= tMin ? std::max(tMax - tMin, 0.1 * tMin) : 0.0;
  return c;
}

std::string kindTableText(const std::vector<KindErrors>& perKind, bool normalsCompared, const std::string& referenceName,
                          const std::string& difference) {
  char text[512];
  std::string out = "per patch kind of the " + referenceName + " (depth error signed, " + difference + ", Å: < 0 in front)\n"
                    "  kind              pixels  compared    median        p1       p99  in front    behind  normal median / p99";
  for (const KindErrors& k : perKind) {
    char normal[64] = "    not compared";
    if (normalsCompared && k.normalSamples > 0)
      std::snprintf(normal, sizeof normal, "  %10.3g° / %.3g°", k.normalMedianDegrees, k.normalP99Degrees);
    else if (normalsCompared)
      std::snprintf(normal, sizeof normal, "  none compared");
    if (k.samples == 0)
      std::snprintf(text, sizeof text, "\n  %u %-14s %7zu %9zu  none compared", k.kind,
                    patchKindName(static_cast<PatchKind>(k.kind)), k.pixels, k.samples);
    else
      std::snprintf(text, sizeof text, "\n  %u %-14s %7zu %9zu %9.3g %9.3g %9.3g %9zu %9zu%s", k.kind,
                    patchKindName(static_cast<PatchKind>(k.kind)), k.pixels, k.samples, k.depthMedian, k.depthP1,
                    k.depthP99, k.inFront, k.behind, normal);
    out += text;
  }
  return out;
}

std::string kindTableJson(const std::vector<KindErrors>& perKind, bool normalsCompared, const std::string& difference) {
  nlohmann::json kinds = nlohmann::json::array();
  for (const KindErrors& k : perKind) {
    nlohmann::json row = {{"kind", patchKindName(static_cast<PatchKind>(k.kind))},
                          {"code", k.kind},
                          {"pixels", k.pixels},
                          {"samples", k.samples},
                          {"median", k.depthMedian},
                          {"p1", k.depthP1},
                          {"p99", k.depthP99},
                          {"unit", "Å, " + difference},
                          {"in_front", k.inFront},
                          {"behind", k.behind},
                          {"histogram", {{"range", k.histogramRange}, {"counts", k.histogram}}}};
    row["normal_degrees"] = normalsCompared ? nlohmann::json{{"compared", true}, {"samples", k.normalSamples},
                                                             {"median", k.normalMedianDegrees}, {"p99", k.normalP99Degrees}}
                                            : nlohmann::json{{"compared", false}};
    kinds.push_back(row);
  }
  return kinds.dump(1);
}

std::string FrameComparison::summary() const {
  char text[640];
  std::snprintf(text, sizeof text, "coverage mismatch %zu of %zu px (%.4f%%; silhouette band %zu px masked)\n",
                coverageMismatch, pixels - silhouette, 100.0 * coverageFraction, silhouette);
  std::string out = text;
  if (depthSamples == 0) {
    out += "depth error      none compared (0 px)\n";
  } else {
    std::snprintf(text, sizeof text,
                  "depth error      median %.3g  p99 %.3g  max %.3g Å  (p99 = %.3g of the scene size %.1f Å, %.3g px)\n",
                  depthMedian, depthP99, depthMax, sceneSize > 0 ? depthP99 / sceneSize : 0.0, sceneSize, depthP99Pixels);
    out += text;
  }
  if (occlusionEdge > 0)
    std::snprintf(text, sizeof text,
                  "occlusion edges  %zu px (one part of the surface hides another; not in the depth error above): median "
                  "%.3g  p99 %.3g  max %.3g Å\n",
                  occlusionEdge, occlusionDepthMedian, occlusionDepthP99, occlusionDepthMax);
  else
    std::snprintf(text, sizeof text, "occlusion edges  0 px\n");
  out += text;
  if (compared.normal)
    out += "normal error     " + figures(normalSamples, "median %.3g°  p99 %.3g°  max %.3g°", normalMedianDegrees,
                                         normalP99Degrees, normalMaxDegrees) + "\n";
  else
    out += "normal error     not compared (the test image carries no normals)\n";
  if (!compared.kind)
    out += "patch kind       not compared (the test image carries no patch kinds)\n";
  else if (kindSamples == 0)
    out += "patch kind       none compared (0 px)\n";
  else
    std::snprintf(text, sizeof text, "patch kind       %.4f%% agree (%zu px, %.1f%% of the reference's %zu hits)\n",
                  100.0 * kindAgreement, kindSamples,
                  100.0 * static_cast<double>(kindSamples) / static_cast<double>(std::max<std::size_t>(1, referenceHits)),
                  referenceHits),
        out += text;
  if (!compared.patchId)
    out += "patch id         not compared (the test image carries no patch ids)";
  else if (patchSamples == 0)
    out += "patch id         none compared (0 px)";
  else
    std::snprintf(text, sizeof text, "patch id         %.4f%% agree (%zu px)", 100.0 * patchAgreement, patchSamples), out += text;
  if (compared.color) {
    std::snprintf(text, sizeof text, " (largest of |dR|, |dG|, |dB|; %zu covered px)", colorSamples);
    out += "\ncolour error     " + figures(colorSamples, "median %.3g  p99 %.3g  max %.3g", colorMedian, colorP99, colorMax) +
           (colorSamples > 0 ? text : "");
    std::snprintf(text, sizeof text, " (%zu px)", backgroundSamples);
    out += "\nbackground       " +
           (backgroundSamples == 0 ? std::string("none (no background pixel to compare)")
                                   : figures(backgroundSamples, "median %.3g  p99 %.3g  max %.3g", backgroundMedian,
                                             backgroundP99, backgroundMax) + text);
  }
  if (!exactMasks) out += "\nmasks            " + masksNote;
  auto nanText = [](const NanCounts& n) {
    if (n.pixels == 0) return std::string("none");
    char t[160];
    std::snprintf(t, sizeof t, "depth %zu px, normal %zu px, colour %zu px", n.depth, n.normal, n.color);
    return std::string(t);
  };
  if (nanTest.pixels + nanReference.pixels > 0)
    out += "\nNaN              test: " + nanText(nanTest) + "; reference: " + nanText(nanReference) + " (mismatches)";
  if (!perKind.empty()) out += "\n" + kindTableText(perKind, compared.normal, "reference", "test − reference");
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
  j["occlusion_edges"] = {{"pixels", occlusionEdge},
                          {"depth", {{"median", occlusionDepthMedian}, {"p99", occlusionDepthP99}, {"max", occlusionDepthMax}}}};
  // A metric not compared keeps its key, with "compared": false and no figures to misread.
  j["normal_degrees"] = compared.normal ? nlohmann::json{{"compared", true}, {"samples", normalSamples}, {"median", normalMedianDegrees},
                                                         {"p99", normalP99Degrees}, {"max", normalMaxDegrees}}
                                        : nlohmann::json{{"compared", false}};
  j["patch_kind"] = compared.kind ? nlohmann::json{{"compared", true}, {"samples", kindSamples}, {"agreement", kindAgreement}}
                                  : nlohmann::json{{"compared", false}};
  j["patch_id"] = compared.patchId
                      ? nlohmann::json{{"compared", true}, {"samples", patchSamples}, {"agreement", patchAgreement}}
                      : nlohmann::json{{"compared", false}};
  if (compared.color) {
    j["color"] = {{"compared", true}, {"samples", colorSamples}, {"median", colorMedian}, {"p99", colorP99}, {"max", colorMax}};
    j["color_background"] = {{"compared", true},        {"samples", backgroundSamples}, {"median", backgroundMedian},
                             {"p99", backgroundP99}, {"max", backgroundMax}};
  } else {
    j["color"] = {{"compared", false}};
    j["color_background"] = {{"compared", false}};
  }
  auto nanJson = [](const NanCounts& n) {
    return nlohmann::json{{"pixels", n.pixels}, {"depth", n.depth}, {"normal", n.normal}, {"color", n.color}};
  };
  j["nan"] = {{"test", nanJson(nanTest)}, {"reference", nanJson(nanReference)}};
  // Keyed by the kind's name (the HTML page's plots are named so), with its code beside it.
  j["per_kind"] = nlohmann::json::parse(kindTableJson(perKind, compared.normal, "test − reference"));
  return j.dump(1);
}

CompareThresholds CompareThresholds::preset(const std::string& name) {
  CompareThresholds t;
  t.maxNanPixels = 0;  // every preset: a NaN is never a value a renderer meant
  if (name == "gl-vs-embree") {
    t.maxCoverageFraction = 1e-3;
    t.maxDepthP99Relative = 1e-3;
    t.minKindAgreement = 0.999;
    // The two engines shade with the same formula, GL in float: measured colour p99 <= 1.9e-5
    // over the covered pixels and <= 2.4e-7 over the background (GL on llvmpipe against Embree,
    // exact masks: every reference/ case, and 1CRN, 1GRM skin, 1VIS, 1AON SES and skin at 256² in
    // every colour scheme, vdW, SAS, ortho, ball and stick, a black background, a 512² close-up);
    // one 8-bit step (3.9e-3) is above the limit.
    t.maxColorP99 = 1e-3;
  } else if (name == "exact") {
    t.maxCoverageFraction = 0.0;
    t.maxDepthP99Relative = 1e-6;
    t.minKindAgreement = 1.0;
    t.minPatchAgreement = 1.0;
    t.maxNormalP99Degrees = 1e-3;
    t.maxColorP99 = 1e-5;  // the same engine and settings: float rounding of the shading
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
  // A limit over no samples: whatever was meant to be measured was not.
  auto none = [&v](const char* what, const char* why) { v.push_back(std::string(what) + ": none compared (" + why + ")"); };
  const double relative = c.sceneSize > 0 ? c.depthP99 / c.sceneSize : 0.0;
  if (maxCoverageFraction && c.pixels == c.silhouette)
    none("coverage", "every pixel lies in the silhouette band");
  else if (maxCoverageFraction && c.coverageFraction > *maxCoverageFraction)
    std::snprintf(line, sizeof line, "coverage mismatch %.4g%% > %.4g%%", 100 * c.coverageFraction, 100 * *maxCoverageFraction), v.emplace_back(line);
  if (maxDepthP99Relative && c.depthSamples == 0)
    none("depth", "no pixel where both images hit, outside the masks");
  else if (maxDepthP99Relative && relative > *maxDepthP99Relative)
    std::snprintf(line, sizeof line, "depth p99 %.3g of the scene (%.3g Å) > %.3g", relative, c.depthP99, *maxDepthP99Relative), v.emplace_back(line);
  if (minKindAgreement && c.compared.kind && c.kindSamples == 0)
    none("patch kind", "no pixel where both images hit, off seams and masks");
  else if (minKindAgreement && c.compared.kind && c.kindAgreement < *minKindAgreement)
    std::snprintf(line, sizeof line, "patch-kind agreement %.4f%% < %.4f%%", 100 * c.kindAgreement, 100 * *minKindAgreement), v.emplace_back(line);
  if (minPatchAgreement && c.compared.patchId && c.patchSamples == 0)
    none("patch id", "no pixel where both images hit, off seams and masks");
  else if (minPatchAgreement && c.compared.patchId && c.patchAgreement < *minPatchAgreement)
    std::snprintf(line, sizeof line, "patch-id agreement %.4f%% < %.4f%%", 100 * c.patchAgreement, 100 * *minPatchAgreement), v.emplace_back(line);
  if (maxNormalP99Degrees && c.compared.normal && c.normalSamples == 0)
    none("normal", "no pixel where both images hit, off seams and masks");
  else if (maxNormalP99Degrees && c.compared.normal && c.normalP99Degrees > *maxNormalP99Degrees)
    std::snprintf(line, sizeof line, "normal p99 %.3g° > %.3g°", c.normalP99Degrees, *maxNormalP99Degrees), v.emplace_back(line);
  if (maxColorP99 && c.compared.color && c.colorSamples == 0)
    none("colour", "no covered pixel where both images hit, off seams and masks");
  else if (maxColorP99 && c.compared.color && c.colorP99 > *maxColorP99)
    std::snprintf(line, sizeof line, "colour p99 %.3g > %.3g (covered pixels)", c.colorP99, *maxColorP99), v.emplace_back(line);
  // The background is judged where the reference has some (a close-up may have none).
  if (maxColorP99 && c.compared.color && c.backgroundP99 > *maxColorP99)
    std::snprintf(line, sizeof line, "background colour p99 %.3g > %.3g", c.backgroundP99, *maxColorP99), v.emplace_back(line);
  for (const auto& [n, whose] : {std::pair{&c.nanTest, "the test"}, std::pair{&c.nanReference, "the reference"}})
    if (maxNanPixels && n->pixels > *maxNanPixels)
      std::snprintf(line, sizeof line, "NaN in %zu px of %s (depth %zu, normal %zu, colour %zu) > %zu", n->pixels, whose,
                    n->depth, n->normal, n->color, *maxNanPixels),
          v.emplace_back(line);
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

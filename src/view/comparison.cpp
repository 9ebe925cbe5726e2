// `compare` as one call (comparison.hpp): the test read into the reference's view, the checks
// that the two are renderings of one view made alike, the figures, the limits and the verdict.
#include "view/comparison.hpp"

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdio>
#include <stdexcept>
#include <utility>

#include <nlohmann/json.hpp>

#include "view/render_settings.hpp"

namespace surftrace::view {
namespace {

// Another renderer's buffers read into the reference's view.
struct ForeignReading {
  FrameBuffers frame;
  TestChannels carried;
  std::string description;
  std::string details;  // lines under "test", each ending in a newline
};

std::string sizeMismatch(const std::string& test, int tw, int th, const std::string& ref, int rw, int rh) {
  return test + " is " + std::to_string(tw) + "x" + std::to_string(th) + " but " + ref + " is " + std::to_string(rw) + "x" +
         std::to_string(rh);
}

// The engine that made an image, from its metadata: "embree", "gl", or "" when not recorded
// (an image from another program).
std::string engineOf(const ImageMetadata& meta) {
  if (const auto e = meta.find("surftrace:engine"); e != meta.end()) return e->second;
  if (const auto r = meta.find("surftrace:renderer"); r != meta.end()) {
    if (r->second.find(" gl:") != std::string::npos) return "gl";
    if (r->second.find(" embree ") != std::string::npos) return "embree";
  }
  return "";
}

// Without a preset given, the strict limits for the pair of engines: `exact` for two images of
// one engine; otherwise (different engines, or one not recorded) `effects` when the reference has
// image-space effects, `transparency` when its surface is transparent, else `gl-vs-embree`.
// `why` gets the line that says which, and why.
std::string defaultPreset(const ImageMetadata& test, const ImageMetadata& ref, std::string& why) {
  const std::string a = engineOf(test), b = engineOf(ref);
  std::string preset = !a.empty() && a == b                ? "exact"
                       : ref.count("surftrace:effects") > 0 ? "effects"
                       : ref.count("surftrace:opacity") > 0 ? "transparency"
                                                            : "gl-vs-embree";
  why = "limits    --preset " + preset + " (engines: test " + (a.empty() ? "not recorded" : a) + ", reference " +
        (b.empty() ? "not recorded" : b) +
        (preset == "effects" ? "; image-space effects" : preset == "transparency" ? "; transparent surface" : "") +
        "; pass --preset to choose)";
  return preset;
}

// Another renderer's buffers along the reference camera's rays, read with `f`.
ForeignReading readForeign(const ForeignBuffers& b, const ForeignBufferOptions& f, const CompareReference& reference) {
  const Camera& camera = *reference.camera;
  try {
    ForeignFrame foreign = foreignFrame(b.depth, b.normalImage(), f, camera);
    ForeignReading t{std::move(foreign.frame), foreign.carried, {}, {}};
    char range[96] = "";
    if (f.depthConvention == DepthConvention::Window)
      std::snprintf(range, sizeof range, " for near %.6g, far %.6g Å", camera.zNear, camera.zFar);
    t.description = "another renderer's buffers, compared in Å along the reference's rays";
    t.details = "          depth   channel " + foreign.depthChannel + ", " + conventionName(f.depthConvention) + " depth" +
                range + ", rows from the " + originName(f.origin) + "\n          normals " +
                (b.normals ? b.normals->path + ", " + spaceName(f.normalSpace) + " space, " + encodingName(f.normalEncoding)
                           : std::string("none (no --test-normal)")) +
                "\n";
    return t;
  } catch (const std::invalid_argument& e) {
    throw std::invalid_argument(reference.name + ": " + e.what());  // the camera's: name the reference
  }
}

// The nearest and farthest view depth of the reference's hits (Å).
std::pair<double, double> viewDepthRange(const FrameBuffers& ref) {
  double lo = HUGE_VAL, hi = 0.0;
  for (std::size_t p = 0; p < ref.pixels(); ++p)
    if (ref.kind[p] != 0 && std::isfinite(ref.viewZ[p])) lo = std::min(lo, double(ref.viewZ[p])), hi = std::max(hi, double(ref.viewZ[p]));
  return {lo, hi};
}

// The buffers read with `f` and compared; nothing when `f` cannot read them (values its depth
// convention cannot hold, window depth without near and far).
std::optional<FrameComparison> tryForeign(const ForeignBuffers& b, const ForeignBufferOptions& f,
                                          const CompareReference& reference) {
  const auto [nearest, farthest] = viewDepthRange(reference.frame);
  try {
    if (!impossibleDepths(b.depth, f, *reference.camera, nearest, farthest).empty()) return std::nullopt;
    const ForeignReading t = readForeign(b, f, reference);
    return compareFrames(t.frame, reference.frame, &*reference.camera, t.carried);
  } catch (const std::exception&) {
    return std::nullopt;
  }
}

// Coverage mismatch plus relative depth p99: how far a reading of the depth is from the reference.
double depthMisfit(const FrameComparison& c) {
  if (c.depthSamples == 0) return HUGE_VAL;
  return c.coverageFraction + (c.sceneSize > 0 ? c.depthP99 / c.sceneSize : c.depthP99);
}

// The other depth conventions that read the buffer within the limits on coverage and depth (or,
// when `current` is null, the best of those whose values fit): "hint: ..." or "".
std::string conventionHint(const ForeignBuffers& b, const ForeignBufferOptions& f, const CompareReference& reference,
                           const CompareThresholds& limits, const FrameComparison* current) {
  std::optional<FrameComparison> best;
  DepthConvention bestConvention = f.depthConvention;
  for (const DepthConvention c : {DepthConvention::Window, DepthConvention::ViewZ, DepthConvention::Ray}) {
    if (c == f.depthConvention) continue;
    ForeignBufferOptions g = f;
    g.depthConvention = c;
    const auto other = tryForeign(b, g, reference);
    if (other && (!best || depthMisfit(*other) < depthMisfit(*best))) best = other, bestConvention = c;
  }
  if (!best || best->depthSamples == 0) return "";
  CompareThresholds depthLimits;
  depthLimits.maxCoverageFraction = limits.maxCoverageFraction;
  depthLimits.maxDepthP99Relative = limits.maxDepthP99Relative;
  const bool fits = depthLimits.violations(*best).empty();
  char text[320];
  if (!current) {  // the declared convention cannot hold the values at all
    std::snprintf(text, sizeof text, "hint: read as --depth-convention %s they %s (coverage mismatch %.4g%%, depth p99 %.3g Å)",
                  conventionName(bestConvention), fits ? "fit" : "fit best", 100 * best->coverageFraction, best->depthP99);
    return text;
  }
  if (!fits || depthMisfit(*best) >= 0.25 * depthMisfit(*current)) return "";
  std::snprintf(text, sizeof text,
                "hint: with --depth-convention %s the depth p99 would be %.3g Å and the coverage mismatch %.4g%% "
                "(they are %.3g Å and %.4g%%): is the depth %s?",
                conventionName(bestConvention), best->depthP99, 100 * best->coverageFraction, current->depthP99,
                100 * current->coverageFraction,
                bestConvention == DepthConvention::Window  ? "GL window depth"
                : bestConvention == DepthConvention::ViewZ ? "view z (along the view direction, not the ray)"
                                                           : "distance along the ray (not view z)");
  return text;
}

// Whether every component of the normals at covered pixels is in [0, 1]: unorm normals, since a
// visible closed surface faces left and right, up and down somewhere.
bool normalsLookUnorm(const ForeignFrame& frame) {
  bool any = false;
  for (std::size_t p = 0; p < frame.frame.pixels(); ++p) {
    if (!std::isfinite(frame.frame.depth[p])) continue;
    any = true;
    for (int k = 0; k < 3; ++k)
      if (frame.frame.normal[3 * p + static_cast<std::size_t>(k)] < 0.0f) return false;
  }
  return any;
}

// The reading of the normals (encoding, space, sign) that fits the reference within the normal
// limit, when the one declared does not: "hint: ..." or "".
std::string normalHint(const ForeignBuffers& b, const ForeignBufferOptions& f, const CompareReference& reference,
                       const CompareThresholds& limits, const FrameComparison& current) {
  if (!b.normals || !limits.maxNormalP99Degrees || current.normalSamples == 0 ||
      current.normalP99Degrees <= *limits.maxNormalP99Degrees)
    return "";
  std::optional<FrameComparison> best;
  ForeignBufferOptions bestOptions = f;
  for (const auto encoding : {NormalEncoding::Signed, NormalEncoding::Unorm})
    for (const auto space : {NormalSpace::View, NormalSpace::World})
      for (const bool negate : {false, true}) {
        ForeignBufferOptions g = f;
        g.normalEncoding = encoding, g.normalSpace = space, g.negateNormals = negate;
        if (encoding == f.normalEncoding && space == f.normalSpace && negate == f.negateNormals) continue;
        const auto other = tryForeign(b, g, reference);
        if (other && other->normalSamples > 0 && (!best || other->normalP99Degrees < best->normalP99Degrees))
          best = other, bestOptions = g;
      }
  if (!best || best->normalP99Degrees > *limits.maxNormalP99Degrees) return "";
  std::string flags, why;
  if (bestOptions.normalEncoding != f.normalEncoding) {
    flags += std::string(" --normal-encoding ") + encodingName(bestOptions.normalEncoding);
    const bool unorm = bestOptions.normalEncoding == NormalEncoding::Unorm;
    ForeignBufferOptions raw = f;
    raw.normalEncoding = NormalEncoding::Signed, raw.normalSpace = NormalSpace::World, raw.negateNormals = false;
    const bool allPositive = unorm && normalsLookUnorm(foreignFrame(b.depth, b.normalImage(), raw, *reference.camera));
    why += unorm ? std::string("unorm normals ((n + 1)/2) read as signed") + (allPositive ? " (every component is in [0, 1])" : "")
                 : "signed normals read as unorm";
  }
  if (bestOptions.normalSpace != f.normalSpace) {
    flags += std::string(" --normal-space ") + spaceName(bestOptions.normalSpace);
    why += std::string(why.empty() ? "" : "; ") +
           (bestOptions.normalSpace == NormalSpace::World ? "world normals read as view ones" : "view normals read as world ones");
  }
  if (bestOptions.negateNormals)
    why += std::string(why.empty() ? "" : "; ") + "the normals point into the surface, against the depth's gradient: write outward ones";
  char figures[160];
  std::snprintf(figures, sizeof figures, "the normal p99 would be %.3g° (it is %.3g°)", best->normalP99Degrees,
                current.normalP99Degrees);
  const std::string how = flags.empty() ? "negated," : "with" + flags + (bestOptions.negateNormals ? ", negated," : "");
  return "hint: " + how + " " + figures + ": " + why + "?";
}

// On a failure with another renderer's buffers: whether their rows might be upside down (the
// most common slip: glReadPixels' rows come bottom first), from the same buffers read the other way.
std::string originHint(const ForeignBuffers& b, ForeignBufferOptions f, const CompareReference& reference,
                       const FrameComparison& c) {
  f.origin = f.origin == RowOrigin::BottomLeft ? RowOrigin::TopLeft : RowOrigin::BottomLeft;
  const ForeignReading flipped = readForeign(b, f, reference);
  const FrameComparison other = compareFrames(flipped.frame, reference.frame, &*reference.camera, flipped.carried);
  if (!(c.coverageFraction > 1e-3 && other.coverageFraction < 0.25 * c.coverageFraction)) return "";
  char text[256];
  std::snprintf(text, sizeof text,
                "hint: with --test-origin %s the coverage mismatch would be %.4g%% (it is %.4g%%): are the rows upside down?",
                originName(f.origin), 100 * other.coverageFraction, 100 * c.coverageFraction);
  return text;
}

// Whether the camera's view frame is the world's (no rotation): view and world normals are then
// the same numbers, and a normal-space mix-up cannot show.
bool viewIsUnrotated(const Camera& camera) {
  const glm::dmat4 v = camera.viewMatrix();
  for (int c = 0; c < 3; ++c)
    for (int r = 0; r < 3; ++r)
      if (std::abs(v[c][r] - (c == r ? 1.0 : 0.0)) > 1e-9) return false;
  return true;
}

// The two SurfTrace images' render settings: an error when a setting that changes pixels
// differs (unless ignored); `lines` gets what differs when ignored and what was not recorded.
// Returns whether the colour may be judged by the preset (made with the same settings).
bool checkSettings(const CompareTest& test, const CompareReference& reference, bool ignoreSettings, std::string& lines) {
  const SettingsComparison s = compareSettings(test.metadata, reference.metadata);
  if (!s.differences.empty() && !ignoreSettings)
    throw std::invalid_argument(test.name + " and " + reference.name + " were rendered with different settings (their surftrace: "
                                "metadata): " + describe(s.differences) +
                                ". Compare renderings made with the same settings, or pass --ignore-settings (the "
                                "preset's colour limit is then not applied)");
  if (!s.differences.empty()) lines += "settings  differ (--ignore-settings): " + describe(s.differences) + "\n";
  auto list = [](const std::vector<std::string>& names) {
    std::string text;
    for (const auto& n : names) {
      if (!text.empty()) text += ", ";
      text += n;
    }
    return text;
  };
  if (!s.notRecordedInTest.empty())
    lines += "settings  not recorded in " + test.name + ": " + list(s.notRecordedInTest) + " (an older image; taken as the same)\n";
  if (!s.notRecordedInReference.empty())
    lines += "settings  not recorded in " + reference.name + ": " + list(s.notRecordedInReference) +
             " (an older image; taken as the same)\n";
  return s.differences.empty();
}

// An error unless the test's recorded camera is the reference's.
void checkCamera(const ImageMetadata& test, const Camera& camera) {
  if (!test.count("surftrace:camera")) return;
  const Camera other = cameraFromJson(test.at("surftrace:camera"));
  const auto window = [](const Camera& c) {
    const ViewWindow w = c.viewWindow();
    return std::array<double, 4>{w.left, w.right, w.bottom, w.top};
  };
  if (other.eye != camera.eye || other.lookAt != camera.lookAt || other.up != camera.up || other.fovY != camera.fovY ||
      other.projection != camera.projection || other.orthoHeight != camera.orthoHeight || window(other) != window(camera))
    throw std::invalid_argument("the two images were rendered with different cameras (see their surftrace:camera "
                                "metadata); compare only renderings of the same view, or pass --ignore-camera");
}

// On a failure with a mesh: whether it is plainly in another frame than the reference's
// structure (PyMOL's OBJ is in its camera frame): the two cover mostly different pixels, or
// where both hit, the depths differ by much more than a mesh's error (a quarter of the scene's
// depth and over 1 Å at the median). "hint: ..." or "".
std::string frameHint(const FrameBuffers& test, const FrameBuffers& ref, const FrameComparison& c) {
  std::size_t both = 0, either = 0, testHits = 0;
  for (std::size_t p = 0; p < ref.pixels(); ++p) {
    const bool t = std::isfinite(test.depth[p]), r = ref.kind[p] != 0;
    both += t && r, either += t || r, testHits += t;
  }
  char text[512];
  const double shared = either > 0 ? static_cast<double>(both) / static_cast<double>(either) : 1.0;
  if (shared < 0.5) {
    std::snprintf(text, sizeof text,
                  "hint: the mesh covers %zu px and the reference %zu px, but only %zu px (%.1f%% of either's) are "
                  "covered by both: the mesh looks to be in another frame than the structure (PyMOL's `save x.obj` "
                  "writes its camera frame); give the map that takes it to the structure's frame with "
                  "--mesh-transform (README, compare)",
                  testHits, c.referenceHits, both, 100.0 * shared);
    return text;
  }
  if (c.depthSamples > 0 && c.depthMedian > 1.0 && c.depthMedian > 0.25 * c.sceneSize) {
    std::snprintf(text, sizeof text,
                  "hint: where both hit, the mesh's depth is off by %.3g Å at the median (the scene is %.3g Å deep): "
                  "the mesh looks to be in another frame than the structure; give the map that takes it to the "
                  "structure's frame with --mesh-transform (README, compare)",
                  c.depthMedian, c.sceneSize);
    return text;
  }
  return "";
}

// The preset's limits, with each limit `given` sets in their place.
CompareThresholds limitsOf(const std::string& preset, const CompareThresholds& given) {
  CompareThresholds limits = preset == "none" ? CompareThresholds{} : CompareThresholds::preset(preset);
  if (given.maxCoverageFraction) limits.maxCoverageFraction = given.maxCoverageFraction;
  if (given.maxDepthP99Relative) limits.maxDepthP99Relative = given.maxDepthP99Relative;
  if (given.minKindAgreement) limits.minKindAgreement = given.minKindAgreement;
  if (given.minPatchAgreement) limits.minPatchAgreement = given.minPatchAgreement;
  if (given.maxNormalP99Degrees) limits.maxNormalP99Degrees = given.maxNormalP99Degrees;
  if (given.maxColorP99) limits.maxColorP99 = given.maxColorP99;
  if (given.maxNanPixels) limits.maxNanPixels = given.maxNanPixels;
  return limits;
}

}  // namespace

ImageChannels memoryChannels(std::string name, int width, int height, std::vector<std::string> channels,
                             std::vector<float> values) {
  if (width <= 0 || height <= 0 || channels.empty())
    throw std::invalid_argument(name + ": an empty buffer (" + std::to_string(width) + "x" + std::to_string(height) + ", " +
                                std::to_string(channels.size()) + " channels)");
  const std::size_t expected = static_cast<std::size_t>(width) * static_cast<std::size_t>(height) * channels.size();
  if (values.size() != expected)
    throw std::invalid_argument(name + ": " + std::to_string(values.size()) + " values for " + std::to_string(width) + "x" +
                                std::to_string(height) + " pixels of " + std::to_string(channels.size()) +
                                " channels; expected " + std::to_string(expected));
  ImageChannels image;
  image.path = std::move(name);
  image.format = "memory";
  image.width = width, image.height = height;
  image.types.assign(channels.size(), "float");
  image.names = std::move(channels);
  image.values = std::move(values);
  return image;
}

CompareReference compareReference(std::string name, FrameBuffers frame, ImageMetadata metadata) {
  CompareReference r{std::move(name), std::move(frame), std::move(metadata), std::nullopt};
  if (const auto c = r.metadata.find("surftrace:camera"); c != r.metadata.end()) r.camera = cameraFromJson(c->second);
  return r;
}

CompareReference readCompareReference(const std::string& path) {
  ImageMetadata metadata;
  FrameBuffers frame = readExr(path, &metadata);
  return compareReference(path, std::move(frame), std::move(metadata));
}

CompareTest readSurfTraceTest(const std::string& path) {
  CompareTest t;
  t.name = path;
  t.frame = readExr(path, &t.metadata);
  return t;
}

CompareTest readForeignTest(const std::string& depthPath, const std::string& normalPath, const ForeignBufferOptions& options) {
  CompareTest t;
  t.name = depthPath;
  t.foreign = ForeignBuffers{readImageChannels(depthPath), std::nullopt, options};
  if (!normalPath.empty()) t.foreign->normals = readImageChannels(normalPath);
  return t;
}

CompareTest readCompareTest(const std::string& path, const std::optional<ForeignBufferOptions>& foreign,
                            const std::string& normalPath) {
  if (foreign || !normalPath.empty() || !hasFrameBufferChannels(path))
    return readForeignTest(path, normalPath, foreign.value_or(ForeignBufferOptions{}));
  return readSurfTraceTest(path);
}

namespace {

// compare, taking the test's SurfTrace buffers from `frame` (a copy of test.frame, or test.frame
// itself moved in).
CompareResult compareWith(FrameBuffers&& frame, const CompareTest& test, const CompareReference& reference,
                          const CompareSettings& settings) {
  const FrameBuffers& ref = reference.frame;
  const Camera* camera = reference.camera ? &*reference.camera : nullptr;
  CompareResult r;
  r.testName = test.name;
  r.referenceName = reference.name;
  r.foreign = test.foreign.has_value() || test.drawn.has_value();
  r.camera = reference.camera;
  if (test.drawn) {
    r.testFrame = test.drawn->frame;
    r.carried = test.drawn->carried;
    r.testDescription = test.drawn->description;
    r.testDetails = test.drawn->details;
  } else if (test.foreign) {
    const ForeignBuffers& b = *test.foreign;
    for (const ImageChannels* image : {static_cast<const ImageChannels*>(&b.depth), b.normalImage()})
      if (image && (image->width != ref.width || image->height != ref.height))
        throw std::invalid_argument(sizeMismatch(image->path, image->width, image->height, reference.name, ref.width, ref.height));
    if (!camera)
      throw std::invalid_argument(reference.name + " records no camera (surftrace:camera metadata), and another renderer's "
                                  "buffers are compared along the reference camera's rays: render the reference with "
                                  "surftrace render --exr");
    // Values the declared depth convention cannot hold are an error, not background.
    const auto [nearest, farthest] = viewDepthRange(ref);
    const std::string impossible = impossibleDepths(b.depth, b.options, *camera, nearest, farthest);
    if (!impossible.empty()) {
      const std::string hint = conventionHint(b, b.options, reference, CompareThresholds::preset("foreign"), nullptr);
      throw std::invalid_argument(impossible + (hint.empty() ? "" : "\n  " + hint));
    }
    ForeignReading reading = readForeign(b, b.options, reference);
    r.testFrame = std::move(reading.frame);
    r.carried = reading.carried;
    r.testDescription = std::move(reading.description);
    r.testDetails = std::move(reading.details);
  } else {
    r.testFrame = std::move(frame);
    r.testDescription = test.metadata.count("surftrace:renderer") ? test.metadata.at("surftrace:renderer") : "?";
  }
  if (r.testFrame.width != ref.width || r.testFrame.height != ref.height)
    throw std::invalid_argument(
        sizeMismatch(test.name, r.testFrame.width, r.testFrame.height, reference.name, ref.width, ref.height));
  if (!settings.ignoreCamera && camera && !test.foreign) checkCamera(test.metadata, *camera);
  const bool sameSettings = r.foreign || checkSettings(test, reference, settings.ignoreSettings, r.settingsLines);
  r.figures = compareFrames(r.testFrame, ref, camera, r.carried);
  r.referenceDescription = reference.metadata.count("surftrace:renderer") ? reference.metadata.at("surftrace:renderer") : "?";
  if (settings.report)
    r.worstPixels = worstPixels(r.testFrame, ref, referenceMasks(ref, camera), r.carried, camera);

  if (!settings.preset.empty()) {
    r.preset = settings.preset;
  } else if (r.foreign) {
    r.preset = "foreign";
    r.presetChoice = test.drawn ? "limits    --preset foreign (a mesh: coverage, depth and normals; pass --preset to choose)"
                                : "limits    --preset foreign (another renderer's buffers: coverage, depth and normals when given; "
                                  "pass --preset to choose)";
  } else {
    r.preset = defaultPreset(test.metadata, reference.metadata, r.presetChoice);
  }
  r.limits = limitsOf(r.preset, settings.limits);
  if (!sameSettings && !settings.limits.maxColorP99 && r.limits.maxColorP99) {
    char line[160];
    std::snprintf(line, sizeof line, "not compared: colour p99 < %.3g (the images were made with different settings)\n",
                  *r.limits.maxColorP99);
    r.notes += line;
    r.limits.maxColorP99.reset();
  }
  if (test.foreign && r.carried.normal && viewIsUnrotated(*camera))
    r.notes += "note      the reference camera's view is not rotated (its axes are the world's): view and world normals "
               "are the same numbers here, so a wrong --normal-space cannot show; render the reference from a rotated "
               "view (e.g. --view 1,0.3,-1) to check the normals' space\n";
  // A limit on a buffer the test does not carry is neither passed nor failed.
  r.notCompared = r.limits.notCompared(r.figures);
  r.violations = r.limits.violations(r.figures);
  if (!r.violations.empty() && test.drawn) {
    if (std::string hint = frameHint(r.testFrame, ref, r.figures); !hint.empty()) r.hints.push_back(std::move(hint));
  } else if (!r.violations.empty() && test.foreign) {
    const ForeignBuffers& b = *test.foreign;
    for (std::string hint : {originHint(b, b.options, reference, r.figures),
                             conventionHint(b, b.options, reference, r.limits, &r.figures),
                             normalHint(b, b.options, reference, r.limits, r.figures)})
      if (!hint.empty()) r.hints.push_back(std::move(hint));
  }
  return r;
}

}  // namespace

CompareResult compare(const CompareTest& test, const CompareReference& reference, const CompareSettings& settings) {
  return compareWith(test.foreign || test.drawn ? FrameBuffers{} : FrameBuffers(test.frame), test, reference, settings);
}

CompareResult compare(CompareTest&& test, const CompareReference& reference, const CompareSettings& settings) {
  FrameBuffers frame = std::move(test.frame);
  return compareWith(std::move(frame), test, reference, settings);
}

std::string CompareResult::verdict() const {
  std::string text = notes;
  for (const auto& line : notCompared) text += "not compared: " + line + "\n";
  const std::string scope = notCompared.empty() ? "" : ", on what the test carries";
  if (passed()) return text + "PASS (" + (preset == "none" ? std::string("no limits: --preset none") : preset) + scope + ")";
  text += "FAIL (" + preset + scope + "):";
  for (const auto& v : violations) text += "\n  " + v;
  for (const auto& h : hints) text += "\n  " + h;
  return text;
}

std::string CompareResult::json() const {
  nlohmann::json report = nlohmann::json::parse(figures.json());
  report["worst_pixels"] = worstPixelsJson(worstPixels);
  return report.dump(1);
}

std::vector<float> differenceImage(const CompareResult& result, const CompareReference& reference) {
  return differenceImage(result.testFrame, reference.frame, result.carried, result.camera ? &*result.camera : nullptr,
                         DifferenceScale::of(result.limits, result.figures));
}

std::string differenceLegend(const CompareResult& result) {
  const DifferenceScale scale = DifferenceScale::of(result.limits, result.figures);
  char limits[160] = "";
  if (scale.depthLimit > 0.0) std::snprintf(limits, sizeof limits, "; the depth limit is %.3g Å", scale.depthLimit);
  else std::snprintf(limits, sizeof limits, "; the depth limit is 1e-3 of the scene size (none set)");
  std::string legend = std::string(kDifferenceLegend) + limits;
  if (scale.colorLimit) {
    std::snprintf(limits, sizeof limits, ", the colour limit %.3g", *scale.colorLimit);
    legend += limits;
  }
  return legend;
}

namespace {

FrameBuffers differenceFrame(const CompareResult& result, const std::vector<float>& rgb) {
  FrameBuffers image;
  image.width = result.testFrame.width;
  image.height = result.testFrame.height;
  image.rgba.resize(4 * image.pixels());
  for (std::size_t p = 0; p < image.pixels(); ++p) {
    for (std::size_t k = 0; k < 3; ++k) image.rgba[4 * p + k] = rgb[3 * p + k];
    image.rgba[4 * p + 3] = 1.0f;
  }
  return image;
}

}  // namespace

EncodedImage encodeDifference(const std::string& path, const CompareResult& result, const std::vector<float>& rgb) {
  return encodePng(path, differenceFrame(result, rgb), {{"surftrace:legend", differenceLegend(result)}});
}

void writeDifference(const std::string& path, const CompareResult& result, const std::vector<float>& rgb) {
  writePng(path, differenceFrame(result, rgb), {{"surftrace:legend", differenceLegend(result)}});
}

std::string comparisonPage(const CompareResult& result, const CompareReference& reference, const std::vector<float>& rgb) {
  HtmlReport page;
  page.title = result.testName + " vs " + result.referenceName;
  page.verdict = result.settingsLines + result.figures.summary() + "\nlimits    --preset " + result.preset + "\n" + result.verdict();
  page.legend = differenceLegend(result);
  page.test = displayPng(result.testFrame, result.carried.color);
  page.reference = displayPng(reference.frame, true);
  page.diff = rgbPng(rgb, reference.frame.width, reference.frame.height);
  page.width = reference.frame.width;
  page.height = reference.frame.height;
  page.reportJson = result.json();
  return comparisonHtml(page);
}

}  // namespace surftrace::view

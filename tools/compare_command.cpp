// `surftrace compare`: two renderings of one view, pixel by pixel, with pass/fail limits; the
// rendering under test may be SurfTrace's EXR or another renderer's depth and normal buffers.
#include <algorithm>
#include <array>
#include <cmath>
#include <cstdio>
#include <fstream>
#include <memory>
#include <optional>
#include <stdexcept>
#include <utility>

#include <nlohmann/json.hpp>

#include "build/io/output_file.hpp"
#include "commands.hpp"
#include "option_checks.hpp"
#include "view/camera.hpp"
#include "view/compare_report.hpp"
#include "view/foreign_buffers.hpp"
#include "view/image_compare.hpp"
#include "view/image_io.hpp"
#include "view/render_settings.hpp"

namespace surftrace::tools {
namespace {

struct CompareOptions {
  std::string test, reference, report, diff, html, preset;
  std::optional<double> maxCoverage, maxDepthP99, minKind, minPatch, maxNormalP99, maxColorP99;
  bool ignoreCamera = false;
  bool ignoreSettings = false;
  // Another renderer's buffers (empty: not given; the defaults are foreignOptions').
  std::string depthChannel, depthConvention, testNormal, normalSpace, normalEncoding, testOrigin;
  bool foreignFlags() const {
    return !depthChannel.empty() || !depthConvention.empty() || !testNormal.empty() || !normalSpace.empty() ||
           !normalEncoding.empty() || !testOrigin.empty();
  }
};

view::ForeignBufferOptions foreignOptions(const CompareOptions& o) {
  view::ForeignBufferOptions f;
  f.depthChannel = o.depthChannel;
  if (o.depthConvention == "view-z") f.depthConvention = view::DepthConvention::ViewZ;
  if (o.depthConvention == "ray") f.depthConvention = view::DepthConvention::Ray;
  if (o.testOrigin == "top-left") f.origin = view::RowOrigin::TopLeft;
  if (o.normalSpace == "world") f.normalSpace = view::NormalSpace::World;
  if (o.normalEncoding == "unorm") f.normalEncoding = view::NormalEncoding::Unorm;
  return f;
}

// What the test holds: SurfTrace's buffers, or another renderer's read into the reference's view.
struct TestImage {
  view::FrameBuffers frame;
  view::TestChannels carried;
  view::ImageMetadata meta;
  std::string description;
  std::string details;  // lines under "test", each ending in a newline
};

// Exit codes: 0 within the limits, 2 outside them (1 is an error, from main).
struct LimitsExceeded : std::runtime_error {
  using std::runtime_error::runtime_error;
};

// The engine that made an image, from its metadata: "embree", "gl", or "" when not recorded
// (an image from another program).
std::string engineOf(const view::ImageMetadata& meta) {
  if (const auto e = meta.find("surftrace:engine"); e != meta.end()) return e->second;
  if (const auto r = meta.find("surftrace:renderer"); r != meta.end()) {
    if (r->second.find(" gl:") != std::string::npos) return "gl";
    if (r->second.find(" embree ") != std::string::npos) return "embree";
  }
  return "";
}

// Without --preset, the strict limits for the pair of engines: `exact` for two images of one
// engine; otherwise (different engines, or one not recorded) `effects` when the reference has
// image-space effects, `transparency` when its surface is transparent, else `gl-vs-embree`.
// Says which.
std::string defaultPreset(const view::ImageMetadata& test, const view::ImageMetadata& ref) {
  const std::string a = engineOf(test), b = engineOf(ref);
  std::string preset = !a.empty() && a == b                ? "exact"
                       : ref.count("surftrace:effects") > 0 ? "effects"
                       : ref.count("surftrace:opacity") > 0 ? "transparency"
                                                            : "gl-vs-embree";
  std::printf("limits    --preset %s (engines: test %s, reference %s%s; pass --preset to choose)\n", preset.c_str(),
              a.empty() ? "not recorded" : a.c_str(), b.empty() ? "not recorded" : b.c_str(),
              preset == "effects" ? "; image-space effects" : preset == "transparency" ? "; transparent surface" : "");
  return preset;
}

std::string sizeMismatch(const std::string& test, int tw, int th, const std::string& ref, int rw, int rh) {
  return test + " is " + std::to_string(tw) + "x" + std::to_string(th) + " but " + ref + " is " + std::to_string(rw) + "x" +
         std::to_string(rh);
}

// Another renderer's files (TEST and --test-normal), read once: the hints read them again in
// other conventions.
struct ForeignFiles {
  view::ImageChannels depth;
  std::optional<view::ImageChannels> normals;
  const view::ImageChannels* normalImage() const { return normals ? &*normals : nullptr; }
};

ForeignFiles readForeignFiles(const CompareOptions& o, const view::FrameBuffers& ref,
                              const std::optional<view::Camera>& camera) {
  ForeignFiles files{readingFile(o.test, "the image", [&] { return view::readImageChannels(o.test); }), std::nullopt};
  if (!o.testNormal.empty())
    files.normals = readingFile(o.testNormal, "the image", [&] { return view::readImageChannels(o.testNormal); });
  for (const view::ImageChannels* image : {static_cast<const view::ImageChannels*>(&files.depth), files.normalImage()})
    if (image && (image->width != ref.width || image->height != ref.height))
      throw std::invalid_argument(sizeMismatch(image->path, image->width, image->height, o.reference, ref.width, ref.height));
  if (!camera)
    throw std::invalid_argument(o.reference + " records no camera (surftrace:camera metadata), and another renderer's "
                                "buffers are compared along the reference camera's rays: render the reference with "
                                "surftrace render --exr");
  return files;
}

// Another renderer's buffers along the reference camera's rays.
TestImage readForeign(const CompareOptions& o, const ForeignFiles& files, const view::ForeignBufferOptions& f,
                      const view::Camera& camera) {
  try {
    view::ForeignFrame foreign = view::foreignFrame(files.depth, files.normalImage(), f, camera);
    TestImage t{std::move(foreign.frame), foreign.carried, {}, {}, {}};
    char range[96] = "";
    if (f.depthConvention == view::DepthConvention::Window)
      std::snprintf(range, sizeof range, " for near %.6g, far %.6g Å", camera.zNear, camera.zFar);
    t.description = "another renderer's buffers, compared in Å along the reference's rays";
    t.details = "          depth   channel " + foreign.depthChannel + ", " + view::conventionName(f.depthConvention) +
                " depth" + range + ", rows from the " + view::originName(f.origin) + "\n          normals " +
                (files.normals ? o.testNormal + ", " + view::spaceName(f.normalSpace) + " space, " + view::encodingName(f.normalEncoding)
                               : std::string("none (no --test-normal)")) +
                "\n";
    return t;
  } catch (const std::invalid_argument& e) {
    throw std::invalid_argument(o.reference + ": " + e.what());  // the camera's: name the reference
  }
}

// The nearest and farthest view depth of the reference's hits (Å).
std::pair<double, double> viewDepthRange(const view::FrameBuffers& ref) {
  double lo = HUGE_VAL, hi = 0.0;
  for (std::size_t p = 0; p < ref.pixels(); ++p)
    if (ref.kind[p] != 0 && std::isfinite(ref.viewZ[p])) lo = std::min(lo, double(ref.viewZ[p])), hi = std::max(hi, double(ref.viewZ[p]));
  return {lo, hi};
}

// The buffers read with `f` and compared; nothing when `f` cannot read them (values its depth
// convention cannot hold, window depth without near and far).
std::optional<view::FrameComparison> tryForeign(const CompareOptions& o, const ForeignFiles& files,
                                                const view::ForeignBufferOptions& f, const view::FrameBuffers& ref,
                                                const view::Camera& camera) {
  const auto [nearest, farthest] = viewDepthRange(ref);
  try {
    if (!view::impossibleDepths(files.depth, f, camera, nearest, farthest).empty()) return std::nullopt;
    const TestImage t = readForeign(o, files, f, camera);
    return view::compareFrames(t.frame, ref, &camera, t.carried);
  } catch (const std::exception&) {
    return std::nullopt;
  }
}

// Coverage mismatch plus relative depth p99: how far a reading of the depth is from the reference.
double depthMisfit(const view::FrameComparison& c) {
  if (c.depthSamples == 0) return HUGE_VAL;
  return c.coverageFraction + (c.sceneSize > 0 ? c.depthP99 / c.sceneSize : c.depthP99);
}

// The other depth conventions that read the buffer within the limits on coverage and depth (or,
// when `anyFit`, the best of those whose values fit): "\n  hint: ..." or "".
std::string conventionHint(const CompareOptions& o, const ForeignFiles& files, const view::ForeignBufferOptions& f,
                           const view::FrameBuffers& ref, const view::Camera& camera, const view::CompareThresholds& limits,
                           const view::FrameComparison* current) {
  std::optional<view::FrameComparison> best;
  view::DepthConvention bestConvention = f.depthConvention;
  for (const view::DepthConvention c : {view::DepthConvention::Window, view::DepthConvention::ViewZ, view::DepthConvention::Ray}) {
    if (c == f.depthConvention) continue;
    view::ForeignBufferOptions g = f;
    g.depthConvention = c;
    const auto other = tryForeign(o, files, g, ref, camera);
    if (other && (!best || depthMisfit(*other) < depthMisfit(*best))) best = other, bestConvention = c;
  }
  if (!best || best->depthSamples == 0) return "";
  view::CompareThresholds depthLimits;
  depthLimits.maxCoverageFraction = limits.maxCoverageFraction;
  depthLimits.maxDepthP99Relative = limits.maxDepthP99Relative;
  const bool fits = depthLimits.violations(*best).empty();
  char text[320];
  if (!current) {  // the declared convention cannot hold the values at all
    std::snprintf(text, sizeof text, "\n  hint: read as --depth-convention %s they %s (coverage mismatch %.4g%%, depth p99 %.3g Å)",
                  view::conventionName(bestConvention), fits ? "fit" : "fit best", 100 * best->coverageFraction,
                  best->depthP99);
    return text;
  }
  if (!fits || depthMisfit(*best) >= 0.25 * depthMisfit(*current)) return "";
  std::snprintf(text, sizeof text,
                "\n  hint: with --depth-convention %s the depth p99 would be %.3g Å and the coverage mismatch %.4g%% "
                "(they are %.3g Å and %.4g%%): is the depth %s?",
                view::conventionName(bestConvention), best->depthP99, 100 * best->coverageFraction, current->depthP99,
                100 * current->coverageFraction,
                bestConvention == view::DepthConvention::Window ? "GL window depth"
                : bestConvention == view::DepthConvention::ViewZ ? "view z (along the view direction, not the ray)"
                                                                 : "distance along the ray (not view z)");
  return text;
}

// Whether every component of the normals at covered pixels is in [0, 1]: unorm normals, since a
// visible closed surface faces left and right, up and down somewhere.
bool normalsLookUnorm(const view::ForeignFrame& frame) {
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
// limit, when the one declared does not: "\n  hint: ..." or "".
std::string normalHint(const CompareOptions& o, const ForeignFiles& files, const view::ForeignBufferOptions& f,
                       const view::FrameBuffers& ref, const view::Camera& camera, const view::CompareThresholds& limits,
                       const view::FrameComparison& current) {
  if (!files.normals || !limits.maxNormalP99Degrees || current.normalSamples == 0 ||
      current.normalP99Degrees <= *limits.maxNormalP99Degrees)
    return "";
  std::optional<view::FrameComparison> best;
  view::ForeignBufferOptions bestOptions = f;
  for (const auto encoding : {view::NormalEncoding::Signed, view::NormalEncoding::Unorm})
    for (const auto space : {view::NormalSpace::View, view::NormalSpace::World})
      for (const bool negate : {false, true}) {
        view::ForeignBufferOptions g = f;
        g.normalEncoding = encoding, g.normalSpace = space, g.negateNormals = negate;
        if (encoding == f.normalEncoding && space == f.normalSpace && negate == f.negateNormals) continue;
        const auto other = tryForeign(o, files, g, ref, camera);
        if (other && other->normalSamples > 0 && (!best || other->normalP99Degrees < best->normalP99Degrees))
          best = other, bestOptions = g;
      }
  if (!best || best->normalP99Degrees > *limits.maxNormalP99Degrees) return "";
  std::string flags, why;
  if (bestOptions.normalEncoding != f.normalEncoding) {
    flags += std::string(" --normal-encoding ") + view::encodingName(bestOptions.normalEncoding);
    const bool unorm = bestOptions.normalEncoding == view::NormalEncoding::Unorm;
    view::ForeignBufferOptions raw = f;
    raw.normalEncoding = view::NormalEncoding::Signed, raw.normalSpace = view::NormalSpace::World, raw.negateNormals = false;
    const bool allPositive = unorm && normalsLookUnorm(view::foreignFrame(files.depth, files.normalImage(), raw, camera));
    why += unorm ? std::string("unorm normals ((n + 1)/2) read as signed") + (allPositive ? " (every component is in [0, 1])" : "")
                 : "signed normals read as unorm";
  }
  if (bestOptions.normalSpace != f.normalSpace) {
    flags += std::string(" --normal-space ") + view::spaceName(bestOptions.normalSpace);
    why += std::string(why.empty() ? "" : "; ") +
           (bestOptions.normalSpace == view::NormalSpace::World ? "world normals read as view ones" : "view normals read as world ones");
  }
  if (bestOptions.negateNormals)
    why += std::string(why.empty() ? "" : "; ") +
           "the normals point into the surface, against the depth's gradient: write outward ones";
  char figures[160];
  std::snprintf(figures, sizeof figures, "the normal p99 would be %.3g° (it is %.3g°)", best->normalP99Degrees,
                current.normalP99Degrees);
  const std::string how = flags.empty() ? "negated," : "with" + flags + (bestOptions.negateNormals ? ", negated," : "");
  return "\n  hint: " + how + " " + figures + ": " + why + "?";
}

// On a failure with another renderer's buffers: whether their rows might be upside down (the
// most common slip: glReadPixels' rows come bottom first), from the same buffers read the other way.
std::string originHint(const CompareOptions& o, const ForeignFiles& files, view::ForeignBufferOptions f,
                       const view::FrameBuffers& ref, const view::Camera& camera, const view::FrameComparison& c) {
  f.origin = f.origin == view::RowOrigin::BottomLeft ? view::RowOrigin::TopLeft : view::RowOrigin::BottomLeft;
  const TestImage flipped = readForeign(o, files, f, camera);
  const view::FrameComparison other = view::compareFrames(flipped.frame, ref, &camera, flipped.carried);
  if (!(c.coverageFraction > 1e-3 && other.coverageFraction < 0.25 * c.coverageFraction)) return "";
  char text[256];
  std::snprintf(text, sizeof text,
                "\n  hint: with --test-origin %s the coverage mismatch would be %.4g%% (it is %.4g%%): are the rows upside "
                "down?",
                view::originName(f.origin), 100 * other.coverageFraction, 100 * c.coverageFraction);
  return text;
}

// Whether the camera's view frame is the world's (no rotation): view and world normals are then
// the same numbers, and a normal-space mix-up cannot show.
bool viewIsUnrotated(const view::Camera& camera) {
  const glm::dmat4 v = camera.viewMatrix();
  for (int c = 0; c < 3; ++c)
    for (int r = 0; r < 3; ++r)
      if (std::abs(v[c][r] - (c == r ? 1.0 : 0.0)) > 1e-9) return false;
  return true;
}

// Without --preset, the limits for another renderer's buffers. Says which.
std::string foreignPreset() {
  std::printf("limits    --preset foreign (another renderer's buffers: coverage, depth and normals when given; "
              "pass --preset to choose)\n");
  return "foreign";
}

// The image under test: SurfTrace's own EXR, or another renderer's buffers when a flag says
// so or TEST lacks SurfTrace's channels.
TestImage readTest(const CompareOptions& o, const view::FrameBuffers& ref, const std::optional<view::Camera>& camera,
                   const ForeignFiles* files, const view::ForeignBufferOptions& foreignOpts) {
  TestImage testImage;
  if (files) {
    // Values the declared depth convention cannot hold are an error, not background.
    const auto [nearest, farthest] = viewDepthRange(ref);
    const std::string impossible = view::impossibleDepths(files->depth, foreignOpts, *camera, nearest, farthest);
    if (!impossible.empty())
      throw std::invalid_argument(impossible + conventionHint(o, *files, foreignOpts, ref, *camera,
                                                              view::CompareThresholds::preset("foreign"), nullptr));
    testImage = readForeign(o, *files, foreignOpts, *camera);
  } else {
    testImage.frame = readingFile(o.test, "the image", [&] { return view::readExr(o.test, &testImage.meta); });
    testImage.description = testImage.meta.count("surftrace:renderer") ? testImage.meta.at("surftrace:renderer") : "?";
  }
  const view::FrameBuffers& test = testImage.frame;
  if (test.width != ref.width || test.height != ref.height)
    throw std::invalid_argument(sizeMismatch(o.test, test.width, test.height, o.reference, ref.width, ref.height));
  if (!o.ignoreCamera && camera && testImage.meta.count("surftrace:camera")) {
    const view::Camera other = view::cameraFromJson(testImage.meta.at("surftrace:camera"));
    const auto window = [](const view::Camera& c) {
      const view::ViewWindow w = c.viewWindow();
      return std::array<double, 4>{w.left, w.right, w.bottom, w.top};
    };
    if (other.eye != camera->eye || other.lookAt != camera->lookAt || other.up != camera->up ||
        other.fovY != camera->fovY || other.projection != camera->projection || other.orthoHeight != camera->orthoHeight ||
        window(other) != window(*camera))
      throw std::invalid_argument("the two images were rendered with different cameras (see their surftrace:camera "
                                  "metadata); compare only renderings of the same view, or pass --ignore-camera");
  }
  return testImage;
}

// The difference image's legend, with the limits its colours are scaled to.
std::string differenceLegend(const view::DifferenceScale& scale) {
  char limits[160] = "";
  if (scale.depthLimit > 0.0) std::snprintf(limits, sizeof limits, "; the depth limit is %.3g Å", scale.depthLimit);
  else std::snprintf(limits, sizeof limits, "; the depth limit is 1e-3 of the scene size (none set)");
  std::string legend = std::string(view::kDifferenceLegend) + limits;
  if (scale.colorLimit) {
    std::snprintf(limits, sizeof limits, ", the colour limit %.3g", *scale.colorLimit);
    legend += limits;
  }
  return legend;
}

void writeDifference(const std::string& path, const std::vector<float>& rgb, const view::FrameBuffers& ref,
                     const view::DifferenceScale& scale) {
  view::FrameBuffers image;
  image.width = ref.width;
  image.height = ref.height;
  image.rgba.resize(4 * ref.pixels());
  for (std::size_t p = 0; p < ref.pixels(); ++p) {
    for (int k = 0; k < 3; ++k) image.rgba[4 * p + k] = rgb[3 * p + k];
    image.rgba[4 * p + 3] = 1.0f;
  }
  view::writePng(path, image, {{"surftrace:legend", differenceLegend(scale)}});
}

// The JSON report: the comparison's metrics, the signed depth error per patch kind and the
// worst pixels.
std::string reportJson(const view::FrameComparison& c, const TestImage& testImage, const view::FrameBuffers& ref,
                       const view::ReferenceMasks& masks, const view::Camera* camera) {
  nlohmann::json report = nlohmann::json::parse(c.json());
  report["worst_pixels"] = view::worstPixelsJson(view::worstPixels(testImage.frame, ref, masks, testImage.carried, camera));
  return report.dump(1);
}

// The preset's limits, with the single limits given on the command line.
view::CompareThresholds limitsOf(const CompareOptions& o, const std::string& preset) {
  view::CompareThresholds limits = preset == "none" ? view::CompareThresholds{} : view::CompareThresholds::preset(preset);
  if (o.maxCoverage) limits.maxCoverageFraction = o.maxCoverage;
  if (o.maxDepthP99) limits.maxDepthP99Relative = o.maxDepthP99;
  if (o.minKind) limits.minKindAgreement = o.minKind;
  if (o.minPatch) limits.minPatchAgreement = o.minPatch;
  if (o.maxNormalP99) limits.maxNormalP99Degrees = o.maxNormalP99;
  if (o.maxColorP99) limits.maxColorP99 = o.maxColorP99;
  return limits;
}

// The two SurfTrace images' render settings: an error when a setting that changes pixels
// differs (unless --ignore-settings); `lines` gets what differs under --ignore-settings and what
// was not recorded. Returns whether the colour may be judged by the preset (made with the same
// settings).
bool checkSettings(const CompareOptions& o, const view::ImageMetadata& test, const view::ImageMetadata& ref,
                   std::string& lines) {
  const view::SettingsComparison s = view::compareSettings(test, ref);
  if (!s.differences.empty() && !o.ignoreSettings)
    throw std::invalid_argument(o.test + " and " + o.reference + " were rendered with different settings (their surftrace: "
                                "metadata): " + view::describe(s.differences) +
                                ". Compare renderings made with the same settings, or pass --ignore-settings (the "
                                "preset's colour limit is then not applied)");
  if (!s.differences.empty()) lines += "settings  differ (--ignore-settings): " + view::describe(s.differences) + "\n";
  auto list = [](const std::vector<std::string>& names) {
    std::string text;
    for (const auto& n : names) {
      if (!text.empty()) text += ", ";
      text += n;
    }
    return text;
  };
  if (!s.notRecordedInTest.empty())
    lines += "settings  not recorded in " + o.test + ": " + list(s.notRecordedInTest) + " (an older image; taken as the same)\n";
  if (!s.notRecordedInReference.empty())
    lines += "settings  not recorded in " + o.reference + ": " + list(s.notRecordedInReference) +
             " (an older image; taken as the same)\n";
  return s.differences.empty();
}

void runCompare(const CompareOptions& o) {
  if (!o.report.empty()) build::prepareOutputPath(o.report, "--report");
  if (!o.diff.empty()) view::checkImageOutputName(o.diff, "--diff", view::ImageContent::Colour);
  if (!o.diff.empty()) build::prepareOutputPath(o.diff, "--diff", build::OutputContent::Binary);
  if (!o.html.empty()) build::prepareOutputPath(o.html, "--html");
  view::ImageMetadata refMeta;
  const view::FrameBuffers ref = readingFile(o.reference, "the image", [&] { return view::readExr(o.reference, &refMeta); });
  std::optional<view::Camera> camera;
  if (refMeta.count("surftrace:camera")) camera = view::cameraFromJson(refMeta.at("surftrace:camera"));
  const bool foreign = o.foreignFlags() || !view::hasFrameBufferChannels(o.test);
  const view::ForeignBufferOptions foreignOpts = foreignOptions(o);
  std::optional<ForeignFiles> files;
  if (foreign) files = readForeignFiles(o, ref, camera);
  const TestImage testImage = readTest(o, ref, camera, files ? &*files : nullptr, foreignOpts);
  std::string settingsLines;
  const bool sameSettings = foreign || checkSettings(o, testImage.meta, refMeta, settingsLines);
  std::printf("%s", settingsLines.c_str());
  const view::FrameComparison c = view::compareFrames(testImage.frame, ref, camera ? &*camera : nullptr, testImage.carried);
  std::printf("test      %s (%s)\n%sreference %s (%s)\n%s\n", o.test.c_str(), testImage.description.c_str(),
              testImage.details.c_str(), o.reference.c_str(),
              refMeta.count("surftrace:renderer") ? refMeta.at("surftrace:renderer").c_str() : "?", c.summary().c_str());
  const view::Camera* cameraPtr = camera ? &*camera : nullptr;
  const view::ReferenceMasks masks =
      o.report.empty() && o.html.empty() ? view::ReferenceMasks{} : view::referenceMasks(ref, cameraPtr);
  const std::string json = masks.mask.empty() ? "" : reportJson(c, testImage, ref, masks, cameraPtr);
  if (!o.report.empty()) build::writeFileAtomically(o.report, json + "\n");
  const std::string preset = !o.preset.empty() ? o.preset : foreign ? foreignPreset() : defaultPreset(testImage.meta, refMeta);
  view::CompareThresholds limits = limitsOf(o, preset);
  std::string notes;  // printed with the verdict
  if (!sameSettings && !o.maxColorP99 && limits.maxColorP99) {
    char line[160];
    std::snprintf(line, sizeof line, "not compared: colour p99 < %.3g (the images were made with different settings)\n",
                  *limits.maxColorP99);
    notes += line;
    limits.maxColorP99.reset();
  }
  if (foreign && testImage.carried.normal && viewIsUnrotated(*camera))
    notes += "note      the reference camera's view is not rotated (its axes are the world's): view and world normals "
             "are the same numbers here, so a wrong --normal-space cannot show; render the reference from a rotated "
             "view (e.g. --view 1,0.3,-1) to check the normals' space\n";
  const view::DifferenceScale scale = view::DifferenceScale::of(limits, c);
  std::vector<float> diff;
  if (!o.diff.empty() || !o.html.empty()) diff = view::differenceImage(testImage.frame, ref, testImage.carried, cameraPtr, scale);
  if (!o.diff.empty()) writeDifference(o.diff, diff, ref, scale);
  // A limit on a buffer the test does not carry is neither passed nor failed.
  const auto unjudged = limits.notCompared(c);
  std::string verdict = notes;
  for (const auto& line : unjudged) verdict += "not compared: " + line + "\n";
  const std::string scope = unjudged.empty() ? "" : ", on what the test carries";
  const auto violations = limits.violations(c);
  if (violations.empty()) {
    verdict += "PASS (" + (preset == "none" ? std::string("no limits: --preset none") : preset) + scope + ")";
  } else {
    verdict += "FAIL (" + preset + scope + "):";
    for (const auto& v : violations) verdict += "\n  " + v;
    if (foreign) {
      verdict += originHint(o, *files, foreignOpts, ref, *camera, c);
      verdict += conventionHint(o, *files, foreignOpts, ref, *camera, limits, &c);
      verdict += normalHint(o, *files, foreignOpts, ref, *camera, limits, c);
    }
  }
  if (!o.html.empty()) {
    view::HtmlReport page;
    page.title = o.test + " vs " + o.reference;
    page.verdict = settingsLines + c.summary() + "\nlimits    --preset " + preset + "\n" + verdict;
    page.legend = differenceLegend(scale);
    page.test = view::displayPng(testImage.frame, testImage.carried.color);
    page.reference = view::displayPng(ref, true);
    page.diff = view::rgbPng(diff, ref.width, ref.height);
    page.width = ref.width;
    page.height = ref.height;
    page.reportJson = json;
    build::writeFileAtomically(o.html, view::comparisonHtml(page));
  }
  if (violations.empty()) {
    std::printf("%s\n", verdict.c_str());
    return;
  }
  throw LimitsExceeded(verdict);
}

// Another renderer's buffers (README "Validating your renderer"): any of these, or a TEST
// without SurfTrace's channels, reads TEST as a depth buffer of the reference's camera.
void addForeignBufferOptions(CLI::App& cmd, CompareOptions& o) {
  const char* foreignGroup = "Another renderer's buffers (TEST without SurfTrace's channels)";
  cmd.add_option("--test-depth-channel", o.depthChannel, "TEST's depth channel (default: Z, depth or Y, else the only channel)")
      ->group(foreignGroup);
  cmd.add_option("--depth-convention", o.depthConvention,
                 "What TEST's depth means: window (GL depth in [0, 1] under glDepthRange 0..1 for the reference "
                 "camera's near and far, background 1.0; the default), view-z (Å along the view direction, −z of the "
                 "view frame) or ray (Å from the eye along the pixel's ray); background +inf or <= 0. Compared in Å "
                 "along the reference's rays")
      ->check(CLI::IsMember({"window", "view-z", "ray"}))
      ->group(foreignGroup);
  cmd.add_option("--test-origin", o.testOrigin,
                 "Which image row TEST's first stored row is: bottom-left (glReadPixels' order, and a PFM's; the "
                 "default) or top-left (image order); applies to --test-normal too")
      ->check(CLI::IsMember({"bottom-left", "top-left"}))
      ->group(foreignGroup);
  cmd.add_option("--test-normal", o.testNormal,
                 "Normal buffer of TEST's renderer, same size and row order (channels R, G, B, or N.X, N.Y, N.Z); "
                 "without it normals are not compared")
      ->check(CLI::ExistingFile)
      ->group(foreignGroup);
  cmd.add_option("--normal-space", o.normalSpace,
                 "Space of --test-normal: view (x right, y up, z towards the eye: the view matrix's frame; the "
                 "default) or world")
      ->check(CLI::IsMember({"view", "world"}))
      ->group(foreignGroup);
  cmd.add_option("--normal-encoding", o.normalEncoding,
                 "Components of --test-normal: signed (snorm: in [-1, 1]; the default) or unorm ((n + 1) / 2, e.g. an 8- or "
                 "16-bit PNG)")
      ->check(CLI::IsMember({"signed", "snorm", "unorm"}))
      ->group(foreignGroup);
}

}  // namespace

void addCompareCommand(CLI::App& app) {
  auto o = std::make_shared<CompareOptions>();
  auto* cmd = app.add_subcommand(
      "compare",
      "Compare a rendering (TEST.exr, or another renderer's depth and normal buffers) with a reference of the same "
      "view (REFERENCE.exr, usually the Embree image) pixel by pixel: coverage, depth, normal, patch kind and id, "
      "colour (covered pixels and background apart), masking the reference's silhouette band, occlusion edges, seams "
      "and flagged pixels, with a table per patch kind. The images' recorded cameras and render settings must agree. "
      "Exit status 0 within the limits, 2 outside them, 1 on an error");
  cmd->add_option("TEST", o->test,
                  "Image under test: an EXR from surftrace render (e.g. --engine gl), or another renderer's depth "
                  "buffer in any format OpenImageIO reads (EXR, PFM, float TIFF, 16-bit PNG; see --depth-convention)")
      ->required()
      ->check(CLI::ExistingFile);
  cmd->add_option("REFERENCE", o->reference, "Reference EXR; its masks and camera are used")->required()->check(CLI::ExistingFile);
  cmd->add_option("--report", o->report, "Write the metrics as JSON here; - for the standard output");
  cmd->add_option("--diff", o->diff,
                  "Write a false-colour difference PNG here (its colours: README, `compare`; its surftrace:legend "
                  "attribute says them too); - for the standard output");
  cmd->add_option("--html", o->html,
                  "Write one self-contained HTML page here: test, reference and difference side by side (zoomed "
                  "together), the signed depth error per patch kind with histograms, and the worst pixels; - for the "
                  "standard output");
  cmd->add_option("--preset", o->preset, "Limits: gl-vs-embree (coverage < 0.1%, depth p99 < 1e-3 of the scene, "
                                         "kinds > 99.9%, colour p99 < 1e-3), exact (a re-render by the same engine; "
                                         "colour p99 < 1e-5), foreign (another renderer's buffers: coverage < 0.1%, depth "
                                         "p99 < 1e-3 of the scene, normal p99 < 1°), effects (gl-vs-embree with colour p99 "
                                         "< 0.02: two engines' images with the same image-space effects), transparency "
                                         "(gl-vs-embree with colour p99 < 1e-3: GL's depth peeling against Embree's layers "
                                         "at --opacity < 1), or none (report the metrics, judge nothing). Every preset "
                                         "fails on NaN and on a limit over no pixels. Default: foreign for another "
                                         "renderer's buffers, exact when the two images' metadata name the same engine, "
                                         "else effects or transparency when the reference has effects or a transparent "
                                         "surface, else gl-vs-embree")
      ->check(CLI::IsMember({"gl-vs-embree", "exact", "foreign", "effects", "transparency", "none"}));
  cmd->add_option("--max-coverage", o->maxCoverage, "Largest coverage-mismatch fraction outside silhouettes")->check(numberIn(0, 1));
  cmd->add_option("--max-depth-p99", o->maxDepthP99, "Largest depth-error p99 relative to the scene size")->check(numberIn(0, HUGE_VAL));
  cmd->add_option("--min-kind", o->minKind, "Smallest patch-kind agreement fraction")->check(numberIn(0, 1));
  cmd->add_option("--min-patch", o->minPatch, "Smallest patch-id agreement fraction")->check(numberIn(0, 1));
  cmd->add_option("--max-normal-p99", o->maxNormalP99, "Largest normal-angle p99 in degrees")->check(numberIn(0, HUGE_VAL));
  cmd->add_option("--max-color-p99", o->maxColorP99,
                  "Largest colour-difference p99 (largest of |dR|, |dG|, |dB| in [0, 1]) outside silhouettes and seams")
      ->check(numberIn(0, 1));
  cmd->add_flag("--ignore-camera", o->ignoreCamera, "Compare even if the images' recorded cameras differ");
  cmd->add_flag("--ignore-settings", o->ignoreSettings,
                "Compare even if the images' recorded render settings differ (colour scheme, background, lighting, "
                "samples, opacity, effects, ball and stick); the preset's colour limit is then not applied");
  addForeignBufferOptions(*cmd, *o);
  cmd->callback([o] {
    try {
      runCompare(*o);
    } catch (const LimitsExceeded& e) {
      std::printf("%s\n", e.what());
      build::finishStandardOutput();  // a closed pipe is an error (1), not a verdict (2)
      std::exit(2);
    }
  });
}

}  // namespace surftrace::tools

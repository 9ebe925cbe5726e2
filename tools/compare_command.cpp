// `surftrace compare`: two renderings of one view, pixel by pixel, with pass/fail limits; the
// rendering under test may be SurfTrace's EXR or another renderer's depth and normal buffers.
#include <array>
#include <cstdio>
#include <fstream>
#include <memory>
#include <optional>
#include <stdexcept>

#include <nlohmann/json.hpp>

#include "build/io/output_file.hpp"
#include "commands.hpp"
#include "option_checks.hpp"
#include "view/camera.hpp"
#include "view/compare_report.hpp"
#include "view/foreign_buffers.hpp"
#include "view/image_compare.hpp"
#include "view/image_io.hpp"

namespace surftrace::tools {
namespace {

struct CompareOptions {
  std::string test, reference, report, diff, html, preset;
  std::optional<double> maxCoverage, maxDepthP99, minKind, minPatch, maxNormalP99, maxColorP99;
  bool ignoreCamera = false;
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
// engine, `gl-vs-embree` otherwise (different engines, or one not recorded). Says which.
std::string defaultPreset(const view::ImageMetadata& test, const view::ImageMetadata& ref) {
  const std::string a = engineOf(test), b = engineOf(ref);
  const std::string preset = !a.empty() && a == b ? "exact" : "gl-vs-embree";
  std::printf("limits    --preset %s (engines: test %s, reference %s; pass --preset to choose)\n", preset.c_str(),
              a.empty() ? "not recorded" : a.c_str(), b.empty() ? "not recorded" : b.c_str());
  return preset;
}

std::string sizeMismatch(const std::string& test, int tw, int th, const std::string& ref, int rw, int rh) {
  return test + " is " + std::to_string(tw) + "x" + std::to_string(th) + " but " + ref + " is " + std::to_string(rw) + "x" +
         std::to_string(rh);
}

// Another renderer's buffers (TEST and --test-normal) along the reference camera's rays.
TestImage readForeign(const CompareOptions& o, const view::ForeignBufferOptions& f, const view::FrameBuffers& ref,
                      const std::optional<view::Camera>& camera) {
  const view::ImageChannels depth = readingFile(o.test, "the image", [&] { return view::readImageChannels(o.test); });
  std::optional<view::ImageChannels> normals;
  if (!o.testNormal.empty())
    normals = readingFile(o.testNormal, "the image", [&] { return view::readImageChannels(o.testNormal); });
  const view::ImageChannels* normalImage = normals ? &*normals : nullptr;
  for (const view::ImageChannels* image : {&depth, normalImage})
    if (image && (image->width != ref.width || image->height != ref.height))
      throw std::invalid_argument(sizeMismatch(image->path, image->width, image->height, o.reference, ref.width, ref.height));
  if (!camera)
    throw std::invalid_argument(o.reference + " records no camera (surftrace:camera metadata), and another renderer's "
                                "buffers are compared along the reference camera's rays: render the reference with "
                                "surftrace render --exr");
  try {
    view::ForeignFrame foreign = view::foreignFrame(depth, normalImage, f, *camera);
    TestImage t{std::move(foreign.frame), foreign.carried, {}, {}, {}};
    char range[96] = "";
    if (f.depthConvention == view::DepthConvention::Window)
      std::snprintf(range, sizeof range, " for near %.6g, far %.6g Å", camera->zNear, camera->zFar);
    t.description = "another renderer's buffers, compared in Å along the reference's rays";
    t.details = "          depth   channel " + foreign.depthChannel + ", " + view::conventionName(f.depthConvention) +
                " depth" + range + ", rows from the " + view::originName(f.origin) + "\n          normals " +
                (normals ? o.testNormal + ", " + view::spaceName(f.normalSpace) + " space, " + view::encodingName(f.normalEncoding)
                         : std::string("none (no --test-normal)")) +
                "\n";
    return t;
  } catch (const std::invalid_argument& e) {
    throw std::invalid_argument(o.reference + ": " + e.what());  // the camera's: name the reference
  }
}

// On a failure with another renderer's buffers: whether their rows might be upside down (the
// most common slip: glReadPixels' rows come bottom first), from the same buffers read the other way.
std::string originHint(const CompareOptions& o, view::ForeignBufferOptions f, const view::FrameBuffers& ref,
                       const view::Camera& camera, const view::FrameComparison& c) {
  f.origin = f.origin == view::RowOrigin::BottomLeft ? view::RowOrigin::TopLeft : view::RowOrigin::BottomLeft;
  const TestImage flipped = readForeign(o, f, ref, camera);
  const view::FrameComparison other = view::compareFrames(flipped.frame, ref, &camera, flipped.carried);
  if (!(c.coverageFraction > 1e-3 && other.coverageFraction < 0.25 * c.coverageFraction)) return "";
  char text[256];
  std::snprintf(text, sizeof text,
                "\n  hint: with --test-origin %s the coverage mismatch would be %.4g%% (it is %.4g%%): are the rows upside "
                "down?",
                view::originName(f.origin), 100 * other.coverageFraction, 100 * c.coverageFraction);
  return text;
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
                   bool foreign, const view::ForeignBufferOptions& foreignOpts) {
  TestImage testImage;
  if (foreign) {
    testImage = readForeign(o, foreignOpts, ref, camera);
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
  report["per_kind"] = view::kindDepthErrorsJson(view::kindDepthErrors(testImage.frame, ref, masks, testImage.carried));
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
  const TestImage testImage = readTest(o, ref, camera, foreign, foreignOpts);
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
  const view::CompareThresholds limits = limitsOf(o, preset);
  const view::DifferenceScale scale = view::DifferenceScale::of(limits, c);
  std::vector<float> diff;
  if (!o.diff.empty() || !o.html.empty()) diff = view::differenceImage(testImage.frame, ref, testImage.carried, cameraPtr, scale);
  if (!o.diff.empty()) writeDifference(o.diff, diff, ref, scale);
  // A limit on a buffer the test does not carry is neither passed nor failed.
  const auto unjudged = limits.notCompared(c);
  std::string verdict;
  for (const auto& line : unjudged) verdict += "not compared: " + line + "\n";
  const std::string scope = unjudged.empty() ? "" : ", on what the test carries";
  const auto violations = limits.violations(c);
  if (violations.empty()) {
    verdict += "PASS (" + (preset == "none" ? std::string("no limits: --preset none") : preset) + scope + ")";
  } else {
    verdict += "FAIL (" + preset + scope + "):";
    for (const auto& v : violations) verdict += "\n  " + v;
    if (foreign) verdict += originHint(o, foreignOpts, ref, *camera, c);
  }
  if (!o.html.empty()) {
    view::HtmlReport page;
    page.title = o.test + " vs " + o.reference;
    page.verdict = c.summary() + "\nlimits    --preset " + preset + "\n" + verdict;
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
      "masking the reference's silhouette band, seams and flagged pixels. Exit status 0 within the limits, 2 outside "
      "them, 1 on an error");
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
                                         "kinds > 99.9%), exact (a re-render by the same engine), foreign (another "
                                         "renderer's buffers: coverage < 0.1%, depth p99 < 1e-3 of the scene, normal p99 "
                                         "< 1°), effects (gl-vs-embree and colour p99 < 0.02: two engines' images with the "
                                         "same image-space effects), transparency (gl-vs-embree and colour p99 < 1e-3: GL's depth peeling "
                                         "against Embree's layers at --opacity < 1), or none (report the metrics, judge nothing). Default: foreign for another "
                                         "renderer's buffers, exact when the two images' metadata name the same engine, "
                                         "else gl-vs-embree")
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

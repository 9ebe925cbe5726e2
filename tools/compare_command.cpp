// `surftrace compare`: two renderings of one view, pixel by pixel, with pass/fail limits.
#include <cstdio>
#include <fstream>
#include <memory>
#include <optional>
#include <stdexcept>

#include "build/io/output_file.hpp"
#include "commands.hpp"
#include "option_checks.hpp"
#include "view/camera.hpp"
#include "view/image_compare.hpp"
#include "view/image_io.hpp"

namespace surftrace::tools {
namespace {

struct CompareOptions {
  std::string test, reference, report, diff, preset;
  std::optional<double> maxCoverage, maxDepthP99, minKind, minPatch, maxNormalP99;
  bool ignoreCamera = false;
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

void runCompare(const CompareOptions& o) {
  if (!o.report.empty()) build::prepareOutputPath(o.report, "--report");
  if (!o.diff.empty()) build::prepareOutputPath(o.diff, "--diff");
  view::ImageMetadata testMeta, refMeta;
  const view::FrameBuffers test = view::readExr(o.test, &testMeta);
  const view::FrameBuffers ref = view::readExr(o.reference, &refMeta);
  if (test.width != ref.width || test.height != ref.height)
    throw std::invalid_argument(o.test + " is " + std::to_string(test.width) + "x" + std::to_string(test.height) + " but " +
                                o.reference + " is " + std::to_string(ref.width) + "x" + std::to_string(ref.height));
  std::optional<view::Camera> camera;
  if (refMeta.count("surftrace:camera")) camera = view::cameraFromJson(refMeta.at("surftrace:camera"));
  if (!o.ignoreCamera && camera && testMeta.count("surftrace:camera")) {
    const view::Camera other = view::cameraFromJson(testMeta.at("surftrace:camera"));
    if (other.eye != camera->eye || other.lookAt != camera->lookAt || other.up != camera->up ||
        other.fovY != camera->fovY || other.projection != camera->projection || other.orthoHeight != camera->orthoHeight)
      throw std::invalid_argument("the two images were rendered with different cameras (see their surftrace:camera "
                                  "metadata); compare only renderings of the same view, or pass --ignore-camera");
  }
  const view::FrameComparison c = view::compareFrames(test, ref, camera ? &*camera : nullptr);
  std::printf("test      %s (%s)\nreference %s (%s)\n%s\n", o.test.c_str(),
              testMeta.count("surftrace:renderer") ? testMeta.at("surftrace:renderer").c_str() : "?", o.reference.c_str(),
              refMeta.count("surftrace:renderer") ? refMeta.at("surftrace:renderer").c_str() : "?", c.summary().c_str());
  if (!o.report.empty()) build::writeFileAtomically(o.report, c.json() + "\n");
  if (!o.diff.empty()) {
    const std::vector<float> rgb = view::differenceImage(test, ref);
    view::FrameBuffers image;
    image.width = ref.width;
    image.height = ref.height;
    image.rgba.resize(4 * ref.pixels());
    for (std::size_t p = 0; p < ref.pixels(); ++p) {
      for (int k = 0; k < 3; ++k) image.rgba[4 * p + k] = rgb[3 * p + k];
      image.rgba[4 * p + 3] = 1.0f;
    }
    view::writePng(o.diff, image, {{"surftrace:legend", "grey agree; blue silhouette band (masked); red coverage differs; "
                                                         "green patch kind differs; yellow to magenta depth error 1e-6..1 Å"}});
  }
  const std::string preset = o.preset.empty() ? defaultPreset(testMeta, refMeta) : o.preset;
  view::CompareThresholds limits = preset == "none" ? view::CompareThresholds{} : view::CompareThresholds::preset(preset);
  if (o.maxCoverage) limits.maxCoverageFraction = o.maxCoverage;
  if (o.maxDepthP99) limits.maxDepthP99Relative = o.maxDepthP99;
  if (o.minKind) limits.minKindAgreement = o.minKind;
  if (o.minPatch) limits.minPatchAgreement = o.minPatch;
  if (o.maxNormalP99) limits.maxNormalP99Degrees = o.maxNormalP99;
  const auto violations = limits.violations(c);
  if (violations.empty()) {
    std::printf("PASS (%s)\n", preset == "none" ? "no limits: --preset none" : preset.c_str());
    return;
  }
  std::string text = "FAIL:";
  for (const auto& v : violations) text += "\n  " + v;
  throw LimitsExceeded(text);
}

}  // namespace

void addCompareCommand(CLI::App& app) {
  auto o = std::make_shared<CompareOptions>();
  auto* cmd = app.add_subcommand(
      "compare",
      "Compare a rendering (TEST.exr) with a reference of the same view (REFERENCE.exr, usually the Embree image) "
      "pixel by pixel: coverage, depth, normal, patch kind and id, masking the reference's silhouette band, seams "
      "and flagged pixels. Exit status 0 within the limits, 2 outside them, 1 on an error");
  cmd->add_option("TEST", o->test, "EXR under test (e.g. from --engine gl)")->required()->check(CLI::ExistingFile);
  cmd->add_option("REFERENCE", o->reference, "Reference EXR; its masks and camera are used")->required()->check(CLI::ExistingFile);
  cmd->add_option("--report", o->report, "Write the metrics as JSON here");
  cmd->add_option("--diff", o->diff, "Write a false-colour difference PNG here");
  cmd->add_option("--preset", o->preset, "Limits: gl-vs-embree (coverage < 0.1%, depth p99 < 1e-3 of the scene, "
                                         "kinds > 99.9%), exact (a re-render by the same engine), or none (report "
                                         "the metrics, judge nothing). Default: exact when the two images' metadata "
                                         "name the same engine, else gl-vs-embree")
      ->check(CLI::IsMember({"gl-vs-embree", "exact", "none"}));
  cmd->add_option("--max-coverage", o->maxCoverage, "Largest coverage-mismatch fraction outside silhouettes")->check(numberIn(0, 1));
  cmd->add_option("--max-depth-p99", o->maxDepthP99, "Largest depth-error p99 relative to the scene size")->check(numberIn(0, HUGE_VAL));
  cmd->add_option("--min-kind", o->minKind, "Smallest patch-kind agreement fraction")->check(numberIn(0, 1));
  cmd->add_option("--min-patch", o->minPatch, "Smallest patch-id agreement fraction")->check(numberIn(0, 1));
  cmd->add_option("--max-normal-p99", o->maxNormalP99, "Largest normal-angle p99 in degrees")->check(numberIn(0, HUGE_VAL));
  cmd->add_flag("--ignore-camera", o->ignoreCamera, "Compare even if the images' recorded cameras differ");
  cmd->callback([o] {
    try {
      runCompare(*o);
    } catch (const LimitsExceeded& e) {
      std::printf("%s\n", e.what());
      std::fflush(stdout);
      std::exit(2);
    }
  });
}

}  // namespace surftrace::tools

// `surftrace compare`: two renderings of one view, pixel by pixel, with pass/fail limits; the
// rendering under test may be SurfTrace's EXR or another renderer's depth and normal buffers.
#include <cmath>
#include <cstdio>
#include <iterator>
#include <memory>
#include <optional>
#include <sstream>
#include <stdexcept>
#include <string>
#include <vector>

#include "commands.hpp"
#include "option_checks.hpp"
#include "progress_bar.hpp"
#include "surface_options.hpp"
#include "surftrace/compare.hpp"
#include "surftrace/files.hpp"
#include "surftrace/image.hpp"

namespace surftrace::tools {
namespace {

struct CompareOptions {
  std::string test, reference, report, diff, html, preset;
  std::optional<double> maxCoverage, maxDepthP99, minKind, minPatch, maxNormalP99, maxColorP99;
  bool ignoreCamera = false;
  bool ignoreSettings = false;
  // Another renderer's buffers (empty: not given; the defaults are foreignOptions').
  std::string depthChannel, depthConvention, testNormal, normalSpace, normalEncoding, testOrigin;
  // Meshes: moved into the structure's frame, and compared all around with a structure.
  std::string meshTransform;
  int views = 0;
  std::string size = "512x512";
  std::optional<double> maxError;
  std::string maxErrorStat = "p99";
  SurfaceOptions surface;
  build::ReadOptions read;
  bool foreignFlags() const {
    return !depthChannel.empty() || !depthConvention.empty() || !testNormal.empty() || !normalSpace.empty() ||
           !normalEncoding.empty() || !testOrigin.empty();
  }
};

ForeignBufferOptions foreignOptions(const CompareOptions& o) {
  ForeignBufferOptions f;
  f.depthChannel = o.depthChannel;
  if (!o.depthConvention.empty()) f.depthConvention = depthConventionNamed(o.depthConvention);
  if (!o.testOrigin.empty()) f.origin = rowOriginNamed(o.testOrigin);
  if (!o.normalSpace.empty()) f.normalSpace = normalSpaceNamed(o.normalSpace);
  if (!o.normalEncoding.empty()) f.normalEncoding = normalEncodingNamed(o.normalEncoding);
  return f;
}

// Exit codes: 0 within the limits, 2 outside them (1 is an error, from main).
struct LimitsExceeded : std::runtime_error {
  using std::runtime_error::runtime_error;
};

// The rendering under test as the flags say: SurfTrace's own EXR, or another renderer's buffers
// when a flag says so or TEST lacks SurfTrace's channels. Each file is read under readingFile, so
// that one too large for memory is named.
CompareTest readTest(const CompareOptions& o) {
  if (!o.foreignFlags() && hasFrameBufferChannels(o.test))
    return readingFile(o.test, "the image", [&] { return readSurfTraceTest(o.test); });
  CompareTest test;
  test.name = o.test;
  test.foreign = ForeignBuffers{readingFile(o.test, "the image", [&] { return readImageChannels(o.test); }),
                                std::nullopt, foreignOptions(o)};
  if (!o.testNormal.empty())
    test.foreign->normals = readingFile(o.testNormal, "the image", [&] { return readImageChannels(o.testNormal); });
  return test;
}

// Whether REFERENCE is a structure rather than an image: OpenImageIO knows no format for it.
bool isStructureLike(const std::string& path) {
  try {
    (void)hasFrameBufferChannels(path);
    return false;
  } catch (const std::exception&) {
    return true;
  }
}

// A mesh TEST against a reference EXR: drawn along the reference's rays.
CompareTest readMeshOf(const CompareOptions& o, const CompareReference& ref) {
  std::optional<glm::dmat4> transform;
  if (!o.meshTransform.empty()) transform = parseMeshTransform(o.meshTransform);
  return readingFile(o.test, "the mesh", [&] { return readMeshTest(o.test, ref, transform); });
}

// WIDTHxHEIGHT for --size.
void parseViewSize(const std::string& text, int& width, int& height) {
  std::istringstream in(text);
  char x = 0;
  if (!(in >> width >> x >> height) || (x != 'x' && x != 'X') || in.peek() != EOF || width < 1 || height < 1 ||
      width > 32768 || height > 32768)
    throw std::invalid_argument("--size '" + text + "': expected WIDTHxHEIGHT, each 1..32768, e.g. 512x512");
}

// `compare MESH STRUCTURE --views N`: the mesh against the structure's exact surface all around.
void runViews(const CompareOptions& o) {
  if (!isMeshPath(o.test))
    throw std::invalid_argument(o.test + ": --views compares a mesh (.obj, .ply, .stl, .off, .gltf, .glb) with a structure's "
                                "exact surface; TEST is not one");
  if (!o.diff.empty() || !o.html.empty())
    throw std::invalid_argument("--diff and --html draw one view; with --views use --report");
  if (!o.report.empty()) prepareOutputPath(o.report, "--report");
  MeshViewsSettings settings;
  settings.views = o.views;
  parseViewSize(o.size, settings.width, settings.height);
  TriangleMesh mesh = readingFile(o.test, "the mesh", [&] { return readMesh(o.test); });
  if (!o.meshTransform.empty()) transformMesh(mesh, parseMeshTransform(o.meshTransform));
  const build::Molecule molecule = readInput(o.reference, "", 0, o.read);
  const build::PatchList patches = buildWithNotes(molecule, o.surface.request());
  ProgressBar bar(true, "views");
  settings.progress = [&bar](std::size_t done, std::size_t total) { bar.items(done, total, "views"); };
  const MeshViewsResult r = compareMeshViews(mesh, patches, molecule, settings);
  bar.clear();
  std::printf("test      %s (a mesh of %zu vertices and %zu triangles, %s%s)\nreference %s (%s surface, exact: Embree)\n%s\n",
              o.test.c_str(), mesh.vertexCount(), mesh.triangleCount(), mesh.normals.empty() ? "face normals" : "vertex normals",
              o.meshTransform.empty() ? "" : ", moved by --mesh-transform", o.reference.c_str(), o.surface.surface.c_str(),
              r.summary().c_str());
  if (!o.report.empty()) writeFileAtomically(o.report, r.json() + "\n");
  if (!o.maxError) {
    std::printf("PASS (no limit: give --max-error to judge)\n");
    return;
  }
  const bool useMax = o.maxErrorStat == "max";
  const double error = r.error(useMax);
  char line[320];
  std::snprintf(line, sizeof line, "the larger %s of the two distance estimates is %.4g Å", o.maxErrorStat.c_str(), error);
  if (error <= *o.maxError) {
    std::printf("PASS (--max-error %g Å, %s): %s\n", *o.maxError, o.maxErrorStat.c_str(), line);
    return;
  }
  char limit[96];
  std::snprintf(limit, sizeof limit, "FAIL (--max-error %g Å, %s):\n  ", *o.maxError, o.maxErrorStat.c_str());
  throw LimitsExceeded(std::string(limit) + line + " > " + std::to_string(*o.maxError) + " Å");
}

CompareSettings settingsOf(const CompareOptions& o) {
  CompareSettings s;
  s.preset = o.preset;
  s.limits.maxCoverageFraction = o.maxCoverage;
  s.limits.maxDepthP99Relative = o.maxDepthP99;
  s.limits.minKindAgreement = o.minKind;
  s.limits.minPatchAgreement = o.minPatch;
  s.limits.maxNormalP99Degrees = o.maxNormalP99;
  s.limits.maxColorP99 = o.maxColorP99;
  s.ignoreCamera = o.ignoreCamera;
  s.ignoreSettings = o.ignoreSettings;
  s.report = !o.report.empty() || !o.html.empty();  // the masks they need take time
  return s;
}

void runCompare(const CompareOptions& o) {
  if (o.views > 0) return runViews(o);
  const bool mesh = isMeshPath(o.test);
  if (!mesh && !o.meshTransform.empty())
    throw std::invalid_argument("--mesh-transform moves a mesh (.obj, .ply, .stl, .off, .gltf, .glb); " + o.test + " is not one");
  if (o.maxError) throw std::invalid_argument("--max-error judges `compare MESH STRUCTURE --views N`; give --views");
  if (mesh && isStructureLike(o.reference))
    throw std::invalid_argument(o.reference + " is not an image: to compare the mesh with a structure's exact surface all "
                                "around, give --views N (e.g. --views 26)");
  if (!o.report.empty()) prepareOutputPath(o.report, "--report");
  if (!o.diff.empty()) view::checkImageOutputName(o.diff, "--diff", view::ImageContent::Colour);
  if (!o.diff.empty()) prepareOutputPath(o.diff, "--diff", OutputContent::Binary);
  if (!o.html.empty()) prepareOutputPath(o.html, "--html");
  const CompareReference ref =
      readingFile(o.reference, "the image", [&] { return readCompareReference(o.reference); });
  const CompareResult r = surftrace::compare(mesh ? readMeshOf(o, ref) : readTest(o), ref, settingsOf(o));
  std::printf("%s", r.settingsLines.c_str());
  std::printf("test      %s (%s)\n%sreference %s (%s)\n%s\n", o.test.c_str(), r.testDescription.c_str(),
              r.testDetails.c_str(), o.reference.c_str(), r.referenceDescription.c_str(), r.figures.summary().c_str());
  if (!o.report.empty()) writeFileAtomically(o.report, r.json() + "\n");
  if (!r.presetChoice.empty()) std::printf("%s\n", r.presetChoice.c_str());
  std::vector<float> diff;
  if (!o.diff.empty() || !o.html.empty()) diff = differenceImage(r, ref);
  if (!o.diff.empty()) writeDifference(o.diff, r, diff);
  if (!o.html.empty()) writeFileAtomically(o.html, comparisonPage(r, ref, diff));
  if (r.passed()) {
    std::printf("%s\n", r.verdict().c_str());
    return;
  }
  throw LimitsExceeded(r.verdict());
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

// Meshes (README, compare): TEST may be a mesh, drawn along REFERENCE's rays, or with --views
// judged against a structure's exact surface all around.
void addMeshOptions(CLI::App& cmd, CompareOptions& o) {
  const char* group = "Meshes (TEST .obj, .ply, .stl, .off, .gltf or .glb)";
  cmd.add_option("--mesh-transform", o.meshTransform,
                 "Move the mesh by a 4x4 affine matrix, given row by row (x' = M (x, y, z, 1), last row 0 0 0 1): a file of "
                 "16 numbers, or 16 comma-separated numbers; normals move by the inverse transpose. For PyMOL's OBJ, which "
                 "is in its camera frame, see README, compare")
      ->group(group);
  cmd.add_option("--views", o.views,
                 "Compare the mesh with the exact surface of REFERENCE (then a structure: PDB, mmCIF, PQR, XYZR, ...) from "
                 "N orthographic views spread evenly over the sphere, each framed tightly: per-kind depth errors, two-sided "
                 "distance estimates and the worst places")
      ->check(wholeIn(1, 10000))
      ->group(group);
  cmd.add_option("--size", o.size, "With --views: each view's size WIDTHxHEIGHT")->default_val("512x512")->group(group);
  cmd.add_option("--max-error", o.maxError,
                 "With --views: the largest distance (Å) allowed to either distance estimate's statistic "
                 "(--max-error-stat); exit status 2 beyond it")
      ->check(numberIn(0, HUGE_VAL))
      ->group(group);
  cmd.add_option("--max-error-stat", o.maxErrorStat, "With --views: which statistic --max-error limits: p99 (the default) or max")
      ->check(CLI::IsMember({"p99", "max"}))
      ->group(group);
  addSurfaceOptions(cmd, o.surface, SurfaceChoice::Any);
  addMoleculeOptions(cmd, o.read);
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
                  "buffer in any format OpenImageIO reads (EXR, PFM, float TIFF, 16-bit PNG; see --depth-convention), or a "
                  "mesh (.obj, .ply, .stl, .off, .gltf, .glb) drawn along REFERENCE's rays")
      ->required()
      ->check(CLI::ExistingFile);
  cmd->add_option("REFERENCE", o->reference,
                  "Reference EXR; its masks and camera are used. With --views: a structure, whose exact surface is rendered")
      ->required()
      ->check(CLI::ExistingFile);
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
      ->check(CLI::IsMember(std::vector<std::string>(std::begin(kComparePresets), std::end(kComparePresets))));
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
  addMeshOptions(*cmd, *o);
  cmd->callback([o] {
    try {
      runCompare(*o);
    } catch (const LimitsExceeded& e) {
      std::printf("%s\n", e.what());
      finishStandardOutput();  // a closed pipe is an error (1), not a verdict (2)
      std::exit(2);
    }
  });
}

}  // namespace surftrace::tools

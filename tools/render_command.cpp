// `surftrace render`: exact ray tracing of a molecular surface to PNG and EXR.
#include <algorithm>
#include <chrono>
#include <cstdio>
#include <memory>
#include <stdexcept>
#include <vector>


#include "commands.hpp"
#include "image_options.hpp"
#include "option_checks.hpp"
#include "pipeline.hpp"
#include "surftrace/files.hpp"
#include "surftrace/image.hpp"
#include "surftrace/molecule.hpp"
#include "surftrace/surface.hpp"

namespace surftrace::tools {
namespace {

struct RenderCommandOptions {
  std::string path;
  build::ReadOptions read;
  SurfaceOptions surface;
  std::string patches;
  std::string trajectory;   // FILE is then its topology
  int frame = 0;
  CLI::Option* frameOption = nullptr;
  ImageOptions image;
  view::EngineOptions engine;
  std::string output, exr;
  int threads = 0;
  bool quiet = false;
  bool cavities = false;  // --cavities: the SES's cavities alone
  std::string commandLine;
};

// Every option is checked before the slow work starts, the output paths too.
void checkRenderOptions(const RenderCommandOptions& o, const view::RenderOptions& render, bool fromPatchList) {
  if (o.output.empty() && o.exr.empty()) throw std::invalid_argument("nothing to write: give -o OUT.png and/or --exr OUT.exr");
  view::checkEngineCanDraw(o.engine, render);
  if (!o.output.empty()) view::checkImageOutputName(o.output, "-o", view::ImageContent::Colour);
  if (!o.exr.empty()) view::checkImageOutputName(o.exr, "--exr", view::ImageContent::Buffers);
  if (!o.output.empty()) build::prepareOutputPath(o.output, "-o", build::OutputContent::Binary);
  if (!o.exr.empty()) build::prepareOutputPath(o.exr, "--exr", build::OutputContent::Binary);
  if (o.cavities && o.surface.dropCavities)
    throw std::invalid_argument("--cavities draws the cavities that --drop-cavities leaves out: give one of them");
  if (o.cavities && o.surface.surface != "ses")
    throw std::invalid_argument("--cavities draws the SES's cavities; --surface " + o.surface.surface +
                                " has none (its patches carry no component labels): leave out --surface");
  if (o.frameOption && o.frameOption->count() > 0 && o.trajectory.empty())
    throw std::invalid_argument("--frame " + std::to_string(o.frame) + " needs --trajectory FILE (and FILE its topology)");
  if (!fromPatchList) return;
  if (o.read.selection)
    throw std::invalid_argument("--select needs the structure file: " + o.path +
                                " is a patch list, which holds no atom records (render the structure file)");
  if (o.image.ballAndStick)
    throw std::invalid_argument("--ball-and-stick needs the atoms and their records, which a patch list (" + o.path +
                                ") does not hold: render the structure file");
  // A patch list given as FILE (told by its magic) is rendered as it is: its own surface,
  // probe and shrink factor, framed from its patches.
  if (!o.patches.empty())
    throw std::invalid_argument(o.path + " is a patch list already; --patches applies to a structure file");
  if (!o.trajectory.empty())
    throw std::invalid_argument(o.path + " is a patch list; --trajectory needs the trajectory's topology as FILE");
  const view::ColorMode color = view::parseColorMode(o.image.color);
  if (color != view::ColorMode::Patch && color != view::ColorMode::Uniform)
    throw std::invalid_argument("--color " + o.image.color + " needs the atoms' records, which a patch list (" + o.path +
                                ") does not hold: render the structure file, or use --color patch|uniform");
  if (!o.image.colorSelect.empty())
    throw std::invalid_argument("--color-select needs the atoms' records, which a patch list (" + o.path +
                                ") does not hold: render the structure file");
}

// The patch list FILE names, held to the options that cannot change it.
build::PatchList readPatchListInput(const RenderCommandOptions& o) {
  build::PatchList list = readingFile(o.path, "the patch list", [&] { return build::readPatchList(o.path); });
  if (o.surface.surface != "ses" && build::parseSurfaceKind(o.surface.surface) != list.params.surface)
    throw std::invalid_argument(o.path + " is a " + build::surfaceKindName(list.params.surface) + " patch list; --surface " +
                                o.surface.surface + " needs the structure file");
  if (o.surface.probeGiven() && o.surface.probe != list.params.probeRadius)
    throw std::invalid_argument(o.path + " was built with probe " + std::to_string(list.params.probeRadius) +
                                " Å; --probe " + std::to_string(o.surface.probe) + " cannot change it (rebuild it)");
  if (o.surface.dropCavities) list = build::outerComponent(list);
  return list;
}

// Stages "read" and "build": the molecule (none for a patch list FILE) and its surface.
build::PatchList readAndBuild(const RenderCommandOptions& o, bool fromPatchList, build::Molecule& molecule,
                              double& readSeconds, double& buildSeconds) {
  auto start = std::chrono::steady_clock::now();
  if (!fromPatchList) molecule = readInput(o.path, o.trajectory, static_cast<std::size_t>(o.frame), o.read);
  readSeconds = secondsSince(start);
  start = std::chrono::steady_clock::now();
  build::PatchList list;
  if (fromPatchList) {
    list = readPatchListInput(o);
  } else if (!o.patches.empty()) {
    list = readingFile(o.patches, "the patch list", [&] { return build::readPatchList(o.patches); });
    build::checkPatchListMatches(list, o.patches, molecule, o.surface.request());
    if (o.surface.dropCavities) list = build::outerComponent(list);
  } else {
    list = buildWithNotes(molecule, o.surface.request());
  }
  buildSeconds = secondsSince(start);
  return list;
}

// Stage "frame the camera": on what the surface can reach; a patch list without its structure
// is framed from its convex patches' atoms, which reach furthest (a buried atom's extended
// sphere lies inside the others'), so the camera is the one the structure itself would get.
void frameRender(ImageSetup& setup, const build::PatchList& list, const build::Molecule& molecule, bool fromPatchList,
                 const std::string& path) {
  if (fromPatchList && list.params.surface != build::SurfaceKind::Mss) {
    const std::vector<double> reach = build::SurfaceRequest::of(list.params).reachOfSpheres(list.convex.radius);
    if (list.convex.size() == 0) throw std::invalid_argument(path + ": the patch list has no convex patches to frame");
    frameSpheres(setup, list.convex.center, reach);
  } else {
    frameSurface(setup, list, molecule);
  }
  writeCameraOut(setup);
}

// What the image records: a patch list FILE's own surface, probe and shrink factor.
ImageRecord recordOfRender(const RenderCommandOptions& o, const build::PatchList& list, bool fromPatchList) {
  ImageRecord record = recordOf(o.surface, o.path, o.image, o.commandLine);
  if (fromPatchList) {
    record.surface = build::surfaceKindName(list.params.surface);
    record.probeRadius = list.params.probeRadius;
    record.shrinkFactor.reset();
    if (list.params.surface == build::SurfaceKind::Mss) record.shrinkFactor = list.params.shrinkFactor;
  }
  if (!o.trajectory.empty()) {
    record.trajectory = o.trajectory;
    record.frame = static_cast<std::size_t>(o.frame);
  }
  return record;
}

// How many layers the covered pixels' centre rays crossed: what --max-layers should be.
void printLayerSummary(std::vector<std::uint32_t> layers, int maxLayers) {
  std::erase(layers, 0u);
  if (layers.empty()) return;
  std::sort(layers.begin(), layers.end());
  const auto at = [&](double q) { return layers[static_cast<std::size_t>(q * static_cast<double>(layers.size() - 1))]; };
  const auto capped = std::count(layers.begin(), layers.end(), static_cast<std::uint32_t>(maxLayers));
  std::printf("layers per covered pixel: median %u, 99th percentile %u, max %u; %td pixels reached --max-layers %d\n",
              at(0.5), at(0.99), layers.back(), capped, maxLayers);
}

// "1 sample a pixel", "4 samples a pixel (2x2)": what the colour averages, as --spp is rounded
// up to a square grid (--spp 2 takes 4).
std::string samplesText(int spp) {
  view::RenderOptions options;
  options.samplesPerPixel = spp;
  const int k = options.sampleGridSide();
  if (k == 1) return "1 sample a pixel";
  return std::to_string(k * k) + " samples a pixel (" + std::to_string(k) + "x" + std::to_string(k) + ")";
}

void printRenderSummary(const RenderCommandOptions& o, const build::PatchList& list, const view::FrameBuffers& frame,
                        double readSeconds, double buildSeconds, double sceneSeconds) {
  std::size_t covered = 0;
  for (auto k : frame.kind) covered += k != 0;
  std::string counts;
  for (const view::PatchKindInfo& k : view::kPatchKinds) {
    const std::size_t n = view::patchCount(list, k.kind);
    if (n > 0) counts += (counts.empty() ? "" : ", ") + std::to_string(n) + " " + k.name;
  }
  std::printf("%s: %zu atoms, %s, %zu patches (%s); engine %s\n", o.path.c_str(),
              static_cast<std::size_t>(list.params.atomCount), build::surfaceKindName(list.params.surface),
              list.patchCount(), counts.c_str(), view::engineKindName(o.engine.kind));
  if (!o.trajectory.empty()) std::printf("frame %d of %s\n", o.frame, o.trajectory.c_str());
  std::printf("read %.1f ms, surface %.1f ms, scene %.1f ms, frame %.1f ms (%dx%d, %s, %.2f Mrays/s), %.1f%% covered\n",
              readSeconds * 1e3, buildSeconds * 1e3, sceneSeconds * 1e3, frame.seconds * 1e3, frame.width,
              frame.height, samplesText(o.image.spp).c_str(), static_cast<double>(frame.rays) / frame.seconds * 1e-6,
              100.0 * static_cast<double>(covered) / static_cast<double>(frame.pixels()));
  if (!frame.layers.empty()) printLayerSummary(frame.layers, o.image.maxLayers);
  if (!o.output.empty()) std::printf("wrote %s\n", o.output.c_str());
  if (!o.exr.empty()) std::printf("wrote %s\n", o.exr.c_str());
  if (!o.image.legendFile.empty()) std::printf("wrote %s\n", o.image.legendFile.c_str());
}

void runRender(const RenderCommandOptions& o) {
  const bool fromPatchList = isPatchListPath(o.path);
  ImageSetup setup = resolveImageOptions(o.image);
  checkRenderOptions(o, setup.render, fromPatchList);
  const auto limit = limitThreads(o.threads);
  build::Molecule molecule;
  double readSeconds = 0.0, buildSeconds = 0.0;
  build::PatchList list = readAndBuild(o, fromPatchList, molecule, readSeconds, buildSeconds);
  // Framed on the whole surface, so that the cavities stand where the whole render has them.
  frameRender(setup, list, molecule, fromPatchList, o.path);
  if (o.cavities) {
    if (list.params.surface != build::SurfaceKind::Ses)
      throw std::invalid_argument("--cavities draws the SES's cavities; " + o.path + " is a " +
                                  build::surfaceKindName(list.params.surface) + " patch list, which has none");
    list = build::cavityComponents(list);
    if (list.patchCount() == 0)
      throw std::invalid_argument(o.path + " has no cavity a probe of " + std::to_string(list.params.probeRadius) +
                                  " Å fits in: --cavities has nothing to draw (a smaller --probe may find some)");
  }
  // An EXR is what `compare` takes as a reference: it records where its masks belong.
  setup.render.referenceMasks = !o.exr.empty();
  const auto colors = fromPatchList
                          ? std::vector<glm::vec3>(list.params.atomCount, view::srgbToLinear(setup.uniformColor))
                          : colorAtoms(setup, molecule);
  const BallAndStick ballAndStick = BallAndStick::of(o.image, molecule);
  const build::BallStickModel model =
      ballAndStick.on ? ballAndStick.model(molecule.centers, molecule.radii) : build::BallStickModel();
  const std::unique_ptr<view::Engine> engine = makeEngine(o.engine);
  // GL reports no progress: its frame is one draw.
  ProgressBar bar(!o.quiet && o.engine.kind == view::EngineKind::Embree, "rendering");
  view::Frame request{&list, molecule.centers, molecule.radii, colors, &model, setup.render};
  request.options.progress = [&bar](double f) { bar.update(f); };
  const view::FrameBuffers frame = engine->render(request);
  ImageRecord record = recordOfRender(o, list, fromPatchList);
  describeEngine(*engine, record);
  ballAndStick.describe(record);
  describeColors(setup, record);
  writeImage(o.output, o.exr, frame, record, setup.render.camera);
  writeLegendFile(setup);
  printRenderSummary(o, list, frame, readSeconds, buildSeconds, engine->sceneSeconds());
}

}  // namespace

void addRenderCommand(CLI::App& app, const std::string& commandLine) {
  auto o = std::make_shared<RenderCommandOptions>();
  o->commandLine = commandLine;
  auto* cmd = app.add_subcommand(
      "render",
      "Ray-trace a molecular surface exactly (Embree, double-precision patches) to a PNG and/or an EXR with "
      "depth, normal, patch kind, patch id, atom id and ambiguity flags for pixel-by-pixel validation");
  cmd->add_option("FILE", o->path,
                  "Structure file (PDB, mmCIF, PQR, XYZR, XYZ; .gz allowed) or a patch list from `surftrace build` "
                  "(.stp, told by its content)")
      ->required();
  addSurfaceOptions(*cmd, o->surface);
  cmd->add_option("--patches", o->patches,
                  "Render this patch list (from `surftrace build` with the same --surface, --probe or --shrink) "
                  "instead of building it")
      ->check(CLI::ExistingFile);
  addImageOptions(*cmd, o->image);
  cmd->add_option("--trajectory", o->trajectory,
                  "Render one frame of this trajectory (DCD, XTC, GRO, XYZ, multi-model PDB/mmCIF); FILE is then "
                  "its topology (PDB, mmCIF, GRO or PSF)")
      ->check(CLI::ExistingFile);
  o->frameOption = cmd->add_option("--frame", o->frame, "The frame of --trajectory to render, numbered from 0")
                       ->check(wholeIn(0, 2147483647))
                       ->default_val(0);
  cmd->add_option("-o,--output", o->output,
                  "PNG (or any OpenImageIO format) colour image to write; - for a PNG on the standard output (the "
                  "summary then goes to the standard error). 8-bit formats hold the sRGB encoding of the linear "
                  "colour (alpha linear); .exr holds the linear colour");
  cmd->add_option("--exr", o->exr,
                  "Multi-channel EXR to write (colour, depth, normal, ids, flags; with Embree also each hit's "
                  "distance to the edge of its patch and the pixels an edge of the surface crosses, for `compare`); "
                  "- for the standard output");
  cmd->add_flag("--cavities", o->cavities,
                "Draw the SES's buried cavities alone (the inverse of --drop-cavities), framed as the whole surface "
                "is; the convex patch of an atom that also faces the outside is left out (it would be drawn as its "
                "whole sphere), so such a wall shows as a hole. With --opacity below 1 the cavities are transparent too");
  addEngineOptions(*cmd, o->engine);
  cmd->add_option("--threads", o->threads, "Worker threads (default: all cores); images do not depend on it")
      ->check(wholeIn(0, 4096));
  cmd->add_flag("--quiet", o->quiet, "No progress bar");
  addMoleculeOptions(*cmd, o->read);
  cmd->callback([o] { runRender(*o); });
}

}  // namespace surftrace::tools

// `surftrace render`: exact ray tracing of a molecular surface to PNG and EXR.
#include <unistd.h>

#include <chrono>
#include <cmath>
#include <cstdio>
#include <memory>
#include <mutex>
#include <optional>
#include <sstream>
#include <stdexcept>

#include <tbb/global_control.h>

#include "build/surface.hpp"
#include "build/io/molecule.hpp"
#include "build/io/trajectory.hpp"
#include "build/io/output_file.hpp"
#include "commands.hpp"
#include "option_checks.hpp"
#include "gl/gl_context.hpp"
#include "gl/gl_renderer.hpp"
#include "trace/patch_scene.hpp"
#include "trace/render.hpp"
#include "view/atom_colors.hpp"
#include "view/image_io.hpp"
#include "image_options.hpp"

namespace surftrace::tools {
namespace {

struct RenderCommandOptions {
  std::string path;
  build::ReadOptions read;
  std::string surface = "ses";
  double probe = 1.4;
  double shrink = 0.5;
  CLI::Option* probeOption = nullptr;  // to tell a --probe given from its default
  std::string patches;
  std::string trajectory;   // FILE is then its topology
  int frame = 0;
  CLI::Option* frameOption = nullptr;
  ImageOptions image;
  std::string engine = "embree";
  std::string glTorus = "quartic";
  std::string glPrimitive = "box";
  int glSteps = 30;
  std::string output, exr;
  int threads = 0;
  bool dropCavities = false;
  bool quiet = false;
  std::string commandLine;
};

double secondsSince(std::chrono::steady_clock::time_point start) {
  return std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
}

void runRender(const RenderCommandOptions& o) {
  if (o.output.empty() && o.exr.empty()) throw std::invalid_argument("nothing to write: give -o OUT.png and/or --exr OUT.exr");
  if (o.engine == "gl" && (o.image.spp > 1 || o.image.shadows || o.image.ao > 0))
    throw std::invalid_argument("--engine gl draws one sample per pixel without shadows or ambient occlusion: drop "
                                "--spp/--shadows/--ao or use --engine embree");
  std::unique_ptr<tbb::global_control> limit;
  if (o.threads > 0)
    limit = std::make_unique<tbb::global_control>(tbb::global_control::max_allowed_parallelism,
                                                  static_cast<std::size_t>(o.threads));
  // Every option is checked before the slow work starts, the output paths too.
  if (!o.output.empty()) build::prepareOutputPath(o.output, "-o");
  if (!o.exr.empty()) build::prepareOutputPath(o.exr, "--exr");
  ImageSetup setup = resolveImageOptions(o.image);
  view::RenderOptions& ro = setup.render;
  if (o.frameOption && o.frameOption->count() > 0 && o.trajectory.empty())
    throw std::invalid_argument("--frame " + std::to_string(o.frame) + " needs --trajectory FILE (and FILE its topology)");

  // A patch list given as FILE (told by its magic) is rendered as it is: its own surface,
  // probe and shrink factor, framed from its patches.
  const bool fromPatchList = isPatchListInput(o.path);
  if (fromPatchList) {
    if (!o.patches.empty())
      throw std::invalid_argument(o.path + " is a patch list already; --patches applies to a structure file");
    if (!o.trajectory.empty())
      throw std::invalid_argument(o.path + " is a patch list; --trajectory needs the trajectory's topology as FILE");
    if (ro.color != view::ColorMode::Patch && ro.color != view::ColorMode::Uniform)
      throw std::invalid_argument("--color " + o.image.color + " needs the atoms' records, which a patch list (" + o.path +
                                  ") does not hold: render the structure file, or use --color patch|uniform");
  }

  auto start = std::chrono::steady_clock::now();
  build::Molecule molecule;
  if (!o.trajectory.empty()) {
    build::Trajectory trajectory(o.path, o.trajectory, o.read);
    trajectory.load(static_cast<std::size_t>(o.frame));
    molecule = trajectory.molecule();
  } else if (!fromPatchList) {
    molecule = build::readMolecule(o.path, o.read);
    printReadNotes(molecule);
  }
  const double readSeconds = secondsSince(start);

  start = std::chrono::steady_clock::now();
  const build::SurfaceRequest request{build::parseSurfaceKind(o.surface), o.probe, o.shrink, o.dropCavities};
  build::PatchList list;
  if (fromPatchList) {
    list = build::readPatchList(o.path);
    if (o.surface != "ses" && build::parseSurfaceKind(o.surface) != list.params.surface)
      throw std::invalid_argument(o.path + " is a " + build::surfaceKindName(list.params.surface) + " patch list; --surface " +
                                  o.surface + " needs the structure file");
    if (o.probeOption && o.probeOption->count() > 0 && o.probe != list.params.probeRadius)
      throw std::invalid_argument(o.path + " was built with probe " + std::to_string(list.params.probeRadius) +
                                  " Å; --probe " + std::to_string(o.probe) + " cannot change it (rebuild it)");
    if (o.dropCavities) list = build::outerComponent(list);
  } else if (!o.patches.empty()) {
    list = build::readPatchList(o.patches);
    build::checkPatchListMatches(list, o.patches, molecule, request);
    if (o.dropCavities) list = build::outerComponent(list);
  } else {
    list = build::buildSurface(molecule, request);
  }
  const double buildSeconds = secondsSince(start);

  // Frame what the surface can reach; a patch list without its structure is framed from its
  // convex patches' atoms, which reach furthest (a buried atom's extended sphere lies inside the
  // others'), so the camera is the one the structure itself would get.
  if (fromPatchList && list.params.surface != build::SurfaceKind::Mss) {
    const double extend = list.params.surface == build::SurfaceKind::Ses ? list.params.probeRadius : 0.0;
    std::vector<double> reach(list.convex.radius);
    for (double& r : reach) r += extend;
    if (list.convex.size() == 0) throw std::invalid_argument(o.path + ": the patch list has no convex patches to frame");
    frameSpheres(setup, list.convex.center, reach);
  } else {
    frameSurface(setup, list, molecule);
  }
  writeCameraOut(setup);

  const auto colors = fromPatchList ? std::vector<glm::vec3>(list.params.atomCount, setup.uniformColor)
                                    : view::atomColors(molecule, ro.color, setup.uniformColor);
  view::FrameBuffers frame;
  ImageRecord record;
  record.engine = o.engine;
  record.surface = o.surface;
  record.probeRadius = fromPatchList ? list.params.probeRadius : o.probe;
  if (list.params.surface == build::SurfaceKind::Mss) record.shrinkFactor = list.params.shrinkFactor;
  record.input = o.path;
  if (!o.trajectory.empty()) {
    record.trajectory = o.trajectory;
    record.frame = static_cast<std::size_t>(o.frame);
  }
  record.color = o.image.color;
  record.commandLine = o.commandLine;
  view::ImageMetadata meta;
  double sceneSeconds = 0.0;
  if (o.engine == "gl") {
    gl::GlOptions glOptions;
    glOptions.torus = gl::parseTorusMethod(o.glTorus);
    glOptions.maxSteps = o.glSteps;
    glOptions.primitive = gl::parsePrimitive(o.glPrimitive);
    const gl::GlContext context;
    frame = gl::renderGl(context, list, ro, colors, glOptions);
    record.glContext = context.description();
    meta = imageMetadata(record, ro.camera);
    meta["surftrace:gl_torus_method"] = gl::torusMethodName(glOptions.torus);
    meta["surftrace:gl_primitive"] = gl::primitiveName(glOptions.primitive);
  } else {
    const trace::PatchScene scene(trace::ScenePatches::fromPatchList(list));
    sceneSeconds = scene.buildSeconds();
    ProgressBar bar(!o.quiet, "rendering");
    ro.progress = [&bar](double f) { bar.update(f); };
    frame = trace::render(scene, ro, colors);
    meta = imageMetadata(record, ro.camera);
  }
  if (!o.output.empty()) view::writePng(o.output, frame, meta);
  if (!o.exr.empty()) view::writeExr(o.exr, frame, meta);

  std::size_t covered = 0;
  for (auto k : frame.kind) covered += k != 0;
  std::string counts;
  for (const view::PatchKindInfo& k : view::kPatchKinds) {
    const std::size_t n = view::patchCount(list, k.kind);
    if (n > 0) counts += (counts.empty() ? "" : ", ") + std::to_string(n) + " " + k.name;
  }
  std::printf("%s: %zu atoms, %s, %zu patches (%s); engine %s\n", o.path.c_str(),
              static_cast<std::size_t>(list.params.atomCount), build::surfaceKindName(list.params.surface),
              list.patchCount(), counts.c_str(), o.engine.c_str());
  if (!o.trajectory.empty()) std::printf("frame %d of %s\n", o.frame, o.trajectory.c_str());
  std::printf("read %.1f ms, surface %.1f ms, scene %.1f ms, frame %.1f ms (%dx%d, %d spp, %.2f Mrays/s), %.1f%% covered\n",
              readSeconds * 1e3, buildSeconds * 1e3, sceneSeconds * 1e3, frame.seconds * 1e3, frame.width,
              frame.height, o.image.spp, static_cast<double>(frame.rays) / frame.seconds * 1e-6,
              100.0 * static_cast<double>(covered) / static_cast<double>(frame.pixels()));
  if (!o.output.empty()) std::printf("wrote %s\n", o.output.c_str());
  if (!o.exr.empty()) std::printf("wrote %s\n", o.exr.c_str());
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
  cmd->add_option("--surface", o->surface,
                  "ses (solvent excluded: exact spheres, tori, concave triangles), mss (molecular skin: spheres and "
                  "hyperboloids in their mixed cells), vdw (atom spheres) or sas (spheres of r + probe)")
      ->check(CLI::IsMember({"ses", "mss", "vdw", "sas"}))
      ->default_val("ses");
  addShrinkOption(*cmd, o->shrink);
  o->probeOption =
      cmd->add_option("--probe", o->probe, "Probe radius rp in Å (> 0)")->check(positive())->default_val(1.4);
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
  cmd->add_option("-o,--output", o->output, "PNG (or any OpenImageIO format) colour image to write");
  cmd->add_option("--exr", o->exr, "Multi-channel EXR to write (colour, depth, normal, ids, flags)");
  cmd->add_option("--engine", o->engine,
                  "embree: exact double-precision CPU ray tracing (the reference); gl: the headless OpenGL "
                  "geometry-shader ray caster (llvmpipe without a GPU), one sample per pixel, no shadows or AO")
      ->check(CLI::IsMember({"embree", "gl"}))
      ->default_val("embree");
  cmd->add_option("--gl-torus", o->glTorus, "GL saddle intersection: quartic (analytic) or sphere-tracing")
      ->check(CLI::IsMember({"quartic", "sphere-tracing"}))
      ->default_val("quartic");
  cmd->add_option("--gl-primitive", o->glPrimitive,
                  "GL rasterisation primitive of tori and concave triangles: box (eye-facing faces of a tight "
                  "bounding box, fewer fragments) or cylinder (Lindow et al. 2010, Fig. 6: the trapezoid of the "
                  "patch's bounding cylinder)")
      ->check(CLI::IsMember({"box", "cylinder"}))
      ->default_val("box");
  cmd->add_option("--gl-steps", o->glSteps, "GL sphere-tracing steps per ray (Lindow et al. 2010 use 30)")
      ->check(wholeIn(1, 10000))
      ->default_val(30);
  cmd->add_option("--threads", o->threads, "Worker threads (default: all cores); images do not depend on it")
      ->check(wholeIn(0, 4096));
  cmd->add_flag("--drop-cavities", o->dropCavities, "Leave out the inner SES components of buried cavities (invisible from outside)");
  cmd->add_flag("--quiet", o->quiet, "No progress bar");
  addMoleculeOptions(*cmd, o->read);
  cmd->callback([o] { runRender(*o); });
}

}  // namespace surftrace::tools

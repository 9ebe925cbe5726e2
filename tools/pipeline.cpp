// The stages `render` and `trajectory` share (pipeline.hpp).
#include "pipeline.hpp"

#include <cstdio>
#include <cmath>
#include <cstdlib>
#include <stdexcept>

#include "build/io/trajectory.hpp"
#include "build/mss/mss_builder.hpp"
#include "build/sphere_blockers.hpp"
#include "commands.hpp"
#include "gl/gl_context.hpp"
#include "gl/gl_renderer.hpp"
#include "option_checks.hpp"
#include "trace/patch_scene.hpp"
#include "trace/render.hpp"
#include "view/image_effects.hpp"
#include "view/image_io.hpp"

namespace surftrace::tools {

std::unique_ptr<tbb::global_control> limitThreads(int threads) {
  if (threads <= 0) return nullptr;
  return std::make_unique<tbb::global_control>(tbb::global_control::max_allowed_parallelism,
                                               static_cast<std::size_t>(threads));
}

build::SurfaceRequest SurfaceOptions::request() const {
  return build::SurfaceRequest{build::parseSurfaceKind(surface), probe, shrink, dropCavities, mergeWithin};
}

void addShrinkOption(CLI::App& cmd, double& shrink) {
  char range[64];
  std::snprintf(range, sizeof range, "[%g, 1]", build::kMinShrinkFactor);
  cmd.add_option("--shrink", shrink,
                 std::string("MSS shrink factor s in ") + range +
                     ": small s is smooth and wraps the molecule loosely, s -> 1 approaches the atoms; s = 1 is "
                     "exactly the union of the van der Waals balls (the vdW surface, built as whole spheres)")
      ->check(CLI::Validator(
          [range = std::string(range)](const std::string& v) {
            const std::string problem = detail::checkNumber(v, build::kMinShrinkFactor, 1.0, false, false);
            if (problem.empty()) return problem;
            return problem + (std::strtod(v.c_str(), nullptr) > 0.0 && std::strtod(v.c_str(), nullptr) < build::kMinShrinkFactor
                                  ? " (below it double precision no longer carries the skin's areas and volume, "
                                    "and the skin is within 0.1% of its s -> 0 limit)"
                                  : "");
          },
          range, ""))
      ->default_val(0.5);
}

void addSurfaceOptions(CLI::App& cmd, SurfaceOptions& o, SurfaceChoice choice) {
  if (choice == SurfaceChoice::Any) {
    cmd.add_option("--surface", o.surface,
                   "ses (solvent excluded: exact spheres, tori, concave triangles), mss (molecular skin: spheres and "
                   "hyperboloids in their mixed cells, --shrink), vdw (atom spheres) or sas (spheres of r + probe)")
        ->check(CLI::IsMember({"ses", "mss", "vdw", "sas"}))
        ->default_val("ses");
  } else {
    cmd.add_option("--surface", o.surface,
                   "Surface to build: ses (solvent excluded: spheres, tori, concave triangles) or mss (molecular "
                   "skin: spheres and hyperboloids clipped to mixed cells)")
        ->check(CLI::IsMember({"ses", "mss"}))
        ->default_val("ses");
  }
  addShrinkOption(cmd, o.shrink);
  o.probeOption = cmd.add_option("--probe", o.probe, "Probe radius rp in Å (> 0); 1.4 Å models water")
                      ->check(positive())
                      ->default_val(1.4);
  cmd.add_flag("--drop-cavities", o.dropCavities,
               "Keep only the outer SES components (positive volume): leave out the inner surfaces of buried "
               "cavities a probe fits in, which cannot be seen from outside");
  cmd.add_option("--merge-within", o.mergeWithin,
                 "Merge every atom whose ball lies within this distance in Å (|centre shift| + |radius change|) of a "
                 "kept atom's into it, noted: the surface of the input with those atoms moved by at most that much. "
                 "Near-coincident clusters (more than " + std::to_string(build::kMaxClusterAtoms) + " atoms within " +
                 detail::shortNumber(build::kClusterRadius) + " Å) are refused until merged")
      ->check(numberIn(build::kMinMergeDistance, HUGE_VAL))
      ->default_val(build::kMinMergeDistance);
}

build::PatchList buildWithNotes(const build::Molecule& molecule, const build::SurfaceRequest& request) {
  std::vector<std::string> notes;
  build::PatchList list = build::buildSurface(molecule, request, &notes);
  for (const std::string& note : notes)
    std::fprintf(stderr, "surftrace: note: %s: %s\n", molecule.source.c_str(), note.c_str());
  return list;
}

build::Molecule readInput(const std::string& path, const std::string& trajectory, std::size_t frame,
                          const build::ReadOptions& read) {
  if (trajectory.empty()) {
    build::Molecule molecule = build::readMolecule(path, read);
    printReadNotes(molecule);
    return molecule;
  }
  build::Trajectory frames(path, trajectory, read);
  frames.load(frame);
  return frames.molecule();
}

void addEngineOptions(CLI::App& cmd, EngineOptions& o) {
  cmd.add_option("--engine", o.engine,
                 "embree: exact double-precision CPU ray tracing (the reference); gl: the headless OpenGL "
                 "geometry-shader ray caster (llvmpipe without a GPU), one sample per pixel, no shadows or AO")
      ->check(CLI::IsMember({"embree", "gl"}))
      ->default_val("embree");
  cmd.add_option("--gl-torus", o.glTorus, "GL saddle intersection: quartic (analytic) or sphere-tracing")
      ->check(CLI::IsMember({"quartic", "sphere-tracing"}))
      ->default_val("quartic");
  cmd.add_option("--gl-primitive", o.glPrimitive,
                 "GL rasterisation primitive of tori and concave triangles: box (eye-facing faces of a tight "
                 "bounding box, fewer fragments) or cylinder (Lindow et al. 2010, Fig. 6: the trapezoid of the "
                 "patch's bounding cylinder)")
      ->check(CLI::IsMember({"box", "cylinder"}))
      ->default_val("box");
  cmd.add_option("--gl-steps", o.glSteps, "GL sphere-tracing steps per ray (Lindow et al. 2010 use 30)")
      ->check(wholeIn(1, 10000))
      ->default_val(30);
}

void checkEngineCanDraw(const EngineOptions& engine, const ImageOptions& image) {
  if (engine.engine == "gl" && (image.spp > 1 || image.shadows || image.ao > 0))
    throw std::invalid_argument("--engine gl draws one sample per pixel without shadows or ambient occlusion: drop "
                                "--spp/--shadows/--ao or use --engine embree");
}

struct FrameRenderer::Impl {
  EngineOptions options;
  gl::GlOptions gl;
  std::optional<trace::EmbreeDevice> device;  // embree
  std::optional<gl::GlContext> context;       // gl, opened by the first frame
  double sceneSeconds = 0.0;
};

FrameRenderer::FrameRenderer(EngineOptions options) : impl_(std::make_unique<Impl>()) {
  impl_->options = std::move(options);
  if (impl_->options.engine == "gl") {
    impl_->gl.torus = gl::parseTorusMethod(impl_->options.glTorus);
    impl_->gl.maxSteps = impl_->options.glSteps;
    impl_->gl.primitive = gl::parsePrimitive(impl_->options.glPrimitive);
  } else {
    impl_->device.emplace();
  }
}

FrameRenderer::~FrameRenderer() = default;

view::FrameBuffers FrameRenderer::render(const build::PatchList& list, const view::RenderOptions& options,
                                         std::span<const glm::vec3> atomColors, ProgressBar* bar,
                                         std::span<const glm::dvec3> centers, std::span<const double> radii) {
  Impl& m = *impl_;
  view::FrameBuffers frame;
  if (!m.device) {
    if (!m.context) m.context.emplace();
    // Transparency: every atom hides parts of the whole spheres (build/sphere_blockers.hpp).
    std::optional<build::SphereBlockers> blockers;
    if (options.opacity < 1.0 && centers.size() == list.params.atomCount) {
      std::vector<glm::dvec4> atoms;
      atoms.reserve(centers.size());
      for (std::size_t i = 0; i < centers.size(); ++i) atoms.push_back(glm::dvec4(centers[i], radii[i]));
      blockers = build::sphereBlockers(list, atoms);
    }
    frame = gl::renderGl(*m.context, list, options, atomColors, m.gl, blockers ? &*blockers : nullptr);
  } else {
    const bool transparent = options.opacity < 1.0 && centers.size() == list.params.atomCount;
    const trace::PatchScene scene(transparent ? trace::ScenePatches::fromPatchList(list, centers, radii)
                                              : trace::ScenePatches::fromPatchList(list),
                                  *m.device);
    m.sceneSeconds = scene.buildSeconds();
    view::RenderOptions withProgress = options;
    if (bar) withProgress.progress = [bar](double f) { bar->update(f); };
    frame = trace::render(scene, withProgress, atomColors);
  }
  // The one place the image-space effects run: on the buffers, whichever engine filled them.
  view::applyImageEffects(frame, options.effects, options.camera, options.background);
  return frame;
}

void FrameRenderer::describe(ImageRecord& record) const {
  const Impl& m = *impl_;
  record.engine = m.options.engine;
  if (m.device) return;
  if (m.context) record.glContext = m.context->description();
  record.engineSettings = {{"surftrace:gl_torus_method", gl::torusMethodName(m.gl.torus)},
                           {"surftrace:gl_primitive", gl::primitiveName(m.gl.primitive)}};
}

double FrameRenderer::sceneSeconds() const { return impl_->sceneSeconds; }

ImageRecord recordOf(const SurfaceOptions& surface, const std::string& input, const ImageOptions& image,
                     const std::string& commandLine) {
  ImageRecord record;
  record.surface = surface.surface;
  record.probeRadius = surface.probe;
  if (build::parseSurfaceKind(surface.surface) == build::SurfaceKind::Mss) record.shrinkFactor = surface.shrink;
  record.input = input;
  record.color = image.color;
  record.commandLine = commandLine;
  record.opacity = image.opacity;
  record.maxLayers = image.maxLayers;
  record.effects = resolveEffects(image);
  return record;
}

void writeImage(const std::string& png, const std::string& exr, const view::FrameBuffers& image,
                const ImageRecord& record, const view::Camera& camera) {
  const view::ImageMetadata meta = imageMetadata(record, camera);
  if (!png.empty()) view::writePng(png, image, meta);
  if (!exr.empty()) view::writeExr(exr, image, meta);
}

}  // namespace surftrace::tools

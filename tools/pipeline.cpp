// The stages `render` and `trajectory` share (pipeline.hpp).
#include "pipeline.hpp"

#include <cstdio>
#include <cmath>
#include <cstdlib>
#include <span>
#include <stdexcept>

#include "build/io/output_file.hpp"
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

BallAndStick BallAndStick::of(const ImageOptions& image, const build::Molecule& topology) {
  BallAndStick b;
  if (!image.ballAndStick) return b;
  b.on = true;
  b.ballScale = image.ballScale;
  b.stickRadius = image.stickRadius;
  b.bonds = build::moleculeBonds(topology);
  return b;
}

build::BallStickModel BallAndStick::model(std::span<const glm::dvec3> centers, std::span<const double> radii) const {
  return build::ballStickModel(centers, radii, bonds, ballScale, stickRadius);
}

void BallAndStick::describe(ImageRecord& record) const {
  record.ballAndStick = on;
  record.ballScale = ballScale;
  record.stickRadius = stickRadius;
  record.bonds = bonds.size();
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

view::FrameBuffers FrameRenderer::render(const build::PatchList& surface, const view::RenderOptions& opacityOptions,
                                         std::span<const glm::vec3> atomColors, ProgressBar* bar,
                                         std::span<const glm::dvec3> centers, std::span<const double> radii,
                                         const build::BallStickModel* model) {
  Impl& m = *impl_;
  // Opacity 0: no surface at all, the model drawn opaque (the same in both engines).
  const bool noSurface = opacityOptions.opacity == 0.0;
  build::PatchList empty;
  empty.params = surface.params;
  const build::PatchList& list = noSurface ? empty : surface;
  view::RenderOptions options = opacityOptions;
  if (noSurface) options.opacity = 1.0;
  if (model && model->empty()) model = nullptr;
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
    frame = gl::renderGl(*m.context, list, options, atomColors, m.gl, blockers ? &*blockers : nullptr, model);
  } else {
    const bool transparent = options.opacity < 1.0 && centers.size() == list.params.atomCount;
    const trace::PatchScene scene(transparent ? trace::ScenePatches::fromPatchList(list, centers, radii, model)
                                              : trace::ScenePatches::fromPatchList(list, {}, {}, model),
                                  *m.device);
    m.sceneSeconds = scene.buildSeconds();
    if (bar) options.progress = [bar](double f) { bar->update(f); };
    frame = trace::render(scene, options, atomColors);
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
  record.uniformColor = parseVector("--uniform-color", image.uniformColor);
  record.background = parseVector("--background", image.background);
  record.shadows = image.shadows;
  record.aoSamples = image.ao;
  record.aoDistance = image.aoDistance;
  // The samples a pixel's colour averages: --spp rounded up to a k×k grid (2 and 4 alike).
  const int side = static_cast<int>(std::ceil(std::sqrt(static_cast<double>(image.spp))));
  record.samplesPerPixel = side * side;
  record.commandLine = commandLine;
  record.opacity = image.opacity;
  record.maxLayers = image.maxLayers;
  record.effects = resolveEffects(image);
  return record;
}

}  // namespace surftrace::tools

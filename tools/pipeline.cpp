// What `render` and `trajectory` share beyond the library's stages (pipeline.hpp).
#include "pipeline.hpp"

#include <cstdio>
#include <cmath>
#include <cstdlib>
#include <span>
#include <stdexcept>
#include <utility>

#include "commands.hpp"
#include "option_checks.hpp"
#include "surftrace/files.hpp"
#include "surftrace/image.hpp"

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

void addEngineOptions(CLI::App& cmd, view::EngineOptions& o) {
  cmd.add_option_function<std::string>(
         "--engine", [&o](const std::string& name) { o.kind = view::parseEngineKind(name); },
         "embree: exact double-precision CPU ray tracing (the reference); gl: the headless OpenGL "
         "geometry-shader ray caster (llvmpipe without a GPU), one sample per pixel; --lighting soft and full "
         "from light maps, no --shadows or --ao")
      ->check(CLI::IsMember({"embree", "gl"}))
      ->default_str("embree");
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

void describeEngine(const view::Engine& engine, ImageRecord& record) {
  view::EngineDescription d = engine.describe();
  record.engine = std::move(d.name);
  record.renderer = std::move(d.renderer);
  record.engineSettings = std::move(d.settings);
}

ImageRecord recordOf(const SurfaceOptions& surface, const std::string& input, const ImageOptions& image,
                     const std::string& commandLine) {
  ImageRecord record;
  record.surface = surface.surface;
  record.probeRadius = surface.probe;
  if (build::parseSurfaceKind(surface.surface) == build::SurfaceKind::Mss) record.shrinkFactor = surface.shrink;
  record.input = input;
  record.color = image.color;
  record.uniformColor = parseColor("--uniform-color", image.uniformColor);
  record.background = glm::dvec3(parseBackground(image.background));
  record.lighting = view::lightingFor(view::parseLightingPreset(image.lighting));
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

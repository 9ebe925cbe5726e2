// What `render` and `trajectory` share beyond the library's stages (surftrace/surftrace.hpp:
// read -> build or update -> frame the camera -> an Engine draws -> encode and write): the
// options that choose the engine and the ball-and-stick model, and the image's record made
// from the command's options. `render` runs each stage once; `trajectory` frames once and runs
// the others per frame inside its TBB pipeline; an option added here reaches both commands.
#pragma once

#include <chrono>
#include <cstddef>
#include <memory>
#include <optional>
#include <span>
#include <string>
#include <vector>

#include <CLI/CLI.hpp>
#include <glm/vec3.hpp>

#include "image_options.hpp"
#include "surface_options.hpp"
#include "surftrace/engine.hpp"
#include "surftrace/image.hpp"
#include "surftrace/molecule.hpp"
#include "surftrace/surface.hpp"

namespace surftrace::tools {

// --ball-and-stick for one topology: its bonds, computed once (build/bonds.hpp), and the
// model of any frame of it (the bonds' indices reused for every frame's centres).
struct BallAndStick {
  bool on = false;
  double ballScale = 0.25, stickRadius = 0.15;
  std::vector<glm::uvec2> bonds;

  // Off unless image.ballAndStick; the bonds of `topology` otherwise.
  static BallAndStick of(const ImageOptions& image, const build::Molecule& topology);
  build::BallStickModel model(std::span<const glm::dvec3> centers, std::span<const double> radii) const;
  // Into the image's record (surftrace:ball_and_stick).
  void describe(ImageRecord& record) const;
};

// --engine and the GL engine's own options, into the library's EngineOptions.
void addEngineOptions(CLI::App& cmd, view::EngineOptions& options);
// The engine's name, context and settings into the image's record.
void describeEngine(const view::Engine& engine, ImageRecord& record);

// What an image of `input` records about the surface and the options that made it; frame,
// time and engine are filled by the stages that know them.
ImageRecord recordOf(const SurfaceOptions& surface, const std::string& input, const ImageOptions& image,
                     const std::string& commandLine);

}  // namespace surftrace::tools

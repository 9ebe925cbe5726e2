// The stages `render` and `trajectory` share, in the order an image is made:
//
//   read (a structure, a trajectory frame)  ->  atoms with radii  ->  build or update the surface
//   ->  frame the camera (image_options.hpp)  ->  render (FrameRenderer)  ->  write (writeImage)
//
// `render` runs each stage once; `trajectory` frames once and runs the others per frame inside
// its TBB pipeline. Each stage is here once, so that an option added to one (an engine, a
// visual effect, a metadata field) reaches both commands.
#pragma once

#include <chrono>
#include <cstddef>
#include <memory>
#include <optional>
#include <span>
#include <string>
#include <vector>

#include <CLI/CLI.hpp>
#include <tbb/global_control.h>
#include <glm/vec3.hpp>

#include "build/bonds.hpp"
#include "build/io/molecule.hpp"
#include "build/patch_list.hpp"
#include "build/surface.hpp"
#include "image_options.hpp"
#include "view/frame_buffers.hpp"
#include "view/render_options.hpp"

namespace surftrace::tools {

// Seconds of wall time since `start`, for the timings commands print.
inline double secondsSince(std::chrono::steady_clock::time_point start) {
  return std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
}

// --threads N: TBB runs at most N worker threads while the returned object lives (N = 0: no
// limit, all cores).
std::unique_ptr<tbb::global_control> limitThreads(int threads);

// --surface, --probe, --shrink, --drop-cavities: what surface to build.
struct SurfaceOptions {
  std::string surface = "ses";
  double probe = 1.4;
  double shrink = 0.5;
  bool dropCavities = false;
  double mergeWithin = build::kMinMergeDistance;
  CLI::Option* probeOption = nullptr;  // to tell a --probe given from its default

  build::SurfaceRequest request() const;
  bool probeGiven() const { return probeOption && probeOption->count() > 0; }
};
// Which surfaces --surface offers: all four (render, trajectory), or those with patches of
// their own to build (build, area: ses, mss).
enum class SurfaceChoice { Any, Built };
void addSurfaceOptions(CLI::App& cmd, SurfaceOptions& options, SurfaceChoice choice = SurfaceChoice::Any);
// --shrink: the MSS shrink factor in [kMinShrinkFactor, 1], default 0.5, with a readable error.
void addShrinkOption(CLI::App& cmd, double& shrink);

// Stage "build" for one structure: buildSurface, with what it left out (atoms inside others,
// merged ones) printed as notes on stderr.
build::PatchList buildWithNotes(const build::Molecule& molecule, const build::SurfaceRequest& request);

// Stage "read": the molecule of a structure file, or of one frame of a trajectory whose
// topology is `path` (when `trajectory` is not empty). Prints the reader's notes.
build::Molecule readInput(const std::string& path, const std::string& trajectory, std::size_t frame,
                          const build::ReadOptions& read);

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

// --engine and the GL engine's own options.
struct EngineOptions {
  std::string engine = "embree";
  std::string glTorus = "quartic";
  std::string glPrimitive = "box";
  int glSteps = 30;
};
void addEngineOptions(CLI::App& cmd, EngineOptions& options);
// std::invalid_argument when the engine cannot draw what the image options ask for.
void checkEngineCanDraw(const EngineOptions& engine, const ImageOptions& image);

// Stage "render": draws patch lists with one engine. Embree keeps one device for every frame;
// GL opens its headless context on first use, in the thread that draws.
class FrameRenderer {
 public:
  explicit FrameRenderer(EngineOptions options);
  ~FrameRenderer();
  FrameRenderer(const FrameRenderer&) = delete;
  FrameRenderer& operator=(const FrameRenderer&) = delete;

  // `bar`, when given, shows the progress of one frame. The atoms (`centers`, `radii`: all or
  // none) let a transparent frame hide the parts of the SES spheres that buried atoms cover.
  // `model`, when given, is drawn opaque with the surface; options.opacity 0 leaves the surface out.
  view::FrameBuffers render(const build::PatchList& list, const view::RenderOptions& options,
                            std::span<const glm::vec3> atomColors, ProgressBar* bar = nullptr,
                            std::span<const glm::dvec3> centers = {}, std::span<const double> radii = {},
                            const build::BallStickModel* model = nullptr);
  // The engine, its context and its own settings, into the image's record.
  void describe(ImageRecord& record) const;
  // Seconds the last frame spent building its acceleration structure (Embree; 0 for GL).
  double sceneSeconds() const;

 private:
  struct Impl;
  std::unique_ptr<Impl> impl_;
};

// What an image of `input` records about the surface and the options that made it; frame,
// time and engine are filled by the stages that know them.
ImageRecord recordOf(const SurfaceOptions& surface, const std::string& input, const ImageOptions& image,
                     const std::string& commandLine);

// Stage "write": the image to `png` and/or `exr` (either may be empty), with its metadata,
// each file whole or not at all.
void writeImage(const std::string& png, const std::string& exr, const view::FrameBuffers& image,
                const ImageRecord& record, const view::Camera& camera);

}  // namespace surftrace::tools

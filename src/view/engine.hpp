// The one interface every engine draws through: a Frame (the patch list, the atoms, the
// ball-and-stick model and the render options) in, the frame's buffers out. Embree
// (trace/embree_engine.hpp) and GL (gl/gl_engine.hpp) implement it; surftrace::makeEngine
// (include/surftrace/engine.hpp) is the one place that chooses between them.
#pragma once

#include <span>
#include <string>
#include <utility>
#include <vector>

#include <glm/vec3.hpp>

#include "build/bonds.hpp"
#include "build/patch_list.hpp"
#include "view/frame_buffers.hpp"
#include "view/render_options.hpp"

namespace surftrace::view {

// What one frame shows. The frame refers to the caller's data (nothing is copied): it must
// outlive Engine::render.
struct Frame {
  const build::PatchList* surface = nullptr;  // required (an empty list draws no surface)
  // Every atom (centre and radius), or none: a transparent surface needs them, because buried
  // atoms hide parts of the SES spheres too (build/sphere_blockers.hpp). Without them, or with
  // fewer than the list's atomCount, a transparent frame clips the spheres by one another alone.
  std::span<const glm::dvec3> centers;
  std::span<const double> radii;
  std::span<const glm::vec3> atomColors;  // per atom, linear, for the colour schemes that colour by atom
  const build::BallStickModel* model = nullptr;  // drawn opaque with the surface when given
  RenderOptions options;  // options.progress, when set, hears how far the frame is (Embree)
};

// What an image records about the engine that drew it.
struct EngineDescription {
  std::string name;     // "embree" or "gl"
  std::string context;  // the GL context's renderer and version; empty for Embree
  // The engine as an image's metadata names it after the program (surftrace:renderer), e.g.
  // "embree 3.13.5 (double-precision patches)" or "gl: " and the context.
  std::string renderer;
  std::vector<std::pair<std::string, std::string>> settings;  // the engine's own, as metadata key/values
};

// Draws frames. render() holds the rules every engine follows; an engine implements draw().
class Engine {
 public:
  virtual ~Engine() = default;
  Engine() = default;
  Engine(const Engine&) = delete;
  Engine& operator=(const Engine&) = delete;

  // The frame's buffers. The rules here are every engine's:
  // - options.opacity 0 draws no surface at all: the model alone, opaque (an empty patch list
  //   at opacity 1 is what the engine sees);
  // - an empty model is no model;
  // - the image-space effects (options.effects) run after the engine, here and nowhere else,
  //   so that every engine's buffers get the same pass; then the legend (options.legend) and
  //   the background's alpha (options.backgroundAlpha).
  // Throws std::invalid_argument for a frame without a surface or with centres and radii of
  // different counts, and what the engine throws (e.g. GL: options it cannot draw).
  FrameBuffers render(const Frame& frame);

  // The engine's name, its context and its own settings, for the image's metadata. GL's
  // context is known after the first frame.
  virtual EngineDescription describe() const = 0;
  // Seconds the last frame spent building its acceleration structure (Embree; 0 for GL).
  virtual double sceneSeconds() const { return 0.0; }
  // "embree" or "gl".
  virtual const char* name() const = 0;

 protected:
  // One frame, after render()'s rules: a surface is given, its opacity is above 0, and a
  // model, when given, is not empty.
  virtual FrameBuffers draw(const Frame& frame) = 0;
};

enum class EngineKind { Embree, Gl };
EngineKind parseEngineKind(const std::string& name);  // "embree" | "gl"; throws std::invalid_argument
const char* engineKindName(EngineKind kind);

// Which engine, and the GL engine's own settings (the Embree engine has none).
struct EngineOptions {
  EngineKind kind = EngineKind::Embree;
  std::string glTorus = "quartic";  // quartic | sphere-tracing (gl::parseTorusMethod)
  std::string glPrimitive = "box";  // box | cylinder (gl::parsePrimitive)
  int glSteps = 30;                 // sphere-tracing steps per ray
};

// std::invalid_argument when the engine cannot draw what the options ask for (GL: one sample
// per pixel, no --shadows or --ao; the soft and full lighting presets from light maps), before
// any slow work.
void checkEngineCanDraw(const EngineOptions& engine, const RenderOptions& options);

}  // namespace surftrace::view

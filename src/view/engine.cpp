// The rules every engine follows (engine.hpp).
#include "view/engine.hpp"

#include <cstdio>
#include <stdexcept>

#include "view/image_effects.hpp"

namespace surftrace::view {

FrameBuffers Engine::render(const Frame& asked) {
  if (!asked.surface) throw std::invalid_argument("Engine::render: the frame has no patch list (Frame::surface is null)");
  if (asked.centers.size() != asked.radii.size())
    throw std::invalid_argument("Engine::render: " + std::to_string(asked.centers.size()) + " atom centres but " +
                                std::to_string(asked.radii.size()) + " radii: give both for every atom, or neither");
  Frame frame = asked;
  // Opacity 0 is no surface at all: the model alone, drawn opaque. The engine sees an empty
  // list (of the same surface) at opacity 1, so that no engine needs a case of its own.
  build::PatchList empty;
  if (frame.options.opacity == 0.0) {
    empty.params = asked.surface->params;
    frame.surface = &empty;
    frame.options.opacity = 1.0;
  }
  if (frame.model && frame.model->empty()) frame.model = nullptr;
  FrameBuffers buffers = draw(frame);
  // The one place the image-space effects run: on the buffers, whichever engine filled them.
  applyImageEffects(buffers, frame.options.effects, frame.options.camera, frame.options.background);
  // Then what lies over the picture, and the background's transparency under it all: one pass
  // here for every engine, so that GL and Embree agree by construction.
  const glm::vec3& background = frame.options.background;
  if (frame.options.legend) drawLegend(buffers, *frame.options.legend, background);
  if (frame.options.backgroundAlpha < 1.0f) {
    const float rgb[3] = {background.r, background.g, background.b};
    applyBackgroundAlpha(buffers, rgb, frame.options.backgroundAlpha);
  }
  return buffers;
}

EngineKind parseEngineKind(const std::string& name) {
  if (name == "embree") return EngineKind::Embree;
  if (name == "gl") return EngineKind::Gl;
  throw std::invalid_argument("unknown engine '" + name + "': use embree or gl");
}

const char* engineKindName(EngineKind kind) { return kind == EngineKind::Gl ? "gl" : "embree"; }

void checkEngineCanDraw(const EngineOptions& engine, const RenderOptions& options) {
  if (engine.kind == EngineKind::Gl && (options.samplesPerPixel > 1 || options.shadows || options.aoSamples > 0))
    throw std::invalid_argument("--engine gl draws one sample per pixel without shadows or ambient occlusion: drop "
                                "--spp/--shadows/--ao (--lighting soft and full give GL soft shadows and occlusion "
                                "from light maps) or use --engine embree");
  // A light map holds only the surface nearest its light, so GL's occlusion counts occluders at
  // any distance: a reach other than the default would be silently ignored.
  if (engine.kind == EngineKind::Gl && options.lighting.keyFill() && options.lighting.occlusionRays > 0 &&
      options.aoDistance != RenderOptions{}.aoDistance) {
    char given[32];
    std::snprintf(given, sizeof given, "%g", options.aoDistance);
    throw std::invalid_argument(std::string("--ao-distance ") + given +
                                ": --engine gl's light maps count occluders at any distance, so the occlusion's "
                                "reach cannot be set there: drop --ao-distance or use --engine embree");
  }
}

}  // namespace surftrace::view

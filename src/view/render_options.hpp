// What a frame should show and how: the options every renderer takes (each rejects what it cannot do).
#pragma once

#include <cmath>
#include <functional>
#include <optional>

#include <glm/vec3.hpp>

#include "view/camera.hpp"
#include "view/color_legend.hpp"
#include "view/image_effects.hpp"
#include "view/shading.hpp"

namespace surftrace::view {

// The Embree path renders everything; the GL path renders the centre sample only and rejects
// samplesPerPixel > 1, shadows and aoSamples (the soft and full lighting presets it draws with
// light maps instead of rays).
struct RenderOptions {
  Camera camera;
  ColorMode color = ColorMode::Patch;
  Lighting lighting;
  glm::vec3 background{1.0f, 1.0f, 1.0f};  // linear (srgbToLinear of a colour given in sRGB)
  // Below 1, the background is transparent to this degree in the frame's alpha (PNG RGBA, EXR
  // A): applyBackgroundAlpha, run by Engine::render for every engine alike.
  float backgroundAlpha = 1.0f;
  int samplesPerPixel = 1;  // a k×k stratified grid per pixel (k = ceil(sqrt(spp)))
  bool shadows = false;     // a ray towards a key light above-left of the eye
  int aoSamples = 0;        // ambient-occlusion rays per hit (0 = off)
  double aoDistance = 8.0;  // Å
  // Transparency (Embree: every crossing exactly; GL: depth peeling): opacity 1 draws the nearest crossing alone; below 1 every
  // crossing of the ray with the surface, up to the nearest maxLayers, is alpha-composited
  // front to back over the background, each shaded as the opaque render shades it.
  double opacity = 1.0;
  int maxLayers = 16;
  // Record what the exact tracer knows of where another renderer may honestly disagree with
  // it, for `compare`'s masks: each centre hit's distance to the edge of its patch
  // (FrameBuffers::seamDistance) and the pixels that an edge of the surface crosses (the
  // kPixelSilhouette and kPixelOcclusion flags, from rays through the pixels' corners: one
  // more ray per pixel). Embree only; the GL path leaves them out.
  bool referenceMasks = false;
  // Image-space effects, applied after the engine by Engine::render (view/engine.hpp), not by
  // the engines: every engine's frame gets the same pass.
  ImageEffects effects;
  // The colour map's legend, drawn opaque into the bottom-right corner by Engine::render after
  // the effects (every engine's frame alike); none when empty.
  std::optional<ColorLegend> legend;
  // The side k of the k×k grid of colour samples a pixel gets: samplesPerPixel rounded up to a
  // square (2..4 -> 2, 5..9 -> 3), 1 for the pixel centre alone. The colour averages k² samples.
  int sampleGridSide() const;
  // Called now and then from worker threads with the fraction done (for a progress bar).
  std::function<void(double)> progress;
};

inline int RenderOptions::sampleGridSide() const {
  return static_cast<int>(std::ceil(std::sqrt(static_cast<double>(samplesPerPixel))));
}

}  // namespace surftrace::view

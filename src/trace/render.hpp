// Tile-parallel rendering of a patch scene into colour and per-pixel buffers.
#pragma once

#include <cstdint>
#include <functional>
#include <limits>
#include <span>
#include <vector>

#include <glm/vec3.hpp>

#include "trace/camera.hpp"
#include "trace/patch_scene.hpp"
#include "trace/shading.hpp"

namespace surftrace::trace {

struct RenderOptions {
  Camera camera;
  ColorMode color = ColorMode::Patch;
  Lighting lighting;
  glm::vec3 background{1.0f, 1.0f, 1.0f};
  int samplesPerPixel = 1;  // a k×k stratified grid per pixel (k = ceil(sqrt(spp)))
  bool shadows = false;     // a ray towards a key light above-left of the eye
  int aoSamples = 0;        // ambient-occlusion rays per hit (0 = off)
  double aoDistance = 8.0;  // Å
  // Called now and then from worker threads with the fraction done (for a progress bar).
  std::function<void(double)> progress;
};

// Per-pixel results. The buffers (all but rgba) come from the pixel-centre ray, so another
// renderer using the same camera can be compared with them pixel by pixel; rgba averages
// all samples. Misses: kind 0, ids ~0u, depths +inf, normal 0.
struct FrameBuffers {
  int width = 0, height = 0;
  std::vector<float> rgba;            // 4 per pixel, display values in [0, 1]; A = coverage
  std::vector<float> depth;           // ray distance t (Å, unit direction)
  std::vector<float> viewZ;           // distance along the view direction (Å)
  std::vector<float> normal;          // 3 per pixel, world space, outward
  std::vector<std::uint32_t> kind;    // PatchKind
  std::vector<std::uint32_t> patchId; // ScenePatches::globalId
  std::vector<std::uint32_t> atomId;
  std::vector<std::uint32_t> flags;   // HitFlag bits of the centre hit
  double seconds = 0.0;               // wall time of the frame
  std::size_t rays = 0;               // camera rays traced (shadow and AO rays not counted)

  std::size_t pixels() const { return static_cast<std::size_t>(width) * static_cast<std::size_t>(height); }
  // Sizes every buffer for width × height and fills it with the miss state.
  void reset(int newWidth, int newHeight);
};

// `atomColors` (one per atom) is used by every scheme but Patch. Identical output for any
// number of threads: every pixel depends on its own rays only.
FrameBuffers render(const PatchScene& scene, const RenderOptions& options, std::span<const glm::vec3> atomColors);

}  // namespace surftrace::trace

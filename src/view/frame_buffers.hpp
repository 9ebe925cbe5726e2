// One rendered frame: colour and the per-pixel buffers (AOVs) every renderer fills alike.
#pragma once

#include <cstddef>
#include <cstdint>
#include <vector>

namespace surftrace::view {

// Per-pixel results. The buffers (all but rgba) come from the pixel-centre ray, so another
// renderer using the same camera can be compared with them pixel by pixel; rgba averages
// all samples. Misses: kind 0, ids ~0u, depths +inf, normal 0.
struct FrameBuffers {
  int width = 0, height = 0;
  std::vector<float> rgba;            // 4 per pixel, display values in [0, 1]; A = coverage
                                      // (see transparentBackground)
  std::vector<float> depth;           // ray distance t (Å, unit direction)
  std::vector<float> viewZ;           // distance along the view direction (Å)
  std::vector<float> normal;          // 3 per pixel, world space, outward
  std::vector<std::uint32_t> kind;    // PatchKind (view/patch_kind.hpp)
  std::vector<std::uint32_t> patchId; // PatchIdOrder::globalId
  std::vector<std::uint32_t> atomId;
  std::vector<std::uint32_t> flags;   // HitFlag bits of the centre hit (view/ray.hpp)
  // Distance (Å) from the centre hit to the nearest edge of its patch, a lower bound from the
  // exact geometry (RenderOptions::referenceMasks; empty when not recorded): +inf for a miss
  // or a patch without edges, NaN where the renderer does not know it (the ball-and-stick model).
  std::vector<float> seamDistance;
  // Crossings of the centre ray with the surface that a transparent frame composited (at
  // most RenderOptions::maxLayers); empty for an opaque frame. Not written to image files.
  std::vector<std::uint32_t> layers;
  // False: the colour is composited over an opaque background, and A is the surface's coverage.
  // True (applyBackgroundAlpha): the background has an alpha below 1; the colour is
  // premultiplied by the pixel's alpha and A = coverage + (1 − coverage)·background alpha, the
  // pixel's opacity: PNGs get an alpha channel.
  bool transparentBackground = false;
  double seconds = 0.0;               // wall time of the frame
  std::size_t rays = 0;               // camera rays traced (shadow and AO rays not counted)

  std::size_t pixels() const { return static_cast<std::size_t>(width) * static_cast<std::size_t>(height); }
  // Sizes every buffer for width × height and fills it with the miss state.
  void reset(int newWidth, int newHeight);
};

// Makes the background of a frame composited over the opaque colour `background` (what every
// engine draws) transparent, with alpha `alpha` in [0, 1): with coverage c = A and colour C, the
// surface's own share is C − (1 − c)·background, the result is premultiplied
// C − (1 − c)(1 − alpha)·background with A = c + (1 − c)·alpha, and transparentBackground is set.
// The same pass for every engine, after the effects and the legend (view/engine.hpp).
void applyBackgroundAlpha(FrameBuffers& frame, const float (&background)[3], float alpha);

}  // namespace surftrace::view

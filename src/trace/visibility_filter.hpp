// Edge-aware smoothing of the per-pixel light visibilities of the soft and full lighting presets.
#pragma once

#include <cstddef>
#include <vector>

#include <glm/vec3.hpp>

namespace surftrace::trace {

// One image plane of hits (one sample position per pixel, the nearest crossing): the key
// light's visibility S and the ambient visibility A estimated with a few rays each, and the
// exact geometry that guides the filter. A value that was not traced (a miss; S where the
// key light is behind the surface) is NaN: the filter neither reads it nor writes it.
struct VisibilityPlane {
  int width = 0, height = 0;
  std::vector<float> key, open;             // S and A
  std::vector<glm::vec3> position, normal;  // the hit point and its unit normal (world)
  std::vector<float> footprint;             // the world distance between adjacent pixels' rays at the hit
  std::vector<unsigned char> hit;           // 1 where the pixel's ray hit
  std::vector<float> weight;                // the weight of the pixel's S and A to its neighbours: its rays over the preset's

  void reset(int w, int h);
  std::size_t index(int x, int y) const { return static_cast<std::size_t>(y) * width + x; }
};

// The hits that have a miss, a depth jump or a crease among their 8 neighbours: there the
// filter finds few neighbours to average with, so the renderer traces more rays.
std::vector<unsigned char> filterEdges(const VisibilityPlane& plane);

// `passes` rounds of an à-trous (dilated 5×5 B3-spline) filter, steps 1, 2, 4, …: each pixel's
// S and A become weighted means over hits on its own smooth surface. A neighbour's weight falls
// with its distance from the pixel's tangent plane (in units of footprint × step: a depth jump
// gets none) and with the angle between the normals (a crease gets little), so no value
// crosses a silhouette or a crease; and with its distance d from the pixel's hit, as
// exp(−d²/reach²), so that the visibilities' own detail (in Å) stays whatever the image's scale
// (though the reach is never under 1.5 pixels). Deterministic: the same planes give the same bits on any
// thread count.
void filterVisibility(VisibilityPlane& plane, int passes, float reach);

}  // namespace surftrace::trace

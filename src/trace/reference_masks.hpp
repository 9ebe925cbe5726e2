// What the exact tracer records for `compare`'s masks (view::RenderOptions::referenceMasks):
// how far each pixel's centre hit lies from the edge of its patch, and which pixels an edge of
// the surface crosses. Another renderer, rounding to float, may honestly disagree with the
// exact one only there.
#pragma once

#include <cstdint>
#include <optional>
#include <vector>

#include <glm/vec3.hpp>

#include "trace/layers.hpp"
#include "trace/patch_scene.hpp"
#include "view/camera.hpp"
#include "view/frame_buffers.hpp"

namespace surftrace::trace {

// The distance (Å) from a hit to the nearest edge of its patch: boundaryDistance() of its
// kind; for the SES's whole spheres the contact circles of their tori, for the vdW and SAS
// spheres the circles their blockers cut (SphereClip). A lower bound: each edge counts as its
// whole circle or plane. NaN for the ball-and-stick model, whose balls and sticks meet in
// creases that no patch records.
class SeamDistance {
 public:
  explicit SeamDistance(const ScenePatches& patches);
  double operator()(const SceneHit& hit, const glm::dvec3& x) const;

 private:
  double sphereDistance(std::uint32_t sphere, const glm::dvec3& x) const;

  const ScenePatches* patches_;
  // SES: the tori of each sphere's atom, CSR over the spheres; a torus index times 2, plus 1
  // where the sphere's atom is the torus's atom j.
  std::vector<std::uint32_t> toriBegin_, tori_;
  std::optional<SphereClip> blockers_;  // vdW, SAS
};

// Sets kPixelSilhouette where the rays through a pixel's centre and its four corners do not
// all hit or all miss, and kPixelOcclusion where they all hit but the surface between two of
// them is not smooth: the chord from the centre's hit to a corner's leaves the tangent plane
// of either end by more than kSmoothChordSine (on a smooth patch of curvature radius ρ a chord
// of length L leaves it by asin(L/2ρ): 30° only for L = ρ, several pixels at the sizes where
// this matters). The centre's hit is read from frame.depth and frame.normal.
inline constexpr double kSmoothChordSine = 0.5;
void markPixelEdges(const PatchScene& scene, const view::Camera& camera, view::FrameBuffers& frame);

}  // namespace surftrace::trace

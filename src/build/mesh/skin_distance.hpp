// The molecular skin as a field: the skin function G of ORACLES D.3 evaluated from its
// definition (a small convex programme over the atoms near the point), and projection onto the
// quadric of the mixed cell that holds the point.
#pragma once

#include <memory>
#include <span>

#include <glm/vec3.hpp>

#include "build/mesh/surface_distance.hpp"

namespace surftrace::build::mesh {

// The skin of `patches` (its shrink factor) over every atom given.
std::unique_ptr<SurfaceDistance> makeSkinDistance(const PatchList& patches, std::span<const glm::dvec3> centers,
                                                  std::span<const double> radii);

// G(x) = min over λ in the simplex of (1 − s)|Σλ_i (c_i − x)|² + s Σλ_i π_i(x), with
// π_i(x) = |x − c_i|² − r_i²/s (Å²; < 0 inside the skin body), and its minimiser's support: the
// Delaunay simplex whose mixed cell holds x (ascending atoms). Exposed for the tests.
struct SkinValue {
  double value = 0.0;
  glm::dvec3 gradient{0.0};  // ∇G = 2(x − z_λ)
  std::uint32_t atoms[4] = {~0u, ~0u, ~0u, ~0u};
  int size = 0;
};

}  // namespace surftrace::build::mesh

// The exact surface as a distance field: what the mesher samples, projects onto and certifies
// its meshes with, and what tests measure meshes against.
#pragma once

#include <cstdint>
#include <memory>
#include <span>

#include <glm/vec3.hpp>

#include "build/patch_list.hpp"

namespace surftrace::build::mesh {

// The surface point nearest to a query point.
struct SurfacePoint {
  glm::dvec3 point{0.0};    // on the surface (to ~1e-9 Å)
  glm::dvec3 normal{0.0};   // unit, outward (away from the body)
  std::uint32_t atom = 0;   // the atom that owns `point` (SES: the patch's atom or nearest contact
                            // atom; skin: the smallest power distance; vdW/SAS: the sphere's)
  std::uint8_t kind = 0;    // patch kind code of `point` (view::PatchKind numbering)
  std::uint32_t component = 0;  // surface component of `point`
};

// The surface of one patch list as a field. Both calls are thread-safe (const, no shared
// mutable state) so that the mesher can call them from TBB tasks.
class SurfaceDistance {
 public:
  virtual ~SurfaceDistance() = default;
  // Signed distance to the surface: < 0 inside the body, > 0 outside (a cavity's void is
  // outside), 0 on it. Exact for the SES, SAS and vdW surfaces where |value| <= reach(); for
  // the skin, a value with the exact sign and zero set whose magnitude is within a factor
  // [0.5, 2] of the distance near the surface. Far away the sign is still right.
  virtual double signedDistance(const glm::dvec3& x) const = 0;
  // The nearest surface point to x, for x with |signedDistance(x)| <= reach(). |x − point| is
  // always an upper bound on the distance from x to the surface (point is on the surface).
  virtual SurfacePoint closest(const glm::dvec3& x) const = 0;
  // Within this distance of the surface the two calls above are exact (Å); meshing grids
  // must be finer than it.
  virtual double reach() const = 0;
  // An axis-aligned box that contains the whole surface.
  virtual glm::dvec3 boundsMin() const = 0;
  virtual glm::dvec3 boundsMax() const = 0;
};

// The field of `patches` (SES, skin, vdW or SAS), made from the molecule's atom centres and
// radii (the patch list's own radii: as the build used them). std::invalid_argument when the
// counts differ from patches.params.atomCount.
std::unique_ptr<SurfaceDistance> makeSurfaceDistance(const PatchList& patches,
                                                     std::span<const glm::dvec3> centers,
                                                     std::span<const double> radii);

}  // namespace surftrace::build::mesh

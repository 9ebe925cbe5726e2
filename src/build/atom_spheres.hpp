// The van der Waals and solvent-accessible surfaces as patch lists of whole spheres.
#pragma once

#include <span>

#include <glm/vec3.hpp>

#include "build/patch_list.hpp"

namespace surftrace::build {

// The van der Waals (inflate = 0, SurfaceKind::Vdw) or solvent-accessible (inflate = rp,
// SurfaceKind::Sas) surface as a patch list of whole spheres, one convex patch per atom,
// so that every renderer draws it through the same contract as the SES. Areas are left 0.
PatchList atomSpheres(std::span<const glm::dvec3> centers, std::span<const double> radii, double inflate,
                      SurfaceKind kind);

}  // namespace surftrace::build

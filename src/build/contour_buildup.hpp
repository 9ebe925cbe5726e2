// SES patches by contour-buildup (Totrov & Abagyan 1996; Lindow et al. 2010, Sect. 4.1).
#pragma once

#include <functional>
#include <span>

#include <glm/vec3.hpp>

#include "build/patch_list.hpp"

namespace surftrace::build {

struct SesParams {
  double probeRadius = 1.4;
};

// Builds the SES patch list of atoms (centres, radii > 0, validated by the caller):
// a convex patch per atom with exposed SAS, a torus per exposed SAS arc, a concave
// triangle per SAS vertex, with self-intersection planes for every pair of probe
// positions closer than 2 rp. The list is identical (order and bits) for any number of
// threads. `params.probeRadius` must be finite and > 0 (std::invalid_argument otherwise).
// Fills patches.params.probeRadius, surface and atomCount; the caller sets the rest.
PatchList buildSes(std::span<const glm::dvec3> centers, std::span<const double> radii, const SesParams& params);

}  // namespace surftrace::build

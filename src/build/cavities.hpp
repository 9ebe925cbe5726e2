// Cavities located: per buried SES component, the atoms that line it, its centroid and box.
#pragma once

#include <cstdint>
#include <vector>

#include <glm/vec3.hpp>

#include "build/patch_list.hpp"

namespace surftrace::build {

// One cavity: an SES component whose volume is negative (computeAreas: a closed surface with
// its normals pointing into the void it encloses).
struct Cavity {
  std::uint32_t component = 0;  // its label in the patch list (`component` of its patches)
  double area = 0.0;            // Å², the component's area
  double volume = 0.0;          // Å³ of void it encloses (minus the component's volume: > 0)
  // The area-weighted centroid of its surface, ∫ x dA / A, exact from the patches. (Not the
  // centroid of the void: that needs ∮ |x|² n dA, second moments of the spherical regions
  // that the area code does not compute.)
  glm::dvec3 centroid{0.0};
  // The box of its surface patches: exact for the convex parts (extremes of the bounding
  // arcs and the sphere's poles inside the part), the tori (over the θ, φ rectangle) and the
  // concave patches (their probe sphere minus the edge and clipping caps).
  glm::dvec3 boxLower{0.0}, boxUpper{0.0};
  // Atoms (ascending) that own a patch of the component: convex patches' atoms (also for the
  // part of a one-atom wall's patch that faces the cavity), tori's i and j, concave
  // triangles' i, j and k.
  std::vector<std::uint32_t> atoms;
};

// The SES's cavities in the order of their labels. std::invalid_argument for a list that is
// not an SES (the skin's patches carry no component labels).
std::vector<Cavity> locateCavities(const PatchList& patches);

}  // namespace surftrace::build

// Which atoms can hide part of a whole convex sphere: the hidden part of the spheres that
// renderers draw whole, data of the patch list that the Embree and GL engines share.
#pragma once

#include <cstdint>
#include <span>
#include <vector>

#include <glm/vec3.hpp>
#include <glm/vec4.hpp>

#include "build/patch_list.hpp"

namespace surftrace::build {

// The whole spheres of a patch list draw their hidden part too: fine for the nearest hit, but a
// transparent surface would show it. A hit x on sphere i (centre c, radius ρ) is on its convex
// patch iff the point y = c + (ρ + g)/ρ (x − c) lies outside the grown sphere (r_k + h) of every
// other atom k: for the SES g = h = rp (y is then a point of the SAS, ORACLES D.1); for the vdW
// balls g = h = 0, for the SAS balls (ρ = r + rp) g = 0, h = rp (x is on the union's boundary).
// Skin spheres are clipped by their mixed cells already.
//
// `atoms` (centre, vdW radius) are every atom of the structure. Without them (a patch-list file
// alone) the spheres themselves stand in: complete for vdW and SAS, but the SES list has spheres
// of exposed atoms only, so a part of a sphere that only buried atoms hide then shows. With
// --drop-cavities the builder keeps a sphere that lines both the outer surface and a cavity
// whole, so its cavity side shows through while the cavity's tori and concave triangles are gone.
struct SphereBlockers {
  double grow = 0.0;                     // g
  std::vector<glm::dvec4> blockers;      // centre, grown radius r_k + h
  // CSR: blockers list[begin[i], begin[i + 1]) may hide sphere i, nearest (centre distance
  // minus grown radius) first, ties by index.
  std::vector<std::uint32_t> begin;
  std::vector<std::uint32_t> list;
};

// The blockers of each sphere (`centers`, `radii`, `sphereAtoms`: the list's convex spheres)
// of a surface `params` describes. Spheres and blockers meet iff their centres are closer than
// ρ_i + g + r_k + h; a sphere's own atom never blocks it.
SphereBlockers sphereBlockers(const SurfaceParams& params, std::span<const glm::dvec3> centers,
                              std::span<const double> radii, std::span<const std::uint32_t> sphereAtoms,
                              std::span<const glm::dvec4> atoms);
inline SphereBlockers sphereBlockers(const PatchList& list, std::span<const glm::dvec4> atoms) {
  return sphereBlockers(list.params, list.convex.center, list.convex.radius, list.convex.atom, atoms);
}

// Whether the point x of sphere i (centre c, radius ρ) is on its convex patch: outside every
// grown blocker of i, points within a relative `tolerance` of a blocker's sphere counting as
// outside it.
bool onConvexPatch(const SphereBlockers& b, std::uint32_t i, const glm::dvec3& c, double rho, const glm::dvec3& x,
                   double tolerance);

// Distance from the point x of sphere i (on its convex patch) to the patch's edge: to the
// nearest circle in which a grown blocker cuts the grown sphere, mapped back to sphere i (a
// lower bound, exact where that circle's nearest point is on the edge). For the SES these are
// the contact circles of the tori; +inf for a sphere that no blocker cuts.
double convexPatchEdgeDistance(const SphereBlockers& b, std::uint32_t i, const glm::dvec3& c, double rho,
                               const glm::dvec3& x);

}  // namespace surftrace::build

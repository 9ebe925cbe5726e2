// SES concave spherical triangle: a probe sphere inside the cone of its three contact
// directions, minus the caps cut off by its self-intersection clipping planes.
#pragma once

#include <optional>
#include <cstdint>
#include <span>

#include "build/patch_list.hpp"
#include "trace/ray.hpp"

namespace surftrace::trace {

// ORACLES A.4, A.5. The patch is {p + rp u : u in cone(dirI, dirJ, dirK)} with every
// kept point x satisfying n·x + w <= 0 for each clipping plane (n, w). `clipPlanes` views
// planes owned elsewhere (the PatchList, or ScenePatches): the patch must not outlive them.
struct ConcavePatch {
  glm::dvec3 probe{0.0};
  double probeRadius = 1.0;
  glm::dvec3 dirI{1.0, 0.0, 0.0}, dirJ{0.0, 1.0, 0.0}, dirK{0.0, 0.0, 1.0};  // unit
  std::span<const build::Plane> clipPlanes;
};

ConcavePatch concavePatch(const build::PatchList& patches, std::size_t index);

// Conservative, finite box of the spherical triangle (clipping ignored, so conservative).
Bounds3d bounds(const ConcavePatch& p);

// Every hit in (tMin, tMax], ascending, from one solve (transparency): the hits intersect() gives
// when called again from each hit's t until it finds none, bit for bit. Returns how many (0 to 2).
int allHits(const ConcavePatch& p, const UnitRay& ray, double tMin, double tMax, PatchHit (&hits)[2]);

// Both roots of the probe sphere in ascending t; the first in (tMin, tMax] inside the cone
// and on the kept side of every clipping plane is the hit. Normal (p − x)/rp, pointing out
// of the SES body. Flags: grazing, near a cone edge or a clipping plane.
std::optional<PatchHit> intersect(const ConcavePatch& p, const UnitRay& ray, double tMin, double tMax);
inline std::optional<PatchHit> intersect(const ConcavePatch& p, const Ray& ray, double tMin, double tMax) {
  return intersect(p, UnitRay(ray), tMin, tMax);
}

// Whether intersect(p, ray, tMin, tMax) has a hit (occlusion rays): its roots and clip tests,
// no normal or flags.
bool occludes(const ConcavePatch& p, const UnitRay& ray, double tMin, double tMax);

// The clip test intersect() applies to a point on the probe sphere. `slack` (Å, >= 0)
// widens the patch by that distance from its cone faces and clipping planes.
bool insidePatch(const ConcavePatch& p, const glm::dvec3& x, double slack = 0.0);

// Distance (Å) from a point x of the patch to its edges: the great circles of the cone's faces
// and the circles of the clipping planes on the probe sphere, each whole (a lower bound, exact
// where the circle's nearest point is on the patch).
double boundaryDistance(const ConcavePatch& p, const glm::dvec3& x);

// The atom a hit at x belongs to, of the triangle's atoms (i, j, k): the one of the
// nearest contact direction.
std::uint32_t atomOf(const ConcavePatch& p, const glm::uvec3& atoms, const glm::dvec3& x);

}  // namespace surftrace::trace

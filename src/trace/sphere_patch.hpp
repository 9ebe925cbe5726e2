// Whole spheres: SES convex patches (drawn whole, Lindow et al. 2010 Sect. 5.2: the hidden
// part is enclosed by the surface), van der Waals and solvent-accessible spheres.
#pragma once

#include <cstdint>
#include <optional>

#include "trace/ray.hpp"

namespace surftrace::trace {

struct SpherePatch {
  glm::dvec3 center{0.0};
  double radius = 1.0;
};

Bounds3d bounds(const SpherePatch& s);

// Every hit in (tMin, tMax], ascending, from one solve (transparency): the hits intersect() gives
// when called again from each hit's t until it finds none, bit for bit. Returns how many (0 to 2).
int allHits(const SpherePatch& s, const UnitRay& ray, double tMin, double tMax, PatchHit (&hits)[2]);

// The first root in (tMin, tMax] (ORACLES B.5: perpendicular-distance form, stable roots).
// A ray starting inside the sphere hits its far side. Normal (x − c)/r.
std::optional<PatchHit> intersect(const SpherePatch& s, const UnitRay& ray, double tMin, double tMax);
inline std::optional<PatchHit> intersect(const SpherePatch& s, const Ray& ray, double tMin, double tMax) {
  return intersect(s, UnitRay(ray), tMin, tMax);
}

// Whether intersect(s, ray, tMin, tMax) has a hit (occlusion rays): its roots, no normal.
bool occludes(const SpherePatch& s, const UnitRay& ray, double tMin, double tMax);

// The atom a hit at x belongs to: the sphere's own.
inline std::uint32_t atomOf(const SpherePatch&, std::uint32_t atom, const glm::dvec3&) { return atom; }

}  // namespace surftrace::trace

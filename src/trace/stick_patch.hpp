// The sticks of the ball-and-stick model: solid capped cylinders from atom a to atom b. Their
// flat caps sit at the atom centres, inside the balls, so what shows is the side between them.
#pragma once

#include <cstdint>
#include <optional>

#include <glm/vec2.hpp>

#include "trace/ray.hpp"

namespace surftrace::trace {

struct StickPatch {
  glm::dvec3 a{0.0}, b{0.0, 0.0, 1.0};  // the axis' ends (a != b)
  double radius = 0.15;
};

Bounds3d bounds(const StickPatch& s);
// The first crossing in (tMin, tMax] of the ray with the solid cylinder's boundary
// |x⊥| = radius, h = (x − a)·u in [0, L] (u = (b − a)/L), or with a cap h = 0, h = L inside the
// radius. Normal: radial on the side, ∓u on the caps. A ray starting inside leaves through it.
std::optional<PatchHit> intersect(const StickPatch& s, const Ray& ray, double tMin, double tMax);
// The same for a ray with its unit direction made (the scene's callbacks): a stick needs none of it.
inline std::optional<PatchHit> intersect(const StickPatch& s, const UnitRay& ray, double tMin, double tMax) {
  return intersect(s, ray.ray(), tMin, tMax);
}
// The atom a hit at x belongs to: a's on a's half of the axis, b's on the other (each half of a
// stick takes its atom's colour).
inline std::uint32_t atomOf(const StickPatch& s, const glm::uvec2& atoms, const glm::dvec3& x) {
  const glm::dvec3 axis = s.b - s.a;
  const glm::dvec3 p = x - s.a;
  return 2.0 * (p.x * axis.x + p.y * axis.y + p.z * axis.z) <= axis.x * axis.x + axis.y * axis.y + axis.z * axis.z
             ? atoms.x
             : atoms.y;
}

}  // namespace surftrace::trace

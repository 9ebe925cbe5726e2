// A ray's two roots on a sphere (ORACLES B.5): the set-up shared by whole spheres and concave
// patches (their probe spheres), and by each one's intersect(), occludes() and allHits().
#pragma once

#include <algorithm>
#include <cmath>

#include <glm/geometric.hpp>
#include <glm/vec3.hpp>

#include "trace/ray.hpp"

namespace surftrace::trace {

// The roots in the caller's t. f is the ray's closest point to the centre, relative to it; the
// roots' points are f ∓ root·d (near, far), exact in that shifted frame, unlike o + t·d − c far
// from the sphere.
struct SphereRoots {
  glm::dvec3 f;
  double root;  // √disc; |n·d| = root/ρ at both roots
  double tNear, tFar;
  bool nearInRange, farInRange;  // t in (tMin, tMax]
};

// False when the ray misses the sphere (or its direction is zero); inline, as it runs once per
// ray and patch in the hot loops.
inline bool sphereRoots(const glm::dvec3& center, double radius, const UnitRay& ray, double tMin, double tMax,
                        SphereRoots& s) {
  // Unit direction internally (Embree's float directions are unit only to float precision);
  // t is converted back to the caller's parametrisation.
  const double len = ray.length;
  const glm::dvec3& d = ray.unit;
  const glm::dvec3 oc = ray.org - center;
  // Project the centre onto the ray: the discriminant ρ² − |f|² keeps the small term that
  // b² − (|oc|² − ρ²) would cancel away.
  const double b = glm::dot(oc, d);
  s.f = oc - b * d;
  const double rr = radius * radius;
  const double disc = rr - glm::dot(s.f, s.f);
  if (!(disc >= 0.0)) return false;  // also rejects NaN (zero direction)
  s.root = std::sqrt(disc);
  const double q = -b - std::copysign(s.root, b);
  // q = 0 only for b = disc = 0: the origin is the tangent point, a double root at 0.
  const double r2 = q != 0.0 ? (glm::dot(oc, oc) - rr) / q : 0.0;
  s.tNear = std::min(q, r2) / len;
  s.tFar = std::max(q, r2) / len;
  s.nearInRange = s.tNear > tMin && s.tNear <= tMax;
  s.farInRange = s.tFar > tMin && s.tFar <= tMax;
  return true;
}

}  // namespace surftrace::trace

// Ray–sphere intersection for whole spheres (ORACLES B.5), in double.
#include "trace/sphere_patch.hpp"

#include <algorithm>
#include <cmath>
#include <limits>

#include <glm/common.hpp>
#include <glm/geometric.hpp>

#include "trace/sphere_roots.hpp"

namespace surftrace::trace {
namespace {

// Outward padding of a box, in units of ε times the coordinate's magnitude: the box corner
// c ± r is rounded once or twice, so a few ulps suffice; 8 keeps it conservative (STYLE §3.6).
constexpr double kBoundsPadUlps = 8.0;

// The hit at root t, whose point is f + sign·root·d (sign −1 near, +1 far).
inline PatchHit hitAt(const SpherePatch& s, const UnitRay& ray, const SphereRoots& r, double t, double sign) {
  PatchHit hit;
  hit.t = t;
  hit.normal = glm::normalize(r.f + (sign * r.root) * ray.unit);
  if (r.root < kGrazingCosine * s.radius) hit.flags |= kHitGrazing;  // |n·d| = √disc / ρ
  return hit;
}

}  // namespace

Bounds3d bounds(const SpherePatch& s) {
  const glm::dvec3 pad = kBoundsPadUlps * std::numeric_limits<double>::epsilon() * (glm::abs(s.center) + s.radius);
  const glm::dvec3 extent = s.radius + pad;
  Bounds3d b;
  b.lower = s.center - extent;
  b.upper = s.center + extent;
  return b;
}

int allHits(const SpherePatch& s, const UnitRay& ray, double tMin, double tMax, PatchHit (&hits)[2]) {
  // intersect()'s roots, normals and flags for both roots at once.
  SphereRoots r;
  if (!sphereRoots(s.center, s.radius, ray, tMin, tMax, r)) return 0;
  int count = 0;
  if (r.nearInRange) hits[count++] = hitAt(s, ray, r, r.tNear, -1.0);
  // After the near root, intersect() from its t finds the far one only if it lies beyond it.
  if (r.farInRange && (count == 0 || r.tFar > r.tNear)) hits[count++] = hitAt(s, ray, r, r.tFar, 1.0);
  return count;
}

std::optional<PatchHit> intersect(const SpherePatch& s, const UnitRay& ray, double tMin, double tMax) {
  SphereRoots r;
  if (!sphereRoots(s.center, s.radius, ray, tMin, tMax, r)) return std::nullopt;
  if (r.nearInRange) return hitAt(s, ray, r, r.tNear, -1.0);
  if (r.farInRange) return hitAt(s, ray, r, r.tFar, 1.0);
  return std::nullopt;
}

bool occludes(const SpherePatch& s, const UnitRay& ray, double tMin, double tMax) {
  SphereRoots r;
  return sphereRoots(s.center, s.radius, ray, tMin, tMax, r) && (r.nearInRange || r.farInRange);
}

}  // namespace surftrace::trace

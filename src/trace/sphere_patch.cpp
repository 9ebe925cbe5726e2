// Ray–sphere intersection for whole spheres (ORACLES B.5), in double.
#include "trace/sphere_patch.hpp"

#include <algorithm>
#include <cmath>
#include <limits>

#include <glm/common.hpp>
#include <glm/geometric.hpp>

namespace surftrace::trace {
namespace {

// Outward padding of a box, in units of ε times the coordinate's magnitude: the box corner
// c ± r is rounded once or twice, so a few ulps suffice; 8 keeps it conservative (STYLE §3.6).
constexpr double kBoundsPadUlps = 8.0;

}  // namespace

Bounds3d bounds(const SpherePatch& s) {
  const glm::dvec3 pad = kBoundsPadUlps * std::numeric_limits<double>::epsilon() * (glm::abs(s.center) + s.radius);
  const glm::dvec3 extent = s.radius + pad;
  Bounds3d b;
  b.lower = s.center - extent;
  b.upper = s.center + extent;
  return b;
}

namespace {

// Both roots of the ray on the sphere, in units of the ray's t, and what their hits share.
struct SphereRoots {
  double tNear, tFar;
  double root;    // √disc: half the chord, in units of the unit direction
  glm::dvec3 f;   // the ray's closest point to the centre, relative to it
};

bool sphereRoots(const SpherePatch& s, const UnitRay& ray, SphereRoots& out) {
  // Work with a unit direction (Embree's float directions are unit only to float
  // precision) and convert t back at the end.
  const double len = ray.length;
  const glm::dvec3& d = ray.unit;
  const glm::dvec3 oc = ray.org - s.center;
  // ORACLES B.5: project the centre onto the ray; f is the ray's closest point to the
  // centre, so the discriminant ρ² − |f|² keeps the small term that b² − (|oc|² − ρ²) loses.
  const double b = glm::dot(oc, d);
  out.f = oc - b * d;
  const double rr = s.radius * s.radius;
  const double disc = rr - glm::dot(out.f, out.f);
  if (!(disc >= 0.0)) return false;  // also rejects NaN (zero direction)
  out.root = std::sqrt(disc);
  const double q = -b - std::copysign(out.root, b);
  // q = 0 only for b = disc = 0: the origin is the tangent point, a double root at 0.
  const double r1 = q;
  const double r2 = q != 0.0 ? (glm::dot(oc, oc) - rr) / q : 0.0;
  out.tNear = std::min(r1, r2) / len;
  out.tFar = std::max(r1, r2) / len;
  return true;
}

// The hit at the near (sign −1) or far (sign +1) root. Its point is f − √disc·d or f + √disc·d
// (relative to the centre): exact in the shifted frame, unlike o + t·d − c far from the sphere.
PatchHit sphereHit(const SpherePatch& s, const UnitRay& ray, const SphereRoots& r, double sign) {
  PatchHit hit;
  hit.t = sign < 0.0 ? r.tNear : r.tFar;
  hit.normal = glm::normalize(r.f + (sign * r.root) * ray.unit);
  // |n·d| = √disc / ρ at both roots.
  if (r.root < kGrazingCosine * s.radius) hit.flags |= kHitGrazing;
  return hit;
}

}  // namespace

std::optional<PatchHit> intersect(const SpherePatch& s, const UnitRay& ray, double tMin, double tMax) {
  SphereRoots r;
  if (!sphereRoots(s, ray, r)) return std::nullopt;
  if (r.tNear > tMin && r.tNear <= tMax) return sphereHit(s, ray, r, -1.0);
  if (r.tFar > tMin && r.tFar <= tMax) return sphereHit(s, ray, r, 1.0);
  return std::nullopt;
}

int intersectAll(const SpherePatch& s, const UnitRay& ray, double tMin, double tMax, PatchHit (&hits)[2]) {
  SphereRoots r;
  if (!sphereRoots(s, ray, r)) return 0;
  int count = 0;
  if (r.tNear > tMin && r.tNear <= tMax) hits[count++] = sphereHit(s, ray, r, -1.0);
  // After the near root, intersect() from its t finds the far one only if it lies beyond it.
  if (r.tFar > tMin && r.tFar <= tMax && (count == 0 || r.tFar > r.tNear)) hits[count++] = sphereHit(s, ray, r, 1.0);
  return count;
}

}  // namespace surftrace::trace

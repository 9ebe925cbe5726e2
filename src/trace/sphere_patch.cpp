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

int allHits(const SpherePatch& s, const UnitRay& ray, double tMin, double tMax, PatchHit (&hits)[2]) {
  // intersect()'s roots, normals and flags, by the same expressions (below), for both roots at once.
  const double len = ray.length;
  const glm::dvec3& d = ray.unit;
  const glm::dvec3 oc = ray.org - s.center;
  const double b = glm::dot(oc, d);
  const glm::dvec3 f = oc - b * d;
  const double rr = s.radius * s.radius;
  const double disc = rr - glm::dot(f, f);
  if (!(disc >= 0.0)) return 0;
  const double root = std::sqrt(disc);
  const double q = -b - std::copysign(root, b);
  const double r1 = q;
  const double r2 = q != 0.0 ? (glm::dot(oc, oc) - rr) / q : 0.0;
  const double tNear = std::min(r1, r2) / len, tFar = std::max(r1, r2) / len;
  int count = 0;
  auto add = [&](double t, double sign) {
    PatchHit& hit = hits[count++];
    hit = PatchHit{};
    hit.t = t;
    hit.normal = glm::normalize(f + (sign * root) * d);
    if (root < kGrazingCosine * s.radius) hit.flags |= kHitGrazing;
  };
  if (tNear > tMin && tNear <= tMax) add(tNear, -1.0);
  // After the near root, intersect() from its t finds the far one only if it lies beyond it.
  if (tFar > tMin && tFar <= tMax && (count == 0 || tFar > tNear)) add(tFar, 1.0);
  return count;
}

std::optional<PatchHit> intersect(const SpherePatch& s, const UnitRay& ray, double tMin, double tMax) {
  // Work with a unit direction (Embree's float directions are unit only to float
  // precision) and convert t back at the end.
  const double len = ray.length;
  const glm::dvec3& d = ray.unit;
  const glm::dvec3 oc = ray.org - s.center;
  // ORACLES B.5: project the centre onto the ray; f is the ray's closest point to the
  // centre, so the discriminant ρ² − |f|² keeps the small term that b² − (|oc|² − ρ²) loses.
  const double b = glm::dot(oc, d);
  const glm::dvec3 f = oc - b * d;
  const double rr = s.radius * s.radius;
  const double disc = rr - glm::dot(f, f);
  if (!(disc >= 0.0)) return std::nullopt;  // also rejects NaN (zero direction)
  const double root = std::sqrt(disc);
  const double q = -b - std::copysign(root, b);
  // q = 0 only for b = disc = 0: the origin is the tangent point, a double root at 0.
  const double r1 = q;
  const double r2 = q != 0.0 ? (glm::dot(oc, oc) - rr) / q : 0.0;
  const double tNear = std::min(r1, r2) / len, tFar = std::max(r1, r2) / len;

  // The near root's point is f − √disc·d, the far one's f + √disc·d (relative to the
  // centre): exact in the shifted frame, unlike o + t·d − c far from the sphere.
  double sign;
  PatchHit hit;
  if (tNear > tMin && tNear <= tMax) {
    hit.t = tNear;
    sign = -1.0;
  } else if (tFar > tMin && tFar <= tMax) {
    hit.t = tFar;
    sign = 1.0;
  } else {
    return std::nullopt;
  }
  hit.normal = glm::normalize(f + (sign * root) * d);
  // |n·d| = √disc / ρ at both roots.
  if (root < kGrazingCosine * s.radius) hit.flags |= kHitGrazing;
  return hit;
}

bool occludes(const SpherePatch& s, const UnitRay& ray, double tMin, double tMax) {
  // intersect()'s roots, by the same expressions; no normal.
  const double len = ray.length;
  const glm::dvec3& d = ray.unit;
  const glm::dvec3 oc = ray.org - s.center;
  const double b = glm::dot(oc, d);
  const glm::dvec3 f = oc - b * d;
  const double rr = s.radius * s.radius;
  const double disc = rr - glm::dot(f, f);
  if (!(disc >= 0.0)) return false;
  const double q = -b - std::copysign(std::sqrt(disc), b);
  const double r2 = q != 0.0 ? (glm::dot(oc, oc) - rr) / q : 0.0;
  const double tNear = std::min(q, r2) / len, tFar = std::max(q, r2) / len;
  return (tNear > tMin && tNear <= tMax) || (tFar > tMin && tFar <= tMax);
}

}  // namespace surftrace::trace

// Small vector helpers that every layer of surftrace_build (ses/, mss/, the spherical regions)
// and the renderers' tests share.
#pragma once

#include <cmath>
#include <limits>

#include <glm/common.hpp>
#include <glm/geometric.hpp>
#include <glm/vec3.hpp>

namespace surftrace::build {

// A unit vector perpendicular to n, chosen by n alone (so it is canonical).
inline glm::dvec3 perpendicularTo(const glm::dvec3& n) {
  const glm::dvec3 a = glm::abs(n);
  const glm::dvec3 helper = (a.x <= a.y && a.x <= a.z) ? glm::dvec3(1, 0, 0)
                            : (a.y <= a.z)               ? glm::dvec3(0, 1, 0)
                                                         : glm::dvec3(0, 0, 1);
  return glm::normalize(glm::cross(n, helper));
}

// Distance from a point x of the sphere (centre c, radius r) to the circle in which the plane
// n·y = n·c + h·r (n unit) cuts it: the circle's nearest point is on x's meridian about n, so
// it is the chord 2r·sin(|α − α0|/2) between the polar angles α of x and α0 = acos(h) of the
// circle. +inf when the plane misses the sphere (|h| >= 1). Where a patch of the sphere ends
// on such a circle, this is how far its point x is from that edge.
inline double distanceToSphereCircle(const glm::dvec3& c, double r, const glm::dvec3& x, const glm::dvec3& n, double h) {
  if (!(std::abs(h) < 1.0)) return std::numeric_limits<double>::infinity();
  const double alpha = std::acos(glm::clamp(glm::dot(n, x - c) / r, -1.0, 1.0));
  return 2.0 * r * std::sin(0.5 * std::abs(alpha - std::acos(h)));
}

}  // namespace surftrace::build

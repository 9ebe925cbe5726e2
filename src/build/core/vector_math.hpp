// Small vector helpers that every layer of surftrace_build (ses/, mss/, the spherical regions)
// and the renderers' tests share.
#pragma once

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

}  // namespace surftrace::build

// Long-double oracle for rays against one sphere (ORACLES B.5), shared by the sphere and
// concave-patch tests: the implicit |x − c|² − ρ² marched and bisected, the grazing cosine.
#pragma once

#include <algorithm>
#include <cmath>
#include <vector>

#include <glm/vec3.hpp>

#include "oracles/ray_march.hpp"
#include "trace/ray.hpp"

namespace surftrace::trace::sphere_oracle {

using Real = long double;

struct Vec3L {
  Real x, y, z;
};
inline Vec3L toL(const glm::dvec3& v) { return {v.x, v.y, v.z}; }
// a − b, each rounded once in long double: exact enough to serve as the reference.
inline Vec3L subL(const glm::dvec3& a, const glm::dvec3& b) {
  return {static_cast<Real>(a.x) - b.x, static_cast<Real>(a.y) - b.y, static_cast<Real>(a.z) - b.z};
}
inline Real dotL(const Vec3L& a, const Vec3L& b) { return a.x * b.x + a.y * b.y + a.z * b.z; }
inline Vec3L crossL(const Vec3L& a, const Vec3L& b) {
  return {a.y * b.z - a.z * b.y, a.z * b.x - a.x * b.z, a.x * b.y - a.y * b.x};
}
inline Vec3L scaleL(const Vec3L& a, Real s) { return {a.x * s, a.y * s, a.z * s}; }

// |x − c|² − ρ² along the ray, in long double with the origin shifted to the centre.
struct SphereImplicit {
  Vec3L oc, d;
  Real rr;
  SphereImplicit(const glm::dvec3& center, double radius, const Ray& r)
      : oc(subL(r.org, center)), d(toL(r.dir)), rr(static_cast<Real>(radius) * radius) {}
  Vec3L local(Real t) const { return {oc.x + t * d.x, oc.y + t * d.y, oc.z + t * d.z}; }
  Real operator()(Real t) const {
    const Vec3L v = local(t);
    return dotL(v, v) - rr;
  }
};

// Every root on [tMin, tMax]. The march covers only the window where the ray is within ρ of
// the centre (|t·|d| − t_c·|d|| <= ρ), since no root can lie outside it.
inline std::vector<Real> sphereRoots(const glm::dvec3& center, double radius, const Ray& r, double tMin, double tMax,
                                     int steps) {
  const SphereImplicit f(center, radius, r);
  const Real dd = dotL(f.d, f.d);
  const Real tc = -dotL(f.oc, f.d) / dd;
  const Real hw = static_cast<Real>(radius) * (1 + 1e-6L) / std::sqrt(dd);
  const Real lo = std::max<Real>(tMin, tc - hw), hi = std::min<Real>(tMax, tc + hw);
  if (!(lo < hi)) return {};
  return oracles::marchRoots(f, lo, hi, steps);
}

// |n·d̂| of the ray against the sphere, as the perpendicular distance gives it: the
// hit/miss answer of a ray below kGrazingCosine flips within rounding (ORACLES B.4).
inline Real sphereGrazingCosine(const glm::dvec3& center, double radius, const Ray& r) {
  const SphereImplicit f(center, radius, r);
  const Real b = dotL(f.oc, f.d) / std::sqrt(dotL(f.d, f.d));
  return std::sqrt(std::abs(f.rr - (dotL(f.oc, f.oc) - b * b)) / f.rr);
}

inline bool finite(const Bounds3d& b) {
  return std::isfinite(b.lower.x) && std::isfinite(b.lower.y) && std::isfinite(b.lower.z) &&
         std::isfinite(b.upper.x) && std::isfinite(b.upper.y) && std::isfinite(b.upper.z);
}
// Whether c + local lies in b, summed in long double.
inline bool containsL(const Bounds3d& b, const glm::dvec3& c, const Vec3L& local) {
  const Real x = c.x + local.x, y = c.y + local.y, z = c.z + local.z;
  return x >= b.lower.x && y >= b.lower.y && z >= b.lower.z && x <= b.upper.x && y <= b.upper.y && z <= b.upper.z;
}

}  // namespace surftrace::trace::sphere_oracle

// Rays, hits and boxes in double precision: the vocabulary every intersector shares.
#pragma once

#include <cstdint>
#include <limits>

#include <glm/common.hpp>
#include <glm/geometric.hpp>
#include <glm/vec3.hpp>

#include "view/ray.hpp"

namespace surftrace::trace {

// The camera's ray and the flag bits are renderer-neutral (view/ray.hpp); the intersectors
// speak of them as their own.
using view::Ray;
using view::HitFlag;
using view::kHitGrazing;
using view::kHitCusp;
using view::kHitNearBoundary;

inline constexpr double kGrazingCosine = 1e-3;
inline constexpr double kCuspFraction = 1e-6;
// Relative (to the patch's scale) distance from a trimming edge below which the hit could
// belong to the neighbouring patch instead: a seam.
inline constexpr double kBoundaryTolerance = 1e-9;

// A ray with its unit direction and that direction's length, where every intersector starts:
// made once per ray for the Embree callbacks, which see one ray at many patches. The same
// expressions the intersectors used on a plain Ray, so their answers are the same bit for bit.
struct UnitRay {
  glm::dvec3 org{0.0}, dir{0.0, 0.0, 1.0};
  double length = 1.0;  // |dir|
  glm::dvec3 unit{0.0, 0.0, 1.0};  // dir / |dir|
  UnitRay() = default;
  explicit UnitRay(const Ray& r) : org(r.org), dir(r.dir), length(glm::length(r.dir)), unit(r.dir / length) {}
  Ray ray() const { return Ray{org, dir}; }
};

struct PatchHit {
  double t = std::numeric_limits<double>::infinity();
  glm::dvec3 normal{0.0};  // unit, pointing out of the SES body (into the solvent)
  std::uint32_t flags = 0;
};

struct Bounds3d {
  glm::dvec3 lower{std::numeric_limits<double>::infinity()};
  glm::dvec3 upper{-std::numeric_limits<double>::infinity()};

  void extend(const glm::dvec3& p) {
    lower = glm::min(lower, p);
    upper = glm::max(upper, p);
  }
  void extend(const Bounds3d& b) {
    lower = glm::min(lower, b.lower);
    upper = glm::max(upper, b.upper);
  }
  bool contains(const glm::dvec3& p, double slack = 0.0) const {
    return p.x >= lower.x - slack && p.y >= lower.y - slack && p.z >= lower.z - slack &&
           p.x <= upper.x + slack && p.y <= upper.y + slack && p.z <= upper.z + slack;
  }
  bool empty() const { return !(lower.x <= upper.x && lower.y <= upper.y && lower.z <= upper.z); }
};

}  // namespace surftrace::trace

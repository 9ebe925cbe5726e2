// Rays, hits and boxes in double precision: the vocabulary every intersector shares.
#pragma once

#include <cstdint>
#include <limits>

#include <glm/common.hpp>
#include <glm/vec3.hpp>

namespace surftrace::trace {

// x(t) = org + t·dir. Intersectors accept any non-zero dir (Embree hands over float
// directions that are unit only to float precision) and report t in this parametrisation.
struct Ray {
  glm::dvec3 org{0.0};
  glm::dvec3 dir{0.0, 0.0, 1.0};
};

// Why a pixel's answer is genuinely ambiguous (ORACLES B.4, D.4). A comparison masks it.
enum HitFlag : std::uint32_t {
  kHitGrazing = 1u << 0,       // |n·d| < kGrazingCosine: hit/miss flips within rounding
  kHitCusp = 1u << 1,          // within kCuspFraction·rp of a spindle torus cusp
  kHitNearBoundary = 1u << 2,  // within kBoundaryTolerance of a patch's trimming edge
};
inline constexpr double kGrazingCosine = 1e-3;
inline constexpr double kCuspFraction = 1e-6;
// Relative (to the patch's scale) distance from a trimming edge below which the hit could
// belong to the neighbouring patch instead: a seam.
inline constexpr double kBoundaryTolerance = 1e-9;

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

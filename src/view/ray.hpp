// A camera ray and the meaning of the `flags` image channel: what every renderer and comparison shares.
#pragma once

#include <cstdint>

#include <glm/vec3.hpp>

namespace surftrace::view {

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
  // Pixel flags, which only a reference frame records (RenderOptions::referenceMasks): the
  // rays through the pixel's centre and its four corners show that within the pixel
  kPixelSilhouette = 1u << 3,  // the surface's outline passes (some of them hit, some miss)
  kPixelOcclusion = 1u << 4,   // the depth jumps: one part of the surface hides another
};

}  // namespace surftrace::view

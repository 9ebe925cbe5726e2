// SES saddle (toroidal) patch: exact ray–torus intersection by quartic root isolation.
#pragma once

#include <limits>
#include <optional>

#include <glm/vec2.hpp>

#include "build/patch_list.hpp"
#include "trace/ray.hpp"

namespace surftrace::trace {

// One torus patch in its own frame (ORACLES A.3): centre c, unit axis n, e1 ⊥ n,
// e2 = n × e1; big radius R, tube radius rp; the saddle is θ ∈ [thetaI, thetaJ]
// (θ = 0 points from the probe-centre circle towards the axis) swept over
// φ ∈ [0, phiExtent] from e1 towards e2. When R < rp (spindle) only the own-tube
// part with ρ >= 0 belongs to it, i.e. |x − c| >= sqrt(rp² − R²); cusps at c ± h n.
struct TorusPatch {
  glm::dvec3 center{0.0};
  glm::dvec3 axis{0.0, 0.0, 1.0};
  glm::dvec3 e1{1.0, 0.0, 0.0};
  glm::dvec3 e2{0.0, 1.0, 0.0};
  double bigRadius = 2.0;
  double probeRadius = 1.0;
  double thetaI = -0.5;
  double thetaJ = 0.5;
  double phiExtent = 6.283185307179586;

  // Derived values that intersect() would otherwise recompute per ray (the sines and cosines
  // of the trimming limits, the normalised radii, the visibility sphere), filled by prepare()
  // from the fields above. `key` records the (R, rp, θi, θj, Δφ) they were computed for:
  // intersect() and insidePatch() use them only while the key still matches those fields
  // bit for bit, and otherwise recompute them on the fly (same expressions, same results), so
  // a patch built or edited by hand without prepare() is merely slower.
  struct Derived {
    double key[5] = {std::numeric_limits<double>::quiet_NaN(), 0.0, 0.0, 0.0, 0.0};
    double invScale = 0.0, normBigRadius = 0.0, normProbeRadius = 0.0;
    double thetaICos = 0.0, thetaISin = 0.0, thetaJCos = 0.0, thetaJSin = 0.0;
    double endCos = 1.0, endSin = 0.0;
    // Visibility sphere (normalised units): clipped only if `visibilityClip`; centre on the
    // axis at visibilityHeight, radius visibilityRadius (padded).
    bool visibilityClip = false;
    double visibilityHeight = 0.0, visibilityRadius = 0.0;
  } derived;
};

// Fill p.derived from the angle and radius fields (torusPatch() does this).
void prepare(TorusPatch& p);

// A patch from its frame and angles (e2 = axis × e1), prepared.
TorusPatch makeTorusPatch(const glm::dvec3& center, const glm::dvec3& axis, const glm::dvec3& e1, double bigRadius,
                          double probeRadius, double thetaI, double thetaJ, double phiExtent);

TorusPatch torusPatch(const build::Tori& tori, std::size_t index, double probeRadius);

// Conservative, finite box of the patch itself (not of the whole torus).
Bounds3d bounds(const TorusPatch& p);

// The nearest hit in (tMin, tMax] on the patch (ORACLES B.1, B.2, B.4): local frame,
// scale by R + rp, clip to the bounding sphere, shift the origin to the closest approach,
// isolate all real roots of the quartic in the interval, polish on the own-tube factor,
// reject lemon roots, and take the first root inside the θ and φ limits. Normal
// (P − x)/rp. Flags: grazing, cusp, near the trimming boundary.
std::optional<PatchHit> intersect(const TorusPatch& p, const UnitRay& ray, double tMin, double tMax);
inline std::optional<PatchHit> intersect(const TorusPatch& p, const Ray& ray, double tMin, double tMax) {
  return intersect(p, UnitRay(ray), tMin, tMax);
}

// Whether intersect(p, ray, tMin, tMax) has a hit, for occlusion rays: the same roots and
// tests, stopping at the first root that passes them, with no normal or flags.
bool occludes(const TorusPatch& p, const UnitRay& ray, double tMin, double tMax);

// Outward SES normal at a point on (or near) the patch: (P(φ) − x)/rp.
glm::dvec3 normalAt(const TorusPatch& p, const glm::dvec3& x);

// Whether a point on the torus lies inside the patch's θ/φ limits (and on the SES sheet
// of a spindle torus), with `slack` radians of tolerance: the clip test the intersector
// and its brute-force oracle share.
bool insidePatch(const TorusPatch& p, const glm::dvec3& x, double slack = 0.0);

// Distance (Å) from a point x of the patch to its trimming edges: the contact circles at θi
// and θj, the tube circles at φ = 0 and Δφ when the ring is partial, and a spindle's cusps.
// Each edge is extended to its whole circle, so this is a lower bound, exact where the
// nearest point of that circle is on the patch (for the contact circles, always).
double boundaryDistance(const TorusPatch& p, const glm::dvec3& x);
// Distance (Å) from any point x to the whole contact circle at θj (`atomJ`) or θi: where the
// saddle meets that atom's convex sphere.
double contactCircleDistance(const TorusPatch& p, bool atomJ, const glm::dvec3& x);

// The atom a hit at x belongs to, of the saddle's atoms (i, j): the one whose contact
// circle is nearer along the axis.
std::uint32_t atomOf(const TorusPatch& p, const glm::uvec2& atoms, const glm::dvec3& x);

}  // namespace surftrace::trace

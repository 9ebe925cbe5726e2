// Ray–capped-cylinder intersection for the ball-and-stick model's sticks, in double.
#include "trace/stick_patch.hpp"

#include <algorithm>
#include <cmath>
#include <limits>
#include <utility>

#include <glm/common.hpp>
#include <glm/geometric.hpp>

namespace surftrace::trace {
namespace {
// Outward padding of a box in units of ε times the coordinate's magnitude (as sphere_patch.cpp).
constexpr double kBoundsPadUlps = 8.0;
}  // namespace

Bounds3d bounds(const StickPatch& s) {
  // The disc of radius ρ about axis u reaches ρ·sqrt(1 − u_k²) along axis k.
  const glm::dvec3 u = glm::normalize(s.b - s.a);
  const glm::dvec3 reach = s.radius * glm::sqrt(glm::max(glm::dvec3(0.0), 1.0 - u * u));
  Bounds3d b;
  b.extend(glm::min(s.a, s.b) - reach);
  b.extend(glm::max(s.a, s.b) + reach);
  const glm::dvec3 pad = kBoundsPadUlps * std::numeric_limits<double>::epsilon() *
                         (glm::max(glm::abs(s.a), glm::abs(s.b)) + s.radius);
  b.lower -= pad;
  b.upper += pad;
  return b;
}

std::optional<PatchHit> intersect(const StickPatch& s, const Ray& ray, double tMin, double tMax) {
  const double len = glm::length(ray.dir);
  const glm::dvec3 d = ray.dir / len;
  const glm::dvec3 axis = s.b - s.a;
  const double L = glm::length(axis);
  const glm::dvec3 u = axis / L;
  const glm::dvec3 oa = ray.org - s.a;
  const double h0 = glm::dot(oa, u), dh = glm::dot(d, u);
  // Everything perpendicular to the axis: the ray's shadow o⊥ + t d⊥ in the cross-section.
  const glm::dvec3 oPerp = oa - h0 * u, dPerp = d - dh * u;
  const double A = glm::dot(dPerp, dPerp);
  const double rr = s.radius * s.radius;
  struct Candidate {
    double t;         // along the unit direction
    glm::dvec3 normal;
    bool grazing;
  };
  Candidate found[4];
  int n = 0;
  if (A > 0.0) {
    // As ORACLES B.5 does for the sphere: the shadow's closest point f to the axis keeps the
    // small term ρ² − |f|² that the expanded quadratic loses when the ray passes far away.
    const double tc = -glm::dot(oPerp, dPerp) / A;
    const glm::dvec3 f = oPerp + tc * dPerp;
    const double disc = rr - glm::dot(f, f);
    if (disc >= 0.0) {
      const double half = std::sqrt(disc / A);
      for (double sign : {-1.0, 1.0}) {
        const double t = tc + sign * half;
        const double h = h0 + t * dh;
        if (h >= 0.0 && h <= L)
          found[n++] = {t, glm::normalize(f + (sign * half) * dPerp), std::sqrt(disc) < kGrazingCosine * s.radius};
      }
    }
  }
  if (dh != 0.0) {
    for (double cap : {0.0, L}) {
      const double t = (cap - h0) / dh;
      const glm::dvec3 p = oPerp + t * dPerp;
      if (glm::dot(p, p) <= rr) found[n++] = {t, cap == 0.0 ? -u : u, std::abs(dh) < kGrazingCosine};
    }
  }
  // At most four: insertion by hand (GCC 12 warns of std::sort's 16-element threshold here).
  for (int i = 1; i < n; ++i)
    for (int j = i; j > 0 && found[j].t < found[j - 1].t; --j) std::swap(found[j], found[j - 1]);
  for (int i = 0; i < n; ++i) {
    const double t = found[i].t / len;
    if (!(t > tMin && t <= tMax)) continue;
    PatchHit hit;
    hit.t = t;
    hit.normal = found[i].normal;
    if (found[i].grazing) hit.flags |= kHitGrazing;
    return hit;
  }
  return std::nullopt;
}

}  // namespace surftrace::trace

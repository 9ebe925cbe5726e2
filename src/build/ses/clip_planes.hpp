// Which self-intersection planes can cut a concave patch (ORACLES A.5).
#pragma once

#include <algorithm>
#include <cmath>

#include <glm/geometric.hpp>
#include <glm/vec3.hpp>

namespace surftrace::build {

// Two probe spheres S(p), S(q) with |q − p| < 2 rp cut each other. The plane between them
// removes from S(p) the points x = p + rp w with |x − q| < rp, which are the directions w
// in the cap w·u > cosAlpha, u = (q − p)/|q − p|, cosAlpha = |q − p| / (2 rp).
//
// TriangleCone answers whether such a cap may meet a concave patch's spherical triangle:
// the unit directions in the convex cone of the contact directions d[0..2], bounded by
// minor arcs. It says no only when the two are apart by more than `margin` (in cosine), so
// a plane dropped for it clips nothing of the patch; a flat (degenerate) cone is always
// met. Apart means: no corner of the triangle in the cap, the cap's centre u outside the
// cone, and no edge through the cap (along an arc the largest u·w is at u's projection
// onto the arc's great circle when that falls between the arc's ends, else at an end).
// Everything that depends on the triangle alone is prepared once per patch; most pairs
// are then settled by a bounding cap of the triangle (centre g, angular radius β).
class TriangleCone {
 public:
  explicit TriangleCone(const glm::dvec3 (&d)[3], double margin = 1e-9) : margin_(margin) {
    for (int e = 0; e < 3; ++e) {
      const glm::dvec3& a = d[e];
      const glm::dvec3& b = d[(e + 1) % 3];
      corner_[e] = a;
      glm::dvec3 m = glm::cross(a, b);
      const double len = glm::length(m);
      const double side = glm::dot(m, d[(e + 2) % 3]);
      if (!(len > 1e-12) || !(std::abs(side) > 1e-12 * len)) {
        flat_ = true;
        return;
      }
      m /= len;                                         // the arc's great circle, a to b
      const double inward = side < 0.0 ? -1.0 : 1.0;   // towards the third corner
      normal_[e] = inward * m;
      fromA_[e] = glm::cross(m, a);  // v between a and b on the circle: v·(m × a) >= 0 ...
      toB_[e] = glm::cross(b, m);    // ... and v·(b × m) >= 0
    }
    // β <= 90°: the cap is spherically convex, so it holds the triangle with its corners.
    const glm::dvec3 sum = d[0] + d[1] + d[2];
    const double sumLen = glm::length(sum);
    if (sumLen > 1e-12) {
      centre_ = sum / sumLen;
      cosBeta_ = std::min({glm::dot(centre_, d[0]), glm::dot(centre_, d[1]), glm::dot(centre_, d[2])});
      sinBeta_ = std::sqrt(std::max(0.0, 1.0 - cosBeta_ * cosBeta_));
      bounded_ = cosBeta_ > 0.0;
    }
  }

  bool capMeets(const glm::dvec3& u, double cosAlpha) const {
    if (flat_) return true;
    const double reach = cosAlpha - margin_;
    if (bounded_) {
      // Apart if the angle from u to g exceeds α + β: cos(u, g) < cos(α + β).
      const double sinAlpha = std::sqrt(std::max(0.0, 1.0 - cosAlpha * cosAlpha));
      if (glm::dot(u, centre_) < cosAlpha * cosBeta_ - sinAlpha * sinBeta_ - 4.0 * margin_) return false;
    }
    bool centreInside = true;
    for (int e = 0; e < 3; ++e) {
      if (glm::dot(u, corner_[e]) > reach) return true;
      const double un = glm::dot(u, normal_[e]);
      centreInside = centreInside && un >= -margin_;
      // u's projection onto the arc's circle lies between its ends (tested on u itself:
      // the tangents are orthogonal to the normal), at height sqrt(1 − un²).
      if (glm::dot(u, fromA_[e]) >= -margin_ && glm::dot(u, toB_[e]) >= -margin_ &&
          (reach < 0.0 || 1.0 - un * un > reach * reach))
        return true;
    }
    return centreInside;
  }

 private:
  double margin_;
  bool flat_ = false, bounded_ = false;
  glm::dvec3 corner_[3]{}, normal_[3]{}, fromA_[3]{}, toB_[3]{};
  glm::dvec3 centre_{0.0};
  double cosBeta_ = -1.0, sinBeta_ = 0.0;
};

}  // namespace surftrace::build

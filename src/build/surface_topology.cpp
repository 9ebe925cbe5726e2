// Euler characteristic per SES component by Gauss–Bonnet over the patches.
//
// Counting V − E + F needs the cell complex of the clipped patches (which arcs end where, which
// faces have holes), which the patch list does not store. Gauss–Bonnet needs only what each
// patch holds: the SES is tangent-continuous everywhere except along the creases where
// self-intersecting concave patches meet and at the corners those creases end in, so
// 2πχ = ∫K dA + Σ creases ∮(κg⁺ + κg⁻) ds + Σ corners (2π − Σ interior angles).
// The areas are the exact ones computeAreas uses; the creases and corners come from the same
// sphere-minus-caps sweep that gives a clipped concave patch its area.
#include "build/surface_topology.hpp"

#include <algorithm>
#include <cmath>
#include <limits>
#include <numbers>
#include <tuple>

#include <glm/geometric.hpp>
#include <tbb/enumerable_thread_specific.h>
#include <tbb/parallel_for.h>

#include "build/ses/surface_area.hpp"
#include "build/spherical_region.hpp"

namespace surftrace::build {
namespace {

constexpr double kPi = std::numbers::pi;
constexpr double kTwoPi = 2.0 * std::numbers::pi;
// A Gauss–Bonnet sum this far from an integer (in units of 2π) is not rounding: some corner
// or crease of the component was not seen.
constexpr double kIntegerTolerance = 1e-6;

// A corner of a face at a singular point of the surface (where creases meet, or a spindle
// torus's cusp): its position and the face's interior angle there.
struct Corner {
  enum Kind { Crease, Edge, Cusp };  // between two creases; a crease and a torus edge; a torus's cusp
  glm::dvec3 at;
  double angle;
  std::uint32_t component;
  Kind kind;
  glm::dvec3 probe;  // a concave corner's probe sphere
};

// ∫K dA of a concave patch (its unit-sphere area) plus what its creases add to 2πχ, from the
// boundary sphereMinusCaps leaves in `s`; the corners where a crease ends go to `corners`.
double concaveCurvature(const PatchList& p, std::size_t c, std::vector<Cap>& caps, SphericalRegionScratch& s,
                        std::vector<Corner>& corners) {
  const SphericalRegion region = sphereMinusCaps(concaveCaps(p, c, caps), s);
  double total = region.area;
  if (p.concave.clipCount[c] == 0 || region.area == 0.0) return total;
  // The three edge caps are half-spheres (cosRadius 0: great circles, κg = 0, bounding tori);
  // a clipping cap's circle is a crease with the neighbouring probe's patch.
  auto crease = [&](int cap) { return s.caps[static_cast<std::size_t>(cap)].cosRadius != 0.0; };
  for (const int cap : s.fullCircles)
    if (crease(cap)) total -= s.caps[static_cast<std::size_t>(cap)].cosRadius * kTwoPi;
  for (const auto& arc : s.arcs) {
    if (!crease(arc.cap)) continue;
    // The region lies outside the cap: κg = −cos β / sin β on the unit sphere, over a length
    // sin β per radian of the circle.
    const Cap& k = s.caps[static_cast<std::size_t>(arc.cap)];
    const glm::dvec3 b = arc.begin - k.cosRadius * k.axis, e = arc.end - k.cosRadius * k.axis;
    double swept = std::atan2(glm::dot(k.axis, glm::cross(b, e)), glm::dot(b, e));
    if (swept <= 0.0) swept += kTwoPi;
    total -= k.cosRadius * swept;
  }
  // Corners, matched as sphereMinusCaps matches them (each arc continues with the arc that
  // starts nearest its end). One between two edge caps is a contact point of the triangle,
  // where the surface is smooth; one at the end of a crease is a singular point, whose
  // defect needs the other faces' corners there (surfaceTopology sums them by position).
  const double rp = p.params.probeRadius;
  for (const auto& in : s.arcs) {
    std::size_t next = 0;
    double nearest = std::numeric_limits<double>::infinity();
    for (std::size_t k = 0; k < s.arcs.size(); ++k) {
      const glm::dvec3 gap = s.arcs[k].begin - in.end;
      if (glm::dot(gap, gap) < nearest) nearest = glm::dot(gap, gap), next = k;
    }
    const auto& out = s.arcs[next];
    if (!crease(in.cap) && !crease(out.cap)) continue;
    const glm::dvec3 tIn = glm::cross(s.caps[static_cast<std::size_t>(in.cap)].axis, in.end);
    const glm::dvec3 tOut = glm::cross(s.caps[static_cast<std::size_t>(out.cap)].axis, in.end);
    const double exterior = -std::atan2(glm::dot(glm::cross(tIn, tOut), in.end), glm::dot(tIn, tOut));
    const Corner::Kind kind = crease(in.cap) && crease(out.cap) ? Corner::Crease : Corner::Edge;
    corners.push_back({p.concave.probe[c] + rp * in.end, kPi - exterior, p.concave.component[c], kind, p.concave.probe[c]});
  }
  return total;
}

}  // namespace

std::vector<ComponentTopology> surfaceTopology(const PatchList& p) {
  if (p.params.surface != SurfaceKind::Ses) return {};
  const double rp = p.params.probeRadius;
  std::size_t count = std::max<std::size_t>(1, p.componentCount);
  for (const auto* labels : {&p.convex.component, &p.tori.component, &p.concave.component})
    for (const std::uint32_t c : *labels) count = std::max<std::size_t>(count, c + std::size_t{1});
  std::vector<double> curvature(count, 0.0);  // 2πχ per component

  // Convex: K = 1/r². A patch whose atom faces several components gives each its part.
  const std::vector<std::vector<ConvexPart>> others = convexPartsOfOtherComponents(p);
  for (std::size_t k = 0; k < p.convex.size(); ++k) {
    const double r2 = p.convex.radius[k] * p.convex.radius[k];
    double own = p.convex.area[k];
    for (const ConvexPart& part : others[k]) {
      own -= part.area;
      if (part.component >= curvature.size()) curvature.resize(part.component + std::size_t{1}, 0.0);
      curvature[part.component] += part.area / r2;
    }
    curvature[p.convex.component[k]] += own / r2;
  }

  std::vector<Corner> corners;
  // Torus: K dA = −cos θ dθ dφ (ORACLES A.3: dA = rp(R − rp cos θ) dθ dφ, K = −cos θ /
  // (rp(R − rp cos θ))), over its SES intervals of θ. A spindle torus ends in a cusp on the
  // axis at each kept end: a cone point of intrinsic angle Φ·sin θc (a full ring's alone; a
  // partial one's also a corner of the concave patches at its ends).
  for (std::size_t t = 0; t < p.tori.size(); ++t) {
    const double R = p.tori.bigRadius[t], phi = p.tori.phiExtent[t];
    const double a = p.tori.thetaI[t], b = p.tori.thetaJ[t];
    double total = 0.0;
    if (R >= rp) {
      total = -phi * (std::sin(b) - std::sin(a));
    } else {
      const double thetaC = std::acos(R / rp), sinC = std::sin(thetaC);
      const glm::dvec3 toCusp = rp * sinC * p.tori.axis[t];
      if (a < -thetaC) {
        total += -phi * (std::sin(std::min(b, -thetaC)) - std::sin(a));
        corners.push_back({p.tori.center[t] - toCusp, phi * sinC, p.tori.component[t], Corner::Cusp, glm::dvec3(0.0)});
      }
      if (b > thetaC) {
        total += -phi * (std::sin(b) - std::sin(std::max(a, thetaC)));
        corners.push_back({p.tori.center[t] + toCusp, phi * sinC, p.tori.component[t], Corner::Cusp, glm::dvec3(0.0)});
      }
    }
    curvature[p.tori.component[t]] += total;
  }

  // Concave: K = 1/rp², plus creases and their corners.
  std::vector<double> concave(p.concave.size());
  struct Local {
    std::vector<Cap> caps;
    SphericalRegionScratch scratch;
    std::vector<Corner> corners;
  };
  tbb::enumerable_thread_specific<Local> tls;
  tbb::parallel_for(std::size_t{0}, p.concave.size(), [&](std::size_t c) {
    Local& l = tls.local();
    concave[c] = concaveCurvature(p, c, l.caps, l.scratch, l.corners);
  });
  for (std::size_t c = 0; c < p.concave.size(); ++c) curvature[p.concave.component[c]] += concave[c];
  for (const Local& l : tls) corners.insert(corners.end(), l.corners.begin(), l.corners.end());

  // Singular vertices: the corners at one point (to kSamePoint) are all the faces around it,
  // and its defect is 2π less their interior angles. Sorted first, so that the sum does not
  // depend on which thread found which corner.
  constexpr double kSamePoint = 1e-5;  // Å
  std::sort(corners.begin(), corners.end(), [](const Corner& x, const Corner& y) {
    return std::tie(x.at.x, x.at.y, x.at.z, x.angle) < std::tie(y.at.x, y.at.y, y.at.z, y.angle);
  });
  std::vector<char> taken(corners.size(), 0), unresolved(curvature.size(), 0);
  for (std::size_t k = 0; k < corners.size(); ++k) {
    if (taken[k]) continue;
    double defect = kTwoPi;
    std::size_t end = k, edges = 0, cusps = 0;
    for (std::size_t m = k; m < corners.size() && corners[m].at.x <= corners[k].at.x + kSamePoint; ++m) {
      if (taken[m] || glm::distance(corners[m].at, corners[k].at) > kSamePoint) continue;
      taken[m] = 2, end = m, defect -= corners[m].angle;
      edges += corners[m].kind == Corner::Edge;
      cusps += corners[m].kind == Corner::Cusp;
    }
    // A crease that reaches a torus edge away from a cusp is a concave patch meeting a torus
    // it overlaps, which the patch list does not clip: unless the edge is one between two
    // triangles of one probe sphere (cospherical atoms), where the crease just crosses it and
    // both sides have the corner.
    if (cusps == 0 && edges > 0)
      for (std::size_t m = k; m <= end; ++m) {
        if (taken[m] != 2 || corners[m].kind != Corner::Edge) continue;
        std::size_t sameProbe = 0;
        for (std::size_t q = k; q <= end; ++q)
          sameProbe += taken[q] == 2 && corners[q].kind == Corner::Edge && glm::distance(corners[q].probe, corners[m].probe) <= kSamePoint;
        if (sameProbe % 2 == 1) unresolved[corners[k].component] = 1;
      }
    for (std::size_t m = k; m <= end; ++m) taken[m] = taken[m] != 0;
    curvature[corners[k].component] += defect;
  }

  std::vector<ComponentTopology> out(curvature.size());
  for (std::size_t c = 0; c < curvature.size(); ++c) {
    const double chi = curvature[c] / kTwoPi;
    out[c].euler = std::llround(chi);
    out[c].genus = (2 - out[c].euler) / 2;
    out[c].residual = std::abs(chi - static_cast<double>(out[c].euler));
    out[c].resolved = !unresolved[c] && out[c].residual < kIntegerTolerance && out[c].euler % 2 == 0;
  }
  return out;
}

}  // namespace surftrace::build

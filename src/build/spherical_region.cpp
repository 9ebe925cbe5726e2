// Sphere minus caps: exposed arcs by interval sweeps, area by Gauss–Bonnet.
#include "build/spherical_region.hpp"

#include <algorithm>
#include <cmath>
#include <limits>
#include <numbers>

#include <glm/geometric.hpp>

#include "build/core/vector_math.hpp"

namespace surftrace::build {
namespace {

constexpr double kTwoPi = 2.0 * std::numbers::pi;

int findRoot(std::vector<int>& parent, int x) {
  while (parent[static_cast<std::size_t>(x)] != x) {
    parent[static_cast<std::size_t>(x)] = parent[static_cast<std::size_t>(parent[static_cast<std::size_t>(x)])];
    x = parent[static_cast<std::size_t>(x)];
  }
  return x;
}

// An arc shorter than this (in φ) is where three or more circles cross at one point, up
// to rounding: it bounds nothing, and its corners would only add a spurious turn.
constexpr double kTinyArc = 1e-12;

// The signed turning angle at u from direction tIn to tOut (both tangent at u),
// counter-clockwise about u positive.
double turningAngle(const glm::dvec3& tIn, const glm::dvec3& tOut, const glm::dvec3& u) {
  return std::atan2(glm::dot(glm::cross(tIn, tOut), u), glm::dot(tIn, tOut));
}

}  // namespace

SphericalRegion sphereMinusCaps(const std::vector<Cap>& input, SphericalRegionScratch& s) {
  // Drop empty caps and exact duplicates (a duplicate's circle would count twice).
  auto& caps = s.caps;
  caps.clear();
  s.arcs.clear();
  s.fullCircles.clear();
  for (const Cap& c : input) {
    if (c.cosRadius <= -1.0) return {0.0, glm::dvec3(0.0), 0};
    if (c.cosRadius >= 1.0) continue;
    const bool duplicate = std::any_of(caps.begin(), caps.end(), [&](const Cap& o) {
      return o.axis == c.axis && o.cosRadius == c.cosRadius;
    });
    if (!duplicate) caps.push_back(c);
  }
  if (caps.empty()) return {4.0 * std::numbers::pi, glm::dvec3(0.0), 0};

  double turning = 0.0;  // Σ (geodesic-curvature term) − Σ exterior angles
  glm::dvec3 vectorArea(0.0);
  int fullCircles = 0;
  double maxCapArea = 0.0;

  const int n = static_cast<int>(caps.size());
  for (int a = 0; a < n; ++a) {
    const Cap& ca = caps[static_cast<std::size_t>(a)];
    maxCapArea = std::max(maxCapArea, kTwoPi * (1.0 - ca.cosRadius));
    const double cosA = ca.cosRadius, sinA = std::sqrt(1.0 - cosA * cosA);
    const glm::dvec3 e1 = perpendicularTo(ca.axis), e2 = glm::cross(ca.axis, e1);
    auto pointAt = [&](double phi) { return cosA * ca.axis + sinA * (std::cos(phi) * e1 + std::sin(phi) * e2); };

    // Buried intervals: u(φ) is inside cap b iff M cos(φ − ψ) > Q.
    s.intervals.clear();
    bool buried = false;
    for (int b = 0; b < n && !buried; ++b) {
      if (b == a) continue;
      const Cap& cb = caps[static_cast<std::size_t>(b)];
      const double be1 = glm::dot(cb.axis, e1), be2 = glm::dot(cb.axis, e2);
      const double M = sinA * std::hypot(be1, be2);
      const double Q = cb.cosRadius - cosA * glm::dot(cb.axis, ca.axis);
      if (M <= std::abs(Q)) {
        buried = Q < 0.0;  // inside everywhere (Q ≤ −M); Q ≥ M never inside
        continue;
      }
      const double psi = std::atan2(be2, be1);
      const double half = std::acos(Q / M);
      double begin = std::fmod(psi - half, kTwoPi);
      if (begin < 0.0) begin += kTwoPi;
      s.intervals.push_back({begin, begin + 2.0 * half, b});
    }
    if (buried) continue;

    // The region lies outside the cap, so its boundary runs with decreasing φ about the
    // axis; with the region on the left, an arc φ0→φ1 adds −½[...] to W (ORACLES D.2).
    auto addArc = [&](double phi0, double phi1) {
      turning += cosA * (phi1 - phi0);
      vectorArea -= 0.5 * (sinA * sinA * (phi1 - phi0) * ca.axis -
                           cosA * sinA * ((std::sin(phi1) - std::sin(phi0)) * e1 + (std::cos(phi0) - std::cos(phi1)) * e2));
    };
    if (s.intervals.empty()) {
      addArc(0.0, kTwoPi);
      ++fullCircles;
      s.fullCircles.push_back(a);
      continue;
    }
    std::sort(s.intervals.begin(), s.intervals.end(),
              [](const auto& x, const auto& y) { return x.begin < y.begin || (x.begin == y.begin && x.cap < y.cap); });
    // Sweep one lap from the smallest begin; intervals that run past 2π already cover the
    // start of that lap.
    const auto& first = s.intervals.front();
    double reach = first.end;
    for (const auto& iv : s.intervals) reach = std::max(reach, iv.end - kTwoPi);
    auto emitGap = [&](double g0, double g1) {
      if (!(g1 - g0 > kTinyArc)) return;
      addArc(g0, g1);
      s.arcs.push_back({pointAt(g0), pointAt(g1), a});
    };
    for (std::size_t k = 1; k < s.intervals.size(); ++k) {
      const auto& iv = s.intervals[k];
      if (iv.begin > reach) emitGap(reach, iv.begin);
      reach = std::max(reach, iv.end);
    }
    if (reach < first.begin + kTwoPi) emitGap(reach, first.begin + kTwoPi);
  }

  // Boundary cycles: each arc (run with increasing φ, the region on its right) continues
  // with the arc that starts where it ends. Matched by position, not by which caps cross
  // there: where three circles meet at one point, rounding decides which cap an arc
  // "enters", and the arc of the third circle there has no length (dropped above). The
  // corner's turn is measured between the two arcs that actually meet, signed.
  const std::size_t arcs = s.arcs.size();
  s.parent.resize(arcs);
  for (std::size_t k = 0; k < arcs; ++k) s.parent[k] = static_cast<int>(k);
  for (std::size_t e = 0; e < arcs; ++e) {
    const auto& in = s.arcs[e];
    std::size_t next = 0;
    double nearest = std::numeric_limits<double>::infinity();
    for (std::size_t k = 0; k < arcs; ++k) {
      const glm::dvec3 gap = s.arcs[k].begin - in.end;
      const double d2 = glm::dot(gap, gap);
      if (d2 < nearest) nearest = d2, next = k;
    }
    const auto& out = s.arcs[next];
    const glm::dvec3& axisIn = caps[static_cast<std::size_t>(in.cap)].axis;
    const glm::dvec3& axisOut = caps[static_cast<std::size_t>(out.cap)].axis;
    turning += turningAngle(glm::cross(axisIn, in.end), glm::cross(axisOut, in.end), in.end);
    s.parent[static_cast<std::size_t>(findRoot(s.parent, static_cast<int>(e)))] = findRoot(s.parent, static_cast<int>(next));
  }
  int cycles = fullCircles;
  for (std::size_t k = 0; k < arcs; ++k) cycles += findRoot(s.parent, static_cast<int>(k)) == static_cast<int>(k);

  if (cycles == 0) return {0.0, glm::dvec3(0.0), 0};  // every circle buried: the caps cover all

  // Gauss–Bonnet fixes the area modulo 4π (2πχ ≡ −2π·cycles). The area is at most 4π
  // minus the largest cap, so a value above that is a tiny area that wrapped around.
  double area = std::fmod(turning - kTwoPi * cycles, 2.0 * kTwoPi);
  if (area < 0.0) area += 2.0 * kTwoPi;
  if (area > 2.0 * kTwoPi - 0.5 * maxCapArea) area -= 2.0 * kTwoPi;
  // |W| <= area for any region (|u| = 1). A region that Gauss–Bonnet finds empty to rounding,
  // such as the sliver between two coincident circles (a mixed cell of zero volume between
  // co-spherical simplices), has no vector area, whether or not its arcs pair up.
  if (area < 1e-12) return {std::max(area, 0.0), glm::dvec3(0.0), cycles};
  return {area, vectorArea, cycles};
}

}  // namespace surftrace::build

// Sphere minus caps: exposed arcs by interval sweeps, area by Gauss–Bonnet.
#include "build/spherical_region.hpp"

#include <algorithm>
#include <cmath>
#include <numbers>

#include <glm/geometric.hpp>

#include "build/sas_geometry.hpp"

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

// Which of the (at most two) crossing points of circles a and b a point u is: the sign of
// det(axis_lo, axis_hi, u) with the caps in index order, the same from either circle.
int crossingSide(const std::vector<Cap>& caps, int a, int b, const glm::dvec3& u) {
  const int lo = std::min(a, b), hi = std::max(a, b);
  const double det = glm::dot(glm::cross(caps[static_cast<std::size_t>(lo)].axis, caps[static_cast<std::size_t>(hi)].axis), u);
  return det >= 0.0 ? 1 : 0;
}

// Exterior angle of the region's boundary at u, between circles a and b: the angle between
// their axes projected into the tangent plane at u (ORACLES D.2).
double exteriorAngle(const glm::dvec3& axisA, const glm::dvec3& axisB, const glm::dvec3& u) {
  const glm::dvec3 ma = axisA - glm::dot(axisA, u) * u;
  const glm::dvec3 mb = axisB - glm::dot(axisB, u) * u;
  const double la = glm::length(ma), lb = glm::length(mb);
  if (la == 0.0 || lb == 0.0) return 0.0;
  return std::acos(std::clamp(glm::dot(ma, mb) / (la * lb), -1.0, 1.0));
}

}  // namespace

SphericalRegion sphereMinusCaps(const std::vector<Cap>& input, SphericalRegionScratch& s) {
  // Drop empty caps and exact duplicates (a duplicate's circle would count twice).
  auto& caps = s.caps;
  caps.clear();
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
  s.starts.clear();
  s.ends.clear();

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
      continue;
    }
    std::sort(s.intervals.begin(), s.intervals.end(),
              [](const auto& x, const auto& y) { return x.begin < y.begin || (x.begin == y.begin && x.cap < y.cap); });
    // Sweep one lap from the smallest begin; intervals that run past 2π already cover the
    // start of that lap.
    const auto& first = s.intervals.front();
    double reach = first.end;
    int reachCap = first.cap;
    for (const auto& iv : s.intervals)
      if (iv.end - kTwoPi > reach) reach = iv.end - kTwoPi, reachCap = iv.cap;
    auto emitGap = [&](double g0, int leftCap, double g1, int enteredCap) {
      if (!(g1 > g0)) return;
      addArc(g0, g1);
      const glm::dvec3 u0 = pointAt(g0), u1 = pointAt(g1);
      turning -= exteriorAngle(ca.axis, caps[static_cast<std::size_t>(enteredCap)].axis, u1);
      s.starts.push_back({a, leftCap, crossingSide(caps, a, leftCap, u0)});
      s.ends.push_back({a, enteredCap, crossingSide(caps, a, enteredCap, u1)});
    };
    for (std::size_t k = 1; k < s.intervals.size(); ++k) {
      const auto& iv = s.intervals[k];
      if (iv.begin > reach) emitGap(reach, reachCap, iv.begin, iv.cap);
      if (iv.end > reach) reach = iv.end, reachCap = iv.cap;
    }
    if (reach < first.begin + kTwoPi) emitGap(reach, reachCap, first.begin + kTwoPi, first.cap);
  }

  // Boundary cycles: the arc of circle a that ends entering cap b continues on circle b,
  // leaving cap a, at the same crossing point.
  const std::size_t arcs = s.starts.size();
  s.parent.resize(arcs);
  for (std::size_t k = 0; k < arcs; ++k) s.parent[k] = static_cast<int>(k);
  for (std::size_t e = 0; e < arcs; ++e) {
    const auto& end = s.ends[e];
    for (std::size_t st = 0; st < arcs; ++st) {
      const auto& start = s.starts[st];
      if (start.capA == end.capB && start.capB == end.capA && start.side == end.side) {
        s.parent[static_cast<std::size_t>(findRoot(s.parent, static_cast<int>(e)))] = findRoot(s.parent, static_cast<int>(st));
        break;
      }
    }
  }
  int cycles = fullCircles;
  for (std::size_t k = 0; k < arcs; ++k) cycles += findRoot(s.parent, static_cast<int>(k)) == static_cast<int>(k);

  if (cycles == 0) return {0.0, glm::dvec3(0.0), 0};  // every circle buried: the caps cover all

  // Gauss–Bonnet fixes the area modulo 4π (2πχ ≡ −2π·cycles). The area is at most 4π
  // minus the largest cap, so a value above that is a tiny area that wrapped around.
  double area = std::fmod(turning - kTwoPi * cycles, 2.0 * kTwoPi);
  if (area < 0.0) area += 2.0 * kTwoPi;
  if (area > 2.0 * kTwoPi - 0.5 * maxCapArea) area -= 2.0 * kTwoPi;
  return {std::max(area, 0.0), vectorArea, cycles};
}

}  // namespace surftrace::build

// Areas and volumes: convex patches carry theirs from the build; tori and concave
// triangles are integrated here from their own parameters.
#include "build/ses/surface_area.hpp"

#include <algorithm>
#include <cmath>
#include <limits>
#include <numbers>
#include <span>
#include <vector>

#include <tbb/parallel_for.h>

#include <glm/geometric.hpp>
#include <tbb/enumerable_thread_specific.h>
#include <tbb/parallel_reduce.h>

#include "build/spherical_region.hpp"

namespace surftrace::build {
namespace {

// The parts of [θi, θj] on the SES: all of it for a ring torus; |θ| >= θc for a spindle.
template <class F> void forEachSesInterval(double R, double rp, double thetaI, double thetaJ, F&& f) {
  if (R >= rp) {
    f(thetaI, thetaJ);
    return;
  }
  const double thetaC = std::acos(R / rp);
  if (thetaI < -thetaC) f(thetaI, std::min(thetaJ, -thetaC));
  if (thetaJ > thetaC) f(std::max(thetaI, thetaC), thetaJ);
}

// ∫ x·n dA of a torus patch (ORACLES D.2), outward SES normal.
double torusFlux(const PatchList& p, std::size_t t) {
  const auto& tr = p.tori;
  const double R = tr.bigRadius[t], rp = p.params.probeRadius, dphi = tr.phiExtent[t];
  const glm::dvec3 n = tr.axis[t], e1 = tr.e1[t], e2 = glm::cross(n, e1);
  const glm::dvec3 E = std::sin(dphi) * e1 + (1.0 - std::cos(dphi)) * e2;
  double local = 0.0;
  glm::dvec3 normalIntegral(0.0);
  forEachSesInterval(R, rp, tr.thetaI[t], tr.thetaJ[t], [&](double a, double b) {
    auto F = [&](double th) { return (R * R + rp * rp) * std::sin(th) - R * rp * (1.5 * th + 0.25 * std::sin(2 * th)); };
    auto G = [&](double th) { return R * std::sin(th) - rp * (0.5 * th + 0.25 * std::sin(2 * th)); };
    auto H = [&](double th) { return -R * std::cos(th) - 0.5 * rp * std::sin(th) * std::sin(th); };
    local += dphi * rp * (F(b) - F(a));
    normalIntegral += rp * (E * (G(b) - G(a)) - n * dphi * (H(b) - H(a)));
  });
  return local + glm::dot(tr.center[t], normalIntegral);
}

// ∫ x dA of a torus patch: x = c + ρ e_ρ(φ) + rp sin θ n with ρ = R − rp cos θ and
// dA = rp ρ dθ dφ (ORACLES A.3), integrated in closed form over each SES interval of θ.
glm::dvec3 torusAreaMoment(const PatchList& p, std::size_t t, double area) {
  const auto& tr = p.tori;
  const double R = tr.bigRadius[t], rp = p.params.probeRadius, dphi = tr.phiExtent[t];
  const glm::dvec3 n = tr.axis[t], e1 = tr.e1[t], e2 = glm::cross(n, e1);
  const glm::dvec3 E = std::sin(dphi) * e1 + (1.0 - std::cos(dphi)) * e2;  // ∫ e_ρ dφ
  glm::dvec3 moment = tr.center[t] * area;
  forEachSesInterval(R, rp, tr.thetaI[t], tr.thetaJ[t], [&](double a, double b) {
    auto rho2 = [&](double th) { return R * R * th - 2.0 * R * rp * std::sin(th) + rp * rp * (0.5 * th + 0.25 * std::sin(2 * th)); };
    auto rhoSin = [&](double th) { return rp * (-R * std::cos(th) - 0.5 * rp * std::sin(th) * std::sin(th)); };
    moment += rp * (rho2(b) - rho2(a)) * E + n * (rp * dphi * (rhoSin(b) - rhoSin(a)));
  });
  return moment;
}

}  // namespace

std::vector<Cap>& concaveCaps(const PatchList& p, std::size_t c, std::vector<Cap>& caps) {
  const auto& cv = p.concave;
  const double rp = p.params.probeRadius;
  caps.clear();
  const glm::dvec3 u[3] = {cv.dirI[c], cv.dirJ[c], cv.dirK[c]};
  for (int e = 0; e < 3; ++e) {
    glm::dvec3 g = glm::cross(u[e], u[(e + 1) % 3]);
    if (glm::dot(g, u[(e + 2) % 3]) < 0.0) g = -g;
    const double len = glm::length(g);
    if (len > 0.0) caps.push_back({-g / len, 0.0});
  }
  for (std::uint32_t k = 0; k < cv.clipCount[c]; ++k) {
    const Plane& pl = p.clipPlanes[cv.clipBegin[c] + k];
    const glm::dvec3 nrm(pl);
    caps.push_back({nrm, -(glm::dot(nrm, cv.probe[c]) + pl.w) / rp});
  }
  return caps;
}

namespace {

// One exposed arc of a convex patch's boundary on its atom's unit sphere: the contact
// circle u(φ) = α·a + β(cos φ e1 + sin φ e2) of a torus, run with the atom's region on its
// left (ORACLES D.2): decreasing φ about a = axis for the torus's atom i, increasing for j.
struct BoundaryArc {
  glm::dvec3 a, e1, e2;
  double alpha, beta, phiStart, phiEnd;
  double toOther;  // +1 when a points from the atom to the circle's other atom, else −1
  bool closed;     // a whole circle (a free circle of two atoms)
  glm::dvec3 at(double phi) const { return alpha * a + beta * (std::cos(phi) * e1 + std::sin(phi) * e2); }
  glm::dvec3 tangent(double phi) const {
    const double sign = phiEnd > phiStart ? 1.0 : -1.0;
    return sign * (-std::sin(phi) * e1 + std::cos(phi) * e2);
  }
};

// The part of a convex patch bounded by `arcs` (a union of the patch's faces): its area on
// the unit sphere by Gauss–Bonnet modulo 4π (as the builder resolves it) and its vector
// area by Stokes, W = ½∮ u × du, which is exact.
struct RegionPart {
  double area = 0.0;
  glm::dvec3 vectorArea{0.0};
};
RegionPart boundedRegion(std::span<const BoundaryArc> arcs) {
  constexpr double kTwoPi = 2.0 * std::numbers::pi;
  RegionPart part;
  double turning = 0.0, maxCap = 0.0;
  std::size_t cycles = 0;
  std::vector<int> next(arcs.size(), -1);
  std::vector<char> seen(arcs.size(), 0);
  for (std::size_t k = 0; k < arcs.size(); ++k) {
    const BoundaryArc& c = arcs[k];
    const double p0 = c.phiStart, p1 = c.phiEnd;
    part.vectorArea += 0.5 * (c.alpha * c.beta * (c.e2 * (std::cos(p1) - std::cos(p0)) - c.e1 * (std::sin(p1) - std::sin(p0))) +
                              c.beta * c.beta * (p1 - p0) * c.a);
    const double cosA = c.toOther * c.alpha;  // the cap's angular radius, about atom → other
    turning += cosA * std::abs(p1 - p0);
    maxCap = std::max(maxCap, kTwoPi * (1.0 - cosA));
    if (c.closed) continue;
    const glm::dvec3 end = c.at(p1);
    double best = std::numeric_limits<double>::infinity();
    for (std::size_t m = 0; m < arcs.size(); ++m) {
      if (arcs[m].closed) continue;
      const double d = glm::distance(end, arcs[m].at(arcs[m].phiStart));
      if (d < best) best = d, next[k] = static_cast<int>(m);
    }
    const BoundaryArc& o = arcs[static_cast<std::size_t>(next[k])];
    const glm::dvec3 tIn = c.tangent(p1), tOut = o.tangent(o.phiStart);
    turning -= std::atan2(glm::dot(end, glm::cross(tIn, tOut)), glm::dot(tIn, tOut));
  }
  for (std::size_t k = 0; k < arcs.size(); ++k) {
    if (seen[k]) continue;
    ++cycles;
    for (int m = static_cast<int>(k); m >= 0 && !seen[static_cast<std::size_t>(m)]; m = next[static_cast<std::size_t>(m)])
      seen[static_cast<std::size_t>(m)] = 1;
  }
  double area = std::fmod(turning - kTwoPi * static_cast<double>(cycles), 2.0 * kTwoPi);
  if (area < 0.0) area += 2.0 * kTwoPi;
  if (area > 2.0 * kTwoPi - 0.5 * maxCap) area -= 2.0 * kTwoPi;
  part.area = std::max(area, 0.0);
  return part;
}

}  // namespace

double torusPatchArea(double R, double rp, double thetaI, double thetaJ, double phiExtent) {
  double area = 0.0;
  forEachSesInterval(R, rp, thetaI, thetaJ, [&](double a, double b) {
    area += phiExtent * rp * (R * (b - a) - rp * (std::sin(b) - std::sin(a)));
  });
  return area;
}

std::vector<std::vector<ConvexPart>> convexPartsOfOtherComponents(const PatchList& p) {
  const double rp = p.params.probeRadius;
  std::vector<std::vector<ConvexPart>> parts(p.convex.size());
  // Atom → tori, a counting sort.
  std::vector<std::uint32_t> toriBegin(p.params.atomCount + 2, 0), toriOf;
  for (std::size_t t = 0; t < p.tori.size(); ++t) ++toriBegin[p.tori.atomI[t] + 2], ++toriBegin[p.tori.atomJ[t] + 2];
  for (std::size_t i = 0; i < p.params.atomCount; ++i) toriBegin[i + 2] += toriBegin[i + 1];
  toriOf.resize(toriBegin[p.params.atomCount + 1]);
  for (std::size_t t = 0; t < p.tori.size(); ++t)
    for (const std::uint32_t x : {p.tori.atomI[t], p.tori.atomJ[t]}) toriOf[toriBegin[x + 1]++] = static_cast<std::uint32_t>(t);
  std::vector<BoundaryArc> arcs;
  for (std::size_t k = 0; k < p.convex.size(); ++k) {
    const double r = p.convex.radius[k], Rs = r + rp;
    const std::uint32_t x = p.convex.atom[k], label = p.convex.component[k];
    const glm::dvec3 c = p.convex.center[k];
    for (std::uint32_t m = toriBegin[x]; m < toriBegin[x + 1]; ++m) {
      const std::uint32_t other = p.tori.component[toriOf[m]];
      if (other == label) continue;
      bool done = false;  // this component's part already taken at an earlier torus
      for (std::uint32_t e = toriBegin[x]; e < m && !done; ++e) done = p.tori.component[toriOf[e]] == other;
      if (done) continue;
      arcs.clear();
      for (std::uint32_t e = m; e < toriBegin[x + 1]; ++e) {
        const std::uint32_t t = toriOf[e];
        if (p.tori.component[t] != other) continue;
        const bool first = p.tori.atomI[t] == x;
        const glm::dvec3 e1 = p.tori.e1[t], e2 = glm::cross(p.tori.axis[t], e1);
        const double ext = p.tori.phiExtent[t];
        const bool closed = ext >= 2.0 * std::numbers::pi;
        // u(φ) in the torus's frame (e1, axis × e1); the region is on the left.
        BoundaryArc arc{p.tori.axis[t], e1, e2, glm::dot(p.tori.center[t] - c, p.tori.axis[t]) / Rs, p.tori.bigRadius[t] / Rs,
                        first ? ext : 0.0, first ? 0.0 : ext, first ? 1.0 : -1.0, closed};
        arcs.push_back(arc);
      }
      const RegionPart part = boundedRegion(arcs);
      parts[k].push_back({other, r * r * part.area, part.vectorArea});
    }
  }
  return parts;
}

SurfaceAreas computeAreas(const PatchList& p) {
  const double rp = p.params.probeRadius;
  SurfaceAreas s;
  s.sasPerAtom.assign(p.params.atomCount, 0.0);
  s.sesPerAtom.assign(p.params.atomCount, 0.0);
  s.components.resize(std::max<std::size_t>(1, p.componentCount));
  auto addToComponent = [&s](std::uint32_t label, double area, double flux, const glm::dvec3& moment) {
    if (label >= s.components.size()) s.components.resize(label + 1);
    s.components[label].area += area;
    s.components[label].volume += flux / 3.0;
    s.components[label].areaMoment += moment;
  };

  // A convex patch whose atom faces several components (a one-atom wall between the
  // outside and a cavity) carries one label; its parts bounded by the tori of each other
  // component go to that component.
  const std::vector<std::vector<ConvexPart>> others = convexPartsOfOtherComponents(p);
  for (std::size_t k = 0; k < p.convex.size(); ++k) {
    const double r = p.convex.radius[k], Rs = r + rp, a = p.convex.area[k];
    const std::uint32_t x = p.convex.atom[k], label = p.convex.component[k];
    const double sas = a * (Rs * Rs) / (r * r);
    s.sas += sas;
    s.sesConvex += a;
    s.sasPerAtom[x] += sas;
    s.sesPerAtom[x] += a;
    // Convex sphere, σ = +1: ∫ x·n dA = ρ² c·W + ρ A.
    const glm::dvec3 c = p.convex.center[k];
    auto flux = [&](double area, const glm::dvec3& w) { return r * r * glm::dot(c, w) + r * area; };
    // ∫ x dA = ∫ (c + r u) r² dΩ = c A + r³ W.
    auto moment = [&](double area, const glm::dvec3& w) { return c * area + (r * r * r) * w; };
    double ownArea = a;
    glm::dvec3 ownW = p.convex.vectorArea[k];
    for (const ConvexPart& part : others[k]) {
      ownArea -= part.area;
      ownW -= part.vectorArea;
      addToComponent(part.component, part.area, flux(part.area, part.vectorArea), moment(part.area, part.vectorArea));
    }
    s.sesVolume += flux(a, p.convex.vectorArea[k]);
    addToComponent(label, ownArea, flux(ownArea, ownW), moment(ownArea, ownW));
  }
  for (std::size_t t = 0; t < p.tori.size(); ++t) {
    const double a = torusPatchArea(p.tori.bigRadius[t], rp, p.tori.thetaI[t], p.tori.thetaJ[t], p.tori.phiExtent[t]);
    s.sesToroidal += a;
    s.sesPerAtom[p.tori.atomI[t]] += 0.5 * a;
    s.sesPerAtom[p.tori.atomJ[t]] += 0.5 * a;
    const double flux = torusFlux(p, t);
    s.sesVolume += flux;
    addToComponent(p.tori.component[t], a, flux, torusAreaMoment(p, t, a));
  }
  // Concave patches are many and independent: sum them in parallel, deterministically
  // (per-patch values first, then an ordered sum).
  std::vector<double> concaveArea(p.concave.size()), concaveFlux(p.concave.size());
  std::vector<glm::dvec3> concaveMoment(p.concave.size());
  tbb::enumerable_thread_specific<std::pair<std::vector<Cap>, SphericalRegionScratch>> tls;
  tbb::parallel_for(std::size_t{0}, p.concave.size(), [&](std::size_t c) {
    auto& [caps, scratch] = tls.local();
    const SphericalRegion region = sphereMinusCaps(concaveCaps(p, c, caps), scratch);
    concaveArea[c] = rp * rp * region.area;
    // Concave sphere, σ = −1: ∫ x·n dA = −(ρ² c·W + ρ A).
    concaveFlux[c] = -(rp * rp * glm::dot(p.concave.probe[c], region.vectorArea) + rp * concaveArea[c]);
    concaveMoment[c] = p.concave.probe[c] * concaveArea[c] + (rp * rp * rp) * region.vectorArea;
  });
  for (std::size_t c = 0; c < p.concave.size(); ++c) {
    s.sesConcave += concaveArea[c];
    s.sesVolume += concaveFlux[c];
    addToComponent(p.concave.component[c], concaveArea[c], concaveFlux[c], concaveMoment[c]);
    for (const std::uint32_t atom : {p.concave.atomI[c], p.concave.atomJ[c], p.concave.atomK[c]})
      s.sesPerAtom[atom] += concaveArea[c] / 3.0;
  }
  s.sesVolume /= 3.0;
  return s;
}

}  // namespace surftrace::build

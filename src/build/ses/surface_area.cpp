// Areas and volumes: convex patches carry theirs from the build; tori and concave
// triangles are integrated here from their own parameters.
#include "build/ses/surface_area.hpp"

#include <algorithm>
#include <cmath>
#include <numbers>

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

// The concave patch as the probe sphere minus caps: three hemispheres beyond its edges
// and one cap per clipping plane.
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

}  // namespace

double torusPatchArea(double R, double rp, double thetaI, double thetaJ, double phiExtent) {
  double area = 0.0;
  forEachSesInterval(R, rp, thetaI, thetaJ, [&](double a, double b) {
    area += phiExtent * rp * (R * (b - a) - rp * (std::sin(b) - std::sin(a)));
  });
  return area;
}

SurfaceAreas computeAreas(const PatchList& p) {
  const double rp = p.params.probeRadius;
  SurfaceAreas s;
  s.sasPerAtom.assign(p.params.atomCount, 0.0);
  s.sesPerAtom.assign(p.params.atomCount, 0.0);
  s.components.resize(std::max<std::size_t>(1, p.componentCount));
  auto addToComponent = [&s](std::uint32_t label, double area, double flux) {
    if (label >= s.components.size()) s.components.resize(label + 1);
    s.components[label].area += area;
    s.components[label].volume += flux / 3.0;
  };

  for (std::size_t k = 0; k < p.convex.size(); ++k) {
    const double r = p.convex.radius[k], Rs = r + rp, a = p.convex.area[k];
    const double sas = a * (Rs * Rs) / (r * r);
    s.sas += sas;
    s.sesConvex += a;
    s.sasPerAtom[p.convex.atom[k]] += sas;
    s.sesPerAtom[p.convex.atom[k]] += a;
    // Convex sphere, σ = +1: ∫ x·n dA = ρ² c·W + ρ A.
    const double flux = r * r * glm::dot(p.convex.center[k], p.convex.vectorArea[k]) + r * a;
    s.sesVolume += flux;
    addToComponent(p.convex.component[k], a, flux);
  }
  for (std::size_t t = 0; t < p.tori.size(); ++t) {
    const double a = torusPatchArea(p.tori.bigRadius[t], rp, p.tori.thetaI[t], p.tori.thetaJ[t], p.tori.phiExtent[t]);
    s.sesToroidal += a;
    s.sesPerAtom[p.tori.atomI[t]] += 0.5 * a;
    s.sesPerAtom[p.tori.atomJ[t]] += 0.5 * a;
    const double flux = torusFlux(p, t);
    s.sesVolume += flux;
    addToComponent(p.tori.component[t], a, flux);
  }
  // Concave patches are many and independent: sum them in parallel, deterministically
  // (per-patch values first, then an ordered sum).
  std::vector<double> concaveArea(p.concave.size()), concaveFlux(p.concave.size());
  tbb::enumerable_thread_specific<std::pair<std::vector<Cap>, SphericalRegionScratch>> tls;
  tbb::parallel_for(std::size_t{0}, p.concave.size(), [&](std::size_t c) {
    auto& [caps, scratch] = tls.local();
    const SphericalRegion region = sphereMinusCaps(concaveCaps(p, c, caps), scratch);
    concaveArea[c] = rp * rp * region.area;
    // Concave sphere, σ = −1: ∫ x·n dA = −(ρ² c·W + ρ A).
    concaveFlux[c] = -(rp * rp * glm::dot(p.concave.probe[c], region.vectorArea) + rp * concaveArea[c]);
  });
  for (std::size_t c = 0; c < p.concave.size(); ++c) {
    s.sesConcave += concaveArea[c];
    s.sesVolume += concaveFlux[c];
    addToComponent(p.concave.component[c], concaveArea[c], concaveFlux[c]);
    for (const std::uint32_t atom : {p.concave.atomI[c], p.concave.atomJ[c], p.concave.atomK[c]})
      s.sesPerAtom[atom] += concaveArea[c] / 3.0;
  }
  s.sesVolume /= 3.0;
  return s;
}

}  // namespace surftrace::build

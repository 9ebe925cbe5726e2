// The patch list as the GPU sees it: the compact std430/std140 records of Lindow et al. 2010, Sect. 5.3.
#include "gl/gpu_layout.hpp"

#include <algorithm>
#include <cmath>
#include <stdexcept>
#include <string>

#include <glm/geometric.hpp>

namespace surftrace::gl {
namespace {

// Clip-plane indices travel as floats (GpuConcave): every integer below 2²⁴ is exact.
constexpr std::size_t kMaxFloatIndex = std::size_t{1} << 24;

glm::vec4 shifted(const glm::dvec3& x, const glm::dvec3& origin, double w) {
  return glm::vec4(glm::vec3(x - origin), static_cast<float>(w));
}

}  // namespace

GpuPatches packPatches(const build::PatchList& list, const glm::dvec3& origin) {
  if (list.mss.size() != 0)
    throw std::invalid_argument("gl engine: molecular skin (MSS) patches are not drawn by the GL path yet; use --engine embree");
  if (list.clipPlanes.size() >= kMaxFloatIndex)
    throw std::invalid_argument("gl engine: " + std::to_string(list.clipPlanes.size()) +
                                " clipping planes exceed the 2^24 the GPU records index exactly");
  GpuPatches g;
  g.origin = origin;
  const double rp = list.params.probeRadius;

  // Bounding sphere of all patches (box centre, largest reach): sets the depth range only.
  glm::dvec3 lo(std::numeric_limits<double>::infinity()), hi(-std::numeric_limits<double>::infinity());
  auto extend = [&](const glm::dvec3& c, double r) {
    lo = glm::min(lo, c - r);
    hi = glm::max(hi, c + r);
  };

  const build::ConvexSpheres& cs = list.convex;
  g.spheres.reserve(cs.size());
  for (std::size_t i = 0; i < cs.size(); ++i) {
    g.spheres.push_back(shifted(cs.center[i], origin, cs.radius[i]));
    extend(cs.center[i], cs.radius[i]);
  }
  g.sphereAtoms = cs.atom;

  const build::Tori& t = list.tori;
  g.tori.reserve(t.size());
  g.torusAtoms.reserve(t.size());
  for (std::size_t i = 0; i < t.size(); ++i) {
    GpuTorus gt;
    gt.centerR = shifted(t.center[i], origin, t.bigRadius[i]);
    gt.axisRp = glm::vec4(glm::vec3(t.axis[i]), static_cast<float>(rp));
    gt.e1Phi = glm::vec4(glm::vec3(t.e1[i]), static_cast<float>(t.phiExtent[i]));
    gt.theta = glm::vec4(static_cast<float>(t.thetaI[i]), static_cast<float>(t.thetaJ[i]), 0.0f, 0.0f);
    g.tori.push_back(gt);
    g.torusAtoms.emplace_back(t.atomI[i], t.atomJ[i]);
    extend(t.center[i], t.bigRadius[i] + rp);
  }

  const build::ConcaveTriangles& c = list.concave;
  g.concave.reserve(c.size());
  g.concaveAtoms.reserve(c.size());
  for (std::size_t i = 0; i < c.size(); ++i) {
    GpuConcave gc;
    gc.probeRp = shifted(c.probe[i], origin, rp);
    gc.dirIBegin = glm::vec4(glm::vec3(c.dirI[i]), static_cast<float>(c.clipBegin[i]));
    gc.dirJCount = glm::vec4(glm::vec3(c.dirJ[i]), static_cast<float>(c.clipCount[i]));
    gc.dirK = glm::vec4(glm::vec3(c.dirK[i]), 0.0f);
    g.concave.push_back(gc);
    g.concaveAtoms.emplace_back(c.atomI[i], c.atomJ[i], c.atomK[i], 0u);
    extend(c.probe[i], rp);
  }

  // n·x + w <= 0 with x = x' + origin becomes n·x' + (w + n·origin) <= 0.
  g.clipPlanes.reserve(list.clipPlanes.size());
  for (const build::Plane& p : list.clipPlanes) {
    const glm::dvec3 n(p);
    g.clipPlanes.emplace_back(glm::vec3(n), static_cast<float>(p.w + glm::dot(n, origin)));
  }

  if (lo.x <= hi.x) {
    g.boundsCenter = 0.5 * (lo + hi);
    g.boundsRadius = 0.5 * glm::length(hi - lo);
  }
  return g;
}

}  // namespace surftrace::gl

// The patch kinds of the GL renderer, one row each: GPU record, atoms, shader file; and the upload of a patch list.
#include "gl/gpu_kinds.hpp"

#include <algorithm>
#include <bit>
#include <cmath>
#include <limits>
#include <stdexcept>
#include <string>
#include <type_traits>

#include <glm/common.hpp>
#include <glm/geometric.hpp>

namespace surftrace::gl {
namespace {

// Clip-plane indices travel as floats (GpuConcave): every integer below 2²⁴ is exact.
constexpr std::size_t kMaxFloatIndex = std::size_t{1} << 24;

glm::vec4 shifted(const glm::dvec3& x, const glm::dvec3& origin, double w) {
  return glm::vec4(glm::vec3(x - origin), static_cast<float>(w));
}

// GpuPatches::skinAtoms and skinGrid. Cells of edge twice the largest radius (a query reaches
// a few of them), widened while there are more than 8 cells an atom.
void packSkinAtoms(const build::PatchList& list, const glm::dvec3& origin, GpuPatches& g) {
  const build::SkinAtoms& atoms = list.skinAtoms;
  const std::size_t n = atoms.size();
  const double s = list.params.shrinkFactor;
  glm::dvec3 lo(0.0), hi(0.0);
  double rMax = 0.0;
  for (std::size_t i = 0; i < n; ++i) {
    const glm::dvec3 c = atoms.center[i] - origin;
    lo = i == 0 ? c : glm::min(lo, c);
    hi = i == 0 ? c : glm::max(hi, c);
    rMax = std::max(rMax, std::sqrt(s * atoms.weight[i]));
  }
  double edge = std::max(2.0 * rMax, 1e-3 * (1.0 + glm::length(hi - lo)));
  glm::uvec3 dims(1u);
  for (;;) {
    const glm::dvec3 cells = glm::floor((hi - lo) / edge) + 1.0;
    if (cells.x * cells.y * cells.z <= 8.0 * static_cast<double>(n) + 8.0) {
      dims = glm::uvec3(cells);
      break;
    }
    edge *= 1.25;
  }
  auto cellOf = [&](std::size_t i) {
    const glm::uvec3 c = glm::min(glm::uvec3(glm::max((atoms.center[i] - origin - lo) / edge, 0.0)), dims - 1u);
    return (c.z * dims.y + c.y) * dims.x + c.x;
  };
  const std::size_t cellCount = n == 0 ? 0 : std::size_t{dims.x} * dims.y * dims.z;
  g.skinGrid.assign(cellCount + 1 + n, 0u);
  for (std::size_t i = 0; i < n; ++i) ++g.skinGrid[cellOf(i) + 1];
  for (std::size_t c = 0; c < cellCount; ++c) g.skinGrid[c + 1] += g.skinGrid[c];
  std::vector<std::uint32_t> next(g.skinGrid.begin(), g.skinGrid.begin() + static_cast<std::ptrdiff_t>(cellCount));
  for (std::size_t i = 0; i < n; ++i) g.skinGrid[cellCount + 1 + next[cellOf(i)]++] = static_cast<std::uint32_t>(i);
  const glm::uvec4 head(static_cast<std::uint32_t>(n), dims.x, dims.y, dims.z);
  g.skinAtoms.reserve(3 + n);
  g.skinAtoms.emplace_back(std::bit_cast<float>(head.x), std::bit_cast<float>(head.y), std::bit_cast<float>(head.z),
                           std::bit_cast<float>(head.w));
  g.skinAtoms.emplace_back(glm::vec3(lo), static_cast<float>(edge));
  g.skinAtoms.emplace_back(static_cast<float>(rMax), 0.0f, 0.0f, 0.0f);
  for (std::size_t i = 0; i < n; ++i) g.skinAtoms.push_back(shifted(atoms.center[i], origin, s * atoms.weight[i]));
}

}  // namespace

GpuSphere GpuSphereKind::record(const build::PatchList& list, std::size_t i, const glm::dvec3& origin) {
  return shifted(list.convex.center[i], origin, list.convex.radius[i]);
}
std::uint32_t GpuSphereKind::atoms(const build::PatchList& list, std::size_t i) { return list.convex.atom[i]; }
std::pair<glm::dvec3, double> GpuSphereKind::reach(const build::PatchList& list, std::size_t i) {
  return {list.convex.center[i], list.convex.radius[i]};
}

GpuTorus GpuTorusKind::record(const build::PatchList& list, std::size_t i, const glm::dvec3& origin) {
  const build::Tori& t = list.tori;
  const double rp = list.params.probeRadius;
  GpuTorus gt;
  gt.centerR = shifted(t.center[i], origin, t.bigRadius[i]);
  gt.axisRp = glm::vec4(glm::vec3(t.axis[i]), static_cast<float>(rp));
  gt.e1Phi = glm::vec4(glm::vec3(t.e1[i]), static_cast<float>(t.phiExtent[i]));
  gt.theta = glm::vec4(static_cast<float>(t.thetaI[i]), static_cast<float>(t.thetaJ[i]), 0.0f, 0.0f);
  return gt;
}
glm::uvec2 GpuTorusKind::atoms(const build::PatchList& list, std::size_t i) {
  return {list.tori.atomI[i], list.tori.atomJ[i]};
}
std::pair<glm::dvec3, double> GpuTorusKind::reach(const build::PatchList& list, std::size_t i) {
  return {list.tori.center[i], list.tori.bigRadius[i] + list.params.probeRadius};
}

GpuConcave GpuConcaveKind::record(const build::PatchList& list, std::size_t i, const glm::dvec3& origin) {
  const build::ConcaveTriangles& c = list.concave;
  GpuConcave gc;
  gc.probeRp = shifted(c.probe[i], origin, list.params.probeRadius);
  gc.dirIBegin = glm::vec4(glm::vec3(c.dirI[i]), static_cast<float>(c.clipBegin[i]));
  gc.dirJCount = glm::vec4(glm::vec3(c.dirJ[i]), static_cast<float>(c.clipCount[i]));
  gc.dirK = glm::vec4(glm::vec3(c.dirK[i]), 0.0f);
  return gc;
}
glm::uvec4 GpuConcaveKind::atoms(const build::PatchList& list, std::size_t i) {
  return {list.concave.atomI[i], list.concave.atomJ[i], list.concave.atomK[i], 0u};
}
std::pair<glm::dvec3, double> GpuConcaveKind::reach(const build::PatchList& list, std::size_t i) {
  return {list.concave.probe[i], list.params.probeRadius};
}

template <build::MssKind K>
GpuSkin GpuSkinKind<K>::record(const build::PatchList& list, std::size_t i, const glm::dvec3& origin) {
  const build::MssQuadrics& q = list.mss;
  const std::size_t k = build::mssKindRange(q, K).first + i;
  GpuSkin g;
  g.centerBound = shifted(q.center[k], origin, q.boundRadius[k]);
  g.axisConstant = glm::vec4(glm::vec3(q.axis[k]), static_cast<float>(q.constant[k]));
  const build::MssExtent e = build::mssExtent(list, k);
  const double R = q.boundRadius[k];
  const float rhoMax = static_cast<float>(e.rho * (1.0 + 1e-4));
  const float pad = static_cast<float>(1e-4 * R);
  g.coefficients = glm::vec4(static_cast<float>(q.radialCoeff[k]), static_cast<float>(q.axialCoeff[k]),
                             static_cast<float>(e.hLo) - pad, static_cast<float>(e.hHi) + pad);
  g.cell = glm::uvec4(static_cast<std::uint32_t>(kind), static_cast<std::uint32_t>(list.clipPlanes.size()) + q.cellBegin[k],
                      q.cellCount[k], std::bit_cast<std::uint32_t>(rhoMax));
  return g;
}
template <build::MssKind K> glm::uvec4 GpuSkinKind<K>::atoms(const build::PatchList& list, std::size_t i) {
  return list.mss.atoms[build::mssKindRange(list.mss, K).first + i];
}
template <build::MssKind K>
std::pair<glm::dvec3, double> GpuSkinKind<K>::reach(const build::PatchList& list, std::size_t i) {
  const std::size_t k = build::mssKindRange(list.mss, K).first + i;
  return {list.mss.center[k], list.mss.boundRadius[k]};
}
template struct GpuSkinKind<build::MssKind::Convex>;
template struct GpuSkinKind<build::MssKind::Edge>;
template struct GpuSkinKind<build::MssKind::Face>;
template struct GpuSkinKind<build::MssKind::Concave>;

GpuPatches packPatches(const build::PatchList& list, const glm::dvec3& origin) {
  if (list.clipPlanes.size() >= kMaxFloatIndex)
    throw std::invalid_argument("gl engine: " + std::to_string(list.clipPlanes.size()) +
                                " clipping planes exceed the 2^24 the GPU records index exactly");
  GpuPatches g;
  g.origin = origin;

  // Bounding sphere of all patches (box centre, largest reach): sets the depth range only.
  glm::dvec3 lo(std::numeric_limits<double>::infinity()), hi(-std::numeric_limits<double>::infinity());
  std::apply(
      [&](auto&... kp) {
        auto pack = [&](auto& k) {
          using Kind = typename std::remove_reference_t<decltype(k)>::Row;
          const std::size_t n = view::patchCount(list, Kind::kind);
          k.records.reserve(n);
          k.atoms.reserve(n);
          for (std::size_t i = 0; i < n; ++i) {
            k.records.push_back(Kind::record(list, i, origin));
            k.atoms.push_back(Kind::atoms(list, i));
            const auto [c, r] = Kind::reach(list, i);
            lo = glm::min(lo, c - r);
            hi = glm::max(hi, c + r);
          }
        };
        (pack(kp), ...);
      },
      g.kinds);

  // n·x + w <= 0 with x = x' + origin becomes n·x' + (w + n·origin) <= 0.
  g.clipPlanes.reserve(list.clipPlanes.size() + list.cellPlanes.size());
  for (const std::vector<build::Plane>* planes : {&list.clipPlanes, &list.cellPlanes}) {
    for (const build::Plane& p : *planes) {
      const glm::dvec3 n(p);
      g.clipPlanes.emplace_back(glm::vec3(n), static_cast<float>(p.w + glm::dot(n, origin)));
    }
  }

  packSkinAtoms(list, origin, g);

  if (lo.x <= hi.x) {
    g.boundsCenter = 0.5 * (lo + hi);
    g.boundsRadius = 0.5 * glm::length(hi - lo);
  }
  return g;
}

}  // namespace surftrace::gl

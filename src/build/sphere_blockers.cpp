// Which atoms can hide part of a whole convex sphere (sphere_blockers.hpp).
#include "build/sphere_blockers.hpp"

#include <algorithm>
#include <limits>
#include <stdexcept>
#include <string>
#include <unordered_map>
#include <utility>

#include <glm/common.hpp>
#include <glm/geometric.hpp>

#include "build/core/vector_math.hpp"

namespace surftrace::build {

SphereBlockers sphereBlockers(const SurfaceParams& params, std::span<const glm::dvec3> centers,
                              std::span<const double> radii, std::span<const std::uint32_t> sphereAtoms,
                              std::span<const glm::dvec4> atoms) {
  const std::size_t n = centers.size();
  if (radii.size() != n || sphereAtoms.size() != n)
    throw std::invalid_argument("sphere blockers: " + std::to_string(n) + " sphere centres but " +
                                std::to_string(radii.size()) + " radii and " + std::to_string(sphereAtoms.size()) + " atoms");
  const double rp = params.probeRadius;
  SphereBlockers out;
  out.grow = params.surface == SurfaceKind::Ses ? rp : 0.0;
  std::vector<std::uint32_t> blockerAtom;  // to skip a sphere's own atom
  if (!atoms.empty()) {
    const double h = params.surface == SurfaceKind::Vdw ? 0.0 : rp;
    for (std::uint32_t k = 0; k < atoms.size(); ++k) {
      out.blockers.push_back(glm::dvec4(glm::dvec3(atoms[k]), atoms[k].w + h));
      blockerAtom.push_back(k);
    }
  } else {
    for (std::uint32_t k = 0; k < n; ++k) {
      out.blockers.push_back(glm::dvec4(centers[k], radii[k] + out.grow));
      blockerAtom.push_back(sphereAtoms[k]);
    }
  }
  double largest = 0.0;
  for (double r : radii) largest = std::max(largest, r + out.grow);
  for (const glm::dvec4& b : out.blockers) largest = std::max(largest, b.w);
  out.begin.assign(n + 1, 0);
  if (n == 0) return out;
  // A hash grid of cell 2·(largest grown radius): grown spheres that meet lie in adjacent cells.
  const double cell = std::max(2.0 * largest, 1e-6);
  auto key = [&](const glm::ivec3& k) {
    return (static_cast<std::uint64_t>(static_cast<std::uint32_t>(k.x)) * 73856093u) ^
           (static_cast<std::uint64_t>(static_cast<std::uint32_t>(k.y)) * 19349663u) ^
           (static_cast<std::uint64_t>(static_cast<std::uint32_t>(k.z)) * 83492791u);
  };
  auto cellOf = [&](const glm::dvec3& c) { return glm::ivec3(glm::floor(c / cell)); };
  std::unordered_multimap<std::uint64_t, std::uint32_t> grid;
  grid.reserve(out.blockers.size());
  for (std::uint32_t k = 0; k < out.blockers.size(); ++k) grid.emplace(key(cellOf(glm::dvec3(out.blockers[k]))), k);
  for (std::uint32_t i = 0; i < n; ++i) {
    const glm::dvec3 c = centers[i];
    const glm::ivec3 k = cellOf(c);
    const std::size_t first = out.list.size();
    for (int dz = -1; dz <= 1; ++dz)
      for (int dy = -1; dy <= 1; ++dy)
        for (int dx = -1; dx <= 1; ++dx) {
          const glm::ivec3 kk = k + glm::ivec3(dx, dy, dz);
          const auto [lo, hi] = grid.equal_range(key(kk));
          for (auto it = lo; it != hi; ++it) {
            const std::uint32_t j = it->second;
            const glm::dvec3 cj(out.blockers[j]);
            if (blockerAtom[j] == sphereAtoms[i] || cellOf(cj) != kk) continue;  // its own atom, a hash collision
            if (glm::length(cj - c) < radii[i] + out.grow + out.blockers[j].w) out.list.push_back(j);
          }
        }
    // Nearest first: the blocker that hides a point is most often a close one, and the test
    // stops at the first. Ties by index keep the order deterministic.
    const auto gap = [&](std::uint32_t j) { return glm::length(glm::dvec3(out.blockers[j]) - c) - out.blockers[j].w; };
    std::sort(out.list.begin() + static_cast<std::ptrdiff_t>(first), out.list.end(),
              [&](std::uint32_t a, std::uint32_t b) { return std::pair(gap(a), a) < std::pair(gap(b), b); });
    out.begin[i + 1] = static_cast<std::uint32_t>(out.list.size());
  }
  return out;
}

bool onConvexPatch(const SphereBlockers& b, std::uint32_t i, const glm::dvec3& c, double rho, const glm::dvec3& x,
                   double tolerance) {
  if (!(rho > 0.0)) return true;
  const glm::dvec3 y = c + ((rho + b.grow) / rho) * (x - c);
  for (std::uint32_t k = b.begin[i]; k < b.begin[i + 1]; ++k) {
    const glm::dvec4 o = b.blockers[b.list[k]];
    if (glm::length(y - glm::dvec3(o)) < o.w * (1.0 - tolerance)) return false;
  }
  return true;
}

double convexPatchEdgeDistance(const SphereBlockers& b, std::uint32_t i, const glm::dvec3& c, double rho,
                               const glm::dvec3& x) {
  double d = std::numeric_limits<double>::infinity();
  if (!(rho > 0.0)) return d;
  const double grown = rho + b.grow;
  for (std::uint32_t k = b.begin[i]; k < b.begin[i + 1]; ++k) {
    const glm::dvec4 o = b.blockers[b.list[k]];
    const glm::dvec3 axis = glm::dvec3(o) - c;
    const double D = glm::length(axis);
    if (!(D > 0.0)) continue;
    // The circle of the grown spheres (law of cosines) is at polar angle acos(h) about the
    // axis towards the blocker, on sphere i as on the grown sphere (y − c ∥ x − c).
    const double h = (D * D + grown * grown - o.w * o.w) / (2.0 * D * grown);
    d = std::min(d, distanceToSphereCircle(c, rho, x, axis / D, h));
  }
  return d;
}

}  // namespace surftrace::build

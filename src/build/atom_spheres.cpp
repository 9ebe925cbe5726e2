// The van der Waals and solvent-accessible surfaces as patch lists of whole spheres.
#include "build/atom_spheres.hpp"

namespace surftrace::build {

PatchList atomSpheres(std::span<const glm::dvec3> centers, std::span<const double> radii, double inflate,
                      SurfaceKind kind) {
  PatchList p;
  p.params.surface = kind;
  p.params.probeRadius = inflate;
  p.params.atomCount = static_cast<std::uint32_t>(centers.size());
  ConvexSpheres& c = p.convex;
  c.center.assign(centers.begin(), centers.end());
  c.radius.resize(radii.size());
  for (std::size_t i = 0; i < radii.size(); ++i) c.radius[i] = radii[i] + inflate;
  c.atom.resize(centers.size());
  for (std::size_t i = 0; i < centers.size(); ++i) c.atom[i] = static_cast<std::uint32_t>(i);
  c.component.assign(centers.size(), 0u);
  c.area.assign(centers.size(), 0.0);
  c.vectorArea.assign(centers.size(), glm::dvec3(0.0));
  p.componentCount = centers.empty() ? 0u : 1u;
  return p;
}

}  // namespace surftrace::build

// The one pipeline from a molecule to a patch list (surface.hpp).
#include "build/surface.hpp"

#include <stdexcept>

#include "build/mss/mss_builder.hpp"
#include "build/ses/contour_buildup.hpp"

namespace surftrace::build {

SurfaceKind parseSurfaceKind(const std::string& name) {
  for (SurfaceKind k : {SurfaceKind::Ses, SurfaceKind::Mss, SurfaceKind::Vdw, SurfaceKind::Sas})
    if (name == surfaceKindName(k)) return k;
  throw std::invalid_argument("unknown surface '" + name + "': choose ses, mss, vdw or sas");
}

PatchList buildSurface(const Molecule& m, const SurfaceRequest& r) {
  PatchList list;
  switch (r.surface) {
    case SurfaceKind::Ses:
      list = buildSes(m.centers, m.radii, SesParams{r.probeRadius});
      if (r.dropCavities) list = outerComponent(list);
      break;
    case SurfaceKind::Mss:
      if (r.shrinkFactor >= 1.0) {
        list = atomSpheres(m.centers, m.radii, 0.0, SurfaceKind::Vdw);
        list.params.shrinkFactor = 1.0;
      } else {
        list = buildMss(m.centers, m.radii, MssParams{r.shrinkFactor});
      }
      break;
    case SurfaceKind::Vdw: list = atomSpheres(m.centers, m.radii, 0.0, SurfaceKind::Vdw); break;
    case SurfaceKind::Sas: list = atomSpheres(m.centers, m.radii, r.probeRadius, SurfaceKind::Sas); break;
  }
  list.params.radiiSet = m.radiiSet;
  list.params.inputCrc32 = m.inputCrc32;
  return list;
}

void checkPatchListMatches(const PatchList& list, const std::string& source, const Molecule& m,
                           const SurfaceRequest& r) {
  auto fail = [&](const std::string& what) {
    throw std::invalid_argument(source + " was built " + what + "; rebuild it with `surftrace build` or match the options");
  };
  if (list.params.atomCount != m.size() || list.params.inputCrc32 != m.inputCrc32)
    fail("from a different input (" + std::to_string(list.params.atomCount) + " atoms) than " + m.source + " with these options (" +
         std::to_string(m.size()) + " atoms)");
  const bool skinAsBalls = r.surface == SurfaceKind::Mss && r.shrinkFactor >= 1.0;
  const SurfaceKind expected = skinAsBalls ? SurfaceKind::Vdw : r.surface;
  if (list.params.surface != expected)
    fail(std::string("for the ") + surfaceKindName(list.params.surface) + " surface, not the " + surfaceKindName(expected));
  if ((expected == SurfaceKind::Ses || expected == SurfaceKind::Sas) && list.params.probeRadius != r.probeRadius)
    fail("with probe radius " + std::to_string(list.params.probeRadius) + " Å, not " + std::to_string(r.probeRadius));
  if (expected == SurfaceKind::Mss && list.params.shrinkFactor != r.shrinkFactor)
    fail("with shrink factor " + std::to_string(list.params.shrinkFactor) + ", not " + std::to_string(r.shrinkFactor));
}

}  // namespace surftrace::build

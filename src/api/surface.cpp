// Stage "build" and the areas of what it builds (surftrace/surface.hpp).
#include "surftrace/surface.hpp"

#include <stdexcept>
#include <string>

#include "build/io/stp_file.hpp"
#include "build/mss/mss_area.hpp"
#include "build/ses/surface_area.hpp"
#include "build/surface_components.hpp"

namespace surftrace {

namespace {

SurfaceAreas sesAreas(const PatchList& patches) {
  const build::SurfaceAreas a = build::computeAreas(patches);
  SurfaceAreas out;
  out.surface = SurfaceKind::Ses;
  out.total = a.sesTotal();
  out.volume = a.sesVolume;
  out.byKind = {a.sesConvex, a.sesToroidal, a.sesConcave};
  out.kindNames = {"convex", "toroidal", "concave"};
  out.perAtom = a.sesPerAtom;
  for (const auto& c : a.components) out.components.push_back({c.area, c.volume, !c.outer()});
  out.sas = a.sas;
  out.sasPerAtom = a.sasPerAtom;
  return out;
}

SurfaceAreas skinAreas(const build::MssAreas& a, SurfaceKind kind) {
  SurfaceAreas out;
  out.surface = kind;
  out.total = a.total();
  out.volume = a.volume;
  for (std::size_t k = 0; k < build::kMssKindCount; ++k) {
    out.byKind.push_back(a.byKind[k]);
    out.kindNames.push_back(build::kMssKinds[k].name);
  }
  out.perAtom = a.perAtom;
  out.areaErrorEstimate = a.areaErrorEstimate;
  out.volumeErrorEstimate = a.volumeErrorEstimate;
  return out;
}

}  // namespace

SurfaceAreas surfaceAreas(const PatchList& patches, std::span<const glm::dvec3> centers) {
  switch (patches.params.surface) {
    case SurfaceKind::Ses:
      return sesAreas(patches);
    case SurfaceKind::Mss:
      return skinAreas(build::computeMssAreas(patches, centers), SurfaceKind::Mss);
    case SurfaceKind::Vdw:
      // The skin at s = 1 is built as the vdW spheres: the union of the balls, exactly.
      return skinAreas(build::unionOfBallsAreas(patches), SurfaceKind::Vdw);
    case SurfaceKind::Sas:
      break;
  }
  throw std::invalid_argument(std::string("the areas of a ") + surfaceKindName(patches.params.surface) +
                              " patch list are not computed: build the SES (whose areas include the SAS) or the skin");
}

}  // namespace surftrace

// The one pipeline from a molecule to a patch list (surface.hpp).
#include "build/surface.hpp"

#include <algorithm>
#include <stdexcept>

#include "build/mss/mss_builder.hpp"
#include "build/moved_atoms.hpp"
#include "build/ses/contour_buildup.hpp"

namespace surftrace::build {

SurfaceKind parseSurfaceKind(const std::string& name) {
  for (SurfaceKind k : {SurfaceKind::Ses, SurfaceKind::Mss, SurfaceKind::Vdw, SurfaceKind::Sas})
    if (name == surfaceKindName(k)) return k;
  throw std::invalid_argument("unknown surface '" + name + "': choose ses, mss, vdw or sas");
}

SurfaceRequest SurfaceRequest::of(const SurfaceParams& params) {
  SurfaceRequest r;
  r.surface = params.surface;
  r.probeRadius = params.probeRadius;
  r.shrinkFactor = params.shrinkFactor;
  return r;
}

std::vector<double> SurfaceRequest::reach(std::span<const double> radii) const {
  std::vector<double> reach(radii.begin(), radii.end());
  switch (surface) {
    case SurfaceKind::Ses:
    case SurfaceKind::Sas:
      for (double& r : reach) r += probeRadius;
      break;
    case SurfaceKind::Vdw: break;
    case SurfaceKind::Mss:
      if (!skinIsUnionOfBalls() && !radii.empty()) reach.assign(radii.size(), *std::max_element(radii.begin(), radii.end()));
      break;
  }
  return reach;
}

PatchList buildSurface(const Molecule& m, const SurfaceRequest& r) {
  PatchList list;
  switch (r.surface) {
    case SurfaceKind::Ses:
      list = buildSes(m.centers, m.radii, SesParams{r.probeRadius});
      if (r.dropCavities) list = outerComponent(list);
      break;
    case SurfaceKind::Mss:
      if (r.skinIsUnionOfBalls()) {
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

struct SurfaceBuilder::State {
  SurfaceRequest request;
  SesBuilder ses;
  MssBuilder mss;
  std::vector<glm::dvec3> centers;
  std::string radiiSet;
  std::uint32_t inputCrc32 = 0;
  std::size_t recomputed = 0;
  bool built = false;

  bool usesSes() const { return request.surface == SurfaceKind::Ses; }
  bool usesMss() const { return request.surface == SurfaceKind::Mss && !request.skinIsUnionOfBalls(); }

  // A copy of the builder's list with the molecule's provenance, as buildSurface gives it.
  PatchList finish(const PatchList& fresh, const Molecule& m) const {
    PatchList list = usesSes() && request.dropCavities ? outerComponent(fresh) : fresh;
    list.params.radiiSet = m.radiiSet;
    list.params.inputCrc32 = m.inputCrc32;
    return list;
  }
  PatchList rebuildSpheres(const Molecule& m) {
    recomputed = m.size();
    return buildSurface(m, request);
  }
};

SurfaceBuilder::SurfaceBuilder(const SurfaceRequest& request) : s_(std::make_unique<State>()) { s_->request = request; }
SurfaceBuilder::~SurfaceBuilder() = default;
SurfaceBuilder::SurfaceBuilder(SurfaceBuilder&&) noexcept = default;
SurfaceBuilder& SurfaceBuilder::operator=(SurfaceBuilder&&) noexcept = default;

PatchList SurfaceBuilder::build(const Molecule& m) {
  State& s = *s_;
  s.built = true;
  s.centers = m.centers;
  s.recomputed = m.size();
  if (s.usesSes()) return s.finish(s.ses.build(m.centers, m.radii, SesParams{s.request.probeRadius}), m);
  if (s.usesMss()) return s.finish(s.mss.build(m.centers, m.radii, MssParams{s.request.shrinkFactor}), m);
  return s.rebuildSpheres(m);
}

PatchList SurfaceBuilder::update(const Molecule& m, std::span<const std::uint32_t> moved) {
  State& s = *s_;
  if (!s.built) throw std::logic_error("SurfaceBuilder::update before build");
  if (m.size() != s.centers.size())
    throw std::invalid_argument("SurfaceBuilder::update: " + std::to_string(m.size()) + " atoms, built with " +
                                std::to_string(s.centers.size()));
  std::vector<glm::dvec3> places(moved.size());
  for (std::size_t k = 0; k < moved.size(); ++k) {
    if (moved[k] >= m.size()) throw std::invalid_argument("SurfaceBuilder::update: atom index out of range");
    places[k] = m.centers[moved[k]];
    s.centers[moved[k]] = places[k];
  }
  if (s.usesSes()) {
    const PatchList& list = s.ses.update(moved, places);
    s.recomputed = s.ses.lastUpdate().full ? m.size() : s.ses.lastUpdate().contours;
    return s.finish(list, m);
  }
  if (s.usesMss()) {
    const PatchList& list = s.mss.update(moved, places);
    s.recomputed = s.mss.lastUpdate().full ? m.size() : s.mss.lastUpdate().recomputed;
    return s.finish(list, m);
  }
  return s.rebuildSpheres(m);
}

PatchList SurfaceBuilder::update(const Molecule& m) {
  if (!s_->built) throw std::logic_error("SurfaceBuilder::update before build");
  std::vector<std::uint32_t> moved;
  std::vector<glm::dvec3> places;
  if (m.size() != s_->centers.size())
    throw std::invalid_argument("SurfaceBuilder::update: " + std::to_string(m.size()) + " atoms, built with " +
                                std::to_string(s_->centers.size()));
  movedAtoms(s_->centers, m.centers, moved, places);
  return update(m, moved);
}

std::size_t SurfaceBuilder::lastRecomputed() const { return s_->recomputed; }

void checkPatchListMatches(const PatchList& list, const std::string& source, const Molecule& m,
                           const SurfaceRequest& r) {
  auto fail = [&](const std::string& what) {
    throw std::invalid_argument(source + " was built " + what + "; rebuild it with `surftrace build` or match the options");
  };
  if (list.params.atomCount != m.size() || list.params.inputCrc32 != m.inputCrc32)
    fail("from a different input (" + std::to_string(list.params.atomCount) + " atoms) than " + m.source + " with these options (" +
         std::to_string(m.size()) + " atoms)");
  const SurfaceKind expected = r.builtKind();
  if (list.params.surface != expected)
    fail(std::string("for the ") + surfaceKindName(list.params.surface) + " surface, not the " + surfaceKindName(expected));
  if ((expected == SurfaceKind::Ses || expected == SurfaceKind::Sas) && list.params.probeRadius != r.probeRadius)
    fail("with probe radius " + std::to_string(list.params.probeRadius) + " Å, not " + std::to_string(r.probeRadius));
  if (expected == SurfaceKind::Mss && list.params.shrinkFactor != r.shrinkFactor)
    fail("with shrink factor " + std::to_string(list.params.shrinkFactor) + ", not " + std::to_string(r.shrinkFactor));
}

}  // namespace surftrace::build

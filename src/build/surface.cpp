// The one pipeline from a molecule to a patch list (surface.hpp).
#include "build/surface.hpp"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <stdexcept>

#include "build/atom_spheres.hpp"
#include "build/mss/mss_builder.hpp"
#include "build/mss/skin_geometry.hpp"
#include "build/moved_atoms.hpp"
#include "build/ses/contour_buildup.hpp"
#include "build/surface_components.hpp"

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

std::vector<double> SurfaceRequest::reachOfSpheres(std::span<const double> sphereRadii) const {
  if (surface == SurfaceKind::Vdw || surface == SurfaceKind::Sas) return {sphereRadii.begin(), sphereRadii.end()};
  return reach(sphereRadii);
}

namespace {

// What cullAtoms may leave out for this surface: contained balls (with the probe added for
// the SES and SAS) except for the skin below s = 1, near-coincident ones always.
CullParams cullParams(const SurfaceRequest& r) {
  if (!(r.mergeWithin >= kMinMergeDistance) || !std::isfinite(r.mergeWithin)) {
    char text[160];
    std::snprintf(text, sizeof text, "merge distance %g Å is below the smallest, %g Å (or not a number)", r.mergeWithin,
                  kMinMergeDistance);
    throw std::invalid_argument(text);
  }
  const bool skin = r.builtKind() == SurfaceKind::Mss;
  const bool probe = r.surface == SurfaceKind::Ses || r.surface == SurfaceKind::Sas;
  return {probe ? r.probeRadius : 0.0, !skin, r.mergeWithin};
}

std::string atomName(const Molecule& m, std::uint32_t i) {
  if (i < m.atoms.size() && m.atoms[i].line > 0) return "line " + std::to_string(m.atoms[i].line);
  return "atom " + std::to_string(i + 1);
}

std::string number(const char* format, double v) {
  char text[64];
  std::snprintf(text, sizeof text, format, v);
  return text;
}

// The merge distance that resolves a cluster: any two of its kept balls lie within twice
// its spread of each other; rounded up to two significant digits.
double resolvingDistance(double spread) {
  const double d = std::max(2.0 * spread, kMinMergeDistance);
  const double unit = std::pow(10.0, std::floor(std::log10(d)) - 1.0);
  return std::ceil(d / unit * (1.0 - 1e-12)) * unit;
}

[[noreturn]] void throwCluster(const Molecule& m, const NearCluster& c, const SurfaceRequest& r) {
  const std::string merged =
      c.kept < c.atoms ? " (" + std::to_string(c.kept) + " of them left after merging balls within " +
                             number("%g", r.mergeWithin) + " Å)"
                       : "";
  const std::string others =
      c.crowdedAtoms > c.kept ? "; " + std::to_string(c.crowdedAtoms) + " kept atoms lie in such clusters in all, " +
                                    "the farthest " + number("%.2g", c.largestSpread) + " Å from the atom it crowds"
                              : "";
  throw std::invalid_argument(
      m.source + ": " + std::to_string(c.atoms) + " atoms lie within " + number("%g", kClusterRadius) + " Å of " +
      atomName(m, c.atom) + " near (" + number("%.6f", c.center.x) + ", " + number("%.6f", c.center.y) + ", " +
      number("%.6f", c.center.z) + ")" + merged + ": a near-coincident cluster (more than " +
      std::to_string(kMaxClusterAtoms) +
      " atoms there; a real structure has one), whose surface would take time growing as the 2.5th power of its "
      "size, deciding nearly degenerate triples exactly. The balls left lie within " + number("%.2g", c.spread) +
      " Å (|Δc| + |Δr|) of " + atomName(m, c.atom) + "'s" + others +
      ". Remove the copies, or merge them with --merge-within " + number("%g", resolvingDistance(c.largestSpread)) +
      " (every ball within that distance of a kept ball is merged into it: the surface of the input with those "
      "atoms moved by at most that much)");
}

std::vector<std::string> cullNotes(const Molecule& m, const CullResult& cull, const SurfaceRequest& r) {
  std::vector<std::string> notes;
  const bool probe = r.surface == SurfaceKind::Ses || r.surface == SurfaceKind::Sas;
  const bool skin = r.builtKind() == SurfaceKind::Mss;
  const std::string surface = r.surface == SurfaceKind::Ses   ? "SES (and SAS)"
                              : r.surface == SurfaceKind::Sas ? "SAS"
                              : skin                          ? "skin"
                                                              : "van der Waals surface";
  const auto plural = [](std::size_t k, const char* one, const char* many) { return k == 1 ? one : many; };
  if (cull.contained > 0)
    notes.push_back(std::to_string(cull.contained) + plural(cull.contained, " atom lies", " atoms lie") +
                    " inside another atom's ball" + (probe ? " (each with the probe radius added)" : "") + ", e.g. " +
                    atomName(m, cull.containedExample) + " inside " + atomName(m, cull.containerExample) +
                    ": adding nothing to the " + surface + ", " + plural(cull.contained, "it was", "they were") +
                    " left out of the build (per-atom areas 0; areas and volume are exact without them)");
  if (cull.merged > 0)
    notes.push_back(std::to_string(cull.merged) + plural(cull.merged, " atom lies", " atoms lie") + " within " +
                    number("%g", r.mergeWithin) + " Å of a kept atom's ball (|Δc| + |Δr|, at most " +
                    number("%.2g", cull.mergedDistance) + " Å: " + atomName(m, cull.mergedExample) + " from " +
                    atomName(m, cull.keeperExample) + ") and " + plural(cull.merged, "was", "were") +
                    " merged into it (per-atom areas 0): the " + surface +
                    " built is exactly that of the input with each of them moved onto its keeper, by at most " +
                    number("%.2g", cull.mergedDistance) + " Å");
  return notes;
}

// The kept atoms' centres and radii (the builders' input).
void gatherKept(const Molecule& m, const CullResult& cull, std::vector<glm::dvec3>& centers, std::vector<double>& radii) {
  centers.resize(cull.kept.size());
  radii.resize(cull.kept.size());
  for (std::size_t k = 0; k < cull.kept.size(); ++k) centers[k] = m.centers[cull.kept[k]], radii[k] = m.radii[cull.kept[k]];
}

// A list built from the atoms `kept` (input indices, ascending) of the input `m`,
// speaking of the input's atoms again. The map is increasing, so every order the builders keep
// by atom index (tori i < j, ascending simplices, patches by lowest atom) stays.
void restoreAtomIndices(PatchList& list, std::span<const std::uint32_t> kept, const Molecule& m) {
  const std::size_t inputCount = m.size();
  list.params.atomCount = static_cast<std::uint32_t>(inputCount);
  if (kept.size() == inputCount) return;
  // The skin's atoms are the input's, left-out ones included, as the file stores them
  // (stp_file.hpp): the kept ones' weights the same, bit for bit.
  if (list.skinAtoms.size() > 0) {
    list.skinAtoms.center = m.centers;
    list.skinAtoms.weight.resize(inputCount);
    for (std::size_t i = 0; i < inputCount; ++i) list.skinAtoms.weight[i] = mss::skinWeight(m.radii[i], list.params.shrinkFactor);
  }
  for (auto* ids : {&list.convex.atom, &list.tori.atomI, &list.tori.atomJ, &list.concave.atomI, &list.concave.atomJ,
                    &list.concave.atomK})
    for (std::uint32_t& a : *ids) a = kept[a];
  for (glm::uvec4& simplex : list.mss.atoms)
    for (int k = 0; k < 4; ++k)
      if (simplex[k] != ~0u) simplex[k] = kept[simplex[k]];
  for (std::uint32_t& a : list.cellPlaneAtom)
    if (a != ~0u) a = kept[a];
}

// Culls m for request r; throws on a cluster that remains.
CullResult cullFor(const Molecule& m, const SurfaceRequest& r) {
  CullResult cull = cullAtoms(m.centers, m.radii, cullParams(r));
  if (cull.cluster) throwCluster(m, *cull.cluster, r);
  return cull;
}

}  // namespace

PatchList buildSurface(const Molecule& m, const SurfaceRequest& r, std::vector<std::string>* notes) {
  // Past 1 the request would be built as the vdW spheres; below kMinShrinkFactor (and NaN)
  // buildMss refuses it, saying why.
  if (r.skinIsUnionOfBalls() && !validShrinkFactor(r.shrinkFactor))
    throw std::invalid_argument("MSS shrink factor " + number("%g", r.shrinkFactor) + " is not in [" +
                                number("%g", kMinShrinkFactor) + ", 1]");
  const CullResult cull = cullFor(m, r);
  if (notes) *notes = cullNotes(m, cull, r);
  std::vector<glm::dvec3> keptCenters;
  std::vector<double> keptRadii;
  if (!cull.keepsAll()) gatherKept(m, cull, keptCenters, keptRadii);
  const std::span<const glm::dvec3> centers = cull.keepsAll() ? std::span<const glm::dvec3>(m.centers) : keptCenters;
  const std::span<const double> radii = cull.keepsAll() ? std::span<const double>(m.radii) : keptRadii;
  PatchList list;
  switch (r.surface) {
    case SurfaceKind::Ses:
      list = buildSes(centers, radii, SesParams{r.probeRadius});
      break;
    case SurfaceKind::Mss:
      if (r.skinIsUnionOfBalls()) {
        list = atomSpheres(centers, radii, 0.0, SurfaceKind::Vdw);
        list.params.shrinkFactor = 1.0;
      } else {
        list = buildMss(centers, radii, MssParams{r.shrinkFactor});
      }
      break;
    case SurfaceKind::Vdw: list = atomSpheres(centers, radii, 0.0, SurfaceKind::Vdw); break;
    case SurfaceKind::Sas: list = atomSpheres(centers, radii, r.probeRadius, SurfaceKind::Sas); break;
  }
  restoreAtomIndices(list, cull.kept, m);
  if (r.surface == SurfaceKind::Ses && r.dropCavities) list = outerComponent(list);
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
  // The atoms the builder was given, input indices ascending, and the builder's index of each
  // input atom (kNotKept for the others). They are the kept atoms of a frame's cull, or of an
  // earlier frame's as long as it still serves (holds every atom kept now, and none merged):
  // contour-buildup buries an atom now inside another itself, exactly as leaving it out would,
  // so a molecule whose atoms drift into one another is still updated in part.
  static constexpr std::uint32_t kNotKept = ~0u;
  std::vector<std::uint32_t> given;
  std::vector<std::uint32_t> givenIndex;

  bool usesSes() const { return request.surface == SurfaceKind::Ses; }
  bool usesMss() const { return request.surface == SurfaceKind::Mss && !request.skinIsUnionOfBalls(); }

  // A copy of the builder's list for the input's atoms, with the molecule's provenance, as
  // buildSurface gives it.
  PatchList finish(const PatchList& fresh, const Molecule& m) const {
    PatchList list = fresh;
    restoreAtomIndices(list, given, m);
    if (usesSes() && request.dropCavities) list = outerComponent(list);
    list.params.radiiSet = m.radiiSet;
    list.params.inputCrc32 = m.inputCrc32;
    return list;
  }
  PatchList rebuildSpheres(const Molecule& m) {
    recomputed = m.size();
    return buildSurface(m, request);
  }
  // Whether the atoms given still serve for a frame culled as `cull`.
  bool givenServe(const CullResult& cull) const {
    for (const std::uint32_t i : cull.kept)
      if (givenIndex[i] == kNotKept) return false;
    for (const std::uint32_t i : given)
      if (cull.fate[i] == AtomFate::Merged) return false;
    return true;
  }
  PatchList fullBuild(const Molecule& m, const CullResult& cull) {
    given = cull.kept;
    givenIndex.assign(m.size(), kNotKept);
    for (std::size_t k = 0; k < given.size(); ++k) givenIndex[given[k]] = static_cast<std::uint32_t>(k);
    std::vector<glm::dvec3> keptCenters;
    std::vector<double> keptRadii;
    gatherKept(m, cull, keptCenters, keptRadii);
    recomputed = m.size();
    if (usesSes()) return finish(ses.build(keptCenters, keptRadii, SesParams{request.probeRadius}), m);
    return finish(mss.build(keptCenters, keptRadii, MssParams{request.shrinkFactor}), m);
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
  if (!s.usesSes() && !s.usesMss()) return s.rebuildSpheres(m);
  return s.fullBuild(m, cullFor(m, s.request));
}

PatchList SurfaceBuilder::update(const Molecule& m, std::span<const std::uint32_t> moved) {
  State& s = *s_;
  if (!s.built) throw std::logic_error("SurfaceBuilder::update before build");
  if (m.size() != s.centers.size())
    throw std::invalid_argument("SurfaceBuilder::update: " + std::to_string(m.size()) + " atoms, built with " +
                                std::to_string(s.centers.size()));
  for (std::size_t k = 0; k < moved.size(); ++k) {
    if (moved[k] >= m.size()) throw std::invalid_argument("SurfaceBuilder::update: atom index out of range");
    s.centers[moved[k]] = m.centers[moved[k]];
  }
  if (!s.usesSes() && !s.usesMss()) return s.rebuildSpheres(m);
  // The frame's own cull, as buildSurface takes it; where the atoms given no longer serve, a
  // full build of those it keeps.
  const CullResult cull = cullFor(m, s.request);
  if (!s.givenServe(cull)) return s.fullBuild(m, cull);
  // The moved atoms the builder has, by its index; an atom left out moved nothing it built.
  std::vector<std::uint32_t> keptMoved;
  std::vector<glm::dvec3> places;
  for (const std::uint32_t i : moved) {
    const std::uint32_t k = s.givenIndex[i];
    if (k == State::kNotKept) continue;
    keptMoved.push_back(k);
    places.push_back(m.centers[i]);
  }
  if (s.usesSes()) {
    const PatchList& list = s.ses.update(keptMoved, places);
    s.recomputed = s.ses.lastUpdate().full ? m.size() : s.ses.lastUpdate().contours;
    return s.finish(list, m);
  }
  const PatchList& list = s.mss.update(keptMoved, places);
  s.recomputed = s.mss.lastUpdate().full ? m.size() : s.mss.lastUpdate().recomputed;
  return s.finish(list, m);
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

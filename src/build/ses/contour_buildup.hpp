// SES patches by contour-buildup (Totrov & Abagyan 1996; Lindow et al. 2010, Sect. 4.1).
#pragma once

#include <cstdint>
#include <memory>
#include <span>

#include <glm/vec3.hpp>

#include "build/patch_list.hpp"
#include "build/surface_limits.hpp"

namespace surftrace::build {

struct SesParams {
  double probeRadius = 1.4;
};

// Builds the SES patch list of atoms (centres, radii > 0, validated by the caller):
// a convex patch per atom with exposed SAS, a torus per exposed SAS arc, a concave
// triangle per SAS vertex, with self-intersection planes for every pair of probe
// positions closer than 2 rp. The list is identical (order and bits) for any number of
// threads. `params.probeRadius` must be finite, > 0 and at most maxProbeRadius(radii)
// (std::invalid_argument otherwise).
// Four or more atoms whose extended spheres pass through one probe position (to 1e-10
// relative; cospherical atoms, ORACLES E.6) make one merged vertex: a fan of concave
// triangles sharing the probe that tiles the convex cone of all contact directions, emitted
// by the lowest atom; the tori of the polygon's boundary pairs end there, other pairs not.
// Fills patches.params.probeRadius, surface and atomCount; the caller sets the rest.
//
// Order: convex patches by atom; tori by their lower atom i, then by j, then along the
// circle; concave triangles by their lowest atom i, then by j, then along circle (i, j).
//
// Components: every patch carries the SES component it belongs to and componentCount
// says how many there are. 0 is the outer surface (the one holding the SES point furthest
// along +x); inner surfaces (cavities) and separate molecules get 1, 2, ... in order of
// their first patch. Patches connect through shared arcs and vertices, tracked per
// connected piece of each atom's exposed region, so an atom exposed both to the outside
// and to a cavity (a one-atom wall) keeps the two apart; its single convex patch carries
// the lower of the two numbers.
PatchList buildSes(std::span<const glm::dvec3> centers, std::span<const double> radii, const SesParams& params);

// The largest probe radius served, kMaxProbeToRadius times the smallest atom radius
// (surface_limits.hpp).
double maxProbeRadius(std::span<const double> radii);
// Throws std::invalid_argument naming the limit and why when probeRadius > maxProbeRadius.
void checkProbeRadius(double probeRadius, std::span<const double> radii);

// What the last SesBuilder::build or update recomputed (for tests and benchmarks).
struct SesUpdateStats {
  std::size_t moved = 0;     // atoms whose centre changed
  std::size_t owners = 0;    // atoms whose SAS vertices (concave patches) were recomputed
  std::size_t contours = 0;  // atoms whose contour (convex patch, tori) was rebuilt
  std::size_t probes = 0;    // concave patches whose clipping planes were recomputed
  bool full = false;         // a full build (build(), or an update moving over 1/8 of the atoms)
};

// Contour-buildup that keeps its per-atom results, so that a trajectory in which few atoms
// move is updated by recomputing only the contours near them (Lindow et al. 2010, end of
// Sect. 4.1). After update() the patch list equals, array for array and bit for bit,
// what buildSes() returns for the new centres.
//
// Atoms are independent: an atom's SAS vertices and contour are pure functions of its
// neighbourhood, so update() recomputes the vertices of every atom within reach of a moved
// atom's old or new position (and of atoms whose burial changed), then the contours of the
// atoms those vertices touch, and the clipping planes of probes near changed probes; the
// fresh per-atom pieces are spliced between the kept ones. The cost is that of the atoms
// recomputed plus a few passes over the arrays (copies, components), a tenth of a full
// build when 1% of the atoms of a 10k-atom protein move together.
//
// Usage: build() once, then update() per frame; patches() stays valid until the next
// call. Not thread-safe (one builder per thread); each call runs in parallel with TBB.
class SesBuilder {
 public:
  SesBuilder();
  ~SesBuilder();
  SesBuilder(SesBuilder&&) noexcept;
  SesBuilder& operator=(SesBuilder&&) noexcept;
  SesBuilder(const SesBuilder&) = delete;
  SesBuilder& operator=(const SesBuilder&) = delete;

  // Full build; same contract and result as buildSes(). Keeps copies of the atoms.
  const PatchList& build(std::span<const glm::dvec3> centers, std::span<const double> radii, const SesParams& params);

  // Moves atoms moved[k] to newCenters[k] (radii and probe unchanged) and updates the
  // patch list. Indices must be < atomCount; a repeated index takes its last position.
  // Throws std::logic_error before the first build(), std::invalid_argument on a bad
  // index, a length mismatch or a non-finite centre.
  const PatchList& update(std::span<const std::uint32_t> moved, std::span<const glm::dvec3> newCenters);

  // Same, for a whole frame: the atoms whose centre differs (in any bit) are the moved ones.
  const PatchList& update(std::span<const glm::dvec3> centers);

  const PatchList& patches() const;
  // Moves the patch list out; the builder needs build() again before update().
  PatchList takePatches();
  const SesUpdateStats& lastUpdate() const;

 private:
  struct State;
  std::unique_ptr<State> s_;
};

}  // namespace surftrace::build

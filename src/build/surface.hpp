// One way from a read molecule to the patch list a command asks for: every command (build,
// area, render, trajectory) goes through it, so they agree on what a surface is.
#pragma once

#include <cstdint>
#include <memory>
#include <span>
#include <string>
#include <vector>

#include "build/atom_culling.hpp"
#include "build/io/molecule.hpp"
#include "build/patch_list.hpp"
#include "build/surface_limits.hpp"

namespace surftrace::build {

// The rules of a surface live here, and nowhere else: what each kind is built as, and how far
// it reaches beyond its atoms.
struct SurfaceRequest {
  SurfaceKind surface = SurfaceKind::Ses;
  double probeRadius = 1.4;    // SES, SAS
  double shrinkFactor = 0.5;   // MSS, validShrinkFactor: [kMinShrinkFactor, 1]; 1 is the vdW balls
  bool dropCavities = false;   // SES: the outer component only

  // The request a patch list was built for (its surface, probe and shrink factor).
  static SurfaceRequest of(const SurfaceParams& params);
  // The skin at s = 1 is exactly the union of the van der Waals balls: built as the vdW spheres.
  bool skinIsUnionOfBalls() const { return surface == SurfaceKind::Mss && shrinkIsUnionOfBalls(shrinkFactor); }
  // The kind of the patch list buildSurface makes: Vdw for the skin at s = 1, else `surface`.
  SurfaceKind builtKind() const { return skinIsUnionOfBalls() ? SurfaceKind::Vdw : surface; }
  // How far the surface reaches beyond each atom's centre (for framing from the atoms alone):
  // r + rp for the SES and SAS, r for the vdW balls (and the skin at s = 1), and for the skin
  // the largest radius r_max: it lies in the centres' hull grown by r_max (every ball of its
  // construction is centred in that hull, shrunk to radius² <= Σλ_i r_i² <= r_max²), and the
  // frustum and the orthographic window are convex, so balls of r_max about the centres frame
  // it (the balls r_i/√s it also lies in grow without bound as s -> 0).
  std::vector<double> reach(std::span<const double> radii) const;
  // The same from a list's convex spheres when its atoms are not at hand (a patch list file
  // alone): an SES sphere is its atom's, so it reaches rp further; the vdW and SAS lists'
  // spheres are the surface itself. The skin's patches are not spheres of atoms: for it this
  // is reach(sphereRadii), as if they were the atoms' radii.
  std::vector<double> reachOfSpheres(std::span<const double> sphereRadii) const;
  // Atoms whose balls lie within this distance (Å, >= kMinMergeDistance) of a kept atom's are
  // merged into it before the build (atom_culling.hpp).
  double mergeWithin = kMinMergeDistance;
};

// "ses", "mss", "vdw", "sas"; std::invalid_argument naming the choices otherwise.
SurfaceKind parseSurfaceKind(const std::string& name);

// The SES by contour-buildup, the MSS from feasible power cells (s = 1: the vdW spheres), or
// the vdW or SAS spheres; params carry the molecule's radii set and input checksum. Throws
// std::invalid_argument for an MSS request whose shrink factor is not validShrinkFactor.
//
// Built from the atoms cullAtoms keeps: for the SES, SAS and vdW surface an atom whose
// (extended) ball lies inside another's adds nothing and is left out, exactly; for every
// surface an atom whose ball lies within request.mergeWithin of a kept one is merged into it.
// The list still speaks of the input's atoms: its atom indices are the input's, atomCount is
// the input's count, and the atoms left out have no patches (per-atom areas 0). What was left
// out is described in `notes` when given (one sentence each, naming lines of the input).
// Throws std::invalid_argument, naming the atoms, their place and extent and the merge
// distance that would resolve them, for a near-coincident cluster that remains (more than
// kMaxClusterAtoms kept atoms within kClusterRadius), rather than build it for minutes, or
// wrongly; and for a mergeWithin below kMinMergeDistance.
PatchList buildSurface(const Molecule& molecule, const SurfaceRequest& request,
                       std::vector<std::string>* notes = nullptr);

// The same surface frame after frame (a trajectory): keeps SesBuilder's or MssBuilder's memory
// and per-atom results, so that a frame in which few atoms moved is a partial update. Every
// list it returns equals, array for array and bit for bit, buildSurface() of that frame's
// molecule (the vdW and SAS spheres, which no builder keeps, are simply rebuilt). Atoms are
// culled frame by frame as buildSurface culls them; a frame that keeps other atoms than the
// last is a full build.
class SurfaceBuilder {
 public:
  explicit SurfaceBuilder(const SurfaceRequest& request);
  ~SurfaceBuilder();
  SurfaceBuilder(SurfaceBuilder&&) noexcept;
  SurfaceBuilder& operator=(SurfaceBuilder&&) noexcept;

  // A full build of `molecule` (its radii are kept for the updates that follow). The list is
  // the caller's: the builder keeps its own, so the next frame can be built while this one is
  // drawn.
  PatchList build(const Molecule& molecule);
  // `molecule` is the last one built with atoms moved[k] now elsewhere (nothing else changed):
  // a partial update. std::logic_error before the first build().
  PatchList update(const Molecule& molecule, std::span<const std::uint32_t> moved);
  // `molecule` is the last one built with any atoms moved (found by comparing the centres).
  PatchList update(const Molecule& molecule);
  // Atoms recomputed by the last call (the builders' own count; every atom for a full build).
  std::size_t lastRecomputed() const;

 private:
  struct State;
  std::unique_ptr<State> s_;
};

// Throws std::invalid_argument, naming `source` and what differs, unless `list` was built from
// `molecule` (atom count, input checksum) with this request (surface, probe or shrink factor).
void checkPatchListMatches(const PatchList& list, const std::string& source, const Molecule& molecule,
                           const SurfaceRequest& request);

}  // namespace surftrace::build

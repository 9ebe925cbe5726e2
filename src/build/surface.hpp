// One way from a read molecule to the patch list a command asks for: every command (build,
// area, render, trajectory) goes through it, so they agree on what a surface is.
#pragma once

#include <string>

#include "build/io/molecule.hpp"
#include "build/patch_list.hpp"

namespace surftrace::build {

struct SurfaceRequest {
  SurfaceKind surface = SurfaceKind::Ses;
  double probeRadius = 1.4;    // SES, SAS
  double shrinkFactor = 0.5;   // MSS, in (0, 1]; 1 is the union of the van der Waals balls
  bool dropCavities = false;   // SES: the outer component only
};

// "ses", "mss", "vdw", "sas"; std::invalid_argument naming the choices otherwise.
SurfaceKind parseSurfaceKind(const std::string& name);

// The SES by contour-buildup, the MSS from feasible power cells (s = 1: the vdW spheres), or
// the vdW or SAS spheres; params carry the molecule's radii set and input checksum.
PatchList buildSurface(const Molecule& molecule, const SurfaceRequest& request);

// Throws std::invalid_argument, naming `source` and what differs, unless `list` was built from
// `molecule` (atom count, input checksum) with this request (surface, probe or shrink factor).
void checkPatchListMatches(const PatchList& list, const std::string& source, const Molecule& molecule,
                           const SurfaceRequest& request);

}  // namespace surftrace::build

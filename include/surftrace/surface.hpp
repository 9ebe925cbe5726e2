// Stage "build": atoms -> the patch list of a surface (SES, skin, vdW or SAS spheres), built
// whole or updated where atoms moved, its areas and volume, and the `.stp` file that keeps it.
#pragma once

#include <span>
#include <string>
#include <vector>

#include <glm/vec3.hpp>

#include "build/bonds.hpp"
#include "build/cavities.hpp"
#include "build/io/stp_file.hpp"
#include "build/patch_list.hpp"
#include "build/surface.hpp"
#include "build/surface_components.hpp"
#include "build/surface_limits.hpp"
#include "surftrace/molecule.hpp"

namespace surftrace {

using build::BallStickModel;
using build::PatchList;
using build::PatchListAtoms;
using build::SurfaceBuilder;  // the same surface frame after frame: partial updates, bit for bit a full build
using build::SurfaceKind;
using build::SurfaceParams;
using build::SurfaceRequest;

using build::buildSurface;            // (molecule, request, notes) -> patch list
using build::checkPatchListMatches;   // a patch list read from a file, held to a molecule and a request
using build::parseSurfaceKind;        // "ses", "mss", "vdw", "sas"
using build::surfaceKindName;
using build::kMaxShrinkFactor;  // the skin's shrink factor s: in [kMinShrinkFactor, kMaxShrinkFactor]
using build::kMinShrinkFactor;
using build::validShrinkFactor;
using build::kMaxShrinkFactor;     // the skin's shrink factor s: in [kMinShrinkFactor, kMaxShrinkFactor]
using build::kMinShrinkFactor;
using build::validShrinkFactor;

// The patch list of a `.stp` file (std::invalid_argument / InputError naming what is wrong),
// and the file itself, written whole or not at all; `atoms` (centres and radii) are kept with
// it so that `render` can frame and colour it alone.
using build::readPatchList;
using build::writePatchList;
// The SES's outer component alone (its cavities left out).
using build::outerComponent;
// The SES's cavities alone (the outer components left out), and each cavity located: its
// lining atoms, the centroid of its surface, its box, area and void.
using build::Cavity;
using build::cavityComponents;
using build::locateCavities;

// One closed piece of a surface: an outer surface, or a cavity inside one.
struct ComponentArea {
  double area = 0.0;    // Å²
  double volume = 0.0;  // Å³, negative for a cavity (minus the void it encloses)
  bool cavity = false;
};

// A surface's areas (Å²) and volume (Å³), exact from its patches.
struct SurfaceAreas {
  SurfaceKind surface = SurfaceKind::Ses;  // the patch list's (Vdw for the skin at s = 1)
  double total = 0.0;
  double volume = 0.0;
  // By patch kind, in the order of `kindNames`: the SES's convex, toroidal and concave
  // patches; the skin's sphere and hyperboloid patches (build::kMssKinds).
  std::vector<double> byKind;
  std::vector<const char*> kindNames;
  // Per atom of the molecule, in its order (atoms with no patch: 0); they sum to `total`.
  std::vector<double> perAtom;
  // The SES: its components, outer surfaces and cavities (none for the other surfaces).
  std::vector<ComponentArea> components;
  // The SES: the solvent-accessible surface of the same probe, total and per atom.
  double sas = 0.0;
  std::vector<double> sasPerAtom;
  // The skin: the estimated quadrature error of its hyperboloid areas and of its volume.
  double areaErrorEstimate = 0.0, volumeErrorEstimate = 0.0;
};

// The areas of a patch list made by buildSurface (SES, skin, or the skin at s = 1: the union
// of the vdW balls); `centers` are the molecule's atoms (the skin shares each point among its
// simplex's atoms by their weights). std::invalid_argument for the SAS and vdW spheres of
// render, which have no areas of their own here.
SurfaceAreas surfaceAreas(const PatchList& patches, std::span<const glm::dvec3> centers);

// The ball-and-stick model of a molecule: its bonds (from the file's records and distances),
// balls of ballScale times each atom's radius and sticks of stickRadius Å.
using build::ballStickModel;
using build::moleculeBonds;

}  // namespace surftrace

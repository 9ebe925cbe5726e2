// Exact areas and volumes from a patch list (ORACLES A.3, A.4, A.5, D.2).
#pragma once

#include <vector>

#include "build/patch_list.hpp"
#include "build/spherical_region.hpp"

namespace surftrace::build {

struct SurfaceAreas {
  double sas = 0.0;          // Å²
  double sesConvex = 0.0;
  double sesToroidal = 0.0;
  double sesConcave = 0.0;   // after self-intersection clipping
  double sesVolume = 0.0;    // Å³, divergence theorem over all patches
  double sesTotal() const { return sesConvex + sesToroidal + sesConcave; }
  std::vector<double> sasPerAtom;  // params.atomCount entries
  std::vector<double> sesPerAtom;  // convex + half of each torus + a third of each concave patch
  // Per SES component (index = label), each a closed surface: volume is ⅓∮ x·n dA with the
  // SES normal pointing into the solvent. An outer surface (one the solvent outside reaches:
  // 0, and every separate molecule's) encloses its body, so its volume is positive; a
  // cavity's normals point into the void, so its volume is negative, minus the void it
  // encloses. (A molecule floating inside another's cavity counts as outer.)
  struct Component {
    double area = 0.0;
    double volume = 0.0;
    // ∫ x dA over the component, Å³: moment / area is the area-weighted centroid of its
    // surface (where `cavities` locates a cavity).
    glm::dvec3 areaMoment{0.0};
    bool outer() const { return volume > 0.0; }
  };
  std::vector<Component> components;
};

// Needs the atoms' radii (convex patches store vdW radius; the SAS radius is r + rp).
SurfaceAreas computeAreas(const PatchList& patches);

// The part of a convex patch that belongs to another component than the patch's own label
// (a one-atom wall between the outside and a cavity): the region of the patch bounded by
// that component's tori, its area (Å², Gauss–Bonnet) and vector area (in the units of
// ConvexSpheres::vectorArea, by Stokes). computeAreas gives these parts to their components;
// outerComponent takes them out of the convex patches it keeps.
struct ConvexPart {
  std::uint32_t component;
  double area;
  glm::dvec3 vectorArea;
};
// For every convex patch (index as in patches.convex), its parts of other components.
std::vector<std::vector<ConvexPart>> convexPartsOfOtherComponents(const PatchList& patches);

// Concave patch c as its probe sphere (unit) minus caps: the three half-spheres beyond its
// edges and one cap per clipping plane (ORACLES A.4, A.5); `caps` is filled and returned.
std::vector<Cap>& concaveCaps(const PatchList& patches, std::size_t c, std::vector<Cap>& caps);

// Area of one torus patch (ORACLES A.3), spindle tori keeping only |θ| >= acos(R/rp).
double torusPatchArea(double R, double rp, double thetaI, double thetaJ, double phiExtent);

}  // namespace surftrace::build

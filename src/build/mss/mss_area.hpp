// Areas and volumes of the molecular skin from its patches (ORACLES C.3, D.2).
#pragma once

#include <cstddef>
#include <span>
#include <vector>

#include <glm/vec3.hpp>

#include "build/patch_list.hpp"

namespace surftrace::build {

struct MssAreas {
  // Å² by patch kind (MssKind order: convex, edge, face, concave) and in all.
  double byKind[kMssKindCount] = {};  // MssKind order (kMssKinds)
  double total() const {
    double sum = 0.0;
    for (double a : byKind) sum += a;
    return sum;
  }
  double volume = 0.0;         // Å³ enclosed by the skin (divergence theorem over the patches)
  // Estimated quadrature error of the hyperboloid areas (the spheres are closed form): the sum
  // over all pieces of QUADPACK's estimate of the 15-point Gauss–Kronrod result's error (from
  // |K15 − G7|; see mss_area.cpp); plus, for every negligible patch (counted as 0), its area
  // bound (mssThinPatchAreaBound).
  double areaErrorEstimate = 0.0;
  double volumeErrorEstimate = 0.0;
  // |Σ ∫ n dA| over all patches, Å²: 0 for a closed surface (a hole or an overlap shows here).
  double closure = 0.0;
  std::vector<double> perPatch;  // Å², one per MSS patch
  // Per atom: each point of the skin shared by the atoms of its simplex in proportion to
  // its convex weights λ (ORACLES D.3: x ∈ μ_X has λ = the barycentric coordinates of
  // y = z_X + P(x − z_X)/(1 − s) in δ_X); these sum to the total. λ of a point of δ_X lies in
  // [0, 1]: where rounding on a nearly flat simplex puts it outside, it is clamped there and
  // renormalised (an even split when nothing is left), so each share is in [0, the patch's area].
  std::vector<double> perAtom;
};

// An upper bound on the area of sphere patch k (convex or concave) from the thinnest slab that
// holds its mixed cell on the sphere: for two cell planes that face each other (n_i·n_j < −½),
// every point x of the patch has n_i·(x − z) within an interval of width
// t = −(n_i·z + d_i) − (n_j·z + d_j) + |n_i + n_j| R, and a sphere meets a slab of width t in
// at most 2πR t (Archimedes). +∞ for a hyperboloid or a cell without such a pair. This is what
// a near-degenerate simplex leaves (issue 18: the sliver tetrahedron of four nearly co-spherical
// atoms has a cell of width ~ the jitter, where Gauss–Bonnet on two almost coincident circles
// cancels catastrophically); the exact placement has no such cell at all.
double mssThinPatchAreaBound(const PatchList& patches, std::size_t k);

// Whether patch k is counted as zero area: its thin-cell bound is below 1e-7 of its sphere's
// area (4πR²), so it is invisible and no computation in double resolves it. computeMssAreas
// adds the bound to its error estimates instead, and camera framing skips such patches.
bool mssPatchIsNegligible(const PatchList& patches, std::size_t k);

// Spheres (convex and concave) exactly, by Gauss–Bonnet on the sphere minus the caps outside
// the mixed cell; hyperboloids by Green's theorem on their (h, φ) parametrisation: closed-form
// terms at the caps and tips plus, along each conic where a lateral plane of the cell cuts the
// surface, a 1-D integral in the conic's cosh/sinh parameter by Gauss–Kronrod quadrature, to an
// estimated 1e-10·2π·bound² a piece, with the summed error estimate reported. `centers` are the
// atoms' (for the per-atom shares). Each patch is integrated on its own and the sums run in patch
// order: the result is the same bit for bit for any thread count.
MssAreas computeMssAreas(const PatchList& patches, std::span<const glm::dvec3> centers);

// The integration computeMssAreas did before issue 22, kept as its test oracle: adaptive
// Gauss–Kronrod in h between every candidate breakpoint, each piece to relTol·2π·bound²; ~900
// integrand evaluations a hyperboloid patch at relTol = 1e-10.
MssAreas computeMssAreasAdaptive(const PatchList& patches, std::span<const glm::dvec3> centers, double relTol = 1e-10);

// The skin at s = 1: the union of the van der Waals balls, exactly (Gauss–Bonnet on each
// sphere minus the caps inside its neighbours). All of it counts as convex.
MssAreas unionOfBallsAreas(std::span<const glm::dvec3> centers, std::span<const double> radii);
// The same for the spheres of a vdW patch list (buildSurface at s = 1: the atoms left out,
// inside another ball or merged, have none); per-atom areas for all params.atomCount atoms.
MssAreas unionOfBallsAreas(const PatchList& vdwSpheres);

}  // namespace surftrace::build

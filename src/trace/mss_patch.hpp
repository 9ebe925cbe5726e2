// MSS patch: the skin quadric of one Delaunay simplex inside its mixed cell (ORACLES B.5,
// C.3, C.4), intersected in double precision.
#pragma once

#include <optional>
#include <span>
#include <vector>

#include "build/neighbour_grid.hpp"
#include "build/patch_list.hpp"
#include "trace/ray.hpp"

namespace surftrace::trace {

struct SkinAtomBalls;

// f(x) = radial·|x − center|² + axial·((x − center)·axis)² + constant, f < 0 inside the skin
// body, kept where every cell plane (n, w) has n·x + w <= 0 and within boundRadius of the
// centre (the list leaves out planes that cannot cut the skin inside that ball). `cellPlanes`
// views planes owned elsewhere: the patch must not outlive them.
struct MssPatch {
  build::MssKind kind = build::MssKind::Convex;
  glm::dvec3 center{0.0};
  glm::dvec3 axis{0.0, 0.0, 1.0};
  double radial = 1.0, axial = 0.0, constant = -1.0;
  double boundRadius = 1.0;
  build::MssExtent extent{-1.0, 1.0, 1.0};  // the cylinder about the axis that holds the patch
  std::span<const build::Plane> cellPlanes;
  // The skin's atoms (SkinAtomBalls) that skinOwner() searches, owned elsewhere like
  // cellPlanes; none (the simplex's lowest atom owns every point) when null.
  const SkinAtomBalls* atomBalls = nullptr;
};

// The skin's atoms as their vdW balls, c_i and r_i² = s·w_i (build::SkinAtoms), and a grid over
// them for skinOwner(). Empty when the list has no atoms.
struct SkinAtomBalls {
  std::vector<glm::dvec4> balls;  // centre, r²
  build::NeighbourGrid grid;      // the centres with their radii r_i
};
SkinAtomBalls skinAtomBalls(const build::PatchList& list);

MssPatch mssPatch(const build::PatchList& patches, std::size_t index);

// The box of the patch's extent cylinder within its bounding ball (build::mssExtent).
Bounds3d bounds(const MssPatch& p);

// A tighter box for traversal: bounds(p) cut by the box of every cap that one cell plane
// cuts from the bounding ball (each cap holds the patch, so each of their boxes does). It
// holds every point intersect() accepts, the cell slack included (both are widened by twice
// that slack). The skin's hyperboloid boxes overlap much less so (1AON, s = 0.5).
Bounds3d cellBounds(const MssPatch& p);

// The first root in (tMin, tMax] whose point lies in the cell. The ray is shifted to its
// closest approach to the centre before the quadratic is formed, and the roots are taken in
// the cancellation-free form; a ray along an asymptote of a hyperboloid (quadratic term 0)
// has one root, a tangent ray a double one. Normal ∇f/|∇f|, out of the body. Flags: grazing,
// near a cell plane (a seam with the neighbouring patch).
std::optional<PatchHit> intersect(const MssPatch& p, const UnitRay& ray, double tMin, double tMax);
inline std::optional<PatchHit> intersect(const MssPatch& p, const Ray& ray, double tMin, double tMax) {
  return intersect(p, UnitRay(ray), tMin, tMax);
}

// Whether intersect(p, ray, tMin, tMax) has a hit (occlusion rays): its roots and cell test,
// no normal or flags.
bool occludes(const MssPatch& p, const UnitRay& ray, double tMin, double tMax);

// The cell test intersect() applies to a point; `slack` (Å, >= 0) widens the cell.
bool insideCell(const MssPatch& p, const glm::dvec3& x, double slack = 0.0);

// Distance (Å) from a point x of the patch to the edge of its cell: on the spheres (convex and
// concave kinds) the distance to each cell plane's circle, on the hyperboloids the distance to
// each cell plane (both lower bounds of the distance to the patch's edge).
double boundaryDistance(const MssPatch& p, const glm::dvec3& x);

// The atom whose ball owns the skin point x: of all the atoms, the one of least power distance
// |x − c_i|² − s·w_i = |x − c_i|² − r_i² to its vdW ball, the lower index on a tie. The search
// starts from the patch's simplex `atoms` (unused slots ~0u) and looks no farther than that
// bound allows. Without atoms (null or empty `balls`) the simplex's lowest atom. Why these
// balls, and why not the simplex's atoms alone: mss_patch.cpp.
std::uint32_t skinOwner(const SkinAtomBalls* balls, const glm::uvec4& atoms, const glm::dvec3& x);
// The atom a hit belongs to (colour, atom.id): its owner.
inline std::uint32_t atomOf(const MssPatch& p, const glm::uvec4& atoms, const glm::dvec3& x) {
  return skinOwner(p.atomBalls, atoms, x);
}

}  // namespace surftrace::trace

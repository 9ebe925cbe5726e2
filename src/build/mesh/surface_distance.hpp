// The exact surface as a distance field: what the mesher samples, projects onto and certifies
// its meshes with, and what tests measure meshes against.
#pragma once

#include <cstdint>
#include <memory>
#include <span>

#include <glm/vec3.hpp>

#include "build/patch_list.hpp"

namespace surftrace::build::mesh {

// The surface point nearest to a query point.
struct SurfacePoint {
  glm::dvec3 point{0.0};    // on the surface (to ~1e-9 Å)
  glm::dvec3 normal{0.0};   // unit, outward (away from the body)
  std::uint32_t atom = 0;   // the atom that owns `point` (SES: the patch's atom or nearest contact
                            // atom; skin: the smallest power distance; vdW/SAS: the sphere's)
  std::uint8_t kind = 0;    // patch kind code of `point` (view::PatchKind numbering)
  std::uint32_t component = 0;  // surface component of `point`
};

// The surface of one patch list as a field. Both calls are thread-safe (const, no shared
// mutable state) so that the mesher can call them from TBB tasks.
//
// What each surface's field is (build/mesh/surface_distance.cpp, skin_distance.cpp):
//  - SES (probe rp). With A the accessible probe centres (outside every ball r_i + rp, ORACLES
//    D.1) and d(x) = dist(x, A), signedDistance = rp − d(x) where x lies inside the SAS: exact
//    on the body side (d >= rp: distance to the SES, self-intersections included), and on the
//    solvent side wherever the point rp from A along the normal lies on the SES; where another
//    probe covers that point (a clipped concave cap, a spindle torus's inner part) the closest
//    point is the ridge where the two probe spheres meet (the clip circles and their corners,
//    the cusps) and the value is its distance. Outside the SAS: rp + min_i(|x − c_i| − r_i − rp),
//    exact when the nearest SAS point is on a sphere face, else a lower bound (>= rp).
//    reach() = rp: every point nearer than rp to the SES lies inside the SAS. The owner: the
//    convex patch's atom; on a torus the atom of the nearer contact circle by the axial
//    coordinate, on a concave triangle the atom of the nearest contact direction (the
//    renderers' atomOf rules, trace/torus_patch.cpp, concave_patch.cpp). kind 1, 2, 3.
//    Every atom's ball counts (a buried atom's ball can fill a void among the others). A list
//    built without its cavities: points in a left-out cavity's void read outside (> 0).
//  - SAS and vdW: the boundary of the union of the list's spheres: −(distance to the boundary)
//    inside, min_k(|x − c_k| − R_k) outside, both exact everywhere. The boundary's arcs and
//    vertices come from an SES built internally with the spheres shrunk by ρ = half the
//    smallest radius and a probe ρ (whose SAS is the union). The owner: the sphere's atom; on a
//    seam (arc, vertex) the sphere whose inward direction from the seam point is nearest to the
//    direction of x. kind 1. reach() = the smallest sphere radius.
//  - Skin: G(x) of ORACLES D.3 from its definition (an active-set solve over the atoms near x,
//    certified against the others) gives the sign. Where the estimate along ∇G (the nearest
//    root of x's cell quadric on that line) is within reach(), the value is the distance to
//    closest(x), exact; farther, that estimate. closest(x): the nearest foot point of x on the
//    quadrics of the list's patches that lies in its patch's cell (every patch that could hold a
//    nearer point is examined). The owner: the simplex's atom of smallest power distance
//    |p − c|² − r². kind 4 + MssKind. reach() = half the smallest atom radius. component 0.
class SurfaceDistance {
 public:
  virtual ~SurfaceDistance() = default;
  // Signed distance to the surface: < 0 inside the body, > 0 outside (a cavity's void is
  // outside), 0 on it. Exact for the SES, SAS and vdW surfaces where |value| <= reach() (see
  // above for where beyond); for the skin, exact where |value| <= reach() and an estimate
  // with the exact sign farther. Far away the sign is still right.
  virtual double signedDistance(const glm::dvec3& x) const = 0;
  // The nearest surface point to x, for x with |signedDistance(x)| <= reach(). |x − point| is
  // always an upper bound on the distance from x to the surface (point is on the surface).
  virtual SurfacePoint closest(const glm::dvec3& x) const = 0;
  // An upper bound on the distance to the surface of every point of the triangle (a, b, c),
  // whose corners lie on the surface (to ~1e-9 Å), from the shape of the one patch that holds
  // all three corners when that patch provably holds the projection of the whole triangle (SES:
  // a convex sphere clear of its neighbours' caps, an unclipped concave triangle, a torus away
  // from its boundary); +inf when it cannot tell (corners on different patches or near a
  // patch's border, a surface kind that has no such bound). The mesher takes it instead of
  // sampling closest() over the triangle: a few queries in place of hundreds.
  virtual double patchDeviation(const glm::dvec3& a, const glm::dvec3& b, const glm::dvec3& c) const;
  // Within this distance of the surface the two calls above are exact (Å); meshing grids
  // must be finer than it. SES rp, SAS and vdW the smallest sphere radius, skin half the
  // smallest atom radius.
  virtual double reach() const = 0;
  // An axis-aligned box that contains the whole surface.
  virtual glm::dvec3 boundsMin() const = 0;
  virtual glm::dvec3 boundsMax() const = 0;
};

// The field of `patches` (SES, skin, vdW or SAS), made from the molecule's atom centres and
// radii (the patch list's own radii: as the build used them). std::invalid_argument when the
// counts differ from patches.params.atomCount.
std::unique_ptr<SurfaceDistance> makeSurfaceDistance(const PatchList& patches,
                                                     std::span<const glm::dvec3> centers,
                                                     std::span<const double> radii);

}  // namespace surftrace::build::mesh

// The mesher: a closed, outward-oriented triangle mesh of an exact surface (a SurfaceDistance),
// with every vertex on the surface and a certified bound on its deviation from it.
#pragma once

#include <cstddef>
#include <functional>
#include <optional>
#include <span>
#include <string>
#include <vector>

#include <glm/vec3.hpp>

#include "build/mesh/surface_distance.hpp"
#include "build/mesh/triangle_mesh.hpp"
#include "build/patch_list.hpp"

namespace surftrace::build::mesh {

// A place where the surface is thinner than the grid may show (a neck, a gap, a tunnel or a
// wall of width `size` Å about `point`): the tetrahedra that hold it are bisected until their
// edges are below `size` before marching, so that the piece is not pinched off or closed over.
struct ThinFeature {
  glm::dvec3 point{0.0};
  double size = 0.0;
};

struct MeshParams {
  double maxError = 0.1;     // ε (Å): the certified bound every triangle must meet
  std::vector<ThinFeature> features;  // see ThinFeature; thinFeatures gives them for a patch list
  // Also search grid edges whose ends differ in sign for further crossings, and bisect the
  // tetrahedra whose marched triangles fold against the surface: for a smooth surface (the
  // skin). On the SES's cusps and ridges the folds are the surface's own and bisecting them
  // only splits off slivers.
  bool followFolds = false;
  double gridSpacing = 0.5;  // h (Å) of the marching-tetrahedra grid; < the field's reach()
  int maxRounds = 40;        // refinement rounds before giving up (a cusp: no bound shrinks)
  // Called with the fraction done (0..1) between the stages; may be empty.
  std::function<void(double)> progress;
};

struct MeshResult {
  TriangleMesh mesh;
  double certifiedError = 0.0;  // max over triangles of the certified deviation bound (Å)
  std::size_t gridCells = 0;    // cells of the sparse grid the surface crosses
  // Cells split into smaller tetrahedra because the body or the solvent is thinner than the
  // grid there (an edge crosses the surface twice with both ends on one side).
  std::size_t refinedCells = 0;
  int rounds = 0;               // refinement rounds taken
  // Triangles left facing against the surface's normals (or of no area) that no collapse
  // could remove: 0 in every mesh the tests have seen; the command reports any.
  std::size_t badTriangles = 0;
};

// Meshes the surface of `field`. `seeds` are points on or near the surface, at least one near
// each of its components (surfaceSeeds gives them for a patch list): the grid is walked from
// them over the cells the surface crosses, so a component with no seed near it is left out.
// Marching tetrahedra (Kuhn's six tetrahedra per cube, so neighbouring cubes' faces match) on
// the grid's values gives a closed manifold mesh; its vertices are the roots of the field on
// grid edges, projected onto the surface with closest(). Then the longest edge of every
// triangle whose certified bound exceeds ε is split (midpoint projected, both triangles of the
// edge split) until every triangle passes. The certified bound of a triangle is the field's
// patchDeviation where it has one (the corners on one sphere or torus patch, bounded from its
// curvature), else
//   max over samples s of |s − closest(s).point|  +  the farthest any point of the triangle
//   lies from its nearest sample,
// an upper bound of its distance to the surface because that distance is 1-Lipschitz.
// std::invalid_argument for ε <= 0, h <= 0 or h >= reach(); std::runtime_error naming the
// place when a triangle cannot be certified within maxRounds.
MeshResult meshSurface(const SurfaceDistance& field, std::span<const glm::dvec3> seeds, const MeshParams& params);

// Points near the surface of `patches`, several on each patch (the contact circles of tori,
// the corners of concave triangles, points on spheres and skin quadrics): seeds for
// meshSurface that reach every component.
std::vector<glm::dvec3> surfaceSeeds(const PatchList& patches);

// The certified deviation bound of one triangle (Å) whose corners are on the surface: the
// field's patchDeviation when it has one (no sampling), else from
// samples no farther than `samplingRadius` from any point of it; +inf when that needs more than
// 32 samples per edge. Sampling stops as soon as the bound exceeds `giveUpAbove` (the value
// returned is then above it, not the triangle's whole bound).
double certifiedDeviation(const SurfaceDistance& field, const glm::dvec3& a, const glm::dvec3& b,
                          const glm::dvec3& c, double samplingRadius, double giveUpAbove = 1e300);

// Where the refinement splits the mesh edge (p, q) whose vertices have the normals np, nq: the
// surface point on the line through the edge's midpoint along np + nq that is nearest to the
// midpoint. Projecting the midpoint to its nearest surface point instead stalls at grooves: an
// edge bridging a narrow one (a vdW crease, a skin neck) has a midpoint nearest to a rim, so its
// halves bridge the groove as before, forever; along the normal the new vertex goes down into
// it. Falls back to the nearest surface point of the midpoint (within half an edge, since the
// ends are on the surface) when the line meets no surface within one edge length of the
// midpoint (a normal sum near zero: a sharp fold; or a line that misses this part of the
// surface: a crossing farther away makes triangles larger than the one split, and on 1AON's
// SES some 5 Å away, too large to certify) or is too nearly tangent to reach it in a bounded
// number of steps. The result is on the surface where the
// field's roots are (to ~1e-13 in value); the mesher projects it with closest().
glm::dvec3 splitPoint(const SurfaceDistance& field, const glm::dvec3& p, const glm::dvec3& q, const glm::dvec3& np,
                      const glm::dvec3& nq);

// Where the refinement splits a mesh edge (p, q) whose corner normals np, nq are more than 90°
// apart: an edge across a crease of the surface (a knife-edge ridge where two concave patches
// clip each other, a cusp), which splitPoint cannot shrink, since its split point lands on one
// side and leaves a triangle across the crease as wide as before. The lines along np + nq
// from the edge's points are traced to the surface; the point of the edge where their surface
// points change from p's side (normal nearer np) to q's is found by bisection, and the
// surface point there is on the crease (its two sides' points within 1e-6 edge lengths). Its
// normal is the mean of the two sides'. Nothing when the traces miss the surface, the sides do
// not change between the edge's quarter and three-quarter points, or the point is an end.
std::optional<SurfacePoint> creasePoint(const SurfaceDistance& field, const glm::dvec3& p, const glm::dvec3& q,
                                        const glm::dvec3& np, const glm::dvec3& nq);

// The skin's places thinner than `gridSpacing` (empty for the other surfaces): the centres of
// its hyperboloid patches, from the patch's weight w = constant / (s(1 − s)): an edge's
// one-sheet hyperboloid (w < 0) is a neck of the body 2√(s|w|) wide at its waist, its two
// sheets (w > 0) face each other across a gap 2√((1 − s)w) wide; a triangle's one sheet
// (w > 0) is a tunnel of solvent 2√((1 − s)w) wide, its two sheets (w < 0) a wall of body
// 2√(s|w|) thick; a tetrahedron's concave sphere (w > 0) a void 2√((1 − s)w) across.
std::vector<ThinFeature> thinFeatures(const PatchList& patches, double gridSpacing);

// One closed piece of a mesh (a connected component over shared vertices).
struct MeshComponent {
  std::size_t vertices = 0, edges = 0, triangles = 0;
  long long euler = 0;          // V − E + F: 2 for a sphere, 0 for a torus
  double area = 0.0;            // Å²
  double volume = 0.0;          // signed (Å³): > 0 an outer surface, < 0 a cavity
  std::uint32_t surfaceComponent = 0;  // the field's component of its first vertex (mesh.component)
  bool closed = true;           // every edge in exactly two triangles, in opposite directions
};
// The connected components of `mesh`, in the order of their first triangle.
std::vector<MeshComponent> meshComponents(const TriangleMesh& mesh);

// The triangles of `mesh` whose connected component is kept (keep[c] for the components of
// meshComponents), with only the vertices they use.
TriangleMesh keepComponents(const TriangleMesh& mesh, const std::vector<bool>& keep);

}  // namespace surftrace::build::mesh

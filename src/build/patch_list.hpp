// The patch list: the one plain-data contract between build, trace and gl.
//
// One struct-of-arrays per patch kind, fixed-width fields, indices instead of pointers.
// Every array of a kind has the same length (checked by PatchList::validate()). Angles
// are radians, lengths Å. Formulas: shared ORACLES.md sections A.3-A.5 and C.
#pragma once

#include <cstdint>
#include <string>
#include <utility>
#include <vector>

#include <glm/vec3.hpp>
#include <glm/vec4.hpp>

namespace surftrace::build {

enum class SurfaceKind : std::uint32_t { Ses = 0, Mss = 1, Vdw = 2, Sas = 3 };
const char* surfaceKindName(SurfaceKind kind);

// What a patch list was built from; stored in the file so it can be checked against.
struct SurfaceParams {
  SurfaceKind surface = SurfaceKind::Ses;
  double probeRadius = 1.4;      // SES/SAS
  double shrinkFactor = 0.5;     // MSS
  std::string radiiSet;          // "bondi", "file", "table:<path>"
  std::uint32_t inputCrc32 = 0;  // CRC-32 of the input structure file
  std::uint32_t atomCount = 0;
};

// SES convex patch of atom `atom`: the part of its vdW sphere outside the SAS contour.
// Renderers draw the whole sphere: the hidden part is enclosed by the surface
// (Lindow et al. 2010, Sect. 5.2). The patch's own area is stored for area reports.
struct ConvexSpheres {
  std::vector<glm::dvec3> center;
  std::vector<double> radius;
  std::vector<std::uint32_t> atom;
  std::vector<std::uint32_t> component;  // SES component (0 = an outer surface), its atom's lowest
  std::vector<double> area;              // exact area of the exposed part, Å²
  std::vector<glm::dvec3> vectorArea;    // ∫ u dΩ over the exposed part of the unit sphere (volumes)

  std::size_t size() const { return center.size(); }
};

// SES saddle: the part of the torus (centre, axis, big radius R, tube radius rp) between
// the contact circles on atoms i and j, θ ∈ [thetaI, thetaJ] (ORACLES A.3: θ = 0 points
// from the probe towards the axis), swept over φ ∈ [0, phiExtent] from the direction
// `e1` about `axis` (φ grows from e1 towards axis × e1). A spindle torus (R < rp) keeps
// only |θ| >= acos(R/rp); its cusps sit at centre ± sqrt(rp² − R²) axis.
struct Tori {
  std::vector<glm::dvec3> center;   // c_ij
  std::vector<glm::dvec3> axis;     // unit, from atom i to atom j
  std::vector<glm::dvec3> e1;       // unit, ⊥ axis: φ = 0
  std::vector<double> bigRadius;    // R = ρ_ij
  std::vector<double> thetaI;       // θ_i = atan2(−t, R)
  std::vector<double> thetaJ;       // θ_j = atan2(d − t, R)
  std::vector<double> phiExtent;    // (0, 2π]; 2π is a full ring
  std::vector<std::uint32_t> atomI;
  std::vector<std::uint32_t> atomJ;
  std::vector<std::uint32_t> component;

  std::size_t size() const { return center.size(); }
};

// SES concave spherical triangle: the probe sphere (centre `probe`, radius rp) inside the
// cone spanned by the unit contact directions u_i, u_j, u_k (ORACLES A.4), minus the caps
// cut off by its clipping planes clipPlanes[clipBegin, clipBegin + clipCount) (A.5).
struct ConcaveTriangles {
  std::vector<glm::dvec3> probe;
  std::vector<glm::dvec3> dirI, dirJ, dirK;  // (c_m − p)/|c_m − p|
  std::vector<std::uint32_t> atomI, atomJ, atomK;
  std::vector<std::uint32_t> clipBegin;
  std::vector<std::uint32_t> clipCount;
  std::vector<std::uint32_t> component;

  std::size_t size() const { return probe.size(); }
};

// MSS patch (ORACLES C.3, C.4): the skin quadric of one Delaunay simplex X inside its mixed
// cell μ_X = (1 − s) δ_X + s ν_X, built by src/build/mss/. The quadric is
//   f(x) = radialCoeff·|x − z|² + axialCoeff·((x − z)·axis)² + constant,   f < 0 inside the body,
// with f = (1 − s)·G(x) for the skin function G of ORACLES D.3, so it is continuous across
// cells; `center` is the orthocentre z_X. The cell is the intersection of the half-spaces
// cellPlanes[cellBegin, cellBegin + cellCount) (n·x + d <= 0); planes that cannot meet the skin
// of the patch are left out, and two cells that share a facet store that plane bit for bit
// negated. Every skin point of the patch lies within boundRadius of `center`.
//   Convex  (vertex i)      sphere, radius r_i              radial 1 − s, axial 0
//   Edge    (edge i j)      hyperboloid about the edge      radial 1 − s, axial −1
//           (one sheet when w_X < 0, two when w_X > 0, the double cone at w_X = 0)
//   Face    (triangle)      hyperboloid about its normal    radial −s, axial 1
//   Concave (tetrahedron)   sphere, radius √((1 − s) w_X)   radial −s, axial 0
// For Edge and Face patches the cell is a prism along `axis`: planes with normal ±axis cap it,
// the others contain the axis direction. The patches are grouped by kind, in MssKind order
// (validate() checks it): mssKindRange gives each kind's range.
enum class MssKind : std::uint32_t { Convex = 0, Edge = 1, Face = 2, Concave = 3 };
// The skin's kinds, one row each in MssKind order: counts, names and the rows of the kind
// tables of the renderers (view::kPatchKinds, trace/patch_kinds.hpp, gl/gpu_kinds.hpp) follow it.
struct MssKindInfo {
  MssKind kind;
  const char* name;     // "convex", "edge", "face", "concave"
  const char* patches;  // what its patches are, for people
};
inline constexpr MssKindInfo kMssKinds[] = {
    {MssKind::Convex, "convex", "atom spheres"},
    {MssKind::Edge, "edge", "hyperboloids of Delaunay edges"},
    {MssKind::Face, "face", "hyperboloids of Delaunay triangles"},
    {MssKind::Concave, "concave", "spheres of Delaunay tetrahedra"},
};
inline constexpr std::size_t kMssKindCount = sizeof(kMssKinds) / sizeof(kMssKinds[0]);
struct MssQuadrics {
  std::vector<std::uint32_t> kind;     // MssKind: the simplex has kind + 1 atoms
  std::vector<glm::dvec3> center;      // z_X
  std::vector<glm::dvec3> axis;        // unit; (0, 0, 1) for the spheres
  std::vector<double> radialCoeff;
  std::vector<double> axialCoeff;
  std::vector<double> constant;        // s(1 − s) w_X
  std::vector<double> boundRadius;     // Å
  std::vector<glm::uvec4> atoms;       // the simplex, ascending; unused slots ~0u
  std::vector<std::uint32_t> cellBegin;
  std::vector<std::uint32_t> cellCount;

  std::size_t size() const { return kind.size(); }
};

// The patches [first, second) of one kind (the list is grouped by kind).
std::pair<std::size_t, std::size_t> mssKindRange(const MssQuadrics& mss, MssKind kind);

// The weighted points the skin was built from, one per atom of the list (index = atom id):
// centre z_i = c_i and weight w_i = r_i²/s (ORACLES C.1). The renderers need them to name the
// atom whose ball owns a skin point (trace/mss_patch.hpp skinOwner), which a patch's quadric
// alone does not tell. Empty for the other surfaces, and where not known (a version 2 file, a
// list not made by the builder): a skin point then belongs to its simplex's lowest atom.
struct SkinAtoms {
  std::vector<glm::dvec3> center;
  std::vector<double> weight;

  std::size_t size() const { return center.size(); }
};


// A half-space n·x + d <= 0 (xyz = n, unit; w = d): the side that is kept.
using Plane = glm::dvec4;

struct PatchList {
  SurfaceParams params;
  ConvexSpheres convex;
  Tori tori;
  ConcaveTriangles concave;
  std::vector<Plane> clipPlanes;   // concave self-intersection planes
  MssQuadrics mss;
  std::vector<Plane> cellPlanes;   // MSS mixed-cell faces
  // Per cell plane of patch X, the atom a across it: the neighbouring cell is that of X ∖ {a}
  // (a ∈ X) or X ∪ {a}; the plane is mss::cellPlane(X, a), which the file stores instead of
  // the plane. ~0u: not known (a list from an older file, or one not made by the builder).
  std::vector<std::uint32_t> cellPlaneAtom;
  SkinAtoms skinAtoms;             // MSS: empty or params.atomCount of them
  std::uint32_t componentCount = 0;

  std::size_t patchCount() const {
    return convex.size() + tori.size() + concave.size() + mss.size();
  }
  // An empty list that keeps the memory of its arrays, for builders that refill one list
  // frame after frame (no allocation, no page faults once it has held the largest frame).
  void clearKeepingMemory();
  // Throws std::runtime_error naming the first field ("tori.axis[17] = (0, 0, 0) ...") that is
  // outside what the builders write: arrays of one kind differ in length; a value is not
  // finite; a probe radius or shrink factor is outside its option's range; a kind of patch
  // the surface does not have; a coordinate or length beyond 1e9 Å, a radius <= 0 or a
  // length < 0 (an SES probe above 2^19 times a convex radius, as the builder refuses); a unit vector (axis, e1, direction, plane normal) off length 1 by over 1e-6;
  // an angle outside its range (θ in [−π/2, π/2], θi <= θj, φ extent in (0, 2π]); a convex
  // area outside [0, 4πr²] or a vector area longer than π; an MSS coefficient that is not
  // its kind's; an atom >= params.atomCount, a torus with atomI >= atomJ, a triangle repeating
  // an atom, a component >= componentCount or one below it that no patch carries, a plane range
  // past its array, MSS kinds out of order or a simplex not ascending with unused slots ~0u;
  // skin atoms neither none nor params.atomCount of them, or a weight outside [0, 1e18] Å².
  void validate() const;
};

// Every array of the patch list, by kind (`group`, whose arrays share one length) and name,
// visited in lockstep in one or more lists: visit(group, name, array...). Writing, reading,
// validation, filtering and the tests' comparisons all walk this one list, so a field added
// to a kind above and here is stored, loaded, checked and compared.
template <class Visit, class... Lists>
void forEachArray(Visit&& visit, Lists&... p) {
  visit("convex", "center", p.convex.center...);
  visit("convex", "radius", p.convex.radius...);
  visit("convex", "atom", p.convex.atom...);
  visit("convex", "component", p.convex.component...);
  visit("convex", "area", p.convex.area...);
  visit("convex", "vectorArea", p.convex.vectorArea...);
  visit("tori", "center", p.tori.center...);
  visit("tori", "axis", p.tori.axis...);
  visit("tori", "e1", p.tori.e1...);
  visit("tori", "bigRadius", p.tori.bigRadius...);
  visit("tori", "thetaI", p.tori.thetaI...);
  visit("tori", "thetaJ", p.tori.thetaJ...);
  visit("tori", "phiExtent", p.tori.phiExtent...);
  visit("tori", "atomI", p.tori.atomI...);
  visit("tori", "atomJ", p.tori.atomJ...);
  visit("tori", "component", p.tori.component...);
  visit("concave", "probe", p.concave.probe...);
  visit("concave", "dirI", p.concave.dirI...);
  visit("concave", "dirJ", p.concave.dirJ...);
  visit("concave", "dirK", p.concave.dirK...);
  visit("concave", "atomI", p.concave.atomI...);
  visit("concave", "atomJ", p.concave.atomJ...);
  visit("concave", "atomK", p.concave.atomK...);
  visit("concave", "clipBegin", p.concave.clipBegin...);
  visit("concave", "clipCount", p.concave.clipCount...);
  visit("concave", "component", p.concave.component...);
  visit("clipPlanes", "plane", p.clipPlanes...);
  visit("mss", "kind", p.mss.kind...);
  visit("mss", "center", p.mss.center...);
  visit("mss", "axis", p.mss.axis...);
  visit("mss", "radialCoeff", p.mss.radialCoeff...);
  visit("mss", "axialCoeff", p.mss.axialCoeff...);
  visit("mss", "constant", p.mss.constant...);
  visit("mss", "boundRadius", p.mss.boundRadius...);
  visit("mss", "atoms", p.mss.atoms...);
  visit("mss", "cellBegin", p.mss.cellBegin...);
  visit("mss", "cellCount", p.mss.cellCount...);
  visit("cellPlanes", "plane", p.cellPlanes...);
  visit("cellPlanes", "atom", p.cellPlaneAtom...);
  visit("skinAtoms", "center", p.skinAtoms.center...);
  visit("skinAtoms", "weight", p.skinAtoms.weight...);
}

// A cylinder about MSS patch k's axis that holds the patch: h = (x − center)·axis in
// [hLo, hHi] (the caps' planes and the bounding ball) and distance from the axis at most rho
// (the quadric's largest radius over that range, and the ball). What the renderers bound and
// rasterise.
struct MssExtent {
  double hLo, hHi, rho;
};
MssExtent mssExtent(const PatchList& list, std::size_t k);

}  // namespace surftrace::build

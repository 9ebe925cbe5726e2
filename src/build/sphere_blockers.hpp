// Which atoms can hide part of a whole convex sphere: the hidden part of the spheres that
// renderers draw whole, data of the patch list that the Embree and GL engines share.
#pragma once

#include <cstdint>
#include <span>
#include <vector>

#include <glm/vec2.hpp>
#include <glm/vec3.hpp>
#include <glm/vec4.hpp>

#include "build/patch_list.hpp"

namespace surftrace::build {

// A torus's arc of probe centres, c + R (cos φ e1 + sin φ e2) for φ in [0, extent]: where the
// grown spheres of its two atoms meet, the edge of both atoms' convex patches (on the grown
// spheres).
struct SaddleArc {
  glm::dvec3 center, e1, e2;
  double radius = 0.0, extent = 0.0;
};

// The whole spheres of a patch list draw their hidden part too: fine for the nearest hit, but a
// transparent surface would show it. A hit x on sphere i (centre c, radius ρ) is on its convex
// patch iff the point y = c + (ρ + g)/ρ (x − c) lies outside the grown sphere (r_k + h) of every
// other atom k: for the SES g = h = rp (y is then a point of the SAS, ORACLES D.1); for the vdW
// balls g = h = 0, for the SAS balls (ρ = r + rp) g = 0, h = rp (x is on the union's boundary).
// Skin spheres are clipped by their mixed cells already.
//
// `atoms` (centre, vdW radius) are every atom of the structure. Without them (a patch-list file
// alone) the spheres themselves stand in: complete for vdW and SAS, but the SES list has spheres
// of exposed atoms only, so a part of a sphere that only buried atoms hide then shows. With
// --drop-cavities the builder keeps a sphere that lines both the outer surface and a cavity
// whole; its cavity side, whose tori and concave triangles are gone, would be a piece of surface
// with an open edge, which a ray crosses once (an odd number of crossings): the saddle arcs
// below tell the parts of a sphere that the list keeps from those it dropped.
struct SphereBlockers {
  double grow = 0.0;                     // g
  std::vector<glm::dvec4> blockers;      // centre, grown radius r_k + h
  // CSR: blockers list[begin[i], begin[i + 1]) may hide sphere i, nearest (centre distance
  // minus grown radius) first, ties by index.
  std::vector<std::uint32_t> begin;
  std::vector<std::uint32_t> list;
  // SES with its atoms only (else empty): CSR, arcs[arcBegin[i], arcBegin[i + 1]) are the arcs
  // of probe centres of the list's saddles (tori) of sphere i's atom, on its grown sphere, for
  // the spheres whose edge they leave partly open (addSaddleArcs).
  std::vector<std::uint32_t> arcBegin;
  std::vector<SaddleArc> arcs;
};

// The blockers of each sphere (`centers`, `radii`, `sphereAtoms`: the list's convex spheres)
// of a surface `params` describes. Spheres and blockers meet iff their centres are closer than
// ρ_i + g + r_k + h; a sphere's own atom never blocks it.
SphereBlockers sphereBlockers(const SurfaceParams& params, std::span<const glm::dvec3> centers,
                              std::span<const double> radii, std::span<const std::uint32_t> sphereAtoms,
                              std::span<const glm::dvec4> atoms);
// With `atoms`, an SES list's blockers come with its saddle arcs (addSaddleArcs).
SphereBlockers sphereBlockers(const PatchList& list, std::span<const glm::dvec4> atoms);

// Adds the saddle arcs (`arcAtoms`: the torus's two atoms) to the spheres (`centers`, `radii`,
// `sphereAtoms`: those sphereBlockers was given) of their atoms; onConvexPatch then keeps a
// sphere's point only on a part of the sphere that one of them bounds (see there). Only the
// spheres whose free part has an edge on no arc keep theirs (the others need no test), and
// arcBegin stays empty when no sphere has one.
void addSaddleArcs(SphereBlockers& b, std::span<const glm::dvec3> centers, std::span<const double> radii,
                   std::span<const std::uint32_t> sphereAtoms, std::span<const SaddleArc> arcs,
                   std::span<const glm::uvec2> arcAtoms);

// addSaddleArcs in two steps, for a caller that only ever asks about some spheres (a transparent
// frame's rays meet a fraction of them): attachSaddleArcs gives every sphere all its arcs, and
// freeEdgeCovered(b, i, ...) says whether sphere i is one addSaddleArcs would have left without
// arcs (every edge of its free part on an arc; `grown` = ρ_i + g). onConvexPatch with
// `keptPartTest` = !freeEdgeCovered then answers as after addSaddleArcs, bit for bit.
void attachSaddleArcs(SphereBlockers& b, std::span<const std::uint32_t> sphereAtoms, std::span<const SaddleArc> arcs,
                      std::span<const glm::uvec2> arcAtoms);
bool freeEdgeCovered(const SphereBlockers& b, std::uint32_t i, const glm::dvec3& c, double grown);

// Whether the point x of sphere i (centre c, radius ρ) is on its convex patch: outside every
// grown blocker of i, points within a relative `tolerance` of a blocker's sphere counting as
// outside it. With saddle arcs, also on a part of the free sphere (the grown sphere minus the
// blockers) that the list keeps: the nearest point of the part's edge to y is the nearest point
// of any blocker's circle (a nearer edge point would be a nearer circle point), and that edge is
// in the list iff a saddle arc of the sphere's atom passes there. A sphere whose atom has no
// saddle arc is kept whole.
bool onConvexPatch(const SphereBlockers& b, std::uint32_t i, const glm::dvec3& c, double rho, const glm::dvec3& x,
                   double tolerance, bool keptPartTest = true);

// Distance from the point x of sphere i (on its convex patch) to the patch's edge: to the
// nearest circle in which a grown blocker cuts the grown sphere, mapped back to sphere i (a
// lower bound, exact where that circle's nearest point is on the edge). For the SES these are
// the contact circles of the tori; +inf for a sphere that no blocker cuts.
double convexPatchEdgeDistance(const SphereBlockers& b, std::uint32_t i, const glm::dvec3& c, double rho,
                               const glm::dvec3& x);

}  // namespace surftrace::build

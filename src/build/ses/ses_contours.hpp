// SES contour pass: exposed arcs, tori, convex patch areas and the faces of each atom's exposed region.
#pragma once

#include <cstdint>
#include <span>

#include <glm/vec3.hpp>

#include "build/ses/ses_types.hpp"

namespace surftrace::build::detail {

// What the contour pass reads: the vertices and free circles, and who touches them.
struct Incidence {
  std::span<const glm::dvec3> probe;
  std::span<const std::uint32_t> atomI, atomJ, atomK;
  std::span<const std::uint8_t> plus;
  std::span<const std::uint8_t> edges;    // per concave patch: its boundary edges (merged vertices)
  std::span<const std::uint32_t> group;   // per concave patch: distance back to its merged vertex's first
  std::span<const std::uint32_t> vertexBegin, vertex;  // per atom: concave indices
  std::span<const std::uint32_t> freeBegin, free;      // per atom: other atom of free circles
  std::span<const CapState> capState;
  // Written by each atom's contour pass at its own places: the face (of its exposed
  // region, see contourPass) that each incident vertex and free circle bounds, the
  // number of faces, and for the atom `extremeAtom` the face facing +x.
  std::span<std::uint32_t> vertexFace, freeFace, faceCount;
  std::uint32_t extremeAtom;
  std::uint32_t* extremeFace;
};

// The contour pass of atom x: its convex patch and the tori of its circles (atom x the
// lower atom) into out (with one convexCount and toriCount entry); its faces into inc.
void contourPass(const Atoms& a, const Incidence& inc, std::uint32_t x, Scratch& s, ContourBuf& out);

}  // namespace surftrace::build::detail

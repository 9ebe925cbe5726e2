// A triangle mesh: what `compare` reads from other programs and what `mesh` writes of the exact
// surface. Plain data, indices instead of pointers, like the patch list.
#pragma once

#include <cstdint>
#include <string>
#include <vector>

#include <glm/vec3.hpp>

namespace surftrace::build::mesh {

struct TriangleMesh {
  std::vector<glm::dvec3> positions;   // Å
  std::vector<glm::uvec3> triangles;   // counter-clockwise seen from outside (outward normal)
  // Optional per-vertex arrays: empty, or one entry per position.
  std::vector<glm::dvec3> normals;     // unit, outward
  std::vector<std::uint32_t> atom;     // the atom that owns the surface point (0-based, file order)
  std::vector<std::uint8_t> kind;      // patch kind, in the codes of the `patch.kind` channel
                                       // (view::PatchKind: 1 convex ... 7 skin concave)
  std::vector<std::uint32_t> component;  // surface component (0 = an outer surface)

  std::size_t vertexCount() const { return positions.size(); }
  std::size_t triangleCount() const { return triangles.size(); }
};

}  // namespace surftrace::build::mesh

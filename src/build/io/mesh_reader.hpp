// Triangle meshes from other programs (OBJ, PLY, STL, OFF, glTF/GLB), read through Assimp into
// the plain TriangleMesh that `compare` draws along a reference's rays.
#pragma once

#include <string>

#include <glm/mat4x4.hpp>

#include "build/mesh/triangle_mesh.hpp"

namespace surftrace::build {

// Whether `path` names a mesh by its extension (case-insensitive): .obj, .ply, .stl, .off,
// .gltf, .glb. How `compare` tells a mesh from an image or a structure before reading it.
bool isMeshPath(const std::string& path);

// The mesh in `path`: every face triangulated, vertices with identical positions (and normals,
// when the file has them) joined, all of the file's meshes in one (glTF's node transforms
// applied). Vertex normals are kept when the file has them (STL's facet normals are not vertex
// normals and are dropped); they are normalised. Positions are what Assimp holds: single
// precision. Throws InputError naming the file when Assimp cannot read it, when it holds no
// triangle (points or lines only, or nothing), or when a position is not finite (naming the
// triangle and the value).
mesh::TriangleMesh readMesh(const std::string& path);

// The affine map `--mesh-transform` gives: `text` names a file holding 16 numbers (separated by
// white space or commas), or is itself 16 comma-separated numbers: the 4x4 matrix row by row,
// acting on column vectors (x' = M·(x, y, z, 1)), its last row 0 0 0 1. Throws InputError
// naming the file (and the line) or the option, and what is wrong: not a number, not 16 of
// them, a last row other than 0 0 0 1, a singular 3x3 part.
glm::dmat4 parseMeshTransform(const std::string& text);

// The mesh moved by `m` (affine): positions by m, normals by the inverse transpose of its 3x3
// part (then normalised); a mirroring m (negative determinant) also reverses each triangle's
// corners, so that counter-clockwise still means outward.
void transformMesh(mesh::TriangleMesh& mesh, const glm::dmat4& m);

}  // namespace surftrace::build

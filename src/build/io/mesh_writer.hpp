// Mesh files SurfTrace writes: PLY, OBJ and GLB of a TriangleMesh, with the per-vertex data
// (normals, atom ids, patch kinds, components) each format carries.
#pragma once

#include <filesystem>
#include <string>

#include "build/mesh/triangle_mesh.hpp"

namespace surftrace::build {

enum class MeshFormat { Ply, Obj, Glb };

// The format a path's extension names (.ply, .obj, .glb; any case); std::invalid_argument
// naming the path and the extensions known otherwise.
MeshFormat meshFormatOf(const std::filesystem::path& path);

// The file's bytes.
// PLY: binary little-endian; vertex x y z (double), nx ny nz (float), atom_id (uint),
//      patch_kind (uchar), component (uint); face vertex_indices (list uchar uint).
// OBJ: v (17 significant digits), vn, and f v//vn; text, no per-vertex ids (OBJ has no place
//      for them).
// GLB: glTF 2.0 binary, one mesh: POSITION and NORMAL (float), indices (uint), and the
//      application attributes _ATOM_ID, _PATCH_KIND and _COMPONENT (float, exact up to 2^24).
std::string meshFileBytes(const mesh::TriangleMesh& mesh, MeshFormat format);

// Writes `mesh` to `path` in the format of its extension, whole or not at all (output_file.hpp).
void writeMesh(const std::filesystem::path& path, const mesh::TriangleMesh& mesh);

}  // namespace surftrace::build

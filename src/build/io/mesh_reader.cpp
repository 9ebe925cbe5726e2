// Meshes through Assimp (mesh_reader.hpp): its importers for the formats, our own joining of
// vertices across the file's meshes and our own checks on what they hold.
#include "build/io/mesh_reader.hpp"

#include <algorithm>
#include <array>
#include <cctype>
#include <cmath>
#include <cstdint>
#include <cstdio>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <unordered_map>

#include <assimp/Importer.hpp>
#include <assimp/postprocess.h>
#include <assimp/scene.h>
#include <glm/mat3x3.hpp>
#include <glm/matrix.hpp>

#include "build/io/error.hpp"

namespace surftrace::build {
namespace {

std::string lowerExtension(const std::string& path) {
  std::string ext = std::filesystem::path(path).extension().string();
  std::transform(ext.begin(), ext.end(), ext.begin(), [](unsigned char c) { return static_cast<char>(std::tolower(c)); });
  return ext;
}

// A vertex as the join sees it: its position and normal, bit for bit (−0 taken as +0).
struct VertexKey {
  std::array<std::uint64_t, 6> bits{};
  bool operator==(const VertexKey&) const = default;
};
struct VertexKeyHash {
  std::size_t operator()(const VertexKey& k) const {
    std::uint64_t h = 1469598103934665603ull;
    for (const std::uint64_t b : k.bits) h = (h ^ b) * 1099511628211ull, h ^= h >> 29;
    return static_cast<std::size_t>(h);
  }
};
std::uint64_t bitsOf(double v) {
  v += 0.0;  // −0 -> +0
  std::uint64_t b;
  std::memcpy(&b, &v, sizeof b);
  return b;
}

std::string point(const glm::dvec3& p) {
  char text[96];
  std::snprintf(text, sizeof text, "(%.9g, %.9g, %.9g)", p.x, p.y, p.z);
  return text;
}

}  // namespace

bool isMeshPath(const std::string& path) {
  const std::string ext = lowerExtension(path);
  for (const char* known : {".obj", ".ply", ".stl", ".off", ".gltf", ".glb"})
    if (ext == known) return true;
  return false;
}

mesh::TriangleMesh readMesh(const std::string& path) {
  std::error_code ec;
  if (!std::filesystem::is_regular_file(path, ec)) throw InputError(path, 0, "no such mesh file");
  Assimp::Importer importer;
  // Lines and points stay out of the triangle meshes (SortByPType), so that a file of lines
  // alone is "no triangles" rather than degenerate triangles; PreTransformVertices applies
  // glTF's node transforms, so that every mesh is in the file's one frame.
  const aiScene* scene = importer.ReadFile(
      path, aiProcess_Triangulate | aiProcess_SortByPType | aiProcess_PreTransformVertices);
  if (!scene) throw InputError(path, 0, std::string("cannot read the mesh: ") + importer.GetErrorString());
  // STL stores one normal per facet, which Assimp copies to the facet's corners: a face
  // normal, which the triangle's own winding gives anyway. Other formats' normals are the
  // author's vertex normals.
  const bool fileNormals = lowerExtension(path) != ".stl";
  bool normals = fileNormals;
  std::size_t triangles = 0, others = 0;
  for (unsigned m = 0; m < scene->mNumMeshes; ++m) {
    const aiMesh* mesh = scene->mMeshes[m];
    if (!(mesh->mPrimitiveTypes & aiPrimitiveType_TRIANGLE)) {
      others += mesh->mNumFaces;
      continue;
    }
    triangles += mesh->mNumFaces;
    normals = normals && mesh->HasNormals();
  }
  if (triangles == 0)
    throw InputError(path, 0, others > 0 ? "no triangles: the file holds " + std::to_string(others) + " points or lines only"
                                         : std::string("no triangles: the mesh is empty"));

  mesh::TriangleMesh out;
  std::unordered_map<VertexKey, std::uint32_t, VertexKeyHash> joined;
  std::size_t triangleNumber = 0;
  for (unsigned m = 0; m < scene->mNumMeshes; ++m) {
    const aiMesh* mesh = scene->mMeshes[m];
    if (!(mesh->mPrimitiveTypes & aiPrimitiveType_TRIANGLE)) continue;
    std::vector<std::uint32_t> index(mesh->mNumVertices, ~0u);  // the joined vertex of each of Assimp's
    for (unsigned f = 0; f < mesh->mNumFaces; ++f) {
      const aiFace& face = mesh->mFaces[f];
      ++triangleNumber;
      if (face.mNumIndices != 3) continue;  // SortByPType keeps triangles only here; stray points/lines
      glm::uvec3 t;
      for (int c = 0; c < 3; ++c) {
        const unsigned v = face.mIndices[c];
        if (index[v] == ~0u) {
          const aiVector3D& a = mesh->mVertices[v];
          const glm::dvec3 p(a.x, a.y, a.z);
          if (!std::isfinite(p.x) || !std::isfinite(p.y) || !std::isfinite(p.z))
            throw InputError(path, 0, "triangle " + std::to_string(triangleNumber) +
                                          " (counting from 1, after triangulation) has a vertex at " + point(p) +
                                          ": every position must be finite");
          glm::dvec3 n(0.0);
          if (normals) n = glm::dvec3(mesh->mNormals[v].x, mesh->mNormals[v].y, mesh->mNormals[v].z);
          const VertexKey key{{bitsOf(p.x), bitsOf(p.y), bitsOf(p.z), bitsOf(n.x), bitsOf(n.y), bitsOf(n.z)}};
          const auto [at, added] = joined.try_emplace(key, static_cast<std::uint32_t>(out.positions.size()));
          if (added) {
            out.positions.push_back(p);
            if (normals) out.normals.push_back(n);
          }
          index[v] = at->second;
        }
        t[c] = index[v];
      }
      // A triangle that joining made degenerate (two corners at one vertex) has no area to hit.
      if (t.x != t.y && t.y != t.z && t.z != t.x) out.triangles.push_back(t);
    }
  }
  if (out.triangles.empty()) throw InputError(path, 0, "no triangles: every triangle is degenerate (repeated vertices)");
  // A normal that cannot be made unit (zero, not finite) leaves the mesh to its face normals
  // everywhere: mixing the author's normals with ours would compare neither.
  for (glm::dvec3& n : out.normals) {
    const double len = std::sqrt(n.x * n.x + n.y * n.y + n.z * n.z);
    if (!(len > 0.0) || !std::isfinite(len)) {
      out.normals.clear();
      break;
    }
    n /= len;
  }
  return out;
}

glm::dmat4 parseMeshTransform(const std::string& text) {
  std::error_code ec;
  const bool file = std::filesystem::is_regular_file(text, ec);
  const std::string where = file ? text : std::string("--mesh-transform");
  std::vector<std::pair<double, int>> numbers;  // value, line
  auto parse = [&](const std::string& line, int lineNumber) {
    std::string field;
    std::istringstream in(line);
    std::string token;
    while (in >> token) {
      std::stringstream parts(token);
      while (std::getline(parts, field, ',')) {
        if (field.empty()) continue;
        char* end = nullptr;
        const double v = std::strtod(field.c_str(), &end);
        if (end != field.c_str() + field.size() || !std::isfinite(v))
          throw InputError(where, lineNumber, "'" + field + "' is not a finite number: a transform is 16 numbers, the 4x4 "
                                              "matrix row by row");
        numbers.emplace_back(v, lineNumber);
      }
    }
  };
  if (file) {
    std::ifstream in(text);
    if (!in) throw InputError(text, 0, "cannot open the transform file");
    std::string line;
    for (int n = 1; std::getline(in, line); ++n) parse(line, n);
  } else {
    if (text.find(',') == std::string::npos)
      throw InputError(where, 0, "'" + text + "' is neither a file nor 16 comma-separated numbers (the 4x4 matrix row by row)");
    parse(text, 0);
  }
  if (numbers.size() != 16)
    throw InputError(where, 0, std::to_string(numbers.size()) + " numbers; a transform is 16 (the 4x4 matrix row by row)");
  glm::dmat4 m(0.0);
  for (int r = 0; r < 4; ++r)
    for (int c = 0; c < 4; ++c) m[c][r] = numbers[static_cast<std::size_t>(4 * r + c)].first;  // glm: m[column][row]
  if (m[0][3] != 0.0 || m[1][3] != 0.0 || m[2][3] != 0.0 || m[3][3] != 1.0) {
    char row[160];
    std::snprintf(row, sizeof row, "the last row is %g %g %g %g; an affine transform's is 0 0 0 1 (the matrix is read row by row: "
                  "is it transposed?)", m[0][3], m[1][3], m[2][3], m[3][3]);
    throw InputError(where, numbers[12].second, row);
  }
  const double det = glm::determinant(glm::dmat3(m));
  if (!(std::abs(det) > 1e-12)) throw InputError(where, 0, "the 3x3 part is singular (determinant " + std::to_string(det) + ")");
  return m;
}

void transformMesh(mesh::TriangleMesh& mesh, const glm::dmat4& m) {
  const glm::dmat3 linear(m);
  const glm::dvec3 shift(m[3]);
  for (glm::dvec3& p : mesh.positions) p = linear * p + shift;
  const glm::dmat3 normalMap = glm::transpose(glm::inverse(linear));
  for (glm::dvec3& n : mesh.normals) n = glm::normalize(normalMap * n);
  if (glm::determinant(linear) < 0.0)
    for (glm::uvec3& t : mesh.triangles) std::swap(t.y, t.z);
}

}  // namespace surftrace::build

// Meshes read through Assimp (build/io/mesh_reader.hpp): one small mesh written by hand in every
// text and binary format (and by Assimp's own exporter for glTF and GLB) reads back as the same
// triangles; the errors name the file; --mesh-transform's parsing and its action on positions,
// normals and winding against formulas.
#include <algorithm>
#include <array>
#include <cmath>
#include <cstdint>
#include <cstring>
#include <fstream>
#include <string>
#include <vector>

#include <assimp/Exporter.hpp>
#include <assimp/scene.h>
#include <glm/geometric.hpp>
#include <gtest/gtest.h>

#include "build/io/error.hpp"
#include "build/io/mesh_reader.hpp"
#include "temp_dir.hpp"

namespace surftrace::build {
namespace {

std::string temp(const std::string& name) { return (test::testTempDir() / name).string(); }

// A closed octahedron stretched along each axis, outward (counter-clockwise from outside), with
// coordinates that floats hold exactly.
struct SmallMesh {
  std::vector<glm::dvec3> v = {{1.5, 0, 0}, {-1.25, 0, 0}, {0, 2.5, 0}, {0, -0.75, 0}, {0, 0, 3.0}, {0, 0, -0.5}};
  std::vector<glm::uvec3> f = {{0, 2, 4}, {2, 1, 4}, {1, 3, 4}, {3, 0, 4}, {2, 0, 5}, {1, 2, 5}, {3, 1, 5}, {0, 3, 5}};
};

// Triangles as position triples, each rotated to start at its smallest corner (orientation
// kept), sorted: what "the same triangles" means whatever order a reader numbers vertices in.
using Corners = std::array<std::array<double, 3>, 3>;
std::vector<Corners> canonical(const std::vector<glm::dvec3>& v, const std::vector<glm::uvec3>& f) {
  std::vector<Corners> out;
  for (const glm::uvec3& t : f) {
    Corners c;
    for (int k = 0; k < 3; ++k) c[static_cast<std::size_t>(k)] = {v[t[k]].x, v[t[k]].y, v[t[k]].z};
    std::rotate(c.begin(), std::min_element(c.begin(), c.end()), c.end());
    out.push_back(c);
  }
  std::sort(out.begin(), out.end());
  return out;
}

void writeText(const std::string& path, const std::string& text) { std::ofstream(path, std::ios::binary) << text; }

std::string objText(const SmallMesh& m) {
  std::string s = "# octahedron\n";
  for (const auto& p : m.v) s += "v " + std::to_string(p.x) + " " + std::to_string(p.y) + " " + std::to_string(p.z) + "\n";
  for (const auto& t : m.f) s += "f " + std::to_string(t.x + 1) + " " + std::to_string(t.y + 1) + " " + std::to_string(t.z + 1) + "\n";
  return s;
}

std::string offText(const SmallMesh& m) {
  std::string s = "OFF\n" + std::to_string(m.v.size()) + " " + std::to_string(m.f.size()) + " 0\n";
  for (const auto& p : m.v) s += std::to_string(p.x) + " " + std::to_string(p.y) + " " + std::to_string(p.z) + "\n";
  for (const auto& t : m.f) s += "3 " + std::to_string(t.x) + " " + std::to_string(t.y) + " " + std::to_string(t.z) + "\n";
  return s;
}

std::string plyAscii(const SmallMesh& m) {
  std::string s = "ply\nformat ascii 1.0\nelement vertex " + std::to_string(m.v.size()) +
                  "\nproperty float x\nproperty float y\nproperty float z\nelement face " + std::to_string(m.f.size()) +
                  "\nproperty list uchar int vertex_indices\nend_header\n";
  for (const auto& p : m.v) s += std::to_string(p.x) + " " + std::to_string(p.y) + " " + std::to_string(p.z) + "\n";
  for (const auto& t : m.f) s += "3 " + std::to_string(t.x) + " " + std::to_string(t.y) + " " + std::to_string(t.z) + "\n";
  return s;
}

template <class T> void put(std::string& s, T value) {
  char bytes[sizeof(T)];
  std::memcpy(bytes, &value, sizeof(T));  // little-endian on every machine this project builds for
  s.append(bytes, sizeof(T));
}

std::string plyBinary(const SmallMesh& m) {
  std::string s = "ply\nformat binary_little_endian 1.0\nelement vertex " + std::to_string(m.v.size()) +
                  "\nproperty float x\nproperty float y\nproperty float z\nelement face " + std::to_string(m.f.size()) +
                  "\nproperty list uchar int vertex_indices\nend_header\n";
  for (const auto& p : m.v) put(s, float(p.x)), put(s, float(p.y)), put(s, float(p.z));
  for (const auto& t : m.f) put(s, std::uint8_t{3}), put(s, std::int32_t(t.x)), put(s, std::int32_t(t.y)), put(s, std::int32_t(t.z));
  return s;
}

glm::dvec3 faceNormal(const SmallMesh& m, const glm::uvec3& t) {
  return glm::normalize(glm::cross(m.v[t.y] - m.v[t.x], m.v[t.z] - m.v[t.x]));
}

std::string stlAscii(const SmallMesh& m) {
  std::string s = "solid octahedron\n";
  for (const auto& t : m.f) {
    const glm::dvec3 n = faceNormal(m, t);
    s += "facet normal " + std::to_string(n.x) + " " + std::to_string(n.y) + " " + std::to_string(n.z) + "\n outer loop\n";
    for (int k = 0; k < 3; ++k)
      s += "  vertex " + std::to_string(m.v[t[k]].x) + " " + std::to_string(m.v[t[k]].y) + " " + std::to_string(m.v[t[k]].z) + "\n";
    s += " endloop\nendfacet\n";
  }
  return s + "endsolid octahedron\n";
}

std::string stlBinary(const SmallMesh& m) {
  std::string s(80, ' ');
  s.replace(0, 10, "octahedron");
  put(s, std::uint32_t(m.f.size()));
  for (const auto& t : m.f) {
    const glm::dvec3 n = faceNormal(m, t);
    put(s, float(n.x)), put(s, float(n.y)), put(s, float(n.z));
    for (int k = 0; k < 3; ++k) put(s, float(m.v[t[k]].x)), put(s, float(m.v[t[k]].y)), put(s, float(m.v[t[k]].z));
    put(s, std::uint16_t{0});
  }
  return s;
}

// glTF and GLB through Assimp's exporter: a scene of the one mesh.
void exportScene(const SmallMesh& m, const std::string& path, const char* format) {
  aiScene scene;
  scene.mRootNode = new aiNode();
  scene.mMaterials = new aiMaterial*[1]{new aiMaterial()};
  scene.mNumMaterials = 1;
  scene.mMeshes = new aiMesh*[1]{new aiMesh()};
  scene.mNumMeshes = 1;
  scene.mRootNode->mMeshes = new unsigned[1]{0};
  scene.mRootNode->mNumMeshes = 1;
  aiMesh* mesh = scene.mMeshes[0];
  mesh->mPrimitiveTypes = aiPrimitiveType_TRIANGLE;
  mesh->mNumVertices = static_cast<unsigned>(m.v.size());
  mesh->mVertices = new aiVector3D[m.v.size()];
  for (std::size_t i = 0; i < m.v.size(); ++i)
    mesh->mVertices[i] = aiVector3D(float(m.v[i].x), float(m.v[i].y), float(m.v[i].z));
  mesh->mNumFaces = static_cast<unsigned>(m.f.size());
  mesh->mFaces = new aiFace[m.f.size()];
  for (std::size_t i = 0; i < m.f.size(); ++i) {
    mesh->mFaces[i].mNumIndices = 3;
    mesh->mFaces[i].mIndices = new unsigned[3]{m.f[i].x, m.f[i].y, m.f[i].z};
  }
  Assimp::Exporter exporter;
  ASSERT_EQ(exporter.Export(&scene, format, path), aiReturn_SUCCESS) << exporter.GetErrorString();
}

TEST(MeshReader, EveryFormatReadsTheSameTriangles) {
  const SmallMesh m;
  const auto want = canonical(m.v, m.f);
  std::vector<std::string> files = {temp("m.obj"), temp("m.off"), temp("ascii.ply"), temp("binary.ply"),
                                    temp("ascii.stl"), temp("binary.stl"), temp("m.gltf"), temp("m.glb")};
  writeText(files[0], objText(m));
  writeText(files[1], offText(m));
  writeText(files[2], plyAscii(m));
  writeText(files[3], plyBinary(m));
  writeText(files[4], stlAscii(m));
  writeText(files[5], stlBinary(m));
  exportScene(m, files[6], "gltf2");
  exportScene(m, files[7], "glb2");
  for (const std::string& file : files) {
    SCOPED_TRACE(file);
    EXPECT_TRUE(isMeshPath(file));
    const mesh::TriangleMesh got = readMesh(file);
    EXPECT_EQ(got.vertexCount(), m.v.size()) << "identical vertices are joined";
    EXPECT_EQ(canonical(got.positions, got.triangles), want);
    // No format here carries vertex normals (STL's are per facet, which are dropped).
    EXPECT_TRUE(got.normals.empty());
  }
}

TEST(MeshReader, QuadsAreTriangulatedAndVertexNormalsKept) {
  const std::string path = temp("quad.obj");
  writeText(path, "v 0 0 0\nv 2 0 0\nv 2 2 0\nv 0 2 0\nvn 0 0 2\nf 1//1 2//1 3//1 4//1\n");
  const mesh::TriangleMesh got = readMesh(path);
  ASSERT_EQ(got.triangleCount(), 2u);
  ASSERT_EQ(got.normals.size(), got.positions.size());
  for (const glm::dvec3& n : got.normals) EXPECT_EQ(n, glm::dvec3(0, 0, 1)) << "normalised";
  for (const glm::uvec3& t : got.triangles) {
    const glm::dvec3 n = glm::cross(got.positions[t.y] - got.positions[t.x], got.positions[t.z] - got.positions[t.x]);
    EXPECT_GT(n.z, 0.0) << "the winding is kept";
  }
}

TEST(MeshReader, IsMeshPathGoesByTheExtension) {
  for (const char* yes : {"a.obj", "A.OBJ", "x/y.Ply", "s.stl", "o.off", "g.gltf", "b.glb"}) EXPECT_TRUE(isMeshPath(yes)) << yes;
  for (const char* no : {"a.exr", "1crn.pdb", "1aon.pdb.gz", "x.stp", "obj", "a.obj.gz"}) EXPECT_FALSE(isMeshPath(no)) << no;
}

void expectError(const std::string& path, const std::string& what) {
  try {
    readMesh(path);
    ADD_FAILURE() << path << ": no error";
  } catch (const InputError& e) {
    const std::string message = e.what();
    EXPECT_NE(message.find(path), std::string::npos) << message;
    EXPECT_NE(message.find(what), std::string::npos) << message;
  }
}

TEST(MeshReader, ErrorsNameTheFileAndWhatIsWrong) {
  expectError(temp("missing.obj"), "no such mesh file");
  writeText(temp("empty.ply"), "");
  expectError(temp("empty.ply"), "cannot read the mesh");
  writeText(temp("lines.obj"), "v 0 0 0\nv 1 0 0\nv 1 1 0\nl 1 2\nl 2 3\n");
  expectError(temp("lines.obj"), "no triangles");
  writeText(temp("nan.off"), "OFF\n3 1 0\n0 0 0\nnan 1 0\n0 0 1\n3 0 1 2\n");
  expectError(temp("nan.off"), "(nan, 1, 0)");
  writeText(temp("garbage.stl"), "this is not a mesh at all\n");
  expectError(temp("garbage.stl"), "cannot read the mesh");
}

TEST(MeshTransform, SixteenNumbersRowByRowInAFileOrWithCommas) {
  const glm::dmat4 a = parseMeshTransform("1,2,3,4, 5,6,7,8, 9,10,12,11, 0,0,0,1");
  EXPECT_EQ(a[3][0], 4.0) << "row 0, column 3: the translation's x";
  EXPECT_EQ(a[0][1], 5.0) << "row 1, column 0";
  EXPECT_EQ(a[2][2], 12.0);
  const std::string file = temp("xf.txt");
  writeText(file, "1 2 3 4\n5 6 7 8\n9 10 12 11\n0 0 0 1\n");
  EXPECT_EQ(parseMeshTransform(file), a);
  writeText(file, "1,2,3,4,5,6,7,8,9,10,12,11,0,0,0,1");
  EXPECT_EQ(parseMeshTransform(file), a);
}

TEST(MeshTransform, BadMatricesAreErrors) {
  auto message = [](const std::string& text) -> std::string {
    try {
      parseMeshTransform(text);
    } catch (const InputError& e) {
      return e.what();
    }
    return "";
  };
  EXPECT_NE(message("1,0,0,0,0,1,0,0,0,0,1,0,0,0,0").find("15 numbers"), std::string::npos);
  EXPECT_NE(message("1,0,0,0,0,1,0,0,0,0,1,0,3,0,0,1").find("last row is 3 0 0 1"), std::string::npos);
  EXPECT_NE(message("1,0,0,0,0,1,0,0,0,0,0,0,0,0,0,1").find("singular"), std::string::npos);
  EXPECT_NE(message("1,0,0,x,0,1,0,0,0,0,1,0,0,0,0,1").find("'x' is not a finite number"), std::string::npos);
  EXPECT_NE(message(temp("nothing-here")).find("neither a file nor 16"), std::string::npos);
  const std::string file = temp("bad.txt");
  writeText(file, "1 0 0 0\n0 1 0 0\n0 0 1 0\n0 0 2 1\n");
  const std::string m = message(file);
  EXPECT_NE(m.find(file + ":4:"), std::string::npos) << m;
}

TEST(MeshTransform, PositionsNormalsAndWinding) {
  mesh::TriangleMesh mesh;
  mesh.positions = {{0, 0, 0}, {1, 0, 0}, {0, 1, 0}};
  mesh.triangles = {{0, 1, 2}};
  mesh.normals = {glm::normalize(glm::dvec3(1, 1, 1)), {0, 0, 1}, {1, 0, 0}};
  // x' = 2x + 1, y' = -y + 2, z' = 4z + 3: a mirror (determinant -8).
  transformMesh(mesh, parseMeshTransform("2,0,0,1, 0,-1,0,2, 0,0,4,3, 0,0,0,1"));
  EXPECT_EQ(mesh.positions[1], glm::dvec3(3, 2, 3));
  EXPECT_EQ(mesh.positions[2], glm::dvec3(1, 1, 3));
  // Normals by the inverse transpose, diag(1/2, -1, 1/4): a normal stays normal to the moved surface.
  const glm::dvec3 n0 = glm::normalize(glm::dvec3(0.5, -1.0, 0.25));
  EXPECT_NEAR(glm::length(mesh.normals[0] - n0), 0.0, 1e-15);
  EXPECT_EQ(mesh.normals[1], glm::dvec3(0, 0, 1));
  // The mirrored triangle (its normal was +z, the moved normal is +z) keeps counter-clockwise = outward.
  const glm::uvec3 t = mesh.triangles[0];
  const glm::dvec3 winding = glm::cross(mesh.positions[t.y] - mesh.positions[t.x], mesh.positions[t.z] - mesh.positions[t.x]);
  EXPECT_GT(glm::dot(winding, mesh.normals[1]), 0.0);
}

}  // namespace
}  // namespace surftrace::build

// Mesh files (mesh_writer.hpp). All three formats are written here rather than through
// Assimp's exporter: Debian's Assimp is built with float positions (ai_real), which would move
// vertices off the surface by up to ~1e-5 Å at protein coordinates (PLY and OBJ keep doubles
// here), its PLY exporter writes no custom vertex properties (atom_id, patch_kind, component),
// and its glTF exporter writes no application attributes (_ATOM_ID, ...). The tests read every
// file back with Assimp.
#include "build/io/mesh_writer.hpp"

#include <algorithm>
#include <cctype>
#include <cstdint>
#include <cstdio>
#include <cstring>
#include <limits>
#include <stdexcept>

#include <glm/common.hpp>

#include "build/io/output_file.hpp"

namespace surftrace::build {
namespace {

template <class T>
void append(std::string& out, const T& value) {
  char bytes[sizeof(T)];
  std::memcpy(bytes, &value, sizeof(T));  // little-endian hosts only (x86-64, AArch64)
  out.append(bytes, sizeof(T));
}

bool hasAttributes(const mesh::TriangleMesh& m) {
  return m.normals.size() == m.positions.size() && m.atom.size() == m.positions.size() &&
         m.kind.size() == m.positions.size() && m.component.size() == m.positions.size();
}

std::string plyBytes(const mesh::TriangleMesh& m) {
  const bool attributes = hasAttributes(m);
  std::string out = "ply\nformat binary_little_endian 1.0\ncomment surftrace mesh of an exact surface (Å)\n";
  out += "element vertex " + std::to_string(m.positions.size()) + "\n";
  out += "property double x\nproperty double y\nproperty double z\n";
  if (attributes)
    out += "property float nx\nproperty float ny\nproperty float nz\nproperty uint atom_id\n"
           "property uchar patch_kind\nproperty uint component\n";
  out += "element face " + std::to_string(m.triangles.size()) + "\nproperty list uchar uint vertex_indices\nend_header\n";
  for (std::size_t v = 0; v < m.positions.size(); ++v) {
    for (int a = 0; a < 3; ++a) append(out, m.positions[v][a]);
    if (!attributes) continue;
    for (int a = 0; a < 3; ++a) append(out, static_cast<float>(m.normals[v][a]));
    append(out, m.atom[v]);
    append(out, m.kind[v]);
    append(out, m.component[v]);
  }
  for (const glm::uvec3& t : m.triangles) {
    append(out, std::uint8_t{3});
    for (int a = 0; a < 3; ++a) append(out, static_cast<std::uint32_t>(t[a]));
  }
  return out;
}

std::string objBytes(const mesh::TriangleMesh& m) {
  const bool normals = m.normals.size() == m.positions.size();
  std::string out = "# surftrace mesh of an exact surface (Å)\n";
  char line[128];
  for (const glm::dvec3& p : m.positions) {
    std::snprintf(line, sizeof line, "v %.17g %.17g %.17g\n", p.x, p.y, p.z);
    out += line;
  }
  if (normals)
    for (const glm::dvec3& n : m.normals) {
      std::snprintf(line, sizeof line, "vn %.9g %.9g %.9g\n", n.x, n.y, n.z);
      out += line;
    }
  for (const glm::uvec3& t : m.triangles) {
    if (normals)
      std::snprintf(line, sizeof line, "f %u//%u %u//%u %u//%u\n", t.x + 1, t.x + 1, t.y + 1, t.y + 1, t.z + 1, t.z + 1);
    else
      std::snprintf(line, sizeof line, "f %u %u %u\n", t.x + 1, t.y + 1, t.z + 1);
    out += line;
  }
  return out;
}

// glTF 2.0 binary (Khronos, "glTF 2.0 Specification", sections 3.7 and 4.4): a 12-byte header,
// a JSON chunk and a BIN chunk, each padded to 4 bytes. Application-specific attributes must
// start with an underscore and must not use the unsigned int type (3.7.2.1), hence floats.
std::string glbBytes(const mesh::TriangleMesh& m) {
  const bool attributes = hasAttributes(m);
  const std::size_t n = m.positions.size();
  std::string bin;
  glm::vec3 lo(std::numeric_limits<float>::max()), hi(-std::numeric_limits<float>::max());
  for (const glm::dvec3& p : m.positions) {
    const glm::vec3 f(p);
    lo = glm::min(lo, f), hi = glm::max(hi, f);
    for (int a = 0; a < 3; ++a) append(bin, f[a]);
  }
  if (n == 0) lo = hi = glm::vec3(0.0f);
  std::string json = "{\"asset\":{\"version\":\"2.0\",\"generator\":\"surftrace\"},\"scene\":0,\"scenes\":[{\"nodes\":[0]}],"
                     "\"nodes\":[{\"mesh\":0}],";
  std::string views, accessors;
  std::size_t viewCount = 0;
  const auto addView = [&](std::size_t offset, std::size_t length, int target) {
    if (!views.empty()) views += ",";
    views += "{\"buffer\":0,\"byteOffset\":" + std::to_string(offset) + ",\"byteLength\":" + std::to_string(length) +
             ",\"target\":" + std::to_string(target) + "}";
    return viewCount++;
  };
  const auto addAccessor = [&](std::size_t view, int componentType, std::size_t count, const char* type,
                               const std::string& extra) {
    if (!accessors.empty()) accessors += ",";
    accessors += "{\"bufferView\":" + std::to_string(view) + ",\"componentType\":" + std::to_string(componentType) +
                 ",\"count\":" + std::to_string(count) + ",\"type\":\"" + type + "\"" + extra + "}";
  };
  constexpr int kFloat = 5126, kUint = 5125, kArrayBuffer = 34962, kElementArrayBuffer = 34963;
  char range[256];
  std::snprintf(range, sizeof range, ",\"min\":[%.9g,%.9g,%.9g],\"max\":[%.9g,%.9g,%.9g]", lo.x, lo.y, lo.z, hi.x, hi.y,
                hi.z);
  addAccessor(addView(0, bin.size(), kArrayBuffer), kFloat, n, "VEC3", range);
  std::string attributesJson = "\"POSITION\":0";
  std::size_t accessor = 1;
  const auto addFloats = [&](const char* name, std::size_t components, auto value) {
    const std::size_t offset = bin.size();
    for (std::size_t v = 0; v < n; ++v)
      for (std::size_t a = 0; a < components; ++a) append(bin, static_cast<float>(value(v, a)));
    addAccessor(addView(offset, bin.size() - offset, kArrayBuffer), kFloat, n, components == 3 ? "VEC3" : "SCALAR", "");
    attributesJson += ",\"" + std::string(name) + "\":" + std::to_string(accessor++);
  };
  if (attributes) {
    addFloats("NORMAL", 3, [&](std::size_t v, std::size_t a) { return m.normals[v][static_cast<int>(a)]; });
    addFloats("_ATOM_ID", 1, [&](std::size_t v, std::size_t) { return static_cast<double>(m.atom[v]); });
    addFloats("_PATCH_KIND", 1, [&](std::size_t v, std::size_t) { return static_cast<double>(m.kind[v]); });
    addFloats("_COMPONENT", 1, [&](std::size_t v, std::size_t) { return static_cast<double>(m.component[v]); });
  }
  const std::size_t indexOffset = bin.size();
  for (const glm::uvec3& t : m.triangles)
    for (int a = 0; a < 3; ++a) append(bin, static_cast<std::uint32_t>(t[a]));
  addAccessor(addView(indexOffset, bin.size() - indexOffset, kElementArrayBuffer), kUint, 3 * m.triangles.size(),
              "SCALAR", "");
  json += "\"meshes\":[{\"primitives\":[{\"attributes\":{" + attributesJson + "},\"indices\":" +
          std::to_string(accessor) + ",\"mode\":4}]}],";
  json += "\"buffers\":[{\"byteLength\":" + std::to_string(bin.size()) + "}],";
  json += "\"bufferViews\":[" + views + "],\"accessors\":[" + accessors + "]}";
  while (json.size() % 4) json += ' ';
  while (bin.size() % 4) bin += '\0';
  std::string out;
  append(out, std::uint32_t{0x46546C67});  // "glTF"
  append(out, std::uint32_t{2});
  append(out, static_cast<std::uint32_t>(12 + 8 + json.size() + 8 + bin.size()));
  append(out, static_cast<std::uint32_t>(json.size()));
  append(out, std::uint32_t{0x4E4F534A});  // "JSON"
  out += json;
  append(out, static_cast<std::uint32_t>(bin.size()));
  append(out, std::uint32_t{0x004E4942});  // "BIN"
  out += bin;
  return out;
}

}  // namespace

MeshFormat meshFormatOf(const std::filesystem::path& path) {
  std::string ext = path.extension().string();
  std::transform(ext.begin(), ext.end(), ext.begin(), [](unsigned char c) { return static_cast<char>(std::tolower(c)); });
  if (ext == ".ply") return MeshFormat::Ply;
  if (ext == ".obj") return MeshFormat::Obj;
  if (ext == ".glb") return MeshFormat::Glb;
  throw std::invalid_argument(path.string() + ": unknown mesh format \"" + ext +
                              "\"; name the file .ply (with atom ids and patch kinds), .obj or .glb");
}

std::string meshFileBytes(const mesh::TriangleMesh& mesh, MeshFormat format) {
  switch (format) {
    case MeshFormat::Ply: return plyBytes(mesh);
    case MeshFormat::Obj: return objBytes(mesh);
    case MeshFormat::Glb: return glbBytes(mesh);
  }
  return {};
}

void writeMesh(const std::filesystem::path& path, const mesh::TriangleMesh& mesh) {
  writeFileAtomically(path, meshFileBytes(mesh, meshFormatOf(path)));
}

}  // namespace surftrace::build

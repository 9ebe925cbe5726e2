// `surftrace mesh` on a real molecule (1CRN's SES), checked by oracles that share nothing with the
// mesher: the brute-force SES oracle for every vertex (tests/oracles/ses_oracle), edge counting for
// closure and orientation, `area`'s exact per-component areas and volumes, and `compare --views`,
// which draws the mesh and the exact surface through the same rays from 26 directions.
#include <algorithm>
#include <array>
#include <cmath>
#include <cstdint>
#include <cstdio>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <limits>
#include <map>
#include <numeric>
#include <sstream>
#include <string>
#include <tuple>
#include <utility>
#include <vector>

#include <glm/geometric.hpp>
#include <glm/vec3.hpp>
#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

#include "build/io/molecule.hpp"
#include "build/ses/contour_buildup.hpp"
#include "build/ses/surface_area.hpp"
#include "build/surface_topology.hpp"
#include "oracles/ses_oracle.hpp"
#include "oracles/skin_certificate.hpp"
#include "run_tool.hpp"
#include "temp_dir.hpp"

namespace {

namespace fs = std::filesystem;
using surftrace::tools::test::runTool;

std::string data(const std::string& file) { return std::string(SURFTRACE_TEST_DATA) + "/" + file; }

// The binary PLY that `mesh` writes, read by hand from its header's layout (doubles x y z, floats
// nx ny nz, uint atom_id, uchar patch_kind, uint component; faces as uchar count + 3 uint).
struct PlyMesh {
  std::vector<glm::dvec3> positions;
  std::vector<glm::dvec3> normals;
  std::vector<std::uint32_t> component;
  std::vector<std::uint32_t> atom;
  std::vector<std::uint8_t> kind;
  std::vector<std::array<std::uint32_t, 3>> triangles;
};

template <class T>
T take(const std::string& bytes, std::size_t& at) {
  T v;
  std::memcpy(&v, bytes.data() + at, sizeof(T));
  at += sizeof(T);
  return v;
}

PlyMesh readPly(const fs::path& path) {
  std::ifstream in(path, std::ios::binary);
  const std::string bytes((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
  const std::size_t end = bytes.find("end_header\n");
  if (end == std::string::npos) throw std::runtime_error("no PLY header in " + path.string());
  const std::string header = bytes.substr(0, end);
  const std::string expected =
      "property double x\nproperty double y\nproperty double z\nproperty float nx\nproperty float ny\n"
      "property float nz\nproperty uint atom_id\nproperty uchar patch_kind\nproperty uint component\n";
  if (header.find(expected) == std::string::npos) throw std::runtime_error("unexpected PLY layout:\n" + header);
  std::size_t vertices = 0, faces = 0;
  std::istringstream h(header);
  for (std::string line; std::getline(h, line);) {
    if (line.rfind("element vertex ", 0) == 0) vertices = std::stoull(line.substr(15));
    if (line.rfind("element face ", 0) == 0) faces = std::stoull(line.substr(13));
  }
  PlyMesh m;
  std::size_t at = end + std::strlen("end_header\n");
  for (std::size_t v = 0; v < vertices; ++v) {
    const double x = take<double>(bytes, at), y = take<double>(bytes, at), z = take<double>(bytes, at);
    const float nx = take<float>(bytes, at), ny = take<float>(bytes, at), nz = take<float>(bytes, at);
    m.atom.push_back(take<std::uint32_t>(bytes, at));
    m.kind.push_back(take<std::uint8_t>(bytes, at));
    m.positions.push_back({x, y, z});
    m.normals.push_back({nx, ny, nz});
    m.component.push_back(take<std::uint32_t>(bytes, at));
  }
  for (std::size_t f = 0; f < faces; ++f) {
    if (take<std::uint8_t>(bytes, at) != 3) throw std::runtime_error("a face that is not a triangle");
    std::array<std::uint32_t, 3> t{};
    for (auto& i : t) i = take<std::uint32_t>(bytes, at);
    m.triangles.push_back(t);
  }
  if (at != bytes.size()) throw std::runtime_error("PLY size does not match its header");
  return m;
}

std::uint32_t root(std::vector<std::uint32_t>& parent, std::uint32_t i) {
  while (parent[i] != i) i = parent[i] = parent[parent[i]];
  return i;
}

// How many directed edges of the mesh miss their one reverse, or repeat (0: closed, every edge
// shared by exactly two triangles, consistently oriented).
std::size_t unmatchedEdges(const PlyMesh& m) {
  std::map<std::pair<std::uint32_t, std::uint32_t>, int> directed;
  for (const auto& t : m.triangles)
    for (int k = 0; k < 3; ++k) ++directed[{t[k], t[(k + 1) % 3]}];
  std::size_t unmatched = 0;
  for (const auto& [e, n] : directed)
    if (n != 1 || directed.count({e.second, e.first}) == 0 || directed.at({e.second, e.first}) != 1) ++unmatched;
  return unmatched;
}

// The connected pieces of a mesh (by shared vertices), largest signed volume first (outer surfaces
// before cavities), each with its counts, area, signed volume, Euler characteristic and the
// `component` property of its first vertex.
struct MeshPiece {
  std::size_t vertices = 0, triangles = 0;
  double area = 0.0, volume = 0.0;
  long long euler = 0;
  std::uint32_t component = 0;
};
std::vector<MeshPiece> piecesOf(const PlyMesh& m) {
  std::vector<std::uint32_t> parent(m.positions.size());
  std::iota(parent.begin(), parent.end(), 0u);
  for (const auto& t : m.triangles) {
    parent[root(parent, t[1])] = root(parent, t[0]);
    parent[root(parent, t[2])] = root(parent, t[0]);
  }
  std::map<std::uint32_t, MeshPiece> pieces;
  std::vector<char> used(m.positions.size(), 0);
  for (const auto& t : m.triangles) {
    const glm::dvec3 a = m.positions[t[0]], b = m.positions[t[1]], c = m.positions[t[2]];
    MeshPiece& p = pieces[root(parent, t[0])];
    if (p.triangles++ == 0) p.component = m.component[t[0]];
    p.area += 0.5 * glm::length(glm::cross(b - a, c - a));
    p.volume += glm::dot(a, glm::cross(b, c)) / 6.0;
    for (std::uint32_t v : t)
      if (!used[v]) used[v] = 1, ++p.vertices;
  }
  std::vector<MeshPiece> out;
  // Closed (checked apart by unmatchedEdges): E = 3F/2, so V − E + F = V − F/2.
  for (auto& [r, p] : pieces) {
    p.euler = static_cast<long long>(p.vertices) - static_cast<long long>(p.triangles / 2);
    out.push_back(p);
  }
  std::sort(out.begin(), out.end(), [](const MeshPiece& a, const MeshPiece& b) { return a.volume > b.volume; });
  return out;
}

// The exact SES's Euler characteristic per component (surfaceTopology, from the patch list by
// Gauss–Bonnet), largest signed volume first as piecesOf orders the mesh's pieces; ~0 marks a
// component whose χ the patches do not resolve.
std::vector<long long> exactEulers(const std::vector<glm::dvec3>& centers, const std::vector<double>& radii) {
  const surftrace::build::PatchList p = surftrace::build::buildSes(centers, radii, surftrace::build::SesParams{1.4});
  const std::vector<surftrace::build::ComponentTopology> topology = surftrace::build::surfaceTopology(p);
  const surftrace::build::SurfaceAreas areas = surftrace::build::computeAreas(p);
  std::vector<std::size_t> order(std::min(topology.size(), areas.components.size()));
  std::iota(order.begin(), order.end(), std::size_t{0});
  std::sort(order.begin(), order.end(),
            [&](std::size_t a, std::size_t b) { return areas.components[a].volume > areas.components[b].volume; });
  std::vector<long long> out;
  for (const std::size_t c : order) out.push_back(topology[c].resolved ? topology[c].euler : ~0ll);
  return out;
}

// The distance from p to triangle abc, independent of the program's own: the foot on the plane
// when it lies inside (all three edge tests agree), else the nearest of the three edges.
double triangleDistance(const glm::dvec3& p, const glm::dvec3& a, const glm::dvec3& b, const glm::dvec3& c) {
  const glm::dvec3 n = glm::cross(b - a, c - a);
  const double area2 = glm::dot(n, n);
  auto segment = [&](const glm::dvec3& u, const glm::dvec3& v) {
    const double len2 = glm::dot(v - u, v - u);
    const double t = len2 > 0.0 ? std::clamp(glm::dot(p - u, v - u) / len2, 0.0, 1.0) : 0.0;
    return glm::length(p - (u + t * (v - u)));
  };
  if (area2 > 0.0) {
    const glm::dvec3 foot = p - (glm::dot(p - a, n) / area2) * n;
    const bool inside = glm::dot(glm::cross(b - a, foot - a), n) >= 0.0 && glm::dot(glm::cross(c - b, foot - b), n) >= 0.0 &&
                        glm::dot(glm::cross(a - c, foot - c), n) >= 0.0;
    if (inside) return glm::length(p - foot);
  }
  return std::min({segment(a, b), segment(b, c), segment(c, a)});
}

TEST(MeshCli, CrambinSesIsClosedOnTheSurfaceAndWithinItsBound) {
  const fs::path dir = surftrace::test::freshTempDir("mesh_cli_1crn");
  const std::string pdb = data("structures/1crn.pdb");
  const double maxError = 0.1;
  const auto made = runTool("mesh " + pdb + " --max-error 0.1 -o " + (dir / "m.ply").string());
  ASSERT_EQ(made.status, 0) << made.output;
  const PlyMesh m = readPly(dir / "m.ply");
  ASSERT_GT(m.triangles.size(), 1000u);

  // Every vertex on the SES: dist(x, accessible probe centres) = rp, by the brute-force oracle.
  const surftrace::build::Molecule mol = surftrace::build::readMolecule(pdb);
  std::vector<surftrace::oracle::Sphere> atoms;
  for (std::size_t i = 0; i < mol.size(); ++i) atoms.push_back({mol.centers[i], mol.radii[i]});
  const surftrace::oracle::SesOracle oracle(atoms, 1.4);
  double worst = 0.0;
  for (const glm::dvec3& p : m.positions) worst = std::max(worst, std::abs(oracle.distanceToAccessible(p).dist - 1.4));
  EXPECT_LT(worst, 1e-9) << "a vertex off the SES";

  // Closed and consistently oriented: every directed edge once, and its reverse once.
  const std::size_t unmatched = unmatchedEdges(m);
  EXPECT_EQ(unmatched, 0u) << "edges not shared by exactly two triangles in opposite directions";

  double normalsAgainst = 0;
  for (const auto& t : m.triangles) {
    const glm::dvec3 n = glm::cross(m.positions[t[1]] - m.positions[t[0]], m.positions[t[2]] - m.positions[t[0]]);
    if (glm::dot(n, m.normals[t[0]] + m.normals[t[1]] + m.normals[t[2]]) < 0.0) ++normalsAgainst;
  }
  EXPECT_LT(normalsAgainst, 1e-3 * m.triangles.size()) << "vertex normals against the winding";

  // Connected components (by shared vertices), each with its Euler characteristic, signed volume
  // and area, against `area`'s exact per-component values (outer first, then the cavity).
  const std::vector<MeshPiece> sorted = piecesOf(m);
  const std::vector<long long> eulers = exactEulers(mol.centers, mol.radii);
  const auto areas = runTool("area " + pdb + " --format json");
  ASSERT_EQ(areas.status, 0) << areas.output;
  const auto exact = nlohmann::json::parse(areas.output.substr(areas.output.find('{')))["ses"]["components"];
  ASSERT_EQ(sorted.size(), exact.size()) << "mesh components against the surface's";
  ASSERT_EQ(eulers.size(), exact.size());
  for (std::size_t k = 0; k < sorted.size(); ++k) {
    const MeshPiece& p = sorted[k];
    // The exact surface's topology, from its patches: crambin's outer surface and its cavity
    // are both spheres (χ 2).
    EXPECT_EQ(p.euler, eulers[k]) << "component " << k;
    const double area = exact[k]["area"], volume = exact[k]["volume"];
    EXPECT_EQ(p.volume > 0.0, !exact[k]["cavity"].get<bool>()) << "component " << k << " faces the wrong way";
    // A mesh within ε of the surface: its volume differs from the exact one by at most the shell
    // of thickness ε (ε times the area); its area by at most about 2ε/r of it, where r is the
    // smallest radius of curvature (a chord at sagitta ε across a sphere of radius r; here the
    // probe's 1.4 Å and crambin's smallest atom's are both >= 1.1 Å).
    EXPECT_NEAR(p.area, area, 2.0 * maxError / 1.1 * area) << "component " << k;
    EXPECT_LT(std::abs(p.area - area), 0.02 * area) << "component " << k;
    EXPECT_NEAR(p.volume, volume, maxError * area) << "component " << k;
  }

  // Drawn through the exact surface's own rays from 26 directions, within the bound (p99).
  const fs::path report = dir / "views.json";
  const auto compared = runTool("compare " + (dir / "m.ply").string() + " " + pdb +
                                " --surface ses --views 26 --size 256x256 --max-error 0.1 --report " + report.string());
  EXPECT_EQ(compared.status, 0) << compared.output;
  // Its worst exact -> mesh places are distances to the mesh, as brute force over every triangle
  // gives them (to the float depths' rounding), not bounds from the triangles that rays near by
  // happened to hit (which read 0.23 Å at a place 0.1 Å from the mesh).
  std::ifstream in(report);
  const auto views = nlohmann::json::parse(in);
  std::size_t checked = 0;
  for (const auto& place : views["worst_places"]) {
    if (place["what"] != "exact -> mesh") continue;
    const glm::dvec3 x(place["point"][0], place["point"][1], place["point"][2]);
    double nearest = std::numeric_limits<double>::infinity();
    for (const auto& t : m.triangles)
      nearest = std::min(nearest, triangleDistance(x, m.positions[t[0]], m.positions[t[1]], m.positions[t[2]]));
    EXPECT_NEAR(place["distance"].get<double>(), nearest, 1e-4) << "at (" << x.x << ", " << x.y << ", " << x.z << ")";
    EXPECT_LE(nearest, maxError);
    ++checked;
  }
  EXPECT_GT(checked, 0u) << views["worst_places"].dump();
}

// A piece of GroEL–GroES (1AON: the atoms within 9 Å of (38.93, −32.65, −9.19)) whose SES has a
// wall of the body 0.54 Å thin between two probe balls, and solvent necks where probe balls
// barely overlap, all thinner than the 0.7 Å grid: meshed closed and consistently oriented,
// every vertex on the SES (the brute-force oracle), as many components as `area` finds, each
// with an even Euler characteristic (closed orientable), and within 0.1 Å by `compare --views
// 26`. Before the grid was subdivided at thin parts, `mesh` gave up here after growing the mesh
// to millions of triangles.
TEST(MeshCli, GroelPieceWithWallsThinnerThanTheGridIsClosedAndWithinItsBound) {
  const fs::path dir = surftrace::test::freshTempDir("mesh_cli_1aon_piece");
  const surftrace::build::Molecule full = surftrace::build::readMolecule(data("paper/1aon.pdb.gz"));
  const glm::dvec3 centre(38.93, -32.65, -9.19);
  std::vector<surftrace::oracle::Sphere> atoms;
  {
    std::ofstream out(dir / "piece.xyzr");
    char line[160];
    for (std::size_t i = 0; i < full.size(); ++i) {
      if (glm::length(full.centers[i] - centre) >= 9.0) continue;
      std::snprintf(line, sizeof line, "%.17g %.17g %.17g %.17g\n", full.centers[i].x, full.centers[i].y,
                    full.centers[i].z, full.radii[i]);
      out << line;
      atoms.push_back({full.centers[i], full.radii[i]});
    }
  }
  ASSERT_GT(atoms.size(), 100u);
  const std::string piece = (dir / "piece.xyzr").string();
  const auto made = runTool("mesh " + piece + " --max-error 0.1 -o " + (dir / "m.ply").string());
  ASSERT_EQ(made.status, 0) << made.output;
  const PlyMesh m = readPly(dir / "m.ply");
  const std::vector<MeshPiece> pieces = piecesOf(m);
  EXPECT_EQ(unmatchedEdges(m), 0u) << "edges not shared by exactly two triangles in opposite directions";
  const surftrace::oracle::SesOracle oracle(atoms, 1.4);
  double worst = 0.0;
  for (const glm::dvec3& p : m.positions) worst = std::max(worst, std::abs(oracle.distanceToAccessible(p).dist - 1.4));
  EXPECT_LT(worst, 1e-9) << "a vertex off the SES";
  const auto areas = runTool("area " + piece + " --format json");
  ASSERT_EQ(areas.status, 0) << areas.output;
  const auto exact = nlohmann::json::parse(areas.output.substr(areas.output.find('{')))["ses"]["components"];
  ASSERT_EQ(pieces.size(), exact.size());
  std::vector<glm::dvec3> centers;
  std::vector<double> radii;
  for (const auto& a : atoms) centers.push_back(a.c), radii.push_back(a.r);
  const std::vector<long long> eulers = exactEulers(centers, radii);
  ASSERT_EQ(eulers.size(), pieces.size());
  // The patches (surfaceTopology) give χ 0 outside (one handle) and 2 for the cavity. The mesh
  // finds the cavity's sphere, but its outer χ depends on the grid, which finds or misses necks
  // thinner than its spacing: −6 at the default 0.7 Å, −8 at 0.5, 0 at 0.35, −2 at 0.25 (with a
  // stray third piece). Necks where probes of two tori overlap are not in the patches' count
  // either (tori are not clipped), so only what any closed orientable surface obeys is asked of
  // the outer one.
  EXPECT_EQ(eulers, (std::vector<long long>{0, 2})) << "the patches' topology";
  EXPECT_EQ(pieces.back().euler, eulers.back()) << "the cavity";
  for (std::size_t k = 0; k < pieces.size(); ++k) {
    std::printf("component %zu: mesh χ %lld, exact χ %lld\n", k, pieces[k].euler, eulers[k]);
    EXPECT_EQ(pieces[k].euler % 2, 0) << "component " << k;
    EXPECT_LE(pieces[k].euler, 2) << "component " << k;
    EXPECT_EQ(pieces[k].volume > 0.0, !exact[k]["cavity"].get<bool>()) << "component " << k;
  }
  const auto compared = runTool("compare " + (dir / "m.ply").string() + " " + piece +
                                " --surface ses --views 26 --size 256x256 --max-error 0.1");
  EXPECT_EQ(compared.status, 0) << compared.output;
}

// Meshes the atoms at ε = 0.01 Å (written as XYZR to `dir`) and checks the mesh: closed,
// outward, every vertex on the SES (the brute-force oracle), volume within ε·area of `area`'s
// exact one, and within ε by `compare --views 26`.
void expectMeshedWithinAHundredth(const fs::path& dir, const std::vector<surftrace::oracle::Sphere>& atoms) {
  {
    std::ofstream out(dir / "piece.xyzr");
    char line[160];
    for (const auto& a : atoms) {
      std::snprintf(line, sizeof line, "%.17g %.17g %.17g %.17g\n", a.c.x, a.c.y, a.c.z, a.r);
      out << line;
    }
  }
  const double maxError = 0.01;
  const std::string xyzr = (dir / "piece.xyzr").string();
  const auto made = runTool("mesh " + xyzr + " --max-error 0.01 -o " + (dir / "m.ply").string());
  ASSERT_EQ(made.status, 0) << made.output;
  const PlyMesh m = readPly(dir / "m.ply");
  EXPECT_EQ(unmatchedEdges(m), 0u) << "edges not shared by exactly two triangles in opposite directions";
  const surftrace::oracle::SesOracle oracle(atoms, 1.4);
  double worst = 0.0;
  for (const glm::dvec3& p : m.positions) worst = std::max(worst, std::abs(oracle.distanceToAccessible(p).dist - 1.4));
  EXPECT_LT(worst, 1e-9) << "a vertex off the SES";
  const std::vector<MeshPiece> pieces = piecesOf(m);
  const auto areas = runTool("area " + xyzr + " --format json");
  ASSERT_EQ(areas.status, 0) << areas.output;
  const auto exact = nlohmann::json::parse(areas.output.substr(areas.output.find('{')))["ses"]["components"];
  ASSERT_EQ(pieces.size(), exact.size());
  for (std::size_t k = 0; k < pieces.size(); ++k) {
    const double area = exact[k]["area"], volume = exact[k]["volume"];
    EXPECT_EQ(pieces[k].volume > 0.0, !exact[k]["cavity"].get<bool>()) << "component " << k << " faces the wrong way";
    EXPECT_NEAR(pieces[k].volume, volume, maxError * area) << "component " << k;
  }
  const auto compared = runTool("compare " + (dir / "m.ply").string() + " " + xyzr +
                                " --surface ses --views 26 --size 256x256 --max-error 0.01");
  EXPECT_EQ(compared.status, 0) << compared.output;
}

// The 29 atoms of that GroEL piece within 5 Å of (35.08, −33.15, −8.15), where concave caps
// clip each other along knife-edge ridges whose two sides meet at about 135° between their
// normals: at ε = 0.01 Å the triangles across a ridge must get a vertex on it. Before edges
// across a crease were split on the crease, the split points of two such edges landed on each
// other's ends round after round and `mesh` gave up after 40 rounds with a triangle at 0.027 Å.
TEST(MeshCli, GroelKnifeEdgeRidgesMeshWithinAHundredthOfAnAngstrom) {
  const surftrace::build::Molecule full = surftrace::build::readMolecule(data("paper/1aon.pdb.gz"));
  const glm::dvec3 piece(38.93, -32.65, -9.19), ridge(35.08, -33.15, -8.15);
  std::vector<surftrace::oracle::Sphere> atoms;
  for (std::size_t i = 0; i < full.size(); ++i)
    if (glm::length(full.centers[i] - piece) < 9.0 && glm::length(full.centers[i] - ridge) < 5.0)
      atoms.push_back({full.centers[i], full.radii[i]});
  ASSERT_EQ(atoms.size(), 29u);
  expectMeshedWithinAHundredth(surftrace::test::freshTempDir("mesh_cli_1aon_ridge"), atoms);
}

// The 33 atoms of 1AON's chain A (residues 2-78) within 6 Å of (55.02, −57.84, −13.26), where
// three concave sheets meet: a triangle with a corner on each (normals 72°, 144° and 72° apart)
// has its longest edge between two neighbours 72° apart, not across a crease, and its split
// landed next to an end round after round; `mesh` gave up after 40 rounds at 0.024 Å until a
// failing triangle's edge across a crease was split on the crease as well.
TEST(MeshCli, GroelMeetingOfThreeConcaveSheetsMeshesWithinAHundredthOfAnAngstrom) {
  surftrace::build::ReadOptions options;
  options.chains = {"A"};
  options.selection = "resid 2-78";
  const surftrace::build::Molecule cut = surftrace::build::readMolecule(data("paper/1aon.pdb.gz"), options);
  const glm::dvec3 meeting(55.02, -57.84, -13.26);
  std::vector<surftrace::oracle::Sphere> atoms;
  for (std::size_t i = 0; i < cut.size(); ++i)
    if (glm::length(cut.centers[i] - meeting) < 6.0) atoms.push_back({cut.centers[i], cut.radii[i]});
  ASSERT_EQ(atoms.size(), 33u);
  expectMeshedWithinAHundredth(surftrace::test::freshTempDir("mesh_cli_1aon_three_sheets"), atoms);
}

// The mesh's topology is the exact surface's, component by component, where the grid resolves
// every neck: ubiquitin's outer surface has two handles (χ −2) beside two spherical cavities,
// gramicidin's channel one (χ 0). The exact values come from the patch list by Gauss–Bonnet
// (surfaceTopology), which shares nothing with the mesher's grid.
TEST(MeshCli, SesMeshHasTheExactSurfacesTopology) {
  const fs::path dir = surftrace::test::freshTempDir("mesh_cli_topology");
  for (const char* file : {"structures/1ubq.pdb.gz", "paper/1grm.pdb.gz"}) {
    SCOPED_TRACE(file);
    const auto made = runTool("mesh " + data(file) + " --max-error 0.1 -o " + (dir / "m.ply").string());
    ASSERT_EQ(made.status, 0) << made.output;
    const PlyMesh m = readPly(dir / "m.ply");
    EXPECT_EQ(unmatchedEdges(m), 0u);
    const surftrace::build::Molecule mol = surftrace::build::readMolecule(data(file));
    const std::vector<long long> eulers = exactEulers(mol.centers, mol.radii);
    const std::vector<MeshPiece> pieces = piecesOf(m);
    ASSERT_EQ(pieces.size(), eulers.size());
    for (std::size_t k = 0; k < pieces.size(); ++k) {
      EXPECT_NE(eulers[k], ~0ll) << "component " << k << ": the patches do not resolve its topology";
      EXPECT_EQ(pieces[k].euler, eulers[k]) << "component " << k;
    }
  }
}

// With --component the printed exact area and volume are those of the kept components (here the
// outer surface), from `area`'s per-component values, and the percentages compare with them.
TEST(MeshCli, ComponentFilterComparesWithTheKeptComponents) {
  const fs::path dir = surftrace::test::freshTempDir("mesh_cli_component");
  const std::string pdb = data("structures/1crn.pdb");
  const auto made = runTool("mesh " + pdb + " --max-error 0.1 --component outer -o " + (dir / "m.ply").string());
  ASSERT_EQ(made.status, 0) << made.output;
  const auto areas = runTool("area " + pdb + " --format json");
  ASSERT_EQ(areas.status, 0) << areas.output;
  double outerArea = 0.0, outerVolume = 0.0;
  const auto json = nlohmann::json::parse(areas.output.substr(areas.output.find('{')));
  for (const auto& c : json["ses"]["components"])
    if (!c["cavity"].get<bool>()) outerArea += c["area"].get<double>(), outerVolume += c["volume"].get<double>();
  for (const auto& [name, unit, expected] :
       {std::tuple{"area", "Å²", outerArea}, std::tuple{"volume", "Å³", outerVolume}}) {
    const std::size_t at = made.output.find(std::string(name) + "    ");
    ASSERT_NE(at, std::string::npos) << made.output;
    std::istringstream line(made.output.substr(at + std::strlen(name), made.output.find('\n', at) - at));
    double mesh = 0.0, exact = 0.0, percent = 0.0;
    std::string word;
    line >> mesh >> word;  // the mesh's value, its unit
    while (line >> word && word != "components") {
    }
    line >> exact >> word >> percent;
    EXPECT_NEAR(exact, expected, 1e-4 * expected) << name << ": " << made.output;
    EXPECT_NEAR(percent, 100.0 * (mesh - exact) / exact, 1e-4) << name << ": " << made.output;
    EXPECT_GT(std::abs(percent), 1e-3) << name << " (a mesh within 0.1 Å is not exact to the digit)";
  }
}

TEST(MeshCli, OtherSurfacesAreRefusedBeforeAnyWork) {
  const fs::path dir = surftrace::test::freshTempDir("mesh_cli_refused");
  for (const char* surface : {"vdw", "sas"}) {
    const auto r = runTool("mesh " + data("structures/1crn.pdb") + " --surface " + surface + " -o " +
                           (dir / "m.ply").string());
    EXPECT_NE(r.status, 0) << surface;
    EXPECT_NE(r.output.find("SES and skin meshes only"), std::string::npos) << r.output;
    EXPECT_FALSE(fs::exists(dir / "m.ply")) << surface;
  }
}

// Triangles whose face normal points against the sum of their corners' normals (the surface's
// outward normals, which the skin certificate checks vertex by vertex): folds, where a triangle
// joins points of two sides of a neck or a thin wall.
std::size_t backwardTriangles(const PlyMesh& m) {
  std::size_t backward = 0;
  for (const auto& t : m.triangles) {
    const glm::dvec3 a = m.positions[t[0]], b = m.positions[t[1]], c = m.positions[t[2]];
    const glm::dvec3 n = m.normals[t[0]] + m.normals[t[1]] + m.normals[t[2]];
    backward += !(glm::dot(glm::cross(b - a, c - a), n) > 0.0);
  }
  return backward;
}

// Every vertex on the skin and its normal outward: G > 0 just outside along the normal and
// G < 0 just inside, certified from the skin function's definition over all atoms. Returns the
// vertices with a sign against their side; `undecided` counts those the certificate left open.
std::size_t offSkin(const PlyMesh& m, const surftrace::build::Molecule& mol, double s, std::size_t& undecided) {
  std::size_t off = 0;
  undecided = 0;
  for (std::size_t v = 0; v < m.positions.size(); ++v) {
    const glm::dvec3 p = m.positions[v], n = glm::normalize(m.normals[v]);
    const int out = surftrace::oracle::skinSign(mol.centers, mol.radii, s, p + 1e-7 * n);
    const int in = surftrace::oracle::skinSign(mol.centers, mol.radii, s, p - 1e-7 * n);
    off += out == -1 || in == 1;
    undecided += out == 0 || in == 0;
  }
  return off;
}

// The skin of gramicidin (1GRM, s = 0.5), checked by oracles that share nothing with the mesher:
// the skin function's certificate (tests/oracles/skin_certificate) on either side of every
// vertex, a brute-force search over all atoms for each vertex's owner, edge counting, `area`'s
// exact skin area and volume, and `compare --views 26` against the exact skin.
TEST(MeshCli, GramicidinSkinIsClosedOnTheSkinAndWithinItsBound) {
  const fs::path dir = surftrace::test::freshTempDir("mesh_cli_1grm_skin");
  const std::string pdb = data("paper/1grm.pdb.gz");
  const double s = 0.5;
  // 0.2 Å, to keep the test short (0.1 Å on 1CRN's skin: CrambinSkinAtATenthOfAnAngstrom...).
  const double maxError = 0.2;
  const auto made = runTool("mesh " + pdb + " --surface mss --shrink 0.5 --max-error 0.2 -o " + (dir / "m.ply").string());
  ASSERT_EQ(made.status, 0) << made.output;
  const PlyMesh m = readPly(dir / "m.ply");
  ASSERT_GT(m.triangles.size(), 1000u);

  // Every vertex on the skin (offSkin: the certificate on both sides along its normal); its owner
  // the atom of least power distance |p − c|² − r² of all (the lower index on a tie); its kind a
  // skin kind.
  const surftrace::build::Molecule mol = surftrace::build::readMolecule(pdb);
  std::size_t undecided = 0, wrongOwner = 0, wrongKind = 0;
  const std::size_t off = offSkin(m, mol, s, undecided);
  for (std::size_t v = 0; v < m.positions.size(); ++v) {
    const glm::dvec3 p = m.positions[v];
    std::uint32_t owner = 0;
    double least = std::numeric_limits<double>::infinity();
    for (std::uint32_t a = 0; a < mol.size(); ++a) {
      const double power = glm::dot(p - mol.centers[a], p - mol.centers[a]) - mol.radii[a] * mol.radii[a];
      if (power < least) least = power, owner = a;
    }
    wrongOwner += m.atom[v] != owner;
    wrongKind += m.kind[v] < 4 || m.kind[v] > 7;
  }
  EXPECT_EQ(off, 0u) << "vertices not on the skin (to 1e-7 Å along their normals)";
  EXPECT_LT(undecided, m.positions.size() / 100) << "vertices the certificate could not decide";
  std::printf("vertices %zu, undecided by the certificate %zu\n", m.positions.size(), undecided);
  EXPECT_EQ(wrongOwner, 0u) << "vertices whose atom_id is not the atom of least power distance";
  EXPECT_EQ(wrongKind, 0u);

  // Closed and consistently oriented: every directed edge once, and its reverse once.
  const std::size_t unmatched = unmatchedEdges(m);
  EXPECT_EQ(unmatched, 0u) << "edges not shared by exactly two triangles in opposite directions";

  // Components: each closed orientable, so V − E + F = 2 − 2g is even and at most 2; the pieces
  // that enclose no body (the cavities) are spheres. Area and volume against `area`'s exact ones.
  double area = 0.0, volume = 0.0;
  std::size_t outer = 0;
  for (const MeshPiece& p : piecesOf(m)) {
    area += p.area, volume += p.volume;
    EXPECT_EQ(p.euler % 2, 0) << "a piece of odd Euler characteristic";
    EXPECT_LE(p.euler, 2);
    if (p.volume > 0.0) ++outer;
    else EXPECT_EQ(p.euler, 2) << "a cavity that is not a sphere";
  }
  EXPECT_EQ(outer, 1u) << "gramicidin's skin has one outer surface";
  const auto areas = runTool("area " + pdb + " --surface mss --shrink 0.5 --format json");
  ASSERT_EQ(areas.status, 0) << areas.output;
  const auto json = nlohmann::json::parse(areas.output.substr(areas.output.find('{')));
  const double exactArea = json["mss"]["total"], exactVolume = json["mss"]["volume"];
  // Within ε of the skin: the volume differs by at most the shell of thickness ε (ε times the
  // area); the area by a small share (chords at sagitta ε; the hyperboloids' necks are narrower
  // than the atoms, so no 2ε/r bound from the radii holds, and 2 % is asked).
  EXPECT_NEAR(volume, exactVolume, maxError * exactArea);
  EXPECT_LT(std::abs(area - exactArea), 0.02 * exactArea);

  // Drawn through the exact skin's own rays from 26 directions, within the bound (p99).
  const auto compared = runTool("compare " + (dir / "m.ply").string() + " " + pdb +
                                " --surface mss --shrink 0.5 --views 26 --size 256x256 --max-error 0.2");
  EXPECT_EQ(compared.status, 0) << compared.output;
}

}  // namespace

// Crambin's skin (s = 0.5) at ε = 0.1 Å: near changes of its topology the skin has necks and
// tunnels a tenth of an Å wide, where a grid edge can cross it three times and a tetrahedron
// holds a piece that turns by more than a right angle; marching tetrahedra made 66 triangles
// there that face inwards. Checked with the skin certificate on every vertex, edge counting,
// the triangles' facing against the certified normals, and `compare --views 26`.
TEST(MeshCli, CrambinSkinAtATenthOfAnAngstromIsClosedOutwardAndWithinItsBound) {
  const fs::path dir = surftrace::test::freshTempDir("mesh_cli_1crn_skin");
  const std::string pdb = data("structures/1crn.pdb");
  const auto made = runTool("mesh " + pdb + " --surface mss --shrink 0.5 --max-error 0.1 -o " + (dir / "m.ply").string());
  ASSERT_EQ(made.status, 0) << made.output;
  const PlyMesh m = readPly(dir / "m.ply");
  ASSERT_GT(m.triangles.size(), 10000u);
  const surftrace::build::Molecule mol = surftrace::build::readMolecule(pdb);
  std::size_t undecided = 0;
  EXPECT_EQ(offSkin(m, mol, 0.5, undecided), 0u) << "vertices not on the skin (to 1e-7 Å along their normals)";
  EXPECT_LT(undecided, m.positions.size() / 100) << "vertices the certificate could not decide";
  EXPECT_EQ(unmatchedEdges(m), 0u) << "edges not shared by exactly two triangles in opposite directions";
  // A few slivers may stay where a crossing lies next to a grid vertex (a needle's facing is
  // rounding: its corners' normals agree); the folds were dozens.
  EXPECT_LE(backwardTriangles(m), 5u) << "triangles facing against the skin's outward normals";
  const auto compared = runTool("compare " + (dir / "m.ply").string() + " " + pdb +
                                " --surface mss --shrink 0.5 --views 26 --size 256x256 --max-error 0.1");
  EXPECT_EQ(compared.status, 0) << compared.output;
}

// Two balls of radius r = 1.5 Å whose skin (s = 0.5) has a neck 0.05 Å wide, a tenth of the
// default grid: the edge's hyperboloid has one sheet where the orthosphere weight
// w = (d/2)² − r²/s is negative, with a waist of radius √(s|w|) (ORACLES D.3), so the skin is
// one closed piece of genus 0. Marching tetrahedra on the grid pinched the neck into two spheres.
TEST(MeshCli, TwoBallSkinWithANeckThinnerThanTheGridIsOnePiece) {
  const fs::path dir = surftrace::test::freshTempDir("mesh_cli_two_ball_neck");
  const double r = 1.5, s = 0.5, d = 4.2420;
  const glm::dvec3 a(0.1, 0.2, 0.3), axis = glm::normalize(glm::dvec3(0.3, 0.9, 0.2));
  const glm::dvec3 b = a + d * axis;
  const double w = 0.25 * d * d - r * r / s;
  ASSERT_LT(w, 0.0);
  ASSERT_LT(2.0 * std::sqrt(s * -w), 0.06) << "the neck is to be far thinner than the grid";
  {
    std::ofstream xyzr(dir / "two.xyzr");
    xyzr.precision(17);
    xyzr << a.x << ' ' << a.y << ' ' << a.z << ' ' << r << '\n' << b.x << ' ' << b.y << ' ' << b.z << ' ' << r << '\n';
  }
  const auto made = runTool("mesh " + (dir / "two.xyzr").string() + " --surface mss --shrink 0.5 --max-error 0.1 -o " +
                            (dir / "m.ply").string());
  ASSERT_EQ(made.status, 0) << made.output;
  const PlyMesh m = readPly(dir / "m.ply");
  EXPECT_EQ(unmatchedEdges(m), 0u) << "edges not shared by exactly two triangles in opposite directions";
  const std::vector<MeshPiece> pieces = piecesOf(m);
  ASSERT_EQ(pieces.size(), 1u) << "the neck was pinched off: " << made.output;
  EXPECT_EQ(pieces[0].euler, 2) << "one closed piece of genus 0";
  surftrace::build::Molecule mol;
  mol.centers = {a, b};
  mol.radii = {r, r};
  std::size_t undecided = 0;
  EXPECT_EQ(offSkin(m, mol, s, undecided), 0u) << "vertices not on the skin (to 1e-7 Å along their normals)";
  EXPECT_EQ(undecided, 0u);
  EXPECT_LE(backwardTriangles(m), 2u) << "triangles facing against the skin's outward normals";
}

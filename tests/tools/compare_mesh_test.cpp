// `surftrace compare MESH ...`: meshes drawn along a reference's rays (one view) and against a
// structure's exact surface all around (--views). Oracles: the chord (sagitta) of a sphere's
// tessellation from its triangles' circumradii; a shift put into the mesh's vertices; and a mesh
// built from the reference's own hit points, moved on one patch kind only.
#include <algorithm>
#include <cmath>
#include <cstdio>
#include <fstream>
#include <map>
#include <string>
#include <vector>

#include <glm/geometric.hpp>
#include <glm/vec3.hpp>
#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

#include "run_tool.hpp"
#include "temp_dir.hpp"
#include "view/camera.hpp"
#include "view/image_io.hpp"

namespace surftrace::tools {
namespace {

using test::Result;
Result run(const std::string& args) { return test::runTool(args); }
std::string temp(const std::string& name) { return (::surftrace::test::testTempDir() / name).string(); }
bool has(const Result& r, const std::string& text) { return r.output.find(text) != std::string::npos; }
nlohmann::json readJson(const std::string& path) { return nlohmann::json::parse(std::ifstream(path)); }

struct Mesh {
  std::vector<glm::dvec3> v;
  std::vector<glm::uvec3> f;
};

// The icosahedron subdivided `levels` times, every vertex projected onto the sphere of `radius`
// about `centre`: counter-clockwise from outside.
Mesh icosphere(int levels, double radius, glm::dvec3 centre = glm::dvec3(0.0)) {
  const double t = (1.0 + std::sqrt(5.0)) / 2.0;
  Mesh m;
  m.v = {{-1, t, 0}, {1, t, 0}, {-1, -t, 0}, {1, -t, 0}, {0, -1, t}, {0, 1, t},
         {0, -1, -t}, {0, 1, -t}, {t, 0, -1}, {t, 0, 1}, {-t, 0, -1}, {-t, 0, 1}};
  for (glm::dvec3& p : m.v) p = glm::normalize(p);
  m.f = {{0, 11, 5}, {0, 5, 1}, {0, 1, 7}, {0, 7, 10}, {0, 10, 11}, {1, 5, 9}, {5, 11, 4}, {11, 10, 2}, {10, 7, 6}, {7, 1, 8},
         {3, 9, 4}, {3, 4, 2}, {3, 2, 6}, {3, 6, 8}, {3, 8, 9}, {4, 9, 5}, {2, 4, 11}, {6, 2, 10}, {8, 6, 7}, {9, 8, 1}};
  for (int l = 0; l < levels; ++l) {
    std::map<std::pair<unsigned, unsigned>, unsigned> mid;
    auto middle = [&](unsigned a, unsigned b) {
      const auto key = std::minmax(a, b);
      if (const auto it = mid.find(key); it != mid.end()) return it->second;
      m.v.push_back(glm::normalize(m.v[a] + m.v[b]));
      return mid[key] = static_cast<unsigned>(m.v.size() - 1);
    };
    std::vector<glm::uvec3> next;
    for (const glm::uvec3& f : m.f) {
      const unsigned ab = middle(f.x, f.y), bc = middle(f.y, f.z), ca = middle(f.z, f.x);
      next.insert(next.end(), {{f.x, ab, ca}, {f.y, bc, ab}, {f.z, ca, bc}, {ab, bc, ca}});
    }
    m.f = next;
  }
  for (glm::dvec3& p : m.v) p = centre + radius * p;
  return m;
}

void writeObj(const Mesh& m, const std::string& path, glm::dvec3 shift = glm::dvec3(0.0)) {
  std::FILE* f = std::fopen(path.c_str(), "w");
  ASSERT_TRUE(f) << path;
  for (const glm::dvec3& p : m.v) std::fprintf(f, "v %.17g %.17g %.17g\n", p.x + shift.x, p.y + shift.y, p.z + shift.z);
  for (const glm::uvec3& t : m.f) std::fprintf(f, "f %u %u %u\n", t.x + 1, t.y + 1, t.z + 1);
  std::fclose(f);
}

// The deepest point of a flat triangle with its corners on a sphere of radius r lies below the
// sphere by the sagitta r − sqrt(r² − R²), R its circumradius (the foot of the perpendicular
// from the centre is the circumcentre, inside the triangle when it is acute).
double largestSagitta(const Mesh& m, double r) {
  double worst = 0.0;
  for (const glm::uvec3& t : m.f) {
    const glm::dvec3 a = m.v[t.x], b = m.v[t.y], c = m.v[t.z];
    const double la = glm::length(b - c), lb = glm::length(a - c), lc = glm::length(a - b);
    const double area = 0.5 * glm::length(glm::cross(b - a, c - a));
    const double circumradius = la * lb * lc / (4.0 * area);
    EXPECT_LT(std::max({la, lb, lc}) * std::max({la, lb, lc}) * 2.0, la * la + lb * lb + lc * lc) << "acute";
    worst = std::max(worst, r - std::sqrt(r * r - circumradius * circumradius));
  }
  return worst;
}

std::string oneAtom(double r) {
  const std::string path = temp("one.xyzr");
  std::ofstream(path) << "0 0 0 " << r << "\n";
  return path;
}

// The sphere tessellated at known resolutions against the exact vdW sphere of one atom of the
// same radius, all around: the largest distance measured either way is the largest sagitta.
TEST(CompareMeshViews, AnIcosphereIsOffByItsChord) {
  const double r = 1.5;
  const std::string atom = oneAtom(r);
  for (int levels : {2, 3}) {
    SCOPED_TRACE("levels " + std::to_string(levels));
    const Mesh m = icosphere(levels, r);
    const double sagitta = largestSagitta(m, r);
    const std::string obj = temp("ico" + std::to_string(levels) + ".obj"), report = temp("views.json");
    writeObj(m, obj);
    const Result ok = run("compare " + obj + " " + atom + " --input-format xyzr --surface vdw --views 26 --size 256x256 --report " +
                          report + " --max-error " + std::to_string(1.05 * sagitta) + " --max-error-stat max");
    ASSERT_EQ(ok.status, 0) << ok.output;
    const nlohmann::json j = readJson(report);
    const double exactToMesh = j["exact_to_mesh"]["max"], meshToExact = j["mesh_to_exact"]["max"];
    std::printf("levels %d: sagitta %.6g Å, exact -> mesh max %.6g, mesh -> exact max %.6g, p99 %.6g\n", levels, sagitta,
                exactToMesh, meshToExact, j["mesh_to_exact"]["p99"].get<double>());
    // Both are distances to the nearest point of the other surface: the sagitta where a pixel
    // centre falls near a circumcentre (the deepest point of a triangle, nearest to the sphere's
    // point straight above it).
    EXPECT_NEAR(exactToMesh, sagitta, 0.005 * sagitta);
    EXPECT_NEAR(meshToExact, sagitta, 0.005 * sagitta);
    // The mesh lies inside the sphere: every ray meets it behind the exact surface.
    ASSERT_EQ(j["per_kind"].size(), 1u);
    EXPECT_EQ(j["per_kind"][0]["kind"], "convex");
    EXPECT_EQ(j["per_kind"][0]["in_front"], 0);
    EXPECT_GT(j["per_kind"][0]["p1"].get<double>(), 0.0);
    // A limit below the chord fails, with exit status 2.
    const Result fail = run("compare " + obj + " " + atom + " --input-format xyzr --surface vdw --views 26 --size 256x256 " +
                            "--max-error " + std::to_string(0.9 * sagitta));
    EXPECT_EQ(fail.status, 2) << fail.output;
    EXPECT_TRUE(has(fail, "FAIL (--max-error")) << fail.output;
  }
}

// One view: the reference EXR of the same sphere, orthographic, and the mesh shifted towards the
// eye by 0.2 Å: every signed depth error moves by exactly −0.2 Å; moved far away it fails with the
// hint; --mesh-transform brings it back.
TEST(CompareMeshOneView, AShiftOf02IsMeasuredAndAWrongFrameHinted) {
  const double r = 1.5;
  const std::string atom = oneAtom(r), ref = temp("ref.exr");
  const Result rendered = run("render " + atom + " --input-format xyzr --surface vdw --ortho --view 1,0.4,-0.7 --size 160x120 "
                              "--quiet --exr " + ref + " -o " + temp("ref.png"));
  ASSERT_EQ(rendered.status, 0) << rendered.output;
  view::ImageMetadata meta;
  view::readExr(ref, &meta);
  const view::Camera camera = view::cameraFromJson(meta.at("surftrace:camera"));
  const Mesh m = icosphere(4, r);
  const std::string obj = temp("ico.obj"), shifted = temp("shifted.obj"), away = temp("away.obj");
  writeObj(m, obj);
  writeObj(m, shifted, -0.2 * camera.forward());
  writeObj(m, away, glm::dvec3(10.0, 0.0, 0.0));
  const Result a = run("compare " + obj + " " + ref + " --report " + temp("a.json"));
  const Result b = run("compare " + shifted + " " + ref + " --report " + temp("b.json"));
  EXPECT_EQ(b.status, 2) << b.output;
  EXPECT_TRUE(has(b, "depth p99")) << b.output;
  const nlohmann::json ja = readJson(temp("a.json")), jb = readJson(temp("b.json"));
  ASSERT_EQ(ja["per_kind"].size(), 1u);
  ASSERT_EQ(jb["per_kind"].size(), 1u);
  EXPECT_EQ(ja["coverage"]["mismatch"], jb["coverage"]["mismatch"]);
  for (const char* stat : {"median", "p1", "p99"})
    EXPECT_NEAR(jb["per_kind"][0][stat].get<double>() - ja["per_kind"][0][stat].get<double>(), -0.2, 1e-6) << stat;
  EXPECT_EQ(jb["per_kind"][0]["in_front"], jb["per_kind"][0]["samples"]);
  EXPECT_FALSE(has(b, "--mesh-transform")) << "a shift along the view is no wrong frame";

  const Result c = run("compare " + away + " " + ref);
  EXPECT_EQ(c.status, 2) << c.output;
  EXPECT_TRUE(has(c, "hint: the mesh covers")) << c.output;
  EXPECT_TRUE(has(c, "--mesh-transform")) << c.output;

  const std::string back = temp("back.txt");
  std::ofstream(back) << "1 0 0 -10\n0 1 0 0\n0 0 1 0\n0 0 0 1\n";
  for (const std::string& transform : {back, std::string("1,0,0,-10,0,1,0,0,0,0,1,0,0,0,0,1")}) {
    const Result d = run("compare " + away + " " + ref + " --mesh-transform " + transform + " --report " + temp("d.json"));
    EXPECT_EQ(d.status, a.status) << d.output;
    const nlohmann::json jd = readJson(temp("d.json"));
    ASSERT_EQ(jd["per_kind"].size(), 1u) << d.output;
    for (const char* stat : {"median", "p1", "p99"})
      EXPECT_NEAR(jd["per_kind"][0][stat].get<double>(), ja["per_kind"][0][stat].get<double>(), 1e-5) << stat;
  }
}

TEST(CompareMeshOneView, MistakesAreErrors) {
  const std::string atom = oneAtom(1.5), obj = temp("m.obj");
  writeObj(icosphere(1, 1.5), obj);
  const Result a = run("compare " + obj + " " + atom);
  EXPECT_EQ(a.status, 1) << a.output;
  EXPECT_TRUE(has(a, "give --views N")) << a.output;
  const Result b = run("compare " + obj + " " + atom + " --input-format xyzr --views 2 --mesh-transform 1,2,3");
  EXPECT_EQ(b.status, 1) << b.output;
  EXPECT_TRUE(has(b, "3 numbers; a transform is 16")) << b.output;
}

// 1CRN's SES seen by SurfTrace, and as the mesh under test the reference's own hit points joined
// pixel to pixel: every ray through a pixel centre meets the mesh at that pixel's vertex. Moving
// the vertices of one patch kind towards the eye by δ moves that kind's signed errors by −δ, and
// no other kind's.
TEST(CompareMeshOneView, PerKindStatisticsMoveOnlyForTheKindMoved) {
  const std::string ref = temp("crn.exr");
  const Result rendered = run("render " + std::string(SURFTRACE_TEST_DATA) + "/structures/1crn.pdb --size 160x160 --quiet --exr " +
                              ref + " -o " + temp("crn.png"));
  ASSERT_EQ(rendered.status, 0) << rendered.output;
  view::ImageMetadata meta;
  const view::FrameBuffers frame = view::readExr(ref, &meta);
  const view::Camera camera = view::cameraFromJson(meta.at("surftrace:camera"));
  const view::Camera::Frame f = camera.frame();
  const int w = frame.width, h = frame.height;
  constexpr std::uint32_t kMoved = 3;  // concave
  constexpr double kDelta = 0.05;
  auto at = [w](int x, int y) { return static_cast<std::size_t>(y) * static_cast<std::size_t>(w) + static_cast<std::size_t>(x); };
  for (const double delta : {0.0, kDelta}) {
    const std::string obj = temp("grid.obj");
    std::FILE* out = std::fopen(obj.c_str(), "w");
    ASSERT_TRUE(out);
    std::vector<long> vertex(frame.pixels(), -1);
    long count = 0;
    for (int y = 0; y < h; ++y)
      for (int x = 0; x < w; ++x) {
        const std::size_t p = at(x, y);
        if (frame.kind[p] == 0) continue;
        const view::Ray ray = f.ray(x + 0.5, y + 0.5);
        const double t = frame.depth[p] - (frame.kind[p] == kMoved ? delta : 0.0);
        const glm::dvec3 v = ray.org + t * ray.dir;
        std::fprintf(out, "v %.17g %.17g %.17g\n", v.x, v.y, v.z);
        vertex[p] = ++count;
      }
    // Counter-clockwise seen from the eye (x right, y down the image).
    for (int y = 0; y + 1 < h; ++y)
      for (int x = 0; x + 1 < w; ++x) {
        const long a = vertex[at(x, y)], b = vertex[at(x, y + 1)], c = vertex[at(x + 1, y)], d = vertex[at(x + 1, y + 1)];
        if (a > 0 && b > 0 && c > 0) std::fprintf(out, "f %ld %ld %ld\n", a, b, c);
        if (c > 0 && b > 0 && d > 0) std::fprintf(out, "f %ld %ld %ld\n", c, b, d);
      }
    std::fclose(out);
    const std::string report = temp("grid.json");
    const Result c = run("compare " + obj + " " + ref + " --preset none --report " + report);
    ASSERT_EQ(c.status, 0) << c.output;
    const nlohmann::json j = readJson(report);
    ASSERT_EQ(j["per_kind"].size(), 3u) << c.output;
    for (const nlohmann::json& k : j["per_kind"]) {
      SCOPED_TRACE(k["kind"].get<std::string>() + ", δ " + std::to_string(delta));
      const double want = k["code"] == kMoved ? -delta : 0.0;
      ASSERT_GT(k["samples"].get<std::size_t>(), 100u);
      for (const char* stat : {"median", "p1", "p99"}) EXPECT_NEAR(k[stat].get<double>(), want, 1e-4) << stat;
      if (delta > 0 && k["code"] == kMoved) {
        EXPECT_EQ(k["in_front"], k["samples"]);
      }
    }
  }
}

}  // namespace
}  // namespace surftrace::tools

// `surftrace compare` judges everything it is given and says what it did not: render settings
// compared like the camera, colour judged between engines, colour over the covered pixels apart
// from the background, occlusion edges reported apart, "none compared" failing, NaN counted as a
// mismatch, and a per-kind table. Each test alters an image in a known way (the oracle) and
// checks that the verdict and the figures say so.
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <limits>
#include <utility>
#include <string>
#include <vector>

#include <glm/geometric.hpp>
#include <glm/vec4.hpp>
#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

#include "run_tool.hpp"
#include "temp_dir.hpp"
#include "view/camera.hpp"
#include "view/image_io.hpp"

namespace surftrace::tools {
namespace {

namespace fs = std::filesystem;
using test::Result;

const std::string kCrambin = std::string(SURFTRACE_TEST_DATA) + "/structures/1crn.pdb";
const std::string kView = " --size 64x64 --view 1,0.3,-1 --quiet";

Result run(const std::string& args) { return test::runTool(args); }
bool has(const Result& r, const std::string& text) { return r.output.find(text) != std::string::npos; }

fs::path scratch(const std::string& name) {
  return ::surftrace::test::freshTempDir(name);
}

// 1CRN rendered with `args` into dir/name.exr.
std::string render(const fs::path& dir, const std::string& name, const std::string& args) {
  const std::string exr = (dir / (name + ".exr")).string();
  const Result r = run("render " + kCrambin + kView + " " + args + " --exr " + exr);
  EXPECT_EQ(r.status, 0) << args << ":\n" << r.output;
  return exr;
}

// `source` with `change` applied to its buffers, written to `path` with the same metadata (so the
// same engine, camera and settings).
template <class F>
std::string altered(const std::string& source, const std::string& path, F change) {
  view::ImageMetadata meta;
  view::FrameBuffers f = view::readExr(source, &meta);
  change(f);
  view::writeExr(path, f, meta);
  return path;
}

nlohmann::json report(const std::string& path) {
  std::ifstream in(path);
  return nlohmann::json::parse(in);
}

// A setting that changes pixels is an error naming both values, as a camera is; with
// --ignore-settings a note, and then the preset does not judge the colour.
TEST(CompareVerdict, RenderSettingsAreComparedLikeTheCamera) {
  const fs::path dir = scratch("settings");
  const std::string patch = render(dir, "patch", ""), element = render(dir, "element", "--color element"),
                    black = render(dir, "black", "--background 0,0,0"), cue = render(dir, "cue", "--depth-cue"),
                    uniform = render(dir, "uniform", "--color uniform --uniform-color 0.2,0.4,0.6"),
                    uniform2 = render(dir, "uniform2", "--color uniform");

  Result r = run("compare " + element + " " + patch);
  EXPECT_EQ(r.status, 1) << r.output;
  EXPECT_TRUE(has(r, "different settings")) << r.output;
  EXPECT_TRUE(has(r, "colour scheme: test element, reference patch")) << r.output;
  EXPECT_TRUE(has(r, "--ignore-settings")) << r.output;
  r = run("compare " + black + " " + patch);
  EXPECT_EQ(r.status, 1) << r.output;
  EXPECT_TRUE(has(r, "background: test 0,0,0, reference 1,1,1")) << r.output;
  r = run("compare " + patch + " " + cue);
  EXPECT_EQ(r.status, 1) << r.output;
  EXPECT_TRUE(has(r, "effects: test none, reference {\"depth_cue\"")) << r.output;
  r = run("compare " + uniform + " " + uniform2);
  EXPECT_EQ(r.status, 1) << r.output;
  EXPECT_TRUE(has(r, "uniform colour: test 0.2,0.4,0.6, reference 0.8,0.8,0.8")) << r.output;

  // Ignored: the geometry is the same, so it passes; the colour limit of the preset is set aside,
  // but one given on the command line still judges.
  r = run("compare " + element + " " + patch + " --ignore-settings");
  EXPECT_EQ(r.status, 0) << r.output;
  EXPECT_TRUE(has(r, "settings  differ (--ignore-settings): colour scheme: test element, reference patch")) << r.output;
  EXPECT_TRUE(has(r, "not compared: colour p99 < 1e-05 (the images were made with different settings)")) << r.output;
  r = run("compare " + element + " " + patch + " --ignore-settings --max-color-p99 0.01");
  EXPECT_EQ(r.status, 2) << r.output;
  EXPECT_TRUE(has(r, "colour p99")) << r.output;
}

// GL against Embree with the same settings: the colour is judged by default (gl-vs-embree has a
// colour limit), so a GL image whose surface is off by 0.05 in red fails.
TEST(CompareVerdict, ColourIsJudgedBetweenEnginesByDefault) {
  const fs::path dir = scratch("engines");
  const std::string embree = render(dir, "embree", ""), gl = render(dir, "gl", "--engine gl");
  Result r = run("compare " + gl + " " + embree);
  EXPECT_EQ(r.status, 0) << r.output;
  EXPECT_TRUE(has(r, "--preset gl-vs-embree")) << r.output;
  EXPECT_TRUE(has(r, "colour error     median")) << r.output;
  EXPECT_FALSE(has(r, "not compared: colour")) << r.output;
  const std::string redder = altered(gl, (dir / "redder.exr").string(), [](view::FrameBuffers& f) {
    for (std::size_t p = 0; p < f.pixels(); ++p)
      if (f.kind[p] != 0) f.rgba[4 * p] += f.rgba[4 * p] > 0.5f ? -0.05f : 0.05f;
  });
  r = run("compare " + redder + " " + embree);
  EXPECT_EQ(r.status, 2) << r.output;
  EXPECT_TRUE(has(r, "colour p99 0.05")) << r.output;
}

// The colour statistic is over the covered pixels; the background has its own, judged by the
// same limit: a background 0.3 darker shows there and only there.
TEST(CompareVerdict, ColourOverCoveredPixelsAndTheBackgroundApart) {
  const fs::path dir = scratch("background");
  const std::string ref = render(dir, "ref", "");
  const std::string grey = altered(ref, (dir / "grey.exr").string(), [](view::FrameBuffers& f) {
    for (std::size_t p = 0; p < f.pixels(); ++p)
      if (f.kind[p] == 0)
        for (int k = 0; k < 3; ++k) f.rgba[4 * p + static_cast<std::size_t>(k)] = 0.7f;
  });
  const std::string json = (dir / "grey.json").string();
  const Result r = run("compare " + grey + " " + ref + " --report " + json);
  EXPECT_EQ(r.status, 2) << r.output;
  EXPECT_TRUE(has(r, "background colour p99 0.3 > 1e-05")) << r.output;
  EXPECT_FALSE(has(r, "  colour p99")) << r.output;
  const nlohmann::json j = report(json);
  EXPECT_LT(j["color"]["p99"].get<double>(), 1e-6);
  EXPECT_NEAR(j["color_background"]["p99"].get<double>(), 0.3, 1e-6);
  EXPECT_GT(j["color"]["samples"].get<int>(), 20);
  EXPECT_GT(j["color_background"]["samples"].get<int>(), 1000);
}

// Two disjoint atoms, one partly hiding the other: where the edge of the front atom crosses a
// pixel (the rays through its corners hit the back atom, its centre the front one), a renderer
// may see either. Such pixels given the back atom's depth along the centre ray (Å off) are kept
// out of the depth figures and reported on the occlusion line. The oracle casts the rays
// through each pixel's centre and corners at the two spheres.
TEST(CompareVerdict, OcclusionEdgesAreReportedApart) {
  const fs::path dir = scratch("occlusion");
  const std::string xyzr = (dir / "two.xyzr").string(), ref = (dir / "ref.exr").string();
  const std::vector<glm::dvec4> atoms = {{0.0, 0.0, 0.0, 3.0}, {3.0, 1.0, -9.0, 3.0}};
  std::ofstream(xyzr) << "0 0 0 3\n3 1 -9 3\n";
  Result r = run("render " + xyzr + " --input-format xyzr --surface vdw --size 128x96 --eye 0,0,30 --look-at 1,0,-4 "
                 "--quiet --exr " + ref);
  ASSERT_EQ(r.status, 0) << r.output;
  // The nearest sphere a ray meets and where (index 2: none). A ray within 1e-3 Å of a sphere's
  // outline counts as neither (the tracer's rounding may go either way there): index 3.
  auto cast = [&](const view::Ray& ray) {
    std::pair<std::size_t, double> best{2, std::numeric_limits<double>::infinity()};
    for (std::size_t i = 0; i < atoms.size(); ++i) {
      const glm::dvec3 oc = glm::dvec3(atoms[i]) - ray.org;
      const double along = glm::dot(oc, ray.dir), perp = std::sqrt(glm::dot(oc, oc) - along * along);
      if (std::abs(perp - atoms[i].w) < 1e-3) return std::pair<std::size_t, double>{3, 0.0};
      const double t = along - std::sqrt(std::max(0.0, atoms[i].w * atoms[i].w - perp * perp));
      if (perp <= atoms[i].w && t < best.second) best = {i, t};
    }
    return best;
  };
  std::size_t moved = 0;
  double largest = 0.0;
  const std::string test = altered(ref, (dir / "edges.exr").string(), [&](view::FrameBuffers& f) {
    view::ImageMetadata meta;
    view::readExr(ref, &meta);
    const view::Camera camera = view::cameraFromJson(meta.at("surftrace:camera"));
    for (int y = 0; y < f.height; ++y)
      for (int x = 0; x < f.width; ++x) {
        const view::Ray centre = camera.ray(x + 0.5, y + 0.5);
        if (cast(centre).first != 0) continue;
        bool cornerOnBack = false;
        for (int c = 0; c < 4; ++c) cornerOnBack = cornerOnBack || cast(camera.ray(x + c % 2, y + c / 2)).first == 1;
        // The back atom along the centre ray, behind the front one.
        const glm::dvec3 oc = glm::dvec3(atoms[1]) - centre.org;
        const double along = glm::dot(oc, centre.dir), perp2 = glm::dot(oc, oc) - along * along;
        if (!cornerOnBack || perp2 > atoms[1].w * atoms[1].w) continue;
        const std::size_t p = static_cast<std::size_t>(y * f.width + x);
        const double back = along - std::sqrt(atoms[1].w * atoms[1].w - perp2);
        largest = std::max(largest, back - static_cast<double>(f.depth[p]));
        f.depth[p] = static_cast<float>(back);
        ++moved;
      }
  });
  ASSERT_GT(moved, 20u);
  const std::string json = (dir / "edges.json").string();
  r = run("compare " + test + " " + ref + " --preset exact --report " + json);
  EXPECT_EQ(r.status, 0) << r.output;
  EXPECT_TRUE(has(r, "occlusion edges ")) << r.output;
  const nlohmann::json j = report(json);
  EXPECT_GE(j["occlusion_edges"]["pixels"].get<std::size_t>(), moved) << r.output;
  EXPECT_NEAR(j["occlusion_edges"]["depth"]["max"].get<double>(), largest, 1e-3) << r.output;
  EXPECT_GT(largest, 3.0);
  EXPECT_LT(j["depth"]["max"].get<double>(), 1e-4) << r.output;
  std::printf("%zu pixels moved to the back atom (up to %.2f Å):\n%s", moved, largest, r.output.c_str());
}

// Nothing compared is not a pass: two images of empty space.
TEST(CompareVerdict, NoneComparedFails) {
  const fs::path dir = scratch("none");
  const std::string away = " --size 48x48 --eye 9,10,60 --look-at 9,10,120 --quiet --exr ";
  const std::string a = (dir / "a.exr").string(), b = (dir / "b.exr").string();
  ASSERT_EQ(run("render " + kCrambin + away + a).status, 0);
  ASSERT_EQ(run("render " + kCrambin + away + b).status, 0);
  const Result r = run("compare " + a + " " + b);
  EXPECT_EQ(r.status, 2) << r.output;
  EXPECT_TRUE(has(r, "depth error      none compared (0 px)")) << r.output;
  EXPECT_TRUE(has(r, "patch kind       none compared (0 px)")) << r.output;
  EXPECT_TRUE(has(r, "  depth: none compared (no pixel where both images hit")) << r.output;
  // Judging nothing on purpose still passes.
  EXPECT_EQ(run("compare " + a + " " + b + " --preset none").status, 0);
}

// NaN in a compared buffer: counted per buffer, kept out of the figures, judged a mismatch.
TEST(CompareVerdict, NanIsCountedAndJudgedAMismatch) {
  const fs::path dir = scratch("nan");
  const std::string ref = render(dir, "ref", "");
  std::size_t made = 0;
  const std::string test = altered(ref, (dir / "nan.exr").string(), [&](view::FrameBuffers& f) {
    for (std::size_t p = 0; p < f.pixels() && made < 5; p += 97)
      if (f.kind[p] != 0) f.depth[p] = std::numeric_limits<float>::quiet_NaN(), ++made;
  });
  ASSERT_EQ(made, 5u);
  const std::string json = (dir / "nan.json").string();
  const Result r = run("compare " + test + " " + ref + " --report " + json);
  EXPECT_EQ(r.status, 2) << r.output;
  EXPECT_TRUE(has(r, "NaN in 5 px of the test (depth 5, normal 0, colour 0)")) << r.output;
  EXPECT_TRUE(has(r, "NaN              test: depth 5 px")) << r.output;
  EXPECT_FALSE(has(r, " nan")) << r.output;
  const nlohmann::json j = report(json);
  EXPECT_EQ(j["nan"]["test"]["depth"].get<int>(), 5);
  EXPECT_EQ(j["nan"]["reference"]["pixels"].get<int>(), 0);
  EXPECT_LT(j["depth"]["max"].get<double>(), 1e-4);
}

// The per-kind table: each kind's signed depth error, from a test image moved by a known amount
// per kind (convex 0.02 Å nearer, concave 0.05 Å farther, toroidal untouched).
TEST(CompareVerdict, PerKindTableInTextAndJson) {
  const fs::path dir = scratch("kinds");
  const std::string ref = render(dir, "ref", "");
  const std::string test = altered(ref, (dir / "moved.exr").string(), [](view::FrameBuffers& f) {
    for (std::size_t p = 0; p < f.pixels(); ++p) {
      if (f.kind[p] == 1) f.depth[p] -= 0.02f;
      if (f.kind[p] == 3) f.depth[p] += 0.05f;
    }
  });
  const std::string json = (dir / "moved.json").string();
  const Result r = run("compare " + test + " " + ref + " --preset none --report " + json);
  EXPECT_EQ(r.status, 0) << r.output;
  EXPECT_TRUE(has(r, "per patch kind of the reference")) << r.output;
  for (const char* row : {"  1 convex", "  2 toroidal", "  3 concave"}) EXPECT_TRUE(has(r, row)) << row << "\n" << r.output;
  const nlohmann::json j = report(json);
  ASSERT_EQ(j["per_kind"].size(), 3u) << j.dump(1);
  std::size_t samples = 0;
  for (const nlohmann::json& k : j["per_kind"]) {
    const int kind = k["code"].get<int>();
    const std::size_t n = k["samples"].get<std::size_t>();
    samples += n;
    const double shift = kind == 1 ? -0.02 : kind == 3 ? 0.05 : 0.0;
    for (const char* q : {"median", "p1", "p99"}) EXPECT_NEAR(k[q].get<double>(), shift, 1e-4) << kind << " " << q;
    EXPECT_EQ(k["in_front"].get<std::size_t>(), kind == 1 ? n : 0u) << kind;
    EXPECT_EQ(k["behind"].get<std::size_t>(), kind == 3 ? n : 0u) << kind;
    EXPECT_GT(n, 50u) << kind;
    EXPECT_LE(n, k["pixels"].get<std::size_t>()) << kind;
    EXPECT_TRUE(k["normal_degrees"]["compared"].get<bool>());
  }
  EXPECT_EQ(samples, j["depth"]["samples"].get<std::size_t>());
}

}  // namespace
}  // namespace surftrace::tools

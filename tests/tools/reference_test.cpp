// Every reference/ recipe, re-rendered: Embree must reproduce its stored image (preset
// exact, and the colour too) and the GL path must agree with it (preset gl-vs-embree, or the
// case's own gl.preset), through the same `surftrace render` and `surftrace compare` a user runs.
#include <algorithm>
#include <array>
#include <cctype>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <string>
#include <vector>

#include <sys/wait.h>

#include <gtest/gtest.h>

#include "run_tool.hpp"
#include "temp_dir.hpp"

namespace {

namespace fs = std::filesystem;

using surftrace::tools::test::Result;
// Runs the tool from the repository root, where recipes' relative paths point.
Result run(const std::string& args) { return surftrace::tools::test::runTool(args, SURFTRACE_SOURCE_DIR); }

std::vector<std::string> referenceCases() {
  std::vector<std::string> cases;
  for (const auto& e : fs::directory_iterator(fs::path(SURFTRACE_SOURCE_DIR) / "reference"))
    if (fs::exists(e.path() / "recipe.args")) cases.push_back(e.path().filename().string());
  std::sort(cases.begin(), cases.end());
  return cases;
}

std::string recipe(const std::string& name) {
  std::ifstream in(fs::path(SURFTRACE_SOURCE_DIR) / "reference" / name / "recipe.args");
  std::string line;
  std::getline(in, line);
  return line;
}

// The preset GL is held to: the first line of reference/CASE/gl.preset (a technique's own
// limits, e.g. `effects`), else gl-vs-embree.
std::string glPreset(const std::string& name) {
  std::ifstream in(fs::path(SURFTRACE_SOURCE_DIR) / "reference" / name / "gl.preset");
  std::string line;
  if (!in || !std::getline(in, line) || line.empty()) return "gl-vs-embree";
  return line;
}

// Same engine, same options: the colour must agree too, to float rounding of the shading.
constexpr const char* kExactColor = " --max-color-p99 1e-5";

class Reference : public testing::TestWithParam<std::string> {};

TEST_P(Reference, EmbreeReproducesTheStoredImage) {
  const std::string name = GetParam();
  const std::string out = (::surftrace::test::testTempDir() / (name + "_embree.exr")).string();
  const Result r = run("render " + recipe(name) + " --quiet --exr " + out);
  ASSERT_EQ(r.status, 0) << r.output;
  const Result c = run("compare " + out + " reference/" + name + "/image.exr --preset exact" + kExactColor);
  EXPECT_EQ(c.status, 0) << "re-render differs from reference/" << name
                         << " (regenerate deliberately with scripts/update-reference.sh " << name << "):\n"
                         << c.output;
}

TEST_P(Reference, GlAgreesWithTheReference) {
  const std::string name = GetParam();
  const std::string out = (::surftrace::test::testTempDir() / (name + "_gl.exr")).string();
  const Result r = run("render " + recipe(name) + " --engine gl --quiet --exr " + out);
  ASSERT_EQ(r.status, 0) << r.output;
  const std::string diff = (::surftrace::test::testTempDir() / (name + "_gl_diff.png")).string();
  const Result c = run("compare " + out + " reference/" + name + "/image.exr --preset " + glPreset(name) + " --diff " + diff);
  EXPECT_EQ(c.status, 0) << c.output << "\ndifference image: " << diff;
  std::printf("%s, GL vs reference:\n%s", name.c_str(), c.output.c_str());
}

// The paper's primitive (bounding cylinder and its trapezoid, --gl-primitive cylinder)
// must cover every patch as the default box does: same agreement on the two close-ups,
// where tori and clipped concave triangles fill the view.
TEST(Reference, GlWithThePapersPrimitiveAgreesWithTheReference) {
  for (const std::string name : {"crambin-spindle-torus-closeup", "1vis-clipped-concave-closeup"}) {
    const std::string out = (::surftrace::test::testTempDir() / (name + "_gl_cylinder.exr")).string();
    const Result r = run("render " + recipe(name) + " --engine gl --gl-primitive cylinder --quiet --exr " + out);
    ASSERT_EQ(r.status, 0) << r.output;
    const Result c = run("compare " + out + " reference/" + name + "/image.exr --preset gl-vs-embree");
    EXPECT_EQ(c.status, 0) << name << ":\n" << c.output;
  }
}

INSTANTIATE_TEST_SUITE_P(Cases, Reference, testing::ValuesIn(referenceCases()),
                         [](const testing::TestParamInfo<std::string>& p) {
                           std::string s = p.param;
                           for (char& ch : s)
                             if (!std::isalnum(static_cast<unsigned char>(ch))) ch = '_';
                           return s;
                         });

// A corrupted reference is caught: the comparison must be able to fail.
TEST(Reference, ComparisonFailsOnADifferentImage) {
  const Result c = run("compare reference/crambin-front/image.exr reference/1vis-front/image.exr --preset exact --ignore-camera");
  EXPECT_EQ(c.status, 2) << c.output;
  const Result cameras = run("compare reference/crambin-front/image.exr reference/1vis-front/image.exr --preset exact");
  EXPECT_EQ(cameras.status, 1) << cameras.output;
  EXPECT_NE(cameras.output.find("different cameras"), std::string::npos) << cameras.output;
}

// The colour is compared too: the same geometry without the silhouettes is refused for its
// settings (the reference records its effects), and fails on its colour when they are set aside.
TEST(Reference, ComparisonFailsOnADifferentColour) {
  const std::string out = (::surftrace::test::testTempDir() / "no_silhouettes.exr").string();
  std::string args = recipe("crambin-silhouettes-darkening");
  const std::string flag = " --silhouettes";
  ASSERT_NE(args.find(flag), std::string::npos) << args;
  args.erase(args.find(flag), flag.size());
  const Result r = run("render " + args + " --quiet --exr " + out);
  ASSERT_EQ(r.status, 0) << r.output;
  const std::string ref = " reference/crambin-silhouettes-darkening/image.exr --preset exact" + std::string(kExactColor);
  const Result settings = run("compare " + out + ref);
  EXPECT_EQ(settings.status, 1) << settings.output;
  EXPECT_NE(settings.output.find("effects: test {"), std::string::npos) << settings.output;
  const Result c = run("compare " + out + ref + " --ignore-settings");
  EXPECT_EQ(c.status, 2) << c.output;
  EXPECT_NE(c.output.find("colour p99"), std::string::npos) << c.output;
}

}  // namespace

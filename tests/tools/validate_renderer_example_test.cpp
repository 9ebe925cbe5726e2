// The README's worked example, "Validating your renderer" (issue 20, item 5): an outside
// renderer that shares no code with SurfTrace (examples/validate_renderer/sphere_caster.py, a
// numpy ray caster that knows only the atoms and the camera's two matrices) passes `compare`
// for the vdW surface and fails it, with the error in Å, against the SES. The commands are the
// README's; its view is rotated, so that a normal-space mix-up shows.
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <regex>
#include <string>

#include <glm/ext/matrix_clip_space.hpp>
#include <glm/ext/matrix_transform.hpp>
#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

#include "oracles/python_oracle.hpp"
#include "run_tool.hpp"
#include "temp_dir.hpp"

namespace surftrace::tools {
namespace {

namespace oracle = ::surftrace::test;  // (tools::test is run_tool.hpp's)

const std::filesystem::path kCaster =
    std::filesystem::path(SURFTRACE_SOURCE_DIR) / "examples" / "validate_renderer" / "sphere_caster.py";
const std::string kMolecule = std::string(SURFTRACE_TEST_DATA) + "/structures/1crn.pdb";
const std::string kFlags = " --depth-convention window --test-origin bottom-left --test-normal normal.pfm --normal-space view";

std::filesystem::path freshDir(const std::string& name) {
  return ::surftrace::test::freshTempDir(name);
}

test::Result runIn(const std::filesystem::path& dir, const std::string& args) { return test::runTool(args, dir.string()); }

// The README's step 2, in `dir`: python3 sphere_caster.py atoms.xyzr cam.json depth.pfm --normal normal.pfm
// (under the configured interpreter, the paths spelled out: it runs from the test's directory).
oracle::OracleRun runCaster(const std::filesystem::path& dir) {
  return oracle::runPythonScript(kCaster,
                                 {(dir / "atoms.xyzr").string(), (dir / "cam.json").string(), (dir / "depth.pfm").string(),
                                  "--normal", (dir / "normal.pfm").string()},
                                 dir);
}

// The depth error line's p99 in Å ("depth error      median 0  p99 3.81e-06  max ... Å").
double depthP99(const std::string& output) {
  std::smatch m;
  if (!std::regex_search(output, m, std::regex(R"(depth error +median \S+ +p99 (\S+) +max \S+ Å)"))) return -1.0;
  return std::stod(m[1]);
}

TEST(CompareExample, NumpyRayCasterPassesTheVdwSurfaceAndFailsTheSes) {
  const std::filesystem::path dir = freshDir("validate_renderer");
  test::Result r = runIn(dir, "info " + kMolecule + " --xyzr atoms.xyzr");
  ASSERT_EQ(r.status, 0) << r.output;
  r = runIn(dir, "render " + kMolecule + " --surface vdw --size 256x256 --view 1,0.3,-1 --exr vdw.exr --camera-out cam.json");
  ASSERT_EQ(r.status, 0) << r.output;
  const oracle::OracleRun caster = runCaster(dir);
  ASSERT_TRUE(caster.ok()) << caster.describe();

  const test::Result pass = runIn(dir, "compare depth.pfm vdw.exr" + kFlags);
  EXPECT_EQ(pass.status, 0) << pass.output;
  EXPECT_NE(pass.output.find("PASS (foreign)"), std::string::npos) << pass.output;
  const double vdwP99 = depthP99(pass.output);
  EXPECT_GE(vdwP99, 0.0) << pass.output;
  EXPECT_LT(vdwP99, 1e-3) << pass.output;
  // The view is rotated, so the normals' space is checked too: world normals read as view ones
  // would fail (here the other way round: view normals declared as world ones).
  EXPECT_EQ(pass.output.find("view is not rotated"), std::string::npos) << pass.output;
  const test::Result space = runIn(dir, "compare depth.pfm vdw.exr --depth-convention window --test-origin bottom-left "
                                        "--test-normal normal.pfm --normal-space world");
  EXPECT_EQ(space.status, 2) << space.output;
  EXPECT_NE(space.output.find("hint: with --normal-space view the normal p99 would be"), std::string::npos) << space.output;

  r = runIn(dir, "render " + kMolecule + " --surface ses --camera cam.json --exr ses.exr");
  ASSERT_EQ(r.status, 0) << r.output;
  const test::Result fail = runIn(dir, "compare depth.pfm ses.exr" + kFlags);
  EXPECT_EQ(fail.status, 2) << fail.output;
  EXPECT_NE(fail.output.find("FAIL (foreign)"), std::string::npos) << fail.output;
  const double sesP99 = depthP99(fail.output);
  EXPECT_GT(sesP99, 0.5) << "the SES fills the crevices between atoms by Å, not less:\n" << fail.output;
  std::printf("vdW surface: depth p99 %.3g Å; SES: depth p99 %.3g Å\n", vdwP99, sesP99);
}

// The same door for a camera the outside program builds itself (glm::lookAt and
// glm::perspective, matrices only), as an acceptance check would.
TEST(CompareExample, NumpyRayCasterWithItsOwnLookAtPerspective) {
  const std::filesystem::path dir = freshDir("validate_renderer_own_camera");
  ASSERT_EQ(runIn(dir, "info " + kMolecule + " --xyzr atoms.xyzr").status, 0);
  auto matrix = [](const glm::dmat4& m) {
    nlohmann::json a = nlohmann::json::array();
    for (int c = 0; c < 4; ++c)
      for (int row = 0; row < 4; ++row) a.push_back(m[c][row]);
    return a;
  };
  const glm::dmat4 view = glm::lookAt(glm::dvec3(40.0, 25.0, 50.0), glm::dvec3(9.0, 10.0, 7.0), glm::dvec3(0.0, 1.0, 0.0));
  const glm::dmat4 projection = glm::perspective(glm::radians(35.0), 200.0 / 150.0, 30.0, 90.0);
  std::ofstream(dir / "cam.json") << nlohmann::json{{"width", 200}, {"height", 150}, {"view_matrix", matrix(view)},
                                                    {"projection_matrix", matrix(projection)}}
                                         .dump();
  ASSERT_EQ(runIn(dir, "render " + kMolecule + " --surface vdw --exr vdw.exr --camera cam.json").status, 0);
  const oracle::OracleRun caster = runCaster(dir);
  ASSERT_TRUE(caster.ok()) << caster.describe();
  const test::Result pass = runIn(dir, "compare depth.pfm vdw.exr" + kFlags);
  EXPECT_EQ(pass.status, 0) << pass.output;
  EXPECT_LT(depthP99(pass.output), 1e-3) << pass.output;
  const test::Result flipped = runIn(dir, "compare depth.pfm vdw.exr --test-origin top-left");
  EXPECT_EQ(flipped.status, 2) << flipped.output;
}

// The README's step 2 exactly as typed, `python3 examples/...` from the repository, where the
// first python3 on PATH cannot import numpy (a bare pyenv or venv; here /usr/bin/python3 with
// its site-packages cut off, as scripts/test.sh makes one): the script finds an interpreter
// that has numpy, as the tests' own choice does, and draws the same buffers.
TEST(CompareExample, ReadmeCommandRunsWhenTheFirstPython3HasNoNumpy) {
  const std::filesystem::path dir = freshDir("validate_renderer_no_numpy");
  ASSERT_EQ(test::runShell("/usr/bin/python3 -c 'import numpy' 2>&1").status, 0)
      << "/usr/bin/python3 must import numpy (Debian: python3-numpy), as the README's example expects";
  const std::filesystem::path bin = dir / "bin";
  std::filesystem::create_directories(bin);
  std::ofstream(bin / "python3") << "#!/bin/sh\nexec /usr/bin/python3 -I -S \"$@\"\n";
  std::filesystem::permissions(bin / "python3", std::filesystem::perms::owner_all);
  const std::string path = "PATH='" + bin.string() + "':\"$PATH\" ";
  ASSERT_NE(test::runShell(path + "python3 -c 'import numpy' 2>&1").status, 0) << "the stub imports numpy";

  ASSERT_EQ(runIn(dir, "info " + kMolecule + " --xyzr atoms.xyzr").status, 0);
  ASSERT_EQ(runIn(dir, "render " + kMolecule + " --surface vdw --size 64x48 --exr vdw.exr --camera-out cam.json").status, 0);
  const std::string inDir = "cd '" + std::string(SURFTRACE_SOURCE_DIR) + "' && " + path;
  const std::string files = " '" + (dir / "atoms.xyzr").string() + "' '" + (dir / "cam.json").string() + "' '" +
                            (dir / "depth.pfm").string() + "' --normal '" + (dir / "normal.pfm").string() + "'";
  const test::Result caster = test::runShell(inDir + "python3 examples/validate_renderer/sphere_caster.py" + files + " 2>&1");
  ASSERT_EQ(caster.status, 0) << caster.output;
  // A 64x48 window-depth PFM (one channel, "Pf"), and the buffers pass as the README says.
  std::ifstream pfm(dir / "depth.pfm", std::ios::binary);
  std::string magic;
  int width = 0, height = 0;
  pfm >> magic >> width >> height;
  EXPECT_EQ(magic, "Pf");
  EXPECT_EQ(width, 64);
  EXPECT_EQ(height, 48);
  const test::Result pass = runIn(dir, "compare depth.pfm vdw.exr" + kFlags);
  EXPECT_EQ(pass.status, 0) << pass.output;
}

}  // namespace
}  // namespace surftrace::tools

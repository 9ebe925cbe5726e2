// What `surftrace` says about the elements and radii of inputs without an element column: a
// GROMACS ruthenium complex, --radii element lines, the ways out of a missing radius, and
// MARTINI coarse-grained systems with --bead-radius.
#include <filesystem>
#include <fstream>
#include <string>

#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

#include "run_tool.hpp"
#include "temp_dir.hpp"

namespace {

using surftrace::tools::test::Result;
Result run(const std::string& args) { return surftrace::tools::test::runTool(args); }

std::string data(const std::string& file) { return std::string(SURFTRACE_TEST_DATA) + "/" + file; }

std::string writeText(const std::string& file, const std::string& text) {
  const std::filesystem::path path = ::surftrace::test::testTempDir() / file;
  std::ofstream(path, std::ios::binary) << text;
  return path.string();
}

bool contains(const std::string& text, const std::string& part) {
  return text.find(part) != std::string::npos;
}

TEST(InputCli, InfoShowsGuessedElementsWithTheMetal) {
  const std::string gro = data("formats/gro/ru_complex.gro");
  const Result text = run("info " + gro);
  ASSERT_EQ(text.status, 0) << text.output;
  EXPECT_TRUE(contains(text.output, "Ru 1")) << text.output;
  EXPECT_TRUE(contains(text.output, "elements guessed: 34 from atom names, 0 from masses")) << text.output;

  const Result json = run("info --json " + gro);
  ASSERT_EQ(json.status, 0) << json.output;
  const auto j = nlohmann::json::parse(json.output);
  EXPECT_EQ(j["elements"]["Ru"], 1);
  EXPECT_EQ(j["elements"]["Cl"], 3);
  EXPECT_FALSE(j["elements"].contains(""));
  EXPECT_EQ(j["elements_guessed"]["from_atom_names"], 34);
  EXPECT_EQ(j["elements_guessed"]["from_masses"], 0);
  EXPECT_EQ(j["radii"]["sources"]["Alvarez 2013"], 1);

  const Result csv = run("area --format csv " + gro);
  ASSERT_EQ(csv.status, 0) << csv.output;
  EXPECT_TRUE(contains(csv.output, ",R2M,3,,,Ru1,Ru,2.4600,")) << csv.output;
}

TEST(InputCli, RadiiElementLineAppliesToGuessedElements) {
  const std::string radii = writeText("ru_radii.txt", "Ru 2.10\n");
  const Result r = run("info --json --radii " + radii + " " + data("formats/gro/ru_complex.gro"));
  ASSERT_EQ(r.status, 0) << r.output;
  const auto j = nlohmann::json::parse(r.output);
  EXPECT_EQ(j["radii"]["sources"]["--radii table"], 1);
  EXPECT_FALSE(j["radii"]["sources"].contains("Alvarez 2013"));

  const Result csv = run("area --format csv --radii " + radii + " " + data("formats/gro/ru_complex.gro"));
  EXPECT_TRUE(contains(csv.output, ",Ru1,Ru,2.1000,")) << csv.output;
}

TEST(InputCli, MissingRadiusNamesAllThreeWaysOut) {
  const std::string gro = writeText("pm.gro",
                                    "promethium\n    2\n"
                                    "    1PMX    Pm1    1   0.000   0.000   0.000\n"
                                    "    1PMX     C1    2   0.300   0.000   0.000\n"
                                    "   3.00000   3.00000   3.00000\n");
  const Result r = run("info " + gro);
  EXPECT_NE(r.status, 0);
  EXPECT_TRUE(contains(r.output, gro + ":3: ")) << r.output;
  EXPECT_TRUE(contains(r.output, "'Pm r'")) << r.output;
  EXPECT_TRUE(contains(r.output, "'PMX:Pm1 r'")) << r.output;
  EXPECT_TRUE(contains(r.output, "--default-radius R")) << r.output;
  const Result fixed = run("info --default-radius 2.0 " + gro);
  EXPECT_EQ(fixed.status, 0) << fixed.output;
}

TEST(InputCli, MartiniNeedsBeadRadius) {
  const std::string gro = data("formats/gro/martini.gro");
  const Result refused = run("info " + gro);
  EXPECT_NE(refused.status, 0);
  EXPECT_TRUE(contains(refused.output, "MARTINI coarse-grained")) << refused.output;
  EXPECT_TRUE(contains(refused.output, "--bead-radius R")) << refused.output;
  EXPECT_FALSE(contains(refused.output, "elements   B")) << refused.output;

  const Result text = run("info --bead-radius 2.35 " + gro);
  ASSERT_EQ(text.status, 0) << text.output;
  EXPECT_TRUE(contains(text.output, "MARTINI coarse-grained: 9 beads, radius 2.35 Å (--bead-radius)")) << text.output;
  EXPECT_TRUE(contains(text.output, "3 water atoms")) << text.output;

  const Result json = run("info --json --bead-radius 2.35 --keep-water " + gro);
  ASSERT_EQ(json.status, 0) << json.output;
  const auto j = nlohmann::json::parse(json.output);
  EXPECT_EQ(j["atoms"], 12);
  EXPECT_EQ(j["coarse_grained"]["martini"], true);
  EXPECT_EQ(j["coarse_grained"]["beads"], 12);
  EXPECT_EQ(j["radii"]["sources"]["--bead-radius"], 12);
  EXPECT_FALSE(j["elements"].contains("B"));
  EXPECT_FALSE(j["elements"].contains("W"));

  const Result area = run("area --bead-radius 2.35 " + gro);
  EXPECT_EQ(area.status, 0) << area.output;
}

// A coarse-grained trajectory drawn on purpose (the GRO file is its own one-frame trajectory).
TEST(InputCli, MartiniTrajectoryDrawsWithBeadRadius) {
  const std::string gro = data("formats/gro/martini.gro");
  const std::string frames = (::surftrace::test::testTempDir() / "martini_%05d.png").string();
  const Result refused = run("trajectory " + gro + " " + gro + " --size 32x32 -o " + frames);
  EXPECT_NE(refused.status, 0);
  EXPECT_TRUE(contains(refused.output, "--bead-radius R")) << refused.output;
  const Result drawn = run("trajectory --bead-radius 2.35 " + gro + " " + gro + " --size 32x32 -o " + frames);
  ASSERT_EQ(drawn.status, 0) << drawn.output;
  EXPECT_TRUE(std::filesystem::exists(::surftrace::test::testTempDir() / "martini_00000.png"));
}

TEST(InputCli, EveryReadingCommandTakesBeadRadius) {
  for (const char* command : {"info", "area", "build", "render", "trajectory"}) {
    const Result r = run(std::string(command) + " --help");
    EXPECT_TRUE(contains(r.output, "--bead-radius")) << command;
  }
}

}  // namespace

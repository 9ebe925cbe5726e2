// The `surftrace` program end to end: what a user types and what they get back.
#include <array>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <string>

#include <sys/wait.h>

#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

#include "build/patch_list.hpp"

namespace {

struct Result {
  int status;
  std::string output;  // stdout and stderr together
};

Result run(const std::string& args) {
  const std::string cmd = std::string(SURFTRACE_TOOL) + " " + args + " 2>&1";
  FILE* pipe = popen(cmd.c_str(), "r");
  if (!pipe) return {-1, "popen failed"};
  std::string out;
  std::array<char, 4096> buf;
  while (std::fgets(buf.data(), static_cast<int>(buf.size()), pipe)) out += buf.data();
  const int status = pclose(pipe);
  return {WIFEXITED(status) ? WEXITSTATUS(status) : -1, out};
}

std::string data(const std::string& file) { return std::string(SURFTRACE_TEST_DATA) + "/" + file; }

TEST(Cli, HelpTeachesTheCommands) {
  const Result r = run("--help");
  EXPECT_EQ(r.status, 0);
  for (const char* word : {"info", "area", "build", "PDB", "mmCIF"}) EXPECT_NE(r.output.find(word), std::string::npos) << word;
}

TEST(Cli, InfoCountsTheDemoMolecule) {
  // 1VIS: 2531 atoms, of which 43 water (tests/data/MANIFEST.md).
  const Result r = run("info --json " + data("paper/1vis.pdb.gz"));
  ASSERT_EQ(r.status, 0) << r.output;
  const auto j = nlohmann::json::parse(r.output);
  EXPECT_EQ(j["atoms"], 2488);
  EXPECT_EQ(j["skipped"]["water"], 43);
  const Result keep = run("info --json --keep-water " + data("paper/1vis.pdb.gz"));
  EXPECT_EQ(nlohmann::json::parse(keep.output)["atoms"], 2531);
}

TEST(Cli, BadInputIsAClearErrorNotACrash) {
  const std::string path = (std::filesystem::path(testing::TempDir()) / "nan.xyzr").string();
  std::ofstream(path) << "0 0 0 1.5\n1 nan 0 1.5\n";
  const Result r = run("info " + path);
  EXPECT_EQ(r.status, 1) << r.output;
  EXPECT_NE(r.output.find(path + ":2"), std::string::npos) << r.output;
  const Result missing = run("info /no/such/file.pdb");
  EXPECT_NE(missing.status, 0);
  EXPECT_NE(missing.output.find("/no/such/file.pdb"), std::string::npos) << missing.output;
  const Result probe = run("area --probe -1 " + data("paper/1grm.pdb.gz"));
  EXPECT_NE(probe.status, 0);
  EXPECT_NE(probe.output.find("--probe"), std::string::npos) << probe.output;
}

TEST(Cli, AreaJsonHasTheDocumentedShape) {
  const Result r = run("area --format json " + data("paper/1grm.pdb.gz"));
  ASSERT_EQ(r.status, 0) << r.output;
  const auto j = nlohmann::json::parse(r.output);
  const double convex = j["ses"]["convex"], toroidal = j["ses"]["toroidal"], concave = j["ses"]["concave"];
  EXPECT_NEAR(j["ses"]["total"].get<double>(), convex + toroidal + concave, 1e-9);
  EXPECT_GT(j["ses"]["volume"].get<double>(), 0.0);
  EXPECT_GT(j["sas"]["total"].get<double>(), j["ses"]["total"].get<double>());
  double perAtom = 0;
  for (double v : j["sas"]["per_atom"]) perAtom += v;
  EXPECT_NEAR(perAtom, j["sas"]["total"].get<double>(), 1e-6);
  EXPECT_EQ(j["sas"]["per_atom"].size(), j["atoms"].get<std::size_t>());
}

TEST(Cli, BuildWritesAReadablePatchList) {
  const std::string out = (std::filesystem::path(testing::TempDir()) / "1grm.stp").string();
  const Result r = run("build " + data("paper/1grm.pdb.gz") + " --probe 1.4 -o " + out);
  ASSERT_EQ(r.status, 0) << r.output;
  const auto p = surftrace::build::readPatchList(out);
  EXPECT_EQ(p.params.atomCount, 272u);
  EXPECT_DOUBLE_EQ(p.params.probeRadius, 1.4);
  EXPECT_GT(p.tori.size(), 0u);
  EXPECT_GT(p.concave.size(), 0u);
  EXPECT_NE(p.params.inputCrc32, 0u);
}

}  // namespace

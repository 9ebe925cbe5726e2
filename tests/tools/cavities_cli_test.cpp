// `area --cavities` and `render --cavities` through the program: the cavities' lining atoms
// carry the file's own records, and the cavity render holds nothing of the outer surface.
#include <cmath>
#include <set>
#include <sstream>
#include <string>

#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

#include "build/io/molecule.hpp"
#include "run_tool.hpp"
#include "temp_dir.hpp"
#include "view/image_io.hpp"

namespace surftrace::tools::test {
namespace {

const std::string kMyoglobin = std::string(SURFTRACE_TEST_DATA) + "/structures/1mbn.pdb.gz";

nlohmann::json cavitiesJson(const std::string& file) {
  const Result r = runTool("area " + file + " --cavities --format json");
  EXPECT_EQ(r.status, 0) << r.output;
  return nlohmann::json::parse(r.output);
}

// As many cavities as `area` counts components of negative volume; every lining atom and
// residue is the file's (chain, number, insertion code, name as the reader gives them); the
// CSV has one row per lining atom.
TEST(CavitiesCli, AreaListsCavitiesWithTheirAtomsAndResidues) {
  const nlohmann::json j = cavitiesJson(kMyoglobin);
  const Result totals = runTool("area " + kMyoglobin + " --format json");
  ASSERT_EQ(totals.status, 0) << totals.output;
  std::size_t negative = 0;
  const nlohmann::json parsed = nlohmann::json::parse(totals.output);
  for (const auto& c : parsed["ses"]["components"]) negative += c["volume"].get<double>() < 0.0;
  ASSERT_EQ(j["cavities"].size(), negative);
  ASSERT_GT(negative, 0u);
  const build::Molecule m = build::readMolecule(kMyoglobin);
  std::size_t rows = 0;
  for (const auto& c : j["cavities"]) {
    EXPECT_GT(c["void_volume"].get<double>(), 0.0);
    std::set<std::string> residues;
    for (const auto& a : c["atoms"]) {
      const auto& r = m.atoms.at(a["atom"].get<std::size_t>());
      EXPECT_EQ(a["chain"], r.chain.str());
      EXPECT_EQ(a["resid"], r.residueNumber);
      EXPECT_EQ(a["resname"], r.residue.str());
      EXPECT_EQ(a["name"], r.name.str());
      EXPECT_EQ(a["icode"], r.insertionCode == ' ' ? std::string() : std::string(1, r.insertionCode));
      residues.insert(r.chain + "/" + std::to_string(r.residueNumber) + r.insertionCode + r.residue);
      ++rows;
    }
    EXPECT_EQ(c["residues"].size(), residues.size());
    for (int k = 0; k < 3; ++k) {
      EXPECT_LE(c["box"]["min"][k].get<double>(), c["centroid"][k].get<double>());
      EXPECT_GE(c["box"]["max"][k].get<double>(), c["centroid"][k].get<double>());
    }
  }
  const Result csv = runTool("area " + kMyoglobin + " --cavities --format csv");
  ASSERT_EQ(csv.status, 0) << csv.output;
  std::istringstream lines(csv.output);
  std::string line;
  std::size_t csvRows = 0;
  while (std::getline(lines, line)) csvRows += !line.empty();
  EXPECT_EQ(csvRows, rows + 1) << "a header and one row per lining atom";
}

TEST(CavitiesCli, SkinAndDropCavitiesAreRefusedWithTheReason) {
  const Result skin = runTool("area " + kMyoglobin + " --cavities --surface mss");
  EXPECT_NE(skin.status, 0);
  EXPECT_NE(skin.output.find("component labels"), std::string::npos) << skin.output;
  const Result both = runTool("render " + kMyoglobin + " --cavities --drop-cavities -o x.png");
  EXPECT_NE(both.status, 0);
  EXPECT_NE(both.output.find("--drop-cavities"), std::string::npos) << both.output;
}

// Every pixel `render --cavities` covers shows a lining atom of some cavity, behind the whole
// surface's pixel there (the outer surface is gone: nothing of it is drawn, so each hit lies
// inside the body); and the cavities are there to see.
TEST(CavitiesCli, RenderDrawsTheCavitiesAloneBehindTheOuterSurface) {
  const auto dir = ::surftrace::test::freshTempDir("cavities_render");
  const std::string all = (dir / "all.exr").string(), cavities = (dir / "cavities.exr").string();
  const std::string common = " --size 128x128 --quiet --exr ";
  ASSERT_EQ(runTool("render " + kMyoglobin + common + all).status, 0);
  const Result r = runTool("render " + kMyoglobin + " --cavities" + common + cavities);
  ASSERT_EQ(r.status, 0) << r.output;
  std::set<std::uint32_t> lining;
  const nlohmann::json listed = cavitiesJson(kMyoglobin);
  for (const auto& c : listed["cavities"])
    for (const auto& a : c["atoms"]) lining.insert(a["atom"].get<std::uint32_t>());
  const auto whole = view::readExr(all), alone = view::readExr(cavities);
  ASSERT_EQ(whole.depth.size(), alone.depth.size());
  std::size_t covered = 0;
  for (std::size_t k = 0; k < alone.depth.size(); ++k) {
    if (!std::isfinite(alone.depth[k])) continue;
    ++covered;
    EXPECT_TRUE(lining.count(alone.atomId[k])) << "pixel " << k << " shows atom " << alone.atomId[k];
    EXPECT_GT(alone.depth[k], whole.depth[k] + 1e-3) << "pixel " << k << " is on the outer surface";
  }
  EXPECT_GT(covered, 500u);
}

}  // namespace
}  // namespace surftrace::tools::test

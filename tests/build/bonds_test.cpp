// Bonds (build/bonds.hpp) against MDAnalysis: its distance guess on 1CRN, its CONECT records on
// 1GRM, and small hand-made cases of the distance rule.
#include "build/bonds.hpp"

#include <filesystem>
#include <map>
#include <set>
#include <sstream>
#include <utility>

#include <gtest/gtest.h>

#include "oracles/python_oracle.hpp"
#include "temp_dir.hpp"

namespace surftrace::build {
namespace {

namespace fs = std::filesystem;
using Pair = std::pair<std::uint32_t, std::uint32_t>;

fs::path tempDir() { return ::surftrace::test::freshTempDir("files"); }

// The oracle's pairs ("i j" lines); a test failure if it cannot run.
std::set<Pair> oracleBonds(const std::vector<std::string>& args) {
  const test::OracleRun run = test::runOracleScript("mda_bonds.py", args, tempDir());
  EXPECT_TRUE(run.ok()) << run.describe();
  std::set<Pair> pairs;
  std::istringstream in(run.out);
  std::uint32_t i = 0, j = 0;
  while (in >> i >> j) pairs.insert({i, j});
  return pairs;
}

std::set<Pair> asSet(const std::vector<glm::uvec2>& bonds) {
  std::set<Pair> pairs;
  for (const glm::uvec2& b : bonds) pairs.insert({b.x, b.y});
  return pairs;
}

TEST(Bonds, DistanceRuleMatchesMdanalysisGuessOn1crn) {
  const std::string path = std::string(SURFTRACE_TEST_DATA) + "/structures/1crn.pdb";
  const Molecule m = readMolecule(path);
  std::map<std::string, double> radii;
  for (const AtomRecord& a : m.atoms) radii[a.element] = covalentRadius(a.element);
  std::string table;
  for (const auto& [element, r] : radii) table += (table.empty() ? "" : ",") + element + "=" + std::to_string(r);
  const std::set<Pair> want = oracleBonds({"guess", path, table, "0.4"});
  ASSERT_GT(want.size(), m.size());  // a protein has more bonds than atoms
  std::vector<double> covalent(m.size());
  for (std::size_t i = 0; i < m.size(); ++i) covalent[i] = covalentRadius(m.atoms[i].element);
  EXPECT_EQ(asSet(distanceBonds(m.centers, covalent, {}, 0.4)), want);
  // 1CRN's CONECT records are its three disulfides, which the distance rule finds too.
  EXPECT_EQ(m.bondRecords.size(), 6u);
  EXPECT_EQ(asSet(moleculeBonds(m)), want);
}

TEST(Bonds, ConectRecordsOfHeteroGroupsMatchMdanalysisOn1grm) {
  const std::string path = std::string(SURFTRACE_TEST_DATA) + "/paper/1grm.pdb.gz";
  const Molecule m = readMolecule(path);
  const std::set<Pair> conect = oracleBonds({"conect", path});
  ASSERT_GT(conect.size(), 100u);
  const std::set<Pair> got = asSet(moleculeBonds(m));
  // Every record is a bond, and between two HETATM atoms that records name, only records are.
  std::vector<char> named(m.size(), 0);
  for (const Pair& p : conect) {
    EXPECT_TRUE(got.count(p)) << "CONECT bond " << p.first << "-" << p.second << " missing";
    named[p.first] = named[p.second] = 1;
  }
  for (const Pair& p : got) {
    if (named[p.first] && named[p.second] && m.atoms[p.first].hetatm && m.atoms[p.second].hetatm) {
      EXPECT_TRUE(conect.count(p)) << "bond " << p.first << "-" << p.second << " between recorded hetero atoms";
    }
  }
}

TEST(Bonds, MmcifStructConnLinksAreReadAndBonded) {
  const std::string path = std::string(SURFTRACE_TEST_DATA) + "/paper/1grm.cif.gz";
  const Molecule m = readMolecule(path);
  const test::OracleRun run = test::runOracleScript("mda_bonds.py", {"structconn", path}, tempDir());
  ASSERT_TRUE(run.ok()) << run.describe();
  // The oracle names each partner by author chain, residue number and atom name.
  auto find = [&](const std::string& chain, int seq, const std::string& name) {
    for (std::uint32_t i = 0; i < m.size(); ++i)
      if (m.atoms[i].chain == chain && m.atoms[i].residueNumber == seq && m.atoms[i].name == name) return i;
    return ~0u;
  };
  std::set<Pair> want;
  std::istringstream in(run.out);
  std::string c1, a1, c2, a2;
  int s1 = 0, s2 = 0;
  while (in >> c1 >> s1 >> a1 >> c2 >> s2 >> a2) {
    const std::uint32_t i = find(c1, s1, a1), j = find(c2, s2, a2);
    ASSERT_TRUE(i != ~0u && j != ~0u) << c1 << s1 << a1 << " " << c2 << s2 << a2;
    want.insert({std::min(i, j), std::max(i, j)});
  }
  ASSERT_EQ(want.size(), 28u);
  EXPECT_EQ(m.bondRecords.size(), 28u);
  const std::set<Pair> got = asSet(moleculeBonds(m));
  for (const Pair& p : want) EXPECT_TRUE(got.count(p)) << p.first << "-" << p.second;
  // mmCIF links add to the distance rule (residues' own bonds are not in the file).
  EXPECT_GT(got.size(), m.size());
}

TEST(Bonds, DistanceRuleAtItsThresholdAndAlternateLocations) {
  // Two carbons (r_cov 0.76 Å each): bonded below 0.76 + 0.76 + 0.4 = 1.92 Å, not above.
  const double r = covalentRadius("C");
  const std::vector<double> radii(4, r);
  const double s = 2 * r + 0.4;
  const std::vector<glm::dvec3> centers{{0, 0, 0}, {s * (1 - 1e-9), 0, 0}, {0, s * (1 + 1e-9), 0}, {0, 0, 0.05}};
  EXPECT_EQ(asSet(distanceBonds(centers, radii, {}, 0.4)), (std::set<Pair>{{0, 1}}))
      << "0-3 lie within the 0.1 Å lower bound, 0-2 beyond the sum";
  const std::vector<glm::dvec3> two{{0, 0, 0}, {1.5, 0, 0}};
  const std::vector<double> rr(2, r);
  EXPECT_EQ(distanceBonds(two, rr, std::vector<char>{'A', 'B'}, 0.4).size(), 0u);
  EXPECT_EQ(distanceBonds(two, rr, std::vector<char>{'A', 'A'}, 0.4).size(), 1u);
  EXPECT_EQ(distanceBonds(two, rr, std::vector<char>{' ', 'B'}, 0.4).size(), 1u);
  EXPECT_EQ(covalentRadius(""), r);
  EXPECT_NEAR(covalentRadius("Fe"), 1.32, 0.2);
}

TEST(Bonds, ToleranceOutsideItsRangeIsAnError) {
  Molecule m;
  EXPECT_THROW(moleculeBonds(m, -0.1), std::invalid_argument);
  EXPECT_THROW(moleculeBonds(m, 3.0), std::invalid_argument);
}

}  // namespace
}  // namespace surftrace::build

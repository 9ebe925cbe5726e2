// selectAtoms against MDAnalysis's select_atoms (tests/oracles/mda_select.py), an independent
// implementation of the same language, on the topologies of tests/data; and its errors.
#include "build/io/atom_selection.hpp"

#include <gmock/gmock.h>
#include <gtest/gtest.h>

#include <cstdio>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <stdexcept>
#include <string>
#include <utility>
#include <vector>

#include "build/io/molecule.hpp"
#include "oracles/python_oracle.hpp"
#include "temp_dir.hpp"

namespace surftrace::build {
namespace {

namespace fs = std::filesystem;
using ::testing::HasSubstr;

fs::path data(const std::string& relative) { return fs::path(SURFTRACE_TEST_DATA) / relative; }

// A fresh directory for one test's files.
fs::path tempDir() { return ::surftrace::test::freshTempDir("files"); }

// Every atom of the file, in file order, as a trajectory's topology is read (water kept; the
// massless sites of TIP4P waters, MW, are left out: AtomRecord::fileIndex keeps their place).
Molecule readTopology(const fs::path& path) {
  ReadOptions options;
  options.keepWater = true;
  options.topologyOnly = true;
  return readMolecule(path, options);
}

// What MDAnalysis selects, per selection: the 0-based indices, ascending.
std::vector<std::vector<std::uint32_t>> mdaSelect(const fs::path& topology, const std::vector<std::string>& selections,
                                                  std::size_t atoms, const fs::path& scratch) {
  std::vector<std::string> args = {topology.string()};
  args.insert(args.end(), selections.begin(), selections.end());
  const test::OracleRun run = test::runOracleScript("mda_select.py", args, scratch);
  if (!run.ok()) {
    ADD_FAILURE() << run.describe();
    return {};
  }
  std::istringstream out(run.out);
  std::string line;
  std::getline(out, line);
  EXPECT_EQ(std::stoul(line), atoms) << "MDAnalysis reads another number of atoms from " << topology;
  std::vector<std::vector<std::uint32_t>> picked;
  while (std::getline(out, line)) {
    std::istringstream in(line);
    picked.emplace_back();
    for (std::uint32_t i = 0; in >> i;) picked.back().push_back(i);
  }
  EXPECT_EQ(picked.size(), selections.size()) << run.out;
  return picked;
}

struct OracleCase {
  const char* file;
  std::vector<std::string> selections;  // each selects at least one atom
};

void PrintTo(const OracleCase& c, std::ostream* os) { *os << c.file; }

class SelectionAgreesWithMDAnalysis : public ::testing::TestWithParam<OracleCase> {};

TEST_P(SelectionAgreesWithMDAnalysis, SameAtoms) {
  const fs::path path = data(GetParam().file);
  const Molecule m = readTopology(path);
  // Our atoms by their place in the file; MDAnalysis's selections restricted to them.
  std::vector<char> present(m.fileAtomCount, 0);
  for (std::size_t i = 0; i < m.size(); ++i) present[m.atoms[i].fileIndex] = 1;
  const std::vector<std::string>& selections = GetParam().selections;
  const auto mda = mdaSelect(path, selections, m.fileAtomCount, tempDir());
  ASSERT_EQ(mda.size(), selections.size());
  for (std::size_t k = 0; k < selections.size(); ++k) {
    ASSERT_FALSE(mda[k].empty()) << "'" << selections[k] << "' selects nothing: choose another";
    std::vector<std::uint32_t> ours, theirs;
    EXPECT_NO_THROW(ours = selectAtoms(m, selections[k])) << selections[k];
    for (std::uint32_t& i : ours) i = static_cast<std::uint32_t>(m.atoms[i].fileIndex);
    for (std::uint32_t i : mda[k])
      if (present[i]) theirs.push_back(i);
    EXPECT_EQ(ours, theirs) << "'" << selections[k] << "' on " << GetParam().file << ": ours " << ours.size()
                            << " atoms, MDAnalysis " << theirs.size();
  }
}

// Precedence, parentheses, ranges, wildcards and the residue classes, on each kind of topology.
INSTANTIATE_TEST_SUITE_P(
    Topologies, SelectionAgreesWithMDAnalysis,
    ::testing::Values(
        OracleCase{"trajectories/adk_dims/adk.psf.gz",
                   {"not resname ALA and name CA or resid 5",
                    "resid 1 or resid 2 and name CA",
                    "name CA or name CB and resid 10-20",
                    "resname GLY and name CA or resname ALA and name CB",
                    "resid 10-20 and (name CA or name CB)",
                    "not not name CA",
                    "not (resid 1-200 or name CA)",
                    "not name CA and not name C and not name N and resid 3",
                    "not protein or name CA",
                    "(resname LYS ARG) and (name NZ or name NH*)",
                    "((resid 1-5) and not (name H* or (name C*)))",
                    "name C*",
                    "name H?",
                    "name [CN]A",
                    "name [!CHNO]*",
                    "name *1 and resname PHE TYR",
                    "resname AL? and not name H*",
                    "resid 10-20 30:35 40 to 42 50 - 52 60- 62 70 :72",
                    "resid 5 7 9",
                    "index 0-9 100",
                    "index 3340",
                    "atom 1-10",
                    "bynum 20:30 3341",
                    "protein",
                    "protein and not backbone",
                    "backbone",
                    "backbone and resid 3-5",
                    "segid 4AKE and resid 100",
                    "chain 4AKE and name SG",
                    "chainID 4AKE and resid 214",
                    "all and resid 214",
                    "name CA, resid 3",
                    "resid 3, resid 4 and name CA"}},
        OracleCase{"trajectories/2r9r/2r9r-1b.psf",
                   {"resname HSE", "protein and not backbone and name C*", "segid A and resid 380-390", "segid B C",
                    "chain D and segid D and name CA", "segid ? and name CA",
                    "resid 381:383 and not name H*", "index 1000-1283", "atom 1284"}},
        OracleCase{"trajectories/watdyn/watdyn.psf",
                   {"water", "water and name H*", "index 3-5", "atom 15", "name OH2 or resid 2", "segid WAT and index 0-5"}},
        OracleCase{"formats/gro/ubiquitin.gro",
                   {"water", "not water", "water and name O*", "protein or water", "water or resid 1 and not backbone",
                    "resid 1-5 and backbone", "index 1404", "name CA and resid 70-76", "segid SYSTEM and resid 1-3",
                    "segid SYS*"}},
        OracleCase{"structures/1ubq.pdb.gz",
                   {"chain A and resid 1-10", "element S", "element C N and not name CA", "element [NO] and resid 1",
                    "protein and element O", "resname HOH and index 600-610", "water", "backbone",
                    "segid A and resid 1-10", "chain A and segid A and name CA"}},
        OracleCase{"small/elements.pdb",
                   {"element Fe Cu", "element C* and not element Ca", "element ?", "element H", "resname Mg Ca",
                    "not element C H N O S", "segid A and element C"}},
        // Columns 67-76 hold E for the ligand only: the other atoms have no segid (MDAnalysis: "").
        OracleCase{"small/tiny.pdb",
                   {"chain C E", "chain E and not water", "resname UNK or resname HOH", "segid E", "segid E and chain E",
                    "not segid E and chain C", "chain C and not segid E"}},
        // No segids: the chains are the segments; some atoms have neither.
        OracleCase{"small/helix_amber.pdb", {"segid B", "chain B and name CA", "not segid B and name CA"}},
        OracleCase{"small/names.pdb", {"segid R", "chain Y", "segid Y and not name C*"}},
        OracleCase{"small/1grm_single.pdb", {"segid 1", "chain B and not segid 1", "chain A and name CA"}},
        // Neither: the one segment SYSTEM.
        OracleCase{"trajectories/sampletrajectory/sampletrajectory.pdb", {"segid SYSTEM and resid 242-244"}},
        // A PQR's chain is its segment, SYSTEM without one.
        OracleCase{"small/pqr/1000-chain-whitespace.pqr", {"segid A", "segid A and not name H*"}},
        OracleCase{"small/pqr/1000-whitespace.pqr", {"segid SYSTEM and name C*"}},
        OracleCase{"trajectories/cobrotoxin/cobrotoxin.pdb.gz",
                   {"water", "not water and not protein", "protein and name CA", "index 19000-19384", "atom 19385",
                    "resname NA CL", "segid SYSTEM and resname NA"}}));

// Insertion codes, on a PDB written here: a plain number is the residue without a code, as in
// MDAnalysis, and a range runs from its first end's code to its last end's.
TEST(SelectionAgreesWithMDAnalysisOnInsertionCodes, SameAtoms) {
  const fs::path dir = tempDir();
  const fs::path path = dir / "icodes.pdb";
  {
    std::ofstream out(path);
    const std::pair<int, char> residues[] = {{51, ' '}, {52, ' '}, {52, 'A'}, {52, 'B'}, {53, ' '}, {54, ' '}};
    int serial = 1;
    for (const auto& [number, code] : residues)
      for (const char* name : {" N  ", " CA ", " C  "}) {
        char line[100];
        std::snprintf(line, sizeof line, "ATOM  %5d %-4s %3s %c%4d%c   %8.3f%8.3f%8.3f%6.2f%6.2f          %2s\n",
                      serial, name, "ALA", 'A', number, code, serial * 1.5, 0.0, 0.0, 1.0, 0.0,
                      std::string(1, name[1]).c_str());
        out << line;
        ++serial;
      }
    out << "END\n";
  }
  const Molecule m = readTopology(path);
  ASSERT_EQ(m.size(), 18u);
  const std::vector<std::string> selections = {"resid 52",     "resid 52A",    "resid 52-53",  "resid 52A-52B",
                                               "resid 51-52A", "resid 52B:54", "resid 52 52B", "resid 51-52"};
  const auto mda = mdaSelect(path, selections, m.size(), dir);
  ASSERT_EQ(mda.size(), selections.size());
  for (std::size_t k = 0; k < selections.size(); ++k) {
    ASSERT_FALSE(mda[k].empty()) << selections[k];
    EXPECT_EQ(selectAtoms(m, selections[k]), mda[k]) << selections[k];
  }
}

// Chains and segment ids apart, as MDAnalysis has them: a PDB whose chain column is blank and
// whose segID column (73-76) names the segment (as adk_open.pdb, written by CHARMM), another
// segment whose chain differs from it, and a GRO (no chains; MDAnalysis's one segment SYSTEM).
TEST(SelectionAgreesWithMDAnalysisOnSegids, ChainsAndSegmentsApart) {
  const fs::path dir = tempDir();
  const fs::path pdb = dir / "segments.pdb";
  {
    std::ofstream out(pdb);
    struct Row {
      char chain;
      const char* segid;
      int resid;
    };
    const Row rows[] = {{' ', "4AKE", 1}, {' ', "4AKE", 2}, {'B', "PROB", 3}, {'B', "PROB", 4}, {'C', "4AKE", 5}};
    int serial = 1;
    for (const Row& r : rows)
      for (const char* name : {" N  ", " CA ", " C  "}) {
        char line[100];
        std::snprintf(line, sizeof line, "ATOM  %5d %-4s ALA %c%4d    %8.3f%8.3f%8.3f%6.2f%6.2f      %-4s\n", serial,
                      name, r.chain, r.resid, serial * 1.5, 0.0, 0.0, 1.0, 0.0, r.segid);
        out << line;
        ++serial;
      }
    out << "END\n";
  }
  const Molecule m = readTopology(pdb);
  ASSERT_EQ(m.size(), 15u);
  EXPECT_EQ(m.atoms[0].chain, "");
  EXPECT_EQ(m.atoms[0].segid, "4AKE");
  EXPECT_EQ(m.atoms[14].chain, "C");
  EXPECT_EQ(m.atoms[14].segid, "4AKE");
  const std::vector<std::string> selections = {"segid 4AKE", "segid PROB", "chain B", "chain C", "segid 4AKE and chain C",
                                               "segid 4AKE and not chain C", "segid PROB or chain C", "segid 4*"};
  const auto mda = mdaSelect(pdb, selections, m.size(), dir);
  ASSERT_EQ(mda.size(), selections.size());
  for (std::size_t k = 0; k < selections.size(); ++k) {
    ASSERT_FALSE(mda[k].empty()) << selections[k];
    EXPECT_EQ(selectAtoms(m, selections[k]), mda[k]) << selections[k];
  }
  // MDAnalysis reads no chain identifiers from a GRO; its one segment is SYSTEM.
  const Molecule gro = readTopology(data("formats/gro/ubiquitin.gro"));
  for (const AtomRecord& a : gro.atoms) {
    ASSERT_EQ(a.chain, "");
    ASSERT_EQ(a.segid, "SYSTEM");
  }
}

// The message of the std::invalid_argument that selectAtoms throws ("" if none).
std::string errorOf(const Molecule& m, const std::string& selection) {
  try {
    selectAtoms(m, selection);
  } catch (const std::invalid_argument& e) {
    return e.what();
  }
  ADD_FAILURE() << "'" << selection << "' was accepted";
  return "";
}

class SelectionErrors : public ::testing::Test {
 protected:
  static void SetUpTestSuite() { adk_ = new Molecule(readTopology(data("trajectories/adk_dims/adk.psf.gz"))); }
  static void TearDownTestSuite() { delete adk_; }
  static const Molecule& adk() { return *adk_; }
  static Molecule* adk_;
};
Molecule* SelectionErrors::adk_ = nullptr;

TEST_F(SelectionErrors, UnknownWordsArePointedAt) {
  // The selection of the issue: 'adn' reads as a residue name, so 'name' is where it breaks.
  EXPECT_EQ(errorOf(adk(), "resname R2M adn name Ru1"),
            "selection 'resname R2M adn name Ru1': at word 4 'name': needs 'and' or 'or' before it ('R2M adn' "
            "before it were read as values of 'resname')\n"
            "  resname R2M adn name Ru1\n"
            "                  ^^^^");
  EXPECT_THAT(errorOf(adk(), "colour red"),
              HasSubstr("at word 1 'colour': unknown keyword 'colour'; a term starts with name"));
  EXPECT_THAT(errorOf(adk(), "residue 9"), HasSubstr("unknown keyword 'residue'"));
  EXPECT_THAT(errorOf(adk(), "NAME CA"), HasSubstr("keywords are case-sensitive, as in MDAnalysis: 'name'"));
  EXPECT_THAT(errorOf(adk(), "name CA AND resid 5"),
              HasSubstr("at word 4 'resid': needs 'and' or 'or' before it ('CA AND' before it were read as values of "
                        "'name'; operators are lower case: 'and')"));
  EXPECT_THAT(
      errorOf(adk(), "name CA and around 5 resid 3"),
      HasSubstr("at word 4 'around': 'around' is an MDAnalysis selection keyword that surftrace does not support"));
  EXPECT_THAT(errorOf(adk(), "protein ALA"),
              HasSubstr("at word 2 'ALA': cannot follow 'protein', which takes no values"));
  EXPECT_THAT(errorOf(adk(), "(name CA) resid 5"), HasSubstr("at word 5 'resid': needs 'and' or 'or' before it"));
  EXPECT_THAT(errorOf(adk(), "resid x"),
              HasSubstr("at word 2 'x': 'x' is not a residue number or a range such as 10-20"));
  EXPECT_THAT(errorOf(adk(), "index 5A"), HasSubstr("'5A' is not an index (from 0)"));
  EXPECT_THAT(errorOf(adk(), "resid 20-10"), HasSubstr("the range 20-10 is empty (20 > 10)"));
  EXPECT_THAT(errorOf(adk(), "resid 10 to"), HasSubstr("at word 3 'to': needs a number on each side"));
  EXPECT_THAT(errorOf(adk(), "resid"), HasSubstr("at word 1 'resid': needs values, e.g. 'resid 10-20'"));
  EXPECT_THAT(errorOf(adk(), "name and resid 5"), HasSubstr("at word 1 'name': needs values"));
}

TEST_F(SelectionErrors, DanglingOperatorsAndParentheses) {
  EXPECT_EQ(errorOf(adk(), "name CA and"),
            "selection 'name CA and': the selection ends after 'and': expected a term such as 'name CA' after it\n"
            "  name CA and\n"
            "             ^");
  EXPECT_THAT(errorOf(adk(), "and name CA"),
              HasSubstr("at word 1 'and': expected a term such as 'name CA' at the start"));
  EXPECT_THAT(errorOf(adk(), "name CA or and resid 5"),
              HasSubstr("at word 4 'and': expected a term such as 'name CA' after 'or'"));
  EXPECT_THAT(errorOf(adk(), "not"), HasSubstr("the selection ends after 'not'"));
  EXPECT_THAT(errorOf(adk(), "name CA,"), HasSubstr("the selection ends after ','"));
  EXPECT_EQ(errorOf(adk(), "(name CA or resid 5"),
            "selection '(name CA or resid 5': at word 1 '(': is never closed: expected ')'\n"
            "  (name CA or resid 5\n"
            "  ^");
  EXPECT_THAT(errorOf(adk(), "((name CA) and resid 5"), HasSubstr("at word 1 '(': is never closed"));
  EXPECT_THAT(errorOf(adk(), "name CA) and resid 5"), HasSubstr("at word 3 ')': closes no '('"));
  EXPECT_THAT(errorOf(adk(), "name CA and ()"), HasSubstr("at words 4-5 '()': the parentheses hold no term"));
}

TEST_F(SelectionErrors, RangesBeyondTheSystem) {
  EXPECT_THAT(errorOf(adk(), "atom 1200-3400"),
              HasSubstr("at word 2 '1200-3400': atom 1200-3400: the topology has 3341 atoms (atom 1 to 3341)"));
  EXPECT_THAT(errorOf(adk(), "index 3341"), HasSubstr("index 3341: the topology has 3341 atoms (index 0 to 3340)"));
  EXPECT_THAT(errorOf(adk(), "bynum 0-5"), HasSubstr("bynum 0-5: the topology has 3341 atoms (bynum 1 to 3341)"));
  EXPECT_THAT(errorOf(adk(), "name CA or atom 10 to 4000"), HasSubstr("at words 5-7 '10 to 4000'"));
  EXPECT_EQ(selectAtoms(adk(), "atom 3341").size(), 1u);  // the last atom is within
}

TEST_F(SelectionErrors, EmptySelections) {
  EXPECT_EQ(errorOf(adk(), "   "), "the atom selection is empty");
  EXPECT_EQ(errorOf(adk(), "resid 900-999"),
            "selection 'resid 900-999' selects no atom (the molecule has residues 1 to 214)");
  EXPECT_THAT(errorOf(adk(), "resname R2M and name Ru1"),
              HasSubstr("selection 'resname R2M and name Ru1' selects no atom: 'resname R2M' matches no atom (the "
                        "molecule has residue names 'ALA', 'ARG', "));
  EXPECT_THAT(errorOf(adk(), "resname R2M and name Ru1"),
              HasSubstr("; 'name Ru1' matches no atom (the molecule has atom names 'C', 'CA', "));
  EXPECT_THAT(errorOf(adk(), "name CA and name CB"),
              HasSubstr("selects no atom, though each of its terms matches atoms ('name CA' 214, 'name CB' "));
  EXPECT_THAT(errorOf(adk(), "water"), HasSubstr("'water' selects no atom (the molecule has residue names"));
  EXPECT_THAT(errorOf(adk(), "element Fe"), HasSubstr("(the molecule has elements 'C', 'H', 'N', 'O', 'S')"));
  EXPECT_THAT(errorOf(adk(), "chain B"), HasSubstr("(the molecule has chains '4AKE')"));
  EXPECT_THAT(errorOf(adk(), "segid B"), HasSubstr("(the molecule has segids '4AKE')"));

  // Water the reader left out is named, with the option that keeps it.
  const Molecule dry = readMolecule(data("structures/1ubq.pdb.gz"));
  EXPECT_THAT(errorOf(dry, "water"),
              HasSubstr("58 water atoms were left out when it was read (--keep-water keeps them)"));
}

// Commas: the union of whole expressions, also inside parentheses.
TEST_F(SelectionErrors, CommasAreTheLoosestUnion) {
  const auto both = [&](const std::string& a, const std::string& b) {
    EXPECT_EQ(selectAtoms(adk(), a), selectAtoms(adk(), b)) << a;
  };
  both("resid 3, resid 4 and name CA", "resid 3 or (resid 4 and name CA)");
  both("name CA and (resid 1-10, resid 50-60)", "name CA and (resid 1-10 or resid 50-60)");
  both("chain 4AKE, resid 120-160", "all");
}

}  // namespace
}  // namespace surftrace::build

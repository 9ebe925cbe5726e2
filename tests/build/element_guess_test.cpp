// Elements guessed from atom names (GRO, PDB without element columns), their plausibility in
// the residue that holds them, the radii they get, MARTINI systems and --bead-radius; the
// guesses against MDAnalysis's guess_atom_element (tests/oracles/mda_elements.py).
#include <gmock/gmock.h>
#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>
#include <map>
#include <sstream>
#include <string>
#include <tuple>
#include <vector>

#include "build/io/error.hpp"
#include "build/io/molecule.hpp"
#include "build/io/radii.hpp"
#include "oracles/python_oracle.hpp"
#include "temp_dir.hpp"

namespace surftrace::build {
namespace {

namespace fs = std::filesystem;
using ::testing::HasSubstr;
using L = AtomNameLayout;

fs::path data(const std::string& relative) { return fs::path(SURFTRACE_TEST_DATA) / relative; }

// A scratch folder of this test's own.
fs::path scratch() {
  const auto* info = ::testing::UnitTest::GetInstance()->current_test_info();
  const fs::path dir = ::surftrace::test::testTempDir() /
                       ("surftrace_element_" + std::string(info->test_suite_name()) + "_" + info->name());
  fs::create_directories(dir);
  return dir;
}

fs::path writeText(const std::string& file, const std::string& text) {
  const fs::path path = scratch() / file;
  std::ofstream(path, std::ios::binary) << text;
  return path;
}

// A GRO file of the given (residue number, residue, name) atoms, 0.3 nm apart.
std::string gro(const std::vector<std::tuple<int, std::string, std::string>>& atoms) {
  std::ostringstream out;
  out << "hand-made\n" << atoms.size() << "\n";
  int i = 0;
  for (const auto& [number, residue, name] : atoms) {
    char line[64];
    std::snprintf(line, sizeof line, "%5d%-5s%5s%5d%8.3f%8.3f%8.3f\n", number, residue.c_str(),
                  name.c_str(), i + 1, 0.3 * i, 0.0, 0.0);
    out << line;
    ++i;
  }
  out << "   3.00000   3.00000   3.00000\n";
  return out.str();
}

std::string readError(const fs::path& path, const ReadOptions& options = {}) {
  try {
    readMolecule(path, options);
  } catch (const InputError& e) {
    return e.what();
  }
  ADD_FAILURE() << path << " read without an error";
  return {};
}

std::map<std::string, std::size_t> elementCounts(const Molecule& m) {
  std::map<std::string, std::size_t> counts;
  for (const AtomRecord& a : m.atoms) ++counts[a.element];
  return counts;
}

std::size_t fromSource(const Molecule& m, RadiusSource source) {
  return m.radiusSources[static_cast<std::size_t>(source)];
}

TEST(ElementGuess, TokensTakeTwoLettersWhereTheNameMeansThem) {
  // Written in the symbol's own case, or with a first letter that is no element.
  EXPECT_EQ(elementFromAtomName("Ru1", "R2M", L::Token), "Ru");
  EXPECT_EQ(elementFromAtomName("RU1", "R2M", L::Token), "Ru");
  EXPECT_EQ(elementFromAtomName("Cl1", "R2M", L::Token), "Cl");
  EXPECT_EQ(elementFromAtomName("Hg1", "LIG", L::Token), "Hg");
  EXPECT_EQ(elementFromAtomName("ZN2", "LIG", L::Token), "Zn");
  // Halogens and bare symbols with digits or charges after them.
  EXPECT_EQ(elementFromAtomName("CL2", "LIG", L::Token), "Cl");
  EXPECT_EQ(elementFromAtomName("BR1", "LIG", L::Token), "Br");
  EXPECT_EQ(elementFromAtomName("FE2", "HEM", L::Token), "Fe");
  EXPECT_EQ(elementFromAtomName("CU1", "LIG", L::Token), "Cu");  // as MDAnalysis
  EXPECT_EQ(elementFromAtomName("SI1", "LIG", L::Token), "Si");
  EXPECT_EQ(elementFromAtomName("NA", "HEM", L::Token), "N");     // heme's pyrrole nitrogen
  EXPECT_EQ(elementFromAtomName("NA+", "NA", L::Token), "Na");
  EXPECT_EQ(elementFromAtomName("CL-", "CL", L::Token), "Cl");
  // Names that MDAnalysis's table knows: CHARMM ions, GROMOS calcium.
  EXPECT_EQ(elementFromAtomName("SOD", "SOD", L::Token), "Na");
  EXPECT_EQ(elementFromAtomName("POT", "POT", L::Token), "K");
  EXPECT_EQ(elementFromAtomName("CLA", "CLA", L::Token), "Cl");
  // Upper-case organic names stay one-letter: C-alpha, H-gamma, N-epsilon, O-sigma.
  EXPECT_EQ(elementFromAtomName("CA1", "LIG", L::Token), "C");
  EXPECT_EQ(elementFromAtomName("HG1", "LIG", L::Token), "H");
  EXPECT_EQ(elementFromAtomName("NE2", "LIG", L::Token), "N");
  EXPECT_EQ(elementFromAtomName("OS1", "LIG", L::Token), "O");
  EXPECT_EQ(elementFromAtomName("1HB", "LIG", L::Token), "H");
  EXPECT_EQ(elementFromAtomName("X1", "LIG", L::Token), "");
  // Standard residues: the first letter.
  EXPECT_EQ(elementFromAtomName("Cd1", "LEU", L::Token), "C");
}

// Monatomic ions: the residue names the same element as the atom (MDAnalysis's table: NA, SOD,
// CL, CLA, POT, CAL, with charges and counts after them), or is the generic ION. Heme's pyrrole
// nitrogen NA and C-alpha stay N and C.
TEST(ElementGuess, IonsByResidueAndName) {
  EXPECT_EQ(elementFromAtomName(" NA ", "NA", L::PdbColumns), "Na");  // cobrotoxin.pdb
  EXPECT_EQ(elementFromAtomName(" CL ", "CL", L::PdbColumns), "Cl");
  EXPECT_EQ(elementFromAtomName("NA", "NA+", L::Token), "Na");  // adk_oplsaa.gro
  EXPECT_EQ(elementFromAtomName("CL", "CL-", L::Token), "Cl");
  EXPECT_EQ(elementFromAtomName("NA", "SOD", L::Token), "Na");
  EXPECT_EQ(elementFromAtomName("SOD ", "SOD", L::PdbColumns), "Na");  // CHARMM PDB: not sulfur
  EXPECT_EQ(elementFromAtomName("CLA ", "CLA", L::PdbColumns), "Cl");
  EXPECT_EQ(elementFromAtomName(" POT", "POT", L::PdbColumns), "K");
  EXPECT_EQ(elementFromAtomName(" K  ", "K", L::PdbColumns), "K");
  EXPECT_EQ(elementFromAtomName("K+", "K+", L::Token), "K");
  EXPECT_EQ(elementFromAtomName("MG", "MG2+", L::Token), "Mg");
  EXPECT_EQ(elementFromAtomName(" CA ", "CA", L::PdbColumns), "Ca");  // calcium (MDAnalysis: C)
  EXPECT_EQ(elementFromAtomName("CA", "CA2+", L::Token), "Ca");
  EXPECT_EQ(elementFromAtomName(" ZN ", "ZN", L::PdbColumns), "Zn");
  EXPECT_EQ(elementFromAtomName("NA", "ION", L::Token), "Na");
  EXPECT_EQ(elementFromAtomName("CL", "ION", L::Token), "Cl");
  EXPECT_EQ(elementFromAtomName(" NA ", "HEM", L::PdbColumns), "N");
  EXPECT_EQ(elementFromAtomName("NA", "HEM", L::Token), "N");
  EXPECT_EQ(elementFromAtomName(" CA ", "ALA", L::PdbColumns), "C");
}

TEST(ElementGuess, PdbNamesOffTheColumnsReadAsTokens) {
  EXPECT_EQ(elementFromAtomName(" RU ", "RUB", L::PdbColumns), "Ru");
  EXPECT_EQ(elementFromAtomName(" CA ", "LIG", L::PdbColumns), "C");  // the column still rules
  EXPECT_EQ(elementFromAtomName("CL1 ", "RUB", L::PdbColumns), "Cl");
}

TEST(ElementGuess, PlausibleElementsOfResidues) {
  EXPECT_FALSE(isPlausibleElement("ALA", "B"));
  EXPECT_FALSE(isPlausibleElement("LYS", "W"));
  EXPECT_TRUE(isPlausibleElement("CYS", "S"));
  EXPECT_TRUE(isPlausibleElement("MET", "Se"));
  EXPECT_FALSE(isPlausibleElement("SOL", "W"));
  EXPECT_FALSE(isPlausibleElement("HOH", "N"));
  EXPECT_TRUE(isPlausibleElement("SOL", "O"));
  EXPECT_TRUE(isPlausibleElement("R2M", "Ru"));
  EXPECT_TRUE(isWaterVirtualSite("MW"));
  EXPECT_TRUE(isWaterVirtualSite("LP1"));
  EXPECT_TRUE(isWaterVirtualSite("EPW"));
  EXPECT_FALSE(isWaterVirtualSite("OW"));
  EXPECT_FALSE(isWaterVirtualSite("HW1"));
}

TEST(ElementGuess, GroRutheniumComplexReadsWithItsMetal) {
  const Molecule m = readMolecule(data("formats/gro/ru_complex.gro"));
  // 38 atoms: 17 of the dipeptide, 18 of R2M, the NA and CL ions, a TIP4P water (4) dropped.
  ASSERT_EQ(m.size(), 34u);
  const auto counts = elementCounts(m);
  EXPECT_EQ(counts.at("Ru"), 1u);
  EXPECT_EQ(counts.at("Cl"), 3u);  // Cl1 and CL2 of R2M, the chloride CL
  EXPECT_EQ(counts.at("Na"), 1u);
  EXPECT_EQ(counts.count(""), 0u);
  EXPECT_EQ(m.elementsFromNames, m.size());
  EXPECT_EQ(m.elementsFromMasses, 0u);
  for (std::size_t i = 0; i < m.size(); ++i) {
    if (m.atoms[i].name == "Ru1") {
      EXPECT_DOUBLE_EQ(m.radii[i], 2.46);  // Alvarez 2013
    }
  }
  EXPECT_EQ(fromSource(m, RadiusSource::Alvarez), 1u);
}

TEST(ElementGuess, TipFourWaterSiteIsNoTungsten) {
  ReadOptions options;
  options.keepWater = true;
  const Molecule m = readMolecule(data("formats/gro/ru_complex.gro"), options);
  EXPECT_EQ(m.size(), 37u);  // OW, HW1, HW2 kept; MW left out
  EXPECT_EQ(m.skipped.virtualSites, 1u);
  EXPECT_EQ(elementCounts(m).count("W"), 0u);
}

TEST(ElementGuess, ElementLinesOfTheRadiusTableApplyToGuessedElements) {
  ReadOptions options;
  options.radiiFile = writeText("radii.txt", "Ru 2.10\n");
  const Molecule m = readMolecule(data("formats/gro/ru_complex.gro"), options);
  for (std::size_t i = 0; i < m.size(); ++i) {
    if (m.atoms[i].element == "Ru") {
      EXPECT_DOUBLE_EQ(m.radii[i], 2.10);
    }
  }
  EXPECT_EQ(fromSource(m, RadiusSource::UserTable), 1u);

  options.radiiFile = writeText("radii_atom.txt", "Ru 2.10\nR2M:Ru1 2.20\n");
  const Molecule n = readMolecule(data("formats/gro/ru_complex.gro"), options);
  for (std::size_t i = 0; i < n.size(); ++i) {
    if (n.atoms[i].element == "Ru") {
      EXPECT_DOUBLE_EQ(n.radii[i], 2.20);
    }
  }
}

TEST(ElementGuess, PdbWithoutElementColumnsFindsTheMetal) {
  const Molecule m = readMolecule(data("small/ru_no_element.pdb"));
  ASSERT_EQ(m.size(), 11u);
  const auto counts = elementCounts(m);
  EXPECT_EQ(counts.at("Ru"), 1u);
  EXPECT_EQ(counts.at("Cl"), 1u);
  EXPECT_EQ(counts.at("C"), 5u);
  EXPECT_EQ(m.elementsFromNames, 11u);
}

TEST(ElementGuess, PsfElementsComeFromMasses) {
  ReadOptions options;
  options.topologyOnly = true;
  const Molecule m = readMolecule(data("trajectories/adk_dims/adk.psf.gz"), options);
  EXPECT_EQ(m.elementsFromMasses, m.size());
  EXPECT_EQ(m.elementsFromNames, 0u);
}

TEST(ElementGuess, PsfMasslessWaterSiteIsLeftOut) {
  // CHARMM's TIP4P: OM is the massless site, whose name alone would read as oxygen.
  const fs::path path = writeText("tip4p.psf",
                                  "PSF\n\n       1 !NTITLE\n REMARKS hand-made\n\n"
                                  "       5 !NATOM\n"
                                  "       1 WAT  1    TIP4 OH2  OT    -1.040000       15.9994           0\n"
                                  "       2 WAT  1    TIP4 H1   HT     0.520000        1.0080           0\n"
                                  "       3 WAT  1    TIP4 H2   HT     0.520000        1.0080           0\n"
                                  "       4 WAT  1    TIP4 OM   LP     0.000000        0.0000           0\n"
                                  "       5 LIG  2    RUC  RU1  RU     2.000000      101.0700           0\n"
                                  "\n       0 !NBOND: bonds\n\n");
  ReadOptions options;
  options.topologyOnly = true;
  options.keepWater = true;
  const Molecule m = readMolecule(path, options);
  ASSERT_EQ(m.size(), 4u);
  EXPECT_EQ(m.skipped.virtualSites, 1u);
  EXPECT_EQ(m.atoms[3].element, "Ru");
  EXPECT_EQ(m.atoms[3].elementSource, ElementSource::Mass);
  EXPECT_EQ(m.elementsFromMasses, 4u);
  options.keepWater = false;
  EXPECT_EQ(readMolecule(path, options).skipped.water, 4u);
}

TEST(ElementGuess, ElementWithoutRadiusNamesAllThreeWaysOut) {
  const fs::path path = writeText("pm.gro", gro({{1, "PMX", "Pm1"}, {1, "PMX", "C1"}}));
  const std::string e = readError(path);
  EXPECT_THAT(e, HasSubstr(path.string() + ":3: "));
  EXPECT_THAT(e, HasSubstr("element Pm has no radius"));
  EXPECT_THAT(e, HasSubstr("'Pm r'"));
  EXPECT_THAT(e, HasSubstr("'PMX:Pm1 r'"));
  EXPECT_THAT(e, HasSubstr("--default-radius R"));
}

TEST(ElementGuess, UnknownElementSaysWhatToDo) {
  const fs::path path = writeText("x.gro", gro({{1, "LIG", "C1"}, {1, "LIG", "X1"}}));
  const std::string e = readError(path);
  EXPECT_THAT(e, HasSubstr(path.string() + ":4: "));
  EXPECT_THAT(e, HasSubstr("its element is unknown"));
  EXPECT_THAT(e, HasSubstr("'LIG:X1 r'"));
  EXPECT_THAT(e, HasSubstr("--default-radius R"));
  EXPECT_THAT(e, HasSubstr("--bead-radius R"));
}

TEST(ElementGuess, ImplausibleGuessInAStandardResidueIsAnError) {
  const fs::path path = writeText("fe_in_gly.gro", gro({{1, "GLY", "N"}, {1, "GLY", "FE"}}));
  const std::string e = readError(path);
  EXPECT_THAT(e, HasSubstr(path.string() + ":4: "));
  EXPECT_THAT(e, HasSubstr("'FE' of GLY 1"));
  EXPECT_THAT(e, HasSubstr("element Fe"));
  EXPECT_THAT(e, HasSubstr("--bead-radius R"));
  EXPECT_THAT(e, HasSubstr("'GLY:FE r'"));

  // A RES:ATOM line gives it a radius all the same, and no element is claimed.
  ReadOptions options;
  options.radiiFile = writeText("radii.txt", "GLY:FE 2.0\n");
  const Molecule m = readMolecule(path, options);
  EXPECT_DOUBLE_EQ(m.radii[1], 2.0);
  EXPECT_EQ(m.atoms[1].element, "");
}

TEST(ElementGuess, ImplausibleGuessInAWaterIsAnError) {
  ReadOptions options;
  options.keepWater = true;
  const fs::path path = writeText("n_in_water.gro", gro({{1, "SOL", "OW"}, {1, "SOL", "NW"}}));
  const std::string e = readError(path, options);
  EXPECT_THAT(e, HasSubstr(path.string() + ":4: "));
  EXPECT_THAT(e, HasSubstr("a water cannot hold"));
}

TEST(ElementGuess, MartiniWithoutBeadRadiusIsAnError) {
  const std::string e = readError(data("formats/gro/martini.gro"));
  EXPECT_THAT(e, HasSubstr("martini.gro:3: "));
  EXPECT_THAT(e, HasSubstr("'BB' of ALA 1"));
  EXPECT_THAT(e, HasSubstr("MARTINI coarse-grained"));
  EXPECT_THAT(e, HasSubstr("--bead-radius R"));
}

TEST(ElementGuess, MartiniWithBeadRadiusDrawsBeads) {
  ReadOptions options;
  options.beadRadius = 2.35;
  const Molecule m = readMolecule(data("formats/gro/martini.gro"), options);
  EXPECT_TRUE(m.martini);
  ASSERT_EQ(m.size(), 9u);  // 8 protein beads and the ion; W, W, WF are water
  EXPECT_EQ(m.skipped.water, 3u);
  for (double r : m.radii) EXPECT_DOUBLE_EQ(r, 2.35);
  EXPECT_EQ(fromSource(m, RadiusSource::Bead), 9u);
  EXPECT_EQ(m.elementsFromNames, 0u);
  for (const AtomRecord& a : m.atoms) EXPECT_EQ(a.element, "") << a.name;  // no boron, no sulfur
  ASSERT_TRUE(m.beadRadius);
  EXPECT_DOUBLE_EQ(*m.beadRadius, 2.35);

  options.keepWater = true;
  options.radiiFile = writeText("radii.txt", "ION:NA+ 1.9\nB 9.9\n");
  const Molecule w = readMolecule(data("formats/gro/martini.gro"), options);
  ASSERT_EQ(w.size(), 12u);
  EXPECT_DOUBLE_EQ(w.radii[11], 1.9);  // RES:ATOM wins; element lines do not touch beads
  EXPECT_DOUBLE_EQ(w.radii[0], 2.35);
  EXPECT_EQ(fromSource(w, RadiusSource::UserTable), 1u);
}

TEST(ElementGuess, MartiniWaterIsNoWaterInAnAtomisticFile) {
  // A residue W of one atom W is a tungsten ion where nothing says beads.
  ReadOptions options;
  const Molecule m = readMolecule(writeText("w.gro", gro({{1, "LIG", "C1"}, {2, "W", "W"}})), options);
  ASSERT_EQ(m.size(), 2u);
  EXPECT_EQ(m.atoms[1].element, "W");
}

// The ions of two solvated systems (cobrotoxin: NA in NA and CL in CL, PDB columns; AdK in OPLS-AA:
// NA in NA+, GRO) against MDAnalysis's guess_atom_element, which reads NA and CL as sodium and
// chlorine wherever they are: here every guess agrees with it, the protein's and the water's too.
TEST(ElementGuess, IonsAgreeWithMDAnalysis) {
  struct Case {
    const char* file;
    std::size_t sodium, chloride;
  };
  for (const Case& c : {Case{"trajectories/cobrotoxin/cobrotoxin.pdb.gz", 8, 11},
                        Case{"small/adk_oplsaa_ions.gro", 4, 0}}) {
    SCOPED_TRACE(c.file);
    const test::OracleRun run = test::runOracleScript("mda_elements.py", {data(c.file).string()}, scratch());
    ASSERT_TRUE(run.ok()) << run.describe();
    std::map<std::size_t, std::string> guess;
    std::map<std::string, std::size_t> mdaCounts;
    std::istringstream lines(run.out);
    for (std::string line; std::getline(lines, line);) {
      std::istringstream fields(line);
      std::size_t index = 0;
      std::string residue, name, element;
      fields >> index >> residue >> name >> element;
      guess[index] = element;
      ++mdaCounts[element];
    }
    ReadOptions options;
    options.keepWater = true;
    const Molecule m = readMolecule(data(c.file), options);
    ASSERT_EQ(guess.size(), m.fileAtomCount);
    for (const AtomRecord& a : m.atoms) {
      ASSERT_EQ(a.elementSource, ElementSource::Name) << a.name;
      std::string got = a.element;
      for (char& ch : got) ch = static_cast<char>(std::toupper(static_cast<unsigned char>(ch)));
      EXPECT_EQ(got, guess.at(a.fileIndex)) << a.name << " of " << a.residue << " " << a.residueNumber;
    }
    const auto counts = elementCounts(m);
    EXPECT_EQ(counts.count("Na") ? counts.at("Na") : 0, c.sodium);
    EXPECT_EQ(counts.count("Cl") ? counts.at("Cl") : 0, c.chloride);
    EXPECT_EQ(mdaCounts["NA"], c.sodium);
    EXPECT_EQ(mdaCounts["CL"], c.chloride);
    for (std::size_t i = 0; i < m.size(); ++i) {
      if (m.atoms[i].element == "Na") {
        EXPECT_DOUBLE_EQ(m.radii[i], 2.27);  // Bondi's sodium, not nitrogen's 1.55
      }
    }
  }
}

// A lipid-only MARTINI system (no protein beads, no water: a membrane patch of POPE, POPG and
// cholesterol, as martinize and insane write it) is recognised as coarse-grained; an atomistic
// CHARMM36 POPE and a heme, whose names look alike in part (C1A of heme), are not.
TEST(ElementGuess, MartiniLipidsAndSterolsAreBeads) {
  std::vector<std::tuple<int, std::string, std::string>> beads;
  for (const char* name : {"NH3", "PO4", "GL1", "GL2", "C1A", "D2A", "C3A", "C4A", "C1B", "C2B", "C3B", "C4B"})
    beads.emplace_back(1, "POPE", name);
  for (const char* name : {"GL0", "PO4", "GL1", "GL2", "C1A", "D2A", "C3A", "C4A", "C1B", "C2B", "C3B", "C4B"})
    beads.emplace_back(2, "POPG", name);
  for (const char* name : {"ROH", "R1", "R2", "R3", "R4", "R5", "C1", "C2"}) beads.emplace_back(3, "CHOL", name);
  const fs::path lipids = writeText("lipids.gro", gro(beads));
  const std::string e = readError(lipids);
  EXPECT_THAT(e, HasSubstr("lipids.gro:3: "));
  EXPECT_THAT(e, HasSubstr("'NH3' of POPE 1"));
  EXPECT_THAT(e, HasSubstr("MARTINI coarse-grained"));
  EXPECT_THAT(e, HasSubstr("--bead-radius R"));
  ReadOptions options;
  options.beadRadius = 2.35;
  const Molecule m = readMolecule(lipids, options);
  EXPECT_TRUE(m.martini);
  ASSERT_EQ(m.size(), beads.size());
  for (const AtomRecord& a : m.atoms) EXPECT_EQ(a.element, "") << a.name;  // no P of PO4, no G
  // The sterol alone is recognised too.
  const std::vector<std::tuple<int, std::string, std::string>> sterol(beads.end() - 8, beads.end());
  EXPECT_TRUE(readMolecule(writeText("chol.gro", gro(sterol)), options).martini);

  // Atomistic: CHARMM36's POPE head and glycerol, and heme's pyrrole carbons, read as atoms.
  const Molecule atoms = readMolecule(writeText(
      "atomistic.gro", gro({{1, "POPE", "N"}, {1, "POPE", "C12"}, {1, "POPE", "C11"}, {1, "POPE", "P"},
                            {1, "POPE", "O13"}, {1, "POPE", "O11"}, {1, "POPE", "C1"}, {1, "POPE", "C2"},
                            {1, "POPE", "O21"}, {1, "POPE", "C21"}, {1, "POPE", "C3"}, {1, "POPE", "O31"},
                            {2, "HEM", "FE"}, {2, "HEM", "NA"}, {2, "HEM", "C1A"}, {2, "HEM", "C2A"}})));
  EXPECT_FALSE(atoms.martini);
  EXPECT_EQ(elementCounts(atoms).at("P"), 1u);
  EXPECT_EQ(elementCounts(atoms).at("Fe"), 1u);
}

// MDAnalysis 2.4.2's guess_atom_element on every name of the GRO and PSF files in tests/data.
// Where SurfTrace guesses from a name it must agree, except where it deviates on purpose:
//  - MDAnalysis knows two-letter symbols only for its 16 light elements (tables.elements), so
//    it reads "Ru1" as "R", no element; SurfTrace reads a two-letter symbol ("Ru") there.
//  - Water virtual sites (MDAnalysis: "DUMMY") are left out, so they are not compared.
//  - Names whose guess a residue cannot hold are errors (tested above), not compared here.
// PSF atoms take their element from the mass; only those guessed from names are compared.
TEST(ElementGuess, AgreesWithMDAnalysis) {
  const std::vector<std::string> files = {
      "formats/gro/ru_complex.gro", "formats/gro/ubiquitin.gro",
      "trajectories/sampletrajectory/sampletrajectory.gro", "trajectories/2r9r/2r9r-1b.psf",
      "trajectories/watdyn/watdyn.psf", "trajectories/adk_dims/adk.psf.gz"};
  std::size_t compared = 0;
  std::size_t deviations = 0;
  for (const std::string& file : files) {
    SCOPED_TRACE(file);
    const test::OracleRun run = test::runOracleScript("mda_elements.py", {data(file).string()}, scratch());
    ASSERT_TRUE(run.ok()) << run.describe();
    std::map<std::size_t, std::string> guess;
    std::istringstream lines(run.out);
    std::string line;
    while (std::getline(lines, line)) {
      std::istringstream fields(line);
      std::size_t index = 0;
      std::string residue, name, element;
      fields >> index >> residue >> name >> element;
      guess[index] = element;
    }
    ReadOptions options;
    options.keepWater = true;
    options.topologyOnly = true;
    const Molecule m = readMolecule(data(file), options);
    ASSERT_EQ(guess.size(), m.fileAtomCount);
    for (const AtomRecord& a : m.atoms) {
      if (a.elementSource != ElementSource::Name) continue;
      const std::string& want = guess.at(a.fileIndex);
      std::string got = a.element;
      for (char& c : got) c = static_cast<char>(std::toupper(static_cast<unsigned char>(c)));
      ++compared;
      if (got == want) continue;
      const bool mdaHasNoSuchElement = canonicalElement(want).empty() && got.size() == 2 &&
                                       !want.empty() && got[0] == want[0];
      EXPECT_TRUE(mdaHasNoSuchElement)
          << a.name << " of " << a.residue << ": SurfTrace " << a.element << ", MDAnalysis " << want;
      ++deviations;
    }
  }
  EXPECT_GT(compared, 1000u);
  EXPECT_EQ(deviations, 1u);  // Ru1
}

}  // namespace
}  // namespace surftrace::build

// The colour maps against matplotlib's own (the oracle: matplotlib.colormaps[name](t) through
// tests/oracles/mpl_colormap.py), and the per-atom colour schemes and values file on small
// molecules built here: the numbers through the map, the missing colour, the selections painted
// over, and the errors for data a molecule does not have.
#include "view/color_map.hpp"

#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <fstream>
#include <random>
#include <sstream>
#include <stdexcept>
#include <string>
#include <utility>
#include <vector>

#include "oracles/mpl_colormap.hpp"
#include "oracles/srgb.hpp"
#include "temp_dir.hpp"
#include "view/atom_colors.hpp"
#include "view/atom_values.hpp"

namespace surftrace::view {
namespace {

// matplotlib's colours of `t` under `map`, one per number.
std::vector<glm::dvec3> matplotlibColors(const std::string& map, const std::vector<double>& t) {
  return ::surftrace::test::matplotlibColors(map, t, ::surftrace::test::testTempDir());
}

// The sRGB colour an image shows for an atom's colour: colorAtoms gives linear colours (what the
// renderers shade), the maps and tables are sRGB, so a test compares after encoding.
glm::dvec3 shown(const glm::vec3& linear) {
  using ::surftrace::test::srgbFromLinear;
  return {srgbFromLinear(linear.r), srgbFromLinear(linear.g), srgbFromLinear(linear.b)};
}

TEST(ColorMap, EveryMapEqualsMatplotlibs) {
  // Both sides of every one of the 256 entries' edges, the ends, out of range, and random numbers.
  std::vector<double> t = {0.0, 1.0, -0.25, 1.5, 0.5};
  for (int i = 1; i < 256; ++i) {
    t.push_back(i / 256.0);
    t.push_back(std::nextafter(i / 256.0, 0.0));
  }
  std::mt19937_64 rng(34);
  std::uniform_real_distribution<double> u(0.0, 1.0);
  for (int i = 0; i < 2000; ++i) t.push_back(u(rng));
  for (const std::string& name : ColorMap::names()) {
    const std::vector<glm::dvec3> want = matplotlibColors(name, t);
    ASSERT_EQ(want.size(), t.size()) << name;
    const ColorMap& map = ColorMap::named(name);
    double worst = 0.0;
    for (std::size_t i = 0; i < t.size(); ++i) {
      const glm::vec3 got = map.at(t[i]);
      for (int c = 0; c < 3; ++c) {
        worst = std::max(worst, std::abs(got[c] - want[i][c]));
        ASSERT_NEAR(got[c], want[i][c], 1e-6) << name << " at t = " << t[i] << ", channel " << c;
      }
    }
    std::printf("%s: %zu numbers, largest difference from matplotlib %.3g\n", name.c_str(), t.size(), worst);
  }
}

TEST(ColorMap, UnknownNameIsAnErrorNamingTheMaps) {
  try {
    ColorMap::named("jet");
    FAIL() << "no error";
  } catch (const std::invalid_argument& e) {
    EXPECT_NE(std::string(e.what()).find("'jet'"), std::string::npos) << e.what();
    EXPECT_NE(std::string(e.what()).find("viridis, magma, cividis, coolwarm"), std::string::npos) << e.what();
  }
}

// Two chains of residues, B-factors 10, 20, ... per atom; `names` false leaves them bare, as an
// XYZR file does.
build::Molecule smallMolecule(bool names = true) {
  build::Molecule m;
  m.source = "small";
  const char* residues[] = {"ALA", "ARG", "GLY", "HOH", "LEU", "HEM"};
  for (int i = 0; i < 12; ++i) {
    m.centers.emplace_back(1.5 * i, 0.0, 0.0);
    m.radii.push_back(1.5);
    build::AtomRecord a;
    a.fileIndex = static_cast<std::size_t>(i);
    a.name = i % 2 ? "CA" : "N";
    if (names) {
      a.residue = residues[i / 2];
      a.chain = i < 6 ? "A" : "B";
      a.residueNumber = 1 + i / 2;
      a.hetatm = a.residue == "HOH" || a.residue == "HEM";
      a.bFactor = 10.0 * (i + 1);
    }
    m.atoms.push_back(a);
  }
  m.fileAtomCount = m.size();
  return m;
}

std::string errorOf(const build::Molecule& m, const ColorScheme& s) {
  try {
    colorAtoms(m, s);
  } catch (const std::exception& e) {
    return e.what();
  }
  return "no error";
}

TEST(AtomColors, NumbersGoThroughTheMapBetweenTheRangesEnds) {
  const build::Molecule m = smallMolecule();
  ColorScheme s;
  s.mode = ColorMode::BFactor;
  s.map = "magma";
  AtomColoring c = colorAtoms(m, s);
  ASSERT_TRUE(c.legend);
  EXPECT_EQ(c.legend->lo, 10.0);
  EXPECT_EQ(c.legend->hi, 120.0);
  EXPECT_TRUE(c.legend->rangeFromData);
  std::vector<double> t;
  for (int i = 0; i < 12; ++i) t.push_back((10.0 * (i + 1) - 10.0) / 110.0);
  std::vector<glm::dvec3> want = matplotlibColors("magma", t);
  ASSERT_EQ(want.size(), t.size());
  for (std::size_t i = 0; i < t.size(); ++i)
    for (int k = 0; k < 3; ++k) EXPECT_NEAR(shown(c.colors[i])[k], want[i][k], 1e-6) << "atom " << i;
  // A range of one's own clips: 40 and below take the first entry, 80 and above the last.
  s.range = std::array<double, 2>{40.0, 80.0};
  c = colorAtoms(m, s);
  EXPECT_FALSE(c.legend->rangeFromData);
  t.clear();
  for (int i = 0; i < 12; ++i) t.push_back((10.0 * (i + 1) - 40.0) / 40.0);
  want = matplotlibColors("magma", t);
  for (std::size_t i = 0; i < t.size(); ++i)
    for (int k = 0; k < 3; ++k) EXPECT_NEAR(shown(c.colors[i])[k], want[i][k], 1e-6) << "atom " << i;
}

TEST(AtomColors, HydrophobicityAndRainbowLeaveOtherResiduesMissing) {
  const build::Molecule m = smallMolecule();
  ColorScheme s;
  s.mode = ColorMode::Hydrophobicity;
  AtomColoring c = colorAtoms(m, s);
  // ALA 1.8, ARG -4.5, GLY -0.4, LEU 3.8 (Kyte and Doolittle 1982, Table 2); HOH and HEM have none.
  EXPECT_EQ(c.legend->lo, -4.5);
  EXPECT_EQ(c.legend->hi, 3.8);
  EXPECT_EQ(c.legend->missing, 4u);
  for (int i : {6, 7, 10, 11})
    for (int k = 0; k < 3; ++k) EXPECT_NEAR(shown(c.colors[static_cast<std::size_t>(i)])[k], kMissingColor[k], 1e-6) << i;
  s.mode = ColorMode::Rainbow;
  c = colorAtoms(m, s);
  // Chain A: ALA, ARG, GLY at 0, 1/2, 1; chain B: LEU alone at 0; HOH and HEM are hetero groups.
  const ColorMap& rainbow = ColorMap::named("rainbow");
  const std::pair<std::size_t, double> at[] = {{0, 0.0}, {3, 0.5}, {5, 1.0}, {8, 0.0}};
  for (const auto& [atom, t] : at)
    for (int k = 0; k < 3; ++k) EXPECT_NEAR(shown(c.colors[atom])[k], rainbow.at(t)[k], 1e-6) << atom;
  for (int k = 0; k < 3; ++k) EXPECT_NEAR(shown(c.colors[6])[k], kMissingColor[k], 1e-6);
  EXPECT_EQ(c.legend->missing, 4u);
}

TEST(AtomColors, SelectionsPaintInOrderOverTheScheme) {
  const build::Molecule m = smallMolecule();
  ColorScheme s;
  s.mode = ColorMode::Uniform;
  s.overrides = {{"chain A", {1.0f, 0.0f, 0.0f}}, {"name CA", {0.0f, 1.0f, 0.0f}}};
  const AtomColoring c = colorAtoms(m, s);
  for (std::size_t i = 0; i < m.size(); ++i) {
    const glm::vec3 want = i % 2 ? glm::vec3(0, 1, 0) : i < 6 ? glm::vec3(1, 0, 0) : glm::vec3(0.8f);
    for (int k = 0; k < 3; ++k) EXPECT_NEAR(shown(c.colors[i])[k], want[k], 1e-6) << "atom " << i;
  }
  EXPECT_EQ(c.overridden, (std::vector<std::size_t>{6, 6}));
  s.overrides = {{"resname TRP", {1.0f, 0.0f, 0.0f}}};
  EXPECT_NE(errorOf(m, s).find("--color-select"), std::string::npos) << errorOf(m, s);
}

TEST(AtomColors, ASchemeWithoutDataIsAnError) {
  const build::Molecule bare = smallMolecule(false);
  ColorScheme s;
  s.mode = ColorMode::BFactor;
  EXPECT_NE(errorOf(bare, s).find("small has no B-factors"), std::string::npos) << errorOf(bare, s);
  s.mode = ColorMode::Residue;
  EXPECT_NE(errorOf(bare, s).find("small has no residue names"), std::string::npos) << errorOf(bare, s);
  s.mode = ColorMode::Hydrophobicity;
  EXPECT_NE(errorOf(bare, s).find("small has no amino-acid residues"), std::string::npos) << errorOf(bare, s);
  s.mode = ColorMode::Rainbow;
  EXPECT_NE(errorOf(bare, s).find("small has no residues"), std::string::npos) << errorOf(bare, s);
  s.mode = ColorMode::Value;
  EXPECT_NE(errorOf(bare, s).find("needs --values"), std::string::npos) << errorOf(bare, s);
  // One B-factor for every atom gives the map no range.
  build::Molecule flat = smallMolecule();
  for (auto& a : flat.atoms) a.bFactor = 20.0;
  s.mode = ColorMode::BFactor;
  EXPECT_NE(errorOf(flat, s).find("every atom's B-factor is 20, so the colour map has no range: give --color-range"), std::string::npos) << errorOf(flat, s);
  s.range = std::array<double, 2>{0.0, 40.0};
  for (int k = 0; k < 3; ++k)
    EXPECT_NEAR(shown(colorAtoms(flat, s).colors[0])[k], ColorMap::named("coolwarm").at(0.5)[k], 1e-6);
}

std::string writeValues(const std::string& name, const std::string& text) {
  const std::string path = (::surftrace::test::testTempDir() / name).string();
  std::ofstream(path) << text;
  return path;
}

std::string valuesError(const std::string& text) {
  const std::string path = writeValues("bad.csv", text);
  try {
    readAtomValues(path, smallMolecule());
  } catch (const std::exception& e) {
    return e.what();
  }
  return "no error";
}

TEST(AtomValues, AtomAndResidueRowsGiveTheirAtomsValues) {
  const build::Molecule m = smallMolecule();
  const AtomValues byAtom = readAtomValues(writeValues("a.csv", "# RMSF\natom, rmsf\n0,1.5\n3, -2\n11,nan\n"), m);
  EXPECT_EQ(byAtom.label, "rmsf");
  EXPECT_EQ(byAtom.values[0], 1.5);
  EXPECT_EQ(byAtom.values[3], -2.0);
  EXPECT_TRUE(std::isnan(byAtom.values[1]));
  EXPECT_TRUE(std::isnan(byAtom.values[11]));
  EXPECT_EQ(byAtom.valued(), 2u);
  const AtomValues byResidue =
      readAtomValues(writeValues("r.csv", "chain,resid,conservation\nA,2,0.25\nB,5,0.75\nB,99,1\n"), m);
  EXPECT_EQ(byResidue.label, "conservation");
  for (std::size_t i = 0; i < m.size(); ++i) {
    const double want = i == 2 || i == 3 ? 0.25 : i == 8 || i == 9 ? 0.75 : NAN;
    if (std::isnan(want))
      EXPECT_TRUE(std::isnan(byResidue.values[i])) << i;
    else
      EXPECT_EQ(byResidue.values[i], want) << i;
  }
  EXPECT_EQ(byResidue.unmatchedRows, 1u);
  EXPECT_EQ(byResidue.firstUnmatched, "line 4 (chain B resid 99)");
}

TEST(AtomValues, ErrorsNameTheFileTheLineAndTheValue) {
  EXPECT_NE(valuesError("atom,rmsf\n0,1\n1,abc\n").find("bad.csv:3: value 'abc' is not a finite number"),
            std::string::npos)
      << valuesError("atom,rmsf\n0,1\n1,abc\n");
  EXPECT_NE(valuesError("index,rmsf\n").find("bad.csv:1: header 'index,rmsf'"), std::string::npos);
  EXPECT_NE(valuesError("atom,rmsf\n2,1,3\n").find("bad.csv:2: '2,1,3': 3 fields, but the header has 2"),
            std::string::npos);
  EXPECT_NE(valuesError("atom,rmsf\n12,1\n").find("bad.csv:2: atom 12 is beyond the structure's 12 atoms"),
            std::string::npos);
  EXPECT_NE(valuesError("atom,rmsf\n-1,1\n").find("bad.csv:2: atom '-1' is not an atom index"), std::string::npos);
  EXPECT_NE(valuesError("chain,resid,x\nA,1,1\nA,1,2\n").find("bad.csv:3: chain A resid 1 gives atom 0 a value that "
                                                             "line 2 gave it already"),
            std::string::npos)
      << valuesError("chain,resid,x\nA,1,1\nA,1,2\n");
  EXPECT_NE(valuesError("chain,resid,x\nC,1,1\n").find("no atom of small gets a value"), std::string::npos);
  EXPECT_NE(valuesError("atom,x\n1,inf\n").find("value 'inf' is not a finite number"), std::string::npos);
}

}  // namespace
}  // namespace surftrace::view

// Tests of the GRO and PSF topology parsers and of the text trajectory readers (GRO, XYZ, PDB,
// mmCIF) against MDAnalysis (tests/oracles/mda_topology.py, mda_frames.py), an independent
// implementation, and against files the tests write themselves. mmCIF, which MDAnalysis 2.4
// cannot read, is checked against a plain tokenizer of the _atom_site loop written here.
#include <gmock/gmock.h>
#include <gtest/gtest.h>
#include <zlib.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <map>
#include <numbers>
#include <optional>
#include <sstream>
#include <string>
#include <vector>

#include "build/io/error.hpp"
#include "build/io/topology_formats.hpp"
#include "build/io/trajectory.hpp"
#include "oracles/python_oracle.hpp"
#include "temp_dir.hpp"

namespace surftrace::build {
namespace {

namespace fs = std::filesystem;
using ::testing::HasSubstr;

fs::path data(const std::string& relative) { return fs::path(SURFTRACE_TEST_DATA) / relative; }

std::string readBytes(const fs::path& path) {
  std::ifstream in(path, std::ios::binary);
  std::stringstream buffer;
  buffer << in.rdbuf();
  return buffer.str();
}

// The text of a file, gunzipped when it starts with the gzip magic (zlib, not our reader).
std::string fileText(const fs::path& path) {
  std::string bytes = readBytes(path);
  if (bytes.size() < 2 || static_cast<unsigned char>(bytes[0]) != 0x1f ||
      static_cast<unsigned char>(bytes[1]) != 0x8b)
    return bytes;
  gzFile in = gzopen(path.string().c_str(), "rb");
  EXPECT_NE(in, nullptr) << path;
  std::string text;
  char buffer[1 << 16];
  int n = 0;
  while (in && (n = gzread(in, buffer, sizeof buffer)) > 0)
    text.append(buffer, static_cast<std::size_t>(n));
  if (in) gzclose(in);
  return text;
}

void writeText(const fs::path& path, const std::string& text) {
  std::ofstream out(path, std::ios::binary);
  out << text;
}

std::vector<std::string> lines(const std::string& text) {
  std::vector<std::string> out;
  std::istringstream in(text);
  for (std::string line; std::getline(in, line);) out.push_back(line);
  return out;
}

std::string joinLines(const std::vector<std::string>& lines) {
  std::string text;
  for (const std::string& line : lines) text.append(line).append(1, '\n');
  return text;
}

// A fresh directory for one test's files.
fs::path tempDir() { return ::surftrace::test::freshTempDir("files"); }

// ---------------------------------------------------------------------------------------------
// The MDAnalysis oracles

// Runs an oracle script under the Python the build chose (tests/oracles/python_oracle.hpp); a
// test failure (never a skip) if it cannot run, saying what to install.
bool runOracle(const std::string& script, const std::vector<std::string>& args,
               const fs::path& scratch) {
  const test::OracleRun run = test::runOracleScript(script, args, scratch);
  if (run.ok()) return true;
  if (run.exitCode == 3 || run.err.find("ImportError") != std::string::npos ||
      run.err.find("ModuleNotFoundError") != std::string::npos)
    ADD_FAILURE() << script << " cannot import MDAnalysis: install python3-mdanalysis "
                  << "(apt-get install python3-mdanalysis).\n"
                  << run.describe();
  else
    ADD_FAILURE() << script << " failed on " << args.front() << ": " << run.describe();
  return false;
}

struct MdaFrame {
  double time = 0.0;
  bool hasCell = false;
  std::array<double, 6> cell{};
  std::vector<float> positions;  // x y z per atom, Å
};

struct MdaFrames {
  std::size_t atoms = 0;
  std::size_t declaredFrames = 0;  // MDAnalysis's n_frames
  std::vector<MdaFrame> frames;    // as many as its iteration gave
};

// MDAnalysis's frames of `path` (mda_frames.py; see its docstring for the layout).
std::optional<MdaFrames> mdaFrames(const fs::path& path, const fs::path& dir,
                                   const std::string& format = "") {
  const fs::path out = dir / (path.filename().string() + ".frames.bin");
  std::vector<std::string> args = {path.string(), out.string()};
  if (!format.empty()) args.push_back(format);
  if (!runOracle("mda_frames.py", args, dir)) return std::nullopt;
  const std::string bytes = readBytes(out);
  MdaFrames result;
  std::int64_t header[2];
  if (bytes.size() < sizeof header) {
    ADD_FAILURE() << "mda_frames.py wrote " << bytes.size() << " bytes for " << path;
    return std::nullopt;
  }
  std::memcpy(header, bytes.data(), sizeof header);
  result.atoms = static_cast<std::size_t>(header[0]);
  result.declaredFrames = static_cast<std::size_t>(header[1]);
  std::size_t at = sizeof header;
  const std::size_t frameBytes = 64 + 12 * result.atoms;
  while (at + frameBytes <= bytes.size()) {
    MdaFrame frame;
    std::int64_t hasCell = 0;
    std::memcpy(&frame.time, bytes.data() + at, 8);
    std::memcpy(&hasCell, bytes.data() + at + 8, 8);
    std::memcpy(frame.cell.data(), bytes.data() + at + 16, 48);
    frame.hasCell = hasCell != 0;
    frame.positions.resize(3 * result.atoms);
    std::memcpy(frame.positions.data(), bytes.data() + at + 64, 12 * result.atoms);
    result.frames.push_back(std::move(frame));
    at += frameBytes;
  }
  return result;
}

struct MdaAtom {
  int id = 0;
  std::string name, residue;
  int residueNumber = 0;
  std::string segid;
  double mass = 0.0;
  std::string massElement;
};

// MDAnalysis's atoms of a topology (mda_topology.py).
std::optional<std::vector<MdaAtom>> mdaTopology(const fs::path& path, const fs::path& dir) {
  const fs::path out = dir / (path.filename().string() + ".atoms.tsv");
  if (!runOracle("mda_topology.py", {path.string(), out.string()}, dir))
    return std::nullopt;
  std::vector<MdaAtom> atoms;
  const std::vector<std::string> rows = lines(readBytes(out));
  for (std::size_t r = 1; r < rows.size(); ++r) {
    std::vector<std::string> f;
    std::stringstream row(rows[r]);
    for (std::string field; std::getline(row, field, '\t');) f.push_back(field);
    if (f.size() == 6) f.emplace_back();  // no mass element
    if (f.size() != 7) {
      ADD_FAILURE() << "mda_topology.py row " << r << ": " << rows[r];
      return std::nullopt;
    }
    atoms.push_back({std::stoi(f[0]), f[1], f[2], std::stoi(f[3]), f[4], std::stod(f[5]), f[6]});
  }
  return atoms;
}

// MDAnalysis keeps float32 positions: the oracle's value and ours, rounded to float, agree
// within 2 float ulps (GRO: MDAnalysis scales nm to Å in float32, one more rounding). This is
// tighter than the files' printed precision (1e-3 nm, 1e-3 Å) except for XYZ written with 6
// or more decimals, where float32 itself holds fewer.
::testing::AssertionResult closeInFloat(double ours, float theirs) {
  const float a = static_cast<float>(ours);
  const float ulp = std::nextafter(std::abs(a), INFINITY) - std::abs(a);
  if (std::abs(a - theirs) <= 2.0F * ulp) return ::testing::AssertionSuccess();
  return ::testing::AssertionFailure() << "ours " << ours << " vs MDAnalysis " << theirs;
}

// Every frame of `source` equals MDAnalysis's, frame by frame (frames [0, count)).
void expectFramesEqual(FrameSource& source, const MdaFrames& mda, std::size_t count,
                       bool compareTime) {
  ASSERT_LE(count, mda.frames.size());
  ASSERT_EQ(source.atomCount(), mda.atoms);
  Frame frame;
  for (std::size_t k = 0; k < count; ++k) {
    SCOPED_TRACE(source.path() + " frame " + std::to_string(k + 1));
    source.read(k, frame);
    const MdaFrame& want = mda.frames[k];
    ASSERT_EQ(frame.positions.size(), mda.atoms);
    std::size_t bad = 0;
    for (std::size_t i = 0; i < mda.atoms; ++i)
      for (int axis = 0; axis < 3; ++axis) {
        const auto result = closeInFloat(frame.positions[i][axis],
                                         want.positions[3 * i + static_cast<std::size_t>(axis)]);
        if (!result && bad++ < 5)
          ADD_FAILURE() << "atom " << i + 1 << " axis " << axis << ": " << result.message();
      }
    EXPECT_EQ(bad, 0U);
    EXPECT_EQ(frame.cell.has_value(), want.hasCell);
    if (frame.cell && want.hasCell) {
      for (std::size_t c = 0; c < 6; ++c) {
        EXPECT_NEAR((*frame.cell)[c], want.cell[c], 1e-5 * std::max(1.0, std::abs(want.cell[c])))
            << "cell entry " << c;
      }
    }
    if (compareTime) {
      EXPECT_DOUBLE_EQ(frame.time, want.time);
    }
  }
}

// Reading the frames last to first gives what reading them first to last gave, exactly.
void expectReverseEqualsForward(const fs::path& path, TrajectoryFormat format) {
  auto forward = openTextTrajectory(path, format);
  auto backward = openTextTrajectory(path, format);
  std::vector<Frame> frames(forward->frameCount());
  for (std::size_t k = 0; k < frames.size(); ++k) forward->read(k, frames[k]);
  Frame frame;
  for (std::size_t k = frames.size(); k-- > 0;) {
    backward->read(k, frame);
    EXPECT_EQ(frame.positions, frames[k].positions) << path << " frame " << k + 1;
    EXPECT_EQ(frame.cell, frames[k].cell) << path << " frame " << k + 1;
    EXPECT_EQ(frame.time, frames[k].time) << path << " frame " << k + 1;
    EXPECT_EQ(frame.step, frames[k].step) << path << " frame " << k + 1;
  }
}

template <typename F>
InputError errorOf(F&& f) {
  try {
    f();
  } catch (const InputError& e) {
    return e;
  }
  ADD_FAILURE() << "no InputError was thrown";
  return InputError("", -1, "no error");
}

// ---------------------------------------------------------------------------------------------
// PSF

struct TopologyCase {
  const char* file;
  std::size_t atoms;  // from the !NATOM line or the GRO count line (and MANIFEST.md)
};

void PrintTo(const TopologyCase& c, std::ostream* os) { *os << c.file; }

class PsfTopology : public ::testing::TestWithParam<TopologyCase> {};

TEST_P(PsfTopology, RecordsMatchMDAnalysis) {
  const fs::path path = data(GetParam().file);
  const fs::path dir = tempDir();
  const Molecule molecule = detail::parsePsf(fileText(path), path.string());
  ASSERT_EQ(molecule.atoms.size(), GetParam().atoms);
  ASSERT_EQ(molecule.centers.size(), GetParam().atoms);
  EXPECT_EQ(molecule.modelCount, 1);
  const auto mda = mdaTopology(path, dir);
  ASSERT_TRUE(mda.has_value());
  ASSERT_EQ(mda->size(), molecule.atoms.size());
  std::size_t mismatches = 0;
  for (std::size_t i = 0; i < mda->size(); ++i) {
    const AtomRecord& a = molecule.atoms[i];
    const MdaAtom& m = (*mda)[i];
    const bool same = a.name == m.name && a.residue == m.residue &&
                      a.residueNumber == m.residueNumber && a.chain == m.segid &&
                      a.serial - 1 == m.id;  // MDAnalysis numbers PSF atoms from 0
    if (!same && mismatches++ < 5)
      ADD_FAILURE() << "atom " << i + 1 << " (line " << a.line << "): ours " << a.serial << " "
                    << a.name << " " << a.residue << " " << a.residueNumber << " " << a.chain
                    << "; MDAnalysis " << m.id << " " << m.name << " " << m.residue << " "
                    << m.residueNumber << " " << m.segid;
    // A PSF has no coordinates.
    EXPECT_TRUE(std::isnan(molecule.centers[i].x) && std::isnan(molecule.centers[i].y) &&
                std::isnan(molecule.centers[i].z));
  }
  EXPECT_EQ(mismatches, 0U);
}

// The element is the one whose mass (in MDAnalysis's own table) is nearest the atom's mass,
// for every atom; all these files are all-atom with standard masses.
TEST_P(PsfTopology, ElementsMatchTheMassOracle) {
  const fs::path path = data(GetParam().file);
  const Molecule molecule = detail::parsePsf(fileText(path), path.string());
  const auto mda = mdaTopology(path, tempDir());
  ASSERT_TRUE(mda.has_value());
  ASSERT_EQ(mda->size(), molecule.atoms.size());
  std::map<std::string, std::size_t> counts;
  std::size_t mismatches = 0;
  for (std::size_t i = 0; i < mda->size(); ++i) {
    ++counts[molecule.atoms[i].element];
    if (molecule.atoms[i].element != (*mda)[i].massElement && mismatches++ < 5)
      ADD_FAILURE() << "atom " << i + 1 << " " << molecule.atoms[i].name << " mass "
                    << (*mda)[i].mass << ": ours "
                    << "'" << molecule.atoms[i].element << "'"
                    << ", mass oracle " << (*mda)[i].massElement;
  }
  EXPECT_EQ(mismatches, 0U);
  EXPECT_EQ(counts.count(""), 0U) << "atoms without an element";
}

INSTANTIATE_TEST_SUITE_P(Files, PsfTopology,
                         ::testing::Values(TopologyCase{"trajectories/adk_dims/adk.psf.gz", 3341},
                                           TopologyCase{"trajectories/watdyn/watdyn.psf", 15},
                                           TopologyCase{"trajectories/2r9r/2r9r-1b.psf", 1284}));

// Counts of adk.psf's elements, as awk counts the mass column (field 8 of lines 8-3348:
// 1.00800 1685, 12.0110 1040, 14.0070 289, 15.9990 320, 32.0600 7), and its charges.
TEST(PsfTopologyAdk, ElementCountsAndCharges) {
  const fs::path path = data("trajectories/adk_dims/adk.psf.gz");
  const Molecule molecule = detail::parsePsf(fileText(path), path.string());
  std::map<std::string, std::size_t> counts;
  double charge = 0.0;
  for (const AtomRecord& a : molecule.atoms) {
    ++counts[a.element];
    charge += a.charge;
  }
  const std::map<std::string, std::size_t> want = {
      {"H", 1685}, {"C", 1040}, {"N", 289}, {"O", 320}, {"S", 7}};
  EXPECT_EQ(counts, want);
  EXPECT_EQ(molecule.atoms.front().line, 8);
  EXPECT_EQ(molecule.atoms.back().line, 8 + 3340);
  EXPECT_DOUBLE_EQ(molecule.atoms.front().charge, -0.3);
  EXPECT_DOUBLE_EQ(molecule.atoms[7].charge, 0.09);  // written "0.900000E-01"
  // The charges sum to -4.000000 (awk over field 7).
  EXPECT_NEAR(charge, -4.0, 1e-6);
}

TEST(PsfTopologyErrors, MissingMassField) {
  const fs::path dir = tempDir();
  std::vector<std::string> text = lines(fileText(data("trajectories/watdyn/watdyn.psf")));
  ASSERT_THAT(text[9], HasSubstr("H1   HT     0.417000"));
  text[9] = "       2 WAT  5    TIP3 H1   HT     0.417000";  // line 10: mass and imove gone
  const fs::path path = dir / "no_mass.psf";
  writeText(path, joinLines(text));
  const InputError e = errorOf([&] { detail::parsePsf(fileText(path), path.string()); });
  EXPECT_EQ(e.path(), path.string());
  EXPECT_EQ(e.line(), 10) << e.what();
  EXPECT_THAT(e.what(), HasSubstr("got 7"));
  EXPECT_THAT(e.what(), HasSubstr("TIP3 H1   HT     0.417000'"));
}

TEST(PsfTopologyErrors, AtomCountLargerThanTheAtomLines) {
  const fs::path dir = tempDir();
  std::vector<std::string> text = lines(fileText(data("trajectories/watdyn/watdyn.psf")));
  ASSERT_EQ(text[7], "      15 !NATOM");
  text[7] = "      17 !NATOM";
  const fs::path path = dir / "count.psf";
  writeText(path, joinLines(text));
  const InputError e = errorOf([&] { detail::parsePsf(fileText(path), path.string()); });
  EXPECT_EQ(e.line(), 8) << e.what();
  EXPECT_THAT(e.what(), HasSubstr(path.string() + ":8: "));
  EXPECT_THAT(e.what(), HasSubstr("count is 17, but only 15 atom lines follow"));

  // The same at the end of the file.
  const fs::path cut = dir / "cut.psf";
  writeText(cut, joinLines(std::vector<std::string>(text.begin(), text.begin() + 8 + 15)));
  const InputError end = errorOf([&] { detail::parsePsf(fileText(cut), cut.string()); });
  EXPECT_EQ(end.line(), 8);
  EXPECT_THAT(end.what(), HasSubstr("only 15 atom lines follow (then the file ends)"));
}

TEST(PsfTopologyErrors, NonNumbersAndNaN) {
  const fs::path dir = tempDir();
  const std::vector<std::string> text = lines(fileText(data("trajectories/watdyn/watdyn.psf")));
  const struct {
    const char* line;
    const char* what;
  } cases[] = {
      {"       2 WAT  5    TIP3 H1   HT     0.417000        nan           0",
       "the mass (field 8) is not finite: 'nan'"},
      {"       2 WAT  5    TIP3 H1   HT     0.4x7000        1.0080        0",
       "expected a number for the charge (field 7), got '0.4x7000'"},
      {"       2 WAT  X    TIP3 H1   HT     0.417000        1.0080        0",
       "expected a residue number (field 3), got 'X'"},
  };
  for (const auto& c : cases) {
    std::vector<std::string> bad = text;
    bad[9] = c.line;
    const fs::path path = dir / "bad.psf";
    writeText(path, joinLines(bad));
    const InputError e = errorOf([&] { detail::parsePsf(fileText(path), path.string()); });
    EXPECT_EQ(e.line(), 10) << e.what();
    EXPECT_THAT(e.what(), HasSubstr(c.what));
  }
  const fs::path header = dir / "header.psf";
  writeText(header, "PDB\n");
  EXPECT_EQ(errorOf([&] { detail::parsePsf(fileText(header), header.string()); }).line(), 1);
}

// CHARMM writes fixed columns; a blank segment id leaves the fields unsplittable, and the
// columns MDAnalysis reads take over.
TEST(PsfTopologyColumns, BlankSegmentIdReadsByColumns) {
  const fs::path dir = tempDir();
  std::vector<std::string> text = lines(fileText(data("trajectories/watdyn/watdyn.psf")));
  ASSERT_EQ(text[8].substr(0, 14), "       1 WAT  ");
  text[8].replace(9, 4, "    ");
  const fs::path path = dir / "blank_segid.psf";
  writeText(path, joinLines(text));
  const Molecule molecule = detail::parsePsf(fileText(path), path.string());
  ASSERT_EQ(molecule.atoms.size(), 15U);
  EXPECT_EQ(molecule.atoms[0].chain, "");
  EXPECT_EQ(molecule.atoms[0].residueNumber, 5);
  EXPECT_EQ(molecule.atoms[0].residue, "TIP3");
  EXPECT_EQ(molecule.atoms[0].name, "OH2");
  EXPECT_EQ(molecule.atoms[0].element, "O");
  EXPECT_DOUBLE_EQ(molecule.atoms[0].charge, -0.834);
  EXPECT_EQ(molecule.atoms[1].chain, "WAT");
}

// ---------------------------------------------------------------------------------------------
// GRO topology

class GroTopology : public ::testing::TestWithParam<TopologyCase> {};

TEST_P(GroTopology, RecordsAndCentresMatchMDAnalysis) {
  const fs::path path = data(GetParam().file);
  const fs::path dir = tempDir();
  const Molecule molecule = detail::parseGro(fileText(path), path.string());
  ASSERT_EQ(molecule.atoms.size(), GetParam().atoms);
  EXPECT_EQ(molecule.modelCount, 1);
  const auto mda = mdaTopology(path, dir);
  ASSERT_TRUE(mda.has_value());
  ASSERT_EQ(mda->size(), molecule.atoms.size());
  std::size_t mismatches = 0;
  for (std::size_t i = 0; i < mda->size(); ++i) {
    const AtomRecord& a = molecule.atoms[i];
    const MdaAtom& m = (*mda)[i];
    const bool same = a.name == m.name && a.residue == m.residue &&
                      a.residueNumber == m.residueNumber && a.serial == m.id && a.chain.empty() &&
                      a.line == static_cast<int>(i) + 3;
    if (!same && mismatches++ < 5)
      ADD_FAILURE() << "atom " << i + 1 << ": ours " << a.serial << " " << a.name << " "
                    << a.residue << " " << a.residueNumber << " line " << a.line << "; MDAnalysis "
                    << m.id << " " << m.name << " " << m.residue << " " << m.residueNumber;
  }
  EXPECT_EQ(mismatches, 0U);
  const auto frames = mdaFrames(path, dir);
  ASSERT_TRUE(frames.has_value());
  ASSERT_EQ(frames->frames.size(), 1U);
  for (std::size_t i = 0; i < molecule.size(); ++i)
    for (int axis = 0; axis < 3; ++axis)
      ASSERT_TRUE(closeInFloat(molecule.centers[i][axis],
                               frames->frames[0].positions[3 * i + static_cast<std::size_t>(axis)]))
          << "atom " << i + 1;
}

// MDAnalysis guesses a mass from the name; the element of that mass is ours, from the name.
TEST_P(GroTopology, ElementsMatchMDAnalysisGuesses) {
  const fs::path path = data(GetParam().file);
  const Molecule molecule = detail::parseGro(fileText(path), path.string());
  const auto mda = mdaTopology(path, tempDir());
  ASSERT_TRUE(mda.has_value());
  ASSERT_EQ(mda->size(), molecule.atoms.size());
  std::size_t mismatches = 0;
  for (std::size_t i = 0; i < mda->size(); ++i)
    if (molecule.atoms[i].element != (*mda)[i].massElement && mismatches++ < 5)
      ADD_FAILURE() << "atom " << i + 1 << " " << molecule.atoms[i].name << " of "
                    << molecule.atoms[i].residue << ": ours " << molecule.atoms[i].element
                    << ", MDAnalysis " << (*mda)[i].massElement;
  EXPECT_EQ(mismatches, 0U);
}

INSTANTIATE_TEST_SUITE_P(
    Files, GroTopology,
    ::testing::Values(TopologyCase{"formats/gro/ubiquitin.gro", 1405},
                      TopologyCase{"trajectories/sampletrajectory/sampletrajectory.gro", 115}));

TEST(GroTopologyErrors, GarbageCoordinate) {
  const fs::path dir = tempDir();
  std::vector<std::string> text =
      lines(fileText(data("trajectories/sampletrajectory/sampletrajectory.gro")));
  ASSERT_EQ(text[9].substr(28, 8), "   5.126");  // y of atom 8, line 10
  const struct {
    const char* field;
    const char* what;
  } cases[] = {{"  5.3x7 ", "expected a number for y in columns 29-36, got '  5.3x7 '"},
               {"     nan", "y in columns 29-36 is not finite: 'nan'"},
               {"        ", "expected a number for y in columns 29-36, got '        '"}};
  for (const auto& c : cases) {
    std::vector<std::string> bad = text;
    bad[9].replace(28, 8, c.field);
    const fs::path path = dir / "bad.gro";
    writeText(path, joinLines(bad));
    const InputError e = errorOf([&] { detail::parseGro(fileText(path), path.string()); });
    EXPECT_EQ(e.line(), 10) << e.what();
    EXPECT_THAT(e.what(), HasSubstr(path.string() + ":10: "));
    EXPECT_THAT(e.what(), HasSubstr(c.what));
    // The trajectory reader says the same when the frame is read.
    const InputError t = errorOf([&] {
      Frame frame;
      openTextTrajectory(path, TrajectoryFormat::Gro)->read(0, frame);
    });
    EXPECT_EQ(t.line(), 10) << t.what();
    EXPECT_THAT(t.what(), HasSubstr(c.what));
  }
}

TEST(GroTopologyErrors, AtomCountTheFileDoesNotHold) {
  const fs::path dir = tempDir();
  std::vector<std::string> text =
      lines(fileText(data("trajectories/sampletrajectory/sampletrajectory.gro")));
  ASSERT_EQ(text[1], "  115");
  text[1] = "  120";
  const fs::path path = dir / "count.gro";
  writeText(path, joinLines(text));
  const InputError e = errorOf([&] { detail::parseGro(fileText(path), path.string()); });
  EXPECT_EQ(e.line(), 2) << e.what();
  EXPECT_THAT(e.what(), HasSubstr("the atom count of frame 0 is 120"));
  EXPECT_EQ(errorOf([&] { openTextTrajectory(path, TrajectoryFormat::Gro); }).line(), 2);

  // A count smaller than the atoms puts an atom line where the box should be.
  text[1] = "  114";
  writeText(path, joinLines(text));
  const InputError box = errorOf([&] { detail::parseGro(fileText(path), path.string()); });
  EXPECT_EQ(box.line(), 117) << box.what();
  EXPECT_THAT(box.what(), HasSubstr("expected the box of frame 0"));
}

// ---------------------------------------------------------------------------------------------
// Frames against MDAnalysis

struct FramesCase {
  const char* file;
  TrajectoryFormat format;
  std::size_t frames;  // MANIFEST.md
  std::size_t atoms;
};

void PrintTo(const FramesCase& c, std::ostream* os) { *os << c.file; }

class TextFrames : public ::testing::TestWithParam<FramesCase> {};

TEST_P(TextFrames, EqualMDAnalysis) {
  const fs::path path = data(GetParam().file);
  auto source = openTextTrajectory(path, GetParam().format);
  ASSERT_EQ(source->frameCount(), GetParam().frames);
  ASSERT_EQ(source->atomCount(), GetParam().atoms);
  EXPECT_TRUE(source->notes().empty()) << source->notes().front();
  const auto mda = mdaFrames(path, tempDir());
  ASSERT_TRUE(mda.has_value());
  ASSERT_EQ(mda->frames.size(), GetParam().frames);
  ASSERT_EQ(mda->declaredFrames, GetParam().frames);
  // MDAnalysis's time is the frame index for these (no "t=" in the GRO titles).
  expectFramesEqual(*source, *mda, GetParam().frames, true);
}

TEST_P(TextFrames, ReverseOrderEqualsInOrder) {
  expectReverseEqualsForward(data(GetParam().file), GetParam().format);
}

INSTANTIATE_TEST_SUITE_P(
    Files, TextFrames,
    ::testing::Values(FramesCase{"trajectories/sampletrajectory/sampletrajectory.gro",
                                 TrajectoryFormat::Gro, 1, 115},
                      FramesCase{"formats/gro/ubiquitin.gro", TrajectoryFormat::Gro, 1, 1405},
                      FramesCase{"formats/xyz/trajectory.xyz", TrajectoryFormat::Xyz, 2, 9},
                      FramesCase{"formats/xyz/methane.xyz", TrajectoryFormat::Xyz, 1, 5},
                      FramesCase{"trajectories/2r9r/2r9r-1b.xyz", TrajectoryFormat::Xyz, 10, 1284},
                      FramesCase{"trajectories/sampletrajectory/sampletrajectory.pdb",
                                 TrajectoryFormat::Pdb, 1, 115},
                      FramesCase{"ensembles/1grm_elNemo_mode7.pdb.gz", TrajectoryFormat::Pdb, 11,
                                 264}));

// The models of an mmCIF file (MDAnalysis 2.4 has no mmCIF reader): each _atom_site row's
// Cartn_x/y/z, grouped by pdbx_PDB_model_num, from a whitespace tokenizer of the loop (the
// file has no quoted values with spaces in this loop).
std::vector<std::vector<std::array<double, 3>>> cifModels(const std::string& text) {
  std::vector<std::string> tags;
  std::vector<std::string> values;
  bool inLoop = false;
  bool inValues = false;
  for (const std::string& line : lines(text)) {
    if (line.rfind("_atom_site.", 0) == 0 && !inValues) {
      inLoop = true;
      std::istringstream in(line);
      std::string tag;
      in >> tag;
      tags.push_back(tag);
      continue;
    }
    if (!inLoop) continue;
    if (line.empty() || line[0] == '#' || line.rfind("loop_", 0) == 0 || line[0] == '_') break;
    inValues = true;
    std::istringstream in(line);
    for (std::string v; in >> v;) values.push_back(v);
  }
  const auto column = [&](const std::string& tag) {
    return static_cast<std::size_t>(std::find(tags.begin(), tags.end(), "_atom_site." + tag) -
                                    tags.begin());
  };
  const std::size_t x = column("Cartn_x"), model = column("pdbx_PDB_model_num");
  std::vector<std::string> names;
  std::vector<std::vector<std::array<double, 3>>> models;
  for (std::size_t row = 0; row + tags.size() <= values.size(); row += tags.size()) {
    const std::string& name = values[row + model];
    auto it = std::find(names.begin(), names.end(), name);
    if (it == names.end()) {
      names.push_back(name);
      models.emplace_back();
      it = names.end() - 1;
    }
    models[static_cast<std::size_t>(it - names.begin())].push_back(
        {std::stod(values[row + x]), std::stod(values[row + x + 1]),
         std::stod(values[row + x + 2])});
  }
  return models;
}

TEST(TextFramesMmcif, ModelsEqualTheAtomSiteTable1v5a) {
  const fs::path path = data("structures/1v5a-3models.cif.gz");
  const auto want = cifModels(fileText(path));
  ASSERT_EQ(want.size(), 3U);  // MANIFEST.md: 3 models x 387 atoms (1161 rows)
  auto source = openTextTrajectory(path, TrajectoryFormat::Mmcif);
  ASSERT_EQ(source->frameCount(), 3U);
  ASSERT_EQ(source->atomCount(), 387U);
  Frame frame;
  for (std::size_t k = 0; k < 3; ++k) {
    source->read(k, frame);
    ASSERT_EQ(want[k].size(), 387U);
    for (std::size_t i = 0; i < 387; ++i)
      for (int axis = 0; axis < 3; ++axis)
        ASSERT_EQ(frame.positions[i][axis], want[k][i][static_cast<std::size_t>(axis)])
            << "model " << k + 1 << " atom " << i + 1;
    EXPECT_EQ(frame.time, static_cast<double>(k));
    EXPECT_FALSE(frame.cell.has_value());  // the file has no _cell
  }
  expectReverseEqualsForward(path, TrajectoryFormat::Mmcif);
  // Auto tells the format from the name, .gz and all.
  EXPECT_EQ(openTextTrajectory(path, TrajectoryFormat::Auto)->frameCount(), 3U);
}

// ---------------------------------------------------------------------------------------------
// GRO frames one after another, written here with known values

std::string groFrames(std::size_t frames, std::size_t atoms, bool triclinic) {
  std::string text;
  char buffer[128];
  for (std::size_t k = 0; k < frames; ++k) {
    std::snprintf(buffer, sizeof buffer, "Test system t= %.3f step= %zu\n%5zu\n",
                  12.0 * static_cast<double>(k + 1), 6000 * (k + 1), atoms);
    text += buffer;
    for (std::size_t i = 0; i < atoms; ++i) {
      std::snprintf(buffer, sizeof buffer, "%5zu%-5s%5s%5zu%8.3f%8.3f%8.3f%8.4f%8.4f%8.4f\n",
                    i / 3 + 1, "SOL", i % 3 == 0 ? "OW" : (i % 3 == 1 ? "HW1" : "HW2"), i + 1,
                    0.1 * static_cast<double>(i) + static_cast<double>(k),
                    -1.5 + 0.001 * static_cast<double>(k), 2.0, 0.1, 0.2, 0.3);
      text += buffer;
    }
    text += triclinic ? "   5.00000   5.00000   5.00000   0.00000   0.00000   2.50000   0.00000   "
                        "2.50000   2.50000\n"
                      : "   3.00000   4.00000   5.00000\n";
  }
  return text;
}

TEST(TextFramesGro, FramesOneAfterAnotherWithTimesAndBoxes) {
  const fs::path dir = tempDir();
  const fs::path path = dir / "three.gro";
  writeText(path, groFrames(3, 6, false));
  auto source = openTextTrajectory(path, TrajectoryFormat::Gro);
  ASSERT_EQ(source->frameCount(), 3U);
  ASSERT_EQ(source->atomCount(), 6U);
  EXPECT_TRUE(source->notes().empty());
  Frame frame;
  for (std::size_t k = 0; k < 3; ++k) {
    source->read(k, frame);
    EXPECT_DOUBLE_EQ(frame.time, 12.0 * static_cast<double>(k + 1));
    EXPECT_EQ(frame.step, static_cast<long long>(6000 * (k + 1)));
    ASSERT_TRUE(frame.cell.has_value());
    EXPECT_EQ(*frame.cell, (std::array<double, 6>{30.0, 40.0, 50.0, 90.0, 90.0, 90.0}));
    for (std::size_t i = 0; i < 6; ++i) {
      EXPECT_NEAR(frame.positions[i].x,
                  (0.1 * static_cast<double>(i) + static_cast<double>(k)) * 10.0, 1e-9);
      EXPECT_NEAR(frame.positions[i].y, (-1.5 + 0.001 * static_cast<double>(k)) * 10.0, 1e-9);
      EXPECT_DOUBLE_EQ(frame.positions[i].z, 20.0);
    }
  }
  expectReverseEqualsForward(path, TrajectoryFormat::Gro);
  const Molecule molecule = detail::parseGro(fileText(path), path.string());
  EXPECT_EQ(molecule.modelCount, 3);
  EXPECT_EQ(molecule.atoms[5].name, "HW2");
  EXPECT_EQ(molecule.atoms[5].element, "H");
  EXPECT_EQ(molecule.atoms[3].element, "O");
  EXPECT_EQ(molecule.atoms[3].residueNumber, 2);

  // gzipped, the same frames.
  const fs::path gz = dir / "three.gro.gz";
  gzFile out = gzopen(gz.string().c_str(), "wb");
  const std::string text = groFrames(3, 6, false);
  gzwrite(out, text.data(), static_cast<unsigned>(text.size()));
  gzclose(out);
  auto zipped = openTextTrajectory(gz, TrajectoryFormat::Auto);
  ASSERT_EQ(zipped->frameCount(), 3U);
  Frame z;
  zipped->read(2, z);
  source->read(2, frame);
  EXPECT_EQ(z.positions, frame.positions);
}

// A triclinic box: the cell MDAnalysis computes from the same nine numbers.
TEST(TextFramesGro, TriclinicBoxMatchesMDAnalysis) {
  const fs::path dir = tempDir();
  const fs::path path = dir / "triclinic.gro";
  writeText(path, groFrames(1, 6, true));
  auto source = openTextTrajectory(path, TrajectoryFormat::Gro);
  const auto mda = mdaFrames(path, dir);
  ASSERT_TRUE(mda.has_value());
  ASSERT_TRUE(mda->frames.at(0).hasCell);
  expectFramesEqual(*source, *mda, 1, false);
  Frame frame;
  source->read(0, frame);
  // a = (5, 0, 0), b = (2.5, 5, 0), c = (2.5, 2.5, 5) nm: gamma = acos(2.5 / |b|).
  EXPECT_NEAR((*frame.cell)[5], std::acos(2.5 / std::sqrt(31.25)) * 180.0 / std::numbers::pi,
              1e-12);
}

TEST(TextFramesGro, TruncatedLastFrameIsLeftOutWithANote) {
  const fs::path dir = tempDir();
  const fs::path path = dir / "cut.gro";
  std::string text = groFrames(3, 6, false);
  text.resize(text.size() - 50);  // inside the last box line and atom
  writeText(path, text);
  auto source = openTextTrajectory(path, TrajectoryFormat::Gro);
  EXPECT_EQ(source->frameCount(), 2U);
  ASSERT_EQ(source->notes().size(), 1U);
  EXPECT_THAT(source->notes()[0], HasSubstr("frame 2"));  // the third: frames from 0
  Frame frame;
  source->read(1, frame);
  EXPECT_DOUBLE_EQ(frame.time, 24.0);
}

// ---------------------------------------------------------------------------------------------
// Broken trajectories

TEST(TextFramesErrors, XyzFrameCutShortInTheMiddle) {
  const fs::path dir = tempDir();
  const std::vector<std::string> original = lines(fileText(data("formats/xyz/trajectory.xyz")));
  ASSERT_EQ(original.size(), 22U);  // 2 frames of 9 atoms
  // Frames 0, 1 (two atom lines short) and 2 (= frame 0).
  std::vector<std::string> text(original.begin(), original.begin() + 11);
  text.insert(text.end(), original.begin() + 11, original.begin() + 20);
  text.insert(text.end(), original.begin(), original.begin() + 11);
  const fs::path path = dir / "cut.xyz";
  writeText(path, joinLines(text));
  auto source = openTextTrajectory(path, TrajectoryFormat::Xyz);
  ASSERT_EQ(source->frameCount(), 2U);
  ASSERT_EQ(source->notes().size(), 1U);
  EXPECT_THAT(source->notes()[0], HasSubstr("only frames 0-1 are read"));
  // Frame 0 reads as in the intact file.
  Frame frame, intact;
  source->read(0, frame);
  openTextTrajectory(data("formats/xyz/trajectory.xyz"), TrajectoryFormat::Xyz)->read(0, intact);
  EXPECT_EQ(frame.positions, intact.positions);
  // Frame 1 takes frame 2's count line for its 8th atom.
  const InputError e = errorOf([&] { source->read(1, frame); });
  EXPECT_EQ(e.line(), 21) << e.what();  // frame 1: count 12, comment 13, 7 atoms 14-20
  EXPECT_THAT(e.what(), HasSubstr("atom 8 of 9 of frame 1, got '9'"));
  source->read(0, frame);  // still readable after the failure
  EXPECT_EQ(frame.positions, intact.positions);
}

TEST(TextFramesErrors, XyzLastFrameCutShortAndGarbage) {
  const fs::path dir = tempDir();
  std::vector<std::string> text = lines(fileText(data("formats/xyz/trajectory.xyz")));
  const fs::path path = dir / "end.xyz";
  writeText(path, joinLines(std::vector<std::string>(text.begin(), text.end() - 3)));
  auto source = openTextTrajectory(path, TrajectoryFormat::Xyz);
  EXPECT_EQ(source->frameCount(), 1U);
  ASSERT_EQ(source->notes().size(), 1U);
  EXPECT_THAT(source->notes()[0], HasSubstr(path.string() + ":12: the atom count of frame 1 is 9"));

  text[15] = "He 8.480960 0.8674x9 4.217944";
  writeText(path, joinLines(text));
  Frame frame;
  const InputError e =
      errorOf([&] { openTextTrajectory(path, TrajectoryFormat::Xyz)->read(1, frame); });
  EXPECT_EQ(e.line(), 16);
  EXPECT_THAT(e.what(), HasSubstr("expected a number for y (field 3) in frame 1, got '0.8674x9'"));
}

TEST(TextFramesErrors, PdbModelsOfDifferentAtomCounts) {
  const fs::path dir = tempDir();
  const std::string atom1 =
      "ATOM      1  N   ALA A   1      11.104   6.134  -6.504  1.00  0.00           N";
  const std::string atom2 =
      "ATOM      2  CA  ALA A   1      11.639   6.071  -5.147  1.00  0.00           C";
  const std::string atom3 =
      "ATOM      3  C   ALA A   1      13.149   6.074  -5.139  1.00  0.00           C";
  const fs::path path = dir / "models.pdb";
  writeText(path,
            joinLines({"CRYST1   50.000   60.000   70.000  90.00 100.00  90.00 P 1           1",
                       "MODEL        1", atom1, atom2, atom3, "ENDMDL", "MODEL        2", atom1,
                       atom2, "ENDMDL", "MODEL        3", atom1, atom2, atom3, "ENDMDL", "END"}));
  auto source = openTextTrajectory(path, TrajectoryFormat::Pdb);
  ASSERT_EQ(source->frameCount(), 3U);
  EXPECT_EQ(source->atomCount(), 3U);
  ASSERT_EQ(source->notes().size(), 1U);
  EXPECT_THAT(source->notes()[0], HasSubstr("frame 1 has 2 atoms, frame 0 has 3"));
  Frame frame;
  source->read(0, frame);
  EXPECT_EQ(frame.positions[2], glm::dvec3(13.149, 6.074, -5.139));
  EXPECT_EQ(frame.cell, (std::array<double, 6>{50.0, 60.0, 70.0, 90.0, 100.0, 90.0}));
  const InputError e = errorOf([&] { source->read(1, frame); });
  EXPECT_EQ(e.line(), 7) << e.what();
  EXPECT_THAT(e.what(), HasSubstr("frame 1 has 2 atoms, but frame 0 has 3"));
  source->read(2, frame);  // frames after it read
  EXPECT_EQ(frame.positions[0], glm::dvec3(11.104, 6.134, -6.504));

  // A garbage coordinate names the line, the columns and the value.
  writeText(path, joinLines({"MODEL        1", atom1, atom2.substr(0, 40) + "x" + atom2.substr(41),
                             "ENDMDL"}));
  const InputError g =
      errorOf([&] { openTextTrajectory(path, TrajectoryFormat::Pdb)->read(0, frame); });
  EXPECT_EQ(g.line(), 3);
  EXPECT_THAT(g.what(),
              HasSubstr("expected a number for y (columns 39-46) in frame 0, got '  x6.071'"));
}

TEST(TextFramesErrors, EmptyBinaryAndBadGzip) {
  const fs::path dir = tempDir();
  writeText(dir / "empty.xyz", "");
  EXPECT_THAT(errorOf([&] { openTextTrajectory(dir / "empty.xyz", TrajectoryFormat::Xyz); }).what(),
              HasSubstr("empty"));
  writeText(dir / "binary.gro", std::string("title\n\0\0\0", 9));
  EXPECT_THAT(
      errorOf([&] { openTextTrajectory(dir / "binary.gro", TrajectoryFormat::Gro); }).what(),
      HasSubstr("binary data"));
  writeText(dir / "plain.xyz.gz", "1\n\nC 0 0 0\n");
  EXPECT_THAT(
      errorOf([&] { openTextTrajectory(dir / "plain.xyz.gz", TrajectoryFormat::Xyz); }).what(),
      HasSubstr("not gzip-compressed"));
  EXPECT_THAT(
      errorOf([&] { openTextTrajectory(dir / "missing.xyz", TrajectoryFormat::Xyz); }).what(),
      HasSubstr("cannot open"));
}

// ---------------------------------------------------------------------------------------------
// Every GRO and XYZ file of the shared data set

TEST(TextFramesSharedData, EveryGroAndXyzEqualsMDAnalysis) {
  const fs::path root = fs::path(SURFTRACE_SOURCE_DIR) / ".." / "shared" / "data";
  if (!fs::is_directory(root)) GTEST_SKIP() << root << " does not exist";
  std::vector<fs::path> files;
  for (const auto& entry : fs::recursive_directory_iterator(root)) {
    std::string name = entry.path().filename().string();
    if (name.size() > 3 && name.compare(name.size() - 3, 3, ".gz") == 0)
      name.resize(name.size() - 3);
    const std::string ext = fs::path(name).extension().string();
    if (entry.is_regular_file() && (ext == ".gro" || ext == ".xyz")) files.push_back(entry.path());
  }
  std::sort(files.begin(), files.end());
  ASSERT_GE(files.size(), 13U);  // as of writing: 5 GRO, 8 XYZ
  const fs::path dir = tempDir();
  for (const fs::path& path : files) {
    SCOPED_TRACE(path.string());
    const bool gro = path.string().find(".gro") != std::string::npos;
    auto source = openTextTrajectory(path, TrajectoryFormat::Auto);
    const auto mda = mdaFrames(path, dir);
    ASSERT_TRUE(mda.has_value());
    // Frames that differ from frame 0 in atom count (ligs3d.xyz: 10 ligands) cannot be read;
    // MDAnalysis reads them as garbage, so only the frames before the first one compare.
    std::size_t readable = source->frameCount();
    Frame frame;
    for (std::size_t k = 0; k < source->frameCount(); ++k) {
      try {
        source->read(k, frame);
      } catch (const InputError& e) {
        EXPECT_THAT(e.what(),
                    HasSubstr("atoms, but frame 0 has " + std::to_string(source->atomCount())));
        EXPECT_FALSE(source->notes().empty());
        readable = k;
        break;
      }
    }
    if (readable == source->frameCount()) {
      // MDAnalysis reads one frame of a GRO file.
      EXPECT_EQ(gro ? 1 : source->frameCount(), mda->frames.size());
      EXPECT_EQ(gro ? 1 : source->frameCount(), mda->declaredFrames);
    }
    expectFramesEqual(*source, *mda, std::min(readable, mda->frames.size()), !gro);
    if (gro) {
      const Molecule molecule = detail::parseGro(fileText(path), path.string());
      EXPECT_EQ(molecule.size(), source->atomCount());
    }
  }
}

}  // namespace
}  // namespace surftrace::build

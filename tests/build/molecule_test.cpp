// Tests of the molecule input layer against facts established outside it: atom counts from
// tests/data/MANIFEST.md or from grep/awk over the files (noted where used), element columns
// of other copies of the same entry, and files the tests write themselves.
#include "build/io/molecule.hpp"

#include <gmock/gmock.h>
#include <gtest/gtest.h>
#include <zlib.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdint>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <map>
#include <set>
#include <sstream>
#include <string>
#include <tuple>
#include <vector>

#include "build/io/error.hpp"
#include "build/io/radii.hpp"
#include "build/io/text_fields.hpp"
#include "oracles/python_oracle.hpp"
#include "temp_dir.hpp"

namespace surftrace::build {
namespace {

namespace fs = std::filesystem;
using ::testing::HasSubstr;

fs::path data(const std::string& relative) { return fs::path(SURFTRACE_TEST_DATA) / relative; }

std::string readText(const fs::path& path) {
  std::ifstream in(path, std::ios::binary);
  std::stringstream buffer;
  buffer << in.rdbuf();
  return buffer.str();
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

// A fresh directory for one test's files.
fs::path tempDir() { return ::surftrace::test::freshTempDir("files"); }

// The InputError that reading `path` throws; a test failure if it throws none.
InputError readError(const fs::path& path, const ReadOptions& options = {}) {
  try {
    readMolecule(path, options);
  } catch (const InputError& e) {
    return e;
  }
  ADD_FAILURE() << "reading " << path << " threw no InputError";
  return InputError(path.string(), -1, "no error");
}

// The error names the file, the line, and the value seen.
void expectError(const fs::path& path, int line, const std::string& value,
                 const ReadOptions& options = {}) {
  const InputError e = readError(path, options);
  EXPECT_EQ(e.path(), path.string());
  EXPECT_EQ(e.line(), line) << e.what();
  EXPECT_THAT(e.what(), HasSubstr(value));
  if (line > 0) {
    EXPECT_THAT(e.what(), HasSubstr(path.string() + ":" + std::to_string(line) + ": "));
  }
}

// Bitwise CRC-32 (IEEE 802.3, reflected, as zlib and gzip use), written here from the
// definition so that Molecule::inputCrc32 is checked against something other than zlib.
std::uint32_t referenceCrc32(std::string_view bytes) {
  std::uint32_t crc = 0xFFFFFFFFu;
  for (const char c : bytes) {
    crc ^= static_cast<unsigned char>(c);
    for (int k = 0; k < 8; ++k) crc = (crc >> 1) ^ (0xEDB88320u & (0u - (crc & 1u)));
  }
  return ~crc;
}

void appendLe32(std::string& out, std::uint32_t v) {
  for (int i = 0; i < 4; ++i) out.push_back(static_cast<char>((v >> (8 * i)) & 0xFFu));
}

// A gzip member (RFC 1952) holding `payload` in stored (uncompressed) deflate blocks
// (RFC 1951, section 3.2.4), built by hand so the reader's gzip path is tested without zlib.
std::string storedGzip(std::string_view payload) {
  std::string out = {static_cast<char>(0x1f), static_cast<char>(0x8b), 8, 0, 0, 0, 0, 0, 0,
                     static_cast<char>(0xff)};
  std::size_t pos = 0;
  do {
    const std::size_t n = std::min<std::size_t>(65535, payload.size() - pos);
    const bool last = pos + n == payload.size();
    out.push_back(static_cast<char>(last ? 1 : 0));
    out.push_back(static_cast<char>(n & 0xFF));
    out.push_back(static_cast<char>(n >> 8));
    out.push_back(static_cast<char>(~n & 0xFF));
    out.push_back(static_cast<char>((~n >> 8) & 0xFF));
    out.append(payload.substr(pos, n));
    pos += n;
  } while (pos < payload.size());
  appendLe32(out, referenceCrc32(payload));
  appendLe32(out, static_cast<std::uint32_t>(payload.size()));
  return out;
}

std::size_t countHetatm(const Molecule& m) {
  std::size_t n = 0;
  for (const AtomRecord& a : m.atoms) n += a.hetatm ? 1 : 0;
  return n;
}

std::map<std::string, std::size_t> elementCounts(const Molecule& m) {
  std::map<std::string, std::size_t> counts;
  for (const AtomRecord& a : m.atoms) ++counts[a.element];
  return counts;
}

// ---------------------------------------------------------------------------------------------
// PDB

TEST(MoleculePdb, WaterIsLeftOutByDefault1vis) {
  // MANIFEST: 1VIS 2531 atoms / 2488 without water (43 HOH).
  const Molecule m = readMolecule(data("paper/1vis.pdb.gz"));
  EXPECT_EQ(m.size(), 2488u);
  EXPECT_EQ(m.skipped.water, 43u);
  EXPECT_EQ(m.format, MoleculeFormat::Pdb);
  EXPECT_EQ(m.modelCount, 1);
  EXPECT_EQ(m.radiiSet, "bondi");
  EXPECT_EQ(m.radii.size(), m.size());
  EXPECT_EQ(m.atoms.size(), m.size());
  for (const AtomRecord& a : m.atoms) EXPECT_NE(a.residue, "HOH");
}

TEST(MoleculePdb, KeepWaterKeepsEveryAtom1vis) {
  ReadOptions options;
  options.keepWater = true;
  const Molecule m = readMolecule(data("paper/1vis.pdb.gz"), options);
  EXPECT_EQ(m.size(), 2531u);
  EXPECT_EQ(m.skipped.water, 0u);
}

TEST(MoleculePdb, HetatmRecordsAreAtoms1grm) {
  // MANIFEST: 5 models x 272 atoms, per model 154 ATOM + 118 HETATM.
  const Molecule m = readMolecule(data("paper/1grm.pdb.gz"));
  EXPECT_EQ(m.size(), 272u);
  EXPECT_EQ(countHetatm(m), 118u);
  EXPECT_EQ(m.modelCount, 5);
  EXPECT_EQ(m.modelUsed, 1);
  EXPECT_EQ(m.skipped.otherModels, 4u * 272u);
}

// A PDB file without the records after which gemmi may change an atom's model or refuse the
// file (MODEL, ENDMDL, ANISOU, SSBOND, LINK, CISPEP) is read straight from its ATOM/HETATM lines
// with gemmi's field readers; with one of them, from gemmi's whole Structure. The same lines
// read both ways (an ENDMDL or an ANISOU at the end sends them through the Structure) give the
// same atoms, the fields the columns hold (gemmi's reading: residue name in columns 18-20, a
// two-column chain 21-22, hybrid-36 residue numbers, a blank one 0), and the same errors.
TEST(MoleculePdb, AtomLinesReadAlikeWithAndWithoutGemmisStructure) {
  const std::string atoms =
      "HEADER    TEST\n"
      "CRYST1   50.000   50.000   50.000  90.00  90.00  90.00 P 1           1\n"
      "ATOM      1  N   ALA A   1       1.000  -2.500   3.250  1.00  0.00           N\n"
      "ATOM      2  CA AALA A   1      +2.125     1e1  -0.000  0.60  0.00           C\n"
      "ATOM      3  CA BALA A   1       2.250    10.5   0.001  0.40  0.00           C\n"
      "HETATM    4 FE   HEMXY-998A    -12.345     0.1      7.  1.00  0.00      HEMEFE\n"
      "hetatm    5 1HB  ZN                  5       6       7  1.00  0.00\n"
      "ATOM  A0000 CD1  LEUXCA000Z        0.5    0.25   0.125  1.00  0.00      S1\r\n"
      "ATOM      7  OW  HOH W9999         4.0     4.5     5.0  1.00  0.00           O\n"
      "TER\n"
      "CONECT    1    2\n";
  const std::string anisou =
      "ANISOU    7  OW  HOH W9999     1000   1000   1000      0      0      0       O\n";
  ReadOptions options;
  options.keepWater = true;
  const Molecule lines = readMoleculeBytes(atoms + "END\n", "lines.pdb", options);
  ASSERT_EQ(lines.size(), 6u);  // the B conformer of atom 3 left out
  const AtomRecord& fe = lines.atoms[2];
  EXPECT_EQ(fe.name, "FE");
  EXPECT_EQ(fe.residue, "HEM");
  EXPECT_EQ(fe.chain, "XY");
  EXPECT_EQ(fe.residueNumber, -998);  // (gemmi reads -999 as no number: 0)
  EXPECT_EQ(fe.insertionCode, 'A');
  EXPECT_EQ(fe.segid, "HEME");
  EXPECT_TRUE(fe.hetatm);
  EXPECT_EQ(lines.centers[2], glm::dvec3(-12.345, 0.1, 7.0));
  EXPECT_EQ(lines.atoms[3].name, "1HB");
  EXPECT_EQ(lines.atoms[3].residue, "ZN");
  EXPECT_EQ(lines.atoms[3].chain, "");
  EXPECT_EQ(lines.atoms[3].residueNumber, 0);
  EXPECT_TRUE(lines.atoms[3].hetatm);
  EXPECT_EQ(lines.atoms[4].residue, "LEU");
  EXPECT_EQ(lines.atoms[4].chain, "XC");
  EXPECT_EQ(lines.atoms[4].residueNumber, 10000);  // hybrid-36 "A000"
  EXPECT_EQ(lines.atoms[4].insertionCode, 'Z');
  EXPECT_EQ(lines.atoms[4].serial, 100000);        // hybrid-36 "A0000"
  EXPECT_EQ(lines.atoms[1].altLoc, 'A');
  EXPECT_EQ(lines.centers[1], glm::dvec3(2.125, 10.0, 0.0));
  EXPECT_EQ(lines.atoms[5].residueNumber, 9999);
  EXPECT_EQ(lines.bondRecords.size(), 1u);
  for (const std::string& extra : {std::string("ENDMDL\n"), anisou}) {
    const Molecule structure = readMoleculeBytes(atoms + extra + "END\n", "structure.pdb", options);
    ASSERT_EQ(structure.size(), lines.size()) << extra;
    EXPECT_EQ(structure.modelCount, lines.modelCount);
    EXPECT_EQ(structure.bondRecords, lines.bondRecords);
    EXPECT_EQ(structure.notes, lines.notes);
    for (std::size_t i = 0; i < lines.size(); ++i) {
      const AtomRecord& a = lines.atoms[i];
      const AtomRecord& b = structure.atoms[i];
      EXPECT_EQ(std::tie(a.name, a.residue, a.chain, a.segid, a.element, a.residueNumber, a.serial, a.line,
                         a.insertionCode, a.altLoc, a.hetatm, a.fileIndex, a.elementSource),
                std::tie(b.name, b.residue, b.chain, b.segid, b.element, b.residueNumber, b.serial, b.line,
                         b.insertionCode, b.altLoc, b.hetatm, b.fileIndex, b.elementSource))
          << "atom " << i << " with " << extra;
      EXPECT_EQ(a.occupancy, b.occupancy);
      EXPECT_EQ(a.bFactor, b.bFactor);
      EXPECT_EQ(lines.centers[i], structure.centers[i]) << "atom " << i;
      EXPECT_EQ(std::signbit(lines.centers[i].z), std::signbit(structure.centers[i].z)) << "atom " << i;
      EXPECT_EQ(lines.radii[i], structure.radii[i]) << "atom " << i;
    }
  }
  // The second model asked of a one-model file, and a malformed coordinate, alike both ways.
  const auto error = [&](const std::string& text, int model) {
    ReadOptions asked = options;
    asked.model = model;
    try {
      readMoleculeBytes(text, "edge.pdb", asked);
    } catch (const InputError& e) {
      return std::to_string(e.line()) + ": " + e.what();
    }
    return std::string("read");
  };
  EXPECT_THAT(error(atoms, 2), HasSubstr("model 2 was asked for, but the file has 1 model"));
  EXPECT_EQ(error(atoms + "ENDMDL\n", 2), error(atoms, 2));
  std::string bad = atoms;
  bad.replace(bad.find("10.5"), 4, "1.5a");
  EXPECT_THAT(error(bad, 1), HasSubstr("expected a number for y in columns 39-46, got '    1.5a'"));
  EXPECT_EQ(error(bad, 1).rfind("5: ", 0), 0u) << error(bad, 1);
  EXPECT_EQ(error(bad + "ENDMDL\n", 1), error(bad, 1));
}

TEST(MoleculePdb, Reads1aonWellUnderASecond) {
  // 58870 ATOM/HETATM records: zcat 1aon.pdb.gz | grep -cE '^(ATOM|HETATM)'; chains A-U.
  const auto start = std::chrono::steady_clock::now();
  const Molecule m = readMolecule(data("paper/1aon.pdb.gz"));
  const double seconds =
      std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  EXPECT_EQ(m.size(), 58870u);
  std::set<std::string> chains;
  for (const AtomRecord& a : m.atoms) chains.insert(a.chain);
  EXPECT_EQ(chains.size(), 21u);
  EXPECT_EQ(*chains.begin(), "A");
  EXPECT_EQ(*chains.rbegin(), "U");
  ::testing::Test::RecordProperty("read_1aon_seconds", std::to_string(seconds));
#ifdef NDEBUG
  EXPECT_LT(seconds, 1.0);
#endif
}

TEST(MoleculePdb, ChainSelection) {
  ReadOptions options;
  options.chains = {"B"};
  // 136 atoms per chain in model 1: awk over the ATOM/HETATM records of the first MODEL.
  const Molecule m = readMolecule(data("paper/1grm.pdb.gz"), options);
  EXPECT_EQ(m.size(), 136u);
  EXPECT_EQ(m.skipped.otherChains, 136u);
  for (const AtomRecord& a : m.atoms) EXPECT_EQ(a.chain, "B");

  // zcat 1aon.pdb.gz | grep -E '^(ATOM|HETATM)' | awk 'substr($0,22,1)=="A"||...=="B"' | wc -l
  options.chains = {"A", "B"};
  EXPECT_EQ(readMolecule(data("paper/1aon.pdb.gz"), options).size(), 7672u);
}

TEST(MoleculePdb, UnknownChainIsAnErrorListingTheChains) {
  ReadOptions options;
  options.chains = {"Z"};
  const InputError e = readError(data("paper/1grm.pdb.gz"), options);
  EXPECT_THAT(e.what(), HasSubstr("'Z'"));
  EXPECT_THAT(e.what(), HasSubstr("'A', 'B'"));
}

TEST(MoleculePdb, ModelSelection1d3z) {
  // MANIFEST: 10 MODELs x 1231 atoms.
  ReadOptions options;
  options.model = 10;
  const Molecule last = readMolecule(data("ensembles/1d3z.pdb.gz"), options);
  const Molecule first = readMolecule(data("ensembles/1d3z.pdb.gz"));
  EXPECT_EQ(last.size(), 1231u);
  EXPECT_EQ(last.modelCount, 10);
  EXPECT_EQ(last.modelUsed, 10);
  EXPECT_EQ(last.skipped.otherModels, 9u * 1231u);
  ASSERT_EQ(first.size(), last.size());
  EXPECT_EQ(first.atoms[0].name, last.atoms[0].name);
  EXPECT_NE(first.centers[0], last.centers[0]);  // NMR models differ
  EXPECT_GT(last.atoms[0].line, first.atoms.back().line);
}

TEST(MoleculePdb, ModelBeyondTheFileSaysHowManyThereAre) {
  ReadOptions options;
  options.model = 6;
  const InputError e = readError(data("paper/1grm.pdb.gz"), options);
  EXPECT_THAT(e.what(), HasSubstr("model 6"));
  EXPECT_THAT(e.what(), HasSubstr("5 models"));
  options.model = 11;
  EXPECT_THAT(readError(data("ensembles/1d3z.pdb.gz"), options).what(), HasSubstr("10 models"));
  options.model = 0;
  EXPECT_THAT(readError(data("paper/1grm.pdb.gz"), options).what(), HasSubstr("model 0"));
}

TEST(MoleculePdb, AltLocsKeepTheHighestOccupancyConformer1cbn) {
  // 777 records: 501 without altloc, 139 A, 104 B, 33 C. Residues 22 and 25 are SER/ILE in
  // A and B (occupancy 0.2 each) and PRO/LEU in C (0.6). Keeping, per residue, the conformer
  // of highest mean occupancy (awk over the records) leaves 644 atoms, 314 of them H.
  const Molecule m = readMolecule(data("structures/1cbn.pdb.gz"));
  EXPECT_EQ(m.size(), 644u);
  EXPECT_EQ(m.skipped.altLocs, 777u - 644u);
  EXPECT_EQ(elementCounts(m)["H"], 314u);
  std::set<std::tuple<std::string, int, char, std::string>> unique;
  for (const AtomRecord& a : m.atoms) {
    EXPECT_TRUE(unique.insert({a.chain, a.residueNumber, a.insertionCode, a.name}).second)
        << "two conformers of " << a.name << " " << a.residueNumber;
    if (a.residueNumber == 22) {
      EXPECT_EQ(a.residue, "PRO");
    }
    if (a.residueNumber == 25) {
      EXPECT_EQ(a.residue, "LEU");
    }
    if (a.residueNumber == 1 && a.altLoc != ' ') {
      EXPECT_EQ(a.altLoc, 'A');  // THR 1: A 0.8, B 0.2
    }
  }
}

// One conformer per atom, and no atom left out for having no alternative: 3AL1's LYS A105 HA
// has only an `A` record (occupancy 1.00) where the residue's B conformer wins (0.56 > 0.44 on
// the side chain). The atoms kept are exactly one per (chain, residue, insertion code, name) of
// what MDAnalysis reads (every record; tests/oracles/mda_atoms.py), as gemmi's
// remove_alternative_conformations keeps them (679 records, 491 atoms).
TEST(MoleculePdb, AltLocsNeverDropAnAtomWithoutAlternative3al1) {
  ReadOptions options;
  options.keepWater = true;
  const Molecule m = readMolecule(data("structures/3al1.pdb.gz"), options);
  const fs::path scratch = test::freshTempDir("altlocs");
  const test::OracleRun run = test::runOracleScript("mda_atoms.py", {data("structures/3al1.pdb.gz").string()}, scratch);
  ASSERT_TRUE(run.ok()) << run.describe();
  using Key = std::tuple<std::string, int, std::string, std::string>;
  std::set<Key> mda;
  std::size_t records = 0;
  std::istringstream lines(run.out);
  for (std::string line; std::getline(lines, line); ++records) {
    std::istringstream f(line);
    std::string index, serial, name, resname, chain, segid, resid, icode, altloc;
    f >> index >> serial >> name >> resname >> chain >> segid >> resid >> icode >> altloc;
    mda.insert({chain == "-" ? "" : chain, std::stoi(resid), icode == "-" ? "" : icode, name});
  }
  EXPECT_EQ(records, 679u);
  std::set<Key> ours;
  for (const AtomRecord& a : m.atoms)
    EXPECT_TRUE(ours.insert({a.chain, a.residueNumber, a.insertionCode == ' ' ? "" : std::string(1, a.insertionCode),
                             a.name})
                    .second)
        << "two conformers of " << a.name << " " << a.chain << a.residueNumber;
  EXPECT_EQ(ours, mda);
  EXPECT_EQ(m.size(), 491u);
  EXPECT_EQ(m.skipped.altLocs, 679u - 491u);
  const auto ha = std::find_if(m.atoms.begin(), m.atoms.end(), [](const AtomRecord& a) {
    return a.chain == "A" && a.residueNumber == 105 && a.name == "HA";
  });
  ASSERT_NE(ha, m.atoms.end()) << "LYS A105 HA was dropped";
  EXPECT_EQ(ha->altLoc, 'A');
  for (const AtomRecord& a : m.atoms) {
    if (a.chain == "A" && a.residueNumber == 105 && a.name == "CB") {
      EXPECT_EQ(a.altLoc, 'B');  // B wins the residue
    }
  }
}

// Chains and segment ids apart in mmCIF: the chain is auth_asym_id, the segment label_asym_id
// (the entity instance: a ligand of chain A has its own, as PyMOL's segi shows); without
// label_asym_id the chain is the segment.
TEST(MoleculeMmcif, SegmentIsTheLabelAsymId) {
  const fs::path dir = test::freshTempDir("segids");
  const std::string head =
      "data_test\nloop_\n_atom_site.group_PDB\n_atom_site.id\n_atom_site.type_symbol\n_atom_site.label_atom_id\n"
      "_atom_site.label_comp_id\n_atom_site.label_seq_id\n_atom_site.Cartn_x\n_atom_site.Cartn_y\n"
      "_atom_site.Cartn_z\n_atom_site.auth_asym_id\n";
  writeText(dir / "two.cif", head + "_atom_site.label_asym_id\n"
                                    "ATOM 1 C CA ALA 1 0.0 0.0 0.0 A A\n"
                                    "ATOM 2 C CB ALA 1 1.5 0.0 0.0 A A\n"
                                    "HETATM 3 Zn ZN ZN . 5.0 0.0 0.0 A C\n");
  const Molecule m = readMolecule(dir / "two.cif");
  ASSERT_EQ(m.size(), 3u);
  for (const AtomRecord& a : m.atoms) EXPECT_EQ(a.chain, "A");
  EXPECT_EQ(m.atoms[0].segid, "A");
  EXPECT_EQ(m.atoms[2].segid, "C");
  writeText(dir / "auth.cif", head + "ATOM 1 C CA ALA 1 0.0 0.0 0.0 B\n");
  EXPECT_EQ(readMolecule(dir / "auth.cif").atoms[0].segid, "B");
}

// Names longer than an AtomString holds in place (7 bytes) are read, compared, selected and
// printed whole: mmCIF allows any length (CCD ids of 5 characters exist; a 9-character atom
// name and 8-character chain and segment ids here), as do PSF and GRO's 5 columns. The oracle
// is the file's own text.
TEST(MoleculeMmcif, LongNamesAreKeptWhole) {
  const fs::path dir = test::freshTempDir("long_names");
  writeText(dir / "long.cif",
            "data_test\nloop_\n_atom_site.group_PDB\n_atom_site.id\n_atom_site.type_symbol\n"
            "_atom_site.label_atom_id\n_atom_site.label_comp_id\n_atom_site.label_seq_id\n_atom_site.Cartn_x\n"
            "_atom_site.Cartn_y\n_atom_site.Cartn_z\n_atom_site.auth_asym_id\n_atom_site.label_asym_id\n"
            "HETATM 1 C C1LONGATM LIGANDXY 1 0.0 0.0 0.0 CHAINABC SEGMENTX\n"
            "HETATM 2 C C2LONGATM LIGANDXY 1 1.5 0.0 0.0 CHAINABC SEGMENTX\n"
            "HETATM 3 C CSEVEN7 A1B2C 1 3.0 0.0 0.0 A SEG7777\n");
  ReadOptions options;
  options.selection = "resname LIGANDXY and name C2LONGATM or name CSEVEN7";
  for (const bool selected : {false, true}) {
    const Molecule m = readMolecule(dir / "long.cif", selected ? options : ReadOptions{});
    ASSERT_EQ(m.size(), selected ? 2u : 3u);
    const std::size_t first = selected ? 0 : 1;  // the C2LONGATM atom
    EXPECT_EQ(m.atoms[first].name, "C2LONGATM");
    EXPECT_EQ(std::string(m.atoms[first].name.c_str()), "C2LONGATM");
    EXPECT_EQ(m.atoms[first].residue, "LIGANDXY");
    EXPECT_EQ(m.atoms[first].chain, "CHAINABC");
    EXPECT_EQ(m.atoms[first].segid, "SEGMENTX");
    EXPECT_EQ(m.atoms[first + 1].name.size(), 7u);  // exactly the in-place capacity
    EXPECT_EQ(std::string(m.atoms[first + 1].name.c_str()), "CSEVEN7");
    EXPECT_EQ(m.atoms[first + 1].residue, "A1B2C");
    EXPECT_EQ(m.atoms[first + 1].segid, "SEG7777");
    if (!selected) {
      EXPECT_NE(m.atoms[0].name, m.atoms[1].name);  // long names stay apart
    }
  }
}

// The record of one atom is 88 bytes (five 8-byte AtomStrings and the numbers, no padding):
// a million atoms' records were 232 MB with five std::strings, the most of `area`'s memory
// after the surface itself.
TEST(Molecule, AtomRecordIsSmall) {
  EXPECT_LE(sizeof(AtomRecord), 88u);
  AtomString text("ALA");
  EXPECT_EQ(text, "ALA");
  EXPECT_EQ(text + ":CA", "ALA:CA");
  EXPECT_LT(text, "ARG");
  EXPECT_TRUE(AtomString().empty());
  EXPECT_EQ(AtomString("LONGER THAN SEVEN").str(), "LONGER THAN SEVEN");
  EXPECT_EQ(AtomString("LONGER THAN SEVEN"), AtomString(std::string("LONGER THAN ") + "SEVEN"));
}

TEST(MoleculePdb, HydrogensCanBeLeftOut) {
  ReadOptions options;
  options.keepHydrogens = false;
  // MANIFEST: 1D3Z has 629 H per model (element column 77-78 == " H": 629).
  const Molecule m = readMolecule(data("ensembles/1d3z.pdb.gz"), options);
  EXPECT_EQ(m.size(), 1231u - 629u);
  EXPECT_EQ(m.skipped.hydrogens, 629u);
  for (const AtomRecord& a : m.atoms) EXPECT_FALSE(isHydrogen(a.element));
  EXPECT_EQ(readMolecule(data("structures/1cbn.pdb.gz"), options).skipped.hydrogens, 314u);
}

TEST(MoleculePdb, AllWaterIsAnErrorThatSaysWhy) {
  // MANIFEST: water.pdb is 648 atoms, all water.
  const InputError e = readError(data("small/water.pdb"));
  EXPECT_THAT(e.what(), HasSubstr("all 648 atoms are water; use --keep-water"));
  ReadOptions options;
  options.keepWater = true;
  EXPECT_EQ(readMolecule(data("small/water.pdb"), options).size(), 648u);
}

TEST(MoleculePdb, ShortLinesEndingAfterZReadFine) {
  // incomplete.pdb: 2 MODELs of 3 CA atoms, lines end after z, a malformed 'MODEL 1'.
  const Molecule m = readMolecule(data("small/incomplete.pdb"));
  ASSERT_EQ(m.size(), 3u);
  EXPECT_EQ(m.modelCount, 2);
  EXPECT_EQ(m.centers[0], glm::dvec3(111.252, 98.373, 98.187));
  EXPECT_EQ(m.centers[2], glm::dvec3(107.607, 102.968, 96.316));
  for (const AtomRecord& a : m.atoms) {
    EXPECT_EQ(a.element, "C");  // "CA" in column 13 of LYS is C-alpha, not calcium
    EXPECT_EQ(a.occupancy, 1.0);
  }
  EXPECT_EQ(m.atoms[0].line, 3);
}

TEST(MoleculePdb, TwoModelsWithTerRecords) {
  // awk: 31 ATOM/HETATM records in each of the 2 MODELs.
  ReadOptions options;
  options.model = 2;
  const Molecule m = readMolecule(data("small/ter-records/multi-model.pdb"), options);
  EXPECT_EQ(m.size(), 31u);
  EXPECT_EQ(m.modelCount, 2);
  EXPECT_EQ(m.skipped.otherModels, 31u);
}

TEST(MoleculePdb, LineNumbersSerialsAndFileOrder) {
  const fs::path path = data("structures/1crn.pdb");
  const std::vector<std::string> text = lines(readText(path));
  const Molecule m = readMolecule(path);
  ASSERT_EQ(m.size(), 327u);  // MANIFEST
  for (std::size_t i = 0; i < m.size(); ++i) {
    const AtomRecord& a = m.atoms[i];
    ASSERT_GE(a.line, 1);
    const std::string& line = text[static_cast<std::size_t>(a.line - 1)];
    EXPECT_EQ(line.substr(0, 4), "ATOM");
    EXPECT_EQ(std::stoi(line.substr(6, 5)), a.serial);
    EXPECT_EQ(a.serial, static_cast<int>(i) + 1);
    EXPECT_DOUBLE_EQ(m.centers[i].x, std::stod(line.substr(30, 8)));
    EXPECT_DOUBLE_EQ(m.centers[i].z, std::stod(line.substr(46, 8)));
    EXPECT_DOUBLE_EQ(a.bFactor, std::stod(line.substr(60, 6)));
  }
  EXPECT_EQ(m.atoms.front().line, 273);  // grep -n -m1 '^ATOM' 1crn.pdb
}

TEST(MoleculePdb, OldEntriesWithSerialsInColumns73To80) {
  // 1HPV keeps '1HPV 186' in columns 73-80; gemmi alone throws on it ("Wrong format for
  // charge"). MANIFEST: 1631 / 1551 atoms. Names: 1003 C, 263 N, 356 O (80 of them water), 9 S.
  ReadOptions options;
  options.keepWater = true;
  const Molecule m = readMolecule(data("structures/1hpv.pdb.gz"), options);
  EXPECT_EQ(m.size(), 1631u);
  const auto counts = elementCounts(m);
  EXPECT_EQ(counts.size(), 4u);
  EXPECT_EQ(counts.at("C"), 1003u);
  EXPECT_EQ(counts.at("N"), 263u);
  EXPECT_EQ(counts.at("O"), 356u);
  EXPECT_EQ(counts.at("S"), 9u);
  EXPECT_EQ(m.atoms[0].line, 185);
}

// ---------------------------------------------------------------------------------------------
// Elements

TEST(MoleculeElements, InferredFromNamesMatchTheElementColumns1grm) {
  // 1grm_single.pdb is model 1 of 1GRM with blank element columns, rewritten by MDAnalysis
  // with its own residue split (FOR 0 + VAL 1 for FVA 1) and order; 1grm.pdb.gz has the
  // element columns. Atoms are matched by position.
  const Molecule inferred = readMolecule(data("small/1grm_single.pdb"));
  const Molecule given = readMolecule(data("paper/1grm.pdb.gz"));
  ASSERT_EQ(inferred.size(), given.size());
  auto key = [](const glm::dvec3& c) {
    return std::tuple{std::lround(c.x * 1000), std::lround(c.y * 1000), std::lround(c.z * 1000)};
  };
  std::map<std::tuple<long, long, long>, std::string> elements;
  for (std::size_t i = 0; i < given.size(); ++i)
    elements[key(given.centers[i])] = given.atoms[i].element;
  ASSERT_EQ(elements.size(), given.size());
  for (std::size_t i = 0; i < inferred.size(); ++i) {
    const auto it = elements.find(key(inferred.centers[i]));
    ASSERT_TRUE(it != elements.end()) << inferred.atoms[i].name;
    EXPECT_EQ(inferred.atoms[i].element, it->second)
        << inferred.atoms[i].name << " of " << inferred.atoms[i].residue;
  }
}

TEST(MoleculeElements, AmberNamesStartingInColumn13) {
  // helix_amber.pdb writes every name from column 13 ("CA  ", "HH31") without element
  // columns; all residues are standard, so each element is the name's first letter.
  const fs::path path = data("small/helix_amber.pdb");
  const Molecule m = readMolecule(path);
  ASSERT_EQ(m.size(), 392u);  // MANIFEST
  for (const AtomRecord& a : m.atoms) {
    ASSERT_FALSE(a.name.empty());
    EXPECT_EQ(a.element, std::string(1, a.name[0])) << a.name << " " << a.residue;
  }
  EXPECT_EQ(elementCounts(m).at("H"), 189u);
  EXPECT_EQ(elementCounts(m).count("Ca"), 0u);
}

TEST(MoleculeElements, NamesWithoutElementColumns) {
  // odd02.pdb: ARG/VAL/... with mixed-case names Hg13 and Hh22, which are hydrogens.
  const Molecule odd = readMolecule(data("small/odd02.pdb"));
  const auto counts = elementCounts(odd);
  EXPECT_EQ(counts, (std::map<std::string, std::size_t>{{"C", 10}, {"H", 19}, {"N", 5}, {"O", 2}}));
  ReadOptions options;
  options.keepWater = true;
  const auto water = elementCounts(readMolecule(data("small/water.pdb"), options));
  EXPECT_EQ(water, (std::map<std::string, std::size_t>{{"H", 432}, {"O", 216}}));
}

TEST(MoleculeElements, ElementColumnsInMixedCase) {
  // elements.pdb has CU, FE, Mg and Ca in columns 77-78.
  ReadOptions options;
  options.defaultRadius = 2.0;
  const Molecule m = readMolecule(data("small/elements.pdb"), options);
  EXPECT_EQ(m.size(), 28u);
  const auto counts = elementCounts(m);
  for (const char* element : {"Cu", "Fe", "Mg", "Ca"})
    EXPECT_EQ(counts.count(element), 1u) << element;
  EXPECT_EQ(m.skipped.defaultRadius, 0u);  // Fe takes Alvarez's radius
  std::map<std::string, double> radius;
  for (std::size_t i = 0; i < m.size(); ++i) radius[m.atoms[i].element] = m.radii[i];
  EXPECT_EQ(radius.at("Fe"), 2.44);  // Alvarez 2013, Table 1
  EXPECT_EQ(radius.at("Cu"), 1.40);  // Bondi 1964
}

TEST(MoleculeElements, TheColumnTellsCarbonFromCalcium) {
  // odd01.pdb: HETATM 500 " CA " (column 14: carbon) and 501 "CA  " (column 13: calcium) in
  // residue UKN without element columns; three AP5 lines carry "1AKE1839" in columns 73-80.
  ReadOptions options;
  options.defaultRadius = 1.5;  // "AC5  AP5" reads as actinium by the column rule
  const Molecule m = readMolecule(data("small/odd01.pdb"), options);
  EXPECT_EQ(m.size(), 18u);
  std::map<int, std::string> bySerial;
  for (const AtomRecord& a : m.atoms) bySerial[a.serial] = a.element;
  EXPECT_EQ(bySerial.at(500), "C");
  EXPECT_EQ(bySerial.at(501), "Ca");
  EXPECT_EQ(bySerial.at(1685), "P");  // " PE " of AP5
  EXPECT_EQ(bySerial.at(1315), "O");  // "ABCD" with element column O
}

// ---------------------------------------------------------------------------------------------
// mmCIF

TEST(MoleculeMmcif, SameAtomsAsThePdbFile1grm) {
  for (const int model : {1, 5}) {
    ReadOptions options;
    options.model = model;
    const Molecule pdb = readMolecule(data("paper/1grm.pdb.gz"), options);
    const Molecule cif = readMolecule(data("paper/1grm.cif.gz"), options);
    EXPECT_EQ(cif.format, MoleculeFormat::Mmcif);
    EXPECT_EQ(cif.modelCount, 5);
    ASSERT_EQ(cif.size(), pdb.size());
    for (std::size_t i = 0; i < pdb.size(); ++i) {
      EXPECT_EQ(cif.centers[i], pdb.centers[i]) << i;
      EXPECT_EQ(cif.atoms[i].name, pdb.atoms[i].name);
      EXPECT_EQ(cif.atoms[i].residue, pdb.atoms[i].residue);
      EXPECT_EQ(cif.atoms[i].chain, pdb.atoms[i].chain);
      EXPECT_EQ(cif.atoms[i].residueNumber, pdb.atoms[i].residueNumber);
      EXPECT_EQ(cif.atoms[i].element, pdb.atoms[i].element);
      EXPECT_EQ(cif.atoms[i].hetatm, pdb.atoms[i].hetatm);
      EXPECT_EQ(cif.radii[i], pdb.radii[i]);
    }
  }
}

TEST(MoleculeMmcif, RowLinesAndModels) {
  // zcat 1grm.cif.gz | sed -n 519p is the first atom_site row (HETATM 1 C C . FVA).
  const Molecule m = readMolecule(data("paper/1grm.cif.gz"));
  EXPECT_EQ(m.atoms[0].line, 519);
  EXPECT_EQ(m.atoms[1].line, 520);
  EXPECT_EQ(m.atoms[0].serial, 1);
  // MANIFEST: 1V5A, 3 models x 387 atoms.
  ReadOptions options;
  options.model = 3;
  const Molecule v5a = readMolecule(data("structures/1v5a-3models.cif.gz"), options);
  EXPECT_EQ(v5a.size(), 387u);
  EXPECT_EQ(v5a.modelCount, 3);
  EXPECT_EQ(v5a.skipped.otherModels, 2u * 387u);
  options.model = 4;
  EXPECT_THAT(readError(data("structures/1v5a-3models.cif.gz"), options).what(),
              HasSubstr("3 models"));
}

// ---------------------------------------------------------------------------------------------
// gzip, CRC, formats

TEST(MoleculeGzip, DetectedByMagicBytesAndCrcOfTheDecompressedBytes) {
  const fs::path dir = tempDir();
  const std::string plain = readText(data("structures/1crn.pdb"));
  ASSERT_EQ(referenceCrc32("123456789"), 0xCBF43926u);  // the CRC-32 check value
  writeText(dir / "crambin.pdb.gz", storedGzip(plain));
  writeText(dir / "crambin_gzip_without_gz.pdb", storedGzip(plain));
  // Two gzip members, as `cat a.gz b.gz` makes.
  writeText(dir / "two_members.pdb.gz",
            storedGzip(plain.substr(0, 20000)) + storedGzip(plain.substr(20000)));

  const Molecule reference = readMolecule(data("structures/1crn.pdb"));
  EXPECT_EQ(reference.inputCrc32, referenceCrc32(plain));
  for (const char* name : {"crambin.pdb.gz", "crambin_gzip_without_gz.pdb", "two_members.pdb.gz"}) {
    const Molecule m = readMolecule(dir / name);
    EXPECT_EQ(m.inputCrc32, referenceCrc32(plain)) << name;
    EXPECT_EQ(m.centers, reference.centers) << name;
    EXPECT_EQ(m.atoms.back().line, reference.atoms.back().line) << name;
  }
}

// A gzip file's bytes inflated with zlib (the reader's own gunzip is what the tests check).
std::string zlibGunzip(const std::string& bytes) {
  z_stream zs{};
  EXPECT_EQ(inflateInit2(&zs, 16 + MAX_WBITS), Z_OK);
  zs.next_in = reinterpret_cast<Bytef*>(const_cast<char*>(bytes.data()));
  zs.avail_in = static_cast<uInt>(bytes.size());
  std::string out;
  char buffer[1 << 16];
  int ret = Z_OK;
  while (ret == Z_OK) {
    zs.next_out = reinterpret_cast<Bytef*>(buffer);
    zs.avail_out = sizeof buffer;
    ret = inflate(&zs, Z_NO_FLUSH);
    out.append(buffer, sizeof buffer - zs.avail_out);
  }
  EXPECT_EQ(ret, Z_STREAM_END);
  inflateEnd(&zs);
  return out;
}

// One gzip member of `text`, deflated by zlib at its best ratio.
std::string zlibGzip(const std::string& text) {
  z_stream zs{};
  EXPECT_EQ(deflateInit2(&zs, 9, Z_DEFLATED, 16 + MAX_WBITS, 9, Z_DEFAULT_STRATEGY), Z_OK);
  std::string out(deflateBound(&zs, static_cast<uLong>(text.size())), '\0');
  zs.next_in = reinterpret_cast<Bytef*>(const_cast<char*>(text.data()));
  zs.avail_in = static_cast<uInt>(text.size());
  zs.next_out = reinterpret_cast<Bytef*>(out.data());
  zs.avail_out = static_cast<uInt>(out.size());
  EXPECT_EQ(deflate(&zs, Z_FINISH), Z_STREAM_END);
  out.resize(zs.total_out);
  deflateEnd(&zs);
  return out;
}

// Every "\n" of `text` replaced by `ending`.
std::string withLineEnding(const std::string& text, const std::string& ending) {
  std::string out;
  for (const char c : text) c == '\n' ? out.append(ending) : out.append(1, c);
  return out;
}

// Files written with Windows (CRLF) or classic Mac OS (CR alone) line ends read exactly as
// their LF originals: the same atoms, centres, radii, names and line numbers, plain and
// gzipped, in every text format. (A CR-only PDB read as 1 atom of 327, with no note.)
TEST(MoleculeLineEnds, CrLfAndCrOnlyFilesReadAsTheirLfOriginals) {
  const Molecule crambin = readMolecule(data("structures/1crn.pdb"));
  std::ostringstream xyzr, xyz;
  xyzr.precision(17);
  xyz.precision(17);
  xyz << crambin.size() << "\ncrambin\n";
  for (std::size_t i = 0; i < crambin.size(); ++i) {
    const glm::dvec3& c = crambin.centers[i];
    xyzr << c.x << ' ' << c.y << ' ' << c.z << ' ' << crambin.radii[i] << '\n';
    xyz << crambin.atoms[i].element << ' ' << c.x << ' ' << c.y << ' ' << c.z << '\n';
  }
  const std::vector<std::pair<std::string, std::string>> files = {
      {"1crn.pdb", readText(data("structures/1crn.pdb"))},
      {"1grm.cif", zlibGunzip(readText(data("paper/1grm.cif.gz")))},
      {"ubiquitin.gro", readText(data("formats/gro/ubiquitin.gro"))},
      {"1000.pqr", readText(data("small/pqr/1000.pqr"))},
      {"crambin.xyzr", xyzr.str()},
      {"crambin.xyz", xyz.str()}};
  for (const auto& [name, lf] : files) {
    ASSERT_EQ(lf.find('\r'), std::string::npos) << name << " is not an LF file";
    const Molecule want = readMoleculeBytes(lf, name);
    ASSERT_GT(want.size(), 30u) << name;
    for (const std::string ending : {"\r\n", "\r"}) {
      const std::string converted = withLineEnding(lf, ending);
      for (const bool gzipped : {false, true}) {
        const std::string what = name + (ending == "\r" ? " with CR line ends" : " with CRLF line ends") +
                                 (gzipped ? ", gzipped" : "");
        const Molecule got = gzipped ? readMoleculeBytes(storedGzip(converted), name + ".gz")
                                     : readMoleculeBytes(converted, name);
        ASSERT_EQ(got.size(), want.size()) << what;
        EXPECT_EQ(got.centers, want.centers) << what;
        EXPECT_EQ(got.radii, want.radii) << what;
        for (std::size_t i = 0; i < got.size(); ++i) {
          EXPECT_EQ(got.atoms[i].line, want.atoms[i].line) << what << ", atom " << i;
          EXPECT_EQ(got.atoms[i].name, want.atoms[i].name) << what << ", atom " << i;
          EXPECT_EQ(got.atoms[i].element, want.atoms[i].element) << what << ", atom " << i;
        }
        EXPECT_EQ(got.notes, want.notes) << what;
      }
    }
  }
  // A radius table too.
  const fs::path dir = tempDir();
  writeText(dir / "radii.txt", "C 1.8\r\nN 1.6\rO 1.5\r");
  const RadiusTable table = RadiusTable::load(dir / "radii.txt");
  EXPECT_EQ(table.size(), 3u);
  EXPECT_EQ(table.find("ALA", "O", "O"), 1.5);
}

// A line longer than kMaxLineBytes is refused, naming the file, the line and the limit, as
// the bytes arrive: a 1 MB gzip that inflates to one 1 GiB line (1,024 members of 1 MiB of
// 'A', as `cat` joins them) is refused after inflating about 1 MiB. A line of exactly the
// limit is read.
TEST(MoleculeLineEnds, ALineLongerThanTheLimitIsRefusedWithItsNumber) {
  const auto expectRefused = [](const std::string& bytes, const std::string& name, int line) {
    try {
      readMoleculeBytes(bytes, name);
      ADD_FAILURE() << name << " was read";
    } catch (const InputError& e) {
      EXPECT_EQ(e.path(), name);
      EXPECT_EQ(e.line(), line) << e.what();
      EXPECT_THAT(e.what(), HasSubstr(name + ":" + std::to_string(line) + ": the line runs past 1048576 bytes"));
      EXPECT_LT(std::string(e.what()).size(), 400u);
    }
  };
  ASSERT_EQ(text::kMaxLineBytes, std::size_t{1} << 20);
  const std::string mib(text::kMaxLineBytes, 'A');
  const std::string member = zlibGzip(mib);
  std::string bomb;
  for (int k = 0; k < 1024; ++k) bomb += member;
  ASSERT_LT(bomb.size(), std::size_t{2} << 20);
  expectRefused(bomb, "bomb.pdb.gz", 1);
  expectRefused(bomb, "bomb.cif.gz", 1);
  expectRefused("0 0 0 1.5\n" + mib + "7\n", "long.xyzr", 2);
  expectRefused(zlibGzip("0 0 0 1.5\r\n1 1 1 1.5\r\n" + mib + "7\n"), "long.xyzr.gz", 3);
  expectRefused("0 0 0 1.5\r1 1 1 1.5\r" + mib + "7\n", "long.xyzr", 3);
  // At the limit: a comment line of 1 MiB, with every kind of line end around it.
  for (const std::string ending : {"\n", "\r\n", "\r"}) {
    const std::string text = "#" + mib.substr(1) + ending + "0 0 0 1.5" + ending + "#" + mib.substr(1);
    const Molecule m = readMoleculeBytes(text, "limit.xyzr");
    ASSERT_EQ(m.size(), 1u);
    EXPECT_EQ(m.atoms[0].line, 2);
    EXPECT_EQ(readMoleculeBytes(zlibGzip(text), "limit.xyzr.gz").size(), 1u);
  }
  // Behind many short lines, at every offset around the 1 MiB steps in which the text is
  // looked at: a line of the limit is read, one byte more refused with its number.
  for (const std::size_t shift : {0, 1, 2, 3, 9, 10, 11, 5000}) {
    std::string before;
    int lines = 0;
    while (before.size() + 10 < text::kMaxLineBytes - shift) before += "0 0 0 1.5\n", ++lines;
    before.append(text::kMaxLineBytes - shift - before.size(), '#');  // a comment line up to the step
    before += "\n";
    ++lines;
    for (const bool gzipped : {false, true}) {
      const std::string atLimit = before + "#" + mib.substr(1) + "\n1 1 1 1.5\n";
      EXPECT_EQ(readMoleculeBytes(gzipped ? zlibGzip(atLimit) : atLimit, gzipped ? "at.xyzr.gz" : "at.xyzr").size(), 2u)
          << shift;
      const std::string over = before + "#" + mib + "\n";
      expectRefused(gzipped ? zlibGzip(over) : over, gzipped ? "over.xyzr.gz" : "over.xyzr", lines + 1);
    }
    const fs::path file = tempDir() / "over.xyzr";
    writeText(file, before + "1 1 1 1.5\n#" + mib + "\n");
    try {
      readMolecule(file);
      ADD_FAILURE() << "over.xyzr was read, shift " << shift;
    } catch (const InputError& e) {
      EXPECT_EQ(e.line(), lines + 2) << e.what();
    }
  }
  // From a file, and in a radius table.
  const fs::path dir = tempDir();
  writeText(dir / "long.gro", "title\n1\n" + mib + mib + "\n");
  try {
    readMolecule(dir / "long.gro");
    ADD_FAILURE() << "long.gro was read";
  } catch (const InputError& e) {
    EXPECT_EQ(e.line(), 3) << e.what();
    EXPECT_THAT(e.what(), HasSubstr("1048576 bytes"));
  }
  writeText(dir / "radii.txt", "C 1.8\n#" + mib + "\n");
  try {
    RadiusTable::load(dir / "radii.txt");
    ADD_FAILURE() << "the radius table was read";
  } catch (const InputError& e) {
    EXPECT_EQ(e.line(), 2) << e.what();
    EXPECT_THAT(e.what(), HasSubstr("radii.txt:2: the line runs past 1048576 bytes"));
  }
}

// A control byte anywhere (the check looks at 64-byte blocks first) is refused with its line
// and offset; tabs, form feeds and a DOS end-of-file byte are text.
TEST(MoleculeLineEnds, AControlByteIsRefusedWithItsLineAndOffset) {
  std::string xyzr;
  for (int i = 0; i < 100; ++i) xyzr += std::to_string(i) + "\t0 0\f 1.5\n";
  xyzr += "# \x1a";
  EXPECT_EQ(readMoleculeBytes(xyzr, "text.xyzr").size(), 100u);
  for (const std::size_t offset : {std::size_t{0}, std::size_t{5}, std::size_t{63}, std::size_t{64}, std::size_t{65},
                                   std::size_t{127}, std::size_t{128}, std::size_t{1000}, xyzr.size() - 1}) {
    std::string bad = xyzr;
    bad[offset] = '\x01';
    const int line = 1 + static_cast<int>(std::count(xyzr.begin(), xyzr.begin() + static_cast<long>(offset), '\n'));
    try {
      readMoleculeBytes(bad, "bad.xyzr");
      ADD_FAILURE() << "read with a control byte at " << offset;
    } catch (const InputError& e) {
      EXPECT_EQ(e.line(), line) << e.what();
      EXPECT_THAT(e.what(), HasSubstr("byte 0x01 at offset " + std::to_string(offset) + ")")) << offset;
    }
  }
}

TEST(MoleculeFormat, ExtensionDecidesUnlessTheFormatIsGiven) {
  const fs::path dir = tempDir();
  fs::copy_file(data("structures/1crn.pdb"), dir / "crambin.txt");
  const InputError e = readError(dir / "crambin.txt");
  EXPECT_THAT(e.what(), HasSubstr("'.txt'"));
  ReadOptions options;
  options.format = MoleculeFormat::Pdb;
  EXPECT_EQ(readMolecule(dir / "crambin.txt", options).size(), 327u);
  EXPECT_STREQ(formatName(MoleculeFormat::Mmcif), "mmCIF");
}

// ---------------------------------------------------------------------------------------------
// Bad input: each names the file, the line and the value

TEST(MoleculeBadInput, NanCoordinate) { expectError(data("bad/nan_coordinate.pdb"), 4, "'nan'"); }

TEST(MoleculeBadInput, CoordinateThatIsNotANumber) {
  // gemmi itself would read "  12.7a4" as 12.7 and "abc" as 0.
  expectError(data("bad/garbage_coordinate.pdb"), 3, "'  12.7a4'");
  expectError(data("bad/partial_number.pdb"), 5, "'   1.2.3'");
}

TEST(MoleculeBadInput, TruncatedLastLine) {
  expectError(data("bad/truncated.pdb"), 4, "ends at column 42");
}

TEST(MoleculeBadInput, TruncatedGzip) {
  expectError(data("bad/truncated.pdb.gz"), 183, "truncated");
}

TEST(MoleculeBadInput, GzNameButNotGzip) {
  expectError(data("bad/not_gzip.pdb.gz"), 0, "not gzip-compressed");
}

TEST(MoleculeBadInput, MissingFile) { expectError(data("bad/no_such_file.pdb"), 0, "cannot open"); }

TEST(MoleculeBadInput, EmptyFile) { expectError(data("bad/empty.pdb"), 0, "empty"); }

TEST(MoleculeBadInput, BinaryFile) {
  expectError(data("bad/binary.pdb"), 1, "byte 0x00 at offset 1");
}

TEST(MoleculeBadInput, NoAtoms) { expectError(data("bad/no_atoms.pdb"), 0, "no ATOM or HETATM"); }

TEST(MoleculeBadInput, GemmiErrorsKeepTheirLine) {
  expectError(data("bad/model_without_endmdl.pdb"), 4, "MODEL without ENDMDL");
}

TEST(MoleculeBadInput, UnreadableOccupancyOfAnAlternateLocation) {
  // An unreadable occupancy elsewhere is tolerated (fullerene.pdb has "inf"): it chooses nothing.
  expectError(data("bad/altloc_occupancy.pdb"), 3, "'  n/a '");
  const Molecule fullerene = readMolecule(data("small/fullerene.pdb"));
  EXPECT_EQ(fullerene.size(), 60u);
  EXPECT_TRUE(std::isnan(fullerene.atoms[0].occupancy));
}

TEST(MoleculeBadInput, MmcifNumbers) {
  expectError(data("bad/garbage_coordinate.cif"), 22, "'1.2.3'");
  expectError(data("bad/missing_coordinate.cif"), 23, "'?'");
}

TEST(MoleculeBadInput, TruncatedMmcif) {
  expectError(data("bad/truncated.cif"), 3, "incomplete row");
}

// Found by fuzz_mmcif: gemmi's category lookup threw a bare std::runtime_error (no file, no
// line) for a loop that mixes two categories.
TEST(MoleculeBadInput, MmcifLoopOfTwoCategories) {
  expectError(data("bad/loop_of_two_categories.cif"), 8, "Tag _other.B_iso_or_equiv in loop with _atom_site");
}

// Found by fuzz_pdb: a line longer than 120 columns with a byte >= 0x80 past column 120, then
// a second ATOM record on the same line. gemmi read that record as a line of its own, which
// the reader's own pass had not seen (an internal assertion). Columns past 120 are ignored:
// one atom, from line 1.
TEST(MoleculeBadInput, LongLineWithAHighByteHidesNoRecord) {
  const Molecule m = readMolecule(data("bad/long_line_high_byte.pdb"));
  ASSERT_EQ(m.size(), 1u);
  EXPECT_EQ(m.atoms[0].name, "N");
  EXPECT_EQ(m.atoms[0].line, 1);
  EXPECT_EQ(m.centers[0], glm::dvec3(17.047, 14.099, 3.625));
}

TEST(MoleculeBadInput, MalformedPqrLine) { expectError(data("bad/malformed.pqr"), 3, "got 9"); }

TEST(MoleculeBadInput, NegativeAndNonFiniteRadii) {
  expectError(data("bad/negative_radius.pqr"), 2, "'-1.9080'");
  expectError(data("bad/nan_radius.xyzr"), 2, "'nan'");
}

TEST(MoleculeBadInput, XyzrLineWithThreeColumns) {
  expectError(data("bad/short_line.xyzr"), 4, "expected 4 fields (x y z r), got 3");
}

// A 1 MB line (issue 18: a 20 MB one was echoed whole; lines past 1 MiB are refused as
// they arrive) is quoted by its first characters and its length, in XYZR, XYZ and a radius
// table alike.
TEST(MoleculeBadInput, HugeLineIsQuotedShort) {
  const std::string huge(1'000'000, '7');
  for (const auto& [name, text] : std::vector<std::pair<std::string, std::string>>{
           {"huge.xyzr", "0 0 0 1.5\n1 2 " + huge + "x 1.5\n"},
           {"huge.xyz", "2\ncomment\nC 0 0 0\nC 1 2 " + huge + "x\n"}}) {
    try {
      readMoleculeBytes(text, name);
      ADD_FAILURE() << name << " was read";
    } catch (const InputError& e) {
      EXPECT_LT(std::string(e.what()).size(), 400u) << name;
      EXPECT_THAT(e.what(), HasSubstr("characters)")) << name << ": " << e.what();
    }
  }
  const fs::path dir = ::surftrace::test::testTempDir() / "huge_radii";
  fs::create_directories(dir);
  {
    std::ofstream(dir / "radii.txt") << "C 1.7 " << huge << "\n";
  }
  try {
    RadiusTable::load(dir / "radii.txt");
    ADD_FAILURE() << "the radius table was read";
  } catch (const InputError& e) {
    EXPECT_LT(std::string(e.what()).size(), 400u);
    EXPECT_THAT(e.what(), HasSubstr("characters)"));
  }
}

// An element column that names no element ("Xx") is not silently carbon (issue 18): the atom
// takes what its name gives, and a note says so with the line.
TEST(Molecule, UnknownElementSymbolIsNoted) {
  const std::string pdb =
      "ATOM      1  N   ALA A   1      11.104   6.134  -6.504  1.00  0.00           N\n"
      "ATOM      2  CA  ALA A   1      11.639   6.071  -5.147  1.00  0.00          Xx\n"
      "END\n";
  const Molecule m = readMoleculeBytes(pdb, "xx.pdb");
  ASSERT_EQ(m.size(), 2u);
  EXPECT_EQ(m.atoms[1].element, "C");
  ASSERT_EQ(m.notes.size(), 1u);
  EXPECT_THAT(m.notes[0], HasSubstr("line 2"));
  EXPECT_THAT(m.notes[0], HasSubstr("'Xx' is no element"));
  EXPECT_THAT(m.notes[0], HasSubstr("took C from the atom name"));
  // A known symbol gives no note.
  EXPECT_TRUE(readMoleculeBytes(pdb.substr(0, pdb.find('\n') + 1) + "END\n", "n.pdb").notes.empty());
}

// 200,000 copies of one atom (issue 18: quadratic, over a minute) read as one atom with a note;
// an atom at the same centre with another radius is kept.
TEST(Molecule, ExactDuplicatesAreLeftOutWithANote) {
  std::string xyzr;
  for (int i = 0; i < 200000; ++i) xyzr += "1.25 -2.5 3 1.5\n";
  xyzr += "1.25 -2.5 3 1.7\n-0 0 0 1.5\n0 -0 0 1.5\n";
  const Molecule m = readMoleculeBytes(xyzr, "copies.xyzr");
  ASSERT_EQ(m.size(), 3u);
  EXPECT_EQ(m.radii, (std::vector<double>{1.5, 1.7, 1.5}));
  EXPECT_EQ(m.skipped.duplicates, 200000u - 1u + 1u);
  ASSERT_EQ(m.notes.size(), 1u);
  EXPECT_THAT(m.notes[0], HasSubstr("200000 atoms lie exactly on an earlier atom"));
  EXPECT_THAT(m.notes[0], HasSubstr("line 2 repeats line 1"));
  EXPECT_EQ(m.atoms[1].line, 200001);
  // PDB: the same atom record twice (same name, residue, element and centre).
  const std::string atom = "ATOM      1  CA  ALA A   1      11.639   6.071  -5.147  1.00  0.00           C\n";
  EXPECT_EQ(readMoleculeBytes(atom + atom + atom + "END\n", "thrice.pdb").size(), 1u);
}

// The duplicate search against a plain oracle (a std::map from each atom's text to the first
// line that has it), on files large enough that the search partitions its atoms: atoms repeat
// earlier ones near and far back, some at the same centre with another radius (kept), PDB
// atoms at the same centre with another name (kept), and -0 against 0 (one coordinate).
TEST(Molecule, ExactDuplicatesMatchAPlainOracle) {
  for (const int atoms : {1, 3, 5000, 60000}) {
    std::string xyzr;
    std::map<std::string, int> firstLine;   // "x y z r" -> the line that has it first
    std::vector<std::string> lineKeys;       // the key of every line
    std::vector<int> wantKeptLines;
    int wantDropped = 0, wantFirstDroppedLine = 0, wantItsOriginal = 0;
    for (int i = 0; i < atoms; ++i) {
      const int line = i + 1;
      std::string key;
      const unsigned h = static_cast<unsigned>(i) * 2654435761u;
      if (i > 0 && h % 5 == 0) {
        key = lineKeys[h / 5 % static_cast<unsigned>(i)];  // an earlier atom, near or far
      } else if (i > 0 && h % 7 == 0) {
        key = lineKeys[h / 7 % static_cast<unsigned>(i)];  // an earlier centre, another radius
        key = key.substr(0, key.rfind(' ')) + " 1.99";
      } else {
        key = std::to_string(i % 97) + "." + std::to_string(i % 1000) + " " + std::to_string(i / 97) + " " +
              (i % 11 == 0 ? "0" : std::to_string(i % 13)) + " 1." + std::to_string(10 + i % 7);
      }
      lineKeys.push_back(key);
      const auto [it, fresh] = firstLine.try_emplace(key, line);
      if (fresh) {
        wantKeptLines.push_back(line);
      } else if (wantDropped++ == 0) {
        wantFirstDroppedLine = line;
        wantItsOriginal = it->second;
      }
      // Zero spelt "-0" on every other line that has it: the same coordinate.
      std::string spelt = key;
      if (i % 2 == 0 && spelt.size() > 2 && spelt.compare(spelt.size() - 7, 3, " 0 ") == 0)
        spelt.replace(spelt.size() - 6, 1, "-0");
      xyzr += spelt + "\n";
    }
    const Molecule m = readMoleculeBytes(xyzr, "dups.xyzr");
    ASSERT_EQ(m.size(), wantKeptLines.size()) << atoms;
    for (std::size_t k = 0; k < m.size(); ++k) ASSERT_EQ(m.atoms[k].line, wantKeptLines[k]) << atoms << ", atom " << k;
    EXPECT_EQ(m.skipped.duplicates, static_cast<std::size_t>(wantDropped)) << atoms;
    if (wantDropped == 0) {
      EXPECT_TRUE(m.notes.empty()) << atoms;
      continue;
    }
    ASSERT_EQ(m.notes.size(), 1u) << atoms;
    EXPECT_THAT(m.notes[0], HasSubstr("line " + std::to_string(wantFirstDroppedLine) + " repeats line " +
                                      std::to_string(wantItsOriginal)));
  }
  // PDB: one centre, the names decide.
  std::string pdb;
  for (int i = 0; i < 3000; ++i) {
    char line[100];
    std::snprintf(line, sizeof line, "ATOM  %5d  %-3s ALA A%4d    %8.3f%8.3f%8.3f  1.00  0.00           %c\n", i + 1,
                  i % 3 == 0 ? "N" : i % 3 == 1 ? "CA" : "C", 1 + i / 3, 1.0 + 0.01 * (i % 1800 / 3), 2.0, 3.0,
                  i % 3 == 0 ? 'N' : 'C');
    pdb += line;
  }
  // N, CA and C of a residue share a centre but not a name (kept); atom i repeats atom i - 1800
  // (same name, residue name and centre) from i = 1800 on.
  const Molecule m = readMoleculeBytes(pdb + "END\n", "dups.pdb");
  EXPECT_EQ(m.size(), 1800u);
  EXPECT_EQ(m.skipped.duplicates, 1200u);
  ASSERT_EQ(m.notes.size(), 1u);
  EXPECT_THAT(m.notes[0], HasSubstr("line 1801 repeats line 1"));
}

// The decimal text of m / 1000 (m an integer): "-12.345", "0.007". Its double is m / 1000.0,
// the division being correctly rounded as the reading of the decimal is.
std::string thousandths(long long m) {
  const long long a = m < 0 ? -m : m;
  char text[32];
  std::snprintf(text, sizeof text, "%s%lld.%03lld", m < 0 ? "-" : "", a / 1000, a % 1000);
  return text;
}

// A large generated XYZR file, read back coordinate by coordinate against its generator: the
// numbers spelt every way a writer spells them (a leading '+', exponents in either case with
// and without a sign, no digit before or after the point, tabs, several spaces, CRLF lines).
TEST(Molecule, LargeGeneratedXyzrReadsEveryNumberExactly) {
  constexpr int kAtoms = 200000;
  // Distinct coordinates (7919 is prime to 2000001), so no atom is a duplicate of another.
  const auto millis = [](int i, int axis) {
    return (static_cast<long long>(i) * 7919 + 104729LL * axis) % 2000001 - 1000000;
  };
  const auto spell = [](long long m, int style) -> std::string {
    switch (style) {
      case 0: return thousandths(m);
      case 1: return (m >= 0 ? "+" : "") + thousandths(m);         // "+12.345"
      case 2: return std::to_string(m) + "e-3";                    // "12345e-3"
      case 3: return std::to_string(m) + "E-03";                   // "12345E-03"
      case 4: return thousandths(m) + "e+0";                       // "12.345e+0"
      case 5: return std::to_string(m * 10) + "E-4";               // "123450E-4"
      default: {                                                   // ".345", "-.345", "12."
        if (m % 1000 == 0) return std::to_string(m / 1000) + ".";
        const std::string t = thousandths(m);
        return t.rfind("0.", 0) == 0 ? t.substr(1) : t.rfind("-0.", 0) == 0 ? "-" + t.substr(2) : t;
      }
    }
  };
  const char* separators[] = {" ", "\t", "   ", " \t "};
  std::string text = "# x y z r, generated\n";
  for (int i = 0; i < kAtoms; ++i) {
    if (i % 97 == 0) text += "  ";
    for (int axis = 0; axis < 3; ++axis)
      text += spell(millis(i, axis), (i + axis) % 7) + separators[(i + axis) % 4];
    text += (i % 5 == 0 ? "+1." : "1.") + std::to_string(10 + i % 90);  // 1.10 ... 1.99
    text += i % 3 == 0 ? "\r\n" : "\n";
  }
  const Molecule m = readMoleculeBytes(text, "generated.xyzr");
  ASSERT_EQ(m.size(), static_cast<std::size_t>(kAtoms));
  int wrong = 0;
  for (int i = 0; i < kAtoms; ++i) {
    const auto k = static_cast<std::size_t>(i);
    for (int axis = 0; axis < 3; ++axis)
      if (m.centers[k][axis] != static_cast<double>(millis(i, axis)) / 1000.0 && ++wrong < 10)
        ADD_FAILURE() << "atom " << i << " axis " << axis << ": " << m.centers[k][axis];
    if (m.radii[k] != static_cast<double>(110 + i % 90) / 100.0 && ++wrong < 10)
      ADD_FAILURE() << "atom " << i << " radius " << m.radii[k];
    if (m.atoms[k].line != i + 2 && ++wrong < 10) ADD_FAILURE() << "atom " << i << " line " << m.atoms[k].line;
  }
  EXPECT_EQ(wrong, 0);
}

// Text std::from_chars reads otherwise than strtod: each is refused with its line and value
// ("+-1.5" was read as -1.5), not-a-number and infinity as not finite.
TEST(MoleculeBadInput, XyzrNumbersStrtodReadsOtherwise) {
  const auto error = [](const std::string& line) {
    try {
      readMoleculeBytes("1 2 3 1.5\n" + line + "\n", "edge.xyzr");
    } catch (const InputError& e) {
      EXPECT_EQ(e.line(), 2) << e.what();
      return std::string(e.what());
    }
    ADD_FAILURE() << line << " was read";
    return std::string();
  };
  EXPECT_THAT(error("+-1.5 2 3 1.5"), HasSubstr("expected a number for x (field 1), got '+-1.5'"));
  EXPECT_THAT(error("1 ++2 3 1.5"), HasSubstr("expected a number for y (field 2), got '++2'"));
  EXPECT_THAT(error("1 2 3 +-1.5"), HasSubstr("expected a number for the radius (field 4), got '+-1.5'"));
  EXPECT_THAT(error("0x1p3 2 3 1.5"), HasSubstr("got '0x1p3'"));  // strtod: 8
  EXPECT_THAT(error("1 2 3e 1.5"), HasSubstr("got '3e'"));        // strtod: 3, the 'e' left over
  EXPECT_THAT(error("1 2 1,5 1.5"), HasSubstr("got '1,5'"));
  EXPECT_THAT(error("1e400 2 3 1.5"), HasSubstr("got '1e400'"));  // strtod: HUGE_VAL
  EXPECT_THAT(error("nan 2 3 1.5"), HasSubstr("x is not finite: 'nan'"));
  EXPECT_THAT(error("1 -NaN 3 1.5"), HasSubstr("y is not finite: '-NaN'"));
  EXPECT_THAT(error("1 2 +inf 1.5"), HasSubstr("z is not finite: '+inf'"));
  EXPECT_THAT(error("1 2 3 infinity"), HasSubstr("the radius is not finite: 'infinity'"));
}

// The reader takes a plain "x y z r" line in one pass and any other line field by field. A form
// feed before the line end sends the same numbers the field-by-field way (it is white space
// there, but not to the one-pass reading), so each line is read both ways: the same atom, its
// numbers those strtod gives (correctly rounded, as from_chars), or the same error.
TEST(Molecule, XyzrPlainLinesReadAsFieldByField) {
  const std::vector<std::string> good = {
      "1 2 3 1.5", "-0 0.1 -.5 5.", "1e-320 5e-324 -2.2250738585072014e-308 1.25",
      "0.30000000000000004441 123456.78901234567890123456789 -1E+2 0.9E-01",
      "\t 63.130\t-67.331 -18.137  1.5500  ", "7 8 9 2\r", "+1 2 3 1.5", "1 +2 3 +1.5"};
  for (const std::string& line : good) {
    const Molecule plain = readMoleculeBytes("0 0 0 1\n" + line + "\n", "plain.xyzr");
    const Molecule fielded = readMoleculeBytes("0 0 0 1\n" + line + "\f\n", "fielded.xyzr");
    ASSERT_EQ(plain.size(), 2u) << line;
    ASSERT_EQ(fielded.size(), 2u) << line;
    std::istringstream in(line);
    std::string spelt[4];
    in >> spelt[0] >> spelt[1] >> spelt[2] >> spelt[3];
    for (int axis = 0; axis < 3; ++axis) {
      const double expected = std::strtod(spelt[axis].c_str(), nullptr);
      EXPECT_EQ(plain.centers[1][axis], expected) << line;
      EXPECT_EQ(std::signbit(plain.centers[1][axis]), std::signbit(expected)) << line;
      EXPECT_EQ(fielded.centers[1][axis], expected) << line;
      EXPECT_EQ(std::signbit(fielded.centers[1][axis]), std::signbit(expected)) << line;
    }
    EXPECT_EQ(plain.radii[1], std::strtod(spelt[3].c_str(), nullptr)) << line;
    EXPECT_EQ(fielded.radii[1], plain.radii[1]) << line;
    for (const Molecule* m : {&plain, &fielded}) {
      EXPECT_EQ(m->atoms[1].line, 2) << line;
      EXPECT_EQ(m->atoms[1].serial, 2) << line;
      EXPECT_EQ(m->atoms[1].segid, "SYSTEM") << line;
      EXPECT_TRUE(m->atoms[1].name.empty()) << line;
    }
  }
  const auto error = [](const std::string& text) {
    try {
      readMoleculeBytes(text, "edge.xyzr");
    } catch (const InputError& e) {
      return std::to_string(e.line()) + ": " + e.what();
    }
    return std::string("read");
  };
  const std::vector<std::pair<std::string, std::string>> bad = {
      {"1 2 3", "expected 4 fields (x y z r), got 3: '1 2 3'"},
      {"1 2 3 1.5 7", "got 5: '1 2 3 1.5 7'"},
      {"1 2 3 1.5 # note", "got 6"},
      {"1 2 3x 1.5", "expected a number for z (field 3), got '3x'"},
      {"1 2 0x1p3 1.5", "got '0x1p3'"},
      {"1 2 3 1.5e", "expected a number for the radius (field 4), got '1.5e'"},
      {"1 nan 3 1.5", "y is not finite: 'nan'"},
      {"1 2 -inf 1.5", "z is not finite: '-inf'"},
      {"1 2 3 1e400", "got '1e400'"},
      {"1 2 3 -1.5", "the radius must be > 0, got '-1.5'"},
      {"1 2 3 0", "the radius must be > 0, got '0'"}};
  for (const auto& [line, message] : bad) {
    const std::string plain = error("0 0 0 1\n" + line + "\n");
    EXPECT_THAT(plain, HasSubstr(message));
    EXPECT_EQ(plain.rfind("2: ", 0), 0u) << plain;
    EXPECT_EQ(error("0 0 0 1\n" + line + "\f\n"), plain);
  }
  // A radius of 0 left out by request, either way: the next atom keeps its serial and line.
  for (const std::string end : {"\n", "\f\n"}) {
    ReadOptions options;
    options.dropZeroRadius = true;
    const Molecule m = readMoleculeBytes("1 2 3 0" + end + "4 5 6 1.5\n", "zero.xyzr", options);
    ASSERT_EQ(m.size(), 1u);
    EXPECT_EQ(m.atoms[0].serial, 2);
    EXPECT_EQ(m.atoms[0].line, 2);
    EXPECT_EQ(m.skipped.zeroRadius, 1u);
  }
}

// A large generated GRO file (wrapping atom and residue numbers as GROMACS writes them), read
// back against its generator: every coordinate is 10 times the nm the columns hold.
TEST(Molecule, LargeGeneratedGroReadsEveryCoordinateExactly) {
  constexpr int kAtoms = 120000;
  const auto millis = [](int i, int axis) {
    return (static_cast<long long>(i) * 7919 + 104729LL * axis) % 1999999 - 999999;  // |x| < 1000 nm
  };
  const char* names[] = {"N", "CA", "C", "O", "CB"};
  std::string text = "generated\n" + std::to_string(kAtoms) + "\n";
  char line[96];
  for (int i = 0; i < kAtoms; ++i) {
    std::snprintf(line, sizeof line, "%5d%-5s%5s%5d%8s%8s%8s\n", (i / 5 + 1) % 100000, "ALA",
                  names[i % 5], (i + 1) % 100000, thousandths(millis(i, 0)).c_str(),
                  thousandths(millis(i, 1)).c_str(), thousandths(millis(i, 2)).c_str());
    text += line;
  }
  text += "   10.00000   10.00000   10.00000\n";
  const Molecule m = readMoleculeBytes(text, "generated.gro");
  ASSERT_EQ(m.size(), static_cast<std::size_t>(kAtoms));
  int wrong = 0;
  for (int i = 0; i < kAtoms; ++i) {
    const auto k = static_cast<std::size_t>(i);
    for (int axis = 0; axis < 3; ++axis)
      if (m.centers[k][axis] != 10.0 * (static_cast<double>(millis(i, axis)) / 1000.0) && ++wrong < 10)
        ADD_FAILURE() << "atom " << i << " axis " << axis << ": " << m.centers[k][axis];
    if (m.atoms[k].residueNumber != i / 5 + 1 && ++wrong < 10)
      ADD_FAILURE() << "atom " << i << " residue " << m.atoms[k].residueNumber;
    if (m.atoms[k].element != std::string(1, names[i % 5][0]) && ++wrong < 10)
      ADD_FAILURE() << "atom " << i << " element " << m.atoms[k].element;
  }
  EXPECT_EQ(wrong, 0);
}

TEST(MoleculeBadInput, XyzProblems) {
  expectError(data("bad/truncated.xyz"), 6, "3 of the 5 atoms");
  expectError(data("bad/bad_count.xyz"), 1, "'five'");
  expectError(data("bad/inf_coordinate.xyz"), 4, "'inf'");
}

// ---------------------------------------------------------------------------------------------
// validateMolecule

TEST(MoleculeValidate, RejectsNonFiniteCentresAndBadRadii) {
  Molecule m;
  m.source = "frame.dcd";
  m.centers = {{0.0, 0.0, 0.0}, {1.0, 0.0, 0.0}};
  m.radii = {1.5, 1.5};
  m.atoms.resize(2);
  m.atoms[1].name = "CA";
  m.atoms[1].line = 7;
  EXPECT_NO_THROW(validateMolecule(m));

  m.centers[1].y = std::nan("");
  try {
    validateMolecule(m);
    ADD_FAILURE() << "no error for a NaN centre";
  } catch (const InputError& e) {
    EXPECT_EQ(e.line(), 7);
    EXPECT_THAT(e.what(), HasSubstr("'CA'"));
  }
  m.centers[1].y = 0.0;
  m.radii[0] = 0.0;
  EXPECT_THROW(validateMolecule(m), InputError);
  m.radii[0] = 1.5;
  // Finite but absurd (issue 18: a coordinate of 1e30 rendered a blank image with exit 0).
  for (const double far : {1e30, -2e6, kMaxCoordinate * (1 + 1e-15)}) {
    m.centers[1].x = far;
    try {
      validateMolecule(m);
      ADD_FAILURE() << "no error for a centre at " << far;
    } catch (const InputError& e) {
      EXPECT_EQ(e.line(), 7);
      EXPECT_THAT(e.what(), HasSubstr("lies beyond 1e+06 Å"));
    }
  }
  m.centers[1].x = kMaxCoordinate;
  EXPECT_NO_THROW(validateMolecule(m));
  m.centers[1].x = 1.0;
  m.radii[1] = 1e4;
  EXPECT_THAT([&] { validateMolecule(m); }, ::testing::ThrowsMessage<InputError>(HasSubstr("larger than 1000 Å")));
  m.radii[1] = 1.5;
  m.radii.pop_back();
  EXPECT_THROW(validateMolecule(m), InputError);
  EXPECT_THROW(validateMolecule(Molecule{}), InputError);
}

// ---------------------------------------------------------------------------------------------
// PQR

struct PqrColumns {
  glm::dvec3 center;
  double radius;
};
using PqrKey = std::pair<int, std::string>;  // residue number, atom name

// ATOM records of a PQR file read independently: PDB columns 13-16 (name), 23-26 (residue
// number) and 31-54 (x, y, z); the radius is the last field.
std::map<PqrKey, PqrColumns> pqrByColumns(const fs::path& path) {
  std::map<PqrKey, PqrColumns> out;
  for (const std::string& line : lines(readText(path))) {
    if (line.rfind("ATOM", 0) != 0) continue;
    std::istringstream name(line.substr(12, 4));
    std::string trimmed;
    name >> trimmed;
    const std::string radius = line.substr(line.find_last_of(' ') + 1);
    out[{std::stoi(line.substr(22, 4)), trimmed}] = {
        {std::stod(line.substr(30, 8)), std::stod(line.substr(38, 8)),
         std::stod(line.substr(46, 8))},
        std::stod(radius)};
  }
  return out;
}

const char* const kPqrVariants[] = {"1000.pqr",
                                    "1000-chain.pqr",
                                    "1000-chain-whitespace.pqr",
                                    "1000-custom.pqr",
                                    "1000-resi.pqr",
                                    "1000-resi-chain.pqr",
                                    "1000-resi-chain-whitespace.pqr",
                                    "1000-resi-whitespace.pqr",
                                    "1000-whitespace.pqr"};

TEST(Pqr, RadiiAreTheFilesLastColumn) {
  for (const char* name : kPqrVariants) {
    const fs::path path = data(std::string("small/pqr/") + name);
    const Molecule m = readMolecule(path);
    EXPECT_EQ(m.radiiSet, "file");
    std::vector<double> lastColumn;
    for (const std::string& line : lines(readText(path)))
      if (line.rfind("ATOM", 0) == 0)
        lastColumn.push_back(std::stod(line.substr(line.find_last_of(' ') + 1)));
    EXPECT_EQ(m.radii, lastColumn) << name;
  }
}

TEST(Pqr, EveryLayoutGivesTheSameCoordinates) {
  // 1000.pqr runs its coordinates together ("1999.3232998.770-900.490"), so its PDB columns
  // are the reference. The -resi variants number the residues from 1001 and order some
  // hydrogens differently, so atoms are matched by residue and name.
  const std::map<PqrKey, PqrColumns> reference = pqrByColumns(data("small/pqr/1000.pqr"));
  ASSERT_EQ(reference.size(), 36u);  // MANIFEST
  for (const char* name : kPqrVariants) {
    const Molecule m = readMolecule(data(std::string("small/pqr/") + name));
    ASSERT_EQ(m.size(), reference.size()) << name;
    const std::string variant = name;
    const int offset = variant.find("resi") != std::string::npos ? 1000 : 0;
    const bool chain = variant.find("chain") != std::string::npos;
    for (std::size_t i = 0; i < m.size(); ++i) {
      const AtomRecord& a = m.atoms[i];
      const auto it = reference.find({a.residueNumber - offset, a.name});
      ASSERT_TRUE(it != reference.end()) << name << ": " << a.name << " " << a.residueNumber;
      EXPECT_EQ(m.centers[i], it->second.center) << name << " " << a.name << " " << a.residueNumber;
      EXPECT_EQ(m.radii[i], it->second.radius) << name << " " << a.name;
      EXPECT_EQ(a.chain, chain ? "A" : "") << name;
    }
    EXPECT_EQ(m.atoms[1].name, "CA");
    EXPECT_EQ(m.atoms[1].element, "C");
    EXPECT_NEAR(m.atoms[0].charge, 0.1414, 1e-12);
    EXPECT_EQ(elementCounts(m), (std::map<std::string, std::size_t>{
                                    {"C", 10}, {"H", 16}, {"N", 3}, {"O", 6}, {"S", 1}}))
        << name;
  }
}

TEST(Pqr, ZeroRadiusIsAnErrorUnlessDropped) {
  // example.pqr (PDB2PQR, AMBER) gives two hydroxyl hydrogens radius 0.0000; PyMOL's PQR
  // writer gives every atom 0.000.
  expectError(data("small/pqr/example.pqr"), 32, "'0.0000'");
  expectError(data("small/pqr/1000-pymol.pqr"), 1, "'0.000'");
  ReadOptions options;
  options.dropZeroRadius = true;
  const fs::path path = data("small/pqr/example.pqr");
  const Molecule m = readMolecule(path, options);
  EXPECT_EQ(m.size(), 191u - 2u);  // MANIFEST: 191 atoms
  EXPECT_EQ(m.skipped.zeroRadius, 2u);
  std::vector<double> lastColumn;
  for (const std::string& line : lines(readText(path))) {
    if (line.rfind("ATOM", 0) != 0) continue;
    const double r = std::stod(line.substr(line.find_last_of(' ') + 1));
    if (r != 0.0) lastColumn.push_back(r);
  }
  EXPECT_EQ(m.radii, lastColumn);
  EXPECT_THAT(readError(data("small/pqr/1000-pymol-chain.pqr"), options).what(),
              HasSubstr("all 19 atoms have radius 0"));
}

TEST(Pqr, RadiusTableReplacesTheFileRadii) {
  const fs::path dir = tempDir();
  writeText(dir / "radii.txt", "C 2.0\nALA:CB 2.5\n");
  ReadOptions options;
  options.radiiFile = dir / "radii.txt";
  const Molecule m = readMolecule(data("small/pqr/1000.pqr"), options);
  EXPECT_EQ(m.radiiSet, "table:" + (dir / "radii.txt").string());
  EXPECT_EQ(m.radii[0], 1.55);  // N: Bondi
  EXPECT_EQ(m.radii[1], 2.0);   // CA
  EXPECT_EQ(m.radii[4], 2.5);   // CB of ALA
}

// ---------------------------------------------------------------------------------------------
// XYZR and XYZ

TEST(Xyz, XyzrRoundTrip) {
  const fs::path dir = tempDir();
  const Molecule original = readMolecule(data("structures/1crn.pdb"));
  std::ostringstream out;
  out.precision(17);
  out << "# crambin as x y z r\n";
  for (std::size_t i = 0; i < original.size(); ++i)
    out << original.centers[i].x << ' ' << original.centers[i].y << ' ' << original.centers[i].z
        << ' ' << original.radii[i] << '\n';
  writeText(dir / "crambin.xyzr", out.str());

  const Molecule back = readMolecule(dir / "crambin.xyzr");
  EXPECT_EQ(back.format, MoleculeFormat::Xyzr);
  EXPECT_EQ(back.radiiSet, "file");
  EXPECT_EQ(back.centers, original.centers);
  EXPECT_EQ(back.radii, original.radii);
  EXPECT_EQ(back.atoms[0].line, 2);
  EXPECT_EQ(back.atoms.back().serial, 327);

  ReadOptions options;
  options.keepHydrogens = false;  // XYZR has no elements to tell hydrogens by
  EXPECT_THAT(readError(dir / "crambin.xyzr", options).what(), HasSubstr("no elements"));
  options = {};
  options.radiiFile = dir / "crambin.xyzr";
  EXPECT_THAT(readError(dir / "crambin.xyzr", options).what(), HasSubstr("cannot apply"));
}

TEST(Xyz, XyzRoundTripWithFrames) {
  const fs::path dir = tempDir();
  const Molecule original = readMolecule(data("structures/1crn.pdb"));
  std::ostringstream out;
  out.precision(17);
  for (int frame = 0; frame < 2; ++frame) {
    out << original.size() << "\nframe " << frame + 1 << "\n";
    for (std::size_t i = 0; i < original.size(); ++i)
      out << original.atoms[i].element << ' ' << original.centers[i].x + 10.0 * frame << ' '
          << original.centers[i].y << ' ' << original.centers[i].z << '\n';
  }
  writeText(dir / "crambin.xyz", out.str());

  ReadOptions options;
  options.model = 2;
  const Molecule back = readMolecule(dir / "crambin.xyz", options);
  EXPECT_EQ(back.format, MoleculeFormat::Xyz);
  EXPECT_EQ(back.modelCount, 2);
  EXPECT_EQ(back.skipped.otherModels, original.size());
  ASSERT_EQ(back.size(), original.size());
  for (std::size_t i = 0; i < back.size(); ++i) {
    EXPECT_EQ(back.centers[i], original.centers[i] + glm::dvec3(10.0, 0.0, 0.0));
    EXPECT_EQ(back.atoms[i].element, original.atoms[i].element);
    EXPECT_EQ(back.radii[i], original.radii[i]);
  }
  EXPECT_EQ(back.atoms[0].line, static_cast<int>(original.size()) + 2 + 3);

  options.model = 3;
  EXPECT_THAT(readError(dir / "crambin.xyz", options).what(), HasSubstr("2 frames"));
  options.model = 1;
  options.chains = {"A"};
  EXPECT_THAT(readError(dir / "crambin.xyz", options).what(), HasSubstr("no chains"));
}

// ---------------------------------------------------------------------------------------------
// Radii

TEST(Radii, BondiWithMantinaExtensions) {
  EXPECT_EQ(bondiRadius("H"), 1.20);
  EXPECT_EQ(bondiRadius("D"), 1.20);
  EXPECT_EQ(bondiRadius("C"), 1.70);
  EXPECT_EQ(bondiRadius("N"), 1.55);
  EXPECT_EQ(bondiRadius("O"), 1.52);
  EXPECT_EQ(bondiRadius("S"), 1.80);
  EXPECT_EQ(bondiRadius("P"), 1.80);
  EXPECT_EQ(bondiRadius("Se"), 1.90);
  EXPECT_EQ(bondiRadius("Zn"), 1.39);
  EXPECT_EQ(bondiRadius("Ca"), 2.31);  // Mantina
  EXPECT_EQ(bondiRadius("B"), 1.92);   // Mantina
  EXPECT_EQ(bondiRadius("Fe"), std::nullopt);
  EXPECT_EQ(bondiRadius("X"), std::nullopt);
  EXPECT_EQ(bondiRadius(""), std::nullopt);
}

TEST(Radii, ElementSymbols) {
  EXPECT_EQ(canonicalElement("FE"), "Fe");
  EXPECT_EQ(canonicalElement("fe"), "Fe");
  EXPECT_EQ(canonicalElement(" C"), "C");
  EXPECT_EQ(canonicalElement("D"), "D");
  EXPECT_EQ(canonicalElement("LP"), "");
  EXPECT_EQ(canonicalElement("X"), "");
  EXPECT_EQ(canonicalElement("CAL"), "");
  EXPECT_EQ(elementSymbol(26), "Fe");
  EXPECT_EQ(elementSymbol(118), "Og");
  EXPECT_EQ(elementSymbol(0), "");
}

TEST(Radii, ElementsFromAtomNames) {
  using L = AtomNameLayout;
  EXPECT_EQ(elementFromAtomName(" CA ", "ALA", L::PdbColumns), "C");
  EXPECT_EQ(elementFromAtomName("CA  ", "CA", L::PdbColumns), "Ca");
  EXPECT_EQ(elementFromAtomName("CA  ", "ALA", L::PdbColumns), "C");  // Amber, standard residue
  EXPECT_EQ(elementFromAtomName("FE  ", "HEM", L::PdbColumns), "Fe");
  EXPECT_EQ(elementFromAtomName("HH31", "ACE", L::PdbColumns), "H");
  EXPECT_EQ(elementFromAtomName("HG21", "LIG", L::PdbColumns), "H");
  EXPECT_EQ(elementFromAtomName("1HB ", "LIG", L::PdbColumns), "H");
  EXPECT_EQ(elementFromAtomName("C210", "LIG", L::PdbColumns), "C");
  EXPECT_EQ(elementFromAtomName("CA", "ALA", L::Token), "C");
  EXPECT_EQ(elementFromAtomName("CA", "CA", L::Token), "Ca");
  EXPECT_EQ(elementFromAtomName("FE", "HEM", L::Token), "Fe");
  EXPECT_EQ(elementFromAtomName("ZN", "ZN", L::Token), "Zn");
  EXPECT_EQ(elementFromAtomName("NE2", "HIS", L::Token), "N");
  EXPECT_EQ(elementFromAtomName("X1", "LIG", L::Token), "");
}

TEST(Radii, UnknownElementNamesFileLineAndAtom) {
  // elements.xyz: one atom of each of 113 "elements", the first "LP" (a lone pair).
  expectError(data("small/elements.xyz"), 3, "'LP'");
  expectError(data("bad/unknown_element.pdb"), 3, "'XX'");
}

// One atom of each element of elements.xyz, read alone. The expectations are typed from the
// papers, not from radii.cpp: which elements each table covers (Bondi 1964 Table I; Mantina
// et al. 2009 Table 12; Alvarez 2013 Table 1, which gives nothing for Pm, Po-Ra or Z >= 100)
// and a few values of each.
TEST(Radii, EveryElementOfElementsXyzReadsOrNamesItsElement) {
  const std::set<std::string> mantina = {"Be", "B",  "Al", "Ca", "Ge", "Rb", "Sr", "Sb",
                                         "Cs", "Ba", "Bi", "Po", "At", "Rn", "Fr", "Ra"};
  const std::set<std::string> bondi = {"H",  "He", "Li", "C",  "N",  "O",  "F",  "Ne",
                                       "Na", "Mg", "Si", "P",  "S",  "Cl", "Ar", "K",
                                       "Ni", "Cu", "Zn", "Ga", "As", "Se", "Br", "Kr",
                                       "Pd", "Ag", "Cd", "In", "Sn", "Te", "I",  "Xe",
                                       "Pt", "Au", "Hg", "Tl", "Pb", "U"};
  const std::map<std::string, double> spot = {
      {"C", 1.70},  {"Zn", 1.39}, {"Ca", 2.31}, {"Ra", 2.83}, {"Fe", 2.44}, {"Mn", 2.45},
      {"Co", 2.40}, {"Mo", 2.45}, {"W", 2.57},  {"Gd", 2.83}, {"Bk", 3.40}, {"Es", 2.70}};
  const fs::path dir = tempDir();
  const std::vector<std::string> text = lines(readText(data("small/elements.xyz")));
  ASSERT_EQ(std::stoul(text.at(0)), text.size() - 2);
  std::size_t covered = 0, refused = 0;
  for (std::size_t i = 2; i < text.size(); ++i) {
    std::istringstream fields(text[i]);
    std::string symbol;
    fields >> symbol;
    const std::string rest = text[i].substr(symbol.size());
    const fs::path one = dir / (symbol + ".xyz");
    writeText(one, "1\n" + symbol + "\n" + symbol + rest + "\n");
    const int z = static_cast<int>(i) - 2;  // line 3 is LP, then H (Z = 1) onwards
    const bool expected = z >= 1 && z <= 99 && z != 61;
    if (!expected) {
      const InputError e = readError(one);
      EXPECT_EQ(e.line(), 3) << symbol;
      EXPECT_THAT(e.what(), HasSubstr(z == 0 ? "'LP' is not an element symbol"
                                             : "element " + symbol + " has no radius"))
          << symbol;
      EXPECT_THAT(e.what(), HasSubstr("--default-radius")) << symbol;
      ++refused;
      continue;
    }
    const Molecule m = readMolecule(one);
    ASSERT_EQ(m.size(), 1u) << symbol;
    const RadiusSource want = bondi.count(symbol)     ? RadiusSource::Bondi
                              : mantina.count(symbol) ? RadiusSource::Mantina
                                                      : RadiusSource::Alvarez;
    EXPECT_EQ(m.radiusSources[static_cast<std::size_t>(want)], 1u) << symbol;
    EXPECT_GE(m.radii[0], 1.2) << symbol;
    EXPECT_LE(m.radii[0], 3.5) << symbol;
    if (const auto it = spot.find(symbol); it != spot.end()) {
      EXPECT_EQ(m.radii[0], it->second) << symbol;
    }
    ++covered;
  }
  EXPECT_EQ(covered, 98u);  // Z = 1..99 but Pm
  EXPECT_EQ(refused, 15u);  // LP, Pm, Fm..Cn
}

TEST(Radii, MoleculeCountsAtomsBySource) {
  // 1MBN: one heme Fe (grep '^HETATM.*FE'); every other atom is C, N, O or S.
  const Molecule m = readMolecule(data("structures/1mbn.pdb.gz"));
  EXPECT_EQ(m.size(), 1260u);  // MANIFEST
  EXPECT_EQ(m.radiusSources[static_cast<std::size_t>(RadiusSource::Alvarez)], 1u);
  EXPECT_EQ(m.radiusSources[static_cast<std::size_t>(RadiusSource::Bondi)], m.size() - 1);
  const Molecule pqr = readMolecule(data("small/pqr/1000.pqr"));
  EXPECT_EQ(pqr.radiusSources[static_cast<std::size_t>(RadiusSource::File)], pqr.size());
}

TEST(Radii, DefaultRadiusCoversUnknownElements) {
  // elements.xyz holds LP and H..Cn (112 elements). Bondi (38, with D), Mantina (16) and
  // Alvarez (44 more) cover 98 of them, so LP, Pm and Fm..Cn (15 atoms) take the default.
  ReadOptions options;
  options.defaultRadius = 1.8;
  const Molecule m = readMolecule(data("small/elements.xyz"), options);
  ASSERT_EQ(m.size(), 113u);
  EXPECT_EQ(m.skipped.defaultRadius, 15u);
  std::map<std::string, double> radius;
  for (std::size_t i = 0; i < m.size(); ++i) radius[m.atoms[i].element] = m.radii[i];
  EXPECT_EQ(radius.at("C"), 1.70);
  EXPECT_EQ(radius.at("Ca"), 2.31);
  EXPECT_EQ(radius.at("Fe"), 2.44);
  EXPECT_EQ(radius.at("Pm"), 1.8);
  EXPECT_EQ(radius.at("Cn"), 1.8);
  EXPECT_EQ(m.radii[0], 1.8);  // LP
  options.defaultRadius = -1.0;
  EXPECT_THAT(readError(data("small/elements.xyz"), options).what(), HasSubstr("default radius"));
}

TEST(Radii, UserTable) {
  const fs::path dir = tempDir();
  writeText(dir / "radii.txt", "# test table\nC 2.0   # carbon\n\nTHR:OG1 1.25\nfe 1.9\n");
  ReadOptions options;
  options.radiiFile = dir / "radii.txt";
  const Molecule m = readMolecule(data("structures/1crn.pdb"), options);
  EXPECT_EQ(m.radiiSet, "table:" + (dir / "radii.txt").string());
  for (std::size_t i = 0; i < m.size(); ++i) {
    const AtomRecord& a = m.atoms[i];
    if (a.residue == "THR" && a.name == "OG1") {
      EXPECT_EQ(m.radii[i], 1.25);
    } else if (a.element == "C") {
      EXPECT_EQ(m.radii[i], 2.0);
    } else {
      EXPECT_EQ(m.radii[i], *bondiRadius(a.element)) << a.name;  // not in the table
    }
  }
  const RadiusTable table = RadiusTable::load(dir / "radii.txt");
  EXPECT_EQ(table.find("HEM", "FE", "Fe"), 1.9);
  EXPECT_EQ(table.find("thr", "og1", "O"), 1.25);
  EXPECT_EQ(table.find("SER", "OG", "O"), std::nullopt);
}

TEST(Radii, MalformedTableLineNamesTheTable) {
  ReadOptions options;
  options.radiiFile = data("bad/malformed_radii.txt");
  const InputError e = readError(data("structures/1crn.pdb"), options);
  EXPECT_EQ(e.path(), data("bad/malformed_radii.txt").string());
  EXPECT_EQ(e.line(), 4);
  EXPECT_THAT(e.what(), HasSubstr("'O'"));

  const fs::path dir = tempDir();
  writeText(dir / "zero.txt", "C 0\n");
  writeText(dir / "element.txt", "Xx 1.0\n");
  writeText(dir / "twice.txt", "C 1.7\nc 1.8\n");
  EXPECT_THROW(RadiusTable::load(dir / "zero.txt"), InputError);
  try {
    RadiusTable::load(dir / "element.txt");
    ADD_FAILURE();
  } catch (const InputError& err) {
    EXPECT_EQ(err.line(), 1);
    EXPECT_THAT(err.what(), HasSubstr("'Xx'"));
  }
  try {
    RadiusTable::load(dir / "twice.txt");
    ADD_FAILURE();
  } catch (const InputError& err) {
    EXPECT_EQ(err.line(), 2);
    EXPECT_THAT(err.what(), HasSubstr("line 1"));
  }
}

}  // namespace
}  // namespace surftrace::build

namespace surftrace::build {
namespace {

// MDAnalysis writes "MODEL 7" with the serial right after the keyword; gemmi alone reads
// the serial from the next line and reports a duplicate model.
TEST(MoleculeModels, ShortModelRecordsFromMdAnalysis) {
  const std::string path = std::string(SURFTRACE_TEST_DATA) + "/ensembles/1grm_elNemo_mode7.pdb.gz";
  ReadOptions options;
  options.model = 7;
  const Molecule m = readMolecule(path, options);
  EXPECT_EQ(m.modelCount, 11);
  EXPECT_EQ(m.size(), 264u);
  EXPECT_EQ(m.atoms.front().line, 1611);  // "MODEL 7" on line 1609, a REMARK, then the first ATOM
}

}  // namespace
}  // namespace surftrace::build

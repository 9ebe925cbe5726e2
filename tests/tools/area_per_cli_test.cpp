// `surftrace area --per atom|residue|chain` and `--radii protor|naccess` end to end, against
// oracles that share no code with them: FreeSASA's own program (its per-residue Lee & Richards
// areas and the radius its classifier gives every atom), the structure files' own columns read
// here, Tien et al. 2013's maximum ASA as typed from the paper, sums of the per-atom rows, and
// `area` of one model alone for each frame of a trajectory.
#include <gtest/gtest.h>

#include <cmath>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <map>
#include <set>
#include <sstream>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "run_tool.hpp"
#include "temp_dir.hpp"

namespace surftrace::tools::test {
namespace {

namespace fs = std::filesystem;
using nlohmann::json;

const std::string kData = SURFTRACE_TEST_DATA;
const std::string kCrambin = kData + "/structures/1crn.pdb";
const std::string kFab = kData + "/structures/1a0q.pdb.gz";         // Kabat insertion codes, ZN, HEP
const std::string kHaemoglobin = kData + "/formats/pdb/4hhb.pdb.gz";  // 4 chains, HEM, PO4, waters
const std::string kCrambinAltLocs = kData + "/structures/1cbn.pdb.gz";
const std::string kEnsemble = kData + "/ensembles/1grm_elNemo_mode7.pdb.gz";  // 11 models

fs::path dir() { return ::surftrace::test::testTempDir(); }

// The program's standard output alone (its notes go to `stderr` in the test's folder).
Result tool(const std::string& args) {
  const fs::path err = dir() / "stderr.txt";
  Result r = runShell(std::string(SURFTRACE_TOOL) + " " + args + " 2>'" + err.string() + "'");
  std::ifstream in(err);
  std::stringstream s;
  s << in.rdbuf();
  if (r.status != 0) r.output += "\n[stderr] " + s.str();
  return r;
}

std::string stderrOfLastRun() {
  std::ifstream in(dir() / "stderr.txt");
  std::stringstream s;
  s << in.rdbuf();
  return s.str();
}

// A plain copy of a (gzipped) structure in the test's folder: FreeSASA reads no gzip.
std::string plain(const std::string& path) {
  const fs::path out = dir() / (fs::path(path).stem().string() + (path.size() > 3 && path.substr(path.size() - 3) == ".gz" ? "" : ".pdb"));
  const Result r = runShell("gzip -dcf '" + path + "' > '" + out.string() + "'");
  if (r.status != 0) throw std::runtime_error("cannot decompress " + path);
  return out.string();
}

// FreeSASA's JSON for `file` (its 2.1.2 command-line program, Debian package freesasa).
json freesasa(const std::string& options, const std::string& file) {
  const fs::path out = dir() / "freesasa.json", err = dir() / "freesasa.err";
  const Result r = runShell("freesasa " + options + " --format=json --output='" + out.string() + "' --error-file='" +
                            err.string() + "' '" + file + "' 2>&1");
  if (r.status != 0)
    throw std::runtime_error("`freesasa` failed (status " + std::to_string(r.status) +
                             "; is it installed? scripts/install-deps.sh --tests): " + r.output);
  std::ifstream in(out);
  return json::parse(in);
}

const json& freesasaChains(const json& j) { return j["results"][0]["structure"][0]["chains"]; }

std::string trimmed(std::string s) {
  s.erase(0, s.find_first_not_of(' '));
  s.erase(s.find_last_not_of(' ') + 1);
  return s;
}

// The file's ATOM records alone: FreeSASA's JSON files hetero groups that follow a TER under the
// chain before them (1A0Q's chain L zinc and waters under chain H), so the per-residue
// comparison is made on the protein, hetero groups being compared atom by atom below.
std::string proteinOnly(const std::string& path) {
  const fs::path out = dir() / ("protein_" + fs::path(path).filename().string() + ".pdb");
  const Result r = runShell("gzip -dcf '" + path + "' | grep -v '^HETATM' > '" + out.string() + "'");
  if (r.status != 0) throw std::runtime_error("cannot write " + out.string());
  return out.string();
}

std::vector<std::string> split(const std::string& line, char by = ',') {
  std::vector<std::string> fields;
  std::string field;
  std::stringstream s(line);
  while (std::getline(s, field, by)) fields.push_back(field);
  if (!line.empty() && line.back() == by) fields.emplace_back();
  return fields;
}

// A CSV as rows of named fields.
std::vector<std::map<std::string, std::string>> csvRows(const std::string& text) {
  std::stringstream s(text);
  std::string line;
  std::getline(s, line);
  const std::vector<std::string> names = split(line);
  std::vector<std::map<std::string, std::string>> rows;
  while (std::getline(s, line)) {
    const std::vector<std::string> f = split(line);
    if (f.size() != names.size()) throw std::runtime_error("CSV row of " + std::to_string(f.size()) + " fields: " + line);
    std::map<std::string, std::string> row;
    for (std::size_t k = 0; k < names.size(); ++k) row[names[k]] = f[k];
    rows.push_back(std::move(row));
  }
  return rows;
}

// Columns 1-6, 17 (altLoc), 18-20, 22, 23-26 and 27 (iCode) of a PDB's ATOM/HETATM lines.
struct PdbAtom {
  std::string record, name, residue, chain;
  char altLoc, insertionCode;
  int serial, residueNumber;
};
std::vector<PdbAtom> pdbAtoms(const std::string& path) {
  std::ifstream in(plain(path));
  std::vector<PdbAtom> atoms;
  std::string line;
  while (std::getline(in, line)) {
    if (line.rfind("ENDMDL", 0) == 0) break;
    if (line.rfind("ATOM  ", 0) != 0 && line.rfind("HETATM", 0) != 0) continue;
    atoms.push_back({line.substr(0, 6), trimmed(line.substr(12, 4)), trimmed(line.substr(17, 3)), trimmed(line.substr(21, 1)),
                     line[16], line[26], std::stoi(line.substr(6, 5)), std::stoi(line.substr(22, 4))});
  }
  return atoms;
}

// Per residue, the SAS with FreeSASA's radii is FreeSASA's Lee & Richards area at 2000 slices,
// for crambin with both presets and for the protein of the 1A0Q Fab (416 residues, insertion
// codes). Lee & Richards converges on our exact areas as its slices thin: on crambin the largest
// residue difference is 6.6e-2 Å² at 250 slices, 6.4e-3 at 1000 and 1.8e-3 at 4000, so the bound
// is that of 2000 slices (measured at most 1.1e-2 Å² on these files). Residues are matched by
// chain, number and insertion code (FreeSASA prints "82A") and name, in order.
TEST(AreaPer, ResidueSasMatchesFreesasaLeeRichardsWithItsRadii) {
  struct Case {
    std::string file, preset;
  };
  for (const Case& c : {Case{kCrambin, "protor"}, Case{kCrambin, "naccess"}, Case{kFab, "protor"}}) {
    SCOPED_TRACE(c.file + " --radii " + c.preset);
    const std::string file = proteinOnly(c.file);
    const Result r = tool("area --radii " + c.preset + " --per residue --format json '" + file + "'");
    ASSERT_EQ(r.status, 0) << r.output;
    const json j = json::parse(r.output), ours = j["per_residue"];
    const json theirs = freesasa("-L --resolution=2000 --radii=" + c.preset + " --depth=residue", file);
    std::size_t k = 0;
    double worst = 0.0, total = 0.0;
    for (const json& chain : freesasaChains(theirs))
      for (const json& residue : chain["residues"]) {
        ASSERT_LT(k, ours.size());
        const json& row = ours[k++];
        std::string number = std::to_string(row["residue_number"].get<int>()) + row["insertion_code"].get<std::string>();
        std::string theirNumber = residue["number"].get<std::string>();
        theirNumber.erase(0, theirNumber.find_first_not_of(' '));
        ASSERT_EQ(row["chain"].get<std::string>(), chain["label"].get<std::string>()) << "row " << k;
        ASSERT_EQ(number, theirNumber) << "row " << k;
        ASSERT_EQ(row["residue"].get<std::string>(), trimmed(residue["name"])) << number;
        ASSERT_EQ(row["atoms"].get<int>(), residue["n-atoms"].get<int>()) << number;
        const double want = residue["area"]["total"].get<double>(), got = row["sas"].get<double>();
        EXPECT_NEAR(got, want, 2e-2) << chain["label"] << " " << number;
        worst = std::max(worst, std::abs(got - want));
        total += want;
      }
    EXPECT_EQ(k, ours.size()) << "FreeSASA has fewer residues";
    EXPECT_NEAR(j["totals"]["sas"].get<double>(), total, 2e-5 * total);
    std::printf("[ %s %s ] %zu residues, largest difference from FreeSASA %.2e Å²\n", fs::path(c.file).filename().c_str(),
                c.preset.c_str(), k, worst);
  }
}

// `--radii protor|naccess` gives every atom the radius FreeSASA's classifier gives it (its
// --radii=protor|naccess, with --hetatm --hydrogen and its default element guess for atoms the
// classifier does not name): crambin, the 1A0Q Fab (zinc, hapten, waters) and 4HHB (four hemes'
// iron, phosphate, waters), atom by atom in file order.
TEST(AreaPer, PresetRadiiAreFreesasaClassifierRadiiOnEveryAtom) {
  for (const std::string& structure : {kCrambin, kFab, kHaemoglobin})
    for (const std::string preset : {"protor", "naccess"}) {
      SCOPED_TRACE(structure + " --radii " + preset);
      const std::string file = plain(structure);
      const Result r = tool("area --radii " + preset + " --keep-water --per atom --format csv '" + file + "'");
      ASSERT_EQ(r.status, 0) << r.output;
      const auto ours = csvRows(r.output);
      const json theirs = freesasa("--radii=" + preset + " --hetatm --hydrogen --depth=atom", file);
      std::size_t k = 0;
      for (const json& chain : freesasaChains(theirs))
        for (const json& residue : chain["residues"])
          for (const json& atom : residue["atoms"]) {
            ASSERT_LT(k, ours.size());
            const auto& row = ours[k++];
            ASSERT_EQ(row.at("name"), atom["name"].get<std::string>()) << "atom " << k - 1;
            ASSERT_EQ(row.at("residue"), trimmed(residue["name"])) << "atom " << k - 1;
            // Both print radii that are multiples of 0.01 Å; ours to 4 decimals.
            EXPECT_NEAR(std::stod(row.at("radius")), atom["radius"].get<double>(), 1e-9)
                << row.at("residue") << " " << row.at("residue_number") << " " << row.at("name");
          }
      EXPECT_EQ(k, ours.size());
    }
}

// The relative SASA is the residue's SAS over Tien et al. 2013's theoretical maximum ASA,
// typed here from the paper (PLoS ONE 8(11): e80635, Table 1, "Theoretical"); the output names
// the table, and residues outside the 20 have no value and a note that says so.
TEST(AreaPer, RelativeSasIsSasOverTiensTheoreticalMaximum) {
  const std::map<std::string, double> typed = {{"ALA", 129.0}, {"ARG", 274.0}, {"GLY", 104.0},
                                               {"THR", 172.0}, {"TRP", 285.0}, {"LEU", 201.0}};
  const Result r = tool("area --per residue --format json " + kFab);
  ASSERT_EQ(r.status, 0) << r.output;
  const json j = json::parse(r.output);
  EXPECT_NE(j["relative_sas_table"].get<std::string>().find("Tien et al. 2013"), std::string::npos);
  std::set<std::string> seen, without;
  for (const json& row : j["per_residue"]) {
    const std::string name = row["residue"];
    if (const auto it = typed.find(name); it != typed.end() && row["sas"].get<double>() > 1.0) {
      EXPECT_NEAR(row["relative_sas"].get<double>(), row["sas"].get<double>() / it->second, 1e-12) << name;
      seen.insert(name);
    }
    if (name == "ZN" || name == "HEP") {
      EXPECT_TRUE(row["relative_sas"].is_null()) << name;
      without.insert(name);
    }
  }
  EXPECT_EQ(seen.size(), typed.size());
  EXPECT_EQ(without, (std::set<std::string>{"ZN", "HEP"}));
  const std::string note = stderrOfLastRun();
  EXPECT_NE(note.find("no relative SASA for 2 residue names"), std::string::npos) << note;
  EXPECT_NE(note.find("ZN, HEP"), std::string::npos) << note;

  const Result csv = tool("area --per residue --format csv " + kFab);
  ASSERT_EQ(csv.status, 0) << csv.output;
  const auto rows = csvRows(csv.output);
  ASSERT_FALSE(rows.empty());
  EXPECT_TRUE(rows.front().count("relative_sas_tien2013")) << csv.output.substr(0, 200);
}

// Insertion codes part residues: in 1A0Q, H 82, 82A, 82B and 82C are four residues (LEU, ASN,
// SER, LEU), and every residue of the file (its ATOM/HETATM lines but the waters, read here) is
// one row with its own atom count. The alternate location of each atom kept is the file's
// column 17 (1CBN, 276 atoms with alternates).
TEST(AreaPer, InsertionCodesAndAlternateLocationsHaveTheirOwnColumns) {
  const Result r = tool("area --per residue --format csv " + kFab);
  ASSERT_EQ(r.status, 0) << r.output;
  const auto rows = csvRows(r.output);
  std::vector<std::string> h82;
  for (const auto& row : rows)
    if (row.at("chain") == "H" && row.at("residue_number") == "82")
      h82.push_back(row.at("residue") + ":" + row.at("insertion_code"));
  EXPECT_EQ(h82, (std::vector<std::string>{"LEU:", "ASN:A", "SER:B", "LEU:C"}));

  std::map<std::string, int> fileResidues;  // "chain number icode name" -> atoms
  std::vector<std::string> order;
  for (const PdbAtom& a : pdbAtoms(kFab)) {
    if (a.residue == "HOH") continue;
    const std::string key = a.chain + " " + std::to_string(a.residueNumber) + " " +
                            (a.insertionCode == ' ' ? std::string() : std::string(1, a.insertionCode)) + " " + a.residue;
    if (!fileResidues.count(key)) order.push_back(key);
    ++fileResidues[key];
  }
  ASSERT_EQ(rows.size(), order.size());
  for (std::size_t k = 0; k < rows.size(); ++k) {
    const auto& row = rows[k];
    const std::string key =
        row.at("chain") + " " + row.at("residue_number") + " " + row.at("insertion_code") + " " + row.at("residue");
    EXPECT_EQ(key, order[k]);
    EXPECT_EQ(std::stoi(row.at("atoms")), fileResidues[order[k]]) << key;
  }

  const Result atoms = tool("area --per atom --format csv " + kCrambinAltLocs);
  ASSERT_EQ(atoms.status, 0) << atoms.output;
  std::map<int, PdbAtom> bySerial;
  for (const PdbAtom& a : pdbAtoms(kCrambinAltLocs)) bySerial[a.serial] = a;
  std::size_t withAltLoc = 0;
  for (const auto& row : csvRows(atoms.output)) {
    const PdbAtom& a = bySerial.at(std::stoi(row.at("serial")));
    EXPECT_EQ(row.at("altloc"), a.altLoc == ' ' ? std::string() : std::string(1, a.altLoc)) << row.at("serial");
    EXPECT_EQ(row.at("insertion_code"), a.insertionCode == ' ' ? std::string() : std::string(1, a.insertionCode));
    withAltLoc += a.altLoc != ' ';
  }
  EXPECT_GT(withAltLoc, 0u);
}

// A chain's areas are the sums of its atoms' rows (4HHB: chains A-D with their hemes), and the
// chains together are the whole surface's.
TEST(AreaPer, ChainTotalsAreSumsOfAtomAreas) {
  const Result atoms = tool("area --per atom --format csv " + kHaemoglobin);
  const Result chains = tool("area --per chain --format json " + kHaemoglobin);
  ASSERT_EQ(atoms.status, 0) << atoms.output;
  ASSERT_EQ(chains.status, 0) << chains.output;
  std::map<std::string, double> sas, ses;
  std::map<std::string, int> count;
  for (const auto& row : csvRows(atoms.output)) {
    sas[row.at("chain")] += std::stod(row.at("sas"));
    ses[row.at("chain")] += std::stod(row.at("ses"));
    ++count[row.at("chain")];
  }
  const json j = json::parse(chains.output);
  ASSERT_EQ(j["per_chain"].size(), 4u);
  double sasAll = 0.0, sesAll = 0.0;
  for (const json& c : j["per_chain"]) {
    const std::string id = c["chain"];
    EXPECT_EQ(c["atoms"].get<int>(), count[id]) << id;
    // The atoms' rows are printed to 1e-6 Å² each.
    EXPECT_NEAR(c["sas"].get<double>(), sas[id], 1e-6 * count[id]) << id;
    EXPECT_NEAR(c["ses"].get<double>(), ses[id], 1e-6 * count[id]) << id;
    sasAll += c["sas"].get<double>();
    sesAll += c["ses"].get<double>();
  }
  EXPECT_NEAR(sasAll, j["totals"]["sas"].get<double>(), 1e-9 * sasAll);
  EXPECT_NEAR(sesAll, j["totals"]["ses"].get<double>(), 1e-9 * sesAll);
}

// `area TOP TRAJ --per residue`: frame k's rows are `area --per residue` of model k + 1 read
// alone (its own process, a fresh build, no builder kept between frames).
TEST(AreaPer, TrajectoryRowsOfFrameKAreAreaOfThatFrameAlone) {
  const Result traj = tool("area " + kEnsemble + " " + kEnsemble + " --per residue --format csv");
  ASSERT_EQ(traj.status, 0) << traj.output;
  const auto rows = csvRows(traj.output);
  for (const int frame : {0, 4, 10}) {
    const Result alone = tool("area --model " + std::to_string(frame + 1) + " --per residue --format csv " + kEnsemble);
    ASSERT_EQ(alone.status, 0) << alone.output;
    const auto want = csvRows(alone.output);
    std::vector<std::map<std::string, std::string>> got;
    for (const auto& row : rows)
      if (row.at("frame") == std::to_string(frame)) got.push_back(row);
    ASSERT_EQ(got.size(), want.size()) << "frame " << frame;
    for (std::size_t k = 0; k < want.size(); ++k) {
      for (const char* text : {"chain", "residue", "residue_number", "insertion_code", "altloc", "atoms"})
        EXPECT_EQ(got[k].at(text), want[k].at(text)) << "frame " << frame << " row " << k;
      for (const char* number : {"sas", "ses", "relative_sas_tien2013"})
        if (!want[k].at(number).empty()) {
          EXPECT_NEAR(std::stod(got[k].at(number)), std::stod(want[k].at(number)), 2e-6)
              << "frame " << frame << " row " << k << " " << number;
        }
    }
  }
}

// What cannot be done is an error that says why and what to do: a preset on an XYZR file (no
// residue or atom names), a preset with --bead-radius, a --radii that is neither a preset nor a
// file, and rows per residue of a patch list (which holds no residues).
TEST(AreaPer, WhatCannotBeDoneIsAnErrorThatSaysWhy) {
  const std::string xyzr = (dir() / "two.xyzr").string();
  std::ofstream(xyzr) << "0 0 0 1.7\n3 0 0 1.5\n";
  const Result onXyzr = tool("area --radii protor " + xyzr);
  EXPECT_EQ(onXyzr.status, 1);
  EXPECT_NE(onXyzr.output.find(xyzr + ": an XYZR file gives its own radii and no atom names or elements, so --radii "
                                       "protor cannot apply"),
            std::string::npos)
      << onXyzr.output;
  const Result withBeads = tool("area --radii naccess --bead-radius 2.35 " + kCrambin);
  EXPECT_EQ(withBeads.status, 1);
  EXPECT_NE(withBeads.output.find("cannot be combined with --bead-radius (choose one)"), std::string::npos)
      << withBeads.output;
  const Result unknown = tool("area --radii protr " + kCrambin);
  EXPECT_NE(unknown.status, 0);
  EXPECT_NE(unknown.output.find("expected protor, naccess or a radius table file, got 'protr'"), std::string::npos)
      << unknown.output;
  const std::string stp = (dir() / "crambin.stp").string();
  ASSERT_EQ(tool("build " + kCrambin + " -o " + stp).status, 0);
  const Result perResidue = tool("area --per residue " + stp);
  EXPECT_EQ(perResidue.status, 1);
  EXPECT_NE(perResidue.output.find(stp + " is a patch list, which holds no residues or chains: run `area --per "
                                         "residue` on the structure it was built from"),
            std::string::npos)
      << perResidue.output;
}

}  // namespace
}  // namespace surftrace::tools::test

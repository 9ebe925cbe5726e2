// `--select` on every command that reads atoms: the surface of the selected atoms only, as if the
// file held no others (a file of just those lines, written here, is the oracle), and `info
// --atoms`, the selected atoms as a table, against MDAnalysis's reading of the same file.
#include <algorithm>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <functional>
#include <map>
#include <sstream>
#include <string>
#include <vector>

#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

#include "frame_buffers_equal.hpp"
#include "oracles/python_oracle.hpp"
#include "run_tool.hpp"
#include "temp_dir.hpp"
#include "view/image_io.hpp"

namespace {

namespace fs = std::filesystem;
using surftrace::tools::test::Result;
using surftrace::tools::test::runShell;
using surftrace::tools::test::runTool;

std::string data(const std::string& file) { return std::string(SURFTRACE_TEST_DATA) + "/" + file; }

fs::path scratch(const std::string& name) { return surftrace::test::freshTempDir("select_" + name); }

std::vector<std::string> readLines(const fs::path& path) {
  std::ifstream in(path);
  std::vector<std::string> lines;
  for (std::string line; std::getline(in, line);) lines.push_back(line);
  return lines;
}

bool isAtomLine(const std::string& line) { return line.rfind("ATOM  ", 0) == 0 || line.rfind("HETATM", 0) == 0; }
int residueNumber(const std::string& line) { return std::stoi(line.substr(22, 4)); }
std::string atomName(const std::string& line) {
  std::string name = line.substr(12, 4);
  name.erase(0, name.find_first_not_of(' '));
  name.erase(name.find_last_not_of(' ') + 1);
  return name;
}

// The lines of `lines` that `keep` keeps (other records: all of them), written to `path`: the
// file that holds only the atoms a selection means, by a reading of the PDB columns that
// shares no code with the selection's.
void writeCut(const fs::path& path, const std::vector<std::string>& lines,
              const std::function<bool(const std::string&)>& keep) {
  std::ofstream out(path);
  for (const std::string& line : lines)
    if (!isAtomLine(line) || keep(line)) out << line << "\n";
}

// 1CRN's residues 10-30 without their amide nitrogens: one selection, and its file.
const char* const kSelection = "resid 10-30 and not name N";
bool inSelection(const std::string& line) {
  return residueNumber(line) >= 10 && residueNumber(line) <= 30 && atomName(line) != "N";
}

nlohmann::json jsonOf(const Result& r) {
  EXPECT_EQ(r.status, 0) << r.output;
  const std::size_t start = r.output.find('{');
  if (start == std::string::npos) return {};
  return nlohmann::json::parse(r.output.substr(start), nullptr, false);
}

TEST(SelectCli, AreaOfASelectionIsTheAreaOfAFileOfItsAtoms) {
  const fs::path dir = scratch("area");
  const std::vector<std::string> lines = readLines(data("structures/1crn.pdb"));
  writeCut(dir / "cut.pdb", lines, inSelection);
  const std::string full = data("structures/1crn.pdb");
  const nlohmann::json selected = jsonOf(runTool("area " + full + " --select '" + kSelection + "' --format json"));
  const nlohmann::json cut = jsonOf(runTool("area " + (dir / "cut.pdb").string() + " --format json"));
  ASSERT_TRUE(selected.is_object() && cut.is_object());
  std::size_t atoms = 0;
  for (const std::string& line : lines) atoms += isAtomLine(line) && inSelection(line);
  EXPECT_EQ(selected["atoms"], atoms);
  EXPECT_LT(atoms, 327u / 2);
  // The same atoms in the same order: the same surface, to the last bit.
  for (const char* surface : {"sas", "ses"}) {
    EXPECT_EQ(selected[surface]["total"], cut[surface]["total"]) << surface;
    EXPECT_EQ(selected[surface]["per_atom"], cut[surface]["per_atom"]) << surface;
  }
  EXPECT_EQ(selected["ses"]["volume"], cut["ses"]["volume"]);
  // The whole crambin's area is another.
  const nlohmann::json whole = jsonOf(runTool("area " + full + " --format json"));
  EXPECT_NE(whole["ses"]["total"], selected["ses"]["total"]);

  // Per atom, `atom` is the place in the file (from 0), as `index` in a selection: the rows of
  // the ATOM lines kept.
  const Result csv = runTool("area " + full + " --select '" + kSelection + "' --format csv");
  ASSERT_EQ(csv.status, 0) << csv.output;
  std::vector<std::string> want;
  std::size_t index = 0;
  for (const std::string& line : lines) {
    if (!isAtomLine(line)) continue;
    if (inSelection(line)) want.push_back(std::to_string(index) + "," + std::to_string(std::stoi(line.substr(6, 5))));
    ++index;
  }
  std::vector<std::string> got;
  std::istringstream rows(csv.output);
  std::string row;
  std::getline(rows, row);  // header
  while (std::getline(rows, row)) {
    const std::size_t second = row.find(',', row.find(',') + 1);
    got.push_back(row.substr(0, second));
  }
  EXPECT_EQ(got, want);
}

TEST(SelectCli, BuildOfASelectionIsTheBuildOfAFileOfItsAtoms) {
  const fs::path dir = scratch("build");
  writeCut(dir / "cut.pdb", readLines(data("structures/1crn.pdb")), inSelection);
  const std::string a = (dir / "selected.stp").string(), b = (dir / "cut.stp").string();
  ASSERT_EQ(runTool("build " + data("structures/1crn.pdb") + " --select '" + kSelection + "' -o " + a).status, 0);
  ASSERT_EQ(runTool("build " + (dir / "cut.pdb").string() + " -o " + b).status, 0);
  const nlohmann::json ia = jsonOf(runTool("info " + a + " --json")), ib = jsonOf(runTool("info " + b + " --json"));
  EXPECT_EQ(ia["atoms"], ib["atoms"]);
  EXPECT_EQ(ia["patches"], ib["patches"]);
  const nlohmann::json aa = jsonOf(runTool("area " + a + " --format json")), ab = jsonOf(runTool("area " + b + " --format json"));
  EXPECT_EQ(aa["ses"]["total"], ab["ses"]["total"]);
  EXPECT_EQ(aa["ses"]["per_atom"], ab["ses"]["per_atom"]);
}

TEST(SelectCli, RenderOfASelectionIsTheRenderOfAFileOfItsAtoms) {
  const fs::path dir = scratch("render");
  writeCut(dir / "cut.pdb", readLines(data("structures/1crn.pdb")), inSelection);
  const std::string a = (dir / "selected.exr").string(), b = (dir / "cut.exr").string();
  const std::string common = " --size 96x96 --color element --quiet --exr ";
  ASSERT_EQ(runTool("render " + data("structures/1crn.pdb") + " --select '" + kSelection + "'" + common + a).status, 0);
  ASSERT_EQ(runTool("render " + (dir / "cut.pdb").string() + common + b).status, 0);
  surftrace::view::ImageMetadata ma, mb;
  const auto fa = surftrace::view::readExr(a, &ma), fb = surftrace::view::readExr(b, &mb);
  EXPECT_EQ(ma.at("surftrace:camera"), mb.at("surftrace:camera"));
  surftrace::test::expectSameBuffers(fa, fb, "render --select");
  std::size_t covered = 0;
  for (auto k : fa.kind) covered += k != 0;
  EXPECT_GT(covered, fa.pixels() / 10);
}

// A trajectory whose topology is its own first model (a multi-model PDB): the frames of a
// selection are the frames of a file of its atoms.
TEST(SelectCli, TrajectoryOfASelectionIsTheTrajectoryOfAFileOfItsAtoms) {
  const fs::path dir = scratch("trajectory");
  ASSERT_EQ(runShell("zcat " + data("ensembles/1grm_elNemo_mode7.pdb.gz") + " > " + (dir / "full.pdb").string()).status,
            0);
  const auto keep = [](const std::string& line) { return residueNumber(line) >= 1 && residueNumber(line) <= 8; };
  writeCut(dir / "cut.pdb", readLines(dir / "full.pdb"), keep);
  const std::string full = (dir / "full.pdb").string(), cut = (dir / "cut.pdb").string();
  const std::string common = " --frames 0:11:5 --size 64x64 --quiet --exr ";
  const Result a = runTool("trajectory " + full + " " + full + " --select 'resid 1-8'" + common +
                           (dir / "selected_%02d.exr").string());
  ASSERT_EQ(a.status, 0) << a.output;
  const Result b = runTool("trajectory " + cut + " " + cut + common + (dir / "cut_%02d.exr").string());
  ASSERT_EQ(b.status, 0) << b.output;
  for (const char* frame : {"00", "05", "10"}) {
    const auto fa = surftrace::view::readExr((dir / ("selected_" + std::string(frame) + ".exr")).string());
    const auto fb = surftrace::view::readExr((dir / ("cut_" + std::string(frame) + ".exr")).string());
    surftrace::test::expectSameBuffers(fa, fb, std::string("frame ") + frame);
  }
}

// `info --atoms`: the atoms MDAnalysis's select_atoms picks, each with the fields MDAnalysis
// reads (tests/oracles/mda_select.py, mda_atoms.py), chains and segment ids apart.
TEST(SelectCli, InfoAtomsListsWhatMDAnalysisSelects) {
  struct Case {
    const char* file;
    const char* selection;
  };
  for (const Case& c : {Case{"small/tiny.pdb", "segid E or (chain C and name C*)"},
                        Case{"formats/gro/ubiquitin.gro", "segid SYSTEM and resid 1-3 and not name H*"},
                        Case{"small/helix_amber.pdb", "chain B and resid 1-4"}}) {
    SCOPED_TRACE(c.file);
    const fs::path dir = scratch("info_atoms");
    const auto picked = surftrace::test::runOracleScript("mda_select.py", {data(c.file), c.selection}, dir);
    ASSERT_TRUE(picked.ok()) << picked.describe();
    const auto atoms = surftrace::test::runOracleScript("mda_atoms.py", {data(c.file)}, dir);
    ASSERT_TRUE(atoms.ok()) << atoms.describe();
    std::map<std::string, std::vector<std::string>> fields;  // by index
    std::istringstream rows(atoms.out);
    for (std::string row; std::getline(rows, row);) {
      std::vector<std::string> f;
      std::istringstream cells(row);
      for (std::string cell; std::getline(cells, cell, '\t');) f.push_back(cell == "-" ? "" : cell);
      fields[f[0]] = f;
    }
    std::istringstream lines(picked.out);
    std::string count, selected;
    std::getline(lines, count);
    std::getline(lines, selected);
    std::vector<std::string> want;
    std::istringstream indices(selected);
    for (std::string i; indices >> i;) {
      const std::vector<std::string>& f = fields.at(i);
      // index serial name resname chain segid resid icode altloc (GRO: no chain, icode, altloc)
      want.push_back(f[0] + "," + f[1] + "," + f[2] + "," + f[3] + "," + f[4] + "," + f[5] + "," +
                     f[6] + "," + f[7] + "," + f[8]);
    }
    ASSERT_FALSE(want.empty());
    const Result csv =
        runTool("info " + data(c.file) + " --keep-water --select '" + c.selection + "' --atoms --format csv");
    ASSERT_EQ(csv.status, 0) << csv.output;
    std::istringstream out(csv.output);
    std::string header;
    std::getline(out, header);
    EXPECT_EQ(header, "index,serial,name,resname,chain,segid,resid,icode,altloc,element,x,y,z,radius");
    std::vector<std::string> got;
    for (std::string row; std::getline(out, row);) {
      std::size_t at = 0;
      for (int k = 0; k < 9; ++k) at = row.find(',', at) + 1;
      got.push_back(row.substr(0, at - 1));
    }
    EXPECT_EQ(got, want);

    // The same rows as JSON and as the table.
    const nlohmann::json j =
        jsonOf(runTool("info " + data(c.file) + " --keep-water --select '" + c.selection + "' --atoms --format json"));
    ASSERT_EQ(j["atoms"].size(), want.size());
    EXPECT_EQ(j["selection"], c.selection);
    for (std::size_t k = 0; k < want.size(); ++k)
      EXPECT_EQ(std::to_string(j["atoms"][k]["index"].get<std::size_t>()), want[k].substr(0, want[k].find(',')));
    const Result table = runTool("info " + data(c.file) + " --keep-water --select '" + c.selection + "' --atoms");
    ASSERT_EQ(table.status, 0);
    EXPECT_EQ(static_cast<std::size_t>(std::count(table.output.begin(), table.output.end(), '\n')), want.size() + 1);
    EXPECT_EQ(table.output.rfind("  index  serial name  resname chain segid", 0), 0u) << table.output;
  }
}

TEST(SelectCli, InfoSaysWhatWasSelected) {
  const Result r = runTool("info " + data("structures/1crn.pdb") + " --select '" + kSelection + "' --json");
  const nlohmann::json j = jsonOf(r);
  EXPECT_EQ(j["selection"], kSelection);
  EXPECT_EQ(j["skipped"]["unselected"], 327 - j["atoms"].get<int>());
  const Result text = runTool("info " + data("structures/1crn.pdb") + " --select 'resid 1'");
  EXPECT_NE(text.output.find("selection  'resid 1': 7 atoms"), std::string::npos) << text.output;
  EXPECT_NE(text.output.find("320 atoms outside --select"), std::string::npos) << text.output;
}

TEST(SelectCli, SelectionsThatCannotApplyAreErrorsNamingThem) {
  const std::string crambin = data("structures/1crn.pdb");
  const fs::path dir = scratch("errors");
  for (const char* command : {"info", "area", "build", "render"}) {
    const std::string out = std::string(command) == "build"    ? " -o " + (dir / "x.stp").string()
                            : std::string(command) == "render" ? " -o " + (dir / "x.png").string()
                                                               : "";
    const Result r = runTool(std::string(command) + " " + crambin + " --select 'resname HEM'" + out);
    EXPECT_EQ(r.status, 1) << command;
    EXPECT_NE(r.output.find(crambin + ": selection 'resname HEM' selects no atom (the molecule has residue names"),
              std::string::npos)
        << command << ": " << r.output;
  }
  const Result empty = runTool("area " + crambin + " --select ''");
  EXPECT_EQ(empty.status, 1);
  EXPECT_NE(empty.output.find("the atom selection is empty"), std::string::npos) << empty.output;
  const Result typo = runTool("area " + crambin + " --select 'resname ALA adn name CA'");
  EXPECT_EQ(typo.status, 1);
  EXPECT_NE(typo.output.find("at word 4 'name': needs 'and' or 'or' before it"), std::string::npos) << typo.output;
  const Result traj = runTool("trajectory " + data("trajectories/adk_dims/adk.psf.gz") + " " +
                              data("trajectories/adk_dims/adk_dims.dcd") + " --select 'segid XYZ' -o " + (dir / "%05d.png").string());
  EXPECT_EQ(traj.status, 1);
  EXPECT_NE(traj.output.find("selection 'segid XYZ' selects no atom (the molecule has segids '4AKE')"),
            std::string::npos)
      << traj.output;

  // A patch list holds no atom records to select from.
  const std::string stp = (dir / "crambin.stp").string();
  ASSERT_EQ(runTool("build " + crambin + " -o " + stp).status, 0);
  for (const char* command : {"info", "area", "render"}) {
    const Result r = runTool(std::string(command) + " " + stp + " --select 'resid 1'" +
                             (std::string(command) == "render" ? " -o " + (dir / "x.png").string() : ""));
    EXPECT_EQ(r.status, 1) << command;
    EXPECT_NE(r.output.find("--select needs the structure file"), std::string::npos) << command << ": " << r.output;
  }
  const Result csv = runTool("info " + crambin + " --format csv");
  EXPECT_EQ(csv.status, 1);
  EXPECT_NE(csv.output.find("add --atoms"), std::string::npos) << csv.output;
}

}  // namespace

// `surftrace info`: what a structure file holds and what reading it left out.
#include <algorithm>
#include <charconv>
#include <chrono>
#include <cstdio>
#include <limits>
#include <map>
#include <memory>
#include <sstream>
#include <utility>
#include <vector>

#include <glm/common.hpp>
#include <nlohmann/json.hpp>

#include "commands.hpp"
#include "option_checks.hpp"
#include "surftrace/files.hpp"
#include "surftrace/image.hpp"
#include "surftrace/molecule.hpp"
#include "surftrace/surface.hpp"

namespace surftrace::tools {

void addMoleculeOptions(CLI::App& cmd, build::ReadOptions& options) {
  auto* group = &cmd;
  group->add_option("--model", options.model, "Model (PDB/mmCIF) or frame (XYZ) to read, 1-based")
      ->check(wholeIn(1, HUGE_VAL))
      ->default_val(1);
  group->add_flag("--keep-water", options.keepWater, "Keep water molecules (dropped by default)");
  group->add_flag("!--no-hydrogens", options.keepHydrogens, "Drop hydrogen and deuterium atoms");
  group->add_option("--chains", options.chains, "Keep only these chains, e.g. --chains A,B")->delimiter(',');
  group->add_option("--select", options.selection,
                    "Only these atoms (the others are not there), in MDAnalysis's selection language: name, resname, "
                    "resid, chain (chainID), segid, element, index (from 0, in the file), atom (from 1; bynum), "
                    "protein, backbone, water, all; several values (resid 10-20 45, name CA CB, name H*); not, then "
                    "and/or left to right, parentheses, e.g. 'protein and not name H*' or 'not resname HEM'; applied "
                    "after --keep-water, --no-hydrogens and --chains. A selection that selects no atom is an error");
  group
      ->add_option_function<std::string>(
          "--radii",
          [&options](const std::string& value) {
            // A preset's name wins over a file of that name (give such a file as ./protor).
            if (const auto preset = build::radiusPresetNamed(value)) options.radiiPreset = preset;
            else options.radiiFile = value;
          },
          "protor or naccess: FreeSASA's radii by residue and atom name (its --radii=protor|naccess; atoms they "
          "do not name get FreeSASA's element guess); or a radius table FILE overriding the default radii (Bondi, "
          "then Mantina, then Alvarez): lines 'ELEMENT r' or 'RES:ATOM r', '#' comments; elements not in it keep "
          "their default radius")
      ->check(CLI::Validator(
          [](std::string& value) -> std::string {
            if (build::radiusPresetNamed(value) || CLI::ExistingFile(value).empty()) return {};
            return "expected protor, naccess or a radius table file, got '" + value + "', which is neither a preset "
                   "nor an existing file";
          },
          "protor|naccess|FILE"));
  group->add_option("--default-radius", options.defaultRadius,
                    "Radius (Å) for elements with no known radius; without it they are an error")
      ->check(positive());
  group->add_option("--bead-radius", options.beadRadius,
                    "Coarse-grained systems (MARTINI): every particle one sphere of this radius (Å), "
                    "no elements guessed from bead names; 'RES:ATOM r' lines of --radii still win, and "
                    "MARTINI waters (W, WF, PW) are water")
      ->check(positive());
  group->add_flag("--drop-zero-radius", options.dropZeroRadius,
                  "Drop atoms whose file gives radius 0 (PQR hydrogens) instead of stopping with an error");
  using build::MoleculeFormat;
  group->add_option("--input-format", options.format, "Input format (default: from the file name)")
      ->transform(namedValue<MoleculeFormat>({{"auto", MoleculeFormat::Auto},
                                              {"pdb", MoleculeFormat::Pdb},
                                              {"mmcif", MoleculeFormat::Mmcif},
                                              {"cif", MoleculeFormat::Mmcif},
                                              {"pqr", MoleculeFormat::Pqr},
                                              {"xyzr", MoleculeFormat::Xyzr},
                                              {"xyz", MoleculeFormat::Xyz},
                                              {"gro", MoleculeFormat::Gro},
                                              {"psf", MoleculeFormat::Psf}}));
}

namespace {

struct InfoOptions {
  std::string path;
  build::ReadOptions read;
  bool json = false;
  std::string format = "table";  // table, csv, json (--json is json)
  bool atoms = false;            // --atoms: the atoms themselves, one row each
  std::string xyzr;  // --xyzr OUT: the atoms as every command uses them
};

// --atoms: one row per atom as every command uses it (after --select and the other choices), in
// the file's order. `index` is the atom's place in the file from 0 (MDAnalysis's index, what
// `--select 'index N'` means), not its row: a user compares it with the file.
void printAtoms(const build::Molecule& m, const std::string& format) {
  const auto code = [](char c) { return c == ' ' ? std::string() : std::string(1, c); };
  if (format == "json") {
    nlohmann::json atoms = nlohmann::json::array();
    for (std::size_t i = 0; i < m.size(); ++i) {
      const build::AtomRecord& a = m.atoms[i];
      atoms.push_back({{"index", a.fileIndex},      {"serial", a.serial},       {"name", a.name},
                       {"resname", a.residue},      {"chain", a.chain},         {"segid", a.segid},
                       {"resid", a.residueNumber},  {"icode", code(a.insertionCode)}, {"altloc", code(a.altLoc)},
                       {"element", a.element},      {"x", m.centers[i].x},      {"y", m.centers[i].y},
                       {"z", m.centers[i].z},       {"radius", m.radii[i]}});
    }
    nlohmann::json j = {{"file", m.source}, {"atoms", atoms}};
    if (m.selection) j["selection"] = *m.selection;
    std::printf("%s\n", j.dump(1).c_str());
    return;
  }
  const bool csv = format == "csv";
  if (csv)
    std::printf("index,serial,name,resname,chain,segid,resid,icode,altloc,element,x,y,z,radius\n");
  else
    std::printf("%7s %7s %-5s %-7s %-5s %-6s %6s %-5s %-6s %-7s %10s %10s %10s %7s\n", "index", "serial", "name",
                "resname", "chain", "segid", "resid", "icode", "altloc", "element", "x", "y", "z", "radius");
  for (std::size_t i = 0; i < m.size(); ++i) {
    const build::AtomRecord& a = m.atoms[i];
    const glm::dvec3& c = m.centers[i];
    // CSV: names never hold commas in these formats (PDB columns, whitespace-separated tokens).
    if (csv)
      std::printf("%zu,%d,%s,%s,%s,%s,%d,%s,%s,%s,%.3f,%.3f,%.3f,%.4f\n", a.fileIndex, a.serial, a.name.c_str(),
                  a.residue.c_str(), a.chain.c_str(), a.segid.c_str(), a.residueNumber, code(a.insertionCode).c_str(),
                  code(a.altLoc).c_str(), a.element.c_str(), c.x, c.y, c.z, m.radii[i]);
    else
      std::printf("%7zu %7d %-5s %-7s %-5s %-6s %6d %-5s %-6s %-7s %10.3f %10.3f %10.3f %7.3f\n", a.fileIndex, a.serial,
                  a.name.c_str(), a.residue.c_str(), a.chain.empty() ? "-" : a.chain.c_str(),
                  a.segid.empty() ? "-" : a.segid.c_str(), a.residueNumber,
                  a.insertionCode == ' ' ? "-" : code(a.insertionCode).c_str(),
                  a.altLoc == ' ' ? "-" : code(a.altLoc).c_str(), a.element.empty() ? "-" : a.element.c_str(), c.x,
                  c.y, c.z, m.radii[i]);
    build::checkStandardOutput();  // a reader that stopped early (| head) ends the command here
  }
}

// The atoms as every command uses them (after the water, hydrogen, chain and model choices,
// duplicates and radii), one "x y z r" line each in the fewest digits that read back to the
// same doubles: an outside renderer given this file draws exactly the spheres SurfTrace does.
void writeXyzr(const std::string& path, const build::Molecule& m) {
  std::string text;
  text.reserve(m.size() * 48);
  char number[32];
  const auto put = [&](double v, char after) {
    const auto end = std::to_chars(number, number + sizeof number, v).ptr;
    text.append(number, end).push_back(after);
  };
  for (std::size_t i = 0; i < m.size(); ++i) {
    put(m.centers[i].x, ' ');
    put(m.centers[i].y, ' ');
    put(m.centers[i].z, ' ');
    put(m.radii[i], '\n');
  }
  build::writeFileAtomically(path, text);
}

std::string fixed(double v, int digits = 3) {
  char buf[64];
  std::snprintf(buf, sizeof buf, "%.*f", digits, v);
  return buf;
}

// A patch list holds no atom records: say what it was built from and what it holds, by patch
// kind (view::kPatchKinds: the SES's and the skin's alike).
void runPatchListInfo(const InfoOptions& o) {
  const build::PatchList p = readingFile(o.path, "the patch list", [&] { return build::readPatchList(o.path); });
  const bool skin = p.params.surface == build::SurfaceKind::Mss;
  if (o.json) {
    nlohmann::json j;
    j["file"] = o.path;
    j["format"] = "SurfTrace patch list";
    j["surface"] = build::surfaceKindName(p.params.surface);
    j["probe_radius"] = p.params.probeRadius;
    if (skin) j["shrink_factor"] = p.params.shrinkFactor;
    j["atoms"] = p.params.atomCount;
    j["input_crc32"] = p.params.inputCrc32;
    j["radii"] = {{"set", p.params.radiiSet}};
    nlohmann::json patches = nlohmann::json::object();
    for (const view::PatchKindInfo& k : view::kPatchKinds)
      if (const std::size_t n = view::patchCount(p, k.kind); n > 0 || !skin) {
        if (skin || k.kind == view::PatchKind::Convex || k.kind == view::PatchKind::Toroidal ||
            k.kind == view::PatchKind::Concave)
          patches[k.name] = n;
      }
    patches["clip_planes"] = p.clipPlanes.size();
    if (skin) patches["cell_planes"] = p.cellPlanes.size();
    j["patches"] = patches;
    j["components"] = p.componentCount;
    std::printf("%s\n", j.dump(2).c_str());
    return;
  }
  if (skin)
    std::printf("file       %s (SurfTrace patch list, %s surface, shrink factor %.3f)\n", o.path.c_str(),
                build::surfaceKindName(p.params.surface), p.params.shrinkFactor);
  else
    std::printf("file       %s (SurfTrace patch list, %s surface, probe %.3f Å)\n", o.path.c_str(),
                build::surfaceKindName(p.params.surface), p.params.probeRadius);
  std::printf("built from %u atoms (input CRC-32 %x, radii %s)\n", p.params.atomCount, p.params.inputCrc32,
              p.params.radiiSet.c_str());
  if (!skin) {
    std::printf("patches    %zu convex, %zu toroidal, %zu concave, %zu clipping planes; %u components\n",
                p.convex.size(), p.tori.size(), p.concave.size(), p.clipPlanes.size(), p.componentCount);
    return;
  }
  std::string counts;
  for (const view::PatchKindInfo& k : view::kPatchKinds)
    if (const std::size_t n = view::patchCount(p, k.kind); n > 0)
      counts += (counts.empty() ? "" : ", ") + std::to_string(n) + " " + k.name;
  std::printf("patches    %s; %zu mixed-cell planes\n", counts.empty() ? "none" : counts.c_str(), p.cellPlanes.size());
}

// What `info` says of a molecule beyond its records: counts, extent, radii and their sources.
struct MoleculeSummary {
  std::map<std::string, std::size_t> elements, chains;
  std::size_t hetatm = 0, residues = 0;
  glm::dvec3 lo{std::numeric_limits<double>::infinity()}, hi{-std::numeric_limits<double>::infinity()};
  double rMin = std::numeric_limits<double>::infinity(), rMax = 0, rMean = 0;
  // Sources in table order, only those that gave some atom a radius.
  std::vector<std::pair<std::string, std::size_t>> sources;
};

MoleculeSummary summarise(const build::Molecule& m) {
  MoleculeSummary u;
  double rSum = 0;
  // Looked up once per run of atoms of one element or chain: building a residue key and
  // searching the maps for every atom was a tenth of `info` on a million atoms.
  auto element = u.elements.end(), chain = u.chains.end();
  for (std::size_t i = 0; i < m.size(); ++i) {
    const auto& a = m.atoms[i];
    const bool sameChain = i > 0 && a.chain == m.atoms[i - 1].chain;
    if (i == 0 || a.element != m.atoms[i - 1].element) element = u.elements.try_emplace(a.element, 0).first;
    if (!sameChain) chain = u.chains.try_emplace(a.chain, 0).first;
    ++element->second;
    ++chain->second;
    u.hetatm += a.hetatm;
    if (i == 0 || !sameChain || a.residueNumber != m.atoms[i - 1].residueNumber ||
        a.insertionCode != m.atoms[i - 1].insertionCode || a.residue != m.atoms[i - 1].residue)
      ++u.residues;
    u.lo = glm::min(u.lo, m.centers[i]);
    u.hi = glm::max(u.hi, m.centers[i]);
    u.rMin = std::min(u.rMin, m.radii[i]);
    u.rMax = std::max(u.rMax, m.radii[i]);
    rSum += m.radii[i];
  }
  u.rMean = rSum / static_cast<double>(m.size());
  for (std::size_t k = 0; k < build::kRadiusSourceCount; ++k)
    if (m.radiusSources[k] != 0)
      u.sources.emplace_back(build::radiusSourceName(static_cast<build::RadiusSource>(k)), m.radiusSources[k]);
  return u;
}

void printMoleculeJson(const build::Molecule& m, const MoleculeSummary& u, double seconds) {
  const auto& s = m.skipped;
  nlohmann::json j;
  j["file"] = m.source;
  j["format"] = build::formatName(m.format);
  j["crc32"] = m.inputCrc32;
  j["models"] = m.modelCount;
  j["model_used"] = m.modelUsed;
  j["atoms"] = m.size();
  j["hetatm"] = u.hetatm;
  j["residues"] = u.residues;
  j["chains"] = u.chains;
  j["elements"] = u.elements;
  j["bbox"] = {{"min", {u.lo.x, u.lo.y, u.lo.z}}, {"max", {u.hi.x, u.hi.y, u.hi.z}}};
  nlohmann::json bySource = nlohmann::json::object();
  for (const auto& [name, n] : u.sources) bySource[name] = n;
  j["radii"] = {{"set", m.radiiSet}, {"min", u.rMin}, {"mean", u.rMean}, {"max", u.rMax}, {"sources", bySource}};
  j["skipped"] = {{"water", s.water},          {"hydrogens", s.hydrogens},       {"alt_locs", s.altLocs},
                  {"other_chains", s.otherChains}, {"other_models", s.otherModels}, {"default_radius", s.defaultRadius},
                  {"water_virtual_sites", s.virtualSites}, {"duplicates", s.duplicates}, {"unselected", s.unselected}};
  if (m.selection) j["selection"] = *m.selection;
  j["elements_guessed"] = {{"from_atom_names", m.elementsFromNames}, {"from_masses", m.elementsFromMasses}};
  if (m.beadRadius)
    j["coarse_grained"] = {{"martini", m.martini}, {"beads", m.size()}, {"bead_radius", *m.beadRadius}};
  j["notes"] = m.notes;
  j["read_seconds"] = seconds;
  std::printf("%s\n", j.dump(2).c_str());
}

// The "skipped" and "notes" lines of the text summary.
void printSkipped(std::ostringstream& out, const build::Molecule& m) {
  const auto& s = m.skipped;
  out << "\nskipped    ";
  bool any = false;
  auto note = [&](std::size_t n, const char* what) {
    if (n == 0) return;
    out << (any ? "; " : "") << n << " " << what;
    any = true;
  };
  note(s.water, "water atoms (--keep-water keeps them)");
  note(s.hydrogens, "hydrogens (--no-hydrogens)");
  note(s.altLocs, "alternate-conformer atoms (kept the first/highest-occupancy one)");
  note(s.otherChains, "atoms of other chains (--chains)");
  note(s.otherModels, "atoms of other models (--model)");
  note(s.virtualSites, "massless water sites (TIP4P MW, TIP5P LP)");
  note(s.duplicates, "atoms exactly on an earlier atom of the same radius");
  note(s.unselected, "atoms outside --select");
  if (!any) out << "nothing";
  out << "\n";
  for (std::size_t k = 0; k < m.notes.size(); ++k) out << (k ? "           " : "notes      ") << m.notes[k] << "\n";
}

void printMoleculeText(const build::Molecule& m, const MoleculeSummary& u, double seconds) {
  const glm::dvec3 &lo = u.lo, &hi = u.hi;
  std::ostringstream out;
  out << "file       " << m.source << " (" << build::formatName(m.format) << ", CRC-32 " << std::hex << m.inputCrc32
      << std::dec << ", read in " << fixed(seconds * 1e3, 1) << " ms)\n";
  out << "models     " << m.modelCount << " (using model " << m.modelUsed << ")\n";
  out << "atoms      " << m.size() << " (" << u.hetatm << " HETATM) in " << u.residues << " residues\n";
  if (m.selection) out << "selection  '" << *m.selection << "': " << m.size() << " atoms\n";
  out << "chains     " << u.chains.size() << ":";
  for (const auto& [c, n] : u.chains) out << " " << (c.empty() ? "-" : c) << " (" << n << ")";
  out << "\nelements   ";
  for (const auto& [e, n] : u.elements) out << (e.empty() ? "none" : e) << " " << n << "  ";
  out << "\n           elements guessed: " << m.elementsFromNames << " from atom names, " << m.elementsFromMasses
      << " from masses";
  if (m.beadRadius)
    out << "\n" << (m.martini ? "MARTINI coarse-grained: " : "coarse-grained: ") << m.size()
        << (m.martini ? " beads" : " particles") << ", radius " << fixed(*m.beadRadius, 2) << " Å (--bead-radius)";
  out << "\nbbox       min (" << fixed(lo.x) << ", " << fixed(lo.y) << ", " << fixed(lo.z) << ")  max (" << fixed(hi.x)
      << ", " << fixed(hi.y) << ", " << fixed(hi.z) << ")  size " << fixed(hi.x - lo.x, 1) << " x "
      << fixed(hi.y - lo.y, 1) << " x " << fixed(hi.z - lo.z, 1) << " Å\n";
  out << "radii      " << m.radiiSet << ": min " << fixed(u.rMin, 2) << ", mean " << fixed(u.rMean, 2) << ", max "
      << fixed(u.rMax, 2) << " Å";
  out << "\n           from";
  for (std::size_t k = 0; k < u.sources.size(); ++k)
    out << (k ? ", " : " ") << u.sources[k].first << " " << u.sources[k].second
        << (u.sources[k].second == 1 ? " atom" : " atoms");
  printSkipped(out, m);
  std::fputs(out.str().c_str(), stdout);
}

void runInfo(InfoOptions o) {
  if (o.json) o.format = "json";
  if (o.format == "csv" && !o.atoms)
    throw std::invalid_argument("--format csv is a table of atoms: add --atoms (the summary is table or json)");
  if (isPatchListPath(o.path) && (o.atoms || o.read.selection))
    throw std::invalid_argument(std::string(o.atoms ? "--atoms" : "--select") + " needs the structure file: " + o.path +
                                " is a patch list, which holds no atom records");
  if (!o.xyzr.empty()) {
    if (isPatchListPath(o.path))
      throw std::invalid_argument("--xyzr needs the structure file: " + o.path + " is a patch list, which holds no atoms");
    build::prepareOutputPath(o.xyzr, "--xyzr");
  }
  if (isPatchListPath(o.path)) return runPatchListInfo(o);
  const auto start = std::chrono::steady_clock::now();
  const build::Molecule m = readingFile(o.path, "the atoms", [&] { return build::readMolecule(o.path, o.read); });
  if (!o.xyzr.empty()) writeXyzr(o.xyzr, m);
  const double seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  if (o.atoms) return printAtoms(m, o.format);
  const MoleculeSummary summary = summarise(m);
  if (o.format == "json")
    printMoleculeJson(m, summary, seconds);
  else
    printMoleculeText(m, summary, seconds);
}

}  // namespace

void printReadNotes(const build::Molecule& molecule) {
  for (const std::string& note : molecule.notes)
    std::fprintf(stderr, "surftrace: note: %s: %s\n", molecule.source.c_str(), note.c_str());
}

void addInfoCommand(CLI::App& app) {
  auto o = std::make_shared<InfoOptions>();
  auto* cmd = app.add_subcommand("info",
                                 "Summarise a structure file: atoms, chains, models, elements, bounding box, "
                                 "radius statistics, and what was skipped and why");
  cmd->add_option("FILE", o->path,
                  "Structure file (PDB, mmCIF, PQR, XYZR, XYZ; .gz allowed) or a patch list from `build` (.stp)")
      ->required();
  addMoleculeOptions(*cmd, o->read);
  cmd->add_flag("--json", o->json, "Print the summary as JSON (--format json)");
  cmd->add_flag("--atoms", o->atoms,
                "Print the atoms instead of the summary, one row each as every command uses them (after --select "
                "and the other choices): index (from 0, the place in the file), serial, name, resname, chain, "
                "segid, resid, icode, altloc, element, x, y, z, radius");
  cmd->add_option("--format", o->format, "Output: table, csv (with --atoms), json")
      ->check(CLI::IsMember({"table", "csv", "json"}))
      ->default_val("table");
  cmd->add_option("--xyzr", o->xyzr,
                  "Also write the atoms as every command uses them (after the water, hydrogen, chain, model and "
                  "radius choices) to this file, one 'x y z r' line each, exactly (shortest round-trip digits), "
                  "so that another renderer draws the same spheres; - for the standard output (the summary then "
                  "goes to the standard error)");
  cmd->callback([o] { runInfo(*o); });
}

}  // namespace surftrace::tools

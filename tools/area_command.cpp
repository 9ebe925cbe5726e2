// `surftrace area`: exact areas and volumes of the SES (by patch kind, per atom, per component)
// and of the skin, for a structure, a patch list, or every frame of a trajectory.
#include <chrono>
#include <cstdio>
#include <algorithm>
#include <memory>
#include <stdexcept>
#include <string>
#include <tuple>
#include <vector>

#include <nlohmann/json.hpp>

#include "area_groups.hpp"
#include "commands.hpp"
#include "progress_bar.hpp"
#include "surface_input.hpp"
#include "surftrace/files.hpp"
#include "surftrace/molecule.hpp"
#include "surftrace/surface.hpp"
#include "trajectory_plan.hpp"

namespace surftrace::tools {
namespace {

struct AreaOptions : SurfaceInputOptions {
  std::string format = "table";
  std::string trajectory;  // FILE is then its topology: one row per frame
  std::string frames;
  std::string per;  // --per atom|residue|chain; empty: the totals (table), per atom (csv)
  bool cavities = false;  // --cavities: each cavity located instead of the areas
};

// One CSV row per atom: who it is (insertion code and alternate location included), its radius,
// then the named per-atom columns (Å²).
void printPerAtomCsv(const build::Molecule& m, std::vector<AreaColumn> columns) {
  const AreaRows rows{AreaLevel::Atom, "csv", std::move(columns), false};
  rows.printHeader();
  rows.printRows(m, {});
}

// The per-atom columns of a surface's areas: the SES's SAS and SES, or the skin's.
std::vector<AreaColumn> areaColumns(const SurfaceAreas& a) {
  if (a.surface == build::SurfaceKind::Ses) return {{"sas", &a.sasPerAtom}, {"ses", &a.perAtom}};
  return {{"mss", &a.perAtom}};
}

// What a relative column left empty, and a probe other than the table's, said once on the
// standard error (a CSV has no room for it).
void noteRelativeSas(const AreaRows& rows, const std::vector<AreaGroup>& groups, const std::string& file, double probe) {
  if (!rows.relative()) return;
  std::fflush(stdout);  // after the rows, where a terminal shows both
  if (probe != 1.4)
    std::fprintf(stderr,
                 "surftrace: note: %s: the relative SASA divides by maxima computed with a 1.4 Å probe (%s); with "
                 "probe %g Å it is not a fraction of the residue's largest possible SAS\n",
                 file.c_str(), kMaxAsaTable, probe);
  const std::vector<std::string> names = residuesWithoutMaxAsa(groups);
  if (names.empty()) return;
  std::string list;
  for (std::size_t k = 0; k < names.size() && k < 8; ++k) list += (k ? ", " : "") + (names[k].empty() ? "(unnamed)" : names[k]);
  if (names.size() > 8) list += ", ...";
  std::fprintf(stderr,
               "surftrace: note: %s: no relative SASA for %zu residue name%s that %s not among the 20 standard amino "
               "acids of %s: %s\n",
               file.c_str(), names.size(), names.size() == 1 ? "" : "s", names.size() == 1 ? "is" : "are", kMaxAsaTable,
               list.c_str());
}

// `area --per atom|residue|chain` on one structure: a row per atom, residue or chain.
void printAreasPer(const AreaOptions& o, const Built& b, const SurfaceAreas& a) {
  const auto& m = b.molecule;
  const AreaLevel level = areaLevelNamed(o.per);
  if (level != AreaLevel::Atom && isPatchListPath(o.path))
    throw std::invalid_argument(o.path + " is a patch list, which holds no residues or chains: run `area --per " + o.per +
                                "` on the structure it was built from");
  const AreaRows rows{level, o.format, areaColumns(a), false};
  const std::vector<AreaGroup> groups = areaGroups(m, level);
  const bool ses = a.surface == build::SurfaceKind::Ses;
  if (o.format == "json") {
    nlohmann::json j;
    j["file"] = m.source;
    j["surface"] = ses ? "ses" : "mss";
    if (ses) j["probe_radius"] = b.patches.params.probeRadius; else j["shrink_factor"] = o.surface.shrink;
    j["atoms"] = m.size();
    j["radii"] = m.radiiSet;
    j["units"] = {{"area", "Å^2"}};
    j["totals"] = ses ? nlohmann::json{{"sas", a.sas}, {"ses", a.total}} : nlohmann::json{{"mss", a.total}};
    if (rows.relative()) j["relative_sas_table"] = kMaxAsaTable;
    j["per_" + o.per] = rows.json(m, groups);
    std::printf("%s\n", j.dump(1).c_str());
    noteRelativeSas(rows, groups, m.source, b.patches.params.probeRadius);
    return;
  }
  if (o.format == "table") {
    if (ses)
      std::printf("# %s: %zu atoms, probe %.3f Å, radii %s; areas in Å² (SAS %.4f, SES %.4f in all)\n", m.source.c_str(),
                  m.size(), b.patches.params.probeRadius, m.radiiSet.c_str(), a.sas, a.total);
    else
      std::printf("# %s: %zu atoms, skin s = %g, radii %s; areas in Å² (MSS %.4f in all)\n", m.source.c_str(), m.size(),
                  o.surface.shrink, m.radiiSet.c_str(), a.total);
  }
  rows.printHeader();
  rows.printRows(m, groups);
  noteRelativeSas(rows, groups, m.source, b.patches.params.probeRadius);
}

// The skin's areas: by patch kind, per atom (each skin point shared by its simplex's atoms in
// proportion to its convex weights), and the volume.
void runMssArea(const AreaOptions& o, const Built& b) {
  const auto& m = b.molecule;
  const auto start = std::chrono::steady_clock::now();
  const SurfaceAreas a = surfaceAreas(b.patches, m.centers);
  const double areaSeconds = secondsSince(start);
  if (!o.per.empty()) {
    printAreasPer(o, b, a);
    return;
  }
  if (o.format == "json") {
    nlohmann::json j;
    j["file"] = m.source;
    j["shrink_factor"] = o.surface.shrink;
    j["atoms"] = m.size();
    j["units"] = {{"area", "Å^2"}, {"volume", "Å^3"}};
    nlohmann::json mss = {{"total", a.total}, {"volume", a.volume}, {"area_error_estimate", a.areaErrorEstimate},
                          {"volume_error_estimate", a.volumeErrorEstimate}, {"per_atom", a.perAtom}};
    for (std::size_t k = 0; k < a.byKind.size(); ++k) mss[a.kindNames[k]] = a.byKind[k];
    j["mss"] = mss;
    std::printf("%s\n", j.dump(1).c_str());
    return;
  }
  if (o.format == "csv") {
    printPerAtomCsv(m, {{"mss", &a.perAtom}});
    return;
  }
  std::printf("file            %s (%zu atoms, shrink factor %g%s)\n", m.source.c_str(), m.size(), o.surface.shrink,
              o.surface.request().skinIsUnionOfBalls() ? ": the union of the van der Waals balls" : "");
  std::printf("MSS area        %14.4f Å²  (error estimate %.1e: quadrature and sliver cells)\n", a.total, a.areaErrorEstimate);
  for (std::size_t k = 0; k < build::kMssKindCount; ++k)
    std::printf("  %-13s %14.4f Å²  (%s)\n", build::kMssKinds[k].name, a.byKind[k], build::kMssKinds[k].patches);
  std::printf("MSS volume      %14.4f Å³\n", a.volume);
  std::printf("build           %.1f ms, areas %.1f ms (+ %.1f ms reading)\n", b.buildSeconds * 1e3, areaSeconds * 1e3,
              b.readSeconds * 1e3);
}

// The header of areas over time: CSV column names, or a table's title and columns.
void printAreaHeader(const AreaOptions& o, std::size_t atoms, std::size_t frames, const std::vector<std::string>& columns) {
  const bool mss = o.surface.surface == "mss";
  if (o.format == "csv") {
    std::printf("frame,time_ps");
    for (const std::string& c : columns) std::printf(",%s", c.c_str());
    std::printf("\n");
  } else if (o.format == "table") {
    std::printf("# %s + %s: %zu atoms, %s, %zu frames (areas in Å², volumes in Å³)\n", o.path.c_str(),
                o.trajectory.c_str(), atoms,
                mss ? ("skin, s = " + std::to_string(o.surface.shrink)).c_str()
                    : ("probe " + std::to_string(o.surface.probe) + " Å").c_str(),
                frames);
    std::printf("%6s %12s", "frame", "time_ps");
    for (const std::string& c : columns) std::printf(" %14s", c.c_str());
    std::printf("\n");
  }
}

// One frame's row of areas over time, in the header's column order.
std::vector<double> areaRow(const AreaOptions& o, const build::PatchList& list, const build::Molecule& m) {
  const SurfaceAreas a = surfaceAreas(list, m.centers);
  if (o.surface.surface == "mss") return {a.total, a.byKind[0], a.byKind[1], a.byKind[2], a.byKind[3], a.volume};
  return {a.sas, a.total, a.byKind[0], a.byKind[1], a.byKind[2], a.volume};
}

// The trajectory of `area TOPOLOGY TRAJECTORY`, its reader's notes said on the standard error.
build::Trajectory openTrajectory(const AreaOptions& o) {
  build::Trajectory trajectory =
      readingFile(o.trajectory, "the trajectory", [&] { return build::Trajectory(o.path, o.trajectory, o.read); });
  for (const std::string& note : trajectory.source().notes())
    std::fprintf(stderr, "surftrace: note: %s: %s\n", o.trajectory.c_str(), note.c_str());
  return trajectory;
}

// `area TOPOLOGY TRAJECTORY --per atom|residue|chain`: one table whose rows are those of `area
// --per` on each frame alone, each after its frame number and time.
void runAreasPerOverTime(const AreaOptions& o) {
  const build::SurfaceRequest request = o.surface.request();
  build::Trajectory trajectory = openTrajectory(o);
  const std::vector<std::size_t> frames = selectFrames(o.frames, trajectory.frameCount());
  const bool mss = request.surface == build::SurfaceKind::Mss;
  const AreaLevel level = areaLevelNamed(o.per);
  // The atoms' records do not change from frame to frame: neither do the groups.
  const std::vector<AreaGroup> groups = areaGroups(trajectory.molecule(), level);
  const std::vector<double> none;
  const std::vector<AreaColumn> names =
      mss ? std::vector<AreaColumn>{{"mss", &none}} : std::vector<AreaColumn>{{"sas", &none}, {"ses", &none}};
  const AreaRows header{level, o.format, names, true};
  if (o.format == "table") {
    char surface[64];
    std::snprintf(surface, sizeof surface, mss ? "skin, s = %g" : "probe %g Å", mss ? o.surface.shrink : o.surface.probe);
    std::printf("# %s + %s: %zu atoms, %s, radii %s, %zu frames (areas in Å²)\n", o.path.c_str(), o.trajectory.c_str(),
                trajectory.molecule().size(), surface, trajectory.molecule().radiiSet.c_str(), frames.size());
  }
  if (o.format != "json") header.printHeader();
  nlohmann::json rows = nlohmann::json::array();
  build::SurfaceBuilder builder(request);
  ProgressBar bar(true, "frames");
  for (std::size_t n = 0; n < frames.size(); ++n) {
    trajectory.load(frames[n]);
    const build::Molecule& m = trajectory.molecule();
    const build::PatchList list = n == 0 ? builder.build(m) : builder.update(m);
    const SurfaceAreas a = surfaceAreas(list, m.centers);
    const AreaRows frameRows{level, o.format, areaColumns(a), true};
    const double time = trajectory.frame().time;
    if (o.format == "json") {
      rows.push_back({{"frame", frames[n]}, {"time_ps", time}, {"per_" + o.per, frameRows.json(m, groups)}});
    } else {
      bar.clear();
      frameRows.printRows(m, groups, frames[n], time);
      std::fflush(stdout);
    }
    bar.items(n + 1, frames.size(), "frames");
  }
  if (o.format == "json") {
    nlohmann::json j = {{"topology", o.path}, {"trajectory", o.trajectory}, {"atoms", trajectory.molecule().size()},
                        {"surface", o.surface.surface}, {"radii", trajectory.molecule().radiiSet},
                        {"units", {{"area", "Å^2"}}}};
    if (mss) j["shrink_factor"] = o.surface.shrink; else j["probe_radius"] = o.surface.probe;
    if (header.relative()) j["relative_sas_table"] = kMaxAsaTable;
    j["frames"] = rows;
    std::printf("%s\n", j.dump(1).c_str());
  }
  noteRelativeSas(header, groups, o.path, o.surface.probe);
}

// Areas over time: one row per frame of a trajectory (FILE is its topology), from one
// SurfaceBuilder that keeps its memory frame after frame.
void runAreaOverTime(const AreaOptions& o) {
  const build::SurfaceRequest request = o.surface.request();
  build::Trajectory trajectory = openTrajectory(o);
  const std::vector<std::size_t> frames = selectFrames(o.frames, trajectory.frameCount());
  const bool mss = request.surface == build::SurfaceKind::Mss;
  const std::vector<std::string> columns =
      mss ? std::vector<std::string>{"mss", "mss_convex", "mss_edge", "mss_face", "mss_concave", "mss_volume"}
          : std::vector<std::string>{"sas", "ses", "ses_convex", "ses_toroidal", "ses_concave", "ses_volume"};
  nlohmann::json rows = nlohmann::json::array();
  printAreaHeader(o, trajectory.molecule().size(), frames.size(), columns);
  build::SurfaceBuilder builder(request);
  ProgressBar bar(true, "frames");
  for (std::size_t n = 0; n < frames.size(); ++n) {
    trajectory.load(frames[n]);
    const build::Molecule& m = trajectory.molecule();
    const build::PatchList list = n == 0 ? builder.build(m) : builder.update(m);
    const std::vector<double> values = areaRow(o, list, m);
    const double time = trajectory.frame().time;
    if (o.format == "json") {
      nlohmann::json row = {{"frame", frames[n]}, {"time_ps", time}};
      for (std::size_t c = 0; c < columns.size(); ++c) row[columns[c]] = values[c];
      rows.push_back(row);
    } else {
      bar.clear();
      std::printf(o.format == "csv" ? "%zu,%.6g" : "%6zu %12.6g", frames[n], time);
      for (double v : values) std::printf(o.format == "csv" ? ",%.6f" : " %14.4f", v);
      std::printf("\n");
      std::fflush(stdout);
      // A reader that stopped early stops the run before the next frame is built.
      build::checkStandardOutput();
    }
    bar.items(n + 1, frames.size(), "frames");
  }
  if (o.format == "json") {
    nlohmann::json j = {{"topology", o.path}, {"trajectory", o.trajectory}, {"atoms", trajectory.molecule().size()},
                        {"surface", o.surface.surface}, {"units", {{"area", "Å^2"}, {"volume", "Å^3"}}}, {"frames", rows}};
    if (mss) j["shrink_factor"] = o.surface.shrink; else j["probe_radius"] = o.surface.probe;
    std::printf("%s\n", j.dump(1).c_str());
  }
}

void printSesAreas(const AreaOptions& o, const Built& b);
void printCavities(const AreaOptions& o, const Built& b);

void runArea(const AreaOptions& o) {
  const auto limit = limitThreads(o.threads);
  if (!o.trajectory.empty()) {
    if (o.cavities) throw std::invalid_argument("--cavities locates the cavities of one structure, not along a TRAJECTORY");
    if (isPatchListPath(o.path))
      throw std::invalid_argument(o.path + " is a patch list; areas over a trajectory need its topology as FILE");
    if (!o.per.empty()) runAreasPerOverTime(o);
    else runAreaOverTime(o);
    return;
  }
  if (!o.frames.empty()) throw std::invalid_argument("--frames needs a TRAJECTORY after FILE");
  if (o.cavities && o.surface.surface == "mss")
    throw std::invalid_argument("--cavities locates the SES's cavities; the skin (--surface mss) has none to locate: its "
                                "patches carry no component labels (the SES builder labels its connected surfaces, the "
                                "skin builder does not). Leave out --surface mss");
  if (o.cavities && o.surface.dropCavities)
    throw std::invalid_argument("--cavities lists the cavities that --drop-cavities leaves out: give one of them");
  if (o.cavities && !o.per.empty())
    throw std::invalid_argument("--cavities lists each cavity's atoms and residues itself; --per " + o.per +
                                " gives areas per group: give one of them");
  const Built b = readAndBuild(o);
  if (o.cavities) {
    printCavities(o, b);
    return;
  }
  if (o.surface.surface == "mss") {
    runMssArea(o, b);
    return;
  }
  printSesAreas(o, b);
}

// The SES's areas by patch kind, per atom and per component, and its volume.
void printSesAreas(const AreaOptions& o, const Built& b) {
  const SurfaceAreas a = surfaceAreas(b.patches, b.molecule.centers);
  const auto& m = b.molecule;
  if (!o.per.empty()) {
    printAreasPer(o, b, a);
    return;
  }
  if (o.format == "json") {
    nlohmann::json j;
    j["file"] = m.source;
    j["probe_radius"] = b.patches.params.probeRadius;
    j["atoms"] = m.size();
    j["units"] = {{"area", "Å^2"}, {"volume", "Å^3"}};
    j["sas"] = {{"total", a.sas}, {"per_atom", a.sasPerAtom}};
    j["ses"] = {{"total", a.total},      {"convex", a.byKind[0]}, {"toroidal", a.byKind[1]},
                {"concave", a.byKind[2]}, {"volume", a.volume}, {"per_atom", a.perAtom}};
    nlohmann::json components = nlohmann::json::array();
    for (const auto& c : a.components) components.push_back({{"area", c.area}, {"volume", c.volume}, {"cavity", c.cavity}});
    j["ses"]["components"] = components;
    std::printf("%s\n", j.dump(1).c_str());
    return;
  }
  if (o.format == "csv") {
    printPerAtomCsv(m, {{"sas", &a.sasPerAtom}, {"ses", &a.perAtom}});
    return;
  }
  std::printf("file            %s (%zu atoms, probe %.3f Å)\n", m.source.c_str(), m.size(), b.patches.params.probeRadius);
  std::printf("SAS area        %14.4f Å²\n", a.sas);
  std::printf("SES area        %14.4f Å²\n", a.total);
  std::printf("  convex        %14.4f Å²\n", a.byKind[0]);
  std::printf("  toroidal      %14.4f Å²\n", a.byKind[1]);
  std::printf("  concave       %14.4f Å²  (after self-intersection clipping)\n", a.byKind[2]);
  std::printf("SES volume      %14.4f Å³\n", a.volume);
  if (a.components.size() > 1) {
    // Outer surfaces have a positive volume, cavities a negative one (minus the void they
    // enclose): printed here as the enclosed voids, positive.
    double outerArea = 0.0, cavityArea = 0.0, cavityVolume = 0.0;
    std::size_t outer = 0;
    for (const auto& c : a.components) {
      if (!c.cavity) ++outer, outerArea += c.area;
      else cavityArea += c.area, cavityVolume -= c.volume;
    }
    std::printf("components      %zu: %zu outer surface%s %.4f Å², %zu cavities %.4f Å² enclosing %.4f Å³ of void (--drop-cavities drops them)\n",
                a.components.size(), outer, outer == 1 ? "" : "s", outerArea, a.components.size() - outer, cavityArea, cavityVolume);
  }
  std::printf("build           %.1f ms (+ %.1f ms reading)\n", b.buildSeconds * 1e3, b.readSeconds * 1e3);
}

// One lining residue: chain, number, insertion code and name, as the file gives them.
struct LiningResidue {
  std::string chain;
  int number;
  char insertionCode;
  std::string name;
  bool operator<(const LiningResidue& o) const {
    return std::tie(chain, number, insertionCode, name) < std::tie(o.chain, o.number, o.insertionCode, o.name);
  }
  bool operator==(const LiningResidue& o) const = default;
};

std::vector<LiningResidue> liningResidues(const build::Molecule& m, const Cavity& c) {
  std::vector<LiningResidue> residues;
  for (const std::uint32_t i : c.atoms) {
    const auto& r = m.atoms[i];
    residues.push_back({r.chain, r.residueNumber, r.insertionCode, r.residue});
  }
  std::sort(residues.begin(), residues.end());
  residues.erase(std::unique(residues.begin(), residues.end()), residues.end());
  return residues;
}

std::string icodeText(char code) { return code == ' ' ? std::string() : std::string(1, code); }

// "A:LEU82C": chain, residue name, number and insertion code.
std::string residueLabel(const LiningResidue& r) {
  return (r.chain.empty() ? "" : r.chain + ":") + r.name + std::to_string(r.number) + icodeText(r.insertionCode);
}

constexpr const char* kCentroidMeaning =
    "area-weighted centroid of the cavity's surface (integral of x dA over its patches / area), exact";
constexpr const char* kBoxMeaning = "box of the cavity's surface patches (convex parts, tori, concave patches), exact";

// Each cavity (an SES component of negative volume): its lining atoms and residues, the
// centroid of its surface, its box, area and void.
void printCavities(const AreaOptions& o, const Built& b) {
  const std::vector<Cavity> cavities = locateCavities(b.patches);
  const auto& m = b.molecule;
  if (o.format == "json") {
    nlohmann::json list = nlohmann::json::array();
    for (std::size_t n = 0; n < cavities.size(); ++n) {
      const Cavity& c = cavities[n];
      nlohmann::json atoms = nlohmann::json::array(), residues = nlohmann::json::array();
      for (const std::uint32_t i : c.atoms) {
        const auto& r = m.atoms[i];
        atoms.push_back({{"atom", i}, {"serial", r.serial}, {"chain", r.chain}, {"resid", r.residueNumber},
                         {"icode", icodeText(r.insertionCode)}, {"resname", r.residue}, {"name", r.name}, {"element", r.element}});
      }
      for (const LiningResidue& r : liningResidues(m, c))
        residues.push_back({{"chain", r.chain}, {"resid", r.number}, {"icode", icodeText(r.insertionCode)}, {"resname", r.name}});
      list.push_back({{"cavity", n + 1}, {"component", c.component}, {"area", c.area}, {"void_volume", c.volume},
                      {"centroid", {c.centroid.x, c.centroid.y, c.centroid.z}},
                      {"box", {{"min", {c.boxLower.x, c.boxLower.y, c.boxLower.z}}, {"max", {c.boxUpper.x, c.boxUpper.y, c.boxUpper.z}}}},
                      {"atoms", atoms}, {"residues", residues}});
    }
    nlohmann::json j = {{"file", m.source}, {"probe_radius", b.patches.params.probeRadius}, {"atoms", m.size()},
                        {"units", {{"area", "Å^2"}, {"volume", "Å^3"}, {"length", "Å"}}},
                        {"centroid", kCentroidMeaning}, {"box", kBoxMeaning}, {"cavities", list}};
    std::printf("%s\n", j.dump(1).c_str());
    return;
  }
  if (o.format == "csv") {
    // One row per lining atom, with its cavity's values repeated: group by `cavity`.
    std::printf("cavity,component,area,void_volume,centroid_x,centroid_y,centroid_z,box_min_x,box_min_y,box_min_z,"
                "box_max_x,box_max_y,box_max_z,atom,serial,chain,resid,icode,resname,name,element\n");
    for (std::size_t n = 0; n < cavities.size(); ++n) {
      const Cavity& c = cavities[n];
      for (const std::uint32_t i : c.atoms) {
        const auto& r = m.atoms[i];
        std::printf("%zu,%u,%.6f,%.6f,%.4f,%.4f,%.4f,%.4f,%.4f,%.4f,%.4f,%.4f,%.4f,%u,%d,%s,%d,%s,%s,%s,%s\n", n + 1, c.component,
                    c.area, c.volume, c.centroid.x, c.centroid.y, c.centroid.z, c.boxLower.x, c.boxLower.y, c.boxLower.z,
                    c.boxUpper.x, c.boxUpper.y, c.boxUpper.z, i, r.serial, r.chain.c_str(), r.residueNumber,
                    icodeText(r.insertionCode).c_str(), r.residue.c_str(), r.name.c_str(), r.element.c_str());
        build::checkStandardOutput();
      }
    }
    return;
  }
  std::printf("file            %s (%zu atoms, probe %.3f Å)\n", m.source.c_str(), m.size(), b.patches.params.probeRadius);
  std::printf("cavities        %zu (area Å², void Å³; centroid: %s; box: %s)\n", cavities.size(), kCentroidMeaning, kBoxMeaning);
  if (cavities.empty()) return;
  std::printf("%6s %9s %10s %10s %26s %26s %26s %6s  %s\n", "cavity", "component", "area", "void", "centroid x y z",
              "box min x y z", "box max x y z", "atoms", "lining residues");
  for (std::size_t n = 0; n < cavities.size(); ++n) {
    const Cavity& c = cavities[n];
    std::string residues;
    for (const LiningResidue& r : liningResidues(m, c)) residues += (residues.empty() ? "" : " ") + residueLabel(r);
    std::printf("%6zu %9u %10.4f %10.4f %8.3f %8.3f %8.3f %8.3f %8.3f %8.3f %8.3f %8.3f %8.3f %6zu  %s\n", n + 1, c.component,
                c.area, c.volume, c.centroid.x, c.centroid.y, c.centroid.z, c.boxLower.x, c.boxLower.y, c.boxLower.z,
                c.boxUpper.x, c.boxUpper.y, c.boxUpper.z, c.atoms.size(), residues.c_str());
    build::checkStandardOutput();
  }
}

}  // namespace

void addAreaCommand(CLI::App& app) {
  auto o = std::make_shared<AreaOptions>();
  auto* cmd = app.add_subcommand("area",
                                 "Exact SAS area, SES area by patch kind, and SES volume (divergence theorem "
                                 "over the patches), with per-atom areas in csv/json; with --surface mss the skin's "
                                 "area by patch kind, per atom, and its volume");
  addSurfaceInputOptions(*cmd, *o);
  cmd->add_option("TRAJECTORY", o->trajectory,
                  "A trajectory of FILE (DCD, XTC, GRO, XYZ, multi-model PDB/mmCIF): one row of areas per frame, FILE "
                  "being its topology (PSF, GRO, PDB, mmCIF)")
      ->check(CLI::ExistingFile);
  cmd->add_option("--frames", o->frames, "With TRAJECTORY: frames a:b:step, numbered from 0 (default: all)");
  cmd->add_option("--per", o->per,
                  "Areas per atom, residue or chain, as a table, csv or json (--format): SAS and SES (or the skin's), "
                  "with insertion codes and alternate locations in their own columns and, per residue, the SAS "
                  "relative to Tien et al. 2013's theoretical maximum ASA; with TRAJECTORY the same rows for every "
                  "frame, after its number and time")
      ->check(CLI::IsMember({"atom", "residue", "chain"}));
  cmd->add_option("--format", o->format,
                  "Output: table (totals), csv (per atom; with TRAJECTORY one row per frame), json (totals and per "
                  "atom; with TRAJECTORY per frame); with --per, the rows of that level in this format")
      ->check(CLI::IsMember({"table", "csv", "json"}))
      ->default_val("table");
  cmd->add_flag("--cavities", o->cavities,
                "Locate the SES's cavities instead: per cavity its lining atoms and residues, the centroid of its "
                "surface, its box, area and void (table; csv: one row per lining atom; json)");
  cmd->callback([o] { runArea(*o); });
}

}  // namespace surftrace::tools

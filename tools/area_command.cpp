// `surftrace area`: exact areas and volumes of the SES (by patch kind, per atom, per component)
// and of the skin, for a structure, a patch list, or every frame of a trajectory.
#include <chrono>
#include <cstdio>
#include <initializer_list>
#include <memory>
#include <stdexcept>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

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
};

// One CSV row per atom: who it is (`atom`: its place in the file from 0, MDAnalysis's index,
// also under --select), its radius, then the named per-atom columns (Å²).
void printPerAtomCsv(const build::Molecule& m,
                     std::initializer_list<std::pair<const char*, const std::vector<double>*>> columns) {
  std::printf("atom,serial,chain,residue,residue_number,name,element,radius");
  for (const auto& [name, values] : columns) std::printf(",%s", name);
  std::printf("\n");
  for (std::size_t i = 0; i < m.size(); ++i) {
    const auto& r = m.atoms[i];
    std::printf("%zu,%d,%s,%s,%d,%s,%s,%.4f", r.fileIndex, r.serial, r.chain.c_str(), r.residue.c_str(), r.residueNumber,
                r.name.c_str(), r.element.c_str(), m.radii[i]);
    for (const auto& [name, values] : columns) std::printf(",%.6f", (*values)[i]);
    std::printf("\n");
    // A reader that stopped early (| head) ends the command here, with the reason.
    build::checkStandardOutput();
  }
}

// The skin's areas: by patch kind, per atom (each skin point shared by its simplex's atoms in
// proportion to its convex weights), and the volume.
void runMssArea(const AreaOptions& o, const Built& b) {
  const auto& m = b.molecule;
  const auto start = std::chrono::steady_clock::now();
  const SurfaceAreas a = surfaceAreas(b.patches, m.centers);
  const double areaSeconds = secondsSince(start);
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

// Areas over time: one row per frame of a trajectory (FILE is its topology), from one
// SurfaceBuilder that keeps its memory frame after frame.
void runAreaOverTime(const AreaOptions& o) {
  const build::SurfaceRequest request = o.surface.request();
  build::Trajectory trajectory =
      readingFile(o.trajectory, "the trajectory", [&] { return build::Trajectory(o.path, o.trajectory, o.read); });
  for (const std::string& note : trajectory.source().notes())
    std::fprintf(stderr, "surftrace: note: %s: %s\n", o.trajectory.c_str(), note.c_str());
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

void runArea(const AreaOptions& o) {
  const auto limit = limitThreads(o.threads);
  if (!o.trajectory.empty()) {
    if (isPatchListPath(o.path))
      throw std::invalid_argument(o.path + " is a patch list; areas over a trajectory need its topology as FILE");
    runAreaOverTime(o);
    return;
  }
  if (!o.frames.empty()) throw std::invalid_argument("--frames needs a TRAJECTORY after FILE");
  const Built b = readAndBuild(o);
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
  cmd->add_option("--format", o->format,
                  "Output: table (totals), csv (per atom; with TRAJECTORY one row per frame), json (totals and per "
                  "atom; with TRAJECTORY per frame)")
      ->check(CLI::IsMember({"table", "csv", "json"}))
      ->default_val("table");
  cmd->callback([o] { runArea(*o); });
}

}  // namespace surftrace::tools

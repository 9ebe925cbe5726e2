// `surftrace build` (write a patch list) and `surftrace area` (exact areas and volume).
#include <chrono>
#include <initializer_list>
#include <limits>
#include <stdexcept>
#include <cstdio>
#include <memory>
#include <sstream>

#include <nlohmann/json.hpp>
#include <tbb/global_control.h>

#include "build/io/molecule.hpp"
#include "build/io/trajectory.hpp"
#include "build/mss/mss_area.hpp"
#include "build/mss/mss_builder.hpp"
#include "build/ses/surface_area.hpp"
#include "build/surface.hpp"
#include "build/io/output_file.hpp"
#include "commands.hpp"
#include "image_options.hpp"
#include "option_checks.hpp"
#include "trajectory_plan.hpp"

namespace surftrace::tools {
namespace {

struct SurfaceOptions {
  std::string path;
  build::ReadOptions read;
  std::string surface = "ses";
  double probe = 1.4;
  double shrink = 0.5;
  int threads = 0;
  bool dropCavities = false;
  double mergeWithin = build::kMinMergeDistance;
  CLI::Option* probeOption = nullptr;  // to tell a --probe given from its default
};

void addSurfaceOptions(CLI::App& cmd, SurfaceOptions& o) {
  cmd.add_option("FILE", o.path,
                 "Structure file (PDB, mmCIF, PQR, XYZR, XYZ; .gz allowed); `area` also takes a patch list from "
                 "`build` (.stp, told by its content)")
      ->required();
  cmd.add_option("--surface", o.surface,
                 "Surface to build: ses (solvent excluded: spheres, tori, concave triangles) or mss (molecular "
                 "skin: spheres and hyperboloids clipped to mixed cells)")
      ->check(CLI::IsMember({"ses", "mss"}))
      ->default_val("ses");
  addShrinkOption(cmd, o.shrink);
  o.probeOption = cmd.add_option("--probe", o.probe, "Probe radius rp in Å (> 0); 1.4 Å models water")
      ->check(positive())
      ->default_val(1.4);
  cmd.add_option("--threads", o.threads, "Worker threads (default: all cores); results do not depend on it")
      ->check(wholeIn(0, 4096));
  cmd.add_flag("--drop-cavities", o.dropCavities,
               "Keep only the outer SES components (positive volume): drop the inner surfaces of buried cavities a probe fits in");
  cmd.add_option("--merge-within", o.mergeWithin,
                 "Merge every atom whose ball lies within this distance in Å (|centre shift| + |radius change|) of a "
                 "kept atom's into it, noted: the surface of the input with those atoms moved by at most that much. "
                 "Near-coincident clusters (more than " + std::to_string(build::kMaxClusterAtoms) + " atoms within " +
                 detail::shortNumber(build::kClusterRadius) + " Å) are refused until merged")
      ->check(numberIn(build::kMinMergeDistance, HUGE_VAL))
      ->default_val(build::kMinMergeDistance);
  addMoleculeOptions(cmd, o.read);
}

double secondsSince(std::chrono::steady_clock::time_point start) {
  return std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
}

struct Built {
  build::Molecule molecule;
  build::PatchList patches;
  double readSeconds, buildSeconds;
};

build::SurfaceRequest surfaceRequest(const SurfaceOptions& o) {
  return {build::parseSurfaceKind(o.surface), o.probe, o.shrink, o.dropCavities, o.mergeWithin};
}

Built readAndBuild(const SurfaceOptions& o) {
  std::unique_ptr<tbb::global_control> limit;
  if (o.threads > 0)
    limit = std::make_unique<tbb::global_control>(tbb::global_control::max_allowed_parallelism,
                                                  static_cast<std::size_t>(o.threads));
  auto start = std::chrono::steady_clock::now();
  Built b;
  if (isPatchListInput(o.path)) {
    // A patch list from `build` (told by its magic): its areas are those of the structure it
    // was built from, with the probe it was built with.
    b.patches = build::readPatchList(o.path);
    if (o.probeOption && o.probeOption->count() > 0 && o.probe != b.patches.params.probeRadius)
      throw std::invalid_argument(o.path + " was built with probe " + std::to_string(b.patches.params.probeRadius) +
                                  " Å; --probe " + std::to_string(o.probe) + " cannot change it (rebuild it)");
    if (b.patches.params.surface != build::SurfaceKind::Ses)
      throw std::invalid_argument(o.path + ": the areas of a " + build::surfaceKindName(b.patches.params.surface) +
                                  " patch list need its structure (per-atom shares): run `area` on the structure");
    b.molecule.source = o.path;
    b.molecule.atoms.resize(b.patches.params.atomCount);
    b.molecule.centers.resize(b.patches.params.atomCount);
    b.molecule.radii.assign(b.patches.params.atomCount, std::numeric_limits<double>::quiet_NaN());
    for (std::size_t k = 0; k < b.patches.convex.size(); ++k)
      b.molecule.radii[b.patches.convex.atom[k]] = b.patches.convex.radius[k];
    b.readSeconds = secondsSince(start);
    start = std::chrono::steady_clock::now();
    if (o.dropCavities) b.patches = build::outerComponent(b.patches);
    b.buildSeconds = secondsSince(start);
    return b;
  }
  b.molecule = build::readMolecule(o.path, o.read);
  printReadNotes(b.molecule);
  b.readSeconds = secondsSince(start);
  start = std::chrono::steady_clock::now();
  std::vector<std::string> notes;
  b.patches = build::buildSurface(b.molecule, surfaceRequest(o), &notes);
  b.buildSeconds = secondsSince(start);
  for (const std::string& note : notes) std::fprintf(stderr, "surftrace: note: %s: %s\n", o.path.c_str(), note.c_str());
  return b;
}

struct BuildOptions : SurfaceOptions {
  std::string output;
};

void runBuild(const BuildOptions& o) {
  if (isPatchListInput(o.path))
    throw std::invalid_argument(o.path + " is a patch list already (built, not a structure); `render` and `area` "
                                "take it as it is");
  build::prepareOutputPath(o.output, "-o");
  const Built b = readAndBuild(o);
  build::writePatchList(o.output, b.patches);
  const auto& p = b.patches;
  if (p.params.surface == build::SurfaceKind::Mss) {
    std::size_t count[4] = {0, 0, 0, 0};
    for (std::uint32_t k : p.mss.kind) ++count[k];
    std::printf("%s: %zu atoms, s = %g -> %zu MSS patches: %zu convex spheres, %zu edge hyperboloids, %zu face "
                "hyperboloids, %zu concave spheres; %zu mixed-cell planes\n",
                o.path.c_str(), b.molecule.size(), o.shrink, p.mss.size(), count[0], count[1], count[2], count[3],
                p.cellPlanes.size());
  } else if (p.params.surface == build::SurfaceKind::Vdw) {
    std::printf("%s: %zu atoms, s = 1: the union of the van der Waals balls, %zu spheres\n", o.path.c_str(),
                b.molecule.size(), p.convex.size());
  } else {
    std::printf("%s: %zu atoms -> %zu convex, %zu toroidal, %zu concave patches, %zu clipping planes\n", o.path.c_str(),
              b.molecule.size(), p.convex.size(), p.tori.size(), p.concave.size(), p.clipPlanes.size());
  }
  std::printf("read %.1f ms, built %.1f ms; wrote %s\n", b.readSeconds * 1e3, b.buildSeconds * 1e3, o.output.c_str());
}

struct AreaOptions : SurfaceOptions {
  std::string format = "table";
  std::string trajectory;  // FILE is then its topology: one row per frame
  std::string frames;
};

// One CSV row per atom: who it is, its radius, then the named per-atom columns (Å²).
void printPerAtomCsv(const build::Molecule& m,
                     std::initializer_list<std::pair<const char*, const std::vector<double>*>> columns) {
  std::printf("atom,serial,chain,residue,residue_number,name,element,radius");
  for (const auto& [name, values] : columns) std::printf(",%s", name);
  std::printf("\n");
  for (std::size_t i = 0; i < m.size(); ++i) {
    const auto& r = m.atoms[i];
    std::printf("%zu,%d,%s,%s,%d,%s,%s,%.4f", i, r.serial, r.chain.c_str(), r.residue.c_str(), r.residueNumber,
                r.name.c_str(), r.element.c_str(), m.radii[i]);
    for (const auto& [name, values] : columns) std::printf(",%.6f", (*values)[i]);
    std::printf("\n");
  }
}

// The skin's areas: by patch kind, per atom (each skin point shared by its simplex's atoms in
// proportion to its convex weights), and the volume.
void runMssArea(const AreaOptions& o, const Built& b) {
  const auto& m = b.molecule;
  const auto start = std::chrono::steady_clock::now();
  const build::MssAreas a = o.shrink >= 1.0 ? build::unionOfBallsAreas(b.patches)
                                            : build::computeMssAreas(b.patches, m.centers);
  const double areaSeconds = secondsSince(start);
  static const char* kinds[4] = {"convex", "edge", "face", "concave"};
  if (o.format == "json") {
    nlohmann::json j;
    j["file"] = m.source;
    j["shrink_factor"] = o.shrink;
    j["atoms"] = m.size();
    j["units"] = {{"area", "Å^2"}, {"volume", "Å^3"}};
    nlohmann::json mss = {{"total", a.total()}, {"volume", a.volume}, {"area_error_estimate", a.areaErrorEstimate},
                          {"volume_error_estimate", a.volumeErrorEstimate}, {"per_atom", a.perAtom}};
    for (int k = 0; k < 4; ++k) mss[kinds[k]] = a.byKind[k];
    j["mss"] = mss;
    std::printf("%s\n", j.dump(1).c_str());
    return;
  }
  if (o.format == "csv") {
    printPerAtomCsv(m, {{"mss", &a.perAtom}});
    return;
  }
  std::printf("file            %s (%zu atoms, shrink factor %g%s)\n", m.source.c_str(), m.size(), o.shrink,
              o.shrink >= 1.0 ? ": the union of the van der Waals balls" : "");
  std::printf("MSS area        %14.4f Å²  (error estimate %.1e: quadrature and sliver cells)\n", a.total(), a.areaErrorEstimate);
  std::printf("  convex        %14.4f Å²  (atom spheres)\n", a.byKind[0]);
  std::printf("  edge          %14.4f Å²  (hyperboloids of Delaunay edges)\n", a.byKind[1]);
  std::printf("  face          %14.4f Å²  (hyperboloids of Delaunay triangles)\n", a.byKind[2]);
  std::printf("  concave       %14.4f Å²  (spheres of Delaunay tetrahedra)\n", a.byKind[3]);
  std::printf("MSS volume      %14.4f Å³\n", a.volume);
  std::printf("build           %.1f ms, areas %.1f ms (+ %.1f ms reading)\n", b.buildSeconds * 1e3, areaSeconds * 1e3,
              b.readSeconds * 1e3);
}

// Areas over time: one row per frame of a trajectory (FILE is its topology), from one
// SurfaceBuilder that keeps its memory frame after frame.
void runAreaOverTime(const AreaOptions& o) {
  std::unique_ptr<tbb::global_control> limit;
  if (o.threads > 0)
    limit = std::make_unique<tbb::global_control>(tbb::global_control::max_allowed_parallelism,
                                                  static_cast<std::size_t>(o.threads));
  const build::SurfaceRequest request = surfaceRequest(o);
  build::Trajectory trajectory(o.path, o.trajectory, o.read);
  for (const std::string& note : trajectory.source().notes())
    std::fprintf(stderr, "surftrace: note: %s: %s\n", o.trajectory.c_str(), note.c_str());
  const std::vector<std::size_t> frames = selectFrames(o.frames, trajectory.frameCount());
  const bool mss = request.surface == build::SurfaceKind::Mss;
  const std::vector<std::string> columns =
      mss ? std::vector<std::string>{"mss", "mss_convex", "mss_edge", "mss_face", "mss_concave", "mss_volume"}
          : std::vector<std::string>{"sas", "ses", "ses_convex", "ses_toroidal", "ses_concave", "ses_volume"};
  nlohmann::json rows = nlohmann::json::array();
  if (o.format == "csv") {
    std::printf("frame,time_ps");
    for (const std::string& c : columns) std::printf(",%s", c.c_str());
    std::printf("\n");
  } else if (o.format == "table") {
    std::printf("# %s + %s: %zu atoms, %s, %zu frames (areas in Å², volumes in Å³)\n", o.path.c_str(),
                o.trajectory.c_str(), trajectory.molecule().size(),
                mss ? ("skin, s = " + std::to_string(o.shrink)).c_str() : ("probe " + std::to_string(o.probe) + " Å").c_str(),
                frames.size());
    std::printf("%6s %12s", "frame", "time_ps");
    for (const std::string& c : columns) std::printf(" %14s", c.c_str());
    std::printf("\n");
  }
  build::SurfaceBuilder builder(request);
  ProgressBar bar(true, "frames");
  for (std::size_t n = 0; n < frames.size(); ++n) {
    trajectory.load(frames[n]);
    const build::Molecule& m = trajectory.molecule();
    const build::PatchList list = n == 0 ? builder.build(m) : builder.update(m);
    std::vector<double> values;
    if (mss) {
      const build::MssAreas a = o.shrink >= 1.0 ? build::unionOfBallsAreas(list)
                                                : build::computeMssAreas(list, m.centers);
      values = {a.total(), a.byKind[0], a.byKind[1], a.byKind[2], a.byKind[3], a.volume};
    } else {
      const build::SurfaceAreas a = build::computeAreas(list);
      values = {a.sas, a.sesTotal(), a.sesConvex, a.sesToroidal, a.sesConcave, a.sesVolume};
    }
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
    }
    bar.items(n + 1, frames.size(), "frames");
  }
  if (o.format == "json") {
    nlohmann::json j = {{"topology", o.path}, {"trajectory", o.trajectory}, {"atoms", trajectory.molecule().size()},
                        {"surface", o.surface}, {"units", {{"area", "Å^2"}, {"volume", "Å^3"}}}, {"frames", rows}};
    if (mss) j["shrink_factor"] = o.shrink; else j["probe_radius"] = o.probe;
    std::printf("%s\n", j.dump(1).c_str());
  }
}

void runArea(const AreaOptions& o) {
  if (!o.trajectory.empty()) {
    if (isPatchListInput(o.path))
      throw std::invalid_argument(o.path + " is a patch list; areas over a trajectory need its topology as FILE");
    runAreaOverTime(o);
    return;
  }
  if (!o.frames.empty()) throw std::invalid_argument("--frames needs a TRAJECTORY after FILE");
  const Built b = readAndBuild(o);
  if (o.surface == "mss") {
    runMssArea(o, b);
    return;
  }
  const build::SurfaceAreas a = build::computeAreas(b.patches);
  const auto& m = b.molecule;
  if (o.format == "json") {
    nlohmann::json j;
    j["file"] = m.source;
    j["probe_radius"] = b.patches.params.probeRadius;
    j["atoms"] = m.size();
    j["units"] = {{"area", "Å^2"}, {"volume", "Å^3"}};
    j["sas"] = {{"total", a.sas}, {"per_atom", a.sasPerAtom}};
    j["ses"] = {{"total", a.sesTotal()}, {"convex", a.sesConvex},     {"toroidal", a.sesToroidal},
                {"concave", a.sesConcave}, {"volume", a.sesVolume}, {"per_atom", a.sesPerAtom}};
    nlohmann::json components = nlohmann::json::array();
    for (const auto& c : a.components) components.push_back({{"area", c.area}, {"volume", c.volume}, {"cavity", !c.outer()}});
    j["ses"]["components"] = components;
    std::printf("%s\n", j.dump(1).c_str());
    return;
  }
  if (o.format == "csv") {
    printPerAtomCsv(m, {{"sas", &a.sasPerAtom}, {"ses", &a.sesPerAtom}});
    return;
  }
  std::printf("file            %s (%zu atoms, probe %.3f Å)\n", m.source.c_str(), m.size(), b.patches.params.probeRadius);
  std::printf("SAS area        %14.4f Å²\n", a.sas);
  std::printf("SES area        %14.4f Å²\n", a.sesTotal());
  std::printf("  convex        %14.4f Å²\n", a.sesConvex);
  std::printf("  toroidal      %14.4f Å²\n", a.sesToroidal);
  std::printf("  concave       %14.4f Å²  (after self-intersection clipping)\n", a.sesConcave);
  std::printf("SES volume      %14.4f Å³\n", a.sesVolume);
  if (a.components.size() > 1) {
    // Outer surfaces have a positive volume, cavities a negative one (minus the void they
    // enclose): printed here as the enclosed voids, positive.
    double outerArea = 0.0, cavityArea = 0.0, cavityVolume = 0.0;
    std::size_t outer = 0;
    for (const auto& c : a.components) {
      if (c.outer()) ++outer, outerArea += c.area;
      else cavityArea += c.area, cavityVolume -= c.volume;
    }
    std::printf("components      %zu: %zu outer surface%s %.4f Å², %zu cavities %.4f Å² enclosing %.4f Å³ of void (--drop-cavities drops them)\n",
                a.components.size(), outer, outer == 1 ? "" : "s", outerArea, a.components.size() - outer, cavityArea, cavityVolume);
  }
  std::printf("build           %.1f ms (+ %.1f ms reading)\n", b.buildSeconds * 1e3, b.readSeconds * 1e3);
}

}  // namespace

void addShrinkOption(CLI::App& cmd, double& shrink) {
  char range[64];
  std::snprintf(range, sizeof range, "[%g, 1]", build::kMinShrinkFactor);
  cmd.add_option("--shrink", shrink,
                 std::string("MSS shrink factor s in ") + range +
                     ": small s is smooth and wraps the molecule loosely, s -> 1 approaches the atoms; s = 1 is "
                     "exactly the union of the van der Waals balls (the vdW surface, built as whole spheres)")
      ->check(CLI::Validator(
          [range = std::string(range)](const std::string& v) {
            const std::string problem = detail::checkNumber(v, build::kMinShrinkFactor, 1.0, false, false);
            if (problem.empty()) return problem;
            return problem + (std::strtod(v.c_str(), nullptr) > 0.0 && std::strtod(v.c_str(), nullptr) < build::kMinShrinkFactor
                                  ? " (below it double precision no longer carries the skin's areas and volume, "
                                    "and the skin is within 0.1% of its s -> 0 limit)"
                                  : "");
          },
          range, ""))
      ->default_val(0.5);
}

void addBuildCommands(CLI::App& app) {
  auto bo = std::make_shared<BuildOptions>();
  auto* build = app.add_subcommand("build",
                                   "Build the analytic patch list and write it to a .stp file for `render --patches`: "
                                   "the SES (convex spheres, tori, concave triangles with their clipping planes) or, "
                                   "with --surface mss, the molecular skin (spheres and hyperboloids with their mixed "
                                   "cells)");
  addSurfaceOptions(*build, *bo);
  build->add_option("-o,--output", bo->output, "Patch-list file to write (.stp)")->required();
  build->callback([bo] { runBuild(*bo); });

  auto ao = std::make_shared<AreaOptions>();
  auto* area = app.add_subcommand("area",
                                  "Exact SAS area, SES area by patch kind, and SES volume (divergence theorem "
                                  "over the patches), with per-atom areas in csv/json; with --surface mss the skin's "
                                  "area by patch kind, per atom, and its volume");
  addSurfaceOptions(*area, *ao);
  area->add_option("TRAJECTORY", ao->trajectory,
                   "A trajectory of FILE (DCD, XTC, GRO, XYZ, multi-model PDB/mmCIF): one row of areas per frame, FILE "
                   "being its topology (PSF, GRO, PDB, mmCIF)")
      ->check(CLI::ExistingFile);
  area->add_option("--frames", ao->frames, "With TRAJECTORY: frames a:b:step, numbered from 0 (default: all)");
  area->add_option("--format", ao->format,
                   "Output: table (totals), csv (per atom; with TRAJECTORY one row per frame), json (totals and per "
                   "atom; with TRAJECTORY per frame)")
      ->check(CLI::IsMember({"table", "csv", "json"}))
      ->default_val("table");
  area->callback([ao] { runArea(*ao); });
}

}  // namespace surftrace::tools

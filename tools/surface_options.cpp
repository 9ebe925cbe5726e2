// The stages "read" and "build" every command shares (surface_options.hpp).
#include "surface_options.hpp"

#include <cmath>
#include <cstdio>
#include <cstdlib>

#include "commands.hpp"
#include "option_checks.hpp"
#include "surftrace/molecule.hpp"
#include "surftrace/surface.hpp"

namespace surftrace::tools {

std::unique_ptr<tbb::global_control> limitThreads(int threads) {
  if (threads <= 0) return nullptr;
  return std::make_unique<tbb::global_control>(tbb::global_control::max_allowed_parallelism,
                                               static_cast<std::size_t>(threads));
}

build::SurfaceRequest SurfaceOptions::request() const {
  return build::SurfaceRequest{build::parseSurfaceKind(surface), probe, shrink, dropCavities, mergeWithin};
}

void addShrinkOption(CLI::App& cmd, double& shrink) {
  char range[64];
  std::snprintf(range, sizeof range, "[%g, %g]", build::kMinShrinkFactor, build::kMaxShrinkFactor);
  cmd.add_option("--shrink", shrink,
                 std::string("MSS shrink factor s in ") + range +
                     ": small s is smooth and wraps the molecule loosely, s -> 1 approaches the atoms; s = 1 is "
                     "exactly the union of the van der Waals balls (the vdW surface, built as whole spheres)")
      ->check(CLI::Validator(
          [range = std::string(range)](const std::string& v) {
            // build::validShrinkFactor's range, which buildSurface and the patch list's checks take too.
            const std::string problem =
                detail::checkNumber(v, build::kMinShrinkFactor, build::kMaxShrinkFactor, false, false);
            if (problem.empty()) return problem;
            return problem + (std::strtod(v.c_str(), nullptr) > 0.0 && std::strtod(v.c_str(), nullptr) < build::kMinShrinkFactor
                                  ? " (below it double precision no longer carries the skin's areas and volume, "
                                    "and the skin is within 0.1% of its s -> 0 limit)"
                                  : "");
          },
          range, ""))
      ->default_val(0.5);
}

void addSurfaceOptions(CLI::App& cmd, SurfaceOptions& o, SurfaceChoice choice) {
  if (choice == SurfaceChoice::Any) {
    cmd.add_option("--surface", o.surface,
                   "ses (solvent excluded: exact spheres, tori, concave triangles), mss (molecular skin: spheres and "
                   "hyperboloids in their mixed cells, --shrink), vdw (atom spheres) or sas (spheres of r + probe)")
        ->check(CLI::IsMember({"ses", "mss", "vdw", "sas"}))
        ->default_val("ses");
  } else {
    cmd.add_option("--surface", o.surface,
                   "Surface to build: ses (solvent excluded: spheres, tori, concave triangles) or mss (molecular "
                   "skin: spheres and hyperboloids clipped to mixed cells)")
        ->check(CLI::IsMember({"ses", "mss"}))
        ->default_val("ses");
  }
  addShrinkOption(cmd, o.shrink);
  o.probeOption = cmd.add_option("--probe", o.probe, "Probe radius rp in Å (> 0); 1.4 Å models water")
                      ->check(positive())
                      ->default_val(1.4);
  cmd.add_flag("--drop-cavities", o.dropCavities,
               "Keep only the outer SES components (positive volume): leave out the inner surfaces of buried "
               "cavities a probe fits in, which cannot be seen from outside");
  cmd.add_option("--merge-within", o.mergeWithin,
                 "Merge every atom whose ball lies within this distance in Å (|centre shift| + |radius change|) of a "
                 "kept atom's into it, noted: the surface of the input with those atoms moved by at most that much. "
                 "Near-coincident clusters (more than " + std::to_string(build::kMaxClusterAtoms) + " atoms within " +
                 detail::shortNumber(build::kClusterRadius) + " Å) are refused until merged")
      ->check(numberIn(build::kMinMergeDistance, HUGE_VAL))
      ->default_val(build::kMinMergeDistance);
}

build::PatchList buildWithNotes(const build::Molecule& molecule, const build::SurfaceRequest& request) {
  std::vector<std::string> notes;
  build::PatchList list = build::buildSurface(molecule, request, &notes);
  for (const std::string& note : notes)
    std::fprintf(stderr, "surftrace: note: %s: %s\n", molecule.source.c_str(), note.c_str());
  return list;
}

build::Molecule readInput(const std::string& path, const std::string& trajectory, std::size_t frame,
                          const build::ReadOptions& read) {
  if (trajectory.empty()) {
    build::Molecule molecule = readingFile(path, "the atoms", [&] { return readStructure(path, read); });
    printReadNotes(molecule);
    return molecule;
  }
  return readingFile(trajectory, "the frame", [&] { return readTrajectoryFrame(path, trajectory, frame, read); });
}

}  // namespace surftrace::tools

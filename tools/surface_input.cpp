// What `build` and `area` read and build (surface_input.hpp).
#include "surface_input.hpp"

#include <chrono>
#include <limits>
#include <memory>
#include <stdexcept>

#include "commands.hpp"
#include "option_checks.hpp"
#include "surftrace/surface.hpp"

namespace surftrace::tools {
void addSurfaceInputOptions(CLI::App& cmd, SurfaceInputOptions& o) {
  cmd.add_option("FILE", o.path,
                 "Structure file (PDB, mmCIF, PQR, XYZR, XYZ; .gz allowed); `area` also takes a patch list from "
                 "`build` (.stp, told by its content)")
      ->required();
  addSurfaceOptions(cmd, o.surface, SurfaceChoice::Built);
  cmd.add_option("--threads", o.threads, "Worker threads (default: all cores); results do not depend on it")
      ->check(wholeIn(0, 4096));
  addMoleculeOptions(cmd, o.read);
}

Built readAndBuild(const SurfaceInputOptions& o) {
  auto start = std::chrono::steady_clock::now();
  Built b;
  if (isPatchListPath(o.path)) {
    if (o.read.selection)
      throw std::invalid_argument("--select needs the structure file: " + o.path +
                                  " is a patch list, which holds no atom records (build it from the selection)");
    b.patches = readingFile(o.path, "the patch list", [&] { return build::readPatchList(o.path); });
    if (o.surface.probeGiven() && o.surface.probe != b.patches.params.probeRadius)
      throw std::invalid_argument(o.path + " was built with probe " + std::to_string(b.patches.params.probeRadius) +
                                  " Å; --probe " + std::to_string(o.surface.probe) + " cannot change it (rebuild it)");
    if (b.patches.params.surface != build::SurfaceKind::Ses)
      throw std::invalid_argument(o.path + ": the areas of a " + build::surfaceKindName(b.patches.params.surface) +
                                  " patch list need its structure (per-atom shares): run `area` on the structure");
    b.molecule.source = o.path;
    readingFile(o.path, "the atoms", [&] {
      b.molecule.atoms.resize(b.patches.params.atomCount);
      b.molecule.centers.resize(b.patches.params.atomCount);
      b.molecule.radii.assign(b.patches.params.atomCount, std::numeric_limits<double>::quiet_NaN());
    });
    for (std::size_t k = 0; k < b.molecule.atoms.size(); ++k) b.molecule.atoms[k].fileIndex = k;
    for (std::size_t k = 0; k < b.patches.convex.size(); ++k)
      b.molecule.radii[b.patches.convex.atom[k]] = b.patches.convex.radius[k];
    b.readSeconds = secondsSince(start);
    start = std::chrono::steady_clock::now();
    if (o.surface.dropCavities) b.patches = build::outerComponent(b.patches);
    b.buildSeconds = secondsSince(start);
    return b;
  }
  b.molecule = readInput(o.path, "", 0, o.read);
  b.readSeconds = secondsSince(start);
  start = std::chrono::steady_clock::now();
  b.patches = buildWithNotes(b.molecule, o.surface.request());
  b.buildSeconds = secondsSince(start);
  return b;
}

}  // namespace surftrace::tools

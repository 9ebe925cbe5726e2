// The stages "read" and "build" as every command runs them (`info`, `build` and `area` as well
// as `render` and `trajectory`): the surface options, the threads, the molecule read and its
// surface built. Nothing here draws an image, so that the commands that draw none do not load
// the renderers (surftrace.cpp).
#pragma once

#include <chrono>
#include <cstddef>
#include <memory>
#include <string>

#include <CLI/CLI.hpp>
#include <tbb/global_control.h>

#include "surftrace/molecule.hpp"
#include "surftrace/surface.hpp"

namespace surftrace::tools {

// Seconds of wall time since `start`, for the timings commands print.
inline double secondsSince(std::chrono::steady_clock::time_point start) {
  return std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
}

// --threads N: TBB runs at most N worker threads while the returned object lives (N = 0: no
// limit, all cores).
std::unique_ptr<tbb::global_control> limitThreads(int threads);

// --surface, --probe, --shrink, --drop-cavities: what surface to build.
struct SurfaceOptions {
  std::string surface = "ses";
  double probe = 1.4;
  double shrink = 0.5;
  bool dropCavities = false;
  double mergeWithin = build::kMinMergeDistance;
  CLI::Option* probeOption = nullptr;  // to tell a --probe given from its default

  build::SurfaceRequest request() const;
  bool probeGiven() const { return probeOption && probeOption->count() > 0; }
};
// Which surfaces --surface offers: all four (render, trajectory), or those with patches of
// their own to build (build, area: ses, mss).
enum class SurfaceChoice { Any, Built };
void addSurfaceOptions(CLI::App& cmd, SurfaceOptions& options, SurfaceChoice choice = SurfaceChoice::Any);
// --shrink: the MSS shrink factor in [kMinShrinkFactor, 1], default 0.5, with a readable error.
void addShrinkOption(CLI::App& cmd, double& shrink);

// Stage "build" for one structure: buildSurface, with what it left out (atoms inside others,
// merged ones) printed as notes on stderr.
build::PatchList buildWithNotes(const build::Molecule& molecule, const build::SurfaceRequest& request);

// Stage "read": the molecule of a structure file, or of one frame of a trajectory whose
// topology is `path` (when `trajectory` is not empty). Prints the reader's notes.
build::Molecule readInput(const std::string& path, const std::string& trajectory, std::size_t frame,
                          const build::ReadOptions& read);

}  // namespace surftrace::tools

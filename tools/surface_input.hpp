// What `build` and `area` read (a structure file, or for `area` a patch list) and the surface
// built from it: the pipeline's stages "read" and "build" for commands that make no image.
#pragma once

#include <string>

#include <CLI/CLI.hpp>

#include "surface_options.hpp"
#include "surftrace/molecule.hpp"
#include "surftrace/surface.hpp"

namespace surftrace::tools {

struct SurfaceInputOptions {
  std::string path;
  build::ReadOptions read;
  SurfaceOptions surface;
  int threads = 0;
};
// FILE, --surface (ses or mss), --probe, --shrink, --drop-cavities, --threads and the
// molecule options.
void addSurfaceInputOptions(CLI::App& cmd, SurfaceInputOptions& options);

struct Built {
  build::Molecule molecule;
  build::PatchList patches;
  double readSeconds = 0.0, buildSeconds = 0.0;
};
// The structure read and its surface built; a patch list FILE (told by its magic) is taken as
// it is, with the radii of its convex patches' atoms (its areas are those of the structure it
// was built from, with the probe it was built with). The caller limits the threads (--threads).
Built readAndBuild(const SurfaceInputOptions& options);

}  // namespace surftrace::tools

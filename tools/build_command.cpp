// `surftrace build`: the analytic patch list, written to a .stp file.
#include <cctype>
#include <chrono>
#include <filesystem>
#include <cstdio>
#include <memory>
#include <stdexcept>

#include "commands.hpp"
#include "surface_input.hpp"
#include "surftrace/files.hpp"
#include "surftrace/surface.hpp"

namespace surftrace::tools {
namespace {

struct BuildOptions : SurfaceInputOptions {
  std::string output;
};

// A patch list is SurfTrace's own format, and a file named like a mesh (.obj, .ply) or
// anything else would be taken for what it is not: the name must say .stp.
void checkPatchListName(const std::string& path) {
  if (build::isWrittenInPlace(path)) return;  // "-", /dev/null: no name to say what it holds
  std::string extension = std::filesystem::path(path).extension().string();
  for (char& c : extension) c = static_cast<char>(std::tolower(static_cast<unsigned char>(c)));
  if (extension == ".stp") return;
  std::filesystem::path suggestion = path;
  suggestion.replace_extension(".stp");
  throw std::invalid_argument(
      "-o " + path + ": `build` writes a patch list (.stp), SurfTrace's own file of the surface's analytic patches " +
      "(spheres, tori, concave triangles, hyperboloids, with their clipping planes) that `render`, `area` and `info` " +
      "read; it is no mesh or other format" + (extension.empty() ? "" : " (" + extension + ")") + ". Name it " +
      suggestion.string());
}

void runBuild(const BuildOptions& o) {
  if (isPatchListPath(o.path))
    throw std::invalid_argument(o.path + " is a patch list already (built, not a structure); `render` and `area` "
                                "take it as it is");
  checkPatchListName(o.output);
  build::prepareOutputPath(o.output, "-o", build::OutputContent::Binary);
  const auto limit = limitThreads(o.threads);
  const Built b = readAndBuild(o);
  // The atoms go along: the file derives the skin's patches from them (build/io/stp_file.hpp, version 3).
  const auto writeStart = std::chrono::steady_clock::now();
  build::writePatchList(o.output, b.patches, {b.molecule.centers, b.molecule.radii});
  const double writeSeconds = secondsSince(writeStart);
  const auto& p = b.patches;
  if (p.params.surface == build::SurfaceKind::Mss) {
    std::size_t count[build::kMssKindCount] = {};
    for (std::uint32_t k : p.mss.kind) ++count[k];
    std::printf("%s: %zu atoms, s = %g -> %zu MSS patches: %zu convex spheres, %zu edge hyperboloids, %zu face "
                "hyperboloids, %zu concave spheres; %zu mixed-cell planes\n",
                o.path.c_str(), b.molecule.size(), o.surface.shrink, p.mss.size(), count[0], count[1], count[2], count[3],
                p.cellPlanes.size());
  } else if (p.params.surface == build::SurfaceKind::Vdw) {
    std::printf("%s: %zu atoms, s = 1: the union of the van der Waals balls, %zu spheres\n", o.path.c_str(),
                b.molecule.size(), p.convex.size());
  } else {
    std::printf("%s: %zu atoms -> %zu convex, %zu toroidal, %zu concave patches, %zu clipping planes\n", o.path.c_str(),
              b.molecule.size(), p.convex.size(), p.tori.size(), p.concave.size(), p.clipPlanes.size());
  }
  std::printf("read %.1f ms, built %.1f ms, wrote %.1f ms: %s\n", b.readSeconds * 1e3, b.buildSeconds * 1e3,
              writeSeconds * 1e3, o.output.c_str());
}

}  // namespace

void addBuildCommand(CLI::App& app) {
  auto o = std::make_shared<BuildOptions>();
  auto* cmd = app.add_subcommand("build",
                                 "Build the analytic patch list and write it to a .stp file for `render --patches`: "
                                 "the SES (convex spheres, tori, concave triangles with their clipping planes) or, "
                                 "with --surface mss, the molecular skin (spheres and hyperboloids with their mixed "
                                 "cells)");
  addSurfaceInputOptions(*cmd, *o);
  cmd->add_option("-o,--output", o->output, "Patch-list file to write: FILE.stp, SurfTrace's own format (the analytic patches), read by `render`, "
                 "`area` and `info`; - for the standard output")->required();
  cmd->callback([o] { runBuild(*o); });
}

}  // namespace surftrace::tools

// The subcommands of `surftrace` and the option groups they share.
#pragma once

#include <new>
#include <stdexcept>
#include <string>

#include <CLI/CLI.hpp>

#include "surftrace/molecule.hpp"

namespace surftrace::tools {

// "surftrace 0.1.0": the program and its version (CMake's project version).
inline constexpr const char* kSoftware = "surftrace " SURFTRACE_VERSION;

// Adds the options that choose atoms and radii (model, chains, water, hydrogens, radii
// table, default radius, format) to `cmd`, storing them in `options`.
void addMoleculeOptions(CLI::App& cmd, build::ReadOptions& options);

// Prints what the reader assumed (Molecule::notes) on stderr, one "surftrace: note:" line each.
void printReadNotes(const build::Molecule& molecule);

// The message for a file whose contents did not fit in memory: the file, `what` it holds, and
// this machine's memory.
std::string outOfMemoryMessage(const std::string& file, const char* what);

// Runs `read`, which reads `file` (`what`: "the image", "the patch list", ...); a
// std::bad_alloc or std::length_error from it (a header that claims more than memory holds: a
// damaged or forged file, or one too large for this machine) becomes an error naming the file
// and what was too big, rather than "std::bad_alloc" alone.
template <class Read>
auto readingFile(const std::string& file, const char* what, Read&& read) -> decltype(read()) {
  try {
    return read();
  } catch (const std::bad_alloc&) {
    throw std::runtime_error(outOfMemoryMessage(file, what));
  } catch (const std::length_error&) {
    throw std::runtime_error(outOfMemoryMessage(file, what));
  }
}

void addInfoCommand(CLI::App& app);
void addBuildCommand(CLI::App& app);
void addAreaCommand(CLI::App& app);
// `mesh`: a triangle mesh of the exact surface with a certified error (mesh_command.cpp).
void addMeshCommand(CLI::App& app);
// `commandLine` is the whole invocation, recorded in every image's metadata.
void addRenderCommand(CLI::App& app, const std::string& commandLine);
void addCompareCommand(CLI::App& app);
// `trajectory`: a surface frame after frame from a trajectory (trajectory_command.cpp).
void addTrajectoryCommand(CLI::App& app, const std::string& commandLine);

}  // namespace surftrace::tools

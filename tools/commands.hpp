// The subcommands of `surftrace` and the option groups they share.
#pragma once

#include <string>

#include <CLI/CLI.hpp>

#include "build/io/molecule.hpp"

namespace surftrace::tools {

// "surftrace 0.1.0": the program and its version (CMake's project version).
inline constexpr const char* kSoftware = "surftrace " SURFTRACE_VERSION;

// Adds the options that choose atoms and radii (model, chains, water, hydrogens, radii
// table, default radius, format) to `cmd`, storing them in `options`.
void addMoleculeOptions(CLI::App& cmd, build::ReadOptions& options);

// Prints what the reader assumed (Molecule::notes) on stderr, one "surftrace: note:" line each.
void printReadNotes(const build::Molecule& molecule);

// Whether FILE is a patch list (.stp) rather than a structure: it starts with the magic
// "SURFTRCE", or it is named .stp (then reading it explains what is wrong).
bool isPatchListInput(const std::string& path);

void addInfoCommand(CLI::App& app);
void addBuildCommand(CLI::App& app);
void addAreaCommand(CLI::App& app);
// `commandLine` is the whole invocation, recorded in every image's metadata.
void addRenderCommand(CLI::App& app, const std::string& commandLine);
void addCompareCommand(CLI::App& app);
// `trajectory`: a surface frame after frame from a trajectory (trajectory_command.cpp).
void addTrajectoryCommand(CLI::App& app, const std::string& commandLine);

}  // namespace surftrace::tools

// The top-level `surftrace` command line that both programs share: its description, --version,
// and how a parsed command ends (exit codes, standard output checked).
#pragma once

#include <CLI/CLI.hpp>

namespace surftrace::tools {

// The name of the program that runs the image commands (render, trajectory, compare): it
// lies beside `surftrace`, which hands those commands to it (surftrace.cpp).
inline constexpr const char* kImageProgram = "surftrace_images";

// The app with its description and --version, and no subcommands yet.
void describeApp(CLI::App& app);

// Parses and runs the command line: 0 done, 1 any error (printed), or the command's own
// status; CLI11's parse errors are printed and exit 0 (--help, --version) or 1.
int runApp(CLI::App& app, int argc, char** argv);

}  // namespace surftrace::tools

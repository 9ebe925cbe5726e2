// surftrace_images: every `surftrace` command, the image commands (render, trajectory,
// compare) among them. `surftrace` runs info, build and area itself and hands every other
// command line to this program unchanged (surftrace.cpp), so that those three do not load
// OpenImageIO, Embree and EGL with their hundreds of libraries.
#include <csignal>
#include <string>

#include <CLI/CLI.hpp>

#include "command_line.hpp"
#include "commands.hpp"

int main(int argc, char** argv) {
  // A closed pipe is an error the commands report, not a silent death (surftrace.cpp).
  std::signal(SIGPIPE, SIG_IGN);
  CLI::App app;
  surftrace::tools::describeApp(app);
  surftrace::tools::addInfoCommand(app);
  surftrace::tools::addBuildCommand(app);
  surftrace::tools::addAreaCommand(app);
  surftrace::tools::addMeshCommand(app);
  std::string commandLine;
  for (int i = 0; i < argc; ++i) commandLine += (i ? " " : "") + std::string(argv[i]);
  surftrace::tools::addRenderCommand(app, commandLine);
  surftrace::tools::addTrajectoryCommand(app, commandLine);
  surftrace::tools::addCompareCommand(app);
  return surftrace::tools::runApp(app, argc, argv);
}

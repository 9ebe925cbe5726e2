// surftrace: the command-line front end. Each subcommand lives in its own *_command.cpp.
//
// `info`, `build` and `area` run in this program, which links no image library; every other
// command line (render, trajectory, compare, --help, --version, a mistyped command) is handed
// unchanged to surftrace_images beside it, which has every command. Loading OpenImageIO (with
// OpenCV, FFmpeg, GDAL behind it), Embree and EGL, about 250 libraries, took 0.25 s of CPU
// before any command ran; `info` on a small protein now starts in a few milliseconds (README,
// Benchmarks). A second program rather than a dlopen()ed module: no interface to keep stable
// between the two, each is an ordinary executable, and exec costs about a millisecond.
#include <unistd.h>

#include <cerrno>
#include <cstdio>
#include <cstring>
#include <filesystem>
#include <string>
#include <string_view>
#include <system_error>

#include <CLI/CLI.hpp>

#include "command_line.hpp"
#include "commands.hpp"

namespace {

namespace fs = std::filesystem;

// Runs surftrace_images from this program's own folder with the same arguments (argv[0]
// included, so that the command line recorded in images is the one typed). Returns only when
// it could not: the reason, naming the path.
std::string runImageProgram(char** argv) {
  std::error_code ec;
  const fs::path self = fs::read_symlink("/proc/self/exe", ec);
  if (ec) return "cannot find this program's own folder (/proc/self/exe: " + ec.message() + ")";
  const fs::path program = self.parent_path() / surftrace::tools::kImageProgram;
  execv(program.c_str(), argv);
  return program.string() + ": " + std::strerror(errno);
}

bool isImageCommand(std::string_view command) {
  return command == "render" || command == "trajectory" || command == "compare";
}

}  // namespace

int main(int argc, char** argv) {
  const std::string_view command = argc > 1 ? argv[1] : "";
  std::string missing;
  if (command != "info" && command != "build" && command != "area") {
    missing = runImageProgram(argv);
    if (isImageCommand(command)) {
      std::fprintf(stderr,
                   "surftrace: error: `surftrace %s` runs in the program %s, which must lie beside surftrace "
                   "(building surftrace builds both), but it cannot be run: %s\n",
                   argv[1], surftrace::tools::kImageProgram, missing.c_str());
      return 1;
    }
  }
  // info, build, area; or --help, --version and errors when surftrace_images is missing.
  CLI::App app;
  surftrace::tools::describeApp(app);
  if (!missing.empty())
    app.footer(std::string("render, trajectory and compare are not available: they run in ") +
               surftrace::tools::kImageProgram + ", which cannot be run (" + missing + ").");
  surftrace::tools::addInfoCommand(app);
  surftrace::tools::addBuildCommand(app);
  surftrace::tools::addAreaCommand(app);
  return surftrace::tools::runApp(app, argc, argv);
}

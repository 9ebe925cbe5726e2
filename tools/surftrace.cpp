// surftrace: the command-line front end. Each subcommand lives in its own *_command.cpp.
//
// `info`, `build`, `area` and `mesh` run in this program, which links no image library; every other
// command line (render, trajectory, compare, --help, --version, a mistyped command) is handed
// unchanged to surftrace_images (beside it in the build tree, in libexec/surftrace/ once
// installed), which has every command. Loading OpenImageIO (with
// OpenCV, FFmpeg, GDAL behind it), Embree and EGL, about 250 libraries, took 0.25 s of CPU
// before any command ran; `info` on a small protein now starts in a few milliseconds (README,
// Benchmarks). A second program rather than a dlopen()ed module: no interface to keep stable
// between the two, each is an ordinary executable, and exec costs about a millisecond.
#include <unistd.h>

#include <cerrno>
#include <csignal>
#include <cstdio>
#include <cstring>
#include <filesystem>
#include <string>
#include <string_view>
#include <system_error>
#include <vector>

#include <CLI/CLI.hpp>

#include "command_line.hpp"
#include "commands.hpp"

namespace {

namespace fs = std::filesystem;

// Where surftrace_images may lie, relative to this program's own file: beside it (the build
// tree, build/release/tools/), then where `cmake --install` puts it (PREFIX/libexec/surftrace
// for PREFIX/bin/surftrace; the relative path comes from tools/CMakeLists.txt). /proc/self/exe
// is the real file, so a symbolic link to surftrace elsewhere on PATH finds it too.
std::vector<fs::path> imageProgramCandidates(const fs::path& self) {
  const fs::path folder = self.parent_path();
  return {folder / surftrace::tools::kImageProgram,
          (folder / SURFTRACE_IMAGE_PROGRAM_FROM_BIN / surftrace::tools::kImageProgram).lexically_normal()};
}

// Runs surftrace_images with the same arguments (argv[0] included, so that the command line
// recorded in images is the one typed). Returns only when it could not: each place looked in,
// with the reason.
std::string runImageProgram(char** argv) {
  std::error_code ec;
  const fs::path self = fs::read_symlink("/proc/self/exe", ec);
  if (ec) return "cannot find this program's own folder (/proc/self/exe: " + ec.message() + ")";
  std::string tried;
  for (const fs::path& program : imageProgramCandidates(self)) {
    execv(program.c_str(), argv);
    tried += (tried.empty() ? "" : "; ") + program.string() + ": " + std::strerror(errno);
  }
  return tried;
}

// What to do when surftrace_images is missing: the two layouts in which surftrace finds it.
constexpr const char* kHowToInstall =
    "Run surftrace from its build folder (build/release/tools/, where both programs are built), or install both "
    "with `cmake --install build/release --prefix PREFIX` (PREFIX/bin/surftrace and "
    "PREFIX/" SURFTRACE_IMAGE_PROGRAM_DIR "/surftrace_images); copying surftrace alone is not enough";

bool isImageCommand(std::string_view command) {
  return command == "render" || command == "trajectory" || command == "compare";
}

}  // namespace

int main(int argc, char** argv) {
  // A reader that closes the pipe early (`surftrace area ... | head`) makes a write fail with
  // EPIPE, which the commands report (exit 1, naming the standard output and the reason),
  // rather than kill the program silently (exit 141). Inherited by surftrace_images.
  std::signal(SIGPIPE, SIG_IGN);
  const std::string_view command = argc > 1 ? argv[1] : "";
  std::string missing;
  if (command != "info" && command != "build" && command != "area" && command != "mesh") {
    missing = runImageProgram(argv);
    if (isImageCommand(command)) {
      std::fprintf(stderr,
                   "surftrace: error: `surftrace %s` runs in the program %s, which could not be run from where "
                   "surftrace looks for it (%s). %s\n",
                   argv[1], surftrace::tools::kImageProgram, missing.c_str(), kHowToInstall);
      return 1;
    }
  }
  // info, build, area, mesh; or --help, --version and errors when surftrace_images is missing.
  CLI::App app;
  surftrace::tools::describeApp(app);
  if (!missing.empty())
    app.footer(std::string("render, trajectory and compare are not available: they run in ") +
               surftrace::tools::kImageProgram + ", which could not be run (" + missing + "). " + kHowToInstall + ".");
  surftrace::tools::addInfoCommand(app);
  surftrace::tools::addBuildCommand(app);
  surftrace::tools::addAreaCommand(app);
  surftrace::tools::addMeshCommand(app);
  return surftrace::tools::runApp(app, argc, argv);
}

// `surftrace` runs info, build and area without loading the image libraries (OpenImageIO,
// Embree, EGL), and hands every other command line to surftrace_images beside it
// (tools/surftrace.cpp): the split changes what is loaded, never what a command does.
#include <filesystem>
#include <fstream>
#include <iterator>
#include <string>
#include <unistd.h>

#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

#include "run_tool.hpp"
#include "temp_dir.hpp"

namespace surftrace::tools::test {
namespace {

namespace fs = std::filesystem;

const std::string kCrambin = std::string(SURFTRACE_TEST_DATA) + "/structures/1crn.pdb";
const fs::path kTool = SURFTRACE_TOOL;
const fs::path kImageTool = kTool.parent_path() / "surftrace_images";

fs::path freshDirectory(const std::string& name) {
  return ::surftrace::test::freshTempDir(name);
}

std::string bytesOf(const fs::path& path) {
  std::ifstream in(path, std::ios::binary);
  return std::string(std::istreambuf_iterator<char>(in), {});
}

// `program args`, with stderr joined to stdout. (Built with +=: GCC 12 warns, wrongly, of an
// overlapping copy in "literal" + std::string&&, -Wrestrict.)
Result runProgram(const fs::path& program, const std::string& args, const std::string& environment = "") {
  std::string line = environment;
  line += " '";
  line += program.string();
  line += "' ";
  line += args;
  line += " 2>&1";
  return runShell(line);
}

// The shared libraries the dynamic loader opened for one command (glibc's LD_DEBUG=libs lines
// "find library=libX.so [0]; searching" on stderr), with what the command printed.
Result withLoaderLog(const fs::path& program, const std::string& args) {
  return runProgram(program, args, "LD_DEBUG=libs");
}

TEST(Startup, SurfaceCommandsLoadNoImageLibrary) {
  const fs::path dir = freshDirectory("libs");
  for (const std::string& args : {"info " + kCrambin, "area " + kCrambin + " --format csv",
                                  "build " + kCrambin + " -o " + (dir / "1crn.stp").string()}) {
    const Result r = withLoaderLog(kTool, args);
    ASSERT_EQ(r.status, 0) << args << "\n" << r.output;
    // The loader log is there (TBB is needed by every command), and names no image library.
    EXPECT_NE(r.output.find("library=libtbb"), std::string::npos) << args << ": no loader log?\n" << r.output;
    for (const char* library : {"library=libOpenImageIO", "library=libembree", "library=libEGL", "library=libOpenGL"})
      EXPECT_EQ(r.output.find(library), std::string::npos) << args << " loaded " << library;
  }
  // The image commands do load them: the log above would have shown them.
  const Result render = withLoaderLog(kTool, "render --help");
  ASSERT_EQ(render.status, 0) << render.output;
  EXPECT_NE(render.output.find("library=libOpenImageIO"), std::string::npos) << render.output;
  fs::remove_all(dir);
}

// A copy of `surftrace` alone in a folder: info, build and area work as the whole program's do,
// --help still answers, and the image commands stop with an error that names the missing
// program, every place it was looked for (beside surftrace; ../libexec/surftrace, where
// `cmake --install` puts it) and how to install the two.
TEST(Startup, SurfaceCommandsRunWithoutTheImageProgram) {
  const fs::path dir = freshDirectory("alone");
  const fs::path alone = dir / "surftrace";
  fs::copy_file(kTool, alone);
  const auto both = [&](const std::string& args) {
    const Result a = runProgram(alone, args);
    const Result b = runProgram(kImageTool, args);
    EXPECT_EQ(a.status, 0) << args << "\n" << a.output;
    EXPECT_EQ(b.status, 0) << args << "\n" << b.output;
    return std::pair{nlohmann::json::parse(a.output, nullptr, false), nlohmann::json::parse(b.output, nullptr, false)};
  };
  auto [info, infoWhole] = both("info --json " + kCrambin);
  ASSERT_FALSE(info.is_discarded());
  EXPECT_EQ(info["atoms"], 327);
  info.erase("read_seconds");
  infoWhole.erase("read_seconds");
  EXPECT_EQ(info, infoWhole);
  const auto [area, areaWhole] = both("area --format json " + kCrambin);
  ASSERT_FALSE(area.is_discarded());
  EXPECT_EQ(area["ses"], areaWhole["ses"]);
  EXPECT_EQ(area["sas"], areaWhole["sas"]);
  EXPECT_EQ(runProgram(alone, "build " + kCrambin + " -o " + (dir / "a.stp").string()).status, 0);
  EXPECT_EQ(runProgram(kImageTool, "build " + kCrambin + " -o " + (dir / "b.stp").string()).status, 0);
  EXPECT_EQ(bytesOf(dir / "a.stp"), bytesOf(dir / "b.stp"));
  EXPECT_GT(bytesOf(dir / "a.stp").size(), 0u);

  const Result help = runProgram(alone, "--help");
  EXPECT_EQ(help.status, 0) << help.output;
  EXPECT_NE(help.output.find("render, trajectory and compare are not available"), std::string::npos) << help.output;
  std::string missing = (dir / "surftrace_images").string();
  missing += ": No such file or directory";
  std::string missingInstalled = (dir.parent_path() / "libexec" / "surftrace" / "surftrace_images").string();
  missingInstalled += ": No such file or directory";
  const std::string howToInstall = "install both with `cmake --install build/release --prefix PREFIX` "
                                   "(PREFIX/bin/surftrace and PREFIX/libexec/surftrace/surftrace_images)";
  EXPECT_NE(help.output.find(howToInstall), std::string::npos) << help.output;
  for (const std::string command : {"render", "trajectory", "compare"}) {
    const Result r = runProgram(alone, command + " " + kCrambin + " -o x.png");
    EXPECT_EQ(r.status, 1) << r.output;
    std::string error = "surftrace: error: `surftrace ";
    error += command;
    error += "` runs in the program surftrace_images";
    EXPECT_NE(r.output.find(error), std::string::npos) << r.output;
    EXPECT_NE(r.output.find(missing), std::string::npos) << r.output;
    EXPECT_NE(r.output.find(missingInstalled), std::string::npos) << r.output;
    EXPECT_NE(r.output.find(howToInstall), std::string::npos) << r.output;
  }
  fs::remove_all(dir);
}

// Through `surftrace`, the image commands, --help and --version are surftrace_images's own,
// exit status included.
TEST(Startup, OtherCommandLinesAreTheImageProgramsOwn) {
  for (const std::string args : {"--help", "--version", "render --help", "compare --help", "trajectory --help",
                                 "no-such-command", "render --no-such-option x.pdb -o x.png"}) {
    const Result front = runProgram(kTool, args);
    const Result whole = runProgram(kImageTool, args);
    EXPECT_EQ(front.status, whole.status) << args;
    EXPECT_EQ(front.output, whole.output) << args;
  }
}

}  // namespace
}  // namespace surftrace::tools::test

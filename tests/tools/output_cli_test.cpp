// Nothing lost (issue 18): every output of the `surftrace` program is whole or an error. A
// full disk is simulated with a file-size limit (`ulimit -f`, SIGXFSZ ignored: every write
// past the limit fails with EFBIG, as ENOSPC would) and with /dev/full for standard output.
#include <cctype>
#include <filesystem>
#include <fstream>
#include <string>
#include <vector>

#include <gtest/gtest.h>

#include "run_tool.hpp"

namespace {

namespace fs = std::filesystem;

std::string data(const std::string& file) { return std::string(SURFTRACE_TEST_DATA) + "/" + file; }

using Shell = surftrace::tools::test::Result;

// Runs `script` under bash, `surftrace` standing for the program under test; stdout and stderr
// together.
Shell shell(const std::string& script) {
  return surftrace::tools::test::runShell("bash -c 'surftrace() { \"" SURFTRACE_TOOL "\" \"$@\"; }; " + script +
                                          "' 2>&1");
}

// A fresh folder for one test.
fs::path folder(const std::string& name) {
  const fs::path dir = fs::path(testing::TempDir()) / ("surftrace_output_" + name);
  fs::remove_all(dir);
  fs::create_directories(dir);
  return dir;
}

// Files left in `dir`, temporary ones included.
std::size_t filesIn(const fs::path& dir) {
  std::size_t n = 0;
  for (const auto& entry : fs::directory_iterator(dir)) n += entry.is_regular_file();
  return n;
}

TEST(Output, StandardOutputOnAFullDiskIsAnError) {
  for (const std::string& command : {"info " + data("structures/1crn.pdb"), "area " + data("structures/1crn.pdb"),
                                     "area --format csv " + data("structures/1crn.pdb")}) {
    const Shell r = shell("surftrace " + command + " > /dev/full");
    EXPECT_EQ(r.status, 1) << command << "\n" << r.output;
    EXPECT_NE(r.output.find("standard output"), std::string::npos) << r.output;
    EXPECT_NE(r.output.find("No space left on device"), std::string::npos) << r.output;
  }
}

TEST(Output, FilesOnAFullDiskAreErrorsAndLeaveNothing) {
  const fs::path dir = folder("full");
  const std::string mol = data("structures/1crn.pdb");
  const std::string limit = "trap \"\" XFSZ; ulimit -f 0; ";
  struct Case {
    std::string command, file;
  };
  const Case cases[] = {
      {"render " + mol + " --size 32x32 --quiet -o " + (dir / "a.png").string(), "a.png"},
      {"render " + mol + " --size 32x32 --quiet --exr " + (dir / "a.exr").string(), "a.exr"},
      {"build " + mol + " -o " + (dir / "a.stp").string(), "a.stp"},
  };
  for (const Case& c : cases) {
    const Shell r = shell(limit + "surftrace " + c.command);
    EXPECT_EQ(r.status, 1) << c.command << "\n" << r.output;
    EXPECT_NE(r.output.find((dir / c.file).string()), std::string::npos) << r.output;
    EXPECT_NE(r.output.find("File too large"), std::string::npos) << r.output;
    EXPECT_EQ(r.output.find("partial"), std::string::npos) << "the error names the user's file\n" << r.output;
    EXPECT_EQ(r.output.find("wrote"), std::string::npos) << r.output;
    EXPECT_EQ(filesIn(dir), 0u) << c.command << ": a file or a temporary one was left";
  }
  // compare --report and --diff, on images written without the limit.
  const std::string exr = (dir / "ref.exr").string();
  ASSERT_EQ(shell("surftrace render " + mol + " --size 32x32 --quiet --exr " + exr).status, 0);
  for (const std::string& option : {"--report " + (dir / "r.json").string(), "--diff " + (dir / "d.png").string()}) {
    const Shell r = shell(limit + "surftrace compare " + exr + " " + exr + " " + option);
    EXPECT_EQ(r.status, 1) << option << "\n" << r.output;
    EXPECT_NE(r.output.find("File too large"), std::string::npos) << r.output;
    EXPECT_EQ(r.output.find("PASS"), std::string::npos) << r.output;
    EXPECT_EQ(filesIn(dir), 1u) << option;
  }
}

TEST(Output, PathsAreCheckedBeforeTheWork) {
  const fs::path dir = folder("paths");
  const std::string mol = data("structures/1crn.pdb");
  // A missing folder is made.
  const fs::path nested = dir / "new" / "deeper" / "a.png";
  const Shell made = shell("surftrace render " + mol + " --size 16x16 --quiet -o " + nested.string());
  EXPECT_EQ(made.status, 0) << made.output;
  EXPECT_TRUE(fs::exists(nested));
  // A folder that cannot be: a file stands where it would go. Said before rendering (no
  // "rendered" line) with the folder named.
  const fs::path blocker = dir / "file";
  ASSERT_EQ(shell("touch " + blocker.string()).status, 0);
  for (const std::string& command :
       {"render " + mol + " --size 16x16 -o " + (blocker / "a.png").string(),
        "render " + mol + " --size 16x16 --exr " + (blocker / "a.exr").string(),
        "build " + mol + " -o " + (blocker / "a.stp").string(),
        "compare " + nested.string() + " " + nested.string() + " --report " + (blocker / "r.json").string()}) {
    const Shell r = shell("surftrace " + command);
    EXPECT_EQ(r.status, 1) << command << "\n" << r.output;
    EXPECT_NE(r.output.find(blocker.string()), std::string::npos) << r.output;
    EXPECT_NE(r.output.find("not a folder"), std::string::npos) << r.output;
  }
  // An output that is a folder.
  const Shell folderOut = shell("surftrace render " + mol + " --size 16x16 -o " + dir.string());
  EXPECT_EQ(folderOut.status, 1) << folderOut.output;
  EXPECT_NE(folderOut.output.find("is a folder"), std::string::npos) << folderOut.output;
}

// On a terminal of 50 columns (script(1) gives the program one), the progress bar of `area
// TOPOLOGY TRAJECTORY` never wraps, and each CSV row starts a line of its own instead of
// landing on the bar's line.
TEST(Output, ProgressBarFitsTheTerminalAndKeepsRowsApart) {
  const std::string inner = "stty cols 50 rows 20; \\\"" SURFTRACE_TOOL "\\\" area " +
                            data("trajectories/adk_dims/adk.psf.gz") + " " +
                            data("trajectories/adk_dims/adk_dims.dcd") + " --frames 0:6 --format csv";
  const Shell r = shell("script -qec \"" + inner + "\" /dev/null");
  ASSERT_EQ(r.status, 0) << r.output;
  std::size_t rows = 0, bars = 0;
  std::size_t start = 0;
  while (start < r.output.size()) {
    std::size_t end = r.output.find('\n', start);
    if (end == std::string::npos) end = r.output.size();
    std::string line = r.output.substr(start, end - start);
    start = end + 1;
    // What the terminal shows of the line: the text after its last carriage return, without
    // the erase-to-end-of-line codes.
    std::vector<std::string> segments;
    for (std::size_t at = 0; at <= line.size();) {
      std::size_t cr = line.find('\r', at);
      if (cr == std::string::npos) cr = line.size();
      std::string segment = line.substr(at, cr - at);
      for (std::size_t e; (e = segment.find("\033[K")) != std::string::npos;) segment.erase(e, 3);
      segments.push_back(segment);
      at = cr + 1;
    }
    for (const std::string& segment : segments)
      if (const std::size_t eta = segment.find("ETA "); eta != std::string::npos) {
        ++bars;
        EXPECT_LE(segment.size(), 49u) << "the bar wraps a 50-column terminal: '" << segment << "'";
        // Nothing follows the bar's ETA mm:ss on its line (no row glued to it).
        EXPECT_EQ(segment.find_first_not_of(' ', eta + 9), std::string::npos)
            << "a line mixes the bar and a row: '" << segment << "'";
      }
    std::string shown;
    for (auto it = segments.rbegin(); it != segments.rend(); ++it)
      if (!it->empty()) {
        shown = *it;
        break;
      }
    if (!shown.empty() && std::isdigit(static_cast<unsigned char>(shown[0])) && shown.find(',') != std::string::npos) {
      ++rows;
      EXPECT_EQ(shown.find("ETA"), std::string::npos) << shown;
    }
  }
  EXPECT_EQ(rows, 6u) << r.output;
  EXPECT_GE(bars, 1u) << "no progress bar was drawn on the terminal\n" << r.output;
}

// `trajectory`: a full disk stops the run with exit 1 and leaves no partial frame; --resume
// re-renders a frame cut short (a PNG without its IEND) and appends to the timings.
TEST(Output, TrajectoryFramesAreWholeAndResumeChecksThem) {
  const fs::path dir = folder("trajectory");
  const std::string inputs = data("trajectories/adk_dims/adk.psf.gz") + " " + data("trajectories/adk_dims/adk_dims.dcd");
  const std::string frames = "surftrace trajectory " + inputs + " --frames 0:4 --size 16x16 --quiet -o " +
                             (dir / "f%02d.png").string();
  const std::string run = frames + " --timings " + (dir / "t.csv").string();
  const Shell full = shell("trap \"\" XFSZ; ulimit -f 0; " + frames);
  EXPECT_EQ(full.status, 1) << full.output;
  EXPECT_NE(full.output.find("File too large"), std::string::npos) << full.output;
  EXPECT_EQ(filesIn(dir), 0u) << "a frame or a temporary file was left";
  const Shell fullTimings = shell("trap \"\" XFSZ; ulimit -f 0; " + run);
  EXPECT_EQ(fullTimings.status, 1) << fullTimings.output;
  EXPECT_NE(fullTimings.output.find("--timings"), std::string::npos) << fullTimings.output;
  fs::remove(dir / "t.csv");

  const Shell first = shell(run);
  ASSERT_EQ(first.status, 0) << first.output;
  // Frame 2 cut short, as a copy that stopped early leaves it.
  fs::resize_file(dir / "f02.png", 20);
  fs::remove(dir / "f03.png");
  const Shell again = shell(run + " --resume");
  ASSERT_EQ(again.status, 0) << again.output;
  EXPECT_NE(again.output.find("2 to render"), std::string::npos) << again.output;
  EXPECT_NE(again.output.find("2 done already"), std::string::npos) << again.output;
  EXPECT_GT(fs::file_size(dir / "f02.png"), 20u);
  // The timings hold the header once and a row for every frame rendered by either run.
  std::ifstream csv(dir / "t.csv");
  std::string line;
  std::vector<std::string> rows;
  while (std::getline(csv, line)) rows.push_back(line);
  ASSERT_EQ(rows.size(), 1u + 4u + 2u);
  EXPECT_EQ(rows[0].rfind("frame,", 0), 0u);
  for (std::size_t k = 1; k < rows.size(); ++k) EXPECT_TRUE(std::isdigit(static_cast<unsigned char>(rows[k][0]))) << rows[k];
}

// Parse errors exit 1, as --help says; --help itself 0.
TEST(Output, ParseErrorsExitOne) {
  EXPECT_EQ(shell("surftrace render --no-such-option x.pdb -o x.png").status, 1);
  EXPECT_EQ(shell("surftrace area").status, 1);
  EXPECT_EQ(shell("surftrace render a b c").status, 1);
  EXPECT_EQ(shell("surftrace --help > /dev/null").status, 0);
  EXPECT_EQ(shell("surftrace render --help > /dev/null").status, 0);
}

}  // namespace

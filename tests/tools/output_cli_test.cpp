// Nothing lost: every output of the `surftrace` program is whole or an error. A full disk is
// simulated with a file-size limit (`ulimit -f`, SIGXFSZ ignored: every write past the limit
// fails with EFBIG, as ENOSPC would) and with /dev/full for standard output. Writing never
// harms what a path names: devices (mknod copies of /dev/null and /dev/full in a temporary
// folder, as root; never the machine's own), FIFOs and links; `-` is the standard output, and a
// reader that closes it early is an error with its reason, not a silent SIGPIPE.
#include <fcntl.h>
#include <poll.h>
#include <sys/stat.h>
#include <sys/sysmacros.h>
#include <sys/wait.h>
#include <unistd.h>

#include <cctype>
#include <cerrno>
#include <csignal>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <string>
#include <thread>
#include <vector>

#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

#include "fifo_reader.hpp"
#include "run_tool.hpp"
#include "temp_dir.hpp"

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
  return ::surftrace::test::freshTempDir(name);
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

// --- What a path names is kept ---

std::string contents(const fs::path& path) {
  std::ifstream in(path, std::ios::binary);
  std::ostringstream text;
  text << in.rdbuf();
  return text.str();
}

bool isDevice(const fs::path& path, unsigned major, unsigned minor) {
  struct stat st;
  return ::lstat(path.c_str(), &st) == 0 && S_ISCHR(st.st_mode) && ::major(st.st_rdev) == major &&
         ::minor(st.st_rdev) == minor;
}

// A reference EXR of 1CRN at 32x32 in `dir`, for compare.
std::string referenceExr(const fs::path& dir) {
  const std::string exr = (dir / "ref.exr").string();
  const Shell r = shell("surftrace render " + data("structures/1crn.pdb") + " --size 32x32 --quiet --exr " + exr);
  EXPECT_EQ(r.status, 0) << r.output;
  return exr;
}

// The four outputs the issue names, each with what it writes to `out`.
std::vector<std::string> commandsWriting(const std::string& out, const std::string& exr) {
  const std::string mol = data("structures/1crn.pdb");
  return {"render " + mol + " --size 16x16 --quiet -o " + fs::path(exr).replace_filename("r.png").string() +
              " --camera-out " + out,
          "build " + mol + " -o " + out, "info " + mol + " --xyzr " + out,
          "compare " + exr + " " + exr + " --report " + out};
}

// Copies of /dev/null and /dev/full (made with mknod in a temporary folder) stay devices:
// /dev/null takes every output, /dev/full makes each an error that names it.
TEST(Output, DevicesAreWrittenInPlace) {
  const fs::path dir = folder("devices");
  const fs::path null = dir / "null", full = dir / "full";
  if (::mknod(null.c_str(), S_IFCHR | 0666, makedev(1, 3)) != 0 || ::mknod(full.c_str(), S_IFCHR | 0666, makedev(1, 7)) != 0)
    GTEST_SKIP() << "mknod needs root: " << std::strerror(errno);
  const std::string exr = referenceExr(dir);
  for (const std::string& command : commandsWriting(null.string(), exr)) {
    const Shell r = shell("surftrace " + command);
    EXPECT_EQ(r.status, 0) << command << "\n" << r.output;
    EXPECT_TRUE(isDevice(null, 1, 3)) << command << ": the null device was replaced";
  }
  for (const std::string& command : commandsWriting(full.string(), exr)) {
    const Shell r = shell("surftrace " + command);
    EXPECT_EQ(r.status, 1) << command << "\n" << r.output;
    EXPECT_NE(r.output.find(full.string() + ": write failed: No space left on device"), std::string::npos)
        << command << "\n" << r.output;
    EXPECT_TRUE(isDevice(full, 1, 7)) << command << ": the full device was replaced";
  }
  for (const auto& entry : fs::directory_iterator(dir))
    EXPECT_EQ(entry.path().filename().string().find(".partial-"), std::string::npos) << entry.path();
}

// A FIFO gets the bytes (here info --xyzr's, the same as a file gets) and stays a FIFO.
TEST(Output, AFifoGetsTheBytes) {
  const fs::path dir = folder("fifo");
  const fs::path fifo = dir / "atoms.fifo";
  ASSERT_EQ(::mkfifo(fifo.c_str(), 0666), 0) << std::strerror(errno);
  const std::string mol = data("structures/1crn.pdb");
  ASSERT_EQ(shell("surftrace info " + mol + " --xyzr " + (dir / "atoms.xyzr").string()).status, 0);
  surftrace::test::FifoReader reader(fifo);
  ASSERT_TRUE(reader.opened()) << std::strerror(errno);
  const Shell r = shell("surftrace info " + mol + " --xyzr " + fifo.string());
  const std::string& received = reader.finish();
  EXPECT_EQ(r.status, 0) << r.output;
  const std::string expected = contents(dir / "atoms.xyzr");
  EXPECT_FALSE(expected.empty());
  EXPECT_TRUE(received == expected) << "the reader got " << received.size() << " bytes of " << expected.size();
  struct stat st;
  ASSERT_EQ(::lstat(fifo.c_str(), &st), 0);
  EXPECT_TRUE(S_ISFIFO(st.st_mode)) << "the FIFO was replaced by a file";
  // A pipe named through /dev/fd (bash's >(...) gives such names): the same bytes.
  const Shell piped = shell("surftrace info " + mol + " --xyzr /dev/fd/3 3>&1 >/dev/null | cat > " +
                            (dir / "piped.xyzr").string() + "; exit ${PIPESTATUS[0]}");
  EXPECT_EQ(piped.status, 0) << piped.output;
  EXPECT_TRUE(contents(dir / "piped.xyzr") == expected) << contents(dir / "piped.xyzr").substr(0, 200);
}

// A symbolic link (relative, absolute, or a chain of them) stays a link, and its final target
// gets the new file.
TEST(Output, SymbolicLinksStayLinksAndTheirTargetIsReplaced) {
  const fs::path dir = folder("links");
  fs::create_directories(dir / "elsewhere");
  fs::create_directories(dir / "links");
  const fs::path target = dir / "elsewhere" / "out";
  const std::string exr = referenceExr(dir);
  // What each command writes starts with (patch list magic, JSON, numbers).
  const std::vector<std::string> starts = {"{", "SURFTRCE", "", "{"};
  int round = 0;
  for (const std::string kind : {"relative", "absolute", "chain"}) {
    // Named .stp, as `build -o` wants.
    const fs::path link = dir / "links" / (kind + "-" + std::to_string(round) + ".stp");
    if (kind == "relative") {
      fs::create_symlink("../elsewhere/out", link);
    } else if (kind == "absolute") {
      fs::create_symlink(target, link);
    } else {
      fs::create_symlink("../elsewhere/out", dir / "links" / "middle");
      fs::create_symlink("middle", link);
    }
    const std::vector<std::string> commands = commandsWriting(link.string(), exr);
    for (std::size_t c = 0; c < commands.size(); ++c) {
      std::ofstream(target) << "old";
      const Shell r = shell("surftrace " + commands[c]);
      EXPECT_EQ(r.status, 0) << commands[c] << "\n" << r.output;
      EXPECT_TRUE(fs::is_symlink(link)) << commands[c] << ": the link was replaced by a file";
      if (kind == "chain") {
        EXPECT_TRUE(fs::is_symlink(dir / "links" / "middle"));
      }
      const std::string written = contents(target);
      EXPECT_NE(written, "old") << commands[c] << ": the link's target kept the old data";
      EXPECT_EQ(written.rfind(starts[c], 0), 0u) << commands[c] << "\n" << written.substr(0, 40);
    }
    ++round;
  }
  for (const fs::path& folder : {dir / "links", dir / "elsewhere"})
    for (const auto& entry : fs::directory_iterator(folder))
      EXPECT_EQ(entry.path().filename().string().find(".partial-"), std::string::npos) << entry.path();
}

// A run killed during its write (kill -9) leaves a hidden temporary; the next run that writes
// the same file removes it.
TEST(Output, AKilledRunsTemporaryIsRemovedByTheNextRun) {
  const fs::path dir = folder("stale");
  const pid_t child = ::fork();
  if (child == 0) ::_exit(0);
  int status = 0;
  ::waitpid(child, &status, 0);  // a process id that no process has now
  const fs::path stale = dir / (".a.stp.partial-" + std::to_string(child));
  std::ofstream(stale) << std::string(4096, 'x');
  const Shell r = shell("surftrace build " + data("structures/1crn.pdb") + " -o " + (dir / "a.stp").string());
  EXPECT_EQ(r.status, 0) << r.output;
  EXPECT_TRUE(fs::exists(dir / "a.stp"));
  EXPECT_FALSE(fs::exists(stale)) << "the killed run's temporary was left";
}

// --- `-`, the standard output ---

TEST(Output, DashIsTheStandardOutput) {
  const fs::path dir = folder("dash");
  const std::string mol = data("structures/1crn.pdb");
  // info --xyzr -: the atoms alone on stdout (the summary goes to stderr), as a file gets them.
  ASSERT_EQ(shell("surftrace info " + mol + " --xyzr " + (dir / "atoms.xyzr").string()).status, 0);
  const Shell xyzr = surftrace::tools::test::runShell("\"" SURFTRACE_TOOL "\" info " + mol + " --xyzr - 2>/dev/null");
  EXPECT_EQ(xyzr.status, 0);
  EXPECT_TRUE(xyzr.output == contents(dir / "atoms.xyzr")) << xyzr.output.substr(0, 200);
  const Shell summary =
      surftrace::tools::test::runShell("\"" SURFTRACE_TOOL "\" info " + mol + " --xyzr - 2>&1 >/dev/null");
  EXPECT_NE(summary.output.find("atoms      327"), std::string::npos) << summary.output;
  // The names a shell gives the standard output are it too (never opened anew, never replaced).
  const Shell procSelf =
      surftrace::tools::test::runShell("\"" SURFTRACE_TOOL "\" info " + mol + " --xyzr /proc/self/fd/1 2>/dev/null");
  EXPECT_EQ(procSelf.status, 0);
  EXPECT_TRUE(procSelf.output == contents(dir / "atoms.xyzr")) << procSelf.output.substr(0, 200);
  // build -o -: a patch list; render -o - and --exr -: a PNG, an EXR; compare --report -: JSON.
  const std::string exr = referenceExr(dir);
  struct Case {
    std::string command, magic;
  };
  const Case cases[] = {
      {"build " + mol + " -o -", "SURFTRCE"},
      {"render " + mol + " --size 16x16 --quiet -o -", "\x89PNG"},
      {"render " + mol + " --size 16x16 --quiet --exr -", "\x76\x2f\x31\x01"},
      {"render " + mol + " --size 16x16 --quiet --exr " + (dir / "x.exr").string() + " --camera-out -", "{"},
      {"compare " + exr + " " + exr + " --report -", "{"},
  };
  for (const Case& c : cases) {
    const fs::path out = dir / "stdout";
    const Shell r = shell("surftrace " + c.command + " > " + out.string());
    EXPECT_EQ(r.status, 0) << c.command << "\n" << r.output;
    const std::string written = contents(out);
    EXPECT_EQ(written.rfind(c.magic, 0), 0u) << c.command << ": " << written.substr(0, 40);
    if (c.magic == "{") {
      EXPECT_TRUE(nlohmann::json::accept(written)) << c.command << ": not JSON\n" << written;
    }
  }
  // One standard output for one file; binary data is not sent to a terminal.
  const Shell both = shell("surftrace render " + mol + " --size 16x16 -o - --exr - > /dev/null");
  EXPECT_EQ(both.status, 1) << both.output;
  EXPECT_NE(both.output.find("both name the standard output"), std::string::npos) << both.output;
  const Shell terminal = shell("script -qec \"\\\"" SURFTRACE_TOOL "\\\" build " + mol + " -o -\" /dev/null");
  EXPECT_EQ(terminal.status, 1) << terminal.output;
  EXPECT_NE(terminal.output.find("terminal"), std::string::npos) << terminal.output;
  EXPECT_EQ(terminal.output.find("SURFTRCE"), std::string::npos) << "binary data reached the terminal";
}

// --- A reader that closes the pipe early ---

struct PipeRun {
  int status = -1;  // the exit status, or 128 + the signal that ended the program (141: SIGPIPE)
  std::string errors;
};

// Runs surftrace with `args`, its standard output a pipe of one page whose reader takes `bytes`
// bytes and then closes it (as `| head -c N` does), as a shell starts it (SIGPIPE at its
// default); its standard error into `errors`. Any output longer than a page and `bytes` meets
// the closed pipe, whatever the timing.
PipeRun runIntoClosedPipe(const std::vector<std::string>& args, std::size_t bytes, const fs::path& errors) {
  std::vector<std::string> words = {SURFTRACE_TOOL};
  words.insert(words.end(), args.begin(), args.end());
  std::vector<char*> argv;
  for (std::string& w : words) argv.push_back(w.data());
  argv.push_back(nullptr);
  int fds[2];
  if (::pipe2(fds, O_CLOEXEC) != 0) return {-1, std::string("pipe2: ") + std::strerror(errno)};
  if (::fcntl(fds[1], F_SETPIPE_SZ, 4096) < 0) return {-1, std::string("F_SETPIPE_SZ: ") + std::strerror(errno)};
  const pid_t pid = ::fork();
  if (pid == 0) {
    const int err = ::open(errors.c_str(), O_WRONLY | O_CREAT | O_TRUNC, 0644);
    ::dup2(fds[1], STDOUT_FILENO);
    ::dup2(err, STDERR_FILENO);
    ::signal(SIGPIPE, SIG_DFL);
    ::execv(argv[0], argv.data());
    ::_exit(127);
  }
  ::close(fds[1]);
  char buffer[64];
  for (std::size_t got = 0; got < bytes;) {
    const ::ssize_t n = ::read(fds[0], buffer, std::min(sizeof buffer, bytes - got));
    if (n <= 0) break;
    got += static_cast<std::size_t>(n);
  }
  ::close(fds[0]);
  int status = 0;
  ::waitpid(pid, &status, 0);
  PipeRun run;
  run.status = WIFEXITED(status) ? WEXITSTATUS(status) : WIFSIGNALED(status) ? 128 + WTERMSIG(status) : -1;
  run.errors = contents(errors);
  return run;
}

// Every command that writes to stdout exits 1 with the reason when its reader goes, as the
// README says, instead of dying of SIGPIPE (exit 141) without a word.
TEST(Output, AClosedPipeIsAnErrorWithItsReason) {
  const fs::path dir = folder("pipe");
  const std::string mol = data("structures/1crn.pdb");
  const std::vector<std::vector<std::string>> commands = {
      {"area", mol, "--format", "csv"},  // 327 rows, 20 KB
      {"info", mol, "--xyzr", "-"},      // 327 lines, 8 KB
      {"build", mol, "-o", "-"},         // a patch list of 1433 patches
  };
  for (const auto& args : commands) {
    const PipeRun r = runIntoClosedPipe(args, 10, dir / "errors");
    EXPECT_EQ(r.status, 1) << args[0] << " " << args.back() << "\n" << r.errors;
    EXPECT_NE(r.errors.find("writing the standard output failed: Broken pipe"), std::string::npos)
        << args[0] << "\n" << r.errors;
  }
}

// A long run that prints a line per frame stops at the first line its gone reader cannot
// take, rather than render every frame first.
TEST(Output, AClosedPipeStopsALongRunEarly) {
  const fs::path dir = folder("pipe_frames");
  const PipeRun r = runIntoClosedPipe({"trajectory", data("trajectories/adk_dims/adk.psf.gz"),
                                       data("trajectories/adk_dims/adk_dims.dcd"), "--frames", "0:30", "--size",
                                       "16x16", "-o", (dir / "f%02d.png").string()},
                                      0, dir.parent_path() / "surftrace_output_pipe_frames.errors");
  EXPECT_EQ(r.status, 1) << r.errors;
  EXPECT_NE(r.errors.find("writing the standard output failed: Broken pipe"), std::string::npos) << r.errors;
  EXPECT_LT(filesIn(dir), 30u) << "every frame was rendered for a reader that had gone";
}

// --- Image names and frame folders, checked before any work ---

TEST(Output, ImageNamesAreCheckedBeforeTheWork) {
  const fs::path dir = folder("names");
  const std::string mol = data("structures/1crn.pdb");
  const std::string traj = data("trajectories/adk_dims/adk.psf.gz") + " " + data("trajectories/adk_dims/adk_dims.dcd");
  struct Case {
    std::string command, message;
  };
  const Case cases[] = {
      {"render " + mol + " --size 16x16 --exr " + (dir / "a.png").string(), "--exr needs an .exr name"},
      {"trajectory " + traj + " --frames 0:2 --size 16x16 --exr " + (dir / "f%03d.png").string(),
       "--exr needs an .exr name"},
      {"render " + mol + " --size 16x16 -o " + (dir / "a.ply").string(), ".ply is not an image format"},
  };
  for (const Case& c : cases) {
    const Shell r = shell("surftrace " + c.command);
    EXPECT_EQ(r.status, 1) << c.command << "\n" << r.output;
    EXPECT_NE(r.output.find(c.message), std::string::npos) << c.command << "\n" << r.output;
    EXPECT_EQ(r.output.find("rendered"), std::string::npos) << "said after the work\n" << r.output;
    EXPECT_EQ(r.output.find(" ms"), std::string::npos) << "said after the work\n" << r.output;
  }
}

// A pattern whose number names a folder makes every frame's folder, not only frame 0's.
TEST(Output, FramePatternsMakeEveryFolderTheyName) {
  const fs::path dir = folder("pattern_folders");
  const Shell r = shell("surftrace trajectory " + data("trajectories/adk_dims/adk.psf.gz") + " " +
                        data("trajectories/adk_dims/adk_dims.dcd") + " --frames 0:3 --size 16x16 --quiet -o " +
                        (dir / "f" / "%03d" / "x.png").string());
  EXPECT_EQ(r.status, 0) << r.output;
  for (const char* frame : {"000", "001", "002"}) EXPECT_TRUE(fs::is_regular_file(dir / "f" / frame / "x.png")) << frame;
}

}  // namespace

// A `surftrace trajectory` run stopped by SIGTERM (a Slurm time limit) or SIGINT (Ctrl-C) while
// its output goes to a file, as in a batch job: the log holds a line for every frame on disk,
// ends with where the run stopped and how to resume, and the process dies of the signal. The
// oracle is the file system: the frames that exist.
#include <fcntl.h>
#include <signal.h>
#include <sys/wait.h>
#include <unistd.h>

#include <algorithm>
#include <chrono>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <regex>
#include <set>
#include <sstream>
#include <string>
#include <thread>
#include <vector>

#include <gtest/gtest.h>

#include "run_tool.hpp"
#include "temp_dir.hpp"

namespace surftrace::tools::test {
namespace {

namespace fs = std::filesystem;

const std::string kPsf = std::string(SURFTRACE_TEST_DATA) + "/trajectories/adk_dims/adk.psf.gz";
const std::string kDcd = std::string(SURFTRACE_TEST_DATA) + "/trajectories/adk_dims/adk_dims.dcd";
constexpr std::size_t kFrames = 98;

fs::path freshDirectory(const std::string& name) {
  return ::surftrace::test::freshTempDir(name);
}

// Starts `surftrace args...` with stdout and stderr appended to `log` (no terminal).
pid_t start(const std::vector<std::string>& args, const fs::path& log) {
  // Everything the child needs is made before fork(): after it, in a threaded process, only
  // async-signal-safe calls are allowed.
  std::vector<char*> argv;
  argv.push_back(const_cast<char*>(SURFTRACE_TOOL));
  for (const std::string& a : args) argv.push_back(const_cast<char*>(a.c_str()));
  argv.push_back(nullptr);
  const std::string logPath = log.string();
  const pid_t pid = fork();
  if (pid == 0) {
    const int fd = open(logPath.c_str(), O_WRONLY | O_CREAT | O_APPEND, 0644);
    if (fd < 0) _exit(126);
    dup2(fd, STDOUT_FILENO);
    dup2(fd, STDERR_FILENO);
    struct sigaction defaults {};
    defaults.sa_handler = SIG_DFL;
    sigaction(SIGINT, &defaults, nullptr);
    sigaction(SIGTERM, &defaults, nullptr);
    execv(SURFTRACE_TOOL, argv.data());
    _exit(127);
  }
  return pid;
}

// The frames written to `dir` as %05d.png (temporary files are not frames).
std::set<std::size_t> framesOnDisk(const fs::path& dir) {
  std::set<std::size_t> frames;
  const std::regex name(R"((\d{5})\.png)");
  std::smatch m;
  for (const auto& entry : fs::directory_iterator(dir)) {
    const std::string file = entry.path().filename().string();
    if (std::regex_match(file, m, name)) frames.insert(std::stoul(m[1]));
  }
  return frames;
}

// Waits for the process; its wait status, or -1 (and the process killed) after `seconds`.
int waitFor(pid_t pid, int seconds) {
  int status = 0;
  const auto deadline = std::chrono::steady_clock::now() + std::chrono::seconds(seconds);
  while (std::chrono::steady_clock::now() < deadline) {
    if (waitpid(pid, &status, WNOHANG) == pid) return status;
    std::this_thread::sleep_for(std::chrono::milliseconds(10));
  }
  kill(pid, SIGKILL);
  waitpid(pid, &status, 0);
  return -1;
}

std::vector<std::string> linesOf(const fs::path& path) {
  std::ifstream in(path);
  std::vector<std::string> lines;
  for (std::string line; std::getline(in, line);) lines.push_back(line);
  return lines;
}

// Runs the trajectory into `dir`, sends `signal` once the first frame is on disk, and checks the
// log against the frames on disk. Returns the frames written.
std::set<std::size_t> interruptAndCheck(int signal, const std::string& name, const fs::path& dir) {
  const fs::path frames = dir / "frames", log = dir / "log.txt";
  const std::vector<std::string> args = {"trajectory", kPsf, kDcd, "--size", "24x24", "--threads", "1",
                                         "-o", (frames / "%05d.png").string()};
  const pid_t pid = start(args, log);
  const auto deadline = std::chrono::steady_clock::now() + std::chrono::seconds(120);
  int status = 0;
  bool ended = false;  // before the signal: a failure (the log says why) or a run too quick to stop
  while (std::chrono::steady_clock::now() < deadline && (!fs::exists(frames) || framesOnDisk(frames).empty())) {
    if (waitpid(pid, &status, WNOHANG) == pid) {
      ended = true;
      break;
    }
    std::this_thread::sleep_for(std::chrono::milliseconds(2));
  }
  if (!ended) {
    kill(pid, signal);
    status = waitFor(pid, 120);
  }
  const std::vector<std::string> lines = linesOf(log);
  std::string text;
  for (const std::string& line : lines) text += line + "\n";
  EXPECT_TRUE(WIFSIGNALED(status) && WTERMSIG(status) == signal) << "wait status " << status << "\n" << text;

  // A line for every frame on disk, and none for a frame that is not.
  const std::set<std::size_t> onDisk = framesOnDisk(frames);
  EXPECT_GE(onDisk.size(), 1u) << text;
  EXPECT_LT(onDisk.size(), kFrames) << "the run ended before " << name << " reached it\n" << text;
  std::set<std::size_t> logged;
  const std::regex frameLine(R"(frame (\d+): build .* ms, render .* ms)");
  std::smatch m;
  for (const std::string& line : lines)
    if (std::regex_match(line, m, frameLine)) logged.insert(std::stoul(m[1]));
  EXPECT_EQ(logged, onDisk) << text;

  // The last line: where it stopped (the first frame not on disk) and how to go on.
  std::size_t firstMissing = 0;
  while (onDisk.count(firstMissing)) ++firstMissing;
  std::ostringstream expected;
  expected << "interrupted by " << name << " at frame " << firstMissing << ": " << onDisk.size()
           << " of the 98 frames to render written, " << kFrames - onDisk.size() << " missing; resume with --resume";
  EXPECT_FALSE(lines.empty());
  if (!lines.empty()) {
    EXPECT_EQ(lines.back().rfind(expected.str(), 0), 0u) << "expected: " << expected.str() << "\n" << text;
  }
  return onDisk;
}

TEST(Interrupt, SigtermLeavesALogOfEveryFrameAndResumeFinishes) {
  const fs::path dir = freshDirectory("term");
  const std::set<std::size_t> written = interruptAndCheck(SIGTERM, "SIGTERM", dir);
  // --resume, as the line says, renders exactly the frames that are missing.
  const Result resumed = runTool("trajectory " + kPsf + " " + kDcd + " --size 24x24 --quiet --resume -o " +
                                 (dir / "frames" / "%05d.png").string());
  EXPECT_EQ(resumed.status, 0) << resumed.output;
  std::ostringstream plan;
  plan << kFrames - written.size() << " to render, " << written.size() << " done already (--resume)";
  EXPECT_NE(resumed.output.find(plan.str()), std::string::npos) << plan.str() << "\n" << resumed.output;
  EXPECT_EQ(framesOnDisk(dir / "frames").size(), kFrames);
  fs::remove_all(dir);
}

TEST(Interrupt, SigintLeavesALogOfEveryFrame) {
  const fs::path dir = freshDirectory("int");
  interruptAndCheck(SIGINT, "SIGINT", dir);
  fs::remove_all(dir);
}

}  // namespace
}  // namespace surftrace::tools::test

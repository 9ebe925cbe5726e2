// Writing never harms what a path names (output_file.hpp): a device, a FIFO or a socket is
// written in place, a symbolic link stays a link while its target is replaced, and the
// temporaries of a killed run go. The devices are copies made with mknod in a temporary
// folder (as root, as in containers and CI), never the machine's own /dev nodes.
#include "build/io/output_file.hpp"

#include <fcntl.h>
#include <poll.h>
#include <sys/socket.h>
#include <sys/stat.h>
#include <sys/sysmacros.h>
#include <sys/un.h>
#include <sys/wait.h>
#include <unistd.h>

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

#include "fifo_reader.hpp"
#include "temp_dir.hpp"

namespace {

namespace fs = std::filesystem;
using surftrace::build::OutputError;
using surftrace::build::prepareOutputPath;
using surftrace::build::writeFileAtomically;

fs::path freshFolder(const std::string& name) {
  return ::surftrace::test::freshTempDir(name);
}

std::string contents(const fs::path& path) {
  std::ifstream in(path, std::ios::binary);
  std::ostringstream text;
  text << in.rdbuf();
  return text.str();
}

void put(const fs::path& path, const std::string& text) { std::ofstream(path, std::ios::binary) << text; }

// Every name in `dir` that holds ".partial-": temporaries left behind.
std::vector<std::string> temporariesIn(const fs::path& dir) {
  std::vector<std::string> names;
  for (const auto& entry : fs::directory_iterator(dir))
    if (entry.path().filename().string().find(".partial-") != std::string::npos)
      names.push_back(entry.path().filename().string());
  return names;
}

// A character device like /dev/MAJOR:MINOR, made in `dir`; false when this process may not
// (not root).
bool makeDevice(const fs::path& path, unsigned major, unsigned minor) {
  return ::mknod(path.c_str(), S_IFCHR | 0666, makedev(major, minor)) == 0;
}

bool isDevice(const fs::path& path, unsigned major, unsigned minor) {
  struct stat st;
  return ::lstat(path.c_str(), &st) == 0 && S_ISCHR(st.st_mode) && ::major(st.st_rdev) == major &&
         ::minor(st.st_rdev) == minor;
}

// A process id that no process has: a child that has exited and been reaped.
pid_t deadPid() {
  const pid_t child = ::fork();
  if (child == 0) ::_exit(0);
  int status = 0;
  ::waitpid(child, &status, 0);
  return child;
}

TEST(OutputFile, DevicesAreWrittenInPlace) {
  const fs::path dir = freshFolder("devices");
  const fs::path null = dir / "null", full = dir / "full";
  if (!makeDevice(null, 1, 3) || !makeDevice(full, 1, 7))
    GTEST_SKIP() << "mknod needs root: " << std::strerror(errno);
  EXPECT_NO_THROW(prepareOutputPath(null, "-o"));
  EXPECT_NO_THROW(prepareOutputPath(full, "-o"));
  EXPECT_NO_THROW(writeFileAtomically(null, std::string(100000, 'x')));
  EXPECT_TRUE(isDevice(null, 1, 3)) << "the null device was replaced";
  try {
    writeFileAtomically(full, std::string("x"));
    ADD_FAILURE() << "writing to a full device succeeded";
  } catch (const OutputError& e) {
    EXPECT_NE(std::string(e.what()).find(full.string()), std::string::npos) << e.what();
    EXPECT_NE(std::string(e.what()).find("No space left on device"), std::string::npos) << e.what();
  }
  EXPECT_TRUE(isDevice(full, 1, 7)) << "the full device was replaced";
  // Through a link, too: the link stays, the device stays.
  fs::create_symlink("null", dir / "to-null");
  EXPECT_NO_THROW(writeFileAtomically(dir / "to-null", std::string("y")));
  EXPECT_TRUE(fs::is_symlink(dir / "to-null"));
  EXPECT_TRUE(isDevice(null, 1, 3));
  EXPECT_TRUE(temporariesIn(dir).empty());
}

TEST(OutputFile, AFifoGetsTheBytes) {
  const fs::path dir = freshFolder("fifo");
  const fs::path fifo = dir / "fifo";
  ASSERT_EQ(::mkfifo(fifo.c_str(), 0666), 0) << std::strerror(errno);
  EXPECT_NO_THROW(prepareOutputPath(fifo, "--xyzr"));
  surftrace::test::FifoReader reader(fifo);
  ASSERT_TRUE(reader.opened()) << std::strerror(errno);
  std::string sent;
  for (int i = 0; i < 20000; ++i) sent += std::to_string(i) + " 1.5 2.5 1.7\n";  // more than a pipe holds
  EXPECT_NO_THROW(writeFileAtomically(fifo, sent));
  const std::string& received = reader.finish();
  EXPECT_TRUE(received == sent) << "the reader got " << received.size() << " bytes of " << sent.size();
  struct stat st;
  ASSERT_EQ(::lstat(fifo.c_str(), &st), 0);
  EXPECT_TRUE(S_ISFIFO(st.st_mode)) << "the FIFO was replaced by a file";
  EXPECT_TRUE(temporariesIn(dir).empty());
}

TEST(OutputFile, ASocketGetsTheBytes) {
  const fs::path dir = freshFolder("socket");
  const fs::path path = dir / "socket";
  const int server = ::socket(AF_UNIX, SOCK_STREAM, 0);
  ASSERT_GE(server, 0);
  sockaddr_un address{};
  address.sun_family = AF_UNIX;
  ASSERT_LT(path.native().size(), sizeof address.sun_path);
  std::strcpy(address.sun_path, path.c_str());
  ASSERT_EQ(::bind(server, reinterpret_cast<const sockaddr*>(&address), sizeof address), 0) << std::strerror(errno);
  ASSERT_EQ(::listen(server, 1), 0);
  std::string received;
  std::thread reading([&] {
    pollfd p{server, POLLIN, 0};
    if (::poll(&p, 1, 20000) <= 0) return;
    const int client = ::accept(server, nullptr, nullptr);
    char buffer[4096];
    for (::ssize_t n; (n = ::read(client, buffer, sizeof buffer)) > 0;) received.append(buffer, static_cast<std::size_t>(n));
    ::close(client);
  });
  EXPECT_NO_THROW(prepareOutputPath(path, "--report"));
  std::string sent;
  try {
    writeFileAtomically(path, std::string("{\"pass\": true}\n"));
    sent = "{\"pass\": true}\n";
  } catch (const OutputError& e) {
    ADD_FAILURE() << e.what();
    // Let the reader go: connect and close.
    const int unblock = ::socket(AF_UNIX, SOCK_STREAM, 0);
    ::connect(unblock, reinterpret_cast<const sockaddr*>(&address), sizeof address);
    ::close(unblock);
  }
  reading.join();
  ::close(server);
  EXPECT_EQ(received, sent);
  struct stat st;
  ASSERT_EQ(::lstat(path.c_str(), &st), 0);
  EXPECT_TRUE(S_ISSOCK(st.st_mode)) << "the socket was replaced by a file";
}

// A link, relative or absolute, alone or in a chain, keeps being a link; its final target gets
// the new bytes (atomically: through a temporary beside the target, not beside the link).
TEST(OutputFile, SymbolicLinksStayLinksAndTheirTargetIsReplaced) {
  const fs::path dir = freshFolder("links");
  fs::create_directories(dir / "elsewhere");
  fs::create_directories(dir / "links");
  const fs::path target = dir / "elsewhere" / "x.stp";
  struct Case {
    fs::path link;
    std::vector<std::pair<fs::path, fs::path>> chain;  // (link, what it points to), made in order
  };
  const Case cases[] = {
      {dir / "links" / "relative.stp", {{dir / "links" / "relative.stp", "../elsewhere/x.stp"}}},
      {dir / "links" / "absolute.stp", {{dir / "links" / "absolute.stp", target}}},
      {dir / "links" / "chain.stp",
       {{dir / "links" / "chain.stp", "middle.stp"}, {dir / "links" / "middle.stp", "../elsewhere/x.stp"}}},
  };
  int round = 0;
  for (const Case& c : cases) {
    put(target, "old");
    for (const auto& [link, to] : c.chain) fs::create_symlink(to, link);
    const std::string text = "new " + std::to_string(++round);
    EXPECT_NO_THROW(prepareOutputPath(c.link, "-o")) << c.link;
    ASSERT_NO_THROW(writeFileAtomically(c.link, text)) << c.link;
    for (const auto& [link, to] : c.chain) {
      EXPECT_TRUE(fs::is_symlink(link)) << link << " was replaced by a file";
      EXPECT_EQ(fs::read_symlink(link), to) << link;
    }
    EXPECT_TRUE(fs::is_regular_file(fs::symlink_status(target))) << target;
    EXPECT_EQ(contents(target), text) << c.link;
    EXPECT_TRUE(temporariesIn(dir / "links").empty());
    EXPECT_TRUE(temporariesIn(dir / "elsewhere").empty());
  }
  // A dangling link whose target's folder exists is written through; one whose folder does
  // not is refused before any work, naming the link's target.
  fs::create_symlink("../elsewhere/new.stp", dir / "links" / "dangling.stp");
  EXPECT_NO_THROW(prepareOutputPath(dir / "links" / "dangling.stp", "-o"));
  ASSERT_NO_THROW(writeFileAtomically(dir / "links" / "dangling.stp", std::string("made")));
  EXPECT_TRUE(fs::is_symlink(dir / "links" / "dangling.stp"));
  EXPECT_EQ(contents(dir / "elsewhere" / "new.stp"), "made");
  fs::create_symlink("../nowhere/x.stp", dir / "links" / "lost.stp");
  try {
    prepareOutputPath(dir / "links" / "lost.stp", "-o");
    ADD_FAILURE() << "a link into a missing folder was accepted";
  } catch (const OutputError& e) {
    EXPECT_NE(std::string(e.what()).find("nowhere"), std::string::npos) << e.what();
  }
  // A loop of links is an error, not a hang.
  fs::create_symlink("loop-b", dir / "links" / "loop-a");
  fs::create_symlink("loop-a", dir / "links" / "loop-b");
  EXPECT_THROW(writeFileAtomically(dir / "links" / "loop-a", std::string("x")), OutputError);
}

// A run killed while writing (kill -9) leaves `.NAME.partial-PID`; the next run that writes
// NAME removes it when its process is gone, or when the process with that id started after the
// temporary was last written (the id was reused). A live writer's temporary and other files'
// temporaries are left alone.
TEST(OutputFile, StaleTemporariesOfTheSameOutputAreRemoved) {
  const fs::path dir = freshFolder("stale");
  const fs::path out = dir / "out.exr";
  const pid_t dead = deadPid();
  const fs::path killed = dir / (".out.exr.partial-" + std::to_string(dead));
  const fs::path reused = dir / ".out.exr.partial-1";  // pid 1 runs, but started long after 1970
  // A writer still at work: a child that waits, started before its temporary is written.
  const pid_t writer = ::fork();
  if (writer == 0) {
    ::pause();
    ::_exit(0);
  }
  const fs::path live = dir / (".out.exr.partial-" + std::to_string(writer));
  const fs::path other = dir / (".other.exr.partial-" + std::to_string(dead));
  for (const fs::path& p : {killed, reused, live, other}) put(p, std::string(1000, 'x'));
  const timespec times[2] = {{1, 0}, {1, 0}};
  ASSERT_EQ(::utimensat(AT_FDCWD, reused.c_str(), times, 0), 0);
  ASSERT_NO_THROW(writeFileAtomically(out, std::string("whole")));
  EXPECT_EQ(contents(out), "whole");
  EXPECT_FALSE(fs::exists(killed)) << "the temporary of a dead process was left";
  EXPECT_FALSE(fs::exists(reused)) << "a temporary older than the process with its id was left";
  EXPECT_TRUE(fs::exists(live)) << "the temporary of a live writer was removed";
  EXPECT_TRUE(fs::exists(other)) << "another file's temporary was removed";
  ::kill(writer, SIGKILL);
  int status = 0;
  ::waitpid(writer, &status, 0);
}

// The names a shell gives the standard output are it, and written as "-" is: never opened
// anew through /proc, never replaced (as root, a rename over /dev/stdout replaced the node).
TEST(OutputFile, TheStandardOutputHasSeveralNames) {
  using surftrace::build::isStandardOutput;
  for (const char* name : {"-", "/dev/stdout", "/dev/fd/1", "/proc/self/fd/1"}) EXPECT_TRUE(isStandardOutput(name)) << name;
  for (const char* name : {"--", "x", "/dev/stderr", "/dev/fd/3", "./-"}) EXPECT_FALSE(isStandardOutput(name)) << name;
}

// A write that fails (here: the target is a folder, so the rename fails) leaves no temporary.
TEST(OutputFile, AFailedWriteLeavesNoTemporary) {
  const fs::path dir = freshFolder("failed");
  fs::create_directories(dir / "taken" / "inside");
  EXPECT_THROW(writeFileAtomically(dir / "taken", std::string("x")), OutputError);
  EXPECT_TRUE(temporariesIn(dir).empty());
  EXPECT_TRUE(fs::is_directory(dir / "taken" / "inside"));
}

}  // namespace

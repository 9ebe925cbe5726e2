// Checked, atomic file output (output_file.hpp).
#include "build/io/output_file.hpp"

#include <fcntl.h>
#include <poll.h>
#include <signal.h>
#include <sys/socket.h>
#include <sys/stat.h>
#include <sys/un.h>
#include <unistd.h>

#include <cerrno>
#include <cstdio>
#include <cstring>
#include <fstream>
#include <map>
#include <mutex>
#include <optional>
#include <sstream>
#include <system_error>
#include <utility>
#include <vector>

namespace surftrace::build {
namespace {

namespace fs = std::filesystem;

std::string reason(int error) { return std::system_category().message(error); }

// A descriptor closed when it goes out of scope (an exception on the way), unless closed
// before with its status checked.
class Descriptor {
 public:
  explicit Descriptor(int fd) : fd_(fd) {}
  Descriptor(const Descriptor&) = delete;
  Descriptor& operator=(const Descriptor&) = delete;
  ~Descriptor() {
    if (fd_ >= 0) ::close(fd_);
  }
  int get() const { return fd_; }
  // close(2)'s errno, or 0.
  int close() {
    const int status = ::close(fd_);
    fd_ = -1;
    return status == 0 ? 0 : errno;
  }

 private:
  int fd_;
};

// A temporary file removed when it goes out of scope, unless kept (renamed into place): a run
// that ends, by an error or an exception, never leaves one behind.
class TemporaryFile {
 public:
  explicit TemporaryFile(fs::path path) : path_(std::move(path)) {}
  TemporaryFile(const TemporaryFile&) = delete;
  TemporaryFile& operator=(const TemporaryFile&) = delete;
  ~TemporaryFile() {
    std::error_code ignored;
    if (!path_.empty()) fs::remove(path_, ignored);
  }
  void keep() { path_.clear(); }

 private:
  fs::path path_;
};

// Writes all of `bytes` to `fd`: 0, or the errno of the write that failed.
int writeAll(int fd, std::span<const std::byte> bytes) {
  const auto* data = reinterpret_cast<const char*>(bytes.data());
  std::size_t left = bytes.size();
  while (left > 0) {
    const ::ssize_t n = ::write(fd, data, left);
    if (n < 0) {
      if (errno == EINTR) continue;
      return errno;
    }
    if (n == 0) return EIO;  // no progress and no reason: never loop on it
    data += n;
    left -= static_cast<std::size_t>(n);
  }
  return 0;
}

constexpr const char* kPartial = ".partial-";

// A name beside `path` that no other writer uses: hidden, with the process id.
fs::path temporaryBeside(const fs::path& path) {
  // (Built by appending: GCC 12 gives a false -Wrestrict for "x" + std::string chains.)
  std::string name(".");
  name.append(path.filename().string()).append(kPartial).append(std::to_string(::getpid()));
  return path.parent_path() / name;
}

// As the kernel's MAXSYMLINKS: more links than this in a chain is a loop.
constexpr int kMaxLinks = 40;

// The file that `path` names in the end: symbolic links followed (a relative one from its own
// folder), however many, to a path that is not a link. It need not exist (a dangling link).
// Replacing that file, rather than the link, keeps the link a link.
fs::path finalTarget(const fs::path& path, const std::string& where) {
  fs::path p = path;
  for (int hops = 0; hops <= kMaxLinks; ++hops) {
    struct stat st;
    if (::lstat(p.c_str(), &st) != 0 || !S_ISLNK(st.st_mode)) return p;
    std::error_code error;
    const fs::path link = fs::read_symlink(p, error);
    if (error) throw OutputError(where + ": cannot read the link " + p.string() + ": " + error.message());
    p = link.is_absolute() ? link : p.parent_path() / link;
  }
  throw OutputError(where + ": " + reason(ELOOP) + " (a chain of links that loops?)");
}

// When process `pid` started, in seconds since the epoch (/proc/PID/stat's start time after
// the boot time of /proc/stat); nullopt when it cannot be told.
std::optional<double> processStart(pid_t pid) {
  std::ifstream stat("/proc/" + std::to_string(pid) + "/stat");
  std::string text;
  if (!std::getline(stat, text)) return std::nullopt;
  // Field 2, the command name, may hold spaces and parentheses: the fields after it follow
  // the last ')'. The start time is field 22, the 20th after it.
  const std::size_t close = text.rfind(')');
  if (close == std::string::npos) return std::nullopt;
  std::istringstream rest(text.substr(close + 1));
  std::string field;
  for (int k = 3; k < 22; ++k) rest >> field;
  unsigned long long ticks = 0;
  if (!(rest >> ticks)) return std::nullopt;
  std::ifstream machine("/proc/stat");
  std::string line;
  while (std::getline(machine, line))
    if (line.rfind("btime ", 0) == 0) {
      const long hz = ::sysconf(_SC_CLK_TCK);
      if (hz <= 0) return std::nullopt;
      return std::stod(line.substr(6)) + static_cast<double>(ticks) / static_cast<double>(hz);
    }
  return std::nullopt;
}

// Whether the temporary file `file`, named for process `pid`, was left by a run that is gone:
// no process has that id, or the one that has it started after the file was last written (the
// id was reused: in a container the same few ids come back run after run).
bool leftByADeadRun(const fs::path& file, pid_t pid) {
  if (pid == ::getpid()) return false;  // this run's own name: it writes over it
  if (::kill(pid, 0) != 0 && errno == ESRCH) return true;
  struct stat st;
  if (::lstat(file.c_str(), &st) != 0) return false;
  const std::optional<double> start = processStart(pid);
  // Two seconds of margin: the boot time is given in whole seconds.
  return start && static_cast<double>(st.st_mtime) + 2.0 < *start;
}

// The temporaries of other runs found beside outputs, by folder. Each folder is listed once per
// process, at its first write (a trajectory writes thousands of frames into one folder, and a
// listing per frame would cost the square of their number); the temporaries of one file are
// looked at when that file is written. Process-wide, as the files are.
class StaleTemporaries {
 public:
  void removeFor(const fs::path& target) {
    const fs::path folder = target.parent_path().empty() ? fs::path(".") : target.parent_path();
    std::vector<std::pair<fs::path, pid_t>> candidates;
    {
      const std::lock_guard lock(mutex_);
      auto [at, fresh] = byFolder_.try_emplace(folder);
      if (fresh) at->second = list(folder);
      const auto [first, last] = at->second.equal_range(target.filename().string());
      for (auto it = first; it != last; ++it) candidates.push_back(it->second);
      at->second.erase(first, last);
    }
    for (const auto& [file, pid] : candidates) {
      std::error_code ignored;
      if (leftByADeadRun(file, pid)) fs::remove(file, ignored);
    }
  }

 private:
  using Found = std::multimap<std::string, std::pair<fs::path, pid_t>>;  // by the file they stand for

  // Every ".NAME.partial-PID" in `folder`, under NAME.
  static Found list(const fs::path& folder) {
    Found found;
    std::error_code error;
    for (fs::directory_iterator it(folder, error), end; !error && it != end; it.increment(error)) {
      const std::string name = it->path().filename().string();
      const std::size_t at = name.rfind(kPartial);
      if (name.size() < 2 || name[0] != '.' || at == std::string::npos || at < 2) continue;
      const std::string digits = name.substr(at + std::strlen(kPartial));
      if (digits.empty() || digits.size() > 9 || digits.find_first_not_of("0123456789") != std::string::npos) continue;
      found.emplace(name.substr(1, at - 1), std::make_pair(it->path(), static_cast<pid_t>(std::stol(digits))));
    }
    return found;
  }

  std::mutex mutex_;
  std::map<fs::path, Found> byFolder_;
};

StaleTemporaries& staleTemporaries() {
  static StaleTemporaries stale;
  return stale;
}

// The standard output once an option claimed it ("-"): the descriptor its bytes go to, and the
// option with the name it was given ("-o -"). Process-wide, as the standard output itself is.
struct StandardOutputClaim {
  int fd = -1;
  std::string option;
};

StandardOutputClaim& standardOutputClaim() {
  static StandardOutputClaim claim;
  return claim;
}

void claimStandardOutput(std::string_view option, const fs::path& path, OutputContent content) {
  StandardOutputClaim& claim = standardOutputClaim();
  const std::string where = std::string(option) + " " + path.string();
  if (claim.fd >= 0) {
    if (claim.option.rfind(std::string(option) + " ", 0) == 0) return;  // the same option again
    throw OutputError(where + " and " + claim.option + " both name the standard output: give one of them a file name");
  }
  struct stat st;
  if (::fstat(STDOUT_FILENO, &st) != 0) throw OutputError(where + ": the standard output is closed (" + reason(errno) + ")");
  if (content == OutputContent::Binary && ::isatty(STDOUT_FILENO))
    throw OutputError(where + ": the file is binary and the standard output is a terminal: redirect it to a file "
                      "or a program (> FILE, | PROGRAM), or give a file name");
  std::fflush(stdout);  // what was printed so far goes where it was going
  const int fd = ::fcntl(STDOUT_FILENO, F_DUPFD_CLOEXEC, 3);
  if (fd < 0) throw OutputError(where + ": cannot keep the standard output: " + reason(errno));
  // What the program prints from now on (its summary lines) goes to the standard error, so
  // that the standard output holds the file's bytes alone.
  if (::dup2(STDERR_FILENO, STDOUT_FILENO) < 0) {
    const int null = ::open("/dev/null", O_WRONLY | O_CLOEXEC);
    if (null >= 0) {
      ::dup2(null, STDOUT_FILENO);
      ::close(null);
    }
  }
  claim.fd = fd;
  claim.option = where;
}

void writeStandardOutput(std::span<const std::byte> bytes) {
  const int fd = standardOutputDescriptor();
  if (fd == STDOUT_FILENO) std::fflush(stdout);  // what was printed before comes first
  if (const int error = writeAll(fd, bytes)) throw OutputError("writing the standard output failed: " + reason(error));
}

// A Unix-domain socket is written as a client of the program that listens on it.
int connectSocket(const fs::path& path) {
  sockaddr_un address{};
  address.sun_family = AF_UNIX;
  if (path.native().size() >= sizeof address.sun_path) {
    errno = ENAMETOOLONG;
    return -1;
  }
  std::memcpy(address.sun_path, path.c_str(), path.native().size() + 1);
  const int fd = ::socket(AF_UNIX, SOCK_STREAM | SOCK_CLOEXEC, 0);
  if (fd < 0) return -1;
  if (::connect(fd, reinterpret_cast<const sockaddr*>(&address), sizeof address) != 0) {
    const int error = errno;
    ::close(fd);
    errno = error;
    return -1;
  }
  return fd;
}

// A device, FIFO or socket: written where it is. Renaming a file over it would turn /dev/null
// into a regular file (as root) and leave a FIFO's reader waiting.
void writeInPlace(const fs::path& path, const fs::path& target, mode_t type, std::span<const std::byte> bytes) {
  Descriptor fd(S_ISSOCK(type) ? connectSocket(target) : ::open(target.c_str(), O_WRONLY | O_CLOEXEC | O_NOCTTY));
  if (fd.get() < 0) throw OutputError(path.string() + ": cannot open it for writing: " + reason(errno));
  if (const int error = writeAll(fd.get(), bytes)) throw OutputError(path.string() + ": write failed: " + reason(error));
  if (const int error = fd.close()) throw OutputError(path.string() + ": write failed: " + reason(error));
}

// The reason of a write to the standard output that failed earlier, when errno no longer holds
// it (stdio keeps only the error flag): a pipe whose reader is gone polls as an error.
int lostReason() {
  pollfd p{STDOUT_FILENO, POLLOUT, 0};
  if (::poll(&p, 1, 0) == 1 && (p.revents & POLLERR)) return EPIPE;
  return 0;
}

[[noreturn]] void standardOutputFailed(int error) {
  std::clearerr(stdout);
  throw OutputError(std::string("writing the standard output failed: ") +
                    (error ? reason(error) : std::string("an earlier write failed, for a reason not kept")));
}

}  // namespace

bool isStandardOutput(const fs::path& path) {
  // The names a shell user gives the standard output too: writing through them would open the
  // file behind it anew (or, run as root, rename a file over the machine's /dev/stdout).
  return path == "-" || path == "/dev/stdout" || path == "/dev/fd/1" || path == "/proc/self/fd/1";
}

bool isWrittenInPlace(const fs::path& path) {
  if (isStandardOutput(path)) return true;
  struct stat st;  // stat(2) follows every link
  return ::stat(path.c_str(), &st) == 0 && !S_ISREG(st.st_mode) && !S_ISDIR(st.st_mode);
}

int standardOutputDescriptor() {
  const int fd = standardOutputClaim().fd;
  return fd >= 0 ? fd : STDOUT_FILENO;
}

void writeFileAtomically(const fs::path& path, std::span<const std::byte> bytes) {
  if (isStandardOutput(path)) return writeStandardOutput(bytes);
  // stat(2) and open(2) follow every link, /proc's links to pipes (/dev/fd/N) among them,
  // which name no path that finalTarget could follow.
  struct stat st;
  if (::stat(path.c_str(), &st) == 0 && !S_ISREG(st.st_mode) && !S_ISDIR(st.st_mode))
    return writeInPlace(path, path, st.st_mode, bytes);
  const fs::path target = finalTarget(path, path.string());
  staleTemporaries().removeFor(target);
  const fs::path temporary = temporaryBeside(target);
  Descriptor fd(::open(temporary.c_str(), O_WRONLY | O_CREAT | O_TRUNC | O_CLOEXEC | O_NOFOLLOW, 0666));
  if (fd.get() < 0) throw OutputError(path.string() + ": cannot create the file: " + reason(errno));
  TemporaryFile guard(temporary);
  const auto fail = [&](int error) {
    throw OutputError(path.string() + ": write failed: " + reason(error) + " (nothing was written)");
  };
  if (const int error = writeAll(fd.get(), bytes)) fail(error);
  if (::fsync(fd.get()) != 0 && errno != EINVAL && errno != EROFS) fail(errno);
  if (const int error = fd.close()) fail(error);
  std::error_code renamed;
  fs::rename(temporary, target, renamed);
  if (renamed) throw OutputError(path.string() + ": cannot replace the file: " + renamed.message());
  guard.keep();
}

void writeFileAtomically(const fs::path& path, std::string_view bytes) {
  writeFileAtomically(path, std::as_bytes(std::span<const char>(bytes.data(), bytes.size())));
}

void prepareOutputPath(const fs::path& path, std::string_view option, OutputContent content) {
  std::string where(option);
  where.append(" ").append(path.string());
  if (path.empty()) throw OutputError(std::string(option).append(": an empty file name"));
  if (isStandardOutput(path)) return claimStandardOutput(option, path, content);
  std::error_code error;
  if (fs::is_directory(path, error)) throw OutputError(where + ": is a folder; give a file name");
  struct stat st;
  if (::stat(path.c_str(), &st) == 0 && !S_ISREG(st.st_mode)) {
    // A device, FIFO or socket is written in place: it must be writable; its folder need not be.
    if (::access(path.c_str(), W_OK) != 0) throw OutputError(where + ": cannot write to it: " + reason(errno));
    return;
  }
  const fs::path target = finalTarget(path, where);
  const bool linked = target != path;
  const std::string named = linked ? where + " (a link to " + target.string() + ")" : where;
  const fs::path folder = target.parent_path().empty() ? fs::path(".") : target.parent_path();
  if (!fs::exists(folder, error)) {
    // A link's target is where the link's owner put it: no folders are made there.
    if (linked) throw OutputError(named + ": the folder " + folder.string() + " does not exist");
    fs::create_directories(folder, error);
    if (error) throw OutputError(where + ": cannot create the folder " + folder.string() + ": " + error.message());
  }
  if (!fs::is_directory(folder, error)) throw OutputError(named + ": " + folder.string() + " is not a folder");
  if (::access(folder.c_str(), W_OK | X_OK) != 0)
    throw OutputError(named + ": cannot write into the folder " + folder.string() + ": " + reason(errno));
  if (fs::exists(target, error) && ::access(target.c_str(), W_OK) != 0 && errno != ENOENT)
    throw OutputError(named + ": cannot replace the file: " + reason(errno));
}

void finishStandardOutput() {
  errno = 0;
  if (std::fflush(stdout) != 0) standardOutputFailed(errno ? errno : lostReason());
  if (std::ferror(stdout)) standardOutputFailed(lostReason());
}

void checkStandardOutput() {
  if (!std::ferror(stdout)) return;
  // Called right after the printing that failed, errno still holds that write's reason.
  const int error = lostReason();
  standardOutputFailed(error ? error : errno);
}

}  // namespace surftrace::build

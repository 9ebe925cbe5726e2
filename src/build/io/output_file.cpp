// Checked, atomic file output (output_file.hpp).
#include "build/io/output_file.hpp"

#include <fcntl.h>
#include <unistd.h>

#include <cerrno>
#include <cstdio>
#include <cstring>
#include <system_error>

namespace surftrace::build {
namespace {

namespace fs = std::filesystem;

std::string reason(int error) { return std::system_category().message(error); }

// A name beside `path` that no other writer uses: hidden, with the process id.
fs::path temporaryBeside(const fs::path& path) {
  // (Built by appending: GCC 12 gives a false -Wrestrict for "x" + std::string chains.)
  std::string name(".");
  name.append(path.filename().string()).append(".partial-").append(std::to_string(::getpid()));
  return path.parent_path() / name;
}

}  // namespace

void writeFileAtomically(const fs::path& path, std::span<const std::byte> bytes) {
  const fs::path temporary = temporaryBeside(path);
  const int fd = ::open(temporary.c_str(), O_WRONLY | O_CREAT | O_TRUNC | O_CLOEXEC, 0666);
  if (fd < 0) throw OutputError(path.string() + ": cannot create the file: " + reason(errno));
  auto fail = [&](const char* what, int error) {
    ::close(fd);
    std::error_code ignored;
    fs::remove(temporary, ignored);
    throw OutputError(path.string() + ": " + what + ": " + reason(error) + " (nothing was written)");
  };
  const auto* data = reinterpret_cast<const char*>(bytes.data());
  std::size_t left = bytes.size();
  while (left > 0) {
    const ::ssize_t n = ::write(fd, data, left);
    if (n < 0) {
      if (errno == EINTR) continue;
      fail("write failed", errno);
    }
    data += n;
    left -= static_cast<std::size_t>(n);
  }
  if (::fsync(fd) != 0 && errno != EINVAL && errno != EROFS) fail("write failed", errno);
  if (::close(fd) != 0) {
    const int error = errno;
    std::error_code ignored;
    fs::remove(temporary, ignored);
    throw OutputError(path.string() + ": write failed: " + reason(error) + " (nothing was written)");
  }
  std::error_code renamed;
  fs::rename(temporary, path, renamed);
  if (renamed) {
    std::error_code ignored;
    fs::remove(temporary, ignored);
    throw OutputError(path.string() + ": cannot replace the file: " + renamed.message());
  }
}

void writeFileAtomically(const fs::path& path, std::string_view bytes) {
  writeFileAtomically(path, std::as_bytes(std::span<const char>(bytes.data(), bytes.size())));
}

void prepareOutputPath(const fs::path& path, std::string_view option) {
  std::string where(option);
  where.append(" ").append(path.string());
  if (path.empty()) throw OutputError(std::string(option).append(": an empty file name"));
  std::error_code error;
  if (fs::is_directory(path, error))
    throw OutputError(where + ": is a folder; give a file name");
  const fs::path folder = path.parent_path().empty() ? fs::path(".") : path.parent_path();
  if (!fs::exists(folder, error)) {
    fs::create_directories(folder, error);
    if (error) throw OutputError(where + ": cannot create the folder " + folder.string() + ": " + error.message());
  }
  if (!fs::is_directory(folder, error)) throw OutputError(where + ": " + folder.string() + " is not a folder");
  if (::access(folder.c_str(), W_OK | X_OK) != 0)
    throw OutputError(where + ": cannot write into the folder " + folder.string() + ": " + reason(errno));
  if (fs::exists(path, error) && ::access(path.c_str(), W_OK) != 0 && errno != ENOENT)
    throw OutputError(where + ": cannot replace the file: " + reason(errno));
}

void finishStandardOutput() {
  errno = 0;
  const bool failed = std::fflush(stdout) != 0 || std::ferror(stdout);
  if (failed) {
    const int error = errno;
    std::clearerr(stdout);
    throw OutputError(std::string("writing the standard output failed: ") +
                      (error ? reason(error) : std::string("unknown error")));
  }
}

}  // namespace surftrace::build

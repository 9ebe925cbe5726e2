// Reads everything a writer sends into a FIFO, on a thread of its own, for the tests of outputs
// that must be written in place (a FIFO is written to, never replaced by a file).
#pragma once

#include <fcntl.h>
#include <poll.h>
#include <unistd.h>

#include <cerrno>
#include <filesystem>
#include <string>
#include <thread>

namespace surftrace::test {

class FifoReader {
 public:
  // Opens `fifo` for reading first, without blocking (so that the writer's open succeeds), then
  // reads until the writer closes, or 20 s pass with nothing to read: a writer that renames a
  // file over the FIFO then fails the test rather than hangs it. `opened()` says whether the
  // open succeeded.
  explicit FifoReader(const std::filesystem::path& fifo)
      : fd_(::open(fifo.c_str(), O_RDONLY | O_NONBLOCK)) {
    if (fd_ < 0) return;
    reading_ = std::thread([this] {
      char buffer[4096];
      for (;;) {
        pollfd p{fd_, POLLIN, 0};
        if (::poll(&p, 1, 20000) <= 0) break;
        const ::ssize_t n = ::read(fd_, buffer, sizeof buffer);
        if (n > 0) received_.append(buffer, static_cast<std::size_t>(n));
        else if (n == 0 || errno != EAGAIN) break;
      }
    });
  }
  FifoReader(const FifoReader&) = delete;
  FifoReader& operator=(const FifoReader&) = delete;
  ~FifoReader() { finish(); }

  bool opened() const { return fd_ >= 0; }

  // Waits for the writer to close and returns every byte it sent.
  const std::string& finish() {
    if (reading_.joinable()) reading_.join();
    if (fd_ >= 0) ::close(fd_);
    fd_ = -1;
    return received_;
  }

 private:
  int fd_;
  std::string received_;
  std::thread reading_;
};

}  // namespace surftrace::test

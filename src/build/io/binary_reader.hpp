// What the binary trajectory readers (dcd.cpp, xtc.cpp) share: numbers decoded in the file's
// byte order, and reads at an offset whose length is checked against the file's size first,
// so that a corrupt length in a header never turns into a huge allocation.
#pragma once

#include <bit>
#include <cstddef>
#include <cstdint>
#include <filesystem>
#include <fstream>
#include <string>
#include <system_error>
#include <vector>

namespace surftrace::build::binary {

// The file's integers and floats, decoded byte by byte so that the host's order never matters.
struct ByteOrder {
  bool big = false;

  std::uint32_t u32(const unsigned char* p) const {
    std::uint32_t v = 0;
    for (int i = 0; i < 4; ++i) v |= std::uint32_t{p[big ? 3 - i : i]} << (8 * i);
    return v;
  }
  std::uint64_t u64(const unsigned char* p) const {
    std::uint64_t v = 0;
    for (int i = 0; i < 8; ++i) v |= std::uint64_t{p[big ? 7 - i : i]} << (8 * i);
    return v;
  }
  std::int32_t i32(const unsigned char* p) const { return std::bit_cast<std::int32_t>(u32(p)); }
  float f32(const unsigned char* p) const { return std::bit_cast<float>(u32(p)); }
  double f64(const unsigned char* p) const { return std::bit_cast<double>(u64(p)); }
};

// "1 byte", "12 bytes".
std::string bytesText(std::uint64_t n);

// One binary file, read at offsets. Each format words its own errors about where the bytes
// ran out (a record, a frame), so holds() and read() report and fail() throws.
class Reader {
 public:
  explicit Reader(const std::filesystem::path& path) : path_(path), name_(path.string()) {}

  // Opens the file for reading; false when it cannot be (errno says why).
  bool open();
  // Measures the file: the size every read is checked against.
  std::error_code measure();
  std::uint64_t size() const { return size_; }

  // Whether the `n` bytes at `offset` lie inside the file.
  bool holds(std::uint64_t offset, std::uint64_t n) const {
    return offset <= size_ && n <= size_ - offset;
  }
  // Reads the `n` bytes at `offset` (which the file holds) into `out`, followed by `padding`
  // zero bytes; false on a read error, which means the file changed while open.
  bool read(std::uint64_t offset, std::uint64_t n, std::vector<unsigned char>& out,
            std::size_t padding = 0);

  // InputError naming the file (and no line).
  [[noreturn]] void fail(const std::string& message) const;
  // InputError unless `index` is one of the file's `count` frames.
  void checkFrameIndex(std::size_t index, std::size_t count) const;

 private:
  std::filesystem::path path_;
  std::string name_;
  std::ifstream file_;
  std::uint64_t size_ = 0;
};

}  // namespace surftrace::build::binary

// Reads at checked offsets of the binary trajectory files, and their errors.
#include "build/io/binary_reader.hpp"

#include <algorithm>

#include "build/core/assert.hpp"
#include "build/io/error.hpp"

namespace surftrace::build::binary {

std::string bytesText(std::uint64_t n) {
  return std::to_string(n) + (n == 1 ? " byte" : " bytes");
}

bool Reader::open() {
  file_.open(path_, std::ios::binary);
  return static_cast<bool>(file_);
}

std::error_code Reader::measure() {
  std::error_code ec;
  size_ = std::filesystem::file_size(path_, ec);
  return ec;
}

bool Reader::read(std::uint64_t offset, std::uint64_t n, std::vector<unsigned char>& out,
                  std::size_t padding) {
  SURFTRACE_ASSERT(holds(offset, n));
  const auto bytes = static_cast<std::size_t>(n);
  out.resize(bytes + padding);
  std::fill(out.begin() + static_cast<std::ptrdiff_t>(bytes), out.end(), 0);
  file_.clear();
  file_.seekg(static_cast<std::streamoff>(offset));
  file_.read(reinterpret_cast<char*>(out.data()), static_cast<std::streamsize>(n));
  return file_ && static_cast<std::uint64_t>(file_.gcount()) == n;
}

void Reader::fail(const std::string& message) const { throw InputError(name_, 0, message); }

void Reader::checkFrameIndex(std::size_t index, std::size_t count) const {
  if (index >= count)
    fail("frame " + std::to_string(index) + " does not exist: the file holds " +
         (count == 1 ? std::string("only frame 0") : "frames 0 to " + std::to_string(count - 1)));
}

}  // namespace surftrace::build::binary

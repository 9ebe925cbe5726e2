// Errors raised where data enters SurfTrace: they always name the file, the line and the value.
#pragma once

#include <stdexcept>
#include <string>

namespace surftrace::build {

// Bad input: a malformed or truncated file, a non-finite coordinate, an unknown element,
// an impossible option. `line` is 1-based; 0 means the problem is not tied to one line.
class InputError : public std::runtime_error {
 public:
  InputError(std::string path, int line, const std::string& message)
      : std::runtime_error(format(path, line, message)), path_(std::move(path)), line_(line) {}

  const std::string& path() const { return path_; }
  int line() const { return line_; }

 private:
  static std::string format(const std::string& path, int line, const std::string& message) {
    // Appends rather than operator+ chains: GCC 12 reports a false -Wrestrict on those.
    std::string where = path.empty() ? std::string("<input>") : path;
    if (line > 0) where.append(1, ':').append(std::to_string(line));
    where.append(": ").append(message);
    return where;
  }
  std::string path_;
  int line_;
};

}  // namespace surftrace::build

// Files SurfTrace writes: whole or not at all, and every failure said. A full disk, a missing
// folder or a read-only one is an error naming the user's file and the reason, never a
// truncated file and exit status 0.
#pragma once

#include <cstddef>
#include <filesystem>
#include <span>
#include <stdexcept>
#include <string>
#include <string_view>

namespace surftrace::build {

// Raised when an output cannot be written; the message names the file (never a temporary
// one) and the system's reason ("No space left on device").
class OutputError : public std::runtime_error {
 public:
  using std::runtime_error::runtime_error;
};

// Writes `bytes` to `path` through a temporary file beside it, checking every write, the
// fsync and the close, then renames it over `path`, so that a file that exists is complete.
// On any failure the temporary file is removed, `path` is left as it was, and OutputError is
// thrown.
void writeFileAtomically(const std::filesystem::path& path, std::span<const std::byte> bytes);
void writeFileAtomically(const std::filesystem::path& path, std::string_view bytes);

// Checks, before any work, that `path` can be written: its folder exists (created with its
// parents when missing) and is a writable folder, and `path` itself is not a folder.
// OutputError names `option` (e.g. "-o"), the path and what is wrong.
void prepareOutputPath(const std::filesystem::path& path, std::string_view option);

// Flushes standard output and checks that everything printed reached it (a full disk or a
// closed pipe makes printf fail silently). OutputError when not.
void finishStandardOutput();

}  // namespace surftrace::build

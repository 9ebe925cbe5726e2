// Files SurfTrace writes: whole or not at all, and every failure said. A full disk, a missing
// folder or a read-only one is an error naming the user's file and the reason, never a
// truncated file and exit status 0. Writing never harms what the path names: a device, a FIFO
// or a socket is written in place, a symbolic link stays a link.
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

// What an output holds, where it matters: binary data (an image, a patch list) is not sent to
// a terminal.
enum class OutputContent { Text, Binary };

// "-", given where an output file is asked for, names the standard output; so do /dev/stdout,
// /dev/fd/1 and /proc/self/fd/1, which are written as "-" is.
bool isStandardOutput(const std::filesystem::path& path);

// Whether writeFileAtomically writes `path` in place: "-", or a path that names (through any
// links) a device, a FIFO or a socket. Such a name need not say the file's format (/dev/null).
bool isWrittenInPlace(const std::filesystem::path& path);

// Writes `bytes` to what `path` names:
// - a regular file (or none yet): through a temporary file `.NAME.partial-<pid>` beside it,
//   checking every write, the fsync and the close, then renamed over it, so that a file that
//   exists is complete. On any failure (an exception included) the temporary file is removed,
//   the file is left as it was, and OutputError is thrown. Temporaries that a killed run left
//   for the same file (their process is gone, or started after they were last written) are
//   removed.
// - a symbolic link (relative, absolute, a chain of them): its final target is replaced as
//   above, and the link stays.
// - a character or block device, a FIFO or a socket: written in place (opened without
//   truncating, no temporary, no rename), so that /dev/null stays a device and a reader at a
//   FIFO gets the bytes; /dev/full is an error.
// - "-": the standard output (the descriptor prepareOutputPath kept for it).
void writeFileAtomically(const std::filesystem::path& path, std::span<const std::byte> bytes);
void writeFileAtomically(const std::filesystem::path& path, std::string_view bytes);

// Checks, before any work, that `path` can be written: its folder exists (created with its
// parents when missing) and is a writable folder, and `path` itself is not a folder. A device,
// FIFO or socket must be writable; a symbolic link is checked at its final target (a dangling
// link is fine when its target's folder exists). OutputError names `option` (e.g. "-o"), the
// path and what is wrong.
// "-" claims the standard output for this option: binary content is refused on a terminal,
// only one option may claim it, and from then on what the program prints (its summaries)
// goes to the standard error, so that the standard output holds the file's bytes alone.
void prepareOutputPath(const std::filesystem::path& path, std::string_view option,
                       OutputContent content = OutputContent::Text);

// The descriptor that an output named "-" writes to: the standard output as it was when
// prepareOutputPath claimed it (STDOUT_FILENO when nothing did).
int standardOutputDescriptor();

// Flushes standard output and checks that everything printed reached it (a full disk or a
// closed pipe makes printf fail silently). OutputError, naming the standard output and the
// reason ("Broken pipe"), when not.
void finishStandardOutput();

// For loops that print much: OutputError as finishStandardOutput's once a write to standard
// output has failed (a reader that closed the pipe early), so that the command stops rather
// than compute on. Cheap (no flush): call it after each row.
void checkStandardOutput();

}  // namespace surftrace::build

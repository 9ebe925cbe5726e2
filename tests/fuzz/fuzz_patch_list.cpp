// libFuzzer harness for the .stp patch-list loader. An input whose first byte is even is
// wrapped as the body of a well-formed file (magic, version, size, and its CRC-32), so that
// the fuzzer reaches the parser of parameters and arrays behind the checksum; an odd first
// byte passes the rest through as the whole file, header and checksum included. Any bytes
// either load into a list that validates or raise std::runtime_error.
#include <zlib.h>

#include <cstddef>
#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <stdexcept>
#include <vector>

#include "build/patch_list.hpp"

namespace {

void append(std::vector<unsigned char>& out, const void* p, std::size_t n) {
  const auto* b = static_cast<const unsigned char*>(p);
  out.insert(out.end(), b, b + n);
}

}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  if (size == 0) return 0;
  std::vector<unsigned char> file;
  const unsigned char* rest = data + 1;
  const std::size_t n = size - 1;
  if (data[0] & 1) {
    file.assign(rest, rest + n);
  } else {
    // Little-endian hosts only (the fuzz build runs on x86-64).
    const char magic[8] = {'S', 'U', 'R', 'F', 'T', 'R', 'C', 'E'};
    const std::uint32_t version = surftrace::build::kPatchFileVersion, tag = 0x01020304u;
    const std::uint64_t bodySize = n;
    append(file, magic, sizeof magic);
    append(file, &version, 4);
    append(file, &tag, 4);
    append(file, &bodySize, 8);
    append(file, rest, n);
    const auto crc = static_cast<std::uint32_t>(crc32_z(crc32_z(0L, Z_NULL, 0), rest, n));
    append(file, &crc, 4);
  }
  surftrace::build::PatchList p;
  try {
    p = surftrace::build::parsePatchList(file, "fuzz-input.stp");
  } catch (const std::runtime_error&) {
    return 0;  // the contract: a bad file is a runtime_error that says what is wrong
  }
  try {
    p.validate();  // what the loader returns must validate
  } catch (const std::runtime_error& e) {
    std::fprintf(stderr, "fuzz: the loader returned a list that does not validate: %s\n", e.what());
    std::abort();
  }
  return 0;
}

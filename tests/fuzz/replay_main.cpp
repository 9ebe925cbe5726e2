// Runs one libFuzzer harness over the files named on the command line, without libFuzzer: the
// harness's contract (valid result or the reader's own error, nothing else) checked on real
// files by every build, and a link of the harness against only the sources tests/fuzz/sources.cmake
// lists. Usage: fuzz_replay_FORMAT [--mode-byte N] FILE...; --mode-byte puts byte N before each
// file's bytes (fuzz_patch_list.cpp reads a mode byte first: 1 passes the file as it is).
#include <cstddef>
#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <fstream>
#include <iterator>
#include <string>

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size);

int main(int argc, char** argv) {
  std::string prefix;
  int replayed = 0;
  for (int i = 1; i < argc; ++i) {
    const std::string arg = argv[i];
    if (arg == "--mode-byte" && i + 1 < argc) {
      prefix.assign(1, static_cast<char>(std::atoi(argv[++i])));
      continue;
    }
    std::ifstream in(arg, std::ios::binary);
    if (!in) {
      std::fprintf(stderr, "fuzz_replay: cannot read %s\n", arg.c_str());
      return 1;
    }
    const std::string bytes = prefix + std::string(std::istreambuf_iterator<char>(in), {});
    LLVMFuzzerTestOneInput(reinterpret_cast<const std::uint8_t*>(bytes.data()), bytes.size());
    ++replayed;
  }
  if (replayed == 0) {
    std::fprintf(stderr, "fuzz_replay: no files given\n");
    return 1;
  }
  std::printf("fuzz_replay: %d files, each read or refused as the contract says\n", replayed);
  return 0;
}

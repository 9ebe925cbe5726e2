// libFuzzer harness for one trajectory reader (DCD, XTC or GRO frames; fixed at compile time):
// any bytes either open and read frame by frame into finite positions of the announced atom
// count, or raise InputError; anything else is a bug (an escaping exception, an ASan or UBSan
// report, a frame of the wrong size). The readers take paths, so the bytes go to a file.
#include <unistd.h>

#include <cmath>
#include <cstddef>
#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <fstream>
#include <string>

#include "build/io/error.hpp"
#include "build/io/trajectory.hpp"

namespace {

using surftrace::build::TrajectoryFormat;

#if defined(SURFTRACE_FUZZ_FORMAT_DCD)
constexpr TrajectoryFormat kFormat = TrajectoryFormat::Dcd;
#elif defined(SURFTRACE_FUZZ_FORMAT_XTC)
constexpr TrajectoryFormat kFormat = TrajectoryFormat::Xtc;
#elif defined(SURFTRACE_FUZZ_FORMAT_GRO)
constexpr TrajectoryFormat kFormat = TrajectoryFormat::Gro;
#else
#error "define SURFTRACE_FUZZ_FORMAT_<FORMAT>"
#endif

[[noreturn]] void fail(const char* what) {
  std::fprintf(stderr, "fuzz: invalid frame: %s\n", what);
  std::abort();
}

const std::string& inputPath() {
  static const std::string path = "/tmp/surftrace_fuzz_trajectory_" + std::to_string(::getpid());
  return path;
}

}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  {
    std::ofstream out(inputPath(), std::ios::binary | std::ios::trunc);
    out.write(reinterpret_cast<const char*>(data), static_cast<std::streamsize>(size));
  }
  try {
    auto source = surftrace::build::openTrajectory(inputPath(), kFormat);
    surftrace::build::Frame frame;
    const std::size_t frames = source->frameCount();
    for (std::size_t k = 0; k < frames && k < 64; ++k) {
      try {
        source->read(frames - 1 - k, frame);  // backwards: random access, not a stream
      } catch (const surftrace::build::InputError&) {
        continue;  // one bad frame; the others must still read
      }
      if (frame.positions.size() != source->atomCount()) fail("a frame of another atom count");
      for (const auto& p : frame.positions)
        if (!std::isfinite(p.x) || !std::isfinite(p.y) || !std::isfinite(p.z)) fail("a position is not finite");
    }
  } catch (const surftrace::build::InputError&) {
  }
  return 0;
}

// libFuzzer harness for one structure reader (the format is fixed at compile time): any bytes
// either read into a valid molecule or raise InputError; anything else is a bug (an escaping
// exception, an ASan or UBSan report, an invalid molecule).
#include <cmath>
#include <cstddef>
#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <string>

#include "build/io/error.hpp"
#include "build/io/molecule.hpp"

namespace {

using surftrace::build::MoleculeFormat;

#if defined(SURFTRACE_FUZZ_FORMAT_PDB)
constexpr MoleculeFormat kFormat = MoleculeFormat::Pdb;
#elif defined(SURFTRACE_FUZZ_FORMAT_MMCIF)
constexpr MoleculeFormat kFormat = MoleculeFormat::Mmcif;
#elif defined(SURFTRACE_FUZZ_FORMAT_PQR)
constexpr MoleculeFormat kFormat = MoleculeFormat::Pqr;
#elif defined(SURFTRACE_FUZZ_FORMAT_XYZR)
constexpr MoleculeFormat kFormat = MoleculeFormat::Xyzr;
#elif defined(SURFTRACE_FUZZ_FORMAT_XYZ)
constexpr MoleculeFormat kFormat = MoleculeFormat::Xyz;
#else
#error "define SURFTRACE_FUZZ_FORMAT_<FORMAT>"
#endif

[[noreturn]] void fail(const char* what) {
  std::fprintf(stderr, "fuzz: invalid molecule: %s\n", what);
  std::abort();
}

}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  surftrace::build::ReadOptions options;
  options.format = kFormat;
  // The last byte, when there is one, also picks the options that change what the reader
  // does after parsing (water, hydrogens, model 2, radius 0), so selection is fuzzed too; a
  // file ending in a newline (0x0a) reads with the defaults.
  if (size > 0) {
    const std::uint8_t knobs = data[size - 1] ^ 0x0a;
    options.keepWater = knobs & 1;
    options.keepHydrogens = !(knobs & 2);
    options.model = (knobs & 4) ? 2 : 1;
    options.dropZeroRadius = knobs & 8;
    if (knobs & 16) options.defaultRadius = 1.5;
  }
  try {
    const surftrace::build::Molecule m = surftrace::build::readMoleculeBytes(
        std::string(reinterpret_cast<const char*>(data), size), "fuzz-input", options);
    if (m.size() == 0) fail("no atoms");
    if (m.radii.size() != m.size() || m.atoms.size() != m.size()) fail("array lengths differ");
    for (std::size_t i = 0; i < m.size(); ++i) {
      const auto& c = m.centers[i];
      if (!std::isfinite(c.x) || !std::isfinite(c.y) || !std::isfinite(c.z)) fail("a centre is not finite");
      if (!std::isfinite(m.radii[i]) || !(m.radii[i] > 0.0)) fail("a radius is not finite and > 0");
    }
  } catch (const surftrace::build::InputError&) {
    // The contract: bad input is an InputError naming the file and line.
  }
  return 0;
}

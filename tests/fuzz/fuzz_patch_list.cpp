// libFuzzer harness for the .stp patch-list loader and what reads a loaded list. An input
// whose first byte is even is wrapped as the body of a well-formed file (magic, version, size,
// and its CRC-32), so that the fuzzer reaches the parser of parameters and arrays behind the
// checksum and the validation of every field; an odd first byte passes the rest through as the
// whole file, header and checksum included. Any bytes either raise std::runtime_error, or load
// into a list that validates and that every consumer takes without a crash, an exception or a
// non-finite result: `surftrace area` (SES areas, with and without --drop-cavities), `info`,
// the trace setup (each patch's record and box, and one ray at it) and the GL upload.
#include <zlib.h>

#include <algorithm>
#include <cmath>
#include <cstddef>
#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <limits>
#include <stdexcept>
#include <string>
#include <vector>

#include <tbb/global_control.h>

#include "build/patch_list.hpp"
#include "build/io/stp_file.hpp"
#include "build/ses/surface_area.hpp"
#include "build/surface_components.hpp"
#include "build/surface_topology.hpp"
#include "gl/gpu_kinds.hpp"
#include "trace/concave_patch.hpp"
#include "trace/mss_patch.hpp"
#include "trace/sphere_patch.hpp"
#include "trace/torus_patch.hpp"

namespace {

using namespace surftrace;

// Per-atom arrays of a list announcing more atoms than this would pass the fuzzer's memory
// limit: such lists are loaded and validated but not handed to `area`.
constexpr std::uint32_t kMaxAreaAtoms = 1u << 20;

void append(std::vector<unsigned char>& out, const void* p, std::size_t n) {
  const auto* b = static_cast<const unsigned char*>(p);
  out.insert(out.end(), b, b + n);
}

[[noreturn]] void fail(const std::string& what) {
  std::fprintf(stderr, "fuzz: %s\n", what.c_str());
  std::abort();
}

bool finite(const glm::dvec3& v) { return std::isfinite(v.x) && std::isfinite(v.y) && std::isfinite(v.z); }

// What `surftrace area FILE.stp` does with an SES list: the atoms' radii from the convex
// patches, then the areas, per atom and per component.
void area(const build::PatchList& p, const char* what) {
  std::vector<double> radii(p.params.atomCount, std::numeric_limits<double>::quiet_NaN());
  for (std::size_t k = 0; k < p.convex.size(); ++k) radii.at(p.convex.atom[k]) = p.convex.radius[k];
  const build::SurfaceAreas a = build::computeAreas(p);
  double sum = a.sas + a.sesTotal() + a.sesVolume;
  for (const double v : a.sasPerAtom) sum += v;
  for (const double v : a.sesPerAtom) sum += v;
  for (const auto& c : a.components) sum += c.area + c.volume;
  if (!std::isfinite(sum)) fail(std::string(what) + ": an area or volume is not finite");
  if (a.components.size() != std::max<std::size_t>(1, p.componentCount))
    fail(std::string(what) + ": " + std::to_string(a.components.size()) + " components, the list says " +
         std::to_string(p.componentCount));
  // The topology line: one entry per component at least, each residual a number.
  const std::vector<build::ComponentTopology> topology = build::surfaceTopology(p);
  if (topology.size() < a.components.size()) fail(std::string(what) + ": fewer topologies than components");
  for (const build::ComponentTopology& t : topology)
    if (t.resolved && !(t.residual < 1.0)) fail(std::string(what) + ": a resolved topology whose sum is off an integer");
}

// The trace setup: each patch's intersector record and its box (Embree drops a box that is
// not finite, silently), and one ray from outside the box at its centre. A box may be empty:
// an MSS cell whose cap cuts off the whole ball holds no skin, and Embree rightly drops it.
template <class Patch> void traceOne(const Patch& patch, const char* kind, std::size_t k) {
  const trace::Bounds3d box = trace::bounds(patch);
  if (!finite(box.lower) || !finite(box.upper))
    fail(std::string(kind) + " patch " + std::to_string(k) + ": its box is not finite");
  if (box.empty()) return;
  const glm::dvec3 centre = 0.5 * (box.lower + box.upper), size = box.upper - box.lower;
  const trace::Ray ray{centre + glm::dvec3(1.0 + size.x + size.y + size.z, 0.25, 0.5), glm::dvec3(-1.0, 0.0, 0.0)};
  if (const auto hit = trace::intersect(patch, ray, 0.0, std::numeric_limits<double>::infinity()))
    if (!std::isfinite(hit->t) || !finite(hit->normal))
      fail(std::string(kind) + " patch " + std::to_string(k) + ": a hit that is not finite");
}

void consumers(const build::PatchList& p) {
  // `info`
  if (std::strcmp(build::surfaceKindName(p.params.surface), "unknown") == 0) fail("info: unknown surface kind");
  // `area`: SES lists only (the tool refuses the others), and --drop-cavities.
  if (p.params.surface == build::SurfaceKind::Ses && p.params.atomCount <= kMaxAreaAtoms) {
    area(p, "area");
    const build::PatchList outer = build::outerComponent(p);
    try {
      outer.validate();
    } catch (const std::runtime_error& e) {
      fail(std::string("outerComponent returned a list that does not validate: ") + e.what());
    }
    area(outer, "area --drop-cavities");
  }
  // `render --engine embree`
  for (std::size_t k = 0; k < p.convex.size(); ++k) traceOne(trace::SpherePatch{p.convex.center[k], p.convex.radius[k]}, "convex", k);
  for (std::size_t k = 0; k < p.tori.size(); ++k) traceOne(trace::torusPatch(p.tori, k, p.params.probeRadius), "torus", k);
  for (std::size_t k = 0; k < p.concave.size(); ++k) traceOne(trace::concavePatch(p, k), "concave", k);
  for (std::size_t k = 0; k < p.mss.size(); ++k) {
    const build::MssExtent e = build::mssExtent(p, k);
    if (!std::isfinite(e.hLo) || !std::isfinite(e.hHi) || !std::isfinite(e.rho))
      fail("mss patch " + std::to_string(k) + ": its extent is not finite");
    traceOne(trace::mssPatch(p, k), "mss", k);
  }
  // `render --engine gl`: the upload, shifted to the first patch as the renderer shifts to the scene.
  const gl::GpuPatches g = gl::packPatches(p, p.convex.size() > 0 ? p.convex.center[0] : glm::dvec3(0.0));
  if (!finite(g.boundsCenter) || !std::isfinite(g.boundsRadius)) fail("gl: the bounding sphere is not finite");
}

}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  // One thread: the areas sum the same way on every run, and a crash is in the fuzzer's thread.
  static tbb::global_control oneThread(tbb::global_control::max_allowed_parallelism, 1);
  if (size == 0) return 0;
  std::vector<unsigned char> file;
  const unsigned char* rest = data + 1;
  const std::size_t n = size - 1;
  if (data[0] & 1) {
    file.assign(rest, rest + n);
  } else {
    // Little-endian hosts only (the fuzz build runs on x86-64).
    const char magic[8] = {'S', 'U', 'R', 'F', 'T', 'R', 'C', 'E'};
    const std::uint32_t version = build::kPatchFileVersion, tag = 0x01020304u;
    const std::uint64_t bodySize = n;
    append(file, magic, sizeof magic);
    append(file, &version, 4);
    append(file, &tag, 4);
    append(file, &bodySize, 8);
    append(file, rest, n);
    const auto crc = static_cast<std::uint32_t>(crc32_z(crc32_z(0L, Z_NULL, 0), rest, n));
    append(file, &crc, 4);
  }
  build::PatchList p;
  try {
    p = build::parsePatchList(file, "fuzz-input.stp");
  } catch (const std::runtime_error&) {
    return 0;  // the contract: a bad file is a runtime_error that says what is wrong
  }
  try {
    p.validate();  // what the loader returns must validate
  } catch (const std::runtime_error& e) {
    fail(std::string("the loader returned a list that does not validate: ") + e.what());
  }
  try {
    consumers(p);
  } catch (const std::exception& e) {
    fail(std::string("a consumer of a loaded list threw: ") + e.what());
  }
  return 0;
}

// The patch list's versioned binary file (.stp): its layout, the writer and the reader, and the
// skin stored by reference to its atoms (derived again with mss/skin_geometry.hpp, the functions
// the builder itself uses; no builder is included here).
#include "build/io/stp_file.hpp"

#include <algorithm>
#include <array>
#include <atomic>
#include <cmath>
#include <cstring>
#include <fstream>
#include <stdexcept>
#include <type_traits>

#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>
#include <zlib.h>

#include "build/io/output_file.hpp"
#include "build/mss/skin_geometry.hpp"
#include "build/patch_list_checks.hpp"

namespace surftrace::build {

namespace {

using list_checks::checkList;
using list_checks::checkParams;
using list_checks::checkRange;
using list_checks::checkSimplices;
using list_checks::finite;
using list_checks::inCube;
using list_checks::kMaxLength;
using list_checks::text;

// Scalar type and component count of an array element, as stored in the file.
enum class Scalar : std::uint32_t { F64 = 1, U32 = 2 };
template <class T> struct ElementInfo;
template <> struct ElementInfo<double> { static constexpr Scalar kScalar = Scalar::F64; static constexpr std::uint32_t kComponents = 1; };
template <> struct ElementInfo<std::uint32_t> { static constexpr Scalar kScalar = Scalar::U32; static constexpr std::uint32_t kComponents = 1; };
template <> struct ElementInfo<glm::dvec3> { static constexpr Scalar kScalar = Scalar::F64; static constexpr std::uint32_t kComponents = 3; };
template <> struct ElementInfo<glm::dvec4> { static constexpr Scalar kScalar = Scalar::F64; static constexpr std::uint32_t kComponents = 4; };
template <> struct ElementInfo<glm::uvec4> { static constexpr Scalar kScalar = Scalar::U32; static constexpr std::uint32_t kComponents = 4; };

static_assert(sizeof(glm::dvec3) == 24 && sizeof(glm::dvec4) == 32 && sizeof(glm::uvec4) == 16,
              "patch arrays are written as packed scalars");

constexpr char kMagic[8] = {'S', 'U', 'R', 'F', 'T', 'R', 'C', 'E'};
constexpr std::uint32_t kEndianTag = 0x01020304u;
constexpr std::size_t kHeaderSize = 8 + 4 + 4 + 8;

// Fills a buffer of the file's exact size (counted first): one allocation, no copies.
class Writer {
 public:
  explicit Writer(std::size_t size) : bytes(size) {}
  void raw(const void* p, std::size_t n) {
    if (n > bytes.size() - pos) throw std::logic_error("patch list writer: the file outgrew its counted size");
    if (n > 0) std::memcpy(bytes.data() + pos, p, n);
    pos += n;
  }
  template <class T> void pod(const T& v) {
    static_assert(std::is_trivially_copyable_v<T>);
    raw(&v, sizeof(T));
  }
  void string(const std::string& s) {
    pod(static_cast<std::uint32_t>(s.size()));
    raw(s.data(), s.size());
  }
  template <class T> void array(const std::vector<T>& v) { raw(v.data(), v.size() * sizeof(T)); }
  std::vector<unsigned char> bytes;
  std::size_t pos = 0;
};

class Reader {
 public:
  Reader(const std::string& path, const unsigned char* data, std::size_t size, bool swap)
      : path_(path), data_(data), size_(size), swap_(swap) {}

  template <class T> T pod(const char* what) {
    static_assert(std::is_trivially_copyable_v<T>);
    need(sizeof(T), what);
    T v;
    std::memcpy(&v, data_ + pos_, sizeof(T));
    pos_ += sizeof(T);
    if constexpr (sizeof(T) > 1 && std::is_arithmetic_v<T>) {
      if (swap_) v = byteSwap(v);
    }
    return v;
  }
  std::string string(const char* what) {
    const auto n = pod<std::uint32_t>(what);
    need(n, what);
    std::string s(reinterpret_cast<const char*>(data_ + pos_), n);
    pos_ += n;
    return s;
  }
  template <class T> void array(std::vector<T>& v, std::uint64_t count, const char* what) {
    using Info = ElementInfo<T>;
    constexpr std::size_t kScalarSize = Info::kScalar == Scalar::F64 ? 8 : 4;
    if (count > (size_ - pos_) / sizeof(T)) fail(std::string("array ") + what + " runs past the end of the file");
    v.resize(count);
    if (count == 0) return;  // v.data() may be null; memcpy forbids that even for 0 bytes
    std::memcpy(v.data(), data_ + pos_, count * sizeof(T));
    pos_ += count * sizeof(T);
    if (swap_) {
      auto* raw = reinterpret_cast<unsigned char*>(v.data());
      for (std::size_t k = 0; k < count * Info::kComponents; ++k) {
        unsigned char* s = raw + k * kScalarSize;
        for (std::size_t a = 0, b = kScalarSize - 1; a < b; ++a, --b) std::swap(s[a], s[b]);
      }
    }
  }
  bool atEnd() const { return pos_ == size_; }
  [[noreturn]] void fail(const std::string& message) const {
    throw std::runtime_error(path_ + ": corrupt patch list: " + message);
  }

 private:
  template <class T> static T byteSwap(T v) {
    unsigned char b[sizeof(T)];
    std::memcpy(b, &v, sizeof(T));
    for (std::size_t a = 0, c = sizeof(T) - 1; a < c; ++a, --c) std::swap(b[a], b[c]);
    std::memcpy(&v, b, sizeof(T));
    return v;
  }
  void need(std::size_t n, const char* what) const {
    if (n > size_ - pos_) fail(std::string("file ends inside ") + what);
  }
  std::string path_;
  const unsigned char* data_;
  std::size_t size_;
  std::size_t pos_ = 0;
  bool swap_;
};

std::uint32_t crc32Of(const unsigned char* data, std::size_t size) {
  uLong crc = crc32(0L, Z_NULL, 0);
  // zlib takes uInt lengths: feed large bodies in pieces.
  while (size > 0) {
    const auto piece = static_cast<uInt>(std::min<std::size_t>(size, 1u << 30));
    crc = crc32(crc, data, piece);
    data += piece;
    size -= piece;
  }
  return static_cast<std::uint32_t>(crc);
}

std::uint32_t swapBytes(std::uint32_t v) {
  return (v >> 24) | ((v >> 8) & 0xff00u) | ((v << 8) & 0xff0000u) | (v << 24);
}

}  // namespace

namespace {

// ---- The file's arrays ----

bool isSkinGroup(const char* group) {
  return std::strcmp(group, "mss") == 0 || std::strcmp(group, "cellPlanes") == 0 || std::strcmp(group, "skinAtoms") == 0;
}

// Version 2: every array of forEachArray but cellPlanes.atom and skinAtoms, which it predates.
template <class Visit, class List>
void version2Arrays(Visit&& visit, List& p) {
  forEachArray([&](const char* group, const char* name, auto& v) {
    const bool newer = (std::strcmp(group, "cellPlanes") == 0 && std::strcmp(name, "atom") == 0) ||
                       std::strcmp(group, "skinAtoms") == 0;
    if (!newer) visit(std::string(group) + "." + name, v);
  }, p);
}

// What version 3 stores of the skin besides the simplices (mss.atoms), the plane counts
// (mss.cellCount) and the atom across each plane (cellPlanes.atom).
struct SkinFile {
  std::vector<glm::dvec3> atomCenter;  // z_i of every atom of the list, or none: skinAtoms.center
  std::vector<double> atomWeight;      // w_i = mss::skinWeight(r_i, s): skinAtoms.weight
  std::vector<std::uint32_t> cellBegin;  // empty: the running sum of mss.cellCount
  // The patches stored whole (ascending) and their fields; the others are derived.
  std::vector<std::uint32_t> wholePatch;
  std::vector<glm::dvec3> center, axis;
  std::vector<double> radialCoeff, axialCoeff, constant, boundRadius;
  // The planes stored whole (ascending) and their values; the others are derived.
  std::vector<std::uint32_t> wholePlane;
  std::vector<Plane> plane;
};

// Version 3: the SES arrays as in version 2, then the skin (SkinFile).
template <class Visit, class List, class Skin>
void version3Arrays(Visit&& visit, List& p, Skin& f) {
  forEachArray([&](const char* group, const char* name, auto& v) {
    if (!isSkinGroup(group)) visit(std::string(group) + "." + name, v);
  }, p);
  visit("skin.center", f.atomCenter);
  visit("skin.weight", f.atomWeight);
  visit("mss.atoms", p.mss.atoms);
  visit("mss.cellCount", p.mss.cellCount);
  visit("mss.cellBegin", f.cellBegin);
  visit("mss.whole", f.wholePatch);
  visit("mss.center", f.center);
  visit("mss.axis", f.axis);
  visit("mss.radialCoeff", f.radialCoeff);
  visit("mss.axialCoeff", f.axialCoeff);
  visit("mss.constant", f.constant);
  visit("mss.boundRadius", f.boundRadius);
  visit("cellPlanes.atom", p.cellPlaneAtom);
  visit("cellPlanes.whole", f.wholePlane);
  visit("cellPlanes.plane", f.plane);
}

// The simplex of a patch's atoms (kind + 1 of them, then ~0u).
mss::Simplex simplexOf(const glm::uvec4& atoms) {
  mss::Simplex x;
  while (x.size < 4 && atoms[x.size] != ~0u) {
    x.atom[x.size] = atoms[x.size];
    ++x.size;
  }
  return x;
}

// Whether the plane of X across atom a is mss::cellPlane's: a is an atom of X (which then has
// two atoms or more) or another atom (and X has three or fewer).
bool planeAcross(const mss::Simplex& x, std::uint32_t a, std::size_t atomCount) {
  if (a >= atomCount) return false;
  for (int k = 0; k < x.size; ++k)
    if (x[k] == a) return x.size >= 2;
  return x.size <= 3;
}

template <class T> bool sameBits(const T& a, const T& b) { return std::memcmp(&a, &b, sizeof(T)) == 0; }

// Patches of a list whose planes lie in one run, each after the one before.
bool runningCells(const MssQuadrics& q) {
  std::uint64_t sum = 0;
  for (std::size_t k = 0; k < q.size(); ++k) {
    if (q.cellBegin[k] != sum) return false;
    sum += q.cellCount[k];
  }
  return true;
}

// Which patches and planes of a valid list derive back to their own bits from `atoms`.
void markDerivable(const PatchList& p, const mss::WeightedPoints& w, std::vector<std::uint8_t>& patchWhole,
                   std::vector<std::uint8_t>& planeWhole) {
  const MssQuadrics& q = p.mss;
  tbb::parallel_for(tbb::blocked_range<std::size_t>(0, q.size(), 512), [&](const tbb::blocked_range<std::size_t>& range) {
    for (std::size_t k = range.begin(); k < range.end(); ++k) {
      const mss::Simplex x = simplexOf(q.atoms[k]);
      try {
        const mss::SkinPatch d = mss::skinPatch(w, x);
        patchWhole[k] = !(sameBits(d.quadric.center, q.center[k]) && sameBits(d.quadric.axis, q.axis[k]) &&
                          sameBits(d.quadric.radial, q.radialCoeff[k]) && sameBits(d.quadric.axial, q.axialCoeff[k]) &&
                          sameBits(d.quadric.constant, q.constant[k]) && sameBits(d.boundRadius, q.boundRadius[k]));
        for (std::uint32_t m = q.cellBegin[k]; m < q.cellBegin[k] + q.cellCount[k]; ++m) {
          const std::uint32_t a = p.cellPlaneAtom[m];
          planeWhole[m] = !(planeAcross(x, a, w.z.size()) && sameBits(mss::cellPlane(w, x, d.quadric.center, a), p.cellPlanes[m]));
        }
      } catch (const std::invalid_argument&) {
        // A degenerate simplex (not the builder's): the patch and its planes are stored whole.
      }
    }
  });
}

SkinFile encodeSkin(const PatchList& p, const PatchListAtoms& atoms) {
  SkinFile f;
  const MssQuadrics& q = p.mss;
  const bool running = runningCells(q);
  if (!running) f.cellBegin = q.cellBegin;
  std::vector<std::uint8_t> patchWhole(q.size(), 1), planeWhole(p.cellPlanes.size(), 1);
  if (!atoms.centers.empty() && q.size() > 0) {
    if (atoms.centers.size() != p.params.atomCount || atoms.radii.size() != atoms.centers.size())
      throw std::invalid_argument("writePatchList: " + std::to_string(atoms.centers.size()) + " centres and " +
                                  std::to_string(atoms.radii.size()) + " radii given for a list of " +
                                  std::to_string(p.params.atomCount) + " atoms");
    f.atomCenter.assign(atoms.centers.begin(), atoms.centers.end());
    f.atomWeight.resize(atoms.radii.size());
    for (std::size_t i = 0; i < atoms.radii.size(); ++i) f.atomWeight[i] = mss::skinWeight(atoms.radii[i], p.params.shrinkFactor);
  } else if (!p.skinAtoms.center.empty()) {
    // The list carries its atoms (the builder's lists do): the same weighted points.
    f.atomCenter = p.skinAtoms.center;
    f.atomWeight = p.skinAtoms.weight;
  }
  if (!f.atomCenter.empty() && q.size() > 0) {
    // Only planes in one run are derived, each from the one patch whose run holds it (the
    // builder's lists); the planes of scattered or overlapping ranges are stored whole.
    if (running) markDerivable(p, {f.atomCenter, f.atomWeight, p.params.shrinkFactor}, patchWhole, planeWhole);
  }
  for (std::size_t k = 0; k < q.size(); ++k) {
    if (!patchWhole[k]) continue;
    f.wholePatch.push_back(static_cast<std::uint32_t>(k));
    f.center.push_back(q.center[k]);
    f.axis.push_back(q.axis[k]);
    f.radialCoeff.push_back(q.radialCoeff[k]);
    f.axialCoeff.push_back(q.axialCoeff[k]);
    f.constant.push_back(q.constant[k]);
    f.boundRadius.push_back(q.boundRadius[k]);
  }
  for (std::size_t m = 0; m < p.cellPlanes.size(); ++m)
    if (planeWhole[m]) {
      f.wholePlane.push_back(static_cast<std::uint32_t>(m));
      f.plane.push_back(p.cellPlanes[m]);
    }
  return f;
}

}  // namespace

std::vector<unsigned char> encodePatchList(const PatchList& patches, const PatchListAtoms& atoms, std::uint32_t version) {
  if (version != 2 && version != 3) throw std::invalid_argument("encodePatchList: version " + std::to_string(version));
  patches.validate();
  SkinFile skin;
  if (version == 3) skin = encodeSkin(patches, atoms);
  auto table = [&](auto&& visit) {
    if (version == 3) version3Arrays(visit, patches, skin);
    else version2Arrays(visit, patches);
  };
  // The whole file in one buffer of its exact size, counted first.
  std::uint32_t arrays = 0;
  std::size_t size = kHeaderSize + 4 + 8 + 8 + 4 + patches.params.radiiSet.size() + 4 + 4 + 4 + 4 + 4;
  table([&](const std::string& name, const auto& v) {
    ++arrays;
    size += 4 + name.size() + 4 + 4 + 8 + v.size() * sizeof(v[0]);
  });
  const std::uint64_t bodySize = size - kHeaderSize - 4;
  if (patches.params.atomCount > kMaxAtomsPerByte * bodySize)
    throw std::invalid_argument(
        "the list speaks of " + std::to_string(patches.params.atomCount) + " atoms but holds " +
        std::to_string(patches.patchCount()) + " patches in " + std::to_string(bodySize) + " bytes, more than " +
        std::to_string(kMaxAtomsPerByte) +
        " atoms a byte, which readers refuse as a damaged file: nearly all of the input's atoms add nothing "
        "to the surface (copies or near-copies of other atoms, or buried); remove them from the input");
  Writer file(size);
  file.raw(kMagic, sizeof kMagic);
  file.pod(version);
  file.pod(kEndianTag);
  file.pod(static_cast<std::uint64_t>(size - kHeaderSize - 4));
  file.pod(static_cast<std::uint32_t>(patches.params.surface));
  file.pod(patches.params.probeRadius);
  file.pod(patches.params.shrinkFactor);
  file.string(patches.params.radiiSet);
  file.pod(patches.params.inputCrc32);
  file.pod(patches.params.atomCount);
  file.pod(patches.componentCount);
  file.pod(arrays);
  table([&](const std::string& name, const auto& v) {
    using Info = ElementInfo<typename std::decay_t<decltype(v)>::value_type>;
    file.string(name);
    file.pod(static_cast<std::uint32_t>(Info::kScalar));
    file.pod(Info::kComponents);
    file.pod(static_cast<std::uint64_t>(v.size()));
    file.array(v);
  });
  file.pod(crc32Of(file.bytes.data() + kHeaderSize, size - kHeaderSize - 4));
  if (file.pos != size) throw std::logic_error("patch list writer: the file is shorter than its counted size");
  return std::move(file.bytes);
}

void writePatchList(const std::string& path, const PatchList& patches, const PatchListAtoms& atoms) {
  std::vector<unsigned char> bytes;
  try {
    bytes = encodePatchList(patches, atoms);
  } catch (const std::invalid_argument& e) {
    throw std::invalid_argument(path + ": " + e.what());
  }
  // Beside the target, checked, then renamed: a full disk or a crash never leaves a
  // half-written file.
  writeFileAtomically(path, std::as_bytes(std::span<const unsigned char>(bytes)));
}

bool isPatchListFile(const std::string& path) {
  std::ifstream in(path, std::ios::binary);
  char head[sizeof kMagic] = {};
  return in.read(head, sizeof head) && std::memcmp(head, kMagic, sizeof kMagic) == 0;
}

PatchList readPatchList(const std::string& path) {
  std::ifstream in(path, std::ios::binary | std::ios::ate);
  if (!in) throw std::runtime_error(path + ": cannot open patch list");
  const std::streamoff size = in.tellg();
  if (size < 0) throw std::runtime_error(path + ": cannot read patch list");
  // One read of the whole file.
  std::vector<unsigned char> bytes(static_cast<std::size_t>(size));
  in.seekg(0);
  if (!in.read(reinterpret_cast<char*>(bytes.data()), size)) throw std::runtime_error(path + ": cannot read patch list");
  return parsePatchList(bytes, path);
}

namespace {

// Reads one named array of the table; the name and element type must be the expected ones.
template <class T>
void readArray(Reader& r, const std::string& want, std::vector<T>& v) {
  using Info = ElementInfo<T>;
  const std::string got = r.string("array name");
  if (got != want) r.fail("expected array " + want + ", found " + got);
  const auto scalar = r.pod<std::uint32_t>("array type");
  const auto components = r.pod<std::uint32_t>("array width");
  if (scalar != static_cast<std::uint32_t>(Info::kScalar) || components != Info::kComponents)
    r.fail("array " + want + " has the wrong element type");
  const auto count = r.pod<std::uint64_t>("array length");
  r.array(v, count, want.c_str());
}

// Strictly ascending indices below `limit`, with `values` of one per index.
void checkWhole(Reader& r, const std::vector<std::uint32_t>& index, std::size_t limit, const char* name, std::size_t values) {
  for (std::size_t e = 0; e < index.size(); ++e)
    if (index[e] >= limit || (e > 0 && index[e] <= index[e - 1]))
      r.fail(std::string(name) + "[" + std::to_string(e) + "] = " + std::to_string(index[e]) +
             " is not an index above the one before and below " + std::to_string(limit) + " (the file is damaged)");
  if (values != index.size())
    r.fail(std::string(name) + " lists " + std::to_string(index.size()) + " entries stored whole, their values " +
           std::to_string(values) + " (the file is damaged)");
}

// The derived fields of patch k and its planes not stored whole; an empty string, or what is
// wrong with them.
std::string derivePatch(PatchList& p, const mss::WeightedPoints& w, const std::vector<std::uint8_t>& patchWhole,
                        const std::vector<std::uint8_t>& planeWhole, std::size_t k) {
  MssQuadrics& q = p.mss;
  const mss::Simplex x = simplexOf(q.atoms[k]);
  bool derived = !patchWhole[k];
  for (std::uint32_t m = q.cellBegin[k]; m < q.cellBegin[k] + q.cellCount[k]; ++m) derived = derived || !planeWhole[m];
  if (!derived) return {};
  if (w.z.empty()) return "mss patch " + std::to_string(k) + " is stored by reference, but the file holds no atoms";
  for (int a = 0; a < x.size; ++a)
    if (x[a] >= w.z.size()) return "mss.atoms[" + std::to_string(k) + "] names atom " + std::to_string(x[a]) + " of " + std::to_string(w.z.size());
  try {
    const mss::SkinPatch d = mss::skinPatch(w, x);
    if (!patchWhole[k]) {
      q.center[k] = d.quadric.center;
      q.axis[k] = d.quadric.axis;
      q.radialCoeff[k] = d.quadric.radial;
      q.axialCoeff[k] = d.quadric.axial;
      q.constant[k] = d.quadric.constant;
      q.boundRadius[k] = d.boundRadius;
    }
    for (std::uint32_t m = q.cellBegin[k]; m < q.cellBegin[k] + q.cellCount[k]; ++m) {
      if (planeWhole[m]) continue;
      const std::uint32_t a = p.cellPlaneAtom[m];
      if (!planeAcross(x, a, w.z.size()))
        return "cellPlanes.atom[" + std::to_string(m) + "] = " + std::to_string(a) + " is not an atom across a face of mss patch " +
               std::to_string(k) + " (its own atoms when it has 2 or more, others when it has 3 or fewer)";
      p.cellPlanes[m] = mss::cellPlane(w, x, d.quadric.center, a);
    }
  } catch (const std::invalid_argument& e) {
    return "mss.atoms[" + std::to_string(k) + "] = " + text(q.atoms[k]) + " is " + e.what() + ": no skin patch";
  }
  return {};
}

// Version 3's skin: the arrays of `f` (read) expanded into the patch list's.
void expandSkin(Reader& r, PatchList& p, const SkinFile& f) {
  MssQuadrics& q = p.mss;
  const std::size_t n = q.atoms.size();
  if (q.cellCount.size() != n) r.fail("mss.cellCount has " + std::to_string(q.cellCount.size()) + " entries, expected " + std::to_string(n));
  if (!f.cellBegin.empty() && f.cellBegin.size() != n)
    r.fail("mss.cellBegin has " + std::to_string(f.cellBegin.size()) + " entries, expected 0 or " + std::to_string(n));
  if (f.atomCenter.size() != f.atomWeight.size() || (!f.atomCenter.empty() && f.atomCenter.size() != p.params.atomCount))
    r.fail("the skin's atoms hold " + std::to_string(f.atomCenter.size()) + " centres and " + std::to_string(f.atomWeight.size()) +
           " weights for a list of " + std::to_string(p.params.atomCount) + " atoms");
  for (std::size_t i = 0; i < f.atomCenter.size(); ++i) {
    if (!finite(f.atomCenter[i]) || !inCube(f.atomCenter[i]))
      r.fail("skin.center[" + std::to_string(i) + "] = " + text(f.atomCenter[i]) + " is not a point within " + text(kMaxLength) + " Å (the file is damaged)");
    if (!(f.atomWeight[i] >= 0.0 && f.atomWeight[i] <= kMaxLength * kMaxLength))
      r.fail("skin.weight[" + std::to_string(i) + "] = " + text(f.atomWeight[i]) + " is not in [0, " + text(kMaxLength * kMaxLength) + "] (the file is damaged)");
  }
  // The simplices, kinds and plane ranges, checked before anything is derived from them.
  q.kind.resize(n);
  for (std::size_t k = 0; k < n; ++k) q.kind[k] = static_cast<std::uint32_t>(std::max(simplexOf(q.atoms[k]).size, 1) - 1);
  try {
    checkSimplices(q, p.params.atomCount);
  } catch (const std::runtime_error& e) {
    r.fail(std::string(e.what()) + " (the file is damaged, or was not written by surftrace)");
  }
  const std::uint64_t planeCount = p.cellPlaneAtom.size();
  if (f.cellBegin.empty()) {
    q.cellBegin.resize(n);
    std::uint64_t sum = 0;
    for (std::size_t k = 0; k < n; ++k) {
      q.cellBegin[k] = static_cast<std::uint32_t>(std::min<std::uint64_t>(sum, ~0u));
      sum += q.cellCount[k];
      if (sum > planeCount)
        r.fail("mss.cellCount[" + std::to_string(k) + "] = " + std::to_string(q.cellCount[k]) + " runs past the " +
               std::to_string(planeCount) + " planes (the file is damaged)");
    }
  } else {
    q.cellBegin = f.cellBegin;
    if (f.wholePlane.size() != planeCount) r.fail("a list with its own mss.cellBegin must store every plane whole (the file is damaged)");
    try {
      checkRange(q.cellBegin, q.cellCount, planeCount, "mss", "cellBegin", "cellCount", "cellPlanes");
    } catch (const std::runtime_error& e) {
      r.fail(std::string(e.what()) + " (the file is damaged)");
    }
  }
  checkWhole(r, f.wholePatch, n, "mss.whole", f.center.size());
  for (const auto* v : {&f.radialCoeff, &f.axialCoeff, &f.constant, &f.boundRadius})
    if (v->size() != f.center.size() || f.axis.size() != f.center.size()) r.fail("the arrays of the mss patches stored whole differ in length");
  checkWhole(r, f.wholePlane, planeCount, "cellPlanes.whole", f.plane.size());
  // Whole ones in place; then the rest derived, patch by patch in parallel.
  std::vector<std::uint8_t> patchWhole(n, 0), planeWhole(planeCount, 0);
  q.center.resize(n);
  q.axis.resize(n);
  q.radialCoeff.resize(n);
  q.axialCoeff.resize(n);
  q.constant.resize(n);
  q.boundRadius.resize(n);
  for (std::size_t e = 0; e < f.wholePatch.size(); ++e) {
    const std::uint32_t k = f.wholePatch[e];
    patchWhole[k] = 1;
    q.center[k] = f.center[e];
    q.axis[k] = f.axis[e];
    q.radialCoeff[k] = f.radialCoeff[e];
    q.axialCoeff[k] = f.axialCoeff[e];
    q.constant[k] = f.constant[e];
    q.boundRadius[k] = f.boundRadius[e];
  }
  p.cellPlanes.resize(planeCount);
  for (std::size_t e = 0; e < f.wholePlane.size(); ++e) {
    planeWhole[f.wholePlane[e]] = 1;
    p.cellPlanes[f.wholePlane[e]] = f.plane[e];
  }
  // A plane outside every patch's run has nothing to be derived from.
  const std::uint64_t covered = n == 0 ? 0 : std::uint64_t{q.cellBegin[n - 1]} + q.cellCount[n - 1];
  for (std::uint64_t m = f.cellBegin.empty() ? covered : planeCount; m < planeCount; ++m)
    if (!planeWhole[m]) r.fail("cellPlanes.atom[" + std::to_string(m) + "] belongs to no mss patch (the file is damaged)");
  const mss::WeightedPoints w{f.atomCenter, f.atomWeight, p.params.shrinkFactor};
  std::atomic<std::size_t> firstBad{n};
  tbb::parallel_for(tbb::blocked_range<std::size_t>(0, n, 512), [&](const tbb::blocked_range<std::size_t>& range) {
    for (std::size_t k = range.begin(); k < range.end(); ++k)
      if (!derivePatch(p, w, patchWhole, planeWhole, k).empty()) {
        std::size_t seen = firstBad.load();
        while (k < seen && !firstBad.compare_exchange_weak(seen, k)) {}
        return;
      }
  });
  if (firstBad.load() < n) r.fail(derivePatch(p, w, patchWhole, planeWhole, firstBad.load()) + " (the file is damaged)");
  p.skinAtoms.center = f.atomCenter;
  p.skinAtoms.weight = f.atomWeight;
}

}  // namespace

PatchList parsePatchList(std::span<const unsigned char> bytes, const std::string& path) {
  if (bytes.size() < sizeof kMagic || std::memcmp(bytes.data(), kMagic, sizeof kMagic) != 0)
    throw std::runtime_error(path + ": not a SurfTrace patch list (bad magic; expected a file written by "
                                    "`surftrace build`)");
  if (bytes.size() < kHeaderSize)
    throw std::runtime_error(path + ": truncated patch list (" + std::to_string(bytes.size()) +
                             " bytes, shorter than its header)");
  std::uint32_t tag;
  std::memcpy(&tag, bytes.data() + 12, 4);
  bool swap = false;
  if (tag != kEndianTag) {
    if (tag != swapBytes(kEndianTag)) throw std::runtime_error(path + ": corrupt patch list (bad endianness tag)");
    swap = true;
  }
  Reader header(path, bytes.data(), kHeaderSize, swap);
  header.pod<std::array<char, 8>>("magic");
  const auto version = header.pod<std::uint32_t>("version");
  header.pod<std::uint32_t>("endianness");
  const auto bodySize = header.pod<std::uint64_t>("body size");
  if (version > kPatchFileVersion)
    throw std::runtime_error(path + ": patch list version " + std::to_string(version) +
                             " is newer than this SurfTrace reads (up to " + std::to_string(kPatchFileVersion) +
                             "); rebuild it with `surftrace build` or upgrade SurfTrace");
  if (version == 0) throw std::runtime_error(path + ": corrupt patch list (version 0)");
  if (version < 2)
    throw std::runtime_error(path + ": patch list version " + std::to_string(version) +
                             " was written by an older SurfTrace (this one reads versions 2 to " +
                             std::to_string(kPatchFileVersion) + "); rebuild it with `surftrace build`");
  const std::size_t available = bytes.size() - kHeaderSize;
  if (bodySize > available || available - bodySize < 4)
    throw std::runtime_error(path + ": truncated patch list: header announces " + std::to_string(bodySize) +
                             " bytes of patches plus a 4-byte checksum, the file holds " + std::to_string(available));
  if (available - bodySize > 4)
    throw std::runtime_error(path + ": corrupt patch list: " + std::to_string(available - bodySize - 4) +
                             " unexpected bytes after the checksum");
  const unsigned char* body = bytes.data() + kHeaderSize;
  std::uint32_t storedCrc;
  std::memcpy(&storedCrc, body + bodySize, 4);
  if (swap) storedCrc = swapBytes(storedCrc);
  if (crc32Of(body, bodySize) != storedCrc)
    throw std::runtime_error(path + ": corrupt patch list: checksum mismatch (the file was modified or damaged)");

  Reader r(path, body, bodySize, swap);
  PatchList p;
  const auto surface = r.pod<std::uint32_t>("surface kind");
  if (surface > static_cast<std::uint32_t>(SurfaceKind::Sas)) r.fail("unknown surface kind " + std::to_string(surface));
  p.params.surface = static_cast<SurfaceKind>(surface);
  p.params.probeRadius = r.pod<double>("probe radius");
  p.params.shrinkFactor = r.pod<double>("shrink factor");
  p.params.radiiSet = r.string("radii set");
  p.params.inputCrc32 = r.pod<std::uint32_t>("input checksum");
  p.params.atomCount = r.pod<std::uint32_t>("atom count");
  // Before anything is sized by it (here or by a caller): see kMaxAtomsPerByte.
  if (p.params.atomCount > kMaxAtomsPerByte * bodySize)
    r.fail("atom count = " + std::to_string(p.params.atomCount) + " is more than the file can speak of: its " +
           std::to_string(bodySize) + " bytes of patches stand for at most " +
           std::to_string(kMaxAtomsPerByte * bodySize) + " atoms (" + std::to_string(kMaxAtomsPerByte) +
           " a byte; a real structure's list holds hundreds of bytes an atom), so the file is damaged or "
           "was not written by surftrace");
  p.componentCount = r.pod<std::uint32_t>("component count");
  const auto arrays = r.pod<std::uint32_t>("array count");
  SkinFile skin;
  auto table = [&](auto&& visit) {
    if (version == 3) version3Arrays(visit, p, skin);
    else version2Arrays(visit, p);
  };
  std::uint32_t expected = 0;
  table([&](const std::string&, auto&) { ++expected; });
  if (arrays != expected)
    r.fail("holds " + std::to_string(arrays) + " arrays, version " + std::to_string(version) + " has " +
           std::to_string(expected));
  table([&](const std::string& name, auto& v) { readArray(r, name, v); });
  if (!r.atEnd()) r.fail("unexpected bytes after the last array");
  if (version == 2) {
    p.cellPlaneAtom.assign(p.cellPlanes.size(), ~0u);  // not stored: unknown
  } else {
    // The derived skin must be that of a sane list: its parameters first.
    try {
      checkParams(p);
    } catch (const std::runtime_error& e) {
      r.fail(std::string(e.what()) + " (the file is damaged, or was not written by surftrace)");
    }
    expandSkin(r, p, skin);
  }
  try {
    checkList(p);
  } catch (const std::runtime_error& e) {
    r.fail(std::string(e.what()) + " (the file is damaged, or was not written by surftrace)");
  }
  return p;
}

}  // namespace surftrace::build

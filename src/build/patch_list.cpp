// The patch list's invariants and its versioned binary file (.stp).
#include "build/patch_list.hpp"

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <fstream>
#include <limits>
#include <numbers>
#include <stdexcept>
#include <type_traits>

#include <zlib.h>

#include "build/io/output_file.hpp"
#include "build/ses/contour_buildup.hpp"
#include "build/ses/surface_area.hpp"

namespace surftrace::build {

const char* surfaceKindName(SurfaceKind kind) {
  switch (kind) {
    case SurfaceKind::Ses: return "ses";
    case SurfaceKind::Mss: return "mss";
    case SurfaceKind::Vdw: return "vdw";
    case SurfaceKind::Sas: return "sas";
  }
  return "unknown";
}

namespace {

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

class Writer {
 public:
  template <class T> void pod(const T& v) {
    static_assert(std::is_trivially_copyable_v<T>);
    const auto* b = reinterpret_cast<const unsigned char*>(&v);
    bytes.insert(bytes.end(), b, b + sizeof(T));
  }
  void string(const std::string& s) {
    pod(static_cast<std::uint32_t>(s.size()));
    bytes.insert(bytes.end(), s.begin(), s.end());
  }
  template <class T> void array(const std::vector<T>& v) {
    const auto* b = reinterpret_cast<const unsigned char*>(v.data());
    bytes.insert(bytes.end(), b, b + v.size() * sizeof(T));
  }
  std::vector<unsigned char> bytes;
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

bool finite(double v) { return std::isfinite(v); }
bool finite(const glm::dvec3& v) { return std::isfinite(v.x) && std::isfinite(v.y) && std::isfinite(v.z); }
bool finite(const glm::dvec4& v) { return finite(glm::dvec3(v)) && std::isfinite(v.w); }

// What a list written by surftrace stays within; past these a value is damage, not geometry.
// Lengths and coordinates: the largest structures span ~1e4 Å and the SES builder takes probes up
// to 2^19 times the smallest radius (~1e6 Å); 1e9 Å is far beyond both, and keeps squares and
// cubes (areas, volumes, quadric coefficients) finite in double and in the renderers' floats.
constexpr double kMaxLength = 1e9;
// Unit vectors are normalised in double (error ~1e-16); 1e-6 tells them from damage alone.
constexpr double kUnitTolerance = 1e-6;
// Angles come from atan2 and differences of its results: a few ulps past their range.
constexpr double kAngleSlack = 1e-12;
// Areas are sums of exact terms; their rounding is far below this share of the bound.
constexpr double kAreaSlack = 1e-6;

// The shortest of 15 to 17 digits that reads back as the same double: "1.4", not "1.3999999999999999".
std::string text(double v) {
  char buf[32];
  for (int digits = 15; digits <= 17; ++digits) {
    std::snprintf(buf, sizeof buf, "%.*g", digits, v);
    if (std::strtod(buf, nullptr) == v) break;
  }
  return buf;
}
std::string text(std::uint32_t v) { return std::to_string(v); }
std::string text(const glm::dvec3& v) { return "(" + text(v.x) + ", " + text(v.y) + ", " + text(v.z) + ")"; }
std::string text(const glm::dvec4& v) {
  return "(" + text(v.x) + ", " + text(v.y) + ", " + text(v.z) + ", " + text(v.w) + ")";
}
std::string text(const glm::uvec4& v) {
  return "(" + text(v.x) + ", " + text(v.y) + ", " + text(v.z) + ", " + text(v.w) + ")";
}

// Throws "group.name[k] = value <what>": the messages of every field check below.
template <class T>
[[noreturn]] void badField(const char* group, const char* name, std::size_t k, const T& value, const std::string& what) {
  throw std::runtime_error(std::string(group) + "." + name + "[" + std::to_string(k) + "] = " + text(value) + " " + what);
}

bool inCube(const glm::dvec3& v) {
  return std::abs(v.x) <= kMaxLength && std::abs(v.y) <= kMaxLength && std::abs(v.z) <= kMaxLength;
}
void checkPoints(const std::vector<glm::dvec3>& points, const char* group, const char* name) {
  for (std::size_t k = 0; k < points.size(); ++k)
    if (!inCube(points[k]))
      badField(group, name, k, points[k], "lies outside the cube |x|, |y|, |z| <= " + text(kMaxLength) + " Å");
}

void checkUnit(const std::vector<glm::dvec3>& v, const char* group, const char* name) {
  for (std::size_t k = 0; k < v.size(); ++k) {
    const double length = std::sqrt(v[k].x * v[k].x + v[k].y * v[k].y + v[k].z * v[k].z);
    if (!(std::abs(length - 1.0) <= kUnitTolerance))
      badField(group, name, k, v[k], "is not a unit vector (length " + text(length) + ")");
  }
}

// Lengths in [lo, kMaxLength], lo excluded when `positive`.
void checkLengths(const std::vector<double>& v, bool positive, const char* group, const char* name) {
  for (std::size_t k = 0; k < v.size(); ++k)
    if (!(positive ? v[k] > 0.0 : v[k] >= 0.0) || v[k] > kMaxLength)
      badField(group, name, k, v[k], std::string("is not in ") + (positive ? "(0, " : "[0, ") + text(kMaxLength) + "] Å");
}

void checkAngles(const std::vector<double>& v, double lo, double hi, bool openLow, const char* group, const char* name) {
  for (std::size_t k = 0; k < v.size(); ++k)
    if (!(openLow ? v[k] > lo : v[k] >= lo - kAngleSlack) || !(v[k] <= hi + kAngleSlack))
      badField(group, name, k, v[k],
               std::string("is not in ") + (openLow ? "(" : "[") + text(lo) + ", " + text(hi) + "] radians");
}

void checkPlanes(const std::vector<Plane>& planes, const char* group) {
  for (std::size_t k = 0; k < planes.size(); ++k) {
    const glm::dvec3 n(planes[k]);
    const double length = std::sqrt(n.x * n.x + n.y * n.y + n.z * n.z);
    if (!(std::abs(length - 1.0) <= kUnitTolerance))
      badField(group, "plane", k, planes[k], "does not have a unit normal (length " + text(length) + ")");
    // The plane meets the cube of valid points: |d| = |n·x| <= sqrt(3) kMaxLength.
    if (!(std::abs(planes[k].w) <= 2.0 * kMaxLength))
      badField(group, "plane", k, planes[k], "passes further than " + text(2.0 * kMaxLength) + " Å from the origin");
  }
}

void checkRange(const std::vector<std::uint32_t>& begin, const std::vector<std::uint32_t>& count, std::size_t limit,
                const char* group, const char* beginName, const char* countName, const char* planes) {
  for (std::size_t k = 0; k < begin.size(); ++k)
    if (std::uint64_t{begin[k]} + count[k] > limit)
      badField(group, countName, k, count[k],
               std::string("with ") + beginName + " " + text(begin[k]) + " runs past " + planes + " (" +
                   std::to_string(limit) + " planes)");
}

void checkAtoms(const std::vector<std::uint32_t>& atoms, std::uint32_t atomCount, const char* group, const char* name) {
  for (std::size_t k = 0; k < atoms.size(); ++k)
    if (atoms[k] >= atomCount)
      badField(group, name, k, atoms[k], "is not an atom: the list was built from " + std::to_string(atomCount));
}

void checkComponents(const std::vector<std::uint32_t>& component, std::uint32_t count, const char* group) {
  for (std::size_t k = 0; k < component.size(); ++k)
    if (component[k] >= count)
      badField(group, "component", k, component[k], "is not a component: the list has " + std::to_string(count));
}

void checkParams(const PatchList& p) {
  const SurfaceParams& q = p.params;
  const auto surface = static_cast<std::uint32_t>(q.surface);
  if (surface > static_cast<std::uint32_t>(SurfaceKind::Sas))
    throw std::runtime_error("params.surface = " + std::to_string(surface) + " is not a surface kind (0 to 3)");
  // Same limits as the options they come from (--probe > 0, --shrink in (0, 1]); the MSS
  // builder takes s < 1 (s = 1 is built as the vdW spheres), and a list with no probe stores 0
  // (vdW) or the default (MSS).
  const bool probed = q.surface == SurfaceKind::Ses || q.surface == SurfaceKind::Sas;
  if (!(probed ? q.probeRadius > 0.0 : q.probeRadius >= 0.0) || !(q.probeRadius <= kMaxLength))
    throw std::runtime_error("params.probeRadius = " + text(q.probeRadius) + " is not in " + (probed ? "(0, " : "[0, ") +
                             text(kMaxLength) + "] Å");
  const bool skin = q.surface == SurfaceKind::Mss;
  if (!(q.shrinkFactor > 0.0) || !(skin ? q.shrinkFactor < 1.0 : q.shrinkFactor <= 1.0))
    throw std::runtime_error("params.shrinkFactor = " + text(q.shrinkFactor) + " is not in (0, 1" + (skin ? ")" : "]"));
  // Each kind of surface holds its own kinds of patch only.
  const char* kind = surfaceKindName(q.surface);
  auto none = [&](std::size_t size, const char* group) {
    if (size != 0)
      throw std::runtime_error(std::string(group) + " has " + std::to_string(size) + " entries, but a " + kind +
                               " list holds none");
  };
  if (skin) none(p.convex.size(), "convex");
  if (q.surface != SurfaceKind::Ses) {
    none(p.tori.size(), "tori");
    none(p.concave.size(), "concave");
    none(p.clipPlanes.size(), "clipPlanes");
  }
  if (!skin) {
    none(p.mss.size(), "mss");
    none(p.cellPlanes.size(), "cellPlanes");
  }
  // Every component holds a patch (componentCount sizes the per-component sums of `area`).
  const std::size_t sesPatches = p.convex.size() + p.tori.size() + p.concave.size();
  if (p.componentCount > sesPatches)
    throw std::runtime_error("componentCount = " + std::to_string(p.componentCount) + " exceeds the " +
                             std::to_string(sesPatches) + " patches that could carry a component");
}

void checkConvex(const PatchList& p) {
  const ConvexSpheres& c = p.convex;
  checkPoints(c.center, "convex", "center");
  checkLengths(c.radius, true, "convex", "radius");
  // The SES builder's own limit (checkProbeRadius): rp <= 2^19 r for every atom. Past it the
  // SAS share of a patch, area·((r + rp)/r)², overflows (0·∞ for a tiny sphere).
  if (p.params.surface == SurfaceKind::Ses)
    for (std::size_t k = 0; k < c.size(); ++k)
      if (!(p.params.probeRadius <= kMaxProbeToRadius * c.radius[k]))
        badField("convex", "radius", k, c.radius[k],
                 "is below the probe radius " + text(p.params.probeRadius) + " Å / 2^19, the builder's limit");
  checkAtoms(c.atom, p.params.atomCount, "convex", "atom");
  checkComponents(c.component, p.componentCount, "convex");
  for (std::size_t k = 0; k < c.size(); ++k) {
    // The exposed part of the sphere: at most all of it, 4πr²; ∫u dΩ over a part of the unit
    // sphere is at most π long (a hemisphere's).
    const double sphere = 4.0 * std::numbers::pi * c.radius[k] * c.radius[k];
    if (!(c.area[k] >= 0.0) || !(c.area[k] <= sphere * (1.0 + kAreaSlack)))
      badField("convex", "area", k, c.area[k], "is not in [0, 4πr²] = [0, " + text(sphere) + "] Å²");
    const glm::dvec3& w = c.vectorArea[k];
    if (!(std::sqrt(w.x * w.x + w.y * w.y + w.z * w.z) <= std::numbers::pi * (1.0 + kAreaSlack)))
      badField("convex", "vectorArea", k, w, "is longer than π, the most of a part of the unit sphere");
  }
}

void checkTori(const PatchList& p) {
  const Tori& t = p.tori;
  constexpr double kHalfPi = 0.5 * std::numbers::pi;
  checkPoints(t.center, "tori", "center");
  checkUnit(t.axis, "tori", "axis");
  checkUnit(t.e1, "tori", "e1");
  for (std::size_t k = 0; k < t.size(); ++k) {
    const double along = t.axis[k].x * t.e1[k].x + t.axis[k].y * t.e1[k].y + t.axis[k].z * t.e1[k].z;
    if (!(std::abs(along) <= kUnitTolerance))
      badField("tori", "e1", k, t.e1[k], "is not perpendicular to the axis (dot product " + text(along) + ")");
  }
  checkLengths(t.bigRadius, false, "tori", "bigRadius");
  // θ = atan2(·, R) with R >= 0, and θi <= θj (atom j lies along the axis from atom i).
  checkAngles(t.thetaI, -kHalfPi, kHalfPi, false, "tori", "thetaI");
  checkAngles(t.thetaJ, -kHalfPi, kHalfPi, false, "tori", "thetaJ");
  for (std::size_t k = 0; k < t.size(); ++k)
    if (!(t.thetaI[k] <= t.thetaJ[k]))
      badField("tori", "thetaJ", k, t.thetaJ[k], "is below thetaI = " + text(t.thetaI[k]));
  checkAngles(t.phiExtent, 0.0, 2.0 * std::numbers::pi, true, "tori", "phiExtent");
  checkAtoms(t.atomI, p.params.atomCount, "tori", "atomI");
  checkAtoms(t.atomJ, p.params.atomCount, "tori", "atomJ");
  for (std::size_t k = 0; k < t.size(); ++k)
    if (!(t.atomI[k] < t.atomJ[k]))
      badField("tori", "atomJ", k, t.atomJ[k], "is not above atomI = " + text(t.atomI[k]));
  checkComponents(t.component, p.componentCount, "tori");
}

void checkConcave(const PatchList& p) {
  const ConcaveTriangles& c = p.concave;
  checkPoints(c.probe, "concave", "probe");
  checkUnit(c.dirI, "concave", "dirI");
  checkUnit(c.dirJ, "concave", "dirJ");
  checkUnit(c.dirK, "concave", "dirK");
  checkAtoms(c.atomI, p.params.atomCount, "concave", "atomI");
  checkAtoms(c.atomJ, p.params.atomCount, "concave", "atomJ");
  checkAtoms(c.atomK, p.params.atomCount, "concave", "atomK");
  for (std::size_t k = 0; k < c.size(); ++k)
    if (c.atomI[k] == c.atomJ[k] || c.atomJ[k] == c.atomK[k] || c.atomI[k] == c.atomK[k])
      badField("concave", "atomK", k, c.atomK[k],
               "repeats an atom of the triangle (atomI " + text(c.atomI[k]) + ", atomJ " + text(c.atomJ[k]) + ")");
  checkRange(c.clipBegin, c.clipCount, p.clipPlanes.size(), "concave", "clipBegin", "clipCount", "clipPlanes");
  checkComponents(c.component, p.componentCount, "concave");
  checkPlanes(p.clipPlanes, "clipPlanes");
}

void checkMss(const PatchList& p) {
  const MssQuadrics& q = p.mss;
  const double s = p.params.shrinkFactor;
  checkPoints(q.center, "mss", "center");
  checkUnit(q.axis, "mss", "axis");
  checkLengths(q.boundRadius, false, "mss", "boundRadius");
  checkRange(q.cellBegin, q.cellCount, p.cellPlanes.size(), "mss", "cellBegin", "cellCount", "cellPlanes");
  checkPlanes(p.cellPlanes, "cellPlanes");
  for (std::size_t k = 0; k < q.size(); ++k) {
    if (q.kind[k] > static_cast<std::uint32_t>(MssKind::Concave))
      badField("mss", "kind", k, q.kind[k], "is not an MSS kind (0 to 3)");
    if (k > 0 && q.kind[k] < q.kind[k - 1])
      badField("mss", "kind", k, q.kind[k], "follows kind " + text(q.kind[k - 1]) + ": the patches are not grouped by kind");
  }
  for (std::size_t k = 0; k < q.size(); ++k) {
    // The quadric's coefficients are fixed by its kind and s (patch_list.hpp's table).
    static constexpr double kAxial[4] = {0.0, -1.0, 1.0, 0.0};
    const double radial = q.kind[k] <= static_cast<std::uint32_t>(MssKind::Edge) ? 1.0 - s : -s;
    if (!(std::abs(q.radialCoeff[k] - radial) <= 1e-9))
      badField("mss", "radialCoeff", k, q.radialCoeff[k],
               "is not " + text(radial) + ", the coefficient of kind " + text(q.kind[k]) + " at s = " + text(s));
    if (!(std::abs(q.axialCoeff[k] - kAxial[q.kind[k]]) <= 1e-9))
      badField("mss", "axialCoeff", k, q.axialCoeff[k],
               "is not " + text(kAxial[q.kind[k]]) + ", the coefficient of kind " + text(q.kind[k]));
    if (!(std::abs(q.constant[k]) <= kMaxLength * kMaxLength))
      badField("mss", "constant", k, q.constant[k],
               "is not in [-" + text(kMaxLength * kMaxLength) + ", " + text(kMaxLength * kMaxLength) + "] Å²");
    // The simplex: kind + 1 ascending atoms, the unused slots ~0u.
    const glm::uvec4& a = q.atoms[k];
    for (std::uint32_t m = 0; m < 4; ++m) {
      const bool used = m <= q.kind[k];
      if (used ? a[m] >= p.params.atomCount || (m > 0 && a[m] <= a[m - 1]) : a[m] != ~0u)
        badField("mss", "atoms", k, a,
                 "is not a simplex of kind " + text(q.kind[k]) + ": " + text(q.kind[k] + 1) +
                     " ascending atoms below " + std::to_string(p.params.atomCount) + ", then 4294967295 (slot " +
                     std::to_string(m) + ")");
    }
  }
}

// Every field against what the builders write; throws std::runtime_error naming the first
// field outside it ("tori.axis[17] = (0, 0, 0) is not a unit vector (length 0)").
void checkList(const PatchList& p) {
  // All arrays of one kind share a length, and every float is finite.
  std::string group;
  std::size_t length = 0;
  forEachArray([&](const char* g, const char* name, const auto& v) {
    if (group != g) {
      group = g;
      length = v.size();
    } else if (v.size() != length) {
      throw std::runtime_error(std::string(g) + "." + name + " has " + std::to_string(v.size()) +
                               " entries, expected " + std::to_string(length));
    }
    using T = typename std::decay_t<decltype(v)>::value_type;
    if constexpr (ElementInfo<T>::kScalar == Scalar::F64) {
      for (std::size_t k = 0; k < v.size(); ++k)
        if (!finite(v[k])) badField(g, name, k, v[k], "is not finite");
    }
  }, p);
  checkParams(p);
  checkConvex(p);
  checkTori(p);
  checkConcave(p);
  checkMss(p);
  // Components are numbered as the builder meets them, so each number up to componentCount
  // labels some patch (0, the outer surface, always: `--drop-cavities` keeps it).
  std::vector<bool> labelled(p.componentCount, false);
  for (const auto* component : {&p.convex.component, &p.tori.component, &p.concave.component})
    for (const std::uint32_t c : *component) labelled[c] = true;
  const auto unused = std::find(labelled.begin(), labelled.end(), false);
  if (unused != labelled.end())
    throw std::runtime_error("componentCount = " + std::to_string(p.componentCount) + ", but no patch is of component " +
                             std::to_string(unused - labelled.begin()));
}

}  // namespace

void PatchList::clearKeepingMemory() {
  params = SurfaceParams{};
  componentCount = 0;
  forEachArray([](const char*, const char*, auto& v) { v.clear(); }, *this);
}

void PatchList::validate() const {
  try {
    checkList(*this);
  } catch (const std::runtime_error& e) {
    throw std::runtime_error(std::string("patch list: ") + e.what());
  }
}

std::pair<std::size_t, std::size_t> mssKindRange(const MssQuadrics& mss, MssKind kind) {
  const auto k = static_cast<std::uint32_t>(kind);
  const auto range = std::equal_range(mss.kind.begin(), mss.kind.end(), k);
  return {static_cast<std::size_t>(range.first - mss.kind.begin()), static_cast<std::size_t>(range.second - mss.kind.begin())};
}

MssExtent mssExtent(const PatchList& list, std::size_t k) {
  const MssQuadrics& q = list.mss;
  const double R = q.boundRadius[k], B = q.radialCoeff[k], A = q.radialCoeff[k] + q.axialCoeff[k];
  double hLo = -R, hHi = R;
  // Caps: planes whose normal is along the axis; the radial part of the normal widened by R.
  for (std::uint32_t m = 0; m < q.cellCount[k]; ++m) {
    const Plane& plane = list.cellPlanes[q.cellBegin[k] + m];
    const glm::dvec3 n(plane);
    const double along = n.x * q.axis[k].x + n.y * q.axis[k].y + n.z * q.axis[k].z;
    if (std::abs(along) < 0.5) continue;
    const glm::dvec3 radial = n - along * q.axis[k];
    const double offset = -(n.x * q.center[k].x + n.y * q.center[k].y + n.z * q.center[k].z + plane.w);
    const double limit = (offset + std::sqrt(radial.x * radial.x + radial.y * radial.y + radial.z * radial.z) * R) / along;
    if (along > 0) hHi = std::min(hHi, limit);
    else hLo = std::max(hLo, limit);
  }
  // On the surface B ρ² + A h² + constant = 0: ρ² is largest at an end of the range or at 0.
  double rho2 = 0.0;
  for (double h : {hLo, hHi, std::clamp(0.0, hLo, hHi)}) rho2 = std::max(rho2, (-A * h * h - q.constant[k]) / B);
  return {hLo, hHi, std::sqrt(std::min(rho2, R * R))};
}

void writePatchList(const std::string& path, const PatchList& patches) {
  patches.validate();
  Writer body;
  body.pod(static_cast<std::uint32_t>(patches.params.surface));
  body.pod(patches.params.probeRadius);
  body.pod(patches.params.shrinkFactor);
  body.string(patches.params.radiiSet);
  body.pod(patches.params.inputCrc32);
  body.pod(patches.params.atomCount);
  body.pod(patches.componentCount);
  std::uint32_t arrays = 0;
  forEachArray([&](const char*, const char*, const auto&) { ++arrays; }, patches);
  body.pod(arrays);
  forEachArray([&](const char* group, const char* name, const auto& v) {
    using Info = ElementInfo<typename std::decay_t<decltype(v)>::value_type>;
    body.string(std::string(group) + "." + name);
    body.pod(static_cast<std::uint32_t>(Info::kScalar));
    body.pod(Info::kComponents);
    body.pod(static_cast<std::uint64_t>(v.size()));
    body.array(v);
  }, patches);

  Writer file;
  file.bytes.insert(file.bytes.end(), kMagic, kMagic + sizeof kMagic);
  file.pod(kPatchFileVersion);
  file.pod(kEndianTag);
  file.pod(static_cast<std::uint64_t>(body.bytes.size()));
  file.bytes.insert(file.bytes.end(), body.bytes.begin(), body.bytes.end());
  file.pod(crc32Of(body.bytes.data(), body.bytes.size()));

  // Beside the target, checked, then renamed: a full disk or a crash never leaves a
  // half-written file.
  writeFileAtomically(path, std::as_bytes(std::span<const unsigned char>(file.bytes)));
}

bool isPatchListFile(const std::string& path) {
  std::ifstream in(path, std::ios::binary);
  char head[sizeof kMagic] = {};
  return in.read(head, sizeof head) && std::memcmp(head, kMagic, sizeof kMagic) == 0;
}

PatchList readPatchList(const std::string& path) {
  std::ifstream in(path, std::ios::binary);
  if (!in) throw std::runtime_error(path + ": cannot open patch list");
  const std::vector<unsigned char> bytes((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
  return parsePatchList(bytes, path);
}

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
  if (version < kPatchFileVersion)
    throw std::runtime_error(path + ": patch list version " + std::to_string(version) +
                             " was written by an older SurfTrace; rebuild it with `surftrace build`");
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
  p.componentCount = r.pod<std::uint32_t>("component count");
  const auto arrays = r.pod<std::uint32_t>("array count");
  std::uint32_t expected = 0;
  forEachArray([&](const char*, const char*, auto&) { ++expected; }, p);
  if (arrays != expected)
    r.fail("holds " + std::to_string(arrays) + " arrays, version " + std::to_string(version) + " has " +
           std::to_string(expected));
  forEachArray([&](const char* group, const char* name, auto& v) {
    using Info = ElementInfo<typename std::decay_t<decltype(v)>::value_type>;
    const std::string want = std::string(group) + "." + name;
    const std::string got = r.string("array name");
    if (got != want) r.fail("expected array " + want + ", found " + got);
    const auto scalar = r.pod<std::uint32_t>("array type");
    const auto components = r.pod<std::uint32_t>("array width");
    if (scalar != static_cast<std::uint32_t>(Info::kScalar) || components != Info::kComponents)
      r.fail("array " + want + " has the wrong element type");
    const auto count = r.pod<std::uint64_t>("array length");
    r.array(v, count, want.c_str());
  }, p);
  if (!r.atEnd()) r.fail("unexpected bytes after the last array");
  try {
    checkList(p);
  } catch (const std::runtime_error& e) {
    r.fail(std::string(e.what()) + " (the file is damaged, or was not written by surftrace)");
  }
  return p;
}

PatchList atomSpheres(std::span<const glm::dvec3> centers, std::span<const double> radii, double inflate,
                      SurfaceKind kind) {
  PatchList p;
  p.params.surface = kind;
  p.params.probeRadius = inflate;
  p.params.atomCount = static_cast<std::uint32_t>(centers.size());
  ConvexSpheres& c = p.convex;
  c.center.assign(centers.begin(), centers.end());
  c.radius.resize(radii.size());
  for (std::size_t i = 0; i < radii.size(); ++i) c.radius[i] = radii[i] + inflate;
  c.atom.resize(centers.size());
  for (std::size_t i = 0; i < centers.size(); ++i) c.atom[i] = static_cast<std::uint32_t>(i);
  c.component.assign(centers.size(), 0u);
  c.area.assign(centers.size(), 0.0);
  c.vectorArea.assign(centers.size(), glm::dvec3(0.0));
  p.componentCount = centers.empty() ? 0u : 1u;
  return p;
}

PatchList outerComponent(const PatchList& in) {
  // New label of each component: outer ones in order, ~0u for cavities.
  const SurfaceAreas areas = computeAreas(in);
  std::vector<std::uint32_t> relabel(std::max<std::size_t>(in.componentCount, areas.components.size()), ~0u);
  std::uint32_t outer = 0;
  for (std::size_t c = 0; c < relabel.size(); ++c)
    if (c == 0 || (c < areas.components.size() && areas.components[c].outer())) relabel[c] = outer++;
  auto keepOuter = [&](const std::vector<std::uint32_t>& component) {
    std::vector<bool> keep(component.size());
    for (std::size_t k = 0; k < component.size(); ++k) keep[k] = component[k] < relabel.size() && relabel[component[k]] != ~0u;
    return keep;
  };
  std::vector<bool> keepConvex = keepOuter(in.convex.component);
  const std::vector<bool> keepTori = keepOuter(in.tori.component), keepConcave = keepOuter(in.concave.component);
  // A convex patch carries its atom's lowest label; it stays, with the outer label, when a
  // torus of its atom is on an outer surface.
  std::vector<std::uint32_t> atomOuter(in.params.atomCount, ~0u);
  for (std::size_t t = 0; t < in.tori.size(); ++t)
    if (keepTori[t])
      for (const std::uint32_t x : {in.tori.atomI[t], in.tori.atomJ[t]})
        if (x < atomOuter.size()) atomOuter[x] = std::min(atomOuter[x], relabel[in.tori.component[t]]);
  PatchList out = in;
  for (std::size_t k = 0; k < in.convex.size(); ++k) {
    const std::uint32_t x = in.convex.atom[k];
    if (keepConvex[k]) out.convex.component[k] = relabel[in.convex.component[k]];
    else if (x < atomOuter.size() && atomOuter[x] != ~0u) keepConvex[k] = true, out.convex.component[k] = atomOuter[x];
  }
  // A kept convex patch that also faces a dropped cavity is drawn whole (its cavity side is
  // hidden from outside), but its area and vector area are the outer side's alone, so that
  // the list's areas are the outer surfaces' (computeAreas splits them the same way).
  const std::vector<std::vector<ConvexPart>> parts = convexPartsOfOtherComponents(in);
  for (std::size_t k = 0; k < in.convex.size(); ++k) {
    if (!keepConvex[k]) continue;
    const bool ownDropped = !(in.convex.component[k] < relabel.size() && relabel[in.convex.component[k]] != ~0u);
    if (ownDropped) {
      // Labelled by a cavity, kept for an outer side: its area is that outer side's.
      double area = 0.0;
      glm::dvec3 vectorArea(0.0);
      for (const ConvexPart& part : parts[k])
        if (part.component < relabel.size() && relabel[part.component] != ~0u) area += part.area, vectorArea += part.vectorArea;
      out.convex.area[k] = area;
      out.convex.vectorArea[k] = vectorArea;
      continue;
    }
    for (const ConvexPart& part : parts[k])
      if (!(part.component < relabel.size() && relabel[part.component] != ~0u)) {
        out.convex.area[k] = std::max(0.0, out.convex.area[k] - part.area);
        out.convex.vectorArea[k] -= part.vectorArea;
      }
  }
  for (std::size_t t = 0; t < in.tori.size(); ++t)
    if (keepTori[t]) out.tori.component[t] = relabel[in.tori.component[t]];
  for (std::size_t k = 0; k < in.concave.size(); ++k)
    if (keepConcave[k]) out.concave.component[k] = relabel[in.concave.component[k]];
  // Kept concave patches' clipping planes, packed in order, with their begin indices moved.
  out.clipPlanes.clear();
  for (std::size_t k = 0; k < in.concave.size(); ++k) {
    if (!keepConcave[k]) continue;
    out.concave.clipBegin[k] = static_cast<std::uint32_t>(out.clipPlanes.size());
    out.clipPlanes.insert(out.clipPlanes.end(), in.clipPlanes.begin() + in.concave.clipBegin[k],
                          in.clipPlanes.begin() + in.concave.clipBegin[k] + in.concave.clipCount[k]);
  }
  // Every array of a kind loses the same entries: the visitor reaches fields added later too.
  forEachArray([&](const char* group, const char*, auto& v) {
    const std::vector<bool>* keep = std::strcmp(group, "convex") == 0    ? &keepConvex
                                    : std::strcmp(group, "tori") == 0    ? &keepTori
                                    : std::strcmp(group, "concave") == 0 ? &keepConcave
                                                                          : nullptr;
    if (!keep) return;
    std::size_t kept = 0;
    for (std::size_t k = 0; k < v.size(); ++k)
      if ((*keep)[k]) v[kept++] = v[k];
    v.resize(kept);
  }, out);
  out.componentCount = in.componentCount > 0 ? outer : 0u;
  return out;
}

}  // namespace surftrace::build

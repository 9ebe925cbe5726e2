// The patch list's invariants (PatchList::validate and the field checks the .stp reader shares),
// its kinds' ranges and the extent of a skin patch.
#include "build/patch_list.hpp"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <numbers>
#include <stdexcept>
#include <string>
#include <type_traits>

#include "build/patch_list_checks.hpp"
#include "build/surface_limits.hpp"

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

namespace list_checks {

bool finite(double v) { return std::isfinite(v); }
bool finite(const glm::dvec3& v) { return std::isfinite(v.x) && std::isfinite(v.y) && std::isfinite(v.z); }
bool finite(const glm::dvec4& v) { return finite(glm::dvec3(v)) && std::isfinite(v.w); }

// What a list written by surftrace stays within (kMaxLength: patch_list_checks.hpp); past these
// a value is damage, not geometry.
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
// (Built by appending: GCC 12 gives a false -Wrestrict for "x" + std::string chains.)
template <class V> std::string textOfVector(const V& v, int n) {
  std::string out("(");
  for (int k = 0; k < n; ++k) out.append(k > 0 ? ", " : "").append(text(v[k]));
  return out.append(")");
}
std::string text(const glm::dvec3& v) { return textOfVector(v, 3); }
std::string text(const glm::dvec4& v) { return textOfVector(v, 4); }
std::string text(const glm::uvec4& v) { return textOfVector(v, 4); }

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
  // Same limits as the options they come from (--probe > 0, --shrink: validShrinkFactor); an
  // MSS list holds s < 1 (s = 1 is built and stored as the vdW spheres, skinBuiltWithCells),
  // and a list with no probe stores 0 (vdW) or the default (MSS).
  const bool probed = q.surface == SurfaceKind::Ses || q.surface == SurfaceKind::Sas;
  if (!(probed ? q.probeRadius > 0.0 : q.probeRadius >= 0.0) || !(q.probeRadius <= kMaxLength))
    throw std::runtime_error("params.probeRadius = " + text(q.probeRadius) + " is not in " + (probed ? "(0, " : "[0, ") +
                             text(kMaxLength) + "] Å");
  const bool skin = q.surface == SurfaceKind::Mss;
  if (!(skin ? skinBuiltWithCells(q.shrinkFactor) : validShrinkFactor(q.shrinkFactor)))
    throw std::runtime_error("params.shrinkFactor = " + text(q.shrinkFactor) + " is not in [" + text(kMinShrinkFactor) +
                             ", 1" + (skin ? "), the skin's (s = 1 is stored as the vdW spheres)" : "]"));
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

// The skin's kinds (grouped, in order) and simplices: kind + 1 ascending atoms below
// atomCount, the unused slots ~0u.
void checkSimplices(const MssQuadrics& q, std::uint32_t atomCount) {
  for (std::size_t k = 0; k < q.size(); ++k) {
    if (q.kind[k] > static_cast<std::uint32_t>(MssKind::Concave))
      badField("mss", "kind", k, q.kind[k], "is not an MSS kind (0 to 3)");
    if (k > 0 && q.kind[k] < q.kind[k - 1])
      badField("mss", "kind", k, q.kind[k], "follows kind " + text(q.kind[k - 1]) + ": the patches are not grouped by kind");
  }
  for (std::size_t k = 0; k < q.size(); ++k) {
    const glm::uvec4& a = q.atoms[k];
    for (std::uint32_t m = 0; m < 4; ++m) {
      const bool used = m <= q.kind[k];
      if (used ? a[m] >= atomCount || (m > 0 && a[m] <= a[m - 1]) : a[m] != ~0u)
        badField("mss", "atoms", k, a,
                 "is not a simplex of kind " + text(q.kind[k]) + ": " + text(q.kind[k] + 1) +
                     " ascending atoms below " + std::to_string(atomCount) + ", then 4294967295 (slot " +
                     std::to_string(m) + ")");
    }
  }
}

void checkMss(const PatchList& p) {
  const MssQuadrics& q = p.mss;
  const double s = p.params.shrinkFactor;
  checkPoints(q.center, "mss", "center");
  checkUnit(q.axis, "mss", "axis");
  checkLengths(q.boundRadius, false, "mss", "boundRadius");
  checkRange(q.cellBegin, q.cellCount, p.cellPlanes.size(), "mss", "cellBegin", "cellCount", "cellPlanes");
  checkPlanes(p.cellPlanes, "cellPlanes");
  for (std::size_t k = 0; k < p.cellPlaneAtom.size(); ++k)
    if (p.cellPlaneAtom[k] >= p.params.atomCount && p.cellPlaneAtom[k] != ~0u)
      badField("cellPlanes", "atom", k, p.cellPlaneAtom[k],
               "is neither an atom (the list was built from " + std::to_string(p.params.atomCount) +
                   ") nor 4294967295 (not known)");
  checkSimplices(q, p.params.atomCount);
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
  }
  // The skin's atoms: all of them or none (patch_list.hpp SkinAtoms).
  const SkinAtoms& a = p.skinAtoms;
  if (!a.center.empty() && a.center.size() != p.params.atomCount)
    throw std::runtime_error("skinAtoms.center has " + std::to_string(a.center.size()) +
                             " entries, expected 0 or one per atom (" + std::to_string(p.params.atomCount) + ")");
  checkPoints(a.center, "skinAtoms", "center");
  for (std::size_t i = 0; i < a.weight.size(); ++i)
    if (!(a.weight[i] >= 0.0 && a.weight[i] <= kMaxLength * kMaxLength))
      badField("skinAtoms", "weight", i, a.weight[i], "is not in [0, " + text(kMaxLength * kMaxLength) + "] Å²");
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
    if constexpr (std::is_same_v<T, double> || std::is_same_v<T, glm::dvec3> || std::is_same_v<T, glm::dvec4>) {
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

}  // namespace list_checks

void PatchList::clearKeepingMemory() {
  params = SurfaceParams{};
  componentCount = 0;
  forEachArray([](const char*, const char*, auto& v) { v.clear(); }, *this);
}

void PatchList::validate() const {
  try {
    list_checks::checkList(*this);
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

}  // namespace surftrace::build

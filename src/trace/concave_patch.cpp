// Ray intersection with SES concave spherical triangles (ORACLES A.4, A.5, B.5), in double.
#include "trace/concave_patch.hpp"

#include <algorithm>
#include <cmath>
#include <limits>

#include <glm/common.hpp>
#include <glm/geometric.hpp>

#include "build/core/vector_math.hpp"
#include "trace/sphere_roots.hpp"

namespace surftrace::trace {
namespace {

// Outward padding of the box, in units of ε times the coordinate's magnitude: the extreme
// directions come from a cross product, a division and a square root (a few ε each), then
// p + rp·u rounds once more. 16 keeps the box conservative (STYLE §3.6).
constexpr double kBoundsPadUlps = 16.0;

// The cone's face normals g_ij = dirI × dirJ, g_jk, g_ki, oriented inwards (ORACLES A.4:
// g_ij·dirK > 0), so u is in the cone iff all three g·u >= 0.
struct ConeFaces {
  glm::dvec3 ij, jk, ki;
};

ConeFaces coneFaces(const ConcavePatch& p) {
  ConeFaces g{glm::cross(p.dirI, p.dirJ), glm::cross(p.dirJ, p.dirK), glm::cross(p.dirK, p.dirI)};
  // g_ij·dirK = g_jk·dirI = g_ki·dirJ = det(dirI, dirJ, dirK): one sign orients all three
  // faces, so a nearly flat triangle cannot get three inconsistently rounded orientations.
  if (glm::dot(g.ij, p.dirK) < 0.0) {
    g.ij = -g.ij;
    g.jk = -g.jk;
    g.ki = -g.ki;
  }
  return g;
}

// The sphere's extreme values of u·e_k over the great-circle arc from a to b (the minor arc:
// the cone is pointed, ORACLES A.4). On the circle with normal m = a × b the extremes are
// ±sqrt(1 − m_k²/|m|²), at ±(e_k − (e_k·m̂)m̂). Such a point lies on the arc iff it is on b's
// side of a and on a's side of b; with the tangents m × a (at a, towards b) and b × m (at b,
// towards a) those two tests reduce to the signs of their k-th components, so the extreme
// point itself is never formed. Inclusive tests: an extra candidate only widens the box.
void extendByArc(const glm::dvec3& a, const glm::dvec3& b, glm::dvec3& lo, glm::dvec3& hi) {
  const glm::dvec3 m = glm::cross(a, b);
  const double mm = glm::dot(m, m);
  if (!(mm > 0.0)) return;  // coincident or antipodal vertices: the vertices bound it
  const glm::dvec3 ta = glm::cross(m, a), tb = glm::cross(b, m);
  for (int k = 0; k < 3; ++k) {
    const double extreme = std::sqrt(std::max(0.0, 1.0 - m[k] * m[k] / mm));
    if (ta[k] >= 0.0 && tb[k] >= 0.0) hi[k] = std::max(hi[k], extreme);
    if (ta[k] <= 0.0 && tb[k] <= 0.0) lo[k] = std::min(lo[k], -extreme);
  }
}

// A root's point on the probe sphere that the cone and the clipping planes keep, with its
// distances to them for the seam flag.
struct KeptPoint {
  glm::dvec3 v;          // relative to the probe
  double sij, sjk, ski;  // g·v for the three cone faces
  double clipMargin;     // least −(n·x + w) over the clipping planes
};

// Whether the root on `side` (0 near, 1 far) lies in the cone (ORACLES A.4) and on the kept side
// of every clipping plane (A.5).
inline bool keptPoint(const ConcavePatch& p, const ConeFaces& g, const SphereRoots& r, const glm::dvec3& d, int side,
                      KeptPoint& k) {
  // The point relative to the probe, in the shifted frame: f ∓ √disc·d (near, far).
  k.v = r.f + (side == 0 ? -r.root : r.root) * d;
  k.sij = glm::dot(g.ij, k.v);
  k.sjk = glm::dot(g.jk, k.v);
  k.ski = glm::dot(g.ki, k.v);
  if (k.sij < 0.0 || k.sjk < 0.0 || k.ski < 0.0) return false;
  const glm::dvec3 x = p.probe + k.v;
  k.clipMargin = std::numeric_limits<double>::infinity();
  for (const build::Plane& c : p.clipPlanes) {
    const double e = glm::dot(glm::dvec3(c), x) + c.w;  // ORACLES A.5: keep e <= 0
    if (e > 0.0) return false;
    k.clipMargin = std::min(k.clipMargin, -e);
  }
  return true;
}

inline PatchHit hitAt(const ConcavePatch& p, const ConeFaces& g, const SphereRoots& r, int side, const KeptPoint& k) {
  const double rp = p.probeRadius;
  PatchHit hit;
  hit.t = side == 0 ? r.tNear : r.tFar;
  hit.normal = glm::normalize(-k.v);  // (p − x)/rp: out of the SES body, into the probe
  if (r.root < kGrazingCosine * rp) hit.flags |= kHitGrazing;  // |n·d| = √disc/rp
  // A seam: within tol of a cone face (distance g·v/|g|, compared squared to skip the
  // square roots) or of a clipping plane, the neighbouring patch may own the pixel.
  const double tol = kBoundaryTolerance * rp, tol2 = tol * tol;
  if (k.sij * k.sij < tol2 * glm::dot(g.ij, g.ij) || k.sjk * k.sjk < tol2 * glm::dot(g.jk, g.jk) ||
      k.ski * k.ski < tol2 * glm::dot(g.ki, g.ki) || k.clipMargin < tol)
    hit.flags |= kHitNearBoundary;
  return hit;
}

}  // namespace

ConcavePatch concavePatch(const build::PatchList& patches, std::size_t index) {
  const build::ConcaveTriangles& cv = patches.concave;
  ConcavePatch p;
  p.probe = cv.probe[index];
  p.probeRadius = patches.params.probeRadius;
  p.dirI = cv.dirI[index];
  p.dirJ = cv.dirJ[index];
  p.dirK = cv.dirK[index];
  p.clipPlanes = std::span<const build::Plane>(patches.clipPlanes.data() + cv.clipBegin[index], cv.clipCount[index]);
  return p;
}

Bounds3d bounds(const ConcavePatch& p) {
  // Box of the unclipped triangle on the unit sphere: the coordinate extremes of a spherical
  // triangle sit at a vertex, at an edge arc's interior extreme, or at a pole ±e_k inside it.
  glm::dvec3 lo = glm::min(glm::min(p.dirI, p.dirJ), p.dirK);
  glm::dvec3 hi = glm::max(glm::max(p.dirI, p.dirJ), p.dirK);
  extendByArc(p.dirI, p.dirJ, lo, hi);
  extendByArc(p.dirJ, p.dirK, lo, hi);
  extendByArc(p.dirK, p.dirI, lo, hi);
  const ConeFaces g = coneFaces(p);
  for (int k = 0; k < 3; ++k) {
    // g·(±e_k) = ±g[k]: the pole is inside iff every face normal has that sign.
    if (g.ij[k] >= 0.0 && g.jk[k] >= 0.0 && g.ki[k] >= 0.0) hi[k] = 1.0;
    if (g.ij[k] <= 0.0 && g.jk[k] <= 0.0 && g.ki[k] <= 0.0) lo[k] = -1.0;
  }
  // A NaN direction would make the box invalid and Embree drop the patch silently
  // (STYLE §3.6); fall back to the whole probe sphere, which is always conservative.
  if (!(std::isfinite(lo.x + lo.y + lo.z) && std::isfinite(hi.x + hi.y + hi.z))) {
    lo = glm::dvec3(-1.0);
    hi = glm::dvec3(1.0);
  }
  const double rp = p.probeRadius;
  const glm::dvec3 pad = kBoundsPadUlps * std::numeric_limits<double>::epsilon() * (glm::abs(p.probe) + rp);
  Bounds3d b;
  b.lower = p.probe + rp * lo - pad;
  b.upper = p.probe + rp * hi + pad;
  return b;
}

bool insidePatch(const ConcavePatch& p, const glm::dvec3& x, double slack) {
  const ConeFaces g = coneFaces(p);
  const glm::dvec3 v = x - p.probe;
  // Distances to the cone faces are g·v/|g|; only a widened test needs the lengths.
  if (slack > 0.0) {
    if (glm::dot(g.ij, v) < -slack * glm::length(g.ij) || glm::dot(g.jk, v) < -slack * glm::length(g.jk) ||
        glm::dot(g.ki, v) < -slack * glm::length(g.ki))
      return false;
  } else if (glm::dot(g.ij, v) < 0.0 || glm::dot(g.jk, v) < 0.0 || glm::dot(g.ki, v) < 0.0) {
    return false;
  }
  // ORACLES A.5: keep n·x + w <= 0, the side of the patch's own probe.
  for (const build::Plane& c : p.clipPlanes)
    if (glm::dot(glm::dvec3(c), x) + c.w > slack) return false;
  return true;
}

int allHits(const ConcavePatch& p, const UnitRay& ray, double tMin, double tMax, PatchHit (&hits)[2]) {
  // intersect()'s roots, clip tests, normals and flags for both roots at once.
  SphereRoots r;
  if (!sphereRoots(p.probe, p.probeRadius, ray, tMin, tMax, r) || (!r.nearInRange && !r.farInRange)) return 0;
  const ConeFaces g = coneFaces(p);
  int count = 0;
  for (int side = 0; side < 2; ++side) {
    if (!(side == 0 ? r.nearInRange : r.farInRange)) continue;
    // After the near hit, intersect() from its t finds the far one only if it lies beyond it.
    if (side == 1 && count == 1 && !(r.tFar > r.tNear)) continue;
    KeptPoint k;
    if (keptPoint(p, g, r, ray.unit, side, k)) hits[count++] = hitAt(p, g, r, side, k);
  }
  return count;
}

std::optional<PatchHit> intersect(const ConcavePatch& p, const UnitRay& ray, double tMin, double tMax) {
  SphereRoots r;
  if (!sphereRoots(p.probe, p.probeRadius, ray, tMin, tMax, r) || (!r.nearInRange && !r.farInRange))
    return std::nullopt;
  // ORACLES A.4: the visible root is usually the far one, but test both in ascending t.
  const ConeFaces g = coneFaces(p);
  for (int side = 0; side < 2; ++side) {
    if (!(side == 0 ? r.nearInRange : r.farInRange)) continue;
    KeptPoint k;
    if (keptPoint(p, g, r, ray.unit, side, k)) return hitAt(p, g, r, side, k);
  }
  return std::nullopt;
}

bool occludes(const ConcavePatch& p, const UnitRay& ray, double tMin, double tMax) {
  // intersect()'s roots and clip tests; no normal or flags.
  SphereRoots r;
  if (!sphereRoots(p.probe, p.probeRadius, ray, tMin, tMax, r) || (!r.nearInRange && !r.farInRange)) return false;
  const ConeFaces g = coneFaces(p);
  for (int side = 0; side < 2; ++side) {
    KeptPoint k;
    if ((side == 0 ? r.nearInRange : r.farInRange) && keptPoint(p, g, r, ray.unit, side, k)) return true;
  }
  return false;
}

double boundaryDistance(const ConcavePatch& p, const glm::dvec3& x) {
  const ConeFaces g = coneFaces(p);
  double d = std::numeric_limits<double>::infinity();
  for (const glm::dvec3& face : {g.ij, g.jk, g.ki}) {
    const double length = glm::length(face);
    if (length > 0.0) d = std::min(d, build::distanceToSphereCircle(p.probe, p.probeRadius, x, face / length, 0.0));
  }
  // A clipping plane n·y + w = 0 cuts the probe sphere where n·(y − p) = −(n·p + w).
  for (const build::Plane& c : p.clipPlanes)
    d = std::min(d, build::distanceToSphereCircle(p.probe, p.probeRadius, x, glm::dvec3(c),
                                                  -(glm::dot(glm::dvec3(c), p.probe) + c.w) / p.probeRadius));
  return d;
}

std::uint32_t atomOf(const ConcavePatch& c, const glm::uvec3& atoms, const glm::dvec3& x) {
  const glm::dvec3 u = x - c.probe;
  const double di = glm::dot(u, c.dirI), dj = glm::dot(u, c.dirJ), dk = glm::dot(u, c.dirK);
  return di >= dj && di >= dk ? atoms.x : (dj >= dk ? atoms.y : atoms.z);
}

}  // namespace surftrace::trace

// Ray–skin-quadric intersection inside a mixed cell (ORACLES B.5, C.3, C.4), in double.
#include "trace/mss_patch.hpp"

#include <algorithm>
#include <cmath>
#include <limits>

#include <glm/common.hpp>
#include <glm/geometric.hpp>

#include "build/core/vector_math.hpp"

namespace surftrace::trace {
namespace {

constexpr double kBoundsPadUlps = 8.0;  // as for the spheres (STYLE §3.6)
// Roots within this distance (relative to the patch's scale) of the cell are accepted: the
// skin is C¹ across cell facets, so the neighbouring patch gives the same point there
// (ORACLES C.4), and no ray slips between two cells.
constexpr double kCellSlack = 1e-9;

}  // namespace

MssPatch mssPatch(const build::PatchList& patches, std::size_t k) {
  const build::MssQuadrics& q = patches.mss;
  MssPatch p;
  p.kind = static_cast<build::MssKind>(q.kind[k]);
  p.center = q.center[k];
  p.axis = q.axis[k];
  p.radial = q.radialCoeff[k];
  p.axial = q.axialCoeff[k];
  p.constant = q.constant[k];
  p.boundRadius = q.boundRadius[k];
  p.extent = build::mssExtent(patches, k);
  p.cellPlanes = {patches.cellPlanes.data() + q.cellBegin[k], q.cellCount[k]};
  return p;
}

SkinAtomBalls skinAtomBalls(const build::PatchList& list) {
  SkinAtomBalls b;
  const build::SkinAtoms& a = list.skinAtoms;
  if (a.size() == 0) return b;
  const double s = list.params.shrinkFactor;
  std::vector<double> radii(a.size());
  b.balls.resize(a.size());
  for (std::size_t i = 0; i < a.size(); ++i) {
    b.balls[i] = glm::dvec4(a.center[i], s * a.weight[i]);
    radii[i] = std::sqrt(b.balls[i].w);
  }
  b.grid.build(a.center, radii, 0.0);
  return b;
}

// Which power distance names the owner. The skin body is the union of the shrunk balls b_λ^s,
// and the shrunk ball of atom i alone is (c_i, s·w_i) = (c_i, r_i²), its vdW ball (ORACLES
// C.1): these are the atomic balls of the skin, so the owner minimises π_i(x) = |x − c_i|² − r_i².
// In the mixed cell μ_X a point is x = (1 − s) y + s v with y in the simplex δ_X and v in the
// power cell ν_X (C.4), and π_i − π_j is affine, so for any atoms i, j
//   π_i(x) − π_j(x) = (1 − s)(|y − c_i|² − |y − c_j|²) + s(π'_i(v) − π'_j(v)),
// π' the power distance to the grown balls (c_i, w_i). For i, j in X the second term is 0 (v
// has equal power to the balls of X): the owner among X is the atom nearest to y, so a convex
// cell (X = {i}) is wholly atom i's and an edge cell splits at its middle slice, the plane
// (1 − s)·(bisector of c_i c_j) + s·ν_X. (The grown balls themselves would split the edge line
// at their own bisector, outside the edge cell, on an atom's own sphere, whenever the
// orthocentre z_X lies outside the edge: common for a hydrogen beside a heavy atom at small s.)
// For j outside X the second term favours X but the first need not: y may lie nearer to an
// atom outside its Delaunay simplex. At s = 0.2 on 1CRN the least π over X is not the least
// over all atoms on 15 % of the pixels (tests/tools/skin_owner_cli_test.cpp), so the search
// goes over every atom: on the skin, outside every vdW ball, π >= 0, and an atom j with
// π_j(x) <= π_i(x) has |x − c_j|² <= π_i(x) + r_j², so |x − c_j| <= r_j + √π_i(x).
std::uint32_t skinOwner(const SkinAtomBalls* b, const glm::uvec4& atoms, const glm::dvec3& x) {
  if (!b || b->balls.empty()) return atoms.x;
  const auto power = [&](std::uint32_t i) {
    const glm::dvec3 d = x - glm::dvec3(b->balls[i]);
    return glm::dot(d, d) - b->balls[i].w;
  };
  std::uint32_t best = atoms.x;
  double least = std::numeric_limits<double>::infinity();
  for (int k = 0; k < 4 && atoms[k] != ~0u; ++k) {
    if (atoms[k] >= b->balls.size()) return atoms.x;  // not this list's atoms
    const double pk = power(atoms[k]);
    if (pk < least) {
      least = pk;
      best = atoms[k];
    }
  }
  thread_local std::vector<std::uint32_t> near;
  near.clear();
  // A hair beyond the bound, for the rounding of π and of the grid's own test.
  const double reach = std::sqrt(std::max(least, 0.0)) * (1.0 + 1e-9) + 1e-9;
  b->grid.atomsNear(x, reach, near);
  for (const std::uint32_t j : near) {
    const double pj = power(j);
    if (pj < least || (pj == least && j < best)) {
      least = pj;
      best = j;
    }
  }
  return best;
}

Bounds3d bounds(const MssPatch& p) {
  const glm::dvec3 pad = kBoundsPadUlps * std::numeric_limits<double>::epsilon() * (glm::abs(p.center) + p.boundRadius);
  // The cylinder's box: its end disks' extents per coordinate, within the ball's box.
  Bounds3d b;
  for (int k = 0; k < 3; ++k) {
    const double a = p.axis[k], across = p.extent.rho * std::sqrt(std::max(0.0, 1.0 - a * a));
    const double lo = std::min(p.extent.hLo * a, p.extent.hHi * a) - across;
    const double hi = std::max(p.extent.hLo * a, p.extent.hHi * a) + across;
    b.lower[k] = p.center[k] + std::max(lo, -p.boundRadius) - pad[k];
    b.upper[k] = p.center[k] + std::min(hi, p.boundRadius) + pad[k];
  }
  return b;
}

Bounds3d cellBounds(const MssPatch& p) {
  Bounds3d b = bounds(p);
  // intersect() accepts points up to kCellSlack·scale beyond the ball and every plane: widen both
  // by twice that, and pad each cap's box like bounds() (its extremes are a few roundings).
  const double slack = 2.0 * kCellSlack * (p.boundRadius + 1.0);
  const double R = p.boundRadius + slack;
  for (const build::Plane& plane : p.cellPlanes) {
    const glm::dvec3 n(plane);
    const double h = glm::dot(n, p.center) + plane.w - slack;  // the centre's distance beyond the plane
    if (!(std::abs(h) < R)) continue;  // the plane misses the ball (or NaN): no cut
    const double circle = std::sqrt((R - h) * (R + h));  // radius of the plane's circle on the ball
    for (int k = 0; k < 3; ++k) {
      // Over the cap {|x − c| <= R, n·(x − c) <= −h}: the ball's pole c ± R e_k when the cap
      // holds it, else the extreme of the plane's circle (centre c − h n).
      const double across = circle * std::sqrt(std::max(0.0, 1.0 - n[k] * n[k]));
      const double hi = n[k] * R <= -h ? R : -h * n[k] + across;
      const double lo = -n[k] * R <= -h ? -R : -h * n[k] - across;
      const double pad = kBoundsPadUlps * std::numeric_limits<double>::epsilon() * (std::abs(p.center[k]) + R) +
                         1e-12 * R;
      b.lower[k] = std::max(b.lower[k], p.center[k] + lo - pad);
      b.upper[k] = std::min(b.upper[k], p.center[k] + hi + pad);
    }
  }
  // A cell whose caps leave no common box holds no skin; keep the plain box (STYLE §3.6: never empty).
  return b.empty() ? bounds(p) : b;
}

bool insideCell(const MssPatch& p, const glm::dvec3& x, double slack) {
  const glm::dvec3 d = x - p.center;
  const double ball = p.boundRadius + slack;
  if (glm::dot(d, d) > ball * ball) return false;
  // Planes relative to the centre: n·x + w = n·d + (n·c + w), the second term small near the cell.
  for (const build::Plane& plane : p.cellPlanes) {
    const glm::dvec3 n(plane);
    if (glm::dot(n, d) + (glm::dot(n, p.center) + plane.w) > slack) return false;
  }
  return true;
}

std::optional<PatchHit> intersect(const MssPatch& p, const UnitRay& ray, double tMin, double tMax) {
  const double len = ray.length;
  const glm::dvec3& d = ray.unit;
  // Shift the origin to the ray's closest approach to the centre: o is then at most the
  // distance of the ray from the centre, and t = t0 + u.
  const glm::dvec3 oc = ray.org - p.center;
  const double t0 = -glm::dot(oc, d);
  const glm::dvec3 o = oc + t0 * d;
  // The ray misses the bounding ball: no skin of this patch on it.
  if (glm::dot(o, o) > p.boundRadius * p.boundRadius * (1.0 + 1e-12)) return std::nullopt;
  const double da = glm::dot(d, p.axis), oa = glm::dot(o, p.axis);
  // f(o + u d) = A u² + 2 B u + C.
  const double A = p.radial + p.axial * da * da;
  const double B = p.radial * glm::dot(o, d) + p.axial * oa * da;
  const double C = p.radial * glm::dot(o, o) + p.axial * oa * oa + p.constant;
  double roots[2];
  int count = 0;
  const double scaleA = std::abs(p.radial) + std::abs(p.axial);
  if (std::abs(A) <= 1e-14 * scaleA) {
    // Along an asymptote of the hyperboloid (or a cone's generator): f is linear in u.
    if (B != 0.0) roots[count++] = -C / (2.0 * B);
  } else {
    const double disc = B * B - A * C;
    if (disc < 0.0) return std::nullopt;
    const double q = -(B + std::copysign(std::sqrt(disc), B));
    if (q == 0.0) {
      roots[count++] = 0.0;  // B = disc = 0: a double root at the closest approach
    } else {
      const double r1 = q / A, r2 = C / q;
      roots[count++] = std::min(r1, r2);
      roots[count++] = std::max(r1, r2);
    }
  }
  const double scale = p.boundRadius + 1.0;
  for (int k = 0; k < count; ++k) {
    const double t = (t0 + roots[k]) / len;
    if (!(t > tMin && t <= tMax)) continue;
    const glm::dvec3 x = o + roots[k] * d;  // relative to the centre
    if (!insideCell(p, p.center + x, kCellSlack * scale)) continue;
    PatchHit hit;
    hit.t = t;
    const glm::dvec3 gradient = p.radial * x + (p.axial * glm::dot(x, p.axis)) * p.axis;
    const double g = glm::length(gradient);
    // At a cone's apex the gradient vanishes: any normal is as good; take the ray's reverse.
    hit.normal = g > 0.0 ? gradient / g : -d;
    if (g == 0.0 || std::abs(glm::dot(hit.normal, d)) < kGrazingCosine) hit.flags |= kHitGrazing;
    for (const build::Plane& plane : p.cellPlanes) {
      const glm::dvec3 n(plane);
      if (std::abs(glm::dot(n, x) + glm::dot(n, p.center) + plane.w) < kBoundaryTolerance * scale) {
        hit.flags |= kHitNearBoundary;
        break;
      }
    }
    return hit;
  }
  return std::nullopt;
}

bool occludes(const MssPatch& p, const UnitRay& ray, double tMin, double tMax) {
  // intersect()'s roots and cell test, by the same expressions; no normal, and no pass over
  // the cell planes for the seam flag.
  const double len = ray.length;
  const glm::dvec3& d = ray.unit;
  const glm::dvec3 oc = ray.org - p.center;
  const double t0 = -glm::dot(oc, d);
  const glm::dvec3 o = oc + t0 * d;
  if (glm::dot(o, o) > p.boundRadius * p.boundRadius * (1.0 + 1e-12)) return false;
  const double da = glm::dot(d, p.axis), oa = glm::dot(o, p.axis);
  const double A = p.radial + p.axial * da * da;
  const double B = p.radial * glm::dot(o, d) + p.axial * oa * da;
  const double C = p.radial * glm::dot(o, o) + p.axial * oa * oa + p.constant;
  double roots[2];
  int count = 0;
  const double scaleA = std::abs(p.radial) + std::abs(p.axial);
  if (std::abs(A) <= 1e-14 * scaleA) {
    if (B != 0.0) roots[count++] = -C / (2.0 * B);
  } else {
    const double disc = B * B - A * C;
    if (disc < 0.0) return false;
    const double q = -(B + std::copysign(std::sqrt(disc), B));
    if (q == 0.0) {
      roots[count++] = 0.0;
    } else {
      const double r1 = q / A, r2 = C / q;
      roots[count++] = std::min(r1, r2);
      roots[count++] = std::max(r1, r2);
    }
  }
  const double scale = p.boundRadius + 1.0;
  for (int k = 0; k < count; ++k) {
    const double t = (t0 + roots[k]) / len;
    if (t > tMin && t <= tMax && insideCell(p, p.center + (o + roots[k] * d), kCellSlack * scale)) return true;
  }
  return false;
}

double boundaryDistance(const MssPatch& p, const glm::dvec3& x) {
  // The spheres: f = radial·|x − c|² + constant, radius √(−constant/radial).
  const double r2 = p.axial == 0.0 && p.radial != 0.0 ? -p.constant / p.radial : 0.0;
  const double r = r2 > 0.0 ? std::sqrt(r2) : 0.0;
  double d = std::numeric_limits<double>::infinity();
  for (const build::Plane& plane : p.cellPlanes) {
    const glm::dvec3 n(plane);
    const double centre = glm::dot(n, p.center) + plane.w;  // the centre's signed distance to the plane
    d = std::min(d, r > 0.0 ? build::distanceToSphereCircle(p.center, r, x, n, -centre / r)
                            : std::abs(glm::dot(n, x - p.center) + centre));
  }
  return d;
}

}  // namespace surftrace::trace

// The SES, SAS and vdW surfaces as exact distance fields, from the nearest point of the SAS
// (ORACLES D.1), and the dispatch to the skin's field.
#include "build/mesh/surface_distance.hpp"

#include <algorithm>
#include <cmath>
#include <limits>
#include <map>
#include <numbers>
#include <stdexcept>
#include <string>
#include <tuple>

#include <glm/geometric.hpp>

#include "build/mesh/ball_union.hpp"
#include "build/mesh/skin_distance.hpp"
#include "build/ses/contour_buildup.hpp"

namespace surftrace::build::mesh {

namespace {

constexpr double kInf = std::numeric_limits<double>::infinity();
constexpr double kUnionReach = 1.5;  // Å
// view::PatchKind's codes, pinned there (build does not depend on view).
constexpr std::uint8_t kConvexCode = 1, kToroidalCode = 2, kConcaveCode = 3;

glm::dvec3 unitOr(const glm::dvec3& v, const glm::dvec3& fallback) {
  const double len = glm::length(v);
  return len > 0.0 ? v / len : fallback;
}

// The points where the line of planes a and b meets the sphere (centre p, radius r).
int planePairOnSphere(const Plane& a, const Plane& b, const glm::dvec3& p, double r, glm::dvec3 (&out)[2]) {
  const glm::dvec3 na(a), nb(b);
  const glm::dvec3 dir = glm::cross(na, nb);
  const double len2 = glm::dot(dir, dir);
  if (len2 < 1e-24) return 0;
  // The point of the line nearest to p: p + α na + β nb with both plane equations met.
  const double fa = glm::dot(na, p) + a.w, fb = glm::dot(nb, p) + b.w;
  const double c = glm::dot(na, nb), det = 1.0 - c * c;
  const double alpha = (-fa + c * fb) / det, beta = (-fb + c * fa) / det;
  const glm::dvec3 m = p + alpha * na + beta * nb;
  const double h2 = r * r - glm::dot(m - p, m - p);
  if (h2 < 0.0) return 0;
  const glm::dvec3 u = dir / std::sqrt(len2);
  const double h = std::sqrt(h2);
  out[0] = m + h * u, out[1] = m - h * u;
  return 2;
}


// The distance from p to the triangle (a, b, c): to its nearest point, found by the Voronoi
// regions of its corners, edges and face (Ericson, Real-Time Collision Detection, 5.1.5).
double distanceToTriangle(const glm::dvec3& p, const glm::dvec3& a, const glm::dvec3& b, const glm::dvec3& c) {
  const glm::dvec3 ab = b - a, ac = c - a, ap = p - a;
  const double d1 = glm::dot(ab, ap), d2 = glm::dot(ac, ap);
  if (d1 <= 0.0 && d2 <= 0.0) return glm::length(ap);
  const glm::dvec3 bp = p - b;
  const double d3 = glm::dot(ab, bp), d4 = glm::dot(ac, bp);
  if (d3 >= 0.0 && d4 <= d3) return glm::length(bp);
  const double vc = d1 * d4 - d3 * d2;
  if (vc <= 0.0 && d1 >= 0.0 && d3 <= 0.0) return glm::length(p - (a + d1 / (d1 - d3) * ab));
  const glm::dvec3 cp = p - c;
  const double d5 = glm::dot(ab, cp), d6 = glm::dot(ac, cp);
  if (d6 >= 0.0 && d5 <= d6) return glm::length(cp);
  const double vb = d5 * d2 - d1 * d6;
  if (vb <= 0.0 && d2 >= 0.0 && d6 <= 0.0) return glm::length(p - (a + d2 / (d2 - d6) * ac));
  const double va = d3 * d6 - d5 * d4;
  if (va <= 0.0 && d4 - d3 >= 0.0 && d5 - d6 >= 0.0)
    return glm::length(p - (b + (d4 - d3) / ((d4 - d3) + (d5 - d6)) * (c - b)));
  const double denom = 1.0 / (va + vb + vc);
  return glm::length(p - (a + vb * denom * ab + vc * denom * ac));
}

// The angle between two unit vectors, accurate near 0 (acos of the dot product loses half the
// digits there).
double angleBetween(const glm::dvec3& u, const glm::dvec3& v) { return std::atan2(glm::length(glm::cross(u, v)), glm::dot(u, v)); }

// The triangle's farthest point from its nearest corner (the circumradius, or L/√2 for an
// obtuse triangle with longest edge L), and the radius of its smallest enclosing ball (the
// circumradius, or L/2 for an obtuse one).
struct TriangleRadii {
  double cover = 0.0, enclosing = 0.0;
};
TriangleRadii triangleRadii(const glm::dvec3& a, const glm::dvec3& b, const glm::dvec3& c) {
  const double ab = glm::length(b - a), bc = glm::length(c - b), ca = glm::length(a - c);
  const double longest = std::max({ab, bc, ca});
  const double others2 = ab * ab + bc * bc + ca * ca - longest * longest;
  const double area2 = glm::length(glm::cross(b - a, c - a));  // twice the area
  if (longest * longest > others2 || area2 <= 0.0) return {longest / std::sqrt(2.0), 0.5 * longest};
  const double circumradius = ab * bc * ca / (2.0 * area2);
  return {circumradius, circumradius};
}

// Rounding slack added to every patch bound (Å): the corners' own distance from the surface is
// counted exactly; this covers the arithmetic of the bound itself.
constexpr double kPatchSlack = 1e-10;
// Angular margin (radians) by which a triangle must clear a neighbour's cap or a patch's edge.
constexpr double kAngleMargin = 1e-6;

// ---------------------------------------------------------------------------------------------
// SES: signedDistance(x) = rp − dist(x, A), with A the accessible probe centres (ORACLES D.1).
class SesDistance final : public SurfaceDistance {
 public:
  SesDistance(const PatchList& list, std::span<const glm::dvec3> centers, std::span<const double> radii)
      : list_(list), rp_(list.params.probeRadius) {
    // Every atom's ball: a buried atom has no patch, but its ball may fill a void that the
    // others leave inside the body, and so cover parts of their spheres.
    std::vector<std::uint32_t> atoms(centers.size());
    for (std::uint32_t a = 0; a < atoms.size(); ++a) atoms[a] = a;
    std::vector<glm::dvec3> ballCenters(centers.begin(), centers.end());
    std::vector<double> ballRadii;
    for (std::uint32_t a : atoms) {
      ballAtom_.push_back(a);
      ballRadii.push_back(radii[a] + rp_);
      atomRadius_.push_back(radii[a]);
    }
    ballComponent_.assign(atoms.size(), 0u);
    for (std::size_t k = 0; k < list.convex.size(); ++k) {
      const auto it = std::lower_bound(atoms.begin(), atoms.end(), list.convex.atom[k]);
      ballComponent_[it - atoms.begin()] = list.convex.component[k];
    }
    std::vector<BallArc> arcs;
    const Tori& t = list.tori;
    for (std::size_t k = 0; k < t.size(); ++k)
      arcs.push_back({t.center[k], t.axis[k], t.e1[k], glm::cross(t.axis[k], t.e1[k]), t.bigRadius[k], t.phiExtent[k],
                      {t.atomI[k], t.atomJ[k]}});
    // A vertex per concave triangle; the triangles of a merged (cospherical) vertex share its
    // probe and make one fan.
    const ConcaveTriangles& cv = list.concave;
    std::vector<BallVertex> vertices;
    std::map<std::tuple<double, double, double>, std::uint32_t> fanOf;
    std::vector<std::vector<std::uint32_t>> fans;
    for (std::uint32_t k = 0; k < cv.size(); ++k) {
      const glm::dvec3 p = cv.probe[k];
      vertices.push_back({p, {cv.atomI[k], cv.atomJ[k], cv.atomK[k]}});
      const auto [it, added] = fanOf.try_emplace({p.x, p.y, p.z}, static_cast<std::uint32_t>(fans.size()));
      if (added) fans.emplace_back();
      fans[it->second].push_back(k);
      fan_.push_back(it->second);
    }
    triangleStart_.push_back(0);
    for (const auto& ts : fans) {
      triangles_.insert(triangles_.end(), ts.begin(), ts.end());
      triangleStart_.push_back(static_cast<std::uint32_t>(triangles_.size()));
    }
    union_ = std::make_unique<BallUnion>(std::move(ballCenters), std::move(ballRadii), std::move(arcs),
                                         std::move(vertices), 2.0 * rp_);  // one cell for |signedDistance| <= rp

    for (std::size_t k = 0; k < list.convex.size(); ++k)
      extend(list.convex.center[k] - list.convex.radius[k], list.convex.center[k] + list.convex.radius[k]);
    for (std::size_t k = 0; k < t.size(); ++k)
      extend(t.center[k] - (t.bigRadius[k] + rp_), t.center[k] + (t.bigRadius[k] + rp_));
    for (const glm::dvec3& p : list.concave.probe) extend(p - rp_, p + rp_);
  }

  double signedDistance(const glm::dvec3& x) const override { return query(x, nullptr); }
  SurfacePoint closest(const glm::dvec3& x) const override {
    SurfacePoint s;
    query(x, &s);
    return s;
  }
  double reach() const override { return rp_; }
  glm::dvec3 boundsMin() const override { return lo_; }
  glm::dvec3 boundsMax() const override { return hi_; }

  // Why each bound is one: dist(p, SES) <= |p − y| for any point y of the SES, and for every p of
  // the triangle T a point y_p of the SES is named whose distance from p has a closed-form
  // maximum over T. The corners' nearest accessible-probe feature (BallUnion::nearest: a sphere,
  // an arc, a probe vertex) says which patch they are on; all three must be on the same one.
  //  - Convex patch of atom i (centre c, radius r, SAS radius R = r + rp): y_p = c + r u_p with
  //    u_p = (p − c)/|p − c|. u_p lies in the cone of the corners' directions (p is a convex
  //    combination of them), which lies in the spherical cap around their mean direction that
  //    holds them (β < 90°: that cap is convex). When that cap clears every overlapping ball's
  //    cap on the SAS sphere (angle(m, w_j) >= β + α_j), the probe c + R u_p lies in no ball:
  //    it is accessible, so dist_A(y_p) <= rp; and y_p, in the atom's ball, is >= rp from A.
  //    So y_p is on the SES, and |p − y_p| = ||p − c| − r| <= max(r − dist(c, T), max_k |v_k − c| − r).
  //  - Concave triangle of probe a: y_p = a + rp (p − a)/|p − a|. Its direction is in the
  //    triangle's cone (convex, and it holds the corners'), and the spherical triangle of an
  //    unclipped concave patch lies on the SES (the patch list's contract, which the field and
  //    the renderers rely on too). Same bound with a and rp.
  //  - Torus (probe circle: centre C, axis, radius R > rp; patch φ in [0, Φ], θ in [θI, θJ]):
  //    y_p = a(φ_p) + rp (p − a(φ_p))/g(p), with a(φ_p) the circle's point at p's azimuth and
  //    g(p) = |p − a(φ_p)| the distance from p to the circle; |p − y_p| = |g(p) − rp|. ρ (the
  //    distance from the axis) and g are 1-Lipschitz and every p is within `cover` of a corner
  //    along a segment in T, so over T ρ >= min ρ_k − cover, g >= min g_k − cover, and φ, θ
  //    (gradients 1/ρ, 1/g) stay within cover/ρmin, cover/gmin of a corner's: inside the patch
  //    when the corners are that far from its edges, so y_p is on the patch, on the SES. g's
  //    Hessian has eigenvalues 0, 1/g and (ρ − R)/(gρ) (|.| <= 1/ρ): with H = max(1/gmin, 1/ρmin),
  //    Taylor's theorem at p towards each corner gives |g(p) − Σλ_k g(v_k)| <= H/2 Σλ_k|v_k − p|²
  //    <= H/2 R_enc² (R_enc: the smallest ball holding T), so |g − rp| <= max_k|g_k − rp| + H R_enc²/2.
  //  - A seam of atom i's sphere and the torus of atoms i and j (corners on both): a point p of
  //    T lies either outside the cone from c_i through the probe circle, where u_p is outside
  //    ball j's cap and the sphere's argument holds (the caps of the other neighbours checked),
  //    or inside it, which is θ_p >= θI (θ_p <= θJ for j's side): the torus's argument holds
  //    with that side's check left out. Both bounds are taken over all of T (the corners of
  //    the other patch count in them at their distance from this one's sphere or circle), and
  //    the larger of the two bounds T.
  //  - A seam of a concave triangle (probe P) and the torus that ends at P: the cone's face
  //    through the two atoms the torus joins is the plane of the torus's end meridian (both hold
  //    the axis and P). A point of T on the cone's side of it is in the cone (the other two faces
  //    hold the corners, so all of T), where the concave argument holds; on the other side it is
  //    in the torus's end half-space (the two sides are checked to be opposite), and with Φ <= π
  //    the other half-space holds the corners, so φ_p is in range: the torus argument holds.
  double patchDeviation(const glm::dvec3& a, const glm::dvec3& b, const glm::dvec3& c) const override {
    const glm::dvec3 v[3] = {a, b, c};
    UnionNearest n[3];
    int spheres = 0, arcs = 0;
    for (int k = 0; k < 3; ++k) {
      n[k] = union_->nearest(v[k]);
      spheres += n[k].feature == UnionFeature::Sphere, arcs += n[k].feature == UnionFeature::Arc;
    }
    if (spheres > 0 && arcs > 0 && spheres + arcs == 3) {
      std::uint32_t ball = 0, arc = 0;
      for (int k = 0; k < 3; ++k) (n[k].feature == UnionFeature::Sphere ? ball : arc) = n[k].index;
      for (int k = 0; k < 3; ++k)
        if (n[k].index != (n[k].feature == UnionFeature::Sphere ? ball : arc)) return kInf;
      const Tori& t = list_.tori;
      if (ballAtom_[ball] != t.atomI[arc] && ballAtom_[ball] != t.atomJ[arc]) return kInf;
      const bool sideI = ballAtom_[ball] == t.atomI[arc];
      const std::uint32_t other = sideI ? t.atomJ[arc] : t.atomI[arc];
      return std::max(convexDeviation(ball, v, other), torusDeviation(arc, v, sideI ? 1 : 2));
    }
    const int vertices = 3 - spheres - arcs -
                         ((n[0].feature == UnionFeature::Outside) + (n[1].feature == UnionFeature::Outside) +
                          (n[2].feature == UnionFeature::Outside));
    if (vertices > 0 && arcs > 0 && vertices + arcs == 3) return concaveTorusDeviation(n, v);
    for (int k = 0; k < 3; ++k)
      if (n[k].feature == UnionFeature::Outside || n[k].feature != n[0].feature) return kInf;
    switch (n[0].feature) {
      case UnionFeature::Sphere:
        if (n[1].index != n[0].index || n[2].index != n[0].index) return kInf;
        return convexDeviation(n[0].index, v);
      case UnionFeature::Vertex:
        if (fan_[n[1].index] != fan_[n[0].index] || fan_[n[2].index] != fan_[n[0].index]) return kInf;
        return concaveDeviation(n[0].index, v);
      case UnionFeature::Arc:
        if (n[1].index != n[0].index || n[2].index != n[0].index) return kInf;
        return torusDeviation(n[0].index, v);
      default: return kInf;
    }
  }

 private:
  // max over T of ||p − centre| − radius| (see patchDeviation).
  static double radialDeviation(const glm::dvec3& centre, double radius, const glm::dvec3 (&v)[3]) {
    const double nearest = distanceToTriangle(centre, v[0], v[1], v[2]);
    if (!(nearest > 0.0)) return kInf;
    double farthest = 0.0;
    for (const glm::dvec3& p : v) farthest = std::max(farthest, glm::length(p - centre));
    return std::max(radius - nearest, farthest - radius) + kPatchSlack;
  }

  // `skip`: a neighbour whose cap is left out (a seam with its torus), or none.
  double convexDeviation(std::uint32_t ball, const glm::dvec3 (&v)[3], std::uint32_t skip = ~0u) const {
    const glm::dvec3 centre = union_->center(ball);
    const double R = union_->radius(ball);
    glm::dvec3 u[3];
    for (int k = 0; k < 3; ++k) u[k] = unitOr(v[k] - centre, glm::dvec3(0.0));
    const glm::dvec3 mean = unitOr(u[0] + u[1] + u[2], glm::dvec3(0.0));
    if (glm::dot(mean, mean) == 0.0) return kInf;
    const double beta = std::max({angleBetween(mean, u[0]), angleBetween(mean, u[1]), angleBetween(mean, u[2])});
    if (!(beta < 1.0)) return kInf;  // well below 90°: the cap is convex
    for (std::uint32_t j : union_->neighbours(ball)) {
      if (j == skip) continue;
      const glm::dvec3 toJ = union_->center(j) - centre;
      const double D = glm::length(toJ), Rj = union_->radius(j);
      if (!(D > 0.0)) return kInf;
      // Ball j covers the directions u with u·w > cos α of the SAS sphere.
      const double cosAlpha = (D * D + R * R - Rj * Rj) / (2.0 * R * D);
      if (cosAlpha >= 1.0) continue;
      if (cosAlpha <= -1.0) return kInf;
      const double alpha = std::atan2(std::sqrt(1.0 - cosAlpha * cosAlpha), cosAlpha);
      if (angleBetween(mean, toJ / D) < beta + alpha + kAngleMargin) return kInf;
    }
    return radialDeviation(centre, atomRadius_[ball], v);
  }

  double concaveDeviation(std::uint32_t vertex, const glm::dvec3 (&v)[3]) const {
    const glm::dvec3 probe = union_->vertex(vertex).point;
    glm::dvec3 u[3];
    for (int k = 0; k < 3; ++k) u[k] = unitOr(v[k] - probe, glm::dvec3(0.0));
    const std::uint32_t t = triangleAt(fan_[vertex], u[0]);
    if (list_.concave.clipCount[t] != 0) return kInf;
    for (const glm::dvec3& d : u)
      if (!inCone(t, d, -kAngleMargin)) return kInf;  // strictly inside, by the margin
    return radialDeviation(probe, rp_, v);
  }

  double concaveTorusDeviation(const UnionNearest (&n)[3], const glm::dvec3 (&v)[3]) const {
    std::uint32_t vertex = 0, arc = 0;
    for (int k = 0; k < 3; ++k) (n[k].feature == UnionFeature::Vertex ? vertex : arc) = n[k].index;
    for (int k = 0; k < 3; ++k)
      if (n[k].feature == UnionFeature::Vertex ? fan_[n[k].index] != fan_[vertex] : n[k].index != arc) return kInf;
    const Tori& tori = list_.tori;
    const ConcaveTriangles& cv = list_.concave;
    const double extent = tori.phiExtent[arc];
    if (!(extent <= std::numbers::pi)) return kInf;
    const glm::dvec3 probe = union_->vertex(vertex).point, centre = tori.center[arc], axis = tori.axis[arc];
    const glm::dvec3 e1 = tori.e1[arc], e2 = glm::cross(axis, e1);
    const double R = tori.bigRadius[arc];
    // Which end of the torus is at the probe: its half-space's inward normal there.
    const glm::dvec3 endDirection = std::cos(extent) * e1 + std::sin(extent) * e2;
    int end = -1;
    if (glm::length(centre + R * e1 - probe) < 1e-9 * (1.0 + R)) end = 0;
    if (glm::length(centre + R * endDirection - probe) < 1e-9 * (1.0 + R)) end = 1;
    if (end < 0) return kInf;
    const glm::dvec3 endNormal = end == 0 ? e2 : std::sin(extent) * e1 - std::cos(extent) * e2;
    // The concave triangle: the one of the fan whose cone holds a concave corner.
    std::uint32_t t = 0;
    for (int k = 0; k < 3; ++k)
      if (n[k].feature == UnionFeature::Vertex) t = triangleAt(fan_[vertex], unitOr(v[k] - probe, glm::dvec3(0.0)));
    if (cv.clipCount[t] != 0) return kInf;
    const std::uint32_t atoms[3] = {cv.atomI[t], cv.atomJ[t], cv.atomK[t]};
    const glm::dvec3 d[3] = {cv.dirI[t], cv.dirJ[t], cv.dirK[t]};
    int face = -1;
    for (int e = 0; e < 3; ++e) {
      const std::uint32_t p = atoms[e], q = atoms[(e + 1) % 3];
      if ((p == tori.atomI[arc] && q == tori.atomJ[arc]) || (p == tori.atomJ[arc] && q == tori.atomI[arc])) face = e;
    }
    if (face < 0) return kInf;
    for (int e = 0; e < 3; ++e) {
      glm::dvec3 g = glm::normalize(glm::cross(d[e], d[(e + 1) % 3]));
      if (glm::dot(g, d[(e + 2) % 3]) < 0.0) g = -g;
      if (e == face) {
        if (!(glm::dot(g, endNormal) < -0.5)) return kInf;  // the two sides opposite
        continue;
      }
      for (int k = 0; k < 3; ++k)
        if (!(glm::dot(g, unitOr(v[k] - probe, glm::dvec3(0.0))) > kAngleMargin)) return kInf;
    }
    return std::max(radialDeviation(probe, rp_, v), torusDeviation(arc, v, 0, end));
  }

  // `skipSide`: 1 leaves out the check θ >= θI, 2 the check θ <= θJ (a seam with that side's
  // sphere), 0 neither.
  // `skipEnd`: 0 leaves out the half-space of the end φ = 0, 1 that of φ = Φ (a seam with the
  // concave triangle there; Φ <= π), -1 neither.
  double torusDeviation(std::uint32_t k, const glm::dvec3 (&v)[3], int skipSide = 0, int skipEnd = -1) const {
    const Tori& t = list_.tori;
    const double R = t.bigRadius[k];
    if (!(R > rp_)) return kInf;  // a spindle: its inner part is cut off
    const glm::dvec3 centre = t.center[k], axis = t.axis[k], e1 = t.e1[k], e2 = glm::cross(axis, e1);
    const TriangleRadii radii = triangleRadii(v[0], v[1], v[2]);
    double phi[3], theta[3], rhoMin = kInf, gMin = kInf, cornerError = 0.0;
    for (int m = 0; m < 3; ++m) {
      const glm::dvec3 d = v[m] - centre;
      const glm::dvec3 radial = d - glm::dot(d, axis) * axis;
      const double rho = glm::length(radial);
      if (!(rho > 0.0)) return kInf;
      const glm::dvec3 ur = radial / rho;
      phi[m] = std::atan2(glm::dot(ur, e2), glm::dot(ur, e1));
      if (phi[m] < 0.0) phi[m] += 2.0 * std::numbers::pi;
      const glm::dvec3 w = v[m] - (centre + R * ur);
      const double g = glm::length(w);
      theta[m] = std::atan2(glm::dot(w, axis), -glm::dot(w, ur));
      rhoMin = std::min(rhoMin, rho), gMin = std::min(gMin, g);
      cornerError = std::max(cornerError, std::abs(g - rp_));
    }
    rhoMin -= radii.cover, gMin -= radii.cover;
    if (!(rhoMin > 0.0) || !(gMin > 0.0)) return kInf;
    const double phiMargin = radii.cover / rhoMin + kAngleMargin, thetaMargin = radii.cover / gMin + kAngleMargin;
    const double extent = t.phiExtent[k];
    const bool fullCircle = extent >= 2.0 * std::numbers::pi;
    if (fullCircle && phiMargin >= 0.5 * std::numbers::pi) return kInf;
    // Where a side of the patch is a convex set, the corners inside it put all of T inside it:
    // φ in [0, Φ] is a wedge of half-spaces when Φ <= π; θ >= θI is the solid cone from the
    // axis point c_i = C + R tanθI axis through the probe circle when θI < 0 (it opens towards
    // +axis: the meridian line from a(φ) at angle θI passes through c_i), and θ <= θJ likewise
    // from C + R tanθJ axis when θJ > 0. Else the corners must clear the side by the margin.
    const glm::dvec3 wedgeEnd = std::sin(extent) * e1 - std::cos(extent) * e2;
    const auto inCone = [&](const glm::dvec3& p, double thetaSide, double direction) {
      const glm::dvec3 apex = centre + R * std::tan(thetaSide) * axis;
      return direction * glm::dot(p - apex, axis) >= std::abs(std::sin(thetaSide)) * glm::length(p - apex) + kPatchSlack;
    };
    for (int m = 0; m < 3; ++m) {
      if (!fullCircle) {
        if (extent <= std::numbers::pi) {
          if ((skipEnd != 0 && !(glm::dot(v[m] - centre, e2) > kPatchSlack)) ||
              (skipEnd != 1 && !(glm::dot(v[m] - centre, wedgeEnd) > kPatchSlack)))
            return kInf;
        } else if (skipEnd >= 0 || phi[m] < phiMargin || phi[m] > extent - phiMargin) {
          return kInf;
        }
      }
      if (skipSide != 1 &&
          (t.thetaI[k] < 0.0 ? !inCone(v[m], t.thetaI[k], 1.0) : theta[m] < t.thetaI[k] + thetaMargin))
        return kInf;
      if (skipSide != 2 &&
          (t.thetaJ[k] > 0.0 ? !inCone(v[m], t.thetaJ[k], -1.0) : theta[m] > t.thetaJ[k] - thetaMargin))
        return kInf;
    }
    const auto bound = [&](double g) {
      return cornerError + 0.5 * std::max(1.0 / g, 1.0 / rhoMin) * radii.enclosing * radii.enclosing;
    };
    double delta = bound(gMin);
    // With |g − rp| <= delta over T, g >= rp − delta there: a smaller Hessian bound, still valid.
    if (rp_ - delta > gMin) delta = bound(rp_ - delta);
    return delta + kPatchSlack;
  }

  void extend(const glm::dvec3& lo, const glm::dvec3& hi) { lo_ = glm::min(lo_, lo), hi_ = glm::max(hi_, hi); }

  double query(const glm::dvec3& x, SurfacePoint* out) const {
    const UnionNearest n = union_->nearest(x);
    if (n.feature == UnionFeature::Outside) {
      // x is a probe centre: the nearest SES point is on the nearest ball's convex patch, rp
      // beyond the SAS, since the segment to any SES point crosses ∂U and then goes rp deeper.
      if (out) {
        const glm::dvec3 u = unitOr(x - union_->center(n.index), glm::dvec3(0, 0, 1));
        *out = {union_->center(n.index) + atomRadius_[n.index] * u, u, ballAtom_[n.index], kConvexCode,
                ballComponent_[n.index]};
      }
      return rp_ + n.distance;
    }
    const double d = n.distance;
    const glm::dvec3 c = n.point;
    const glm::dvec3 u = (x - c) / d;  // d > 0: x lies inside an open ball
    const glm::dvec3 y = c + rp_ * u;
    // Body side (d >= rp): the ball B(y, rp) lies in B(x, d), free of A, so y is on the SES.
    // Solvent side: y is on the SES unless another probe's ball holds it (a clipped concave
    // cap, a spindle torus's inner part); then the SES near x is a ridge.
    std::uint32_t triangle = 0;
    if (n.feature == UnionFeature::Vertex) triangle = triangleAt(fan_[n.index], u);
    glm::dvec3 ridge;
    if (d < rp_ && !onSurface(n, triangle, y) && ridgePoint(n, triangle, x, ridge)) {
      if (out) describe(n, triangle, ridge, unitOr(x - ridge, -u), *out);
      return glm::length(x - ridge);
    }
    if (out) describe(n, triangle, y, -u, *out);
    return rp_ - d;
  }

  // The triangle of the fan whose cone holds direction u (the first one otherwise).
  std::uint32_t triangleAt(std::uint32_t fan, const glm::dvec3& u) const {
    for (std::uint32_t k = triangleStart_[fan]; k < triangleStart_[fan + 1]; ++k)
      if (inCone(triangles_[k], u, 1e-12)) return triangles_[k];
    return triangles_[triangleStart_[fan]];
  }

  bool inCone(std::uint32_t t, const glm::dvec3& u, double slack) const {
    const ConcaveTriangles& c = list_.concave;
    const glm::dvec3 d[3] = {c.dirI[t], c.dirJ[t], c.dirK[t]};
    for (int e = 0; e < 3; ++e) {
      glm::dvec3 g = glm::cross(d[e], d[(e + 1) % 3]);
      if (glm::dot(g, d[(e + 2) % 3]) < 0.0) g = -g;
      if (glm::dot(g, u) < -slack * glm::length(g)) return false;
    }
    return true;
  }

  bool keptByClips(std::uint32_t t, const glm::dvec3& y, double slack) const {
    const ConcaveTriangles& c = list_.concave;
    for (std::uint32_t k = c.clipBegin[t]; k < c.clipBegin[t] + c.clipCount[t]; ++k) {
      const Plane& p = list_.clipPlanes[k];
      if (glm::dot(glm::dvec3(p), y) + p.w > slack) return false;
    }
    return true;
  }

  // The renderers' membership tests of the patch that y, a point on the feature's probe sphere,
  // would lie on (trace/*_patch.cpp).
  bool onSurface(const UnionNearest& n, std::uint32_t triangle, const glm::dvec3& y) const {
    switch (n.feature) {
      case UnionFeature::Vertex: return keptByClips(triangle, y, 0.0);
      case UnionFeature::Arc: {
        const Tori& t = list_.tori;
        const double R = t.bigRadius[n.index];
        if (R >= rp_) return true;
        const double h = std::sqrt(rp_ * rp_ - R * R);
        return glm::length(y - t.center[n.index]) >= h;
      }
      default: return true;
    }
  }

  // The nearest point to x of the ridge that bounds the feature's patch where another probe
  // cuts it: on a clipped concave triangle the clipping circles and their corners, on a
  // spindle torus its cusps. False when none lies on the patch.
  bool ridgePoint(const UnionNearest& n, std::uint32_t triangle, const glm::dvec3& x, glm::dvec3& best) const {
    double bestD = kInf;
    auto offer = [&](const glm::dvec3& q) {
      const double dq = glm::length(q - x);
      if (dq < bestD) bestD = dq, best = q;
    };
    if (n.feature == UnionFeature::Arc) {
      const Tori& t = list_.tori;
      const std::size_t k = n.index;
      const double h = std::sqrt(std::max(rp_ * rp_ - t.bigRadius[k] * t.bigRadius[k], 0.0));
      const double thetaC = std::acos(std::min(t.bigRadius[k] / rp_, 1.0));
      if (t.thetaJ[k] >= thetaC) offer(t.center[k] + h * t.axis[k]);
      if (t.thetaI[k] <= -thetaC) offer(t.center[k] - h * t.axis[k]);
      return bestD < kInf;
    }
    if (n.feature != UnionFeature::Vertex) return false;
    const ConcaveTriangles& c = list_.concave;
    const glm::dvec3 p = union_->vertex(n.index).point;
    const std::uint32_t fan = fan_[n.index];
    const double slack = 1e-9 * rp_;
    auto valid = [&](const glm::dvec3& q) {
      if (!keptByClips(triangle, q, slack)) return false;
      const glm::dvec3 u = (q - p) / rp_;
      for (std::uint32_t k = triangleStart_[fan]; k < triangleStart_[fan + 1]; ++k)
        if (inCone(triangles_[k], u, 1e-9)) return true;
      return false;
    };
    auto check = [&](const glm::dvec3& q) {
      if (valid(q)) offer(q);
    };
    // The planes that bound the patch: its clips, then its cone's faces through p.
    std::vector<Plane> planes(list_.clipPlanes.begin() + c.clipBegin[triangle],
                              list_.clipPlanes.begin() + c.clipBegin[triangle] + c.clipCount[triangle]);
    const std::size_t clips = planes.size();
    const glm::dvec3 d[3] = {c.dirI[triangle], c.dirJ[triangle], c.dirK[triangle]};
    for (int e = 0; e < 3; ++e) {
      glm::dvec3 g = glm::normalize(glm::cross(d[e], d[(e + 1) % 3]));
      if (glm::dot(g, d[(e + 2) % 3]) < 0.0) g = -g;
      planes.emplace_back(-g, glm::dot(g, p));  // kept: g·(y − p) >= 0
    }
    for (std::size_t a = 0; a < clips; ++a) {
      const glm::dvec3 na(planes[a]);
      const double offset = glm::dot(na, p) + planes[a].w;
      const glm::dvec3 m = p - offset * na;
      const double r2 = rp_ * rp_ - offset * offset;
      if (r2 <= 0.0) continue;
      const glm::dvec3 inPlane = x - (glm::dot(na, x) + planes[a].w) * na - m;
      const double len = glm::length(inPlane);
      if (len > 0.0) check(m + std::sqrt(r2) * inPlane / len);
      for (std::size_t b = 0; b < planes.size(); ++b) {
        if (b == a) continue;
        glm::dvec3 q[2];
        for (int k = 0, m2 = planePairOnSphere(planes[a], planes[b], p, rp_, q); k < m2; ++k) check(q[k]);
      }
    }
    return bestD < kInf;
  }

  void describe(const UnionNearest& n, std::uint32_t triangle, const glm::dvec3& y, const glm::dvec3& normal,
                SurfacePoint& out) const {
    out.point = y;
    out.normal = normal;
    switch (n.feature) {
      case UnionFeature::Arc: {
        const Tori& t = list_.tori;
        const std::size_t k = n.index;
        // The renderer's rule (trace/torus_patch.cpp atomOf): the nearer contact circle by the
        // axial coordinate.
        const double a = glm::dot(y - t.center[k], t.axis[k]);
        const double aI = rp_ * std::sin(t.thetaI[k]), aJ = rp_ * std::sin(t.thetaJ[k]);
        out.atom = a - aI <= aJ - a ? t.atomI[k] : t.atomJ[k];
        out.kind = kToroidalCode;
        out.component = t.component[k];
        break;
      }
      case UnionFeature::Vertex: {
        const ConcaveTriangles& c = list_.concave;
        const glm::dvec3 u = y - c.probe[triangle];
        const double di = glm::dot(u, c.dirI[triangle]), dj = glm::dot(u, c.dirJ[triangle]),
                     dk = glm::dot(u, c.dirK[triangle]);
        out.atom = di >= dj && di >= dk ? c.atomI[triangle] : (dj >= dk ? c.atomJ[triangle] : c.atomK[triangle]);
        out.kind = kConcaveCode;
        out.component = c.component[triangle];
        break;
      }
      default:
        out.atom = ballAtom_[n.index];
        out.kind = kConvexCode;
        out.component = ballComponent_[n.index];
    }
  }

  PatchList list_;  // a copy: the field may outlive the caller's list
  double rp_;
  std::vector<std::uint32_t> ballAtom_, ballComponent_;
  std::vector<double> atomRadius_;
  std::vector<std::uint32_t> fan_;                        // the fan of each concave triangle
  std::vector<std::uint32_t> triangleStart_, triangles_;  // CSR: the triangles of each fan
  std::unique_ptr<BallUnion> union_;
  glm::dvec3 lo_{kInf}, hi_{-kInf};
};

// ---------------------------------------------------------------------------------------------
// SAS and vdW: the boundary of the union of the list's spheres, whose arcs and vertices are
// those of the SES of the same balls shrunk by a probe ρ and rolled with it (that SES's SAS is
// the union): signedDistance = −dist(x, ∂U) inside, dist(x, U) outside, both exact.
class UnionDistance final : public SurfaceDistance {
 public:
  explicit UnionDistance(const PatchList& list) {
    const ConvexSpheres& s = list.convex;
    std::vector<glm::dvec3> centers(s.center.begin(), s.center.end());
    std::vector<double> radii(s.radius.begin(), s.radius.end());
    atom_ = s.atom;
    component_ = s.component;
    std::vector<BallArc> arcs;
    std::vector<BallVertex> vertices;
    minRadius_ = kInf;
    for (double r : radii) minRadius_ = std::min(minRadius_, r);
    if (!centers.empty()) {
      // Any ρ below the smallest radius gives the same arcs and vertices.
      const double rho = 0.5 * minRadius_;
      std::vector<double> shrunk(radii.size());
      for (std::size_t k = 0; k < radii.size(); ++k) shrunk[k] = radii[k] - rho;
      ses_ = buildSes(centers, shrunk, SesParams{rho});
      const Tori& t = ses_.tori;
      for (std::size_t k = 0; k < t.size(); ++k)
        arcs.push_back({t.center[k], t.axis[k], t.e1[k], glm::cross(t.axis[k], t.e1[k]), t.bigRadius[k],
                        t.phiExtent[k], {t.atomI[k], t.atomJ[k]}});
      const ConcaveTriangles& cv = ses_.concave;
      for (std::size_t k = 0; k < cv.size(); ++k) vertices.push_back({cv.probe[k], {cv.atomI[k], cv.atomJ[k], cv.atomK[k]}});
    }
    for (std::size_t k = 0; k < centers.size(); ++k) lo_ = glm::min(lo_, centers[k] - radii[k]), hi_ = glm::max(hi_, centers[k] + radii[k]);
    // One grid cell answers for points up to kUnionReach inside.
    union_ = std::make_unique<BallUnion>(std::move(centers), std::move(radii), std::move(arcs), std::move(vertices),
                                         kUnionReach);
  }

  double signedDistance(const glm::dvec3& x) const override {
    if (union_->size() == 0) return kInf;
    const UnionNearest n = union_->nearest(x);
    return n.feature == UnionFeature::Outside ? n.distance : -n.distance;
  }

  SurfacePoint closest(const glm::dvec3& x) const override {
    SurfacePoint s;
    if (union_->size() == 0) return s;
    const UnionNearest n = union_->nearest(x);
    s.point = n.point;
    s.kind = kConvexCode;
    std::uint32_t ball = n.index;
    if (n.feature == UnionFeature::Outside || n.feature == UnionFeature::Sphere) {
      s.normal = (n.point - union_->center(ball)) / union_->radius(ball);
    } else {
      // On a seam the owner is the ball whose inward direction from the seam point is nearest
      // to the direction of x; the normal is the direction from x (in the seam's normal cone).
      s.normal = unitOr(n.point - x, glm::dvec3(0, 0, 1));
      std::uint32_t balls[3];
      int count = 0;
      if (n.feature == UnionFeature::Arc) {
        balls[0] = ses_.tori.atomI[n.index], balls[1] = ses_.tori.atomJ[n.index], count = 2;
      } else {
        const std::size_t t = n.index;
        balls[0] = ses_.concave.atomI[t], balls[1] = ses_.concave.atomJ[t], balls[2] = ses_.concave.atomK[t];
        count = 3;
      }
      double bestCos = -kInf;
      for (int k = 0; k < count; ++k) {
        const double cosine =
            glm::dot(unitOr(union_->center(balls[k]) - n.point, glm::dvec3(0.0)), unitOr(x - n.point, glm::dvec3(0.0)));
        if (cosine > bestCos) bestCos = cosine, ball = balls[k];
      }
    }
    s.atom = atom_[ball];
    s.component = component_[ball];
    return s;
  }

  double reach() const override { return minRadius_; }
  glm::dvec3 boundsMin() const override { return lo_; }
  glm::dvec3 boundsMax() const override { return hi_; }

 private:
  std::vector<std::uint32_t> atom_, component_;
  PatchList ses_;  // the shrunk balls' SES: only its tori's circles and its probes are used
  double minRadius_ = 0.0;
  std::unique_ptr<BallUnion> union_;
  glm::dvec3 lo_{kInf}, hi_{-kInf};
};

}  // namespace

double SurfaceDistance::patchDeviation(const glm::dvec3&, const glm::dvec3&, const glm::dvec3&) const { return kInf; }

std::unique_ptr<SurfaceDistance> makeSurfaceDistance(const PatchList& patches, std::span<const glm::dvec3> centers,
                                                     std::span<const double> radii) {
  if (centers.size() != patches.params.atomCount || radii.size() != patches.params.atomCount)
    throw std::invalid_argument("makeSurfaceDistance: the patch list was built from " +
                                std::to_string(patches.params.atomCount) + " atoms, but " +
                                std::to_string(centers.size()) + " centres and " + std::to_string(radii.size()) +
                                " radii were given; pass the atoms the list was built from");
  switch (patches.params.surface) {
    case SurfaceKind::Ses: return std::make_unique<SesDistance>(patches, centers, radii);
    case SurfaceKind::Sas:
    case SurfaceKind::Vdw: return std::make_unique<UnionDistance>(patches);
    case SurfaceKind::Mss: return makeSkinDistance(patches, centers, radii);
  }
  throw std::invalid_argument("makeSurfaceDistance: unknown surface kind " +
                              std::to_string(static_cast<unsigned>(patches.params.surface)));
}

}  // namespace surftrace::build::mesh

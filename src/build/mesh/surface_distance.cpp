// The SES, SAS and vdW surfaces as exact distance fields, from the nearest point of the SAS
// (ORACLES D.1), and the dispatch to the skin's field.
#include "build/mesh/surface_distance.hpp"

#include <algorithm>
#include <cmath>
#include <limits>
#include <map>
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

 private:
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

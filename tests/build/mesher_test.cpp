// The mesher against analytic surfaces (a sphere, a torus, two spheres' union with its crease,
// two far-apart spheres, a sphere with a spherical cavity) whose distance is a formula; the
// mesh files read back with Assimp.
#include <algorithm>
#include <cmath>
#include <cstdint>
#include <cstring>
#include <fstream>
#include <limits>
#include <map>
#include <numbers>
#include <string>
#include <vector>

#include <assimp/Importer.hpp>
#include <assimp/postprocess.h>
#include <assimp/scene.h>
#include <glm/geometric.hpp>
#include <gtest/gtest.h>

#include "build/io/mesh_writer.hpp"
#include "build/mesh/mesher.hpp"
#include "temp_dir.hpp"

namespace surftrace::build::mesh {
namespace {

constexpr double kPi = std::numbers::pi;

// A ball's signed distance and nearest point: the parts the fields below are made of.
struct Ball {
  glm::dvec3 c;
  double r;
  double distance(const glm::dvec3& x) const { return glm::length(x - c) - r; }
  glm::dvec3 project(const glm::dvec3& x) const {
    const glm::dvec3 d = x - c;
    const double len = glm::length(d);
    return c + r * (len > 0.0 ? d / len : glm::dvec3(0, 0, 1));
  }
};

class SphereField : public SurfaceDistance {
 public:
  explicit SphereField(Ball b) : b_(b) {}
  double signedDistance(const glm::dvec3& x) const override { return b_.distance(x); }
  SurfacePoint closest(const glm::dvec3& x) const override {
    SurfacePoint p;
    p.point = b_.project(x);
    p.normal = glm::normalize(p.point - b_.c);
    p.kind = 1;
    p.atom = 7;
    return p;
  }
  double reach() const override { return 0.9 * b_.r; }
  glm::dvec3 boundsMin() const override { return b_.c - glm::dvec3(b_.r); }
  glm::dvec3 boundsMax() const override { return b_.c + glm::dvec3(b_.r); }

 private:
  Ball b_;
};

// A ring torus about z: major radius R, tube radius r.
class TorusField : public SurfaceDistance {
 public:
  TorusField(double R, double r) : R_(R), r_(r) {}
  glm::dvec3 core(const glm::dvec3& x) const {
    const double rho = std::hypot(x.x, x.y);
    const glm::dvec3 radial = rho > 0.0 ? glm::dvec3(x.x / rho, x.y / rho, 0.0) : glm::dvec3(1, 0, 0);
    return R_ * radial;
  }
  double signedDistance(const glm::dvec3& x) const override { return glm::length(x - core(x)) - r_; }
  SurfacePoint closest(const glm::dvec3& x) const override {
    const glm::dvec3 c = core(x);
    glm::dvec3 d = x - c;
    if (glm::length(d) == 0.0) d = glm::dvec3(0, 0, 1);
    SurfacePoint p;
    p.normal = glm::normalize(d);
    p.point = c + r_ * p.normal;
    p.kind = 2;
    return p;
  }
  double reach() const override { return 0.9 * r_; }
  glm::dvec3 boundsMin() const override { return -glm::dvec3(R_ + r_, R_ + r_, r_); }
  glm::dvec3 boundsMax() const override { return glm::dvec3(R_ + r_, R_ + r_, r_); }

 private:
  double R_, r_;
};

// The union of balls that are pairwise apart or overlap (no ball inside another): the exact
// distance, creases included. Outside, the distance to the union is the smallest distance to
// a ball. Inside, the nearest boundary point is a ball's radial projection that no other ball
// covers, or a point of a crease circle. Component: the ball's, unless `joined`.
class UnionField : public SurfaceDistance {
 public:
  UnionField(std::vector<Ball> balls, bool joined) : balls_(std::move(balls)), joined_(joined) {}
  bool covered(const glm::dvec3& p, std::size_t except) const {
    for (std::size_t i = 0; i < balls_.size(); ++i)
      if (i != except && balls_[i].distance(p) < 0.0) return true;
    return false;
  }
  SurfacePoint nearest(const glm::dvec3& x, double* distance) const {
    SurfacePoint best;
    double d = 1e300;
    const auto consider = [&](const glm::dvec3& p, const glm::dvec3& n, std::uint32_t atom) {
      if (glm::length(x - p) < d) d = glm::length(x - p), best.point = p, best.normal = n, best.atom = atom;
    };
    const bool inside = std::any_of(balls_.begin(), balls_.end(), [&](const Ball& b) { return b.distance(x) < 0.0; });
    for (std::size_t i = 0; i < balls_.size(); ++i) {
      const glm::dvec3 p = balls_[i].project(x);
      if (!inside || !covered(p, i)) consider(p, glm::normalize(p - balls_[i].c), static_cast<std::uint32_t>(i));
      for (std::size_t j = i + 1; j < balls_.size() && inside; ++j) {
        // The crease circle of balls i and j: centre m on the axis, radius a.
        const glm::dvec3 axis = balls_[j].c - balls_[i].c;
        const double dist = glm::length(axis);
        const double t = (dist * dist + balls_[i].r * balls_[i].r - balls_[j].r * balls_[j].r) / (2.0 * dist);
        const double a2 = balls_[i].r * balls_[i].r - t * t;
        if (a2 <= 0.0) continue;
        const glm::dvec3 u = axis / dist, m = balls_[i].c + t * u;
        glm::dvec3 radial = (x - m) - glm::dot(x - m, u) * u;
        if (glm::length(radial) == 0.0) radial = glm::normalize(glm::cross(u, glm::dvec3(0.3, 0.5, 0.7)));
        const glm::dvec3 q = m + std::sqrt(a2) * glm::normalize(radial);
        consider(q, glm::normalize(glm::normalize(q - balls_[i].c) + glm::normalize(q - balls_[j].c)),
                 static_cast<std::uint32_t>(i));
      }
    }
    best.kind = 1;
    best.component = joined_ ? 0u : best.atom;
    *distance = inside ? -d : d;
    return best;
  }
  double signedDistance(const glm::dvec3& x) const override {
    double d;
    nearest(x, &d);
    return d;
  }
  SurfacePoint closest(const glm::dvec3& x) const override {
    double d;
    return nearest(x, &d);
  }
  double reach() const override { return 1.0; }
  glm::dvec3 boundsMin() const override {
    glm::dvec3 lo(1e300);
    for (const Ball& b : balls_) lo = glm::min(lo, b.c - glm::dvec3(b.r));
    return lo;
  }
  glm::dvec3 boundsMax() const override {
    glm::dvec3 hi(-1e300);
    for (const Ball& b : balls_) hi = glm::max(hi, b.c + glm::dvec3(b.r));
    return hi;
  }

 private:
  std::vector<Ball> balls_;
  bool joined_;
};

// A ball with a ball-shaped cavity inside: the body is outer minus inner. Component 0 is the
// outer sphere, 1 the cavity, whose outward normal points into the void (to the centre).
class CavityField : public SurfaceDistance {
 public:
  CavityField(Ball outer, Ball inner) : outer_(outer), inner_(inner) {}
  double signedDistance(const glm::dvec3& x) const override {
    return std::max(outer_.distance(x), -inner_.distance(x));
  }
  SurfacePoint closest(const glm::dvec3& x) const override {
    SurfacePoint p;
    if (std::abs(outer_.distance(x)) <= std::abs(inner_.distance(x))) {
      p.point = outer_.project(x);
      p.normal = glm::normalize(p.point - outer_.c);
    } else {
      p.point = inner_.project(x);
      p.normal = glm::normalize(inner_.c - p.point);
      p.component = 1;
      p.kind = 3;
    }
    return p;
  }
  double reach() const override { return 0.9 * inner_.r; }
  glm::dvec3 boundsMin() const override { return outer_.c - glm::dvec3(outer_.r); }
  glm::dvec3 boundsMax() const override { return outer_.c + glm::dvec3(outer_.r); }

 private:
  Ball outer_, inner_;
};

// Independent checks of a mesh: counted here, not with the mesher's meshComponents.
struct Topology {
  bool watertight = true;  // every directed edge's reverse appears exactly once, itself once
  std::map<std::uint32_t, long long> eulerByComponent;  // by the vertices' field component
};
Topology topologyOf(const TriangleMesh& m) {
  Topology t;
  std::map<std::pair<std::uint32_t, std::uint32_t>, int> directed;
  for (const glm::uvec3& tri : m.triangles)
    for (int e = 0; e < 3; ++e) directed[{tri[e], tri[(e + 1) % 3]}]++;
  for (const auto& [edge, count] : directed) {
    const auto back = directed.find({edge.second, edge.first});
    if (count != 1 || back == directed.end() || back->second != 1) t.watertight = false;
  }
  std::map<std::uint32_t, long long> v, e, f;
  std::vector<bool> used(m.positions.size(), false);
  for (const glm::uvec3& tri : m.triangles) {
    const std::uint32_t c = m.component[tri.x];
    f[c]++;
    for (int k = 0; k < 3; ++k) {
      if (!used[tri[k]]) used[tri[k]] = true, v[m.component[tri[k]]]++;
      if (tri[k] < tri[(k + 1) % 3]) e[c]++;
    }
  }
  for (const auto& [c, faces] : f) t.eulerByComponent[c] = v[c] - e[c] + faces;
  return t;
}

double area(const TriangleMesh& m) {
  double a = 0.0;
  for (const glm::uvec3& t : m.triangles)
    a += 0.5 * glm::length(glm::cross(m.positions[t.y] - m.positions[t.x], m.positions[t.z] - m.positions[t.x]));
  return a;
}
double volume(const TriangleMesh& m) {
  double v = 0.0;
  for (const glm::uvec3& t : m.triangles)
    v += glm::dot(m.positions[t.x], glm::cross(m.positions[t.y], m.positions[t.z])) / 6.0;
  return v;
}

// The largest |distance| over a dense barycentric sampling of every triangle, from the
// field's formula (exact for these fields): the deviation the certificate must bound.
double denseDeviation(const SurfaceDistance& f, const TriangleMesh& m, int n = 8) {
  double worst = 0.0;
  for (const glm::uvec3& t : m.triangles)
    for (int i = 0; i <= n; ++i)
      for (int j = 0; i + j <= n; ++j) {
        const glm::dvec3 s = (double(i) * m.positions[t.x] + double(j) * m.positions[t.y] +
                              double(n - i - j) * m.positions[t.z]) / double(n);
        worst = std::max(worst, std::abs(f.signedDistance(s)));
      }
  return worst;
}

double maxVertexDistance(const SurfaceDistance& f, const TriangleMesh& m) {
  double worst = 0.0;
  for (const glm::dvec3& p : m.positions) worst = std::max(worst, std::abs(f.signedDistance(p)));
  return worst;
}

MeshResult meshOf(const SurfaceDistance& f, std::vector<glm::dvec3> seeds, double eps, double h) {
  MeshParams params;
  params.maxError = eps;
  params.gridSpacing = h;
  return meshSurface(f, seeds, params);
}

// Checks every mesh must pass: closed and consistently oriented, vertices on the surface,
// the certificate within ε and the dense oracle within the certificate.
void expectSound(const SurfaceDistance& f, const MeshResult& r, double eps) {
  const Topology t = topologyOf(r.mesh);
  EXPECT_TRUE(t.watertight);
  EXPECT_LE(maxVertexDistance(f, r.mesh), 1e-9);
  EXPECT_LE(r.certifiedError, eps);
  EXPECT_LE(denseDeviation(f, r.mesh), r.certifiedError + 1e-12);
  // Vertex normals are the surface's (unit) and agree with the triangles' orientation.
  std::size_t against = 0;
  for (const glm::uvec3& tri : r.mesh.triangles) {
    const glm::dvec3 n = glm::cross(r.mesh.positions[tri.y] - r.mesh.positions[tri.x],
                                    r.mesh.positions[tri.z] - r.mesh.positions[tri.x]);
    if (glm::dot(n, r.mesh.normals[tri.x] + r.mesh.normals[tri.y] + r.mesh.normals[tri.z]) <= 0.0) ++against;
  }
  EXPECT_EQ(against, 0u);
  EXPECT_EQ(r.badTriangles, 0u);
}

// A ball with a ball-shaped cavity meshed right: two components of Euler characteristic 2, the
// outer one holding the ball's volume and the cavity minus the void's (normals into the void),
// each within the shell of thickness ε over its sphere. Returns the mesh's components.
std::vector<MeshComponent> expectBallWithCavity(const MeshResult& r, const Ball& outer, const Ball& inner, double eps) {
  const Topology t = topologyOf(r.mesh);
  EXPECT_EQ(t.eulerByComponent.size(), 2u);
  EXPECT_EQ(t.eulerByComponent.count(0) ? t.eulerByComponent.at(0) : 0, 2);
  EXPECT_EQ(t.eulerByComponent.count(1) ? t.eulerByComponent.at(1) : 0, 2);
  const std::vector<MeshComponent> c = meshComponents(r.mesh);
  EXPECT_EQ(c.size(), 2u);
  for (const MeshComponent& k : c) {
    const Ball& b = k.surfaceComponent == 0 ? outer : inner;
    const double sign = k.surfaceComponent == 0 ? 1.0 : -1.0;
    EXPECT_NEAR(k.volume, sign * 4.0 / 3 * kPi * b.r * b.r * b.r, eps * 4 * kPi * b.r * b.r) << "component " << k.surfaceComponent;
  }
  return c;
}

TEST(Mesher, SphereIsClosedGenusZeroAndWithinTheBound) {
  const Ball b{{0.3, -0.2, 0.1}, 2.0};
  const SphereField f(b);
  for (double eps : {0.1, 0.02}) {
    const MeshResult r = meshOf(f, {b.c + glm::dvec3(0, 0, b.r)}, eps, 0.5);
    SCOPED_TRACE("eps " + std::to_string(eps));
    expectSound(f, r, eps);
    const Topology t = topologyOf(r.mesh);
    ASSERT_EQ(t.eulerByComponent.size(), 1u);
    EXPECT_EQ(t.eulerByComponent.at(0), 2);
    EXPECT_GT(volume(r.mesh), 0.0);  // outward
    EXPECT_EQ(r.mesh.atom[0], 7u);
    EXPECT_EQ(r.mesh.kind[0], 1u);
  }
}

TEST(Mesher, TorusHasEulerCharacteristicZero) {
  const TorusField f(2.0, 0.7);
  const MeshResult r = meshOf(f, {glm::dvec3(2.7, 0, 0)}, 0.05, 0.3);
  expectSound(f, r, 0.05);
  const Topology t = topologyOf(r.mesh);
  ASSERT_EQ(t.eulerByComponent.size(), 1u);
  EXPECT_EQ(t.eulerByComponent.at(0), 0);
  EXPECT_NEAR(volume(r.mesh), 2 * kPi * kPi * 2.0 * 0.7 * 0.7, 0.05 * 4 * kPi * kPi * 2.0 * 0.7);
}

TEST(Mesher, CreaseOfTwoOverlappingSpheresIsWithinTheBound) {
  const UnionField f({{{0, 0, 0}, 1.6}, {{2.0, 0.3, 0}, 1.3}}, true);
  for (double eps : {0.1, 0.02}) {
    SCOPED_TRACE("eps " + std::to_string(eps));
    const MeshResult r = meshOf(f, {glm::dvec3(-1.6, 0, 0)}, eps, 0.45);
    expectSound(f, r, eps);
    const Topology t = topologyOf(r.mesh);
    ASSERT_EQ(t.eulerByComponent.size(), 1u);
    EXPECT_EQ(t.eulerByComponent.at(0), 2);
  }
}

TEST(Mesher, FarApartSpheresAreTwoComponents) {
  const UnionField f({{{0, 0, 0}, 1.5}, {{6.0, 1.0, -1.0}, 1.1}}, false);
  // One seed on each; a seed near only one sphere meshes only that one.
  const MeshResult both = meshOf(f, {glm::dvec3(1.5, 0, 0), glm::dvec3(6.0, 1.0, 0.1)}, 0.05, 0.4);
  expectSound(f, both, 0.05);
  const Topology t = topologyOf(both.mesh);
  ASSERT_EQ(t.eulerByComponent.size(), 2u);
  EXPECT_EQ(t.eulerByComponent.at(0), 2);
  EXPECT_EQ(t.eulerByComponent.at(1), 2);
  const std::vector<MeshComponent> c = meshComponents(both.mesh);
  ASSERT_EQ(c.size(), 2u);
  EXPECT_TRUE(c[0].closed && c[1].closed);
  EXPECT_NE(c[0].surfaceComponent, c[1].surfaceComponent);
  const MeshResult one = meshOf(f, {glm::dvec3(1.5, 0, 0)}, 0.05, 0.4);
  EXPECT_EQ(topologyOf(one.mesh).eulerByComponent.size(), 1u);
}

// A gap of solvent thinner than the grid: two balls 0.02 Å apart, a grid of 0.6 Å whose edges
// across the gap have both ends inside (one in each ball). Marching tetrahedra on the grid's
// values alone bridges the gap (one component); the two spheres are two components, each
// closed with Euler characteristic 2, and the mesh stays within ε of them.
TEST(Mesher, GapThinnerThanTheGridIsNotBridged) {
  const UnionField f({{{0, 0, 0}, 2.5}, {{5.02, 0.02, -0.01}, 2.5}}, false);
  for (double eps : {0.1, 0.02}) {
    SCOPED_TRACE("eps " + std::to_string(eps));
    const MeshResult r = meshOf(f, {glm::dvec3(-2.5, 0, 0), glm::dvec3(7.52, 0.02, -0.01)}, eps, 0.6);
    expectSound(f, r, eps);
    const Topology t = topologyOf(r.mesh);
    ASSERT_EQ(t.eulerByComponent.size(), 2u);
    EXPECT_EQ(t.eulerByComponent.at(0), 2);
    EXPECT_EQ(t.eulerByComponent.at(1), 2);
    EXPECT_EQ(meshComponents(r.mesh).size(), 2u);
  }
}

// A wall of the body thinner than the grid: a ball with a cavity 0.08 Å under its surface.
// Grid edges across the wall have both ends outside the body (one in the cavity, one in the
// solvent), so marching tetrahedra on the grid's values alone opens a hole through the wall.
// The outer surface and the cavity are two closed components of Euler characteristic 2.
TEST(Mesher, WallThinnerThanTheGridIsNotPierced) {
  const Ball outer{{0, 0, 0}, 3.0}, inner{{1.72, 0.03, -0.02}, 1.2};
  const CavityField f(outer, inner);
  for (double eps : {0.1, 0.02}) {
    SCOPED_TRACE("eps " + std::to_string(eps));
    const MeshResult r = meshOf(f, {glm::dvec3(-3, 0, 0), inner.c - glm::dvec3(1.2, 0, 0)}, eps, 0.5);
    expectSound(f, r, eps);
    expectBallWithCavity(r, outer, inner, eps);
  }
}

TEST(Mesher, CavityIsItsOwnInwardFacingComponent) {
  const Ball outer{{0, 0, 0}, 3.0}, inner{{0.4, 0.2, -0.3}, 1.2};
  const CavityField f(outer, inner);
  const MeshResult r = meshOf(f, {glm::dvec3(3, 0, 0), inner.c + glm::dvec3(1.2, 0, 0)}, 0.03, 0.5);
  expectSound(f, r, 0.03);
  const std::vector<MeshComponent> c = expectBallWithCavity(r, outer, inner, 0.03);
  // The component filter keeps the cavity alone.
  std::vector<bool> keep(c.size());
  for (std::size_t k = 0; k < c.size(); ++k) keep[k] = c[k].surfaceComponent == 1;
  const TriangleMesh cavity = keepComponents(r.mesh, keep);
  EXPECT_LT(volume(cavity), 0.0);
  for (std::size_t v = 0; v < cavity.positions.size(); ++v)
    EXPECT_GT(glm::dot(cavity.normals[v], inner.c - cavity.positions[v]), 0.0);
}

// Area and volume errors against 4πR² and 4πR³/3 fall at second order in the edge length
// (first order in ε, the chord's sagitta being quadratic in its length).
TEST(Mesher, AreaAndVolumeConvergeAtSecondOrder) {
  const Ball b{{0.11, 0.07, -0.05}, 3.0};
  const SphereField f(b);
  std::vector<double> logEdge, logArea, logVolume;
  for (double eps : {0.04, 0.02, 0.01}) {
    const MeshResult r = meshOf(f, {b.c + glm::dvec3(b.r, 0, 0)}, eps, 1.2);
    double edges = 0.0;
    for (const glm::uvec3& t : r.mesh.triangles)
      for (int e = 0; e < 3; ++e) edges += glm::length(r.mesh.positions[t[e]] - r.mesh.positions[t[(e + 1) % 3]]);
    logEdge.push_back(std::log(edges / (3.0 * r.mesh.triangles.size())));
    logArea.push_back(std::log(4 * kPi * 9.0 - area(r.mesh)));
    logVolume.push_back(std::log(4.0 / 3 * kPi * 27.0 - volume(r.mesh)));
  }
  const auto slope = [&](const std::vector<double>& y) {
    const double mx = (logEdge[0] + logEdge[1] + logEdge[2]) / 3, my = (y[0] + y[1] + y[2]) / 3;
    double sxy = 0.0, sxx = 0.0;
    for (int k = 0; k < 3; ++k) sxy += (logEdge[k] - mx) * (y[k] - my), sxx += (logEdge[k] - mx) * (logEdge[k] - mx);
    return sxy / sxx;
  };
  std::printf("orders: area %.3f, volume %.3f\n", slope(logArea), slope(logVolume));
  EXPECT_NEAR(slope(logArea), 2.0, 0.3);
  EXPECT_NEAR(slope(logVolume), 2.0, 0.3);
}

TEST(Mesher, RejectsAGridCoarserThanTheReach) {
  const SphereField f({{0, 0, 0}, 1.0});
  EXPECT_THROW(meshOf(f, {glm::dvec3(1, 0, 0)}, 0.1, 0.95), std::invalid_argument);
  EXPECT_THROW(meshOf(f, {glm::dvec3(1, 0, 0)}, 0.0, 0.5), std::invalid_argument);
}

// A split line that leaves the body through a thin gap and runs on into a second body: the
// split point is the first crossing, on the near sphere. Two unit balls 0.03 apart along x; the
// edge's ends are on the first at ±25° with normals tilted to 30°, so the line from the
// midpoint (0.906, 0, 0) meets the first sphere 0.107 along, the second 0.03 beyond, and leaves
// the second ~2.9 along (where steps that double from |f(midpoint)| = 0.094 land).
TEST(Mesher, SplitPointIsTheFirstCrossingPastAThinGap) {
  const UnionField f({{{0, 0, 0}, 1.0}, {{2.03, 0, 0}, 1.0}}, false);
  const double a = 25.0 * kPi / 180.0, tilt = 30.0 * kPi / 180.0;
  const glm::dvec3 p(std::cos(a), std::sin(a), 0.0), q(std::cos(a), -std::sin(a), 0.0);
  const glm::dvec3 n(std::cos(tilt), std::sin(tilt), 0.0);
  const glm::dvec3 s = splitPoint(f, p, q, n, n);
  // The oracle: the line m + t n meets the unit sphere at t = −m·n + √((m·n)² − |m|² + 1).
  const glm::dvec3 m = 0.5 * (p + q);
  const double mn = glm::dot(m, n), t = -mn + std::sqrt(mn * mn - glm::dot(m, m) + 1.0);
  EXPECT_LT(glm::length(s - (m + t * n)), 1e-9) << "split point " << s.x << " " << s.y << " " << s.z;
}

// A field whose sign changes without a zero (a sphere's distance, but -1 anywhere inside) is
// refused with the place named, rather than meshed with vertices off the surface.
class SignJumpField : public SphereField {
 public:
  using SphereField::SphereField;
  double signedDistance(const glm::dvec3& x) const override {
    const double d = SphereField::signedDistance(x);
    return d < 0.0 ? -1.0 : d + 0.05;
  }
};

TEST(Mesher, DiscontinuousFieldIsAnError) {
  const SignJumpField f({{0, 0, 0}, 1.5});
  try {
    (void)meshOf(f, {glm::dvec3(1.5, 0, 0)}, 0.1, 0.4);
    FAIL() << "no error";
  } catch (const std::runtime_error& e) {
    EXPECT_NE(std::string(e.what()).find("changes sign without a zero"), std::string::npos) << e.what();
  }
}

// A field whose closest points are not numbers above z = 0.5 (a broken field): a triangle
// there has no bound (+inf), rather than the bound of its corners alone.
class NanClosestField : public SphereField {
 public:
  using SphereField::SphereField;
  SurfacePoint closest(const glm::dvec3& x) const override {
    SurfacePoint p = SphereField::closest(x);
    if (x.z > 0.5) p.point = glm::dvec3(std::nan(""));
    return p;
  }
};

TEST(Mesher, NanClosestPointLeavesATriangleUnbounded) {
  const NanClosestField f({{0, 0, 0}, 2.0});
  const glm::dvec3 a = glm::normalize(glm::dvec3(0.2, 0.0, 1.0)) * 2.0, b = glm::normalize(glm::dvec3(0.0, 0.2, 1.0)) * 2.0,
                   c = glm::normalize(glm::dvec3(-0.2, -0.2, 1.0)) * 2.0;
  EXPECT_EQ(certifiedDeviation(f, a, b, c, 0.05), std::numeric_limits<double>::infinity());
  // Below z = 0.5 the same triangle shape has its finite bound.
  const glm::dvec3 a2(a.x, a.z, -a.y), b2(b.x, b.z, -b.y), c2(c.x, c.z, -c.y);
  EXPECT_LT(certifiedDeviation(f, a2, b2, c2, 0.05), 0.1);
}

// --- Files --------------------------------------------------------------------------------

TriangleMesh smallMesh() {
  const CavityField f({{1, 2, 3}, 2.0}, {{1.2, 2.1, 3.0}, 0.8});
  return meshOf(f, {glm::dvec3(3, 2, 3), glm::dvec3(2.0, 2.1, 3.0)}, 0.1, 0.35).mesh;
}

// Assimp's view of a file: one mesh, its positions and normals, with nothing merged or
// reordered (no post-processing asked for).
const aiMesh* importOne(Assimp::Importer& importer, const std::string& path) {
  const aiScene* scene = importer.ReadFile(path, 0);
  EXPECT_NE(scene, nullptr) << importer.GetErrorString();
  if (!scene) return nullptr;
  EXPECT_EQ(scene->mNumMeshes, 1u);
  return scene->mNumMeshes ? scene->mMeshes[0] : nullptr;
}

void expectSameGeometry(const TriangleMesh& m, const aiMesh* a, double tolerance) {
  ASSERT_NE(a, nullptr);
  ASSERT_EQ(a->mNumFaces, m.triangles.size());
  ASSERT_TRUE(a->HasNormals());
  // Importers may duplicate vertices per face (OBJ): compare face by face.
  for (unsigned t = 0; t < a->mNumFaces; ++t) {
    ASSERT_EQ(a->mFaces[t].mNumIndices, 3u);
    for (int k = 0; k < 3; ++k) {
      const unsigned i = a->mFaces[t].mIndices[k];
      const glm::dvec3 p = m.positions[m.triangles[t][k]], n = m.normals[m.triangles[t][k]];
      ASSERT_NEAR(a->mVertices[i].x, p.x, tolerance);
      ASSERT_NEAR(a->mVertices[i].y, p.y, tolerance);
      ASSERT_NEAR(a->mVertices[i].z, p.z, tolerance);
      ASSERT_NEAR(a->mNormals[i].x, n.x, 1e-6);
      ASSERT_NEAR(a->mNormals[i].z, n.z, 1e-6);
    }
  }
}

TEST(MeshWriter, ObjAndGlbReadBackWithAssimp) {
  const TriangleMesh m = smallMesh();
  const std::filesystem::path dir = test::freshTempDir("mesh_writer");
  for (const char* name : {"m.obj", "m.glb", "m.ply"}) {
    SCOPED_TRACE(name);
    const std::string path = (dir / name).string();
    writeMesh(path, m);
    Assimp::Importer importer;
    // Positions are float in Assimp (and in glTF): within float rounding at these coordinates.
    expectSameGeometry(m, importOne(importer, path), 2e-6);
  }
}

// PLY's own properties, read here from the bytes the header announces (Assimp drops them).
TEST(MeshWriter, PlyCarriesAtomKindAndComponent) {
  const TriangleMesh m = smallMesh();
  const std::string bytes = meshFileBytes(m, MeshFormat::Ply);
  const std::string header =
      "ply\nformat binary_little_endian 1.0\ncomment surftrace mesh of an exact surface (Å)\nelement vertex " +
      std::to_string(m.positions.size()) +
      "\nproperty double x\nproperty double y\nproperty double z\nproperty float nx\nproperty float ny\nproperty float "
      "nz\nproperty uint atom_id\nproperty uchar patch_kind\nproperty uint component\nelement face " +
      std::to_string(m.triangles.size()) + "\nproperty list uchar uint vertex_indices\nend_header\n";
  ASSERT_EQ(bytes.substr(0, header.size()), header);
  const std::size_t record = 3 * 8 + 3 * 4 + 4 + 1 + 4;
  ASSERT_EQ(bytes.size(), header.size() + record * m.positions.size() + 13 * m.triangles.size());
  std::size_t cavity = 0;
  for (std::size_t v = 0; v < m.positions.size(); ++v) {
    const char* at = bytes.data() + header.size() + record * v;
    double x;
    std::uint32_t atom, component;
    std::uint8_t kind;
    std::memcpy(&x, at, 8);
    std::memcpy(&atom, at + 36, 4);
    std::memcpy(&kind, at + 40, 1);
    std::memcpy(&component, at + 41, 4);
    ASSERT_EQ(x, m.positions[v].x);  // doubles: exact
    ASSERT_EQ(kind, component == 1 ? 3u : 0u);
    ASSERT_EQ(atom, 0u);
    cavity += component == 1;
  }
  EXPECT_GT(cavity, 0u);
  EXPECT_LT(cavity, m.positions.size());
}

TEST(MeshWriter, UnknownExtensionIsNamed) {
  try {
    (void)meshFormatOf("out.stl");
    FAIL();
  } catch (const std::invalid_argument& e) {
    EXPECT_NE(std::string(e.what()).find("out.stl"), std::string::npos);
    EXPECT_NE(std::string(e.what()).find(".ply"), std::string::npos);
  }
}

}  // namespace
}  // namespace surftrace::build::mesh

// The surface distance fields (build/mesh/surface_distance.hpp) against closed forms, the
// Embree scene of the trace module (an independent intersector), the SES membership oracle,
// the skin certificate and brute-force unions of balls.
#include "build/mesh/surface_distance.hpp"

#include <algorithm>
#include <cmath>
#include <limits>
#include <numbers>
#include <random>
#include <string>
#include <vector>

#include <glm/geometric.hpp>
#include <gtest/gtest.h>

#include "build/atom_spheres.hpp"
#include "build/io/molecule.hpp"
#include "build/mss/mss_builder.hpp"
#include "build/ses/contour_buildup.hpp"
#include "oracles/ses_oracle.hpp"
#include "oracles/skin_certificate.hpp"
#include "trace/patch_scene.hpp"

namespace surftrace {
namespace {

using build::PatchList;
using build::mesh::makeSurfaceDistance;
using build::mesh::SurfaceDistance;
using build::mesh::SurfacePoint;

constexpr double kExact = 1e-9;  // Å: closed forms against the field

glm::dvec3 randomDirection(std::mt19937_64& rng) {
  std::normal_distribution<double> n(0.0, 1.0);
  glm::dvec3 d;
  do d = {n(rng), n(rng), n(rng)};
  while (glm::length(d) < 1e-3);
  return glm::normalize(d);
}

build::Molecule molecule(const std::string& file) {
  return build::readMolecule(std::string(SURFTRACE_TEST_DATA) + "/" + file);
}

// ---------------------------------------------------------------------------------------------
// Closed forms.

TEST(SurfaceDistance, SingleAtomIsASphereForEverySurface) {
  const std::vector<glm::dvec3> c{{0.5, -1.0, 2.0}};
  const std::vector<double> r{1.7};
  const double rp = 1.4;
  struct Case {
    PatchList list;
    double radius;
  };
  std::vector<Case> cases;
  cases.push_back({build::buildSes(c, r, {rp}), r[0]});
  cases.push_back({build::atomSpheres(c, r, rp, build::SurfaceKind::Sas), r[0] + rp});
  cases.push_back({build::atomSpheres(c, r, 0.0, build::SurfaceKind::Vdw), r[0]});
  cases.push_back({build::buildMss(c, r, {0.5}), r[0]});
  std::mt19937_64 rng(1);
  std::uniform_real_distribution<double> radial(0.05, 6.0);
  for (const Case& k : cases) {
    const auto field = makeSurfaceDistance(k.list, c, r);
    for (int i = 0; i < 200; ++i) {
      const glm::dvec3 u = randomDirection(rng);
      const double rho = radial(rng);
      const glm::dvec3 x = c[0] + rho * u;
      EXPECT_NEAR(field->signedDistance(x), rho - k.radius, kExact) << "surface " << int(k.list.params.surface) << " trial " << i;
      const SurfacePoint s = field->closest(x);
      EXPECT_NEAR(glm::length(s.point - (c[0] + k.radius * u)), 0.0, kExact) << "trial " << i;
      EXPECT_NEAR(glm::length(s.normal - u), 0.0, 1e-9) << "trial " << i;
      EXPECT_EQ(s.atom, 0u);
      EXPECT_EQ(s.kind, k.list.params.surface == build::SurfaceKind::Mss ? 4 : 1);
    }
  }
}

// Two atoms: points on the normals of the saddle torus (ORACLES A.3), written out by hand.
TEST(SurfaceDistance, TwoAtomsSaddleIsTheTorusByHand) {
  const double r = 1.6, rp = 1.4, d = 4.0;
  const std::vector<glm::dvec3> c{{-d / 2, 0, 0}, {d / 2, 0, 0}};
  const std::vector<double> radii{r, r};
  const PatchList list = build::buildSes(c, radii, {rp});
  const auto field = makeSurfaceDistance(list, c, radii);
  // The probe circle: plane x = 0, radius R; the contact circles at θ = ±atan2(d/2, R).
  const double R = std::sqrt((r + rp) * (r + rp) - d * d / 4);
  const double thetaLimit = std::atan2(d / 2, R);
  std::mt19937_64 rng(2);
  std::uniform_real_distribution<double> unit(0.0, 1.0);
  for (int i = 0; i < 500; ++i) {
    const double phi = 2 * M_PI * unit(rng);
    const double theta = (2 * unit(rng) - 1) * thetaLimit * 0.999;
    // > 0: inside the body, up to where x would cross the axis (nearer the circle's far side).
    const double delta = -0.9 * rp + unit(rng) * 0.9 * (rp + (R - rp));
    const glm::dvec3 eRho(0, std::cos(phi), std::sin(phi)), n(1, 0, 0);
    const glm::dvec3 P = R * eRho;
    const glm::dvec3 m = -std::cos(theta) * eRho + std::sin(theta) * n;  // probe → surface
    const glm::dvec3 x = P + (rp + delta) * m;
    EXPECT_NEAR(field->signedDistance(x), -delta, kExact) << "trial " << i;
    const SurfacePoint s = field->closest(x);
    EXPECT_NEAR(glm::length(s.point - (P + rp * m)), 0.0, kExact) << "trial " << i;
    EXPECT_NEAR(glm::length(s.normal + m), 0.0, 1e-9) << "trial " << i;
    EXPECT_EQ(s.kind, 2) << "trial " << i;
    EXPECT_EQ(s.atom, theta < 0 ? 0u : 1u) << "trial " << i;  // the nearer contact circle
  }
  // Beyond the SAS (x = 0 plane, outside the probe circle): the convex patches are nearest.
  for (int i = 0; i < 100; ++i) {
    const glm::dvec3 x = c[1] + (r + rp + 0.01 + 3 * unit(rng)) * glm::normalize(glm::dvec3(1, unit(rng), unit(rng)));
    EXPECT_NEAR(field->signedDistance(x), glm::length(x - c[1]) - r, kExact) << "trial " << i;
  }
}

// Three atoms: points on the normals of a concave triangle, from the probe position by hand.
TEST(SurfaceDistance, ThreeAtomsConcaveTriangleIsTheProbeSphereByHand) {
  const double r = 1.5, rp = 1.4, side = 3.6;
  const double circum = side / std::sqrt(3.0);
  std::vector<glm::dvec3> c;
  for (int k = 0; k < 3; ++k) c.push_back(circum * glm::dvec3(std::cos(2 * M_PI * k / 3), std::sin(2 * M_PI * k / 3), 0));
  const std::vector<double> radii{r, r, r};
  const PatchList list = build::buildSes(c, radii, {rp});
  ASSERT_EQ(list.concave.size(), 2u);
  const auto field = makeSurfaceDistance(list, c, radii);
  const double h = std::sqrt((r + rp) * (r + rp) - circum * circum);
  std::mt19937_64 rng(3);
  std::uniform_real_distribution<double> unit(0.0, 1.0);
  for (int i = 0; i < 400; ++i) {
    const glm::dvec3 p(0, 0, i % 2 ? h : -h);
    // A direction inside the cone of the contact directions: a positive mix of them.
    glm::dvec3 u(0.0);
    for (int k = 0; k < 3; ++k) u += (0.2 + unit(rng)) * glm::normalize(c[k] - p);
    u = glm::normalize(u);
    // Up to before the atoms' plane, beyond which the twin probe is nearer.
    const double delta = -0.9 * rp + unit(rng) * (0.9 * rp + 0.5 * (h - rp));
    const glm::dvec3 x = p + (rp + delta) * u;
    EXPECT_NEAR(field->signedDistance(x), -delta, kExact) << "trial " << i;
    const SurfacePoint s = field->closest(x);
    EXPECT_NEAR(glm::length(s.point - (p + rp * u)), 0.0, kExact) << "trial " << i;
    EXPECT_NEAR(glm::length(s.normal + u), 0.0, 1e-9) << "trial " << i;
    EXPECT_EQ(s.kind, 3) << "trial " << i;
    // The nearest contact direction's atom.
    std::uint32_t nearest = 0;
    for (std::uint32_t k = 1; k < 3; ++k)
      if (glm::dot(u, glm::normalize(c[k] - p)) > glm::dot(u, glm::normalize(c[nearest] - p))) nearest = k;
    EXPECT_EQ(s.atom, nearest) << "trial " << i;
  }
}

// Three atoms whose two probe positions p± are closer than 2 rp: their spheres cut each other
// at the atoms' plane, and the SES has a ridge there (the circle of radius √(rp² − h²)).
// Points between the probes whose normal from p+ lands beyond the plane are nearest to it.
TEST(SurfaceDistance, TwinProbesRidgeIsTheirSpheresCircle) {
  const double r = 1.5, rp = 1.4, circum = 2.6;
  std::vector<glm::dvec3> c;
  for (int k = 0; k < 3; ++k) c.push_back(circum * glm::dvec3(std::cos(2 * M_PI * k / 3), std::sin(2 * M_PI * k / 3), 0));
  const std::vector<double> radii{r, r, r};
  const PatchList list = build::buildSes(c, radii, {rp});
  const auto field = makeSurfaceDistance(list, c, radii);
  const double h = std::sqrt((r + rp) * (r + rp) - circum * circum);
  ASSERT_LT(h, rp);
  const double ring = std::sqrt(rp * rp - h * h);
  std::mt19937_64 rng(4);
  std::uniform_real_distribution<double> unit(0.0, 1.0);
  for (int i = 0; i < 200; ++i) {
    const double phi = 2 * M_PI * unit(rng), rho = 0.05 + 0.4 * unit(rng), z = 0.02 + 0.1 * unit(rng);
    const glm::dvec3 x(rho * std::cos(phi), rho * std::sin(phi), z);
    const glm::dvec3 ridge(ring * std::cos(phi), ring * std::sin(phi), 0.0);
    EXPECT_NEAR(field->signedDistance(x), glm::length(x - ridge), kExact) << "trial " << i;
    const SurfacePoint s = field->closest(x);
    EXPECT_NEAR(glm::length(s.point - ridge), 0.0, kExact) << "trial " << i;
    EXPECT_EQ(s.kind, 3) << "trial " << i;
  }
}

TEST(SurfaceDistance, WrongAtomCountIsRefused) {
  const std::vector<glm::dvec3> c{{0, 0, 0}};
  const std::vector<double> r{1.5};
  const PatchList list = build::buildSes(c, r, {1.4});
  const std::vector<glm::dvec3> two{{0, 0, 0}, {1, 0, 0}};
  const std::vector<double> radii2{1.5, 1.5};
  EXPECT_THROW(makeSurfaceDistance(list, two, radii2), std::invalid_argument);
}

// ---------------------------------------------------------------------------------------------
// Real molecules against the trace module's Embree scene and the membership oracles.

// Random points with |signedDistance| below `band`, spread over the surface's box.
std::vector<glm::dvec3> pointsNearSurface(const SurfaceDistance& f, double band, int count, std::uint64_t seed) {
  std::mt19937_64 rng(seed);
  const glm::dvec3 lo = f.boundsMin(), hi = f.boundsMax();
  std::uniform_real_distribution<double> ux(lo.x, hi.x), uy(lo.y, hi.y), uz(lo.z, hi.z);
  std::vector<glm::dvec3> out;
  while (static_cast<int>(out.size()) < count) {
    const glm::dvec3 x(ux(rng), uy(rng), uz(rng));
    if (std::abs(f.signedDistance(x)) < band) out.push_back(x);
  }
  return out;
}

// The nearest crossing of the ray x + t d (t > 0) with the surface drawn by the scene (the
// whole spheres' hidden parts left out).
double firstHit(const trace::PatchScene& scene, const glm::dvec3& x, const glm::dvec3& d) {
  const std::vector<trace::SceneHit> layers = scene.intersectLayers1(trace::Ray{x, d}, 1);
  return layers.empty() ? std::numeric_limits<double>::infinity() : layers[0].hit.t;
}

struct RealCase {
  const char* name;
  double band;
};

// (a) the closest point is where a ray from x towards it first meets the surface, and no
// crossing is nearer in 200 other directions (c); the point's distance is |signedDistance|.
void checkAgainstScene(const SurfaceDistance& field, const trace::PatchScene& scene,
                       const std::vector<glm::dvec3>& points, bool exactMagnitude, int& unsure) {
  std::mt19937_64 rng(7);
  std::vector<glm::dvec3> dirs;
  for (int k = 0; k < 200; ++k) dirs.push_back(randomDirection(rng));
  for (std::size_t i = 0; i < points.size(); ++i) {
    const glm::dvec3 x = points[i];
    const double sd = field.signedDistance(x);
    const SurfacePoint s = field.closest(x);
    const double dist = glm::length(s.point - x);
    // The skin's value is the distance within the reach, an estimate of it beyond.
    if (exactMagnitude || std::abs(sd) <= field.reach()) {
      EXPECT_NEAR(dist, std::abs(sd), 1e-9) << "point " << i;
    }
    EXPECT_NEAR(glm::length(s.normal), 1.0, 1e-12);
    if (dist < 1e-6) continue;
    const glm::dvec3 toward = (s.point - x) / dist;
    const double t = firstHit(scene, x, toward);
    // A ray grazing the surface at its nearest point may miss it by rounding: count, not fail.
    if (!std::isfinite(t)) {
      ++unsure;
      continue;
    }
    EXPECT_NEAR(t, dist, 1e-7) << "point " << i << " kind " << int(s.kind) << " sd " << sd << " x " << x.x << " " << x.y << " " << x.z;
    for (std::size_t k = 0; k < dirs.size(); ++k)
      EXPECT_GE(firstHit(scene, x, dirs[k]), dist * (1 - 1e-9) - 1e-9) << "point " << i << " direction " << k;
    // The outward normal points from the body into the solvent.
    if (sd > 1e-6) {
      EXPECT_GT(glm::dot(s.normal, x - s.point), 0.0) << "point " << i;
    }
    if (sd < -1e-6) {
      EXPECT_LT(glm::dot(s.normal, x - s.point), 0.0) << "point " << i;
    }
  }
}

TEST(SurfaceDistance, CrambinSesAgreesWithEmbreeAndTheSesOracle) {
  const build::Molecule m = molecule("structures/1crn.pdb");
  const double rp = 1.4;
  const PatchList list = build::buildSes(m.centers, m.radii, {rp});
  const auto field = makeSurfaceDistance(list, m.centers, m.radii);
  const trace::PatchScene scene(trace::ScenePatches::fromPatchList(list, m.centers, m.radii));
  std::vector<oracle::Sphere> atoms;
  for (std::size_t k = 0; k < m.size(); ++k) atoms.push_back({m.centers[k], m.radii[k]});
  const oracle::SesOracle ses(atoms, rp);
  const std::vector<glm::dvec3> points = pointsNearSurface(*field, 1.2, 400, 11);
  int unsure = 0;
  checkAgainstScene(*field, scene, points, true, unsure);
  EXPECT_LE(unsure, 4);
  for (std::size_t i = 0; i < points.size(); ++i) {
    const double sd = field->signedDistance(points[i]);
    const oracle::SesOracle::Result o = ses.distanceToAccessible(points[i]);
    // The oracle's dist(x, A) gives the distance to the SES exactly on the body side.
    if (o.kind != oracle::SesOracle::Result::Far && o.dist >= rp) {
      EXPECT_NEAR(sd, rp - o.dist, 1e-9) << "point " << i;
    }
    if (std::abs(sd) > 1e-9) {
      EXPECT_EQ(sd < 0, ses.insideSesBody(points[i])) << "point " << i << " sd " << sd;
    }
  }
}

TEST(SurfaceDistance, SkinOf1grmAgreesWithEmbreeAndTheSkinCertificate) {
  const build::Molecule m = molecule("paper/1grm.pdb.gz");
  const double s = 0.5;
  const PatchList list = build::buildMss(m.centers, m.radii, {s});
  const auto field = makeSurfaceDistance(list, m.centers, m.radii);
  const trace::PatchScene scene(trace::ScenePatches::fromPatchList(list));
  const std::vector<glm::dvec3> points = pointsNearSurface(*field, 1.0, 300, 12);
  int unsure = 0;
  checkAgainstScene(*field, scene, points, false, unsure);
  EXPECT_LE(unsure, 3);
  for (std::size_t i = 0; i < points.size(); ++i) {
    const double sd = field->signedDistance(points[i]);
    const int sign = oracle::skinSign(m.centers, m.radii, s, points[i]);
    if (sign != 0 && std::abs(sd) > 1e-9) {
      EXPECT_EQ(sd < 0 ? -1 : 1, sign) << "point " << i << " sd " << sd;
    }
    // The closest point's simplex is certified by the skin function, and G vanishes there.
    const SurfacePoint p = field->closest(points[i]);
    EXPECT_EQ(oracle::skinSign(m.centers, m.radii, s, p.point + 1e-6 * p.normal), 1) << "point " << i;
    EXPECT_EQ(oracle::skinSign(m.centers, m.radii, s, p.point - 1e-6 * p.normal), -1) << "point " << i;
    EXPECT_GE(p.kind, 4);
    EXPECT_LE(p.kind, 7);
  }
}

// ---------------------------------------------------------------------------------------------
// SAS and vdW against a brute-force union of balls.

void checkUnionOfBalls(build::SurfaceKind kind) {
  const build::Molecule m = molecule("structures/1crn.pdb");
  const double inflate = kind == build::SurfaceKind::Sas ? 1.4 : 0.0;
  const PatchList list = build::atomSpheres(m.centers, m.radii, inflate, kind);
  const auto field = makeSurfaceDistance(list, m.centers, m.radii);
  const std::size_t n = m.size();
  std::vector<double> R(n);
  for (std::size_t k = 0; k < n; ++k) R[k] = m.radii[k] + inflate;
  // Dense samples of every sphere (a Fibonacci lattice) that lie in no other ball: the boundary,
  // kept per sphere so that a query looks only at the spheres that pass near it.
  constexpr int kSamples = 20000;
  std::vector<std::vector<glm::dvec3>> boundary(n);
  double gap = 0.0;  // an upper bound on how far a boundary point is from its nearest sample
  for (std::size_t k = 0; k < n; ++k) {
    gap = std::max(gap, 2.0 * R[k] * std::sqrt(4.0 * M_PI / kSamples));
    std::vector<std::size_t> overlapping;
    for (std::size_t o = 0; o < n; ++o)
      if (o != k && glm::length(m.centers[o] - m.centers[k]) < R[o] + R[k]) overlapping.push_back(o);
    for (int i = 0; i < kSamples; ++i) {
      const double z = 1.0 - (2.0 * i + 1.0) / kSamples, rho = std::sqrt(1.0 - z * z);
      const double phi = i * M_PI * (3.0 - std::sqrt(5.0));
      const glm::dvec3 y = m.centers[k] + R[k] * glm::dvec3(rho * std::cos(phi), rho * std::sin(phi), z);
      bool covered = false;
      for (std::size_t o : overlapping) covered = covered || glm::length(y - m.centers[o]) < R[o];
      if (!covered) boundary[k].push_back(y);
    }
  }
  const std::vector<glm::dvec3> points = pointsNearSurface(*field, 1.5, 300, 13);
  for (std::size_t i = 0; i < points.size(); ++i) {
    const glm::dvec3 x = points[i];
    const double sd = field->signedDistance(x);
    double outside = std::numeric_limits<double>::infinity();
    for (std::size_t k = 0; k < n; ++k) outside = std::min(outside, glm::length(x - m.centers[k]) - R[k]);
    const SurfacePoint s = field->closest(x);
    EXPECT_NEAR(glm::length(s.point - x), std::abs(sd), 1e-9) << "point " << i;
    // The closest point is on the boundary: on a sphere, in no other ball.
    double onSphere = std::numeric_limits<double>::infinity(), inside = 0.0;
    for (std::size_t k = 0; k < n; ++k) {
      const double e = glm::length(s.point - m.centers[k]) - R[k];
      onSphere = std::min(onSphere, std::abs(e));
      inside = std::min(inside, e);
    }
    EXPECT_LT(onSphere, 1e-9) << "point " << i;
    EXPECT_GT(inside, -1e-9) << "point " << i;
    if (outside >= 0.0) {
      EXPECT_NEAR(sd, outside, 1e-9) << "point " << i;
      continue;
    }
    // A sample of sphere k is at least ||x − c_k| − R_k| from x.
    double sampled = std::numeric_limits<double>::infinity();
    for (std::size_t k = 0; k < n; ++k)
      if (std::abs(glm::length(x - m.centers[k]) - R[k]) < sampled)
        for (const glm::dvec3& y : boundary[k]) sampled = std::min(sampled, glm::length(y - x));
    EXPECT_LT(sd, 0.0) << "point " << i;
    EXPECT_LE(-sd, sampled + 1e-9) << "point " << i;
    EXPECT_GE(-sd, sampled - gap) << "point " << i;
  }
}

TEST(SurfaceDistance, CrambinSasIsTheUnionOfBallsBruteForce) { checkUnionOfBalls(build::SurfaceKind::Sas); }
TEST(SurfaceDistance, CrambinVdwIsTheUnionOfBallsBruteForce) { checkUnionOfBalls(build::SurfaceKind::Vdw); }

// ---------------------------------------------------------------------------------------------
// The patch bound that the mesher certifies triangles with (patchDeviation) against a dense
// sampling oracle: on random triangles with their corners on crambin's SES, on one sphere,
// concave triangle or torus, or across a seam of a torus with a sphere or a concave triangle
// (random sizes up to 0.6 Å,
// random shapes), the bound is at least the
// largest |dist(p, A) − rp| over ~500 points p of the triangle, which is a lower bound of
// dist(p, SES) (dist(·, A) is 1-Lipschitz and rp on the SES; the independent SES oracle gives it).
// And off seams it is tight where it has a closed form: on spheres within 1e-3 Å of the sampled maximum (the samples' spacing),
// on tori within a factor 10 (their Hessian bound takes the largest curvature in every direction).
TEST(SurfaceDistance, PatchDeviationBoundsTheSampledDeviationOfTriangles) {
  const build::Molecule m = molecule("structures/1crn.pdb");
  const double rp = 1.4;
  const PatchList list = build::buildSes(m.centers, m.radii, {rp});
  const auto field = makeSurfaceDistance(list, m.centers, m.radii);
  std::vector<oracle::Sphere> atoms;
  for (std::size_t k = 0; k < m.size(); ++k) atoms.push_back({m.centers[k], m.radii[k]});
  const oracle::SesOracle ses(atoms, rp);
  std::mt19937_64 rng(23);
  std::uniform_real_distribution<double> size(0.02, 0.6), unit(0.0, 1.0);
  const std::vector<glm::dvec3> centres = pointsNearSurface(*field, 0.5, 700, 29);
  int bounded[5] = {0, 0, 0, 0, 0};
  for (std::size_t i = 0; i < centres.size(); ++i) {
    const SurfacePoint s = field->closest(centres[i]);
    // Three corners around s in its tangent plane, projected onto the surface.
    const glm::dvec3 t1 = glm::normalize(glm::cross(s.normal, randomDirection(rng)));
    const glm::dvec3 t2 = glm::cross(s.normal, t1);
    const double r = size(rng);
    glm::dvec3 v[3];
    int kinds = 0;  // bits 1 << kind of the corners
    for (int k = 0; k < 3; ++k) {
      const double angle = 2.0 * std::numbers::pi * (k + 0.6 * unit(rng)) / 3.0;
      const SurfacePoint corner = field->closest(s.point + r * (std::cos(angle) * t1 + std::sin(angle) * t2));
      v[k] = corner.point;
      kinds |= 1 << corner.kind;
    }
    const bool seam = kinds != 1 << s.kind;
    const double bound = field->patchDeviation(v[0], v[1], v[2]);
    if (!std::isfinite(bound)) continue;
    ASSERT_LT(s.kind, 4);
    ASSERT_TRUE(kinds == 2 || kinds == 4 || kinds == 8 || kinds == 6 || kinds == 12) << "corner kinds " << kinds;
    ++bounded[kinds == 6 ? 0 : kinds == 12 ? 4 : s.kind];
    double sampled = 0.0;
    constexpr int n = 30;
    for (int a = 0; a <= n; ++a)
      for (int b = 0; a + b <= n; ++b) {
        const glm::dvec3 p = (double(a) * v[0] + double(b) * v[1] + double(n - a - b) * v[2]) / double(n);
        const oracle::SesOracle::Result o = ses.distanceToAccessible(p);
        ASSERT_NE(o.kind, oracle::SesOracle::Result::Far);
        sampled = std::max(sampled, std::abs(o.dist - rp));
      }
    EXPECT_GE(bound, sampled) << "triangle " << i << " kind " << int(s.kind) << " size " << r;
    if (!seam) {
      EXPECT_LE(bound, s.kind == 2 ? 10.0 * sampled + 1e-6 : sampled + 1e-3)
          << "triangle " << i << " kind " << int(s.kind) << " size " << r;
    }
  }
  // bounded[0]: seams of a sphere and its torus; bounded[4]: of a concave triangle and a torus.
  for (int kind = 0; kind <= 4; ++kind) EXPECT_GT(bounded[kind], 30) << "kind " << kind;
}

}  // namespace
}  // namespace surftrace

// What the exact tracer records for compare's masks (trace/reference_masks.hpp): each patch
// kind's distance to its edges against the edges sampled densely, and the pixel edge flags
// against supersampled pixels.
#include <algorithm>
#include <cmath>
#include <cstdio>
#include <limits>
#include <numbers>
#include <random>
#include <set>
#include <vector>

#include <glm/geometric.hpp>
#include <gtest/gtest.h>

#include "build/core/vector_math.hpp"
#include "build/ses/contour_buildup.hpp"
#include "build/sphere_blockers.hpp"
#include "random_geometry.hpp"
#include "trace/concave_patch.hpp"
#include "trace/mss_patch.hpp"
#include "trace/reference_masks.hpp"
#include "trace/render.hpp"
#include "trace/torus_patch.hpp"

namespace surftrace::trace {
namespace {

using testing_random::randomUnit;
using testing_random::uniform;
constexpr double kPi = std::numbers::pi;
constexpr int kTrials = 200;

// The distance from x to a curve c(s), s in [lo, hi]: dense samples, then a ternary search
// around the best one (the oracle: slow and obviously right).
template <class Curve> double sampledDistance(const glm::dvec3& x, Curve curve, double lo, double hi) {
  constexpr int kSamples = 4000;
  double best = std::numeric_limits<double>::infinity(), at = lo;
  for (int i = 0; i <= kSamples; ++i) {
    const double s = lo + (hi - lo) * i / kSamples;
    const double d = glm::length(curve(s) - x);
    if (d < best) best = d, at = s;
  }
  double a = std::max(lo, at - (hi - lo) / kSamples), b = std::min(hi, at + (hi - lo) / kSamples);
  for (int k = 0; k < 200; ++k) {
    const double m1 = a + (b - a) / 3, m2 = b - (b - a) / 3;
    if (glm::length(curve(m1) - x) < glm::length(curve(m2) - x)) b = m2;
    else a = m1;
  }
  return std::min(best, glm::length(curve(0.5 * (a + b)) - x));
}

// The whole circle (centre, unit normal, radius).
double circleDistance(const glm::dvec3& x, const glm::dvec3& centre, const glm::dvec3& normal, double radius) {
  const glm::dvec3 u = build::perpendicularTo(normal), v = glm::cross(normal, u);
  return sampledDistance(x, [&](double phi) { return centre + radius * (std::cos(phi) * u + std::sin(phi) * v); }, 0.0, 2.0 * kPi);
}

// The circle in which the plane n·y + w = 0 cuts the sphere (c, r); +inf when it misses.
double planeCircleDistance(const glm::dvec3& x, const glm::dvec3& c, double r, const glm::dvec3& n, double w) {
  const double e = glm::dot(n, c) + w;
  if (!(std::abs(e) < r)) return std::numeric_limits<double>::infinity();
  return circleDistance(x, c - e * n, n, std::sqrt(r * r - e * e));
}

constexpr double kSampleTolerance = 1e-9;  // the ternary search converges far below this

// A distance against its oracle: equal within `tolerance`, or both +inf (no edge at all).
void expectDistance(double got, double want, double tolerance, int trial) {
  if (std::isinf(want)) EXPECT_EQ(got, want) << "trial " << trial;
  else EXPECT_NEAR(got, want, tolerance) << "trial " << trial;
}

TEST(SeamDistance, SphereCircleMatchesTheSampledCircle) {
  for (int i = 0; i < kTrials; ++i) {
    std::mt19937_64 rng(i);
    const glm::dvec3 c(uniform(rng, -50, 50), uniform(rng, -50, 50), uniform(rng, -50, 50));
    const double r = uniform(rng, 0.3, 4.0);
    const glm::dvec3 n = randomUnit(rng), x = c + r * randomUnit(rng);
    const double h = uniform(rng, -0.99, 0.99);
    const double got = build::distanceToSphereCircle(c, r, x, n, h);
    expectDistance(got, planeCircleDistance(x, c, r, n, -glm::dot(n, c) - h * r), kSampleTolerance * (1 + r), i);
  }
  EXPECT_EQ(build::distanceToSphereCircle({0, 0, 0}, 1.0, {1, 0, 0}, {0, 0, 1}, 1.0), std::numeric_limits<double>::infinity());
}

// A point of the torus patch at (θ, φ), and the patch's edges (ORACLES A.3).
glm::dvec3 torusPoint(const TorusPatch& p, double theta, double phi) {
  return p.center + (p.bigRadius - p.probeRadius * std::cos(theta)) * (std::cos(phi) * p.e1 + std::sin(phi) * p.e2) +
         p.probeRadius * std::sin(theta) * p.axis;
}

TEST(SeamDistance, TorusIsTheDistanceToItsWholeEdgeCircles) {
  int partial = 0, spindle = 0;
  for (int i = 0; i < kTrials; ++i) {
    std::mt19937_64 rng(i);
    const double rp = uniform(rng, 0.8, 2.0);
    const bool isSpindle = i % 4 == 3;
    const double R = isSpindle ? uniform(rng, 0.3, 0.9) * rp : uniform(rng, 1.05, 4.0) * rp;
    // On a spindle the patch is the apple: cos θ <= R/rp, here on the side θ > 0.
    const double lowest = isSpindle ? std::acos(R / rp) + 0.01 : -1.3, highest = isSpindle ? 0.5 * kPi - 0.06 : 1.2;
    double thetaI = uniform(rng, lowest, highest), thetaJ = uniform(rng, lowest, highest);
    if (thetaI > thetaJ) std::swap(thetaI, thetaJ);
    if (thetaJ - thetaI < 0.05) thetaJ = thetaI + 0.05;
    const double phiExtent = i % 2 == 0 ? 2.0 * kPi : uniform(rng, 0.3, 6.0);
    const glm::dvec3 axis = randomUnit(rng), e1 = build::perpendicularTo(axis);
    const glm::dvec3 center(uniform(rng, -30, 30), uniform(rng, -30, 30), uniform(rng, -30, 30));
    const TorusPatch p = makeTorusPatch(center, axis, e1, R, rp, thetaI, thetaJ, phiExtent);
    const double theta = uniform(rng, thetaI, thetaJ), phi = uniform(rng, 0.0, phiExtent);
    const glm::dvec3 x = torusPoint(p, theta, phi);
    ASSERT_TRUE(insidePatch(p, x, 1e-9)) << "trial " << i;
    // The oracle: the whole contact circles, the whole tube circles at the φ limits, the cusps.
    const auto tubeCircle = [&](double phiEnd) {
      return sampledDistance(x, [&](double t) { return torusPoint(p, t, phiEnd); }, -kPi, kPi);
    };
    double want = std::numeric_limits<double>::infinity();
    for (const double limit : {thetaI, thetaJ})
      want = std::min(want, circleDistance(x, center + rp * std::sin(limit) * axis, axis, R - rp * std::cos(limit)));
    if (phiExtent < 2.0 * kPi) want = std::min({want, tubeCircle(0.0), tubeCircle(phiExtent)}), ++partial;
    if (R < rp) {
      const double h = std::sqrt(rp * rp - R * R);
      want = std::min({want, glm::length(x - center - h * axis), glm::length(x - center + h * axis)}), ++spindle;
    }
    expectDistance(boundaryDistance(p, x), want, 1e-8 * (R + rp), i);
    // And so no more than the distance to the patch's own edge arcs.
    double arcs = std::min(sampledDistance(x, [&](double f) { return torusPoint(p, thetaI, f); }, 0.0, phiExtent),
                           sampledDistance(x, [&](double f) { return torusPoint(p, thetaJ, f); }, 0.0, phiExtent));
    if (phiExtent < 2.0 * kPi)
      for (const double end : {0.0, phiExtent})
        arcs = std::min(arcs, sampledDistance(x, [&](double t) { return torusPoint(p, t, end); }, thetaI, thetaJ));
    EXPECT_LE(boundaryDistance(p, x), arcs + 1e-8 * (R + rp)) << "trial " << i;
  }
  EXPECT_GT(partial, kTrials / 3);
  EXPECT_GT(spindle, kTrials / 5);
}

TEST(SeamDistance, ConcaveTriangleIsTheDistanceToItsFaceAndClipCircles) {
  std::vector<build::Plane> planes(kTrials);
  for (int i = 0; i < kTrials; ++i) {
    std::mt19937_64 rng(i);
    ConcavePatch p;
    p.probe = glm::dvec3(uniform(rng, -30, 30), uniform(rng, -30, 30), uniform(rng, -30, 30));
    p.probeRadius = uniform(rng, 0.8, 2.0);
    const glm::dvec3 base = randomUnit(rng);
    p.dirI = glm::normalize(base + 0.6 * randomUnit(rng));
    p.dirJ = glm::normalize(base + 0.6 * randomUnit(rng));
    p.dirK = glm::normalize(base + 0.6 * randomUnit(rng));
    const glm::dvec3 u = glm::normalize(uniform(rng, 0.1, 1) * p.dirI + uniform(rng, 0.1, 1) * p.dirJ + uniform(rng, 0.1, 1) * p.dirK);
    const glm::dvec3 x = p.probe + p.probeRadius * u;
    // One clipping plane that keeps x: n·y + w <= 0 there.
    const glm::dvec3 n = randomUnit(rng);
    planes[i] = build::Plane(n, -glm::dot(n, x) - uniform(rng, 0.0, 0.5) * p.probeRadius);
    p.clipPlanes = {&planes[i], 1};
    double want = planeCircleDistance(x, p.probe, p.probeRadius, n, planes[i].w);
    for (const glm::dvec3& face : {glm::cross(p.dirI, p.dirJ), glm::cross(p.dirJ, p.dirK), glm::cross(p.dirK, p.dirI)})
      want = std::min(want, circleDistance(x, p.probe, glm::normalize(face), p.probeRadius));
    expectDistance(boundaryDistance(p, x), want, 1e-8 * p.probeRadius, i);
  }
}

TEST(SeamDistance, SkinSphereIsTheDistanceToItsCellPlanesCircles) {
  std::vector<build::Plane> planes(3 * kTrials);
  for (int i = 0; i < kTrials; ++i) {
    std::mt19937_64 rng(i);
    MssPatch p;
    p.kind = i % 2 == 0 ? build::MssKind::Convex : build::MssKind::Concave;
    p.center = glm::dvec3(uniform(rng, -30, 30), uniform(rng, -30, 30), uniform(rng, -30, 30));
    const double r = uniform(rng, 0.5, 2.5);
    p.radial = i % 2 == 0 ? 0.5 : -0.5;
    p.axial = 0.0;
    p.constant = -p.radial * r * r;
    p.boundRadius = 1.01 * r;
    const glm::dvec3 x = p.center + r * randomUnit(rng);
    double want = std::numeric_limits<double>::infinity();
    for (int k = 0; k < 3; ++k) {
      const glm::dvec3 n = randomUnit(rng);
      build::Plane& plane = planes[3 * i + k];
      plane = build::Plane(n, -glm::dot(n, x) - uniform(rng, 0.0, 0.8) * r);
      want = std::min(want, planeCircleDistance(x, p.center, r, n, plane.w));
    }
    p.cellPlanes = {&planes[3 * i], 3};
    ASSERT_TRUE(insideCell(p, x)) << "trial " << i;
    expectDistance(boundaryDistance(p, x), want, 1e-8 * r, i);
  }
}

TEST(SeamDistance, SkinHyperboloidIsAtMostItsDistanceToEachCellPlane) {
  // An edge hyperboloid of one sheet about z (s = 0.5: radial 0.5, axial −1, constant −0.5):
  // f = 0.5ρ² − 0.5z² − 0.5, so its points at height z have ρ² = 1 + z².
  build::Plane planes[2] = {build::Plane(0, 0, 1, -0.7), build::Plane(0.6, 0, 0.8, -1.5)};
  MssPatch p;
  p.kind = build::MssKind::Edge;
  p.radial = 0.5, p.axial = -1.0, p.constant = -0.5;
  p.boundRadius = 10.0;
  p.cellPlanes = planes;
  int inside = 0;
  for (int i = 0; i < kTrials; ++i) {
    std::mt19937_64 rng(i);
    const double z = uniform(rng, -0.5, 0.6), phi = uniform(rng, 0, 2 * kPi), rho = std::sqrt(1 + z * z);
    const glm::dvec3 x(rho * std::cos(phi), rho * std::sin(phi), z);
    if (!insideCell(p, x)) continue;
    ++inside;
    double want = std::numeric_limits<double>::infinity();
    for (const build::Plane& plane : planes) want = std::min(want, std::abs(glm::dot(glm::dvec3(plane), x) + plane.w));
    EXPECT_NEAR(boundaryDistance(p, x), want, 1e-12) << "trial " << i;
  }
  EXPECT_GT(inside, kTrials / 4);
}

TEST(SeamDistance, WholeSphereIsTheDistanceToTheContactCirclesOfItsBlockers) {
  for (int i = 0; i < kTrials; ++i) {
    std::mt19937_64 rng(i);
    build::SurfaceParams params;
    params.surface = i % 3 == 0 ? build::SurfaceKind::Vdw : build::SurfaceKind::Ses;
    params.probeRadius = 1.4;
    const double grow = params.surface == build::SurfaceKind::Ses ? 1.4 : 0.0;
    std::vector<glm::dvec3> centers{{0, 0, 0}};
    std::vector<double> radii{uniform(rng, 1.2, 2.0)};
    for (int k = 0; k < 3; ++k) {
      radii.push_back(uniform(rng, 1.2, 2.0));
      centers.push_back(uniform(rng, 0.5, 0.95) * (radii[0] + radii.back() + 2 * grow) * randomUnit(rng));
    }
    const std::vector<std::uint32_t> atoms{0, 1, 2, 3};
    const build::SphereBlockers blockers = build::sphereBlockers(params, centers, radii, atoms, {});
    // A point of sphere 0 on its patch, and each pair's circle mapped back to sphere 0.
    glm::dvec3 x;
    for (;;) {
      x = radii[0] * randomUnit(rng);
      if (build::onConvexPatch(blockers, 0, centers[0], radii[0], x, 0.0)) break;
    }
    double want = std::numeric_limits<double>::infinity();
    const double R0 = radii[0] + grow;
    for (int k = 1; k < 4; ++k) {
      const double D = glm::length(centers[k]), Rk = radii[k] + grow, a = (D * D + R0 * R0 - Rk * Rk) / (2 * D);
      if (!(std::abs(a) < R0)) continue;
      const glm::dvec3 axis = centers[k] / D;
      want = std::min(want, circleDistance(x, a * axis * (radii[0] / R0), axis, std::sqrt(R0 * R0 - a * a) * radii[0] / R0));
    }
    expectDistance(build::convexPatchEdgeDistance(blockers, 0, centers[0], radii[0], x), want, 1e-8 * R0, i);
  }
}

// Two balls (a vdW list): `front` is nearer the eye, which looks down −z.
build::PatchList twoBalls(const glm::dvec3& back, double backRadius, const glm::dvec3& front, double frontRadius) {
  build::PatchList list;
  list.params.surface = build::SurfaceKind::Vdw;
  list.params.atomCount = 2;
  list.convex.center = {back, front};
  list.convex.radius = {backRadius, frontRadius};
  list.convex.atom = {0, 1};
  list.convex.component = {0, 0};
  list.convex.area = {0, 0};
  list.convex.vectorArea = {glm::dvec3(0), glm::dvec3(0)};
  list.componentCount = 1;
  return list;
}

view::RenderOptions maskedView(int size) {
  view::RenderOptions o;
  o.camera.eye = {0, 0, 30};
  o.camera.lookAt = {0, 0, 0};
  o.camera.fovY = 20;
  o.camera.width = o.camera.height = size;
  o.referenceMasks = true;
  return o;
}

// Each pixel sampled on a 9×9 grid that holds its corners and its centre: what the rays say.
struct Supersample {
  bool someHit = false, someMiss = false;
  std::set<std::uint32_t> spheres;
};
Supersample supersample(const ScenePatches& patches, const view::Camera& camera, int x, int y) {
  Supersample s;
  for (int j = 0; j <= 8; ++j)
    for (int i = 0; i <= 8; ++i) {
      const SceneHit h = patches.intersectAll(camera.ray(x + i / 8.0, y + j / 8.0), 0.0, std::numeric_limits<double>::infinity());
      (h.valid() ? s.someHit : s.someMiss) = true;
      if (h.valid()) s.spheres.insert(h.patch);
    }
  return s;
}

TEST(PixelEdges, FlagTheOutlineAndTheOcclusionThatCrossAPixel) {
  // The front ball hides part of the back one; they do not touch.
  const build::PatchList list = twoBalls({-1.0, 0.5, 0.0}, 3.0, {1.5, -0.5, 5.0}, 1.6);
  const PatchScene scene(ScenePatches::fromPatchList(list));
  const view::RenderOptions o = maskedView(64);
  const view::FrameBuffers f = render(scene, o, {});
  std::size_t silhouettes = 0, occlusions = 0, missedSilhouettes = 0, missedOcclusions = 0;
  for (int y = 0; y < 64; ++y)
    for (int x = 0; x < 64; ++x) {
      const std::uint32_t flags = f.flags[static_cast<std::size_t>(y) * 64 + static_cast<std::size_t>(x)];
      const Supersample s = supersample(scene.patches(), o.camera, x, y);
      const bool outline = s.someHit && s.someMiss, occlusion = !s.someMiss && s.spheres.size() > 1;
      // The corners and the centre are among the samples: a flag is always right.
      if (flags & view::kPixelSilhouette) {
        EXPECT_TRUE(outline) << x << ", " << y;
      }
      if (flags & view::kPixelOcclusion) {
        EXPECT_TRUE(occlusion) << x << ", " << y;
      }
      silhouettes += outline, occlusions += occlusion;
      missedSilhouettes += outline && !(flags & view::kPixelSilhouette);
      missedOcclusions += occlusion && !(flags & view::kPixelOcclusion);
    }
  std::printf("outline pixels %zu (%zu not flagged), occlusion pixels %zu (%zu not flagged)\n", silhouettes, missedSilhouettes,
              occlusions, missedOcclusions);
  EXPECT_GT(silhouettes, 100u);
  EXPECT_GT(occlusions, 20u);
  // An edge that only clips a pixel's corner, between the five rays, escapes them.
  EXPECT_LT(missedSilhouettes, silhouettes / 5);
  EXPECT_LT(missedOcclusions, occlusions / 5);
}

TEST(PixelEdges, RecordedOnlyWhenAsked) {
  const build::PatchList list = twoBalls({-1.0, 0.5, 0.0}, 3.0, {1.5, -0.5, 5.0}, 1.6);
  const PatchScene scene(ScenePatches::fromPatchList(list));
  view::RenderOptions o = maskedView(32);
  o.referenceMasks = false;
  const view::FrameBuffers f = render(scene, o, {});
  EXPECT_TRUE(f.seamDistance.empty());
  for (const std::uint32_t flags : f.flags) EXPECT_EQ(flags & (view::kPixelSilhouette | view::kPixelOcclusion), 0u);
}

TEST(SeamDistance, RenderedFrameHoldsEachHitsDistanceToTheCrease) {
  // Two intersecting balls meet in a crease circle: a hit's seam distance is its distance to
  // that circle, misses +inf; opaque and transparent frames alike.
  const build::PatchList list = twoBalls({-1.0, 0.0, 0.0}, 2.0, {1.5, 0.0, 1.0}, 1.8);
  const glm::dvec3 c0 = list.convex.center[0], c1 = list.convex.center[1];
  const double r0 = list.convex.radius[0], r1 = list.convex.radius[1], D = glm::length(c1 - c0);
  const double a = (D * D + r0 * r0 - r1 * r1) / (2 * D);
  const glm::dvec3 axis = (c1 - c0) / D, circleCentre = c0 + a * axis;
  const double circleRadius = std::sqrt(r0 * r0 - a * a);
  const PatchScene scene(ScenePatches::fromPatchList(list));
  for (const double opacity : {1.0, 0.5}) {
    view::RenderOptions o = maskedView(48);
    o.opacity = opacity;
    const view::FrameBuffers f = render(scene, o, {});
    ASSERT_EQ(f.seamDistance.size(), f.pixels());
    std::size_t hits = 0;
    for (int y = 0; y < 48; ++y)
      for (int x = 0; x < 48; ++x) {
        const std::size_t p = static_cast<std::size_t>(y) * 48 + static_cast<std::size_t>(x);
        if (f.kind[p] == 0) {
          EXPECT_EQ(f.seamDistance[p], std::numeric_limits<float>::infinity());
          continue;
        }
        ++hits;
        const view::Ray ray = o.camera.ray(x + 0.5, y + 0.5);
        const glm::dvec3 hit = ray.org + static_cast<double>(f.depth[p]) * ray.dir;
        EXPECT_NEAR(f.seamDistance[p], circleDistance(hit, circleCentre, axis, circleRadius), 1e-4)
            << "opacity " << opacity << ", pixel " << x << ", " << y;
      }
    EXPECT_GT(hits, 300u);
  }
}

TEST(SeamDistance, SesSpheresAndTheirTorusMeasureToTheContactCircles) {
  // Two atoms and the probe rolling round them: one full torus between two spheres. Each
  // contact circle is where the probe touches an atom: the probe-centre circle (the SAS
  // spheres' intersection) pulled towards that atom's centre to its radius.
  const double rp = 1.4;
  const std::vector<glm::dvec3> centers{{-1.0, 0.2, 0.0}, {1.4, -0.1, 0.5}};
  const std::vector<double> radii{1.8, 1.5};
  const build::PatchList list = build::buildSes(centers, radii, build::SesParams{rp});
  ASSERT_EQ(list.tori.size(), 1u);
  const double D = glm::length(centers[1] - centers[0]);
  const glm::dvec3 axis = (centers[1] - centers[0]) / D;
  const double R0 = radii[0] + rp, R1 = radii[1] + rp, a = (D * D + R0 * R0 - R1 * R1) / (2 * D);
  const glm::dvec3 probeCircle = centers[0] + a * axis;
  const double probeRadius = std::sqrt(R0 * R0 - a * a);
  auto contactDistance = [&](int atom, const glm::dvec3& x) {
    // The contact circle on atom k: the probe-centre circle scaled about c_k by r_k/(r_k + rp).
    const double scale = radii[atom] / (radii[atom] + rp);
    return circleDistance(x, centers[atom] + scale * (probeCircle - centers[atom]), axis, scale * probeRadius);
  };
  const PatchScene scene(ScenePatches::fromPatchList(list));
  view::RenderOptions o = maskedView(48);
  o.camera.eye = {3, 5, 25};
  const view::FrameBuffers f = render(scene, o, {});
  std::size_t convex = 0, toroidal = 0;
  for (int y = 0; y < 48; ++y)
    for (int x = 0; x < 48; ++x) {
      const std::size_t p = static_cast<std::size_t>(y) * 48 + static_cast<std::size_t>(x);
      if (f.kind[p] == 0) continue;
      const view::Ray ray = o.camera.ray(x + 0.5, y + 0.5);
      const glm::dvec3 hit = ray.org + static_cast<double>(f.depth[p]) * ray.dir;
      const int atom = f.atomId[p] == 0 ? 0 : 1;
      const double want = f.kind[p] == 1 ? contactDistance(atom, hit) : std::min(contactDistance(0, hit), contactDistance(1, hit));
      EXPECT_NEAR(f.seamDistance[p], want, 1e-4) << "kind " << f.kind[p] << ", pixel " << x << ", " << y;
      (f.kind[p] == 1 ? convex : toroidal) += 1;
    }
  EXPECT_GT(convex, 200u);
  EXPECT_GT(toroidal, 30u);
}

}  // namespace
}  // namespace surftrace::trace

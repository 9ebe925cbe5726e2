// Concave spherical triangle intersector against the brute-force ray oracle (STYLE §4,
// ORACLES A.4, A.5, B.5), on random, degenerate and real (1crn) patches.
#include "trace/concave_patch.hpp"

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdint>
#include <cstdlib>
#include <iostream>
#include <limits>
#include <numbers>
#include <random>
#include <string>
#include <vector>

#include <gtest/gtest.h>
#include <glm/common.hpp>
#include <glm/geometric.hpp>

#include "build/core/vector_math.hpp"
#include "build/ses/contour_buildup.hpp"
#include "build/io/molecule.hpp"
#include "build/ses/sas_geometry.hpp"
#include "oracles/ray_march.hpp"
#include "trace/random_geometry.hpp"
#include "trace/sphere_oracle.hpp"

namespace surftrace::trace {
namespace {

using namespace testing_random;
using namespace sphere_oracle;

using Rng = std::mt19937_64;
using build::Plane;

constexpr int kTrials = 4000;
// Steps across the oracle's window (2 rp wide): two roots of a non-grazing ray
// (|n·d| >= kGrazingCosine) are at least 2e-3·rp apart, four steps or more.
constexpr int kMarchSteps = 4000;
constexpr double kHitTolerance = 1e-9;  // Å, ORACLES D.1
constexpr double kInf = std::numeric_limits<double>::infinity();

// Trial i uses seed base + i; SURFTRACE_TEST_SEED overrides the base to explore other seeds.
std::uint64_t seedBase() {
  const char* s = std::getenv("SURFTRACE_TEST_SEED");
  return s != nullptr ? std::strtoull(s, nullptr, 10) : 0;
}


// ---- fixtures -----------------------------------------------------------------------------

// A patch with its own clipping planes (ConcavePatch only holds a span of them).
struct Fixture {
  glm::dvec3 probe{0.0};
  double rp = 1.0;
  std::array<glm::dvec3, 3> dir{};
  std::vector<Plane> planes;

  ConcavePatch patch() const {
    ConcavePatch p;
    p.probe = probe;
    p.probeRadius = rp;
    p.dirI = dir[0];
    p.dirJ = dir[1];
    p.dirK = dir[2];
    p.clipPlanes = planes;
    return p;
  }
  glm::dvec3 centroidDir() const { return glm::normalize(dir[0] + dir[1] + dir[2]); }
  // The clip plane a neighbour probe q cuts into this probe sphere (ORACLES A.5), built as
  // contour-buildup builds it: the bisector of p and q, keeping p's side.
  void addNeighbour(const glm::dvec3& q) {
    const glm::dvec3 n = glm::normalize(q - probe);
    planes.emplace_back(n, -glm::dot(n, 0.5 * (probe + q)));
  }
};

// A direction in the cone, from random barycentric weights (not uniform on the sphere,
// which the tests do not need).
glm::dvec3 sampleCone(Rng& rng, const std::array<glm::dvec3, 3>& dir) {
  std::exponential_distribution<double> e;
  return glm::normalize(e(rng) * dir[0] + e(rng) * dir[1] + e(rng) * dir[2]);
}

// Real geometry: three atoms around a trial probe position p0 at distance R_m = r_m + rp,
// then the probe positions recomputed from the atoms alone with build::probePositions
// (ORACLES A.2), so the directions are genuine contact directions of a genuine vertex.
// `spread` scales how far apart the contact directions are.
bool realTriangle(Rng& rng, Fixture& f, double spread = 1.0) {
  f.rp = logUniform(rng, 0.1, 10.0);
  const glm::dvec3 p0 = randomUnit(rng) * logUniform(rng, 1e-2, 1e3);
  const glm::dvec3 axis = randomUnit(rng);
  std::array<glm::dvec3, 3> c;
  std::array<double, 3> R;
  for (int m = 0; m < 3; ++m) {
    R[m] = logUniform(rng, 0.1, 10.0) + f.rp;
    c[m] = p0 + R[m] * glm::normalize(axis + spread * randomUnit(rng));
  }
  const auto pair = build::probePositions(c[0], R[0], c[1], R[1], c[2], R[2]);
  if (!pair) return false;
  f.probe = uniform(rng, 0, 1) < 0.5 ? pair->plus : pair->minus;
  for (int m = 0; m < 3; ++m) f.dir[m] = glm::normalize(c[m] - f.probe);
  // The other position is a genuine twin; when h < rp the builder clips by it (ORACLES A.5).
  // Half the trials do, half keep the whole triangle.
  const glm::dvec3 twin = f.probe == pair->plus ? pair->minus : pair->plus;
  if (glm::length(twin - f.probe) < 2 * f.rp && uniform(rng, 0, 1) < 0.5) f.addNeighbour(twin);
  return true;
}

// ---- the oracle ---------------------------------------------------------------------------

// The patch's accept test in long double, written from ORACLES A.4/A.5 independently of the
// intersector: each g_ij = dirI × dirJ flipped on its own so that g_ij·dirK > 0, then every
// clipping plane n·x + w <= 0. Returns the smallest margin (Å; negative = rejected).
struct OracleClip {
  std::array<Vec3L, 3> g;  // inward face normals, unit
  Vec3L probe;
  const std::vector<Plane>* planes;

  explicit OracleClip(const Fixture& f) : probe(toL(f.probe)), planes(&f.planes) {
    for (int m = 0; m < 3; ++m) {
      const Vec3L a = toL(f.dir[m]), b = toL(f.dir[(m + 1) % 3]), third = toL(f.dir[(m + 2) % 3]);
      Vec3L n = crossL(a, b);
      if (dotL(n, third) < 0) n = scaleL(n, -1);
      g[m] = scaleL(n, 1 / std::sqrt(dotL(n, n)));
    }
  }
  // local = x − p.
  Real margin(const Vec3L& local) const {
    Real m = std::numeric_limits<Real>::infinity();
    for (const Vec3L& n : g) m = std::min(m, dotL(n, local));
    const Vec3L x{probe.x + local.x, probe.y + local.y, probe.z + local.z};
    for (const Plane& c : *planes) m = std::min(m, -(dotL(toL(glm::dvec3(c)), x) + c.w));
    return m;
  }
};

std::vector<Real> sphereRoots(const Fixture& f, const Ray& r, double tMin, double tMax) {
  return sphere_oracle::sphereRoots(f.probe, f.rp, r, tMin, tMax, kMarchSteps);
}
Real grazingCosine(const Fixture& f, const Ray& r) { return sphereGrazingCosine(f.probe, f.rp, r); }

// ---- one trial against the oracle ------------------------------------------------------

struct Tally {
  int hits = 0, misses = 0, grazing = 0, seams = 0;
  double worstT = 0.0, worstNormal = 0.0, worstImplicit = 0.0;
  void print(const std::string& what, int trials) const {
    std::cout << "[ stats    ] " << what << ": " << trials << " rays, " << hits << " hits, " << misses << " misses, "
              << grazing << " grazing skipped, " << seams << " seam disagreements; worst |Δt| " << worstT
              << " Å, |x−p|−rp " << worstImplicit << " Å, normal " << worstNormal << "\n";
  }
};

// Compares intersect() with the oracle on one ray; `allowSeams` lets them disagree where the
// oracle's deciding point lies within kBoundaryTolerance·rp of a trimming edge (only the
// deliberately degenerate slivers, whose every point is that close, need it).
void checkRay(const Fixture& f, const Ray& ray, double tMin, double tMax, const std::string& where, Tally& tally,
              bool allowSeams = false) {
  const ConcavePatch p = f.patch();
  const Bounds3d box = bounds(p);
  ASSERT_TRUE(finite(box) && !box.empty()) << where;
  const OracleClip clip(f);
  const SphereImplicit s(f.probe, f.rp, ray);
  const std::vector<Real> roots = sphereRoots(f, ray, tMin, tMax);
  bool found = false;  // (tMin may be negative, so no sentinel t)
  Real want = 0, wantMargin = 0, minAbsMargin = std::numeric_limits<Real>::infinity();
  for (Real t : roots) {
    const Real m = clip.margin(s.local(t));
    minAbsMargin = std::min(minAbsMargin, std::abs(m));
    if (m < 0) continue;
    EXPECT_TRUE(containsL(box, f.probe, s.local(t))) << where << ": an accepted oracle hit lies outside bounds()";
    if (!found) {
      found = true;
      want = t;
      wantMargin = m;
    }
  }
  const std::optional<PatchHit> got = intersect(p, ray, tMin, tMax);
  if (grazingCosine(f, ray) < kGrazingCosine) {
    ++tally.grazing;
    if (got) {
      EXPECT_TRUE(got->flags & kHitGrazing) << where;
    }
    return;
  }
  if (got.has_value() != found) {
    const bool seam = minAbsMargin < kBoundaryTolerance * f.rp;
    if (allowSeams && seam) {
      ++tally.seams;
      return;
    }
    ADD_FAILURE() << where << ": intersect " << (got ? "hits" : "misses") << ", oracle "
                  << (found ? "hits" : "misses") << " (closest margin " << static_cast<double>(minAbsMargin)
                  << " Å)";
    return;
  }
  if (!got) {
    ++tally.misses;
    return;
  }
  ++tally.hits;
  const Real len = std::sqrt(dotL(s.d, s.d));
  const double errT = static_cast<double>(std::abs(got->t - want) * len);
  EXPECT_LE(errT, kHitTolerance) << where;
  EXPECT_LE(got->t, tMax) << where;
  const Vec3L x = s.local(got->t);
  const double implicit = static_cast<double>(std::abs(std::sqrt(dotL(x, x)) - static_cast<Real>(f.rp)));
  EXPECT_LE(implicit, kHitTolerance) << where;
  // Normal (p − x)/rp, out of the SES body (ORACLES A.4).
  const Vec3L xw = s.local(want);
  const Real rp = f.rp;
  const glm::dvec3 wantN(static_cast<double>(-xw.x / rp), static_cast<double>(-xw.y / rp),
                         static_cast<double>(-xw.z / rp));
  const double errN = glm::length(got->normal - wantN);
  EXPECT_LE(errN, 1e-9) << where;
  EXPECT_NEAR(glm::length(got->normal), 1.0, 1e-14) << where;
  if (wantMargin > 2 * kBoundaryTolerance * f.rp) {
    EXPECT_FALSE(got->flags & kHitNearBoundary) << where;
  } else if (wantMargin < 0.5 * kBoundaryTolerance * f.rp) {
    EXPECT_TRUE(got->flags & kHitNearBoundary) << where;
  }
  tally.worstT = std::max(tally.worstT, errT);
  tally.worstNormal = std::max(tally.worstNormal, errN);
  tally.worstImplicit = std::max(tally.worstImplicit, implicit);
}

// A random ray for patch f: cameras inside the probe ball, near it, or up to 2e3 Å away;
// aimed at a point of the patch or anywhere in (and a little beyond) its box; direction
// lengths 1e-3..1e3; tMin and tMax now and then.
struct RandomRay {
  Ray ray;
  double tMin = 0.0, tMax = kInf;
};
RandomRay randomRay(Rng& rng, const Fixture& f) {
  RandomRay r;
  const double camera = uniform(rng, 0, 1) < 0.25 ? f.rp * uniform(rng, 0.0, 0.99) : f.rp + logUniform(rng, 1e-3, 2e3);
  r.ray.org = f.probe + camera * randomUnit(rng);
  glm::dvec3 target;
  if (uniform(rng, 0, 1) < 0.6) {
    target = f.probe + f.rp * sampleCone(rng, f.dir);
  } else {
    const Bounds3d b = bounds(f.patch());
    const glm::dvec3 mid = 0.5 * (b.lower + b.upper), half = 0.6 * (b.upper - b.lower);
    target = mid + half * glm::dvec3(uniform(rng, -1, 1), uniform(rng, -1, 1), uniform(rng, -1, 1));
  }
  const glm::dvec3 toTarget = target - r.ray.org;
  r.ray.dir = glm::normalize(toTarget) * logUniform(rng, 1e-3, 1e3);
  const double tTarget = glm::length(toTarget) / glm::length(r.ray.dir);
  if (uniform(rng, 0, 1) < 0.2) r.tMin = uniform(rng, -0.5, 1.5) * tTarget;
  if (uniform(rng, 0, 1) < 0.2) r.tMax = r.tMin + uniform(rng, 0.0, 2.0) * tTarget;
  return r;
}

// A real triangle (spread 0.2..3) clipped by up to three random neighbour probes around its
// centroid direction; false when the three atoms have no probe position.
bool clippedTriangle(Rng& rng, Fixture& f) {
  if (!realTriangle(rng, f, uniform(rng, 0.2, 3.0))) return false;
  const int neighbours = std::uniform_int_distribution<int>(0, 3)(rng);
  for (int k = 0; k < neighbours; ++k) {
    const glm::dvec3 toward = glm::normalize(f.centroidDir() + uniform(rng, 0.0, 1.5) * randomUnit(rng));
    f.addNeighbour(f.probe + toward * f.rp * uniform(rng, 0.05, 1.99));
  }
  return true;
}

std::string trialName(const char* what, int i, std::uint64_t seed) {
  return std::string(what) + " trial " + std::to_string(i) + " seed " + std::to_string(seed);
}

// ---- tests --------------------------------------------------------------------------------

// Random patches from real three-atom geometry with random neighbour clip planes.
TEST(ConcavePatch, MatchesBruteForceOracle) {
  Tally tally;
  for (int i = 0; i < kTrials; ++i) {
    const std::uint64_t seed = seedBase() + static_cast<std::uint64_t>(i);
    Rng rng(seed);
    Fixture f;
    if (!clippedTriangle(rng, f)) continue;
    const RandomRay r = randomRay(rng, f);
    checkRay(f, r.ray, r.tMin, r.tMax, trialName("random", i, seed), tally);
    if (::testing::Test::HasFailure()) break;  // the first failing seed is the useful one
  }
  tally.print("random patches", kTrials);
  EXPECT_GT(tally.hits, kTrials / 8);
  EXPECT_GT(tally.misses, kTrials / 5);
}

// allHits() solves once and gives the very hits (t, normal, flags, bit for bit) that intersect()
// gives when called again from each hit's t, as transparency did before (up to three solves).
TEST(ConcavePatch, AllHitsFromOneSolveAreTheRepeatedHits) {
  int twoHits = 0, oneHit = 0;
  for (int i = 0; i < kTrials; ++i) {
    const std::uint64_t seed = seedBase() + static_cast<std::uint64_t>(i) + 7000000;
    Rng rng(seed);
    Fixture f;
    if (!clippedTriangle(rng, f)) continue;
    const ConcavePatch p = f.patch();
    const RandomRay r = randomRay(rng, f);
    const UnitRay ray(r.ray);
    std::vector<PatchHit> repeated;
    for (double tMin = r.tMin; repeated.size() < 4;) {
      const std::optional<PatchHit> h = intersect(p, ray, tMin, r.tMax);
      if (!h || !(h->t > tMin)) break;
      repeated.push_back(*h);
      tMin = h->t;
    }
    PatchHit all[2];
    const int count = allHits(p, ray, r.tMin, r.tMax, all);
    ASSERT_EQ(static_cast<std::size_t>(count), repeated.size()) << "seed " << seed;
    for (int k = 0; k < count; ++k) {
      EXPECT_EQ(all[k].t, repeated[k].t) << "seed " << seed << " hit " << k;
      EXPECT_EQ(all[k].normal, repeated[k].normal) << "seed " << seed << " hit " << k;
      EXPECT_EQ(all[k].flags, repeated[k].flags) << "seed " << seed << " hit " << k;
    }
    twoHits += count == 2;
    oneHit += count == 1;
  }
  EXPECT_GT(twoHits, 0);
  EXPECT_GT(oneHit, kTrials / 8);
}

// The box is finite, holds every point of the patch and is tight: no face more than
// 1% of rp beyond the extremes of dense samples.
TEST(ConcavePatch, BoundsAreConservativeAndTight) {
  for (int i = 0; i < 300; ++i) {
    const std::uint64_t seed = seedBase() + static_cast<std::uint64_t>(i);
    Rng rng(seed);
    Fixture f;
    if (!realTriangle(rng, f, uniform(rng, 0.2, 3.0))) continue;
    f.planes.clear();
    const Bounds3d box = bounds(f.patch());
    ASSERT_TRUE(finite(box)) << trialName("bounds", i, seed);
    // Interior samples, dense ones along the edge arcs, and directions near the six poles
    // kept by the oracle's own cone test: every extreme lies on an edge or at a pole.
    Bounds3d samples;
    const OracleClip cone(f);
    for (int k = 0; k < 6; ++k) {
      glm::dvec3 pole(0.0);
      pole[k / 2] = k % 2 == 0 ? 1.0 : -1.0;
      for (int m = 0; m < 200; ++m) {
        const glm::dvec3 u = glm::normalize(pole + 0.02 * randomUnit(rng));
        if (cone.margin(toL(f.rp * u)) >= 0) samples.extend(f.probe + f.rp * u);
      }
    }
    for (int k = 0; k < 2000; ++k) samples.extend(f.probe + f.rp * sampleCone(rng, f.dir));
    for (int m = 0; m < 3; ++m)
      for (int k = 0; k <= 1000; ++k) {
        const double s = k / 1000.0;
        samples.extend(f.probe + f.rp * glm::normalize((1 - s) * f.dir[m] + s * f.dir[(m + 1) % 3]));
      }
    for (int k = 0; k < 3; ++k) {
      EXPECT_LE(box.lower[k], samples.lower[k]) << trialName("bounds", i, seed);
      EXPECT_GE(box.upper[k], samples.upper[k]) << trialName("bounds", i, seed);
      EXPECT_LT(samples.lower[k] - box.lower[k], 0.01 * f.rp) << trialName("bounds", i, seed);
      EXPECT_LT(box.upper[k] - samples.upper[k], 0.01 * f.rp) << trialName("bounds", i, seed);
    }
  }
}

// (tMin, tMax] decides which of the two sphere roots can be the hit.
TEST(ConcavePatch, RespectsTminTmax) {
  for (int i = 0; i < 300; ++i) {
    const std::uint64_t seed = seedBase() + static_cast<std::uint64_t>(i);
    Rng rng(seed);
    Fixture f;
    if (!realTriangle(rng, f)) continue;
    f.planes.clear();
    const ConcavePatch p = f.patch();
    // Through the probe centre along u in the cone: the far root p + rp·u is on the patch.
    const glm::dvec3 u = sampleCone(rng, f.dir);
    const double k = logUniform(rng, 1e-2, 1e2), dist = f.rp + logUniform(rng, 1e-2, 1e3);
    const Ray ray{f.probe - dist * u, u * k};
    const std::optional<PatchHit> h = intersect(p, ray, 0.0, kInf);
    ASSERT_TRUE(h.has_value()) << trialName("tmin", i, seed);
    EXPECT_NEAR(h->t * k, dist + f.rp, kHitTolerance) << trialName("tmin", i, seed);
    EXPECT_TRUE(intersect(p, ray, 0.0, h->t).has_value()) << trialName("tmin", i, seed);
    EXPECT_FALSE(intersect(p, ray, 0.0, std::nextafter(h->t, 0.0)).has_value()) << trialName("tmin", i, seed);
    EXPECT_FALSE(intersect(p, ray, h->t, kInf).has_value()) << trialName("tmin", i, seed);
    // Reversed, the patch point is the near root; with tMin past it nothing is left.
    const Ray back{f.probe + dist * u, -u * k};
    const std::optional<PatchHit> hb = intersect(p, back, 0.0, kInf);
    ASSERT_TRUE(hb.has_value()) << trialName("tmin", i, seed);
    EXPECT_NEAR(hb->t * k, dist - f.rp, kHitTolerance) << trialName("tmin", i, seed);
    EXPECT_FALSE(intersect(p, back, hb->t, kInf).has_value()) << trialName("tmin", i, seed);
  }
}

// Rays through the probe centre, from outside, from inside and from the centre itself.
TEST(ConcavePatch, RayThroughProbeCentre) {
  for (int i = 0; i < 500; ++i) {
    const std::uint64_t seed = seedBase() + static_cast<std::uint64_t>(i);
    Rng rng(seed);
    Fixture f;
    if (!realTriangle(rng, f)) continue;
    f.planes.clear();
    const ConcavePatch p = f.patch();
    const glm::dvec3 u = sampleCone(rng, f.dir);
    for (double dist : {0.0, 0.5 * f.rp, 3.0 * f.rp, 1e3}) {
      const Ray ray{f.probe - dist * u, u};
      const std::optional<PatchHit> h = intersect(p, ray, 0.0, kInf);
      ASSERT_TRUE(h.has_value()) << trialName("centre", i, seed) << " dist " << dist;
      EXPECT_NEAR(h->t, dist + f.rp, kHitTolerance) << trialName("centre", i, seed);
      EXPECT_LT(glm::length(h->normal + u), 1e-10) << trialName("centre", i, seed);
      EXPECT_EQ(h->flags & kHitGrazing, 0u) << trialName("centre", i, seed);
      // From inside, the opposite way meets the sphere only at p − rp·u, outside the
      // pointed cone; from beyond p + rp·u it meets that point first.
      const std::optional<PatchHit> back = intersect(p, Ray{f.probe + dist * u, -u}, 0.0, kInf);
      if (dist <= f.rp) {
        EXPECT_FALSE(back.has_value()) << trialName("centre", i, seed);
      } else {
        ASSERT_TRUE(back.has_value()) << trialName("centre", i, seed);
        EXPECT_NEAR(back->t, dist - f.rp, kHitTolerance) << trialName("centre", i, seed);
      }
    }
  }
}

// Three contacts almost on a great circle, both ways: (a) a probe just above the plane of
// three atoms (h -> 0): the contacts span the whole circle and the cone is nearly a half
// space, clipped by the twin probe into a thin band; (b) three contacts on a short arc:
// a thin sliver. Built exactly, then perturbed by 2^-45 (STYLE §4).
TEST(ConcavePatch, NearlyFlatTriangles) {
  Tally tally;
  int rays = 0;
  const double perturb = std::ldexp(1.0, -45);
  for (double eta : {1e-3, 1e-6, 1e-9, 1e-12}) {
    for (int i = 0; i < 200; ++i) {
      const std::uint64_t seed = seedBase() + static_cast<std::uint64_t>(i);
      Rng rng(seed);
      // (a) Equilateral atoms, circumradius R·sqrt(1 − η²): probe height h = R·η.
      Fixture wide;
      wide.rp = logUniform(rng, 0.5, 3.0);
      const double R = wide.rp + logUniform(rng, 1.0, 2.0);
      const glm::dvec3 centre = randomUnit(rng) * logUniform(rng, 1.0, 1e3);
      const glm::dvec3 n = randomUnit(rng), e1 = build::perpendicularTo(n), e2 = glm::cross(n, e1);
      std::array<glm::dvec3, 3> c;
      for (int m = 0; m < 3; ++m) {
        const double phi = 2.0 * std::numbers::pi * m / 3.0;
        c[m] = centre + R * std::sqrt(1 - eta * eta) * (std::cos(phi) * e1 + std::sin(phi) * e2);
        c[m] *= 1.0 + perturb * uniform(rng, -1, 1);
      }
      const auto pair = build::probePositions(c[0], R, c[1], R, c[2], R);
      if (pair) {
        wide.probe = pair->plus;
        for (int m = 0; m < 3; ++m) wide.dir[m] = glm::normalize(c[m] - wide.probe);
        if (uniform(rng, 0, 1) < 0.5) wide.addNeighbour(pair->minus);
        const std::string where = "wide eta " + std::to_string(eta) + " " + trialName("", i, seed);
        const RandomRay r = randomRay(rng, wide);
        checkRay(wide, r.ray, r.tMin, r.tMax, where, tally, true);
        ++rays;
        // Straight at a point of the patch from inside the probe ball: it must be hit there
        // unless that point is within the seam tolerance of an edge.
        const glm::dvec3 u = sampleCone(rng, wide.dir);
        const Ray radial{wide.probe + 0.5 * wide.rp * u, u};
        checkRay(wide, radial, 0.0, kInf, where + " radial", tally, true);
        ++rays;
      }
      // (b) A sliver: contacts a, b, c on a short arc, b lifted off the arc's great circle
      // by η. Built as real geometry around p0 (ORACLES A.2 recomputes the probe).
      Fixture thin;
      thin.rp = logUniform(rng, 0.5, 3.0);
      const glm::dvec3 p0 = randomUnit(rng) * logUniform(rng, 1.0, 1e3);
      const glm::dvec3 a = randomUnit(rng), t = build::perpendicularTo(a), axis = glm::cross(a, t);
      const double arc = uniform(rng, 0.3, 1.5);
      const std::array<glm::dvec3, 3> u3 = {
          a, glm::normalize(std::cos(0.4 * arc) * a + std::sin(0.4 * arc) * t + eta * axis),
          std::cos(arc) * a + std::sin(arc) * t};
      std::array<double, 3> Rs;
      for (int m = 0; m < 3; ++m) {
        Rs[m] = thin.rp + logUniform(rng, 1.0, 2.0);
        c[m] = (p0 + Rs[m] * u3[m]) * (1.0 + perturb * uniform(rng, -1, 1));
      }
      const auto pt = build::probePositions(c[0], Rs[0], c[1], Rs[1], c[2], Rs[2]);
      if (!pt) continue;
      thin.probe = glm::length(pt->plus - p0) < glm::length(pt->minus - p0) ? pt->plus : pt->minus;
      for (int m = 0; m < 3; ++m) thin.dir[m] = glm::normalize(c[m] - thin.probe);
      const std::string where = "sliver eta " + std::to_string(eta) + " " + trialName("", i, seed);
      const RandomRay r = randomRay(rng, thin);
      checkRay(thin, r.ray, r.tMin, r.tMax, where, tally, true);
      ++rays;
      const glm::dvec3 u = sampleCone(rng, thin.dir);
      checkRay(thin, Ray{thin.probe + 0.5 * thin.rp * u, u}, 0.0, kInf, where + " radial", tally, true);
      ++rays;
      const Bounds3d box = bounds(thin.patch());
      ASSERT_TRUE(finite(box)) << where;
      for (int k = 0; k < 100; ++k)
        ASSERT_TRUE(box.contains(thin.probe + thin.rp * sampleCone(rng, thin.dir))) << where;
    }
  }
  tally.print("nearly flat", rays);
  EXPECT_GT(tally.hits, rays / 4);
}

// A clipping plane through the middle of the triangle: points on the kept side are hit where
// aimed, points on the cut side are not hit at all.
TEST(ConcavePatch, ClipPlaneThroughTheMiddle) {
  Tally tally;
  int kept = 0, cut = 0, rays = 0;
  for (int i = 0; i < 500; ++i) {
    const std::uint64_t seed = seedBase() + static_cast<std::uint64_t>(i);
    Rng rng(seed);
    Fixture f;
    if (!realTriangle(rng, f)) continue;
    f.planes.clear();
    // A neighbour at distance rp, 60° off the centroid direction: its bisector plane (at
    // rp/2 from p) passes through the centroid point p + rp·ū.
    const glm::dvec3 ubar = f.centroidDir();
    const glm::dvec3 side = glm::normalize(glm::cross(ubar, f.dir[0] - f.dir[1]));
    const glm::dvec3 toward = 0.5 * ubar + std::sqrt(0.75) * side;
    f.addNeighbour(f.probe + f.rp * toward);
    const ConcavePatch p = f.patch();
    for (int k = 0; k < 4; ++k) {
      const glm::dvec3 u = sampleCone(rng, f.dir);
      const glm::dvec3 x = f.probe + f.rp * u;
      const double e = glm::dot(glm::dvec3(f.planes[0]), x) + f.planes[0].w;
      if (std::abs(e) < 1e-9 * f.rp) continue;
      const Ray ray{f.probe + uniform(rng, 0.0, 0.9) * f.rp * u, u * logUniform(rng, 1e-2, 1e2)};
      const std::optional<PatchHit> h = intersect(p, ray, 0.0, kInf);
      if (e < 0) {
        ++kept;
        ASSERT_TRUE(h.has_value()) << trialName("middle", i, seed);
        EXPECT_LT(glm::length(ray.org + h->t * ray.dir - x), kHitTolerance) << trialName("middle", i, seed);
      } else {
        ++cut;
        EXPECT_FALSE(h.has_value()) << trialName("middle", i, seed);
      }
      const RandomRay r = randomRay(rng, f);
      checkRay(f, r.ray, r.tMin, r.tMax, trialName("middle", i, seed), tally);
      ++rays;
    }
  }
  tally.print("clip through middle", rays);
  EXPECT_GT(kept, 200);
  EXPECT_GT(cut, 200);
}

// A neighbour so close that its plane removes the whole triangle: no ray ever hits it.
TEST(ConcavePatch, ClippedAwayCompletelyIsNeverHit) {
  int patches = 0, rays = 0;
  for (int i = 0; i < 300; ++i) {
    const std::uint64_t seed = seedBase() + static_cast<std::uint64_t>(i);
    Rng rng(seed);
    Fixture f;
    if (!realTriangle(rng, f)) continue;
    f.planes.clear();
    // u·ū over the triangle is smallest at a vertex (it is concave along each minor arc):
    // the plane ū·(x − p) = rp·cosMin/2 of the neighbour p + rp·cosMin·ū cuts all of it.
    const glm::dvec3 ubar = f.centroidDir();
    const double cosMin = std::min({glm::dot(ubar, f.dir[0]), glm::dot(ubar, f.dir[1]), glm::dot(ubar, f.dir[2])});
    if (cosMin < 0.05) continue;
    f.addNeighbour(f.probe + f.rp * cosMin * ubar);
    const ConcavePatch p = f.patch();
    ++patches;
    for (int k = 0; k < 10; ++k) {
      const RandomRay r = randomRay(rng, f);
      ++rays;
      ASSERT_FALSE(intersect(p, r.ray, r.tMin, r.tMax).has_value()) << trialName("clipped away", i, seed);
      const glm::dvec3 u = sampleCone(rng, f.dir);
      ASSERT_FALSE(intersect(p, Ray{f.probe, u}, 0.0, kInf).has_value()) << trialName("clipped away", i, seed);
      ASSERT_FALSE(insidePatch(p, f.probe + f.rp * u)) << trialName("clipped away", i, seed);
    }
  }
  std::cout << "[ stats    ] clipped away: " << patches << " patches, " << rays << " rays, no hit\n";
  EXPECT_GT(patches, 100);
}

// Tangent and nearly tangent rays at a point inside the patch: flagged grazing when they
// hit, never NaN, and where they hit, near the tangent point.
TEST(ConcavePatch, GrazingRays) {
  int flagged = 0;
  for (int i = 0; i < 300; ++i) {
    const std::uint64_t seed = seedBase() + static_cast<std::uint64_t>(i);
    Rng rng(seed);
    Fixture f;
    if (!realTriangle(rng, f)) continue;
    f.planes.clear();
    const ConcavePatch p = f.patch();
    const glm::dvec3 u = f.centroidDir();
    const glm::dvec3 tangent = build::perpendicularTo(u);
    // The roots lie within ~5e-4 rad of the tangent point; only a roomy triangle must contain them.
    const bool roomy = OracleClip(f).margin(toL(f.rp * u)) > 1e-2 * f.rp;
    for (double offset : {0.0, 1e-12, 1e-9, 1e-7}) {
      // Perpendicular distance rp(1 − offset): |n·d| ≈ sqrt(2·offset) < kGrazingCosine.
      const double L = f.rp * logUniform(rng, 1e-2, 1e3);
      const Ray ray{f.probe + f.rp * (1 - offset) * u - L * tangent, tangent};
      const std::optional<PatchHit> h = intersect(p, ray, 0.0, kInf);
      if (roomy && offset >= 1e-9) {
        ASSERT_TRUE(h.has_value()) << trialName("grazing", i, seed) << " offset " << offset;
      }
      if (!h) continue;
      ++flagged;
      EXPECT_TRUE(h->flags & kHitGrazing) << trialName("grazing", i, seed);
      EXPECT_TRUE(std::isfinite(h->t) && std::isfinite(h->normal.x)) << trialName("grazing", i, seed);
      EXPECT_NEAR(h->t, L, 1e-3 * f.rp) << trialName("grazing", i, seed);
    }
    const Ray outside{f.probe + f.rp * (1 + 1e-7) * u - f.rp * tangent, tangent};
    EXPECT_FALSE(intersect(p, outside, 0.0, kInf).has_value()) << trialName("grazing", i, seed);
  }
  EXPECT_GT(flagged, 600);
}

// Seams: a hit on an edge or at a corner is flagged near-boundary, one at the centroid not.
TEST(ConcavePatch, FlagsHitsNearTheBoundary) {
  for (int i = 0; i < 300; ++i) {
    const std::uint64_t seed = seedBase() + static_cast<std::uint64_t>(i);
    Rng rng(seed);
    Fixture f;
    if (!realTriangle(rng, f)) continue;
    f.planes.clear();
    const ConcavePatch p = f.patch();
    const auto shoot = [&](const glm::dvec3& u) { return intersect(p, Ray{f.probe, u}, 0.0, kInf); };
    const std::optional<PatchHit> centre = shoot(f.centroidDir());
    ASSERT_TRUE(centre.has_value()) << trialName("seam", i, seed);
    EXPECT_EQ(centre->flags, 0u) << trialName("seam", i, seed);
    for (int m = 0; m < 3; ++m) {
      // Exactly on an edge or a vertex the hit may go either way; if it is taken, it is flagged.
      for (const glm::dvec3& u : {f.dir[m], glm::normalize(f.dir[m] + f.dir[(m + 1) % 3])}) {
        const std::optional<PatchHit> h = shoot(u);
        if (h) {
          EXPECT_TRUE(h->flags & kHitNearBoundary) << trialName("seam", i, seed);
        }
      }
    }
  }
}

// insidePatch's slack widens both kinds of trimming edge by that many Å.
TEST(ConcavePatch, InsidePatchSlackWidens) {
  for (int i = 0; i < 300; ++i) {
    const std::uint64_t seed = seedBase() + static_cast<std::uint64_t>(i);
    Rng rng(seed);
    Fixture f;
    if (!realTriangle(rng, f)) continue;
    f.planes.clear();
    const OracleClip oracle(f);
    // Just outside the edge (I, J): the edge midpoint pushed off the cone face by δ·rp.
    const double delta = logUniform(rng, 1e-8, 1e-3);
    const glm::dvec3 g(static_cast<double>(oracle.g[0].x), static_cast<double>(oracle.g[0].y),
                       static_cast<double>(oracle.g[0].z));
    const glm::dvec3 mid = glm::normalize(f.dir[0] + f.dir[1]);
    const glm::dvec3 x = f.probe + f.rp * glm::normalize(mid - delta * g);
    const double dist = -static_cast<double>(oracle.margin(subL(x, f.probe)));  // ≈ δ·rp
    ASSERT_GT(dist, 0.0) << trialName("slack", i, seed);
    EXPECT_FALSE(insidePatch(f.patch(), x)) << trialName("slack", i, seed);
    EXPECT_FALSE(insidePatch(f.patch(), x, 0.5 * dist)) << trialName("slack", i, seed);
    EXPECT_TRUE(insidePatch(f.patch(), x, 2.0 * dist)) << trialName("slack", i, seed);
    // Just beyond a clipping plane through a point of the patch.
    const glm::dvec3 inner = f.probe + f.rp * f.centroidDir();
    const glm::dvec3 n = randomUnit(rng);
    f.planes.emplace_back(n, -glm::dot(n, inner) + delta * f.rp);  // inner is δ·rp beyond
    EXPECT_FALSE(insidePatch(f.patch(), inner)) << trialName("slack", i, seed);
    EXPECT_FALSE(insidePatch(f.patch(), inner, 0.5 * delta * f.rp)) << trialName("slack", i, seed);
    EXPECT_TRUE(insidePatch(f.patch(), inner, 2.0 * delta * f.rp)) << trialName("slack", i, seed);
  }
}

// Every concave patch of crambin's SES (1crn, rp = 1.4 Å): rays from inside the probe ball
// (solvent side) at points sampled in the patch must hit exactly there. A miss is a hole.
TEST(ConcavePatch, CrambinPatchesHaveNoHoles) {
  const build::Molecule mol = build::readMolecule(std::string(SURFTRACE_TEST_DATA) + "/structures/1crn.pdb");
  const build::PatchList patches = build::buildSes(mol.centers, mol.radii, build::SesParams{1.4});
  ASSERT_GT(patches.concave.size(), 100u);
  Rng rng(seedBase());
  int rays = 0, clippedPatches = 0, nearEdgeSkipped = 0, clipped = 0;
  double worst = 0.0;
  const double rp = patches.params.probeRadius;
  for (std::size_t i = 0; i < patches.concave.size(); ++i) {
    const ConcavePatch p = concavePatch(patches, i);
    const Bounds3d box = bounds(p);
    ASSERT_TRUE(finite(box) && !box.empty()) << "patch " << i;
    const std::array<glm::dvec3, 3> dirs{p.dirI, p.dirJ, p.dirK};
    int shot = 0;
    for (int k = 0; k < 40 && shot < 4; ++k) {
      const glm::dvec3 u = sampleCone(rng, dirs);
      const glm::dvec3 x = p.probe + rp * u;
      double margin = kInf;
      for (const Plane& c : p.clipPlanes) margin = std::min(margin, -(glm::dot(glm::dvec3(c), x) + c.w));
      if (margin < 0) {
        ++clipped;
        continue;
      }
      if (margin < 1e-9 * rp) {  // a seam with the neighbouring probe: either may own it
        ++nearEdgeSkipped;
        continue;
      }
      // From a point inside the probe ball towards x: first exactly against the outward
      // normal, then tilted up to ~60° off it.
      glm::dvec3 d = glm::normalize(u + 0.6 * randomUnit(rng));
      if (shot == 0 || glm::dot(d, u) < 0.2) d = u;
      const double chord = 2 * rp * glm::dot(d, u);  // the ray's path inside the ball
      const Ray ray{x - uniform(rng, 0.01, 0.99) * chord * d, d};
      const std::optional<PatchHit> h = intersect(p, ray, 0.0, kInf);
      ++shot;
      ++rays;
      ASSERT_TRUE(h.has_value()) << "patch " << i << " atoms " << patches.concave.atomI[i] << " "
                                 << patches.concave.atomJ[i] << " " << patches.concave.atomK[i];
      const glm::dvec3 hit = ray.org + h->t * ray.dir;
      const double err = glm::length(hit - x);
      EXPECT_LT(err, kHitTolerance) << "patch " << i;
      EXPECT_TRUE(box.contains(hit)) << "patch " << i;
      EXPECT_LT(glm::length(h->normal + u), 1e-9) << "patch " << i;
      worst = std::max(worst, err);
    }
    if (shot == 0) ++clippedPatches;
  }
  std::cout << "[ stats    ] 1crn: " << patches.concave.size() << " concave patches, " << rays << " rays, worst "
            << worst << " Å; " << clipped << " samples clipped, " << nearEdgeSkipped << " within 1e-9 rp of a plane, "
            << clippedPatches << " patches with no unclipped sample\n";
}

}  // namespace
}  // namespace surftrace::trace

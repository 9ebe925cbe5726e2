// MSS quadric intersector against the brute-force ray oracle (STYLE §4, ORACLES B.5, C.4):
// real patches of 1CRN (all four kinds) at s = 0.3 and 0.5, far-translated copies, rays from
// log-uniform distances with log-uniform direction lengths, near-tangent rays and rays through
// the centre (a cone's apex when w_X = 0); the oracle marches f in long double and applies the
// same cell test in long double.
#include "trace/mss_patch.hpp"

#include <cmath>
#include <cstdint>
#include <iostream>
#include <limits>
#include <random>
#include <vector>

#include <glm/geometric.hpp>
#include <gtest/gtest.h>

#include "build/io/molecule.hpp"
#include "build/mss/mss_builder.hpp"
#include "oracles/ray_march.hpp"
#include "trace/random_geometry.hpp"

namespace surftrace::trace {
namespace {

using namespace testing_random;
using Real = long double;
using Rng = std::mt19937_64;

constexpr int kMarchSteps = 4000;
constexpr double kHitTolerance = 1e-9;  // Å
constexpr double kInf = std::numeric_limits<double>::infinity();

struct Oracle {
  const MssPatch& p;
  const Ray& ray;

  Real coord(int k, Real t) const { return static_cast<Real>(ray.org[k]) + t * static_cast<Real>(ray.dir[k]); }
  Real f(Real t) const {
    Real dd = 0, da = 0;
    for (int k = 0; k < 3; ++k) {
      const Real d = coord(k, t) - static_cast<Real>(p.center[k]);
      dd += d * d;
      da += d * static_cast<Real>(p.axis[k]);
    }
    return static_cast<Real>(p.radial) * dd + static_cast<Real>(p.axial) * da * da + static_cast<Real>(p.constant);
  }
  // Whether the point is in the bounding ball (a bound the list guarantees, tight for the
  // spheres, so not a place where the answer is ambiguous).
  bool inBall(Real t) const {
    Real dd = 0;
    for (int k = 0; k < 3; ++k) {
      const Real d = coord(k, t) - static_cast<Real>(p.center[k]);
      dd += d * d;
    }
    return std::sqrt(dd) <= static_cast<Real>(p.boundRadius) * (1 + 1e-9L);
  }
  // Signed distance of the point beyond the cell's planes (<= 0 inside), in long double.
  Real outside(Real t) const {
    Real worst = -std::numeric_limits<Real>::infinity();
    for (const build::Plane& plane : p.cellPlanes) {
      Real v = static_cast<Real>(plane.w);
      for (int k = 0; k < 3; ++k) v += static_cast<Real>(plane[k]) * coord(k, t);
      worst = std::max(worst, v);
    }
    return worst;
  }
  Real cosine(Real t) const {
    Real g[3], gn = 0, dn = 0, dot = 0, da = 0;
    for (int k = 0; k < 3; ++k) da += (coord(k, t) - static_cast<Real>(p.center[k])) * static_cast<Real>(p.axis[k]);
    for (int k = 0; k < 3; ++k) {
      g[k] = static_cast<Real>(p.radial) * (coord(k, t) - static_cast<Real>(p.center[k])) +
             static_cast<Real>(p.axial) * da * static_cast<Real>(p.axis[k]);
      gn += g[k] * g[k];
      dn += static_cast<Real>(ray.dir[k]) * static_cast<Real>(ray.dir[k]);
      dot += g[k] * static_cast<Real>(ray.dir[k]);
    }
    return gn > 0 ? std::abs(dot) / std::sqrt(gn * dn) : 0.0L;
  }
};

struct Stats {
  int hits = 0, misses = 0, skipped = 0;
  int hitsByKind[4] = {0, 0, 0, 0};
  double worstT = 0.0;
};

void checkList(const build::PatchList& list, std::uint64_t seed, Stats& stats) {
  Rng rng(seed);
  for (std::size_t k = 0; k < list.mss.size(); k += 3) {
    const MssPatch p = mssPatch(list, k);
    for (int trial = 0; trial < 6; ++trial) {
      // A target inside the bounding ball (at the centre now and then: the apex of a cone),
      // a camera from just outside to 2e3 Å away, a direction of any length.
      const double R = p.boundRadius;
      const glm::dvec3 target = trial == 0 ? p.center : p.center + randomUnit(rng) * R * uniform(rng, 0.0, 1.0);
      Ray ray;
      ray.org = target + randomUnit(rng) * (R + logUniform(rng, 1e-3, 2e3));
      ray.dir = glm::normalize(target - ray.org) * logUniform(rng, 1e-3, 1e3);
      const double tTarget = glm::length(target - ray.org) / glm::length(ray.dir);
      const double tMin = uniform(rng, 0, 1) < 0.2 ? uniform(rng, 0.0, 1.5) * tTarget : 0.0;
      const double tMax = kInf;

      const Oracle o{p, ray};
      // March only where the ray is inside the ball (the rest cannot hold the patch).
      const double len = glm::length(ray.dir);
      const double tc = glm::dot(p.center - ray.org, ray.dir) / (len * len);
      const glm::dvec3 closest = ray.org + tc * ray.dir - p.center;
      const double half2 = R * R * 1.0001 - glm::dot(closest, closest);
      if (half2 <= 0) continue;
      const double half = std::sqrt(half2) / len;
      const Real lo = std::max<double>(tMin, tc - half), hi = tc + half;
      if (!(lo < hi)) continue;
      const double slack = 1e-9 * (R + 1.0);
      std::optional<Real> want;
      bool ambiguous = false;
      for (Real t : oracles::marchRoots([&](Real u) { return o.f(u); }, lo, hi, kMarchSteps)) {
        const Real out = o.outside(t);
        if (std::abs(out) < 1e3 * slack || o.cosine(t) < 2 * kGrazingCosine) ambiguous = true;
        if (out <= slack && o.inBall(t)) {
          want = t;
          break;
        }
      }
      const std::optional<PatchHit> got = intersect(p, ray, tMin, tMax);
      if (ambiguous || (got && (got->flags & (kHitGrazing | kHitNearBoundary)))) {
        ++stats.skipped;
        continue;
      }
      ASSERT_EQ(got.has_value(), want.has_value()) << "patch " << k << " kind " << static_cast<int>(p.kind) << " trial " << trial;
      if (!got) {
        ++stats.misses;
        continue;
      }
      ++stats.hits;
      ++stats.hitsByKind[static_cast<int>(p.kind)];
      // The hit lies in the patch's box (what Embree culls with).
      const glm::dvec3 x = ray.org + static_cast<double>(*want) * ray.dir;
      EXPECT_TRUE(bounds(p).contains(x, 1e-9 * (R + 1.0))) << "patch " << k << " kind " << static_cast<int>(p.kind);
      // And in the box cut by the cell's planes (what the scene traverses with), with no slack
      // beyond the rounding of x: that box already holds the intersector's cell slack.
      const double roundoff = 1e-12 * (glm::length(x) + R + 1.0);
      EXPECT_TRUE(cellBounds(p).contains(x, roundoff)) << "patch " << k << " kind " << static_cast<int>(p.kind);
      EXPECT_TRUE(cellBounds(p).contains(ray.org + got->t * ray.dir, roundoff)) << "patch " << k;
      const double err = static_cast<double>(std::abs(static_cast<Real>(got->t) - *want)) * len;
      EXPECT_LE(err, kHitTolerance) << "patch " << k << " kind " << static_cast<int>(p.kind);
      stats.worstT = std::max(stats.worstT, err);
      EXPECT_NEAR(glm::length(got->normal), 1.0, 1e-12);
    }
  }
}

TEST(MssPatch, MatchesBruteForceOracleOnRealPatches) {
  const build::Molecule m = build::readMolecule(std::string(SURFTRACE_TEST_DATA) + "/structures/1crn.pdb");
  Stats stats;
  for (double s : {0.3, 0.5}) {
    for (double shift : {0.0, 1e4}) {
      std::vector<glm::dvec3> c = m.centers;
      for (auto& x : c) x += glm::dvec3(shift, -shift, 0.5 * shift);
      checkList(build::buildMss(c, m.radii, {s}), static_cast<std::uint64_t>(s * 100 + shift), stats);
    }
  }
  std::cout << "[ stats    ] " << stats.hits << " hits, " << stats.misses << " misses, " << stats.skipped
            << " grazing or at a cell facet skipped; worst |Δt| " << stats.worstT << " Å; hits by kind "
            << stats.hitsByKind[0] << " " << stats.hitsByKind[1] << " " << stats.hitsByKind[2] << " "
            << stats.hitsByKind[3] << "\n";
  EXPECT_GT(stats.hits, 1000);
  for (int kind = 0; kind < 4; ++kind) EXPECT_GT(stats.hitsByKind[kind], 50) << "kind " << kind;
  EXPECT_GT(stats.misses, 1000);
}

// The double cone (w_X = 0, two atoms exactly (r_i + r_j)/√s apart): rays through the apex
// and along a generator hit where the oracle says, and never produce NaN.
TEST(MssPatch, ConeApexAndGenerators) {
  const double ri = 1.5, rj = 1.1, s = 0.4, d = (ri + rj) / std::sqrt(s);
  const std::vector<glm::dvec3> c{{0, 0, 0}, {d, 0, 0}};
  const build::PatchList list = build::buildMss(c, std::vector<double>{ri, rj}, {s});
  for (std::size_t k = 0; k < list.mss.size(); ++k) {
    const MssPatch p = mssPatch(list, k);
    if (p.kind != build::MssKind::Edge) continue;
    // Through the apex, across the axis: the apex itself is on the skin.
    Ray ray{p.center + glm::dvec3(0, 0, 5), glm::dvec3(0, 0, -1)};
    const std::optional<PatchHit> hit = intersect(p, ray, 0.0, kInf);
    ASSERT_TRUE(hit.has_value());
    EXPECT_NEAR(hit->t, 5.0, 1e-9);
    EXPECT_TRUE(std::isfinite(hit->normal.x) && std::isfinite(hit->normal.y) && std::isfinite(hit->normal.z));
    // Along a generator: |u|²/(1 − s) = |v|²/s, a ray with f linear in t.
    const glm::dvec3 gen = glm::normalize(glm::dvec3(std::sqrt(1 - s), std::sqrt(s), 0.0));
    Ray along{p.center - 2.0 * gen + glm::dvec3(0, 0, 1e-3), gen};
    const std::optional<PatchHit> h2 = intersect(p, along, 0.0, kInf);
    if (h2) {
      EXPECT_TRUE(std::isfinite(h2->t));
    }
  }
}

// The owner of a skin point (skinOwner): a convex patch is wholly its atom's (the skin there is
// that atom's ball alone, ORACLES C.3), and the owners of an edge patch split at the middle of
// its mixed cell along the edge, (1 − s)·(bisector of c_i c_j) + s·z_X. A carbon and a
// hydrogen 1.0 Å apart at s = 0.2, hit by rays from all around: the power distance to the
// grown balls (w = r²/s) instead would hand the hydrogen's own sphere to the carbon (their
// bisector lies 4.7 Å out, beyond both cells), which the test shows too, so that it tells the
// two rules apart. Without atoms: the lowest atom.
TEST(MssPatch, OwnerIsTheAtomWhoseBallHoldsThePoint) {
  const double s = 0.2, ri = 1.7, rj = 1.1, d = 1.0;
  const std::vector<glm::dvec3> c{{0, 0, 0}, {d, 0, 0}};
  const build::PatchList list = build::buildMss(c, std::vector<double>{ri, rj}, {s});
  ASSERT_EQ(list.skinAtoms.size(), 2u);
  const SkinAtomBalls balls = skinAtomBalls(list);
  // The edge cell's middle along the edge: z_X = c_i + α d (ORACLES C.2, grown weights).
  const double alpha = 0.5 + (ri * ri - rj * rj) / (2.0 * s * d * d);
  const double middle = (1.0 - s) * 0.5 * d + s * alpha * d;
  Rng rng(7);
  std::normal_distribution<double> gauss;
  int convexHits = 0, edgeHits = 0, grownWrong = 0;
  for (int n = 0; n < 20000; ++n) {
    const glm::dvec3 dir = glm::normalize(glm::dvec3(gauss(rng), gauss(rng), gauss(rng)));
    const glm::dvec3 aim(gauss(rng), 0.3 * gauss(rng), 0.3 * gauss(rng));
    const Ray ray{aim - 20.0 * dir, dir};
    for (std::size_t k = 0; k < list.mss.size(); ++k) {
      const MssPatch p = mssPatch(list, k);
      const std::optional<PatchHit> hit = intersect(p, ray, 0.0, kInf);
      if (!hit) continue;
      const glm::dvec3 x = ray.org + hit->t * ray.dir;
      const glm::uvec4& atoms = list.mss.atoms[k];
      const std::uint32_t owner = skinOwner(&balls, atoms, x);
      if (p.kind == build::MssKind::Convex) {
        ++convexHits;
        EXPECT_EQ(owner, atoms.x) << "x = (" << x.x << ", " << x.y << ", " << x.z << ")";
        const double grownI = glm::dot(x - c[0], x - c[0]) - ri * ri / s, grownJ = glm::dot(x - c[1], x - c[1]) - rj * rj / s;
        grownWrong += (grownI <= grownJ ? 0u : 1u) != atoms.x;
      } else {
        ++edgeHits;
        if (std::abs(x.x - middle) > 1e-9) {
          EXPECT_EQ(owner, x.x < middle ? 0u : 1u) << "x.x = " << x.x << ", middle " << middle;
        }
      }
    }
  }
  EXPECT_GT(convexHits, 1000);
  EXPECT_GT(edgeHits, 100);
  EXPECT_GT(grownWrong, 100);
  EXPECT_EQ(skinOwner(&balls, glm::uvec4(0, 1, ~0u, ~0u), glm::dvec3(5.0, 0.0, 0.0)), 1u);
  EXPECT_EQ(skinOwner(nullptr, glm::uvec4(0, 1, ~0u, ~0u), glm::dvec3(5.0, 0.0, 0.0)), 0u);
}

}  // namespace
}  // namespace surftrace::trace

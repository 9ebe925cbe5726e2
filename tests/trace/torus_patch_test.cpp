// Ray–torus patch intersection against a long-double brute-force march and a closed-form
// Ferrari solver (STYLE §4, ORACLES A.3 and B).
#include <glm/common.hpp>

#include "trace/torus_patch.hpp"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <limits>
#include <numbers>
#include <random>
#include <string>
#include <vector>

#include <glm/geometric.hpp>
#include <gtest/gtest.h>

#include "oracles/ray_march.hpp"
#include "trace/random_geometry.hpp"

namespace surftrace::trace {
namespace {

using namespace testing_random;

using Ld = long double;
constexpr double kPi = std::numbers::pi;
constexpr double kTwoPi = 2.0 * std::numbers::pi;
constexpr double kInf = std::numeric_limits<double>::infinity();
constexpr double kEps = std::numeric_limits<double>::epsilon();
// The oracle calls a trial grazing (and the comparison skips it) when a root up to the first
// accepted one meets the surface at |n·d| below this, or the ray passes within kLeaf of the
// tube without a certified crossing. At |n·d| = 1e-5 the two roots of a tube of radius
// 0.05 S are 1e-6 S apart and the quartic dips 2.5e-13 below zero, well above rounding, so
// the intersector must still get them right; much below, hit or miss is a coin toss.
constexpr Ld kOracleGrazing = 1e-5L;
// Leaf length of the oracle's subdivision, in units of S.
constexpr Ld kLeaf = 1e-7L;

// One seed per trial (STYLE §4); SURFTRACE_SEED=<n> reruns trial n alone.
std::vector<std::uint64_t> trialSeeds(int count) {
  if (const char* env = std::getenv("SURFTRACE_SEED")) return {std::strtoull(env, nullptr, 10)};
  std::vector<std::uint64_t> seeds(static_cast<std::size_t>(count));
  for (int i = 0; i < count; ++i) seeds[static_cast<std::size_t>(i)] = static_cast<std::uint64_t>(i);
  return seeds;
}

// ---- long-double vectors for the oracle ------------------------------------------------------

struct LVec {
  Ld x = 0.0L, y = 0.0L, z = 0.0L;
};
LVec operator+(LVec a, LVec b) { return {a.x + b.x, a.y + b.y, a.z + b.z}; }
LVec operator-(LVec a, LVec b) { return {a.x - b.x, a.y - b.y, a.z - b.z}; }
LVec operator*(Ld s, LVec a) { return {s * a.x, s * a.y, s * a.z}; }
Ld dot(LVec a, LVec b) { return a.x * b.x + a.y * b.y + a.z * b.z; }
Ld length(LVec a) { return std::sqrt(dot(a, a)); }
LVec toL(const glm::dvec3& v) { return {v.x, v.y, v.z}; }
glm::dvec3 toD(LVec v) { return {static_cast<double>(v.x), static_cast<double>(v.y), static_cast<double>(v.z)}; }

// ---- patches and rays ------------------------------------------------------------------------

// Orthonormalises the frame from the hints; the library fills and prepares the rest.
TorusPatch makePatch(const glm::dvec3& center, const glm::dvec3& axis, const glm::dvec3& e1Hint, double R, double rp,
                     double thetaI, double thetaJ, double phiExtent) {
  const glm::dvec3 n = glm::normalize(axis);
  return makeTorusPatch(center, n, glm::normalize(e1Hint - glm::dot(e1Hint, n) * n), R, rp, thetaI, thetaJ, phiExtent);
}

double scaleOf(const TorusPatch& p) { return p.bigRadius + p.probeRadius; }

// The point of the torus with meridian angle θ and azimuth φ (ORACLES A.3), in long double.
LVec torusPointL(const TorusPatch& p, Ld theta, Ld phi) {
  const Ld rho = p.bigRadius - p.probeRadius * std::cos(theta);
  const LVec er = std::cos(phi) * toL(p.e1) + std::sin(phi) * toL(p.e2);
  return toL(p.center) + rho * er + (p.probeRadius * std::sin(theta)) * toL(p.axis);
}
glm::dvec3 torusPoint(const TorusPatch& p, double theta, double phi) { return toD(torusPointL(p, theta, phi)); }

// θ of the SES part of the patch: [θi, θj], minus |θ| < θc on a spindle torus (A.3).
bool thetaOnSes(const TorusPatch& p, double theta) {
  if (p.bigRadius >= p.probeRadius) return true;
  return std::abs(theta) >= std::acos(p.bigRadius / p.probeRadius);
}

// A random interior point of the patch, by its (θ, φ); false if the patch is (nearly) empty.
bool randomPatchAngles(std::mt19937_64& rng, const TorusPatch& p, double& theta, double& phi) {
  for (int attempt = 0; attempt < 200; ++attempt) {
    theta = uniform(rng, p.thetaI, p.thetaJ);
    phi = uniform(rng, 0.0, p.phiExtent);
    if (thetaOnSes(p, theta)) return true;
  }
  return false;
}

// Random patch: log-uniform scale and R/rp in [0.05, 20] (ring and spindle), random frame
// and offset, random θ limits (on spindles often straddling both cusps), sometimes a full ring.
TorusPatch randomPatch(std::mt19937_64& rng) {
  const double rp = logUniform(rng, 1e-2, 1e2);
  const double R = rp * logUniform(rng, 0.05, 20.0);
  const double S = R + rp;
  const glm::dvec3 center = uniform(rng, 0.0, 30.0) * S * randomUnit(rng);
  const double limit = kPi / 2 - 1e-3;
  double thetaI = 0.0, thetaJ = 0.0;
  const int mode = static_cast<int>(rng() % 4);
  if (R < rp && mode < 2) {
    const double thetaC = std::acos(R / rp);
    if (mode == 0) {  // both SES pieces, each ending at a cusp
      thetaI = uniform(rng, -limit, -thetaC);
      thetaJ = uniform(rng, thetaC, limit);
    } else {  // one piece, away from the cusps or ending at one
      const double a = uniform(rng, thetaC, limit), b = uniform(rng, thetaC, limit);
      thetaI = std::min(a, b);
      thetaJ = std::max(a, b) + 1e-3;
      if (rng() % 2) {
        std::swap(thetaI, thetaJ);
        thetaI = -thetaI;
        thetaJ = -thetaJ;
      }
      if (rng() % 3 == 0) thetaJ = std::max(thetaJ, thetaC * uniform(rng, 0.5, 1.0));
    }
  } else {
    const double a = uniform(rng, -limit, limit), b = uniform(rng, -limit, limit);
    thetaI = std::min(a, b);
    thetaJ = std::max(a, b) + 1e-3;
  }
  thetaJ = std::min(thetaJ, limit);
  const double phiExtent = rng() % 4 == 0 ? kTwoPi : logUniform(rng, 1e-2, kTwoPi);
  return makePatch(center, randomUnit(rng), randomUnit(rng), R, rp, thetaI, thetaJ, phiExtent);
}

struct Trial {
  TorusPatch patch;
  Ray ray;
  double tMin = 0.0, tMax = kInf;
};

// Random ray aimed at the patch: from outside (up to 100 S away), sometimes from inside its
// box; at a random patch point with a log-uniform jitter, or at a uniform point of the box.
// The direction has a random length: the intersector must not assume it is unit.
Trial randomTrial(std::uint64_t seed) {
  std::mt19937_64 rng(seed);
  Trial tr;
  tr.patch = randomPatch(rng);
  const TorusPatch& p = tr.patch;
  const double S = scaleOf(p);
  const Bounds3d box = bounds(p);
  auto inBox = [&](double grow) {
    const glm::dvec3 mid = 0.5 * (box.lower + box.upper), half = 0.5 * (box.upper - box.lower) + grow * S;
    return mid + glm::dvec3{uniform(rng, -1, 1), uniform(rng, -1, 1), uniform(rng, -1, 1)} * half;
  };
  glm::dvec3 target;
  double theta, phi;
  if (rng() % 5 < 3 && randomPatchAngles(rng, p, theta, phi)) {
    target = torusPoint(p, theta, phi) + S * logUniform(rng, 1e-9, 0.3) * randomUnit(rng);
  } else {
    target = inBox(0.0);
  }
  glm::dvec3 org;
  if (rng() % 5 == 0) {
    org = inBox(0.2);
  } else {
    org = p.center + S * logUniform(rng, 1.2, 100.0) * randomUnit(rng);
  }
  if (glm::length(target - org) < 1e-6 * S) target = org + S * randomUnit(rng);
  tr.ray.org = org;
  tr.ray.dir = glm::normalize(target - org) * logUniform(rng, 1e-2, 1e2);
  const double tTarget = glm::length(target - org) / glm::length(tr.ray.dir);
  if (rng() % 5 == 0) tr.tMin = uniform(rng, 0.0, 1.0) * tTarget;
  if (rng() % 10 == 0) tr.tMax = uniform(rng, 0.5, 1.5) * tTarget;
  return tr;
}

// ---- the brute-force oracle ------------------------------------------------------------------

// F1 = (ρ − R)² + a² − rp² (own tube, ρ = |x − c − a n| >= 0: ring torus and apple, never the
// lemon) and the distance D = sqrt((ρ − R)² + a²) − rp, whose slope along a unit ray is <= 1.
struct Tube {
  LVec center, axis, org, dir;
  Ld R, r;

  Tube(const TorusPatch& p, const Ray& ray)
      : center(toL(p.center)), axis(toL(p.axis)), org(toL(ray.org)), dir(toL(ray.dir)), R(p.bigRadius),
        r(p.probeRadius) {}

  LVec point(Ld t) const { return org + t * dir; }
  void at(Ld t, Ld& f1, Ld& distance, LVec* gradient = nullptr, Ld* rhoOut = nullptr) const {
    const LVec w = point(t) - center;
    const Ld a = dot(w, axis);
    const LVec v = w - a * axis;
    const Ld rho = length(v);
    const Ld dr = rho - R;
    f1 = dr * dr + a * a - r * r;
    distance = std::sqrt(dr * dr + a * a) - r;
    if (gradient) *gradient = (rho > 0.0L ? (dr / rho) * v : LVec{}) + a * axis;  // ∇F1 / 2
    if (rhoOut) *rhoOut = rho;
  }
};

struct OracleRoot {
  Ld t = 0.0L;
  Ld cosine = 1.0L;     // |n·d| at the root
  bool accepted = false;
  bool nearEdge = false;  // within ~1e-9 of a θ/φ limit or 1e-5 rp of a cusp: may go either way
  glm::dvec3 point{0.0};
};

struct Oracle {
  std::vector<OracleRoot> roots;    // every crossing of F1 on the clipped chord, ascending
  std::vector<Ld> nearTangent;      // uncertified leaves where D has a local extremum
};

// March F1 in long double along the ray clipped to the bounding sphere |x − c| <= S and to
// [tMin, tMax]: subdivide until each piece is certified root-free by the Lipschitz bound on D
// or is shorter than kLeaf·S (so no pair of crossings further apart than that is missed, as a
// fixed-step march would), bisect every sign change with oracles::marchRoots, then apply
// insidePatch to each root.
Oracle runOracle(const TorusPatch& p, const Ray& ray, double tMin, double tMax) {
  Oracle out;
  const Tube tube(p, ray);
  const Ld S = scaleOf(p);
  const Ld dl = length(tube.dir);
  const LVec w0 = tube.org - tube.center;
  const Ld tc = -dot(w0, tube.dir) / (dl * dl);
  const LVec closest = w0 + tc * tube.dir;
  const Ld radius = S * (1.0L + 1e-9L);
  const Ld disc = radius * radius - dot(closest, closest);
  if (!(disc > 0.0L)) return out;
  const Ld half = std::sqrt(disc) / dl;
  const Ld lo = std::max<Ld>(tc - half, tMin), hi = std::min<Ld>(tc + half, tMax);
  if (!(lo < hi)) return out;
  const Ld leaf = kLeaf * S / dl;
  const Ld guard = 1e-16L * (S + length(w0));

  std::vector<std::pair<Ld, Ld>> brackets;
  auto distance = [&](Ld t) {
    Ld f1, d;
    tube.at(t, f1, d);
    return d;
  };
  auto slope = [&](Ld t) {  // sign of D' = ∇D·dir
    Ld f1, d;
    LVec g;
    tube.at(t, f1, d, &g);
    return dot(g, tube.dir);
  };
  auto subdivide = [&](auto&& self, Ld a, Ld b, Ld da, Ld db) -> void {
    const bool sameSign = da != 0.0L && db != 0.0L && (da > 0.0L) == (db > 0.0L);
    if (sameSign && std::abs(da) + std::abs(db) > dl * (b - a) + guard) return;  // certified empty
    if (b - a <= leaf) {
      if (!sameSign) {
        brackets.emplace_back(a, b);
      } else if ((slope(a) > 0.0L) != (slope(b) > 0.0L)) {
        // D has a local extremum within kLeaf·S of the surface: a near-tangency whose
        // crossings, if any, are closer together than the leaf. Next to an ordinary crossing
        // D is monotone and the Lipschitz bound alone cannot certify the leaf, but nothing
        // is hidden there (D'' is bounded by the curvatures, ≫ kLeaf·S away from cusps).
        out.nearTangent.push_back(0.5L * (a + b));
      }
      return;
    }
    const Ld m = 0.5L * (a + b), dm = distance(m);
    self(self, a, m, da, dm);
    self(self, m, b, dm, db);
  };
  subdivide(subdivide, lo, hi, distance(lo), distance(hi));

  auto f1At = [&](Ld t) {
    Ld f1, d;
    tube.at(t, f1, d);
    return f1;
  };
  for (const auto& [a, b] : brackets) {
    for (Ld t : oracles::marchRoots(f1At, a, b, 8)) {
      if (!(t > static_cast<Ld>(tMin) && t <= static_cast<Ld>(tMax))) continue;
      if (!out.roots.empty() && t <= out.roots.back().t) continue;
      OracleRoot root;
      root.t = t;
      Ld f1, d, rho;
      LVec g;
      tube.at(t, f1, d, &g, &rho);
      const Ld gl = length(g);
      root.cosine = gl > 0.0L ? std::abs(dot(g, tube.dir)) / (gl * dl) : 0.0L;
      root.point = toD(tube.point(t));
      root.accepted = insidePatch(p, root.point, 0.0);
      root.nearEdge = insidePatch(p, root.point, 1e-9) != insidePatch(p, root.point, -1e-9) ||
                      rho < 1e-5L * tube.r;
      out.roots.push_back(root);
    }
  }
  return out;
}

// What the oracle says about the first accepted root after `after`.
struct Verdict {
  const OracleRoot* first = nullptr;
  bool grazing = false;
  bool nearEdge = false;
};

Verdict judge(const Oracle& o, Ld after) {
  Verdict v;
  for (const OracleRoot& r : o.roots) {
    if (r.t <= after) continue;
    if (r.cosine < kOracleGrazing) v.grazing = true;
    if (r.nearEdge) v.nearEdge = true;
    if (r.accepted) {
      v.first = &r;
      break;
    }
  }
  const Ld limit = v.first ? v.first->t : std::numeric_limits<Ld>::infinity();
  for (Ld t : o.nearTangent)
    if (t > after && t <= limit) v.grazing = true;
  return v;
}

// ---- checks shared by every test -------------------------------------------------------------

struct Stats {
  int trials = 0, compared = 0, hits = 0, skippedGrazing = 0, skippedEdge = 0;
  double worstDepth = 0.0;        // |Δt| in units of S
  double worstDepthScaled = 0.0;  // |Δt|/tolerance
  double worstResidual = 0.0;     // |D(hit)| in units of S
  double worstDepthPlain = 0.0;   // |Δt|/S where |n·d| > 0.1 and the origin is within 3 S (ORACLES B.3's
                                  // "shifted, random rays" column)
  void print(const char* name) const {
    std::printf(
        "[torus] %s: %d trials, %d compared (%d hits), skipped %d grazing, %d at a trimming edge/cusp; "
        "worst depth error %.3g S (%.3g of tolerance; %.3g S for |n.d| > 0.1 within 3 S), worst |D(hit)| %.3g S\n",
        name, trials, compared, hits, skippedGrazing, skippedEdge, worstDepth, worstDepthScaled, worstDepthPlain,
        worstResidual);
  }
};

// Depth tolerance in units of S. Forming org − c, the unit direction and the shifted origin
// each round at ε·|org − c|, which moves the ray sideways by that much at the torus (as a
// one-ulp change of the ray's own origin would); sideways error becomes depth error divided
// by |n·d|, as does the ε-level noise of the root itself.
double depthTolerance(const TorusPatch& p, const Ray& ray, Ld cosine) {
  const double S = scaleOf(p);
  const double far = glm::length(ray.org - p.center) / S;
  return 16.0 * kEps * (4.0 + (1.0 + far) / static_cast<double>(std::max<Ld>(cosine, 1e-12L)));
}

// Properties of a hit that hold whatever the oracle says: t in range, the point on the own
// tube, the normal unit and equal to the normalised −∇F1 (outward (P − x)/rp) and to normalAt.
void checkHitProperties(const TorusPatch& p, const Ray& ray, double tMin, double tMax, const PatchHit& hit,
                        const std::string& label, Stats* stats) {
  EXPECT_TRUE(hit.t > tMin && hit.t <= tMax) << label << " t " << hit.t;
  const Tube tube(p, ray);
  Ld f1, d;
  LVec g;
  tube.at(hit.t, f1, d, &g);
  const double S = scaleOf(p);
  const double residual = static_cast<double>(std::abs(d)) / S;
  const double far = glm::length(ray.org - p.center) / S;
  if (stats) stats->worstResidual = std::max(stats->worstResidual, residual);
  if ((hit.flags & (kHitCusp | kHitGrazing)) == 0) {
    EXPECT_LT(residual, 64.0 * kEps * (4.0 + far)) << label << " |D(hit)|/S";
  } else {
    EXPECT_LT(residual, 1e-6) << label << " |D(hit)|/S (grazing or cusp)";
  }
  EXPECT_NEAR(glm::length(hit.normal), 1.0, 1e-12) << label;
  if ((hit.flags & kHitCusp) == 0) {
    const glm::dvec3 expected = -glm::normalize(toD(g));
    EXPECT_LT(glm::length(hit.normal - expected), 1e-9 + 1e-3 * residual / (p.probeRadius / S)) << label << " normal";
    const glm::dvec3 x = ray.org + hit.t * ray.dir;
    EXPECT_LT(glm::length(normalAt(p, x) - hit.normal), 1e-9 + 1e-3 * residual / (p.probeRadius / S))
        << label << " normalAt";
  }
}

// Compares intersect with the oracle for the first accepted root after tMin; returns the
// oracle's verdict. Mismatches are allowed only where the oracle says the ray is grazing, or
// the root sits on a trimming edge or cusp within the tolerance of the flags.
Verdict compareWithOracle(const TorusPatch& p, const Ray& ray, double tMin, double tMax, const Oracle& oracle,
                          const std::string& label, Stats& stats) {
  const std::optional<PatchHit> got = intersect(p, ray, tMin, tMax);
  const Verdict v = judge(oracle, tMin);
  ++stats.trials;
  if (got) checkHitProperties(p, ray, tMin, tMax, *got, label, &stats);
  if (v.grazing) {
    ++stats.skippedGrazing;
    return v;
  }
  if (got.has_value() != (v.first != nullptr)) {
    const bool flagged = got && (got->flags & (kHitNearBoundary | kHitCusp)) != 0;
    if (v.nearEdge || flagged) {
      ++stats.skippedEdge;
      return v;
    }
    ADD_FAILURE() << label << ": intersect " << (got ? "hits at t = " + std::to_string(got->t) : "misses")
                  << ", oracle " << (v.first ? "hits at t = " + std::to_string(static_cast<double>(v.first->t)) : "misses");
    return v;
  }
  ++stats.compared;
  if (!got) return v;
  ++stats.hits;
  const double S = scaleOf(p);
  const double dl = glm::length(ray.dir);
  const double err = static_cast<double>(std::abs(static_cast<Ld>(got->t) - v.first->t)) * dl / S;
  const double tol = depthTolerance(p, ray, v.first->cosine);
  if (err > tol && (v.nearEdge || (got->flags & (kHitNearBoundary | kHitCusp)) != 0)) {
    ++stats.skippedEdge;  // a different root of the same ray, across an edge
    return v;
  }
  stats.worstDepth = std::max(stats.worstDepth, err);
  stats.worstDepthScaled = std::max(stats.worstDepthScaled, err / tol);
  if (v.first->cosine > 0.1L && glm::length(ray.org - p.center) < 3.0 * S)
    stats.worstDepthPlain = std::max(stats.worstDepthPlain, err);
  EXPECT_LE(err, tol) << label << " depth error in S (|n·d| = " << static_cast<double>(v.first->cosine) << ")";
  const bool grazingFlag = (got->flags & kHitGrazing) != 0;
  if (std::abs(static_cast<double>(v.first->cosine) - kGrazingCosine) > 0.01 * kGrazingCosine) {
    EXPECT_EQ(grazingFlag, v.first->cosine < kGrazingCosine) << label << " grazing flag";
  }
  // The patch's box holds every accepted oracle point.
  const Bounds3d box = bounds(p);
  for (const OracleRoot& r : oracle.roots) {
    if (r.accepted) {
      EXPECT_TRUE(box.contains(r.point, 1e-13 * S)) << label << " bounds miss an oracle hit";
    }
  }
  return v;
}

// ---- the tests -------------------------------------------------------------------------------

TEST(TorusPatch, FromToriArrays) {
  build::Tori tori;
  const glm::dvec3 axis = glm::normalize(glm::dvec3{1.0, 2.0, -0.5});
  const glm::dvec3 e1 = glm::normalize(glm::cross(axis, glm::dvec3{0.0, 0.0, 1.0}));
  tori.center.push_back({1.0, -2.0, 3.0});
  tori.axis.push_back(axis);
  tori.e1.push_back(e1);
  tori.bigRadius.push_back(2.5);
  tori.thetaI.push_back(-0.4);
  tori.thetaJ.push_back(0.7);
  tori.phiExtent.push_back(1.0);
  tori.atomI.push_back(0);
  tori.atomJ.push_back(1);
  tori.component.push_back(0);
  const TorusPatch p = torusPatch(tori, 0, 1.4);
  EXPECT_EQ(p.center, tori.center[0]);
  EXPECT_EQ(p.axis, axis);
  EXPECT_EQ(p.e1, e1);
  EXPECT_LT(glm::length(p.e2 - glm::cross(axis, e1)), 1e-15);
  EXPECT_NEAR(glm::dot(glm::cross(p.e1, p.e2), p.axis), 1.0, 1e-15);  // e1 × e2 = n (A.1)
  EXPECT_EQ(p.bigRadius, 2.5);
  EXPECT_EQ(p.probeRadius, 1.4);
  EXPECT_EQ(p.thetaI, -0.4);
  EXPECT_EQ(p.thetaJ, 0.7);
  EXPECT_EQ(p.phiExtent, 1.0);
  // φ runs from e1 towards e2.
  EXPECT_TRUE(insidePatch(p, torusPoint(p, 0.1, 0.5)));
  EXPECT_FALSE(insidePatch(p, torusPoint(p, 0.1, -0.5)));
  EXPECT_FALSE(insidePatch(p, torusPoint(p, 0.1, 1.5)));
}

// insidePatch against the parametrisation: a point built from (θ, φ) is inside exactly when
// θ ∈ [θi, θj], φ mod 2π ∈ [0, Δφ] and, on a spindle, R − rp cos θ >= 0 (otherwise the point
// is on the lemon, the far side of the probe).
TEST(TorusPatch, InsidePatchMatchesParametrisation) {
  int checked = 0;
  for (std::uint64_t seed : trialSeeds(300)) {
    std::mt19937_64 rng(seed + 7000000);
    const TorusPatch p = randomPatch(rng);
    for (int k = 0; k < 50; ++k) {
      const double theta = uniform(rng, -kPi, kPi), phi = uniform(rng, -kPi, 3 * kPi);
      const double rho = p.bigRadius - p.probeRadius * std::cos(theta);
      double phiMod = std::fmod(phi, kTwoPi);
      if (phiMod < 0) phiMod += kTwoPi;
      const bool inTheta = theta >= p.thetaI && theta <= p.thetaJ;
      const bool inPhi = p.phiExtent >= kTwoPi || phiMod <= p.phiExtent;
      const bool expected = rho >= 0.0 && inTheta && inPhi;
      const double margin = 1e-9;
      const bool ambiguous = std::abs(theta - p.thetaI) < margin || std::abs(theta - p.thetaJ) < margin ||
                             std::abs(phiMod - p.phiExtent) < margin || phiMod < margin ||
                             kTwoPi - phiMod < margin || std::abs(rho) < 1e-6 * p.probeRadius;
      if (ambiguous) continue;
      EXPECT_EQ(insidePatch(p, torusPoint(p, theta, phi)), expected)
          << "seed " << seed << " θ " << theta << " φ " << phi << " R/rp " << p.bigRadius / p.probeRadius;
      ++checked;
    }
  }
  EXPECT_GT(checked, 10000);
}

// bounds: finite, containing every point of the patch, and no larger than the exact box of
// the annular sector × axial range that contains it.
TEST(TorusPatch, BoundsContainThePatchAndAreTight) {
  for (std::uint64_t seed : trialSeeds(300)) {
    std::mt19937_64 rng(seed + 8000000);
    const TorusPatch p = randomPatch(rng);
    const double S = scaleOf(p);
    const Bounds3d box = bounds(p);
    for (int k = 0; k < 3; ++k) {
      ASSERT_TRUE(std::isfinite(box.lower[k]) && std::isfinite(box.upper[k])) << "seed " << seed;
      ASSERT_LE(box.lower[k], box.upper[k]) << "seed " << seed;
    }
    // Dense samples of the patch itself, and the extremes of ρ and a over its θ range.
    double rhoMin = kInf, rhoMax = -kInf, aMin = kInf, aMax = -kInf;
    const int n = 400;
    std::vector<double> thetas;
    for (int i = 0; i <= n; ++i) thetas.push_back(p.thetaI + (p.thetaJ - p.thetaI) * i / n);
    // The extremes of ρ: θ = 0, and on a spindle the cusps ±θc (ρ = 0).
    const double thetaC = p.bigRadius < p.probeRadius ? std::acos(p.bigRadius / p.probeRadius) : 0.0;
    for (double extra : {0.0, thetaC, -thetaC})
      if (extra >= p.thetaI && extra <= p.thetaJ) thetas.push_back(extra);
    for (std::size_t i = 0; i < thetas.size(); ++i) {
      const double theta = thetas[i];
      if (!thetaOnSes(p, theta)) continue;
      const double rho = p.bigRadius - p.probeRadius * std::cos(theta), a = p.probeRadius * std::sin(theta);
      rhoMin = std::min(rhoMin, rho);
      rhoMax = std::max(rhoMax, rho);
      aMin = std::min(aMin, a);
      aMax = std::max(aMax, a);
      if (i % 8 != 0 && i <= static_cast<std::size_t>(n)) continue;  // every 8th, the ends and the extremes
      for (int j = 0; j <= 16; ++j) {
        const glm::dvec3 x = torusPoint(p, theta, p.phiExtent * j / 16);
        EXPECT_TRUE(box.contains(x)) << "seed " << seed << " θ " << theta;
      }
    }
    if (!(rhoMin <= rhoMax)) continue;  // empty spindle patch
    Bounds3d sector;
    for (int j = 0; j <= 1024; ++j) {
      const double phi = p.phiExtent * j / 1024;
      const glm::dvec3 er = std::cos(phi) * p.e1 + std::sin(phi) * p.e2;
      for (double rho : {std::max(rhoMin, 0.0), rhoMax})
        for (double a : {aMin, aMax}) sector.extend(p.center + rho * er + a * p.axis);
    }
    for (int k = 0; k < 3; ++k) {
      // θ sampling at 400 points misses the true extremes by < (π/400)²·rp; φ by < (π/1024)²·S.
      EXPECT_GT(box.lower[k], sector.lower[k] - 1e-4 * S) << "seed " << seed << " box not tight";
      EXPECT_LT(box.upper[k], sector.upper[k] + 1e-4 * S) << "seed " << seed << " box not tight";
    }
  }
}

TEST(TorusPatch, NormalAtMatchesGradient) {
  for (std::uint64_t seed : trialSeeds(300)) {
    std::mt19937_64 rng(seed + 9000000);
    const TorusPatch p = randomPatch(rng);
    double theta, phi;
    if (!randomPatchAngles(rng, p, theta, phi)) continue;
    const LVec xl = torusPointL(p, theta, phi);
    const glm::dvec3 x = toD(xl);
    // (P − x)/rp with P = c + R e_ρ(φ), which is −∇F1/|∇F1| = cos θ e_ρ − sin θ n (A.3).
    const glm::dvec3 er = std::cos(phi) * p.e1 + std::sin(phi) * p.e2;
    const glm::dvec3 expected = std::cos(theta) * er - std::sin(theta) * p.axis;
    EXPECT_LT(glm::length(normalAt(p, x) - expected), 1e-9) << "seed " << seed;
    EXPECT_TRUE(insidePatch(p, x, 1e-9)) << "seed " << seed;
  }
}

// The main oracle comparison (STYLE §4), with tMin/tMax and re-shooting past each hit.
TEST(TorusPatch, MatchesBruteForceOracle) {
  Stats stats, reshoot;
  for (std::uint64_t seed : trialSeeds(4000)) {
    const Trial tr = randomTrial(seed);
    const std::string label = "seed " + std::to_string(seed) + " (SURFTRACE_SEED=" + std::to_string(seed) + ")";
    const Oracle oracle = runOracle(tr.patch, tr.ray, tr.tMin, tr.tMax);
    const Verdict v = compareWithOracle(tr.patch, tr.ray, tr.tMin, tr.tMax, oracle, label, stats);
    if (v.grazing || !v.first) continue;
    const std::optional<PatchHit> hit = intersect(tr.patch, tr.ray, tr.tMin, tr.tMax);
    if (!hit) continue;
    // (tMin, tMax] is respected: the hit is gone below tMax = t − δ and kept at tMax = t + δ,
    // and re-shooting from t + δ finds the oracle's next accepted root only.
    const double S = scaleOf(tr.patch);
    const double delta = 1e-7 * S / glm::length(tr.ray.dir);
    EXPECT_FALSE(intersect(tr.patch, tr.ray, tr.tMin, hit->t - delta).has_value()) << label << " tMax";
    const std::optional<PatchHit> again = intersect(tr.patch, tr.ray, tr.tMin, hit->t + delta);
    ASSERT_TRUE(again.has_value()) << label << " tMax";
    // The same root, isolated from a different interval: equal to the last few ulps.
    const double far = glm::length(tr.ray.org - tr.patch.center) / glm::length(tr.ray.dir);
    EXPECT_NEAR(again->t, hit->t, 64 * kEps * (hit->t + far + S / glm::length(tr.ray.dir))) << label;
    compareWithOracle(tr.patch, tr.ray, hit->t + delta, tr.tMax, oracle, label + " re-shot", reshoot);
  }
  stats.print("random rays vs march");
  reshoot.print("re-shot past the first hit");
  EXPECT_GT(stats.hits, 1000);
  EXPECT_LT(stats.skippedGrazing + stats.skippedEdge, stats.trials / 100);
}

// Before the quartic, a ring torus's ray is dropped unless it meets the slab between the contact
// circles' planes outside the ring's inner cylinder (ρ >= R − rp·max cos θ). Rays that cross
// the saddle exactly on those sets' faces: at a contact circle (θ a hair inside θi or θj) and
// on the circle of least ρ (θ = 0, or the limit nearest it), from every direction that meets
// the surface at |n·d| >= 0.2, and with (tMin, tMax] a window of ±1e-7 S around the crossing,
// so that the ray's clipped chord barely enters the sets. Each must find that crossing; a slab
// or cylinder drawn too tight by more than about 1e-7 S, or on the wrong limit, drops it.
TEST(TorusPatch, RingSaddleFacesKeepTheirHits) {
  int checked = 0;
  for (std::uint64_t seed = 0; seed < 3000; ++seed) {
    std::mt19937_64 rng(seed + 9000000);
    TorusPatch p = randomPatch(rng);
    if (p.bigRadius < p.probeRadius) continue;  // spindles skip the test (clipLocal keeps lemon points)
    const double S = scaleOf(p);
    const int face = static_cast<int>(seed % 3);  // 0: at θi, 1: at θj, 2: on the least-ρ circle
    const double inside = 1e-10;
    const double theta = face == 0   ? p.thetaI + inside
                         : face == 1 ? p.thetaJ - inside
                         : p.thetaI <= 0.0 && p.thetaJ >= 0.0 ? 0.0
                         : p.thetaI > 0.0                     ? p.thetaI + inside
                                                              : p.thetaJ - inside;
    const double phi = p.phiExtent * uniform(rng, 0.1, 0.9);
    const LVec target = torusPointL(p, theta, phi);
    const glm::dvec3 normal = normalAt(p, toD(target));
    glm::dvec3 dir;
    do dir = randomUnit(rng);
    while (std::abs(glm::dot(dir, normal)) < 0.2);
    const double reach = S * uniform(rng, 0.5, 3.0);
    const double length = logUniform(rng, 1e-2, 1e2);
    Ray ray{toD(target - static_cast<Ld>(reach) * toL(dir)), dir * length};
    const double tTarget = reach / length, window = 1e-7 * S / length;
    const std::string label = "seed " + std::to_string(seed) + " face " + std::to_string(face);
    const std::optional<PatchHit> hit = intersect(p, ray, tTarget - window, tTarget + window);
    if (!hit) {
      ADD_FAILURE() << label << ": the crossing at t = " << tTarget << " is lost";
      continue;
    }
    EXPECT_NEAR(hit->t, tTarget, 1e-9 * S / length) << label;
    ++checked;
  }
  EXPECT_GT(checked, 1000);
}

// Scaling the direction scales t and nothing else.
// The derived values prepare() caches are exactly those intersect() would compute: a patch
// without them (built by hand, or edited after prepare()) gives bit-identical results.
TEST(TorusPatch, PreparedMatchesUnprepared) {
  for (std::uint64_t seed = 0; seed < 20000; ++seed) {
    const Trial tr = randomTrial(seed + 5000000);
    TorusPatch bare = tr.patch;
    bare.derived = TorusPatch::Derived{};
    TorusPatch edited = tr.patch;
    edited.thetaJ = std::nextafter(edited.thetaJ, 0.0);  // stale cache must be ignored
    TorusPatch reprepared = edited;
    prepare(reprepared);
    const auto a = intersect(tr.patch, tr.ray, tr.tMin, tr.tMax), b = intersect(bare, tr.ray, tr.tMin, tr.tMax);
    const auto c = intersect(edited, tr.ray, tr.tMin, tr.tMax), e = intersect(reprepared, tr.ray, tr.tMin, tr.tMax);
    for (const auto& [x, y] : {std::pair{&a, &b}, std::pair{&c, &e}}) {
      ASSERT_EQ(x->has_value(), y->has_value()) << "seed " << seed;
      if (!x->has_value()) continue;
      EXPECT_EQ((*x)->t, (*y)->t) << "seed " << seed;
      EXPECT_EQ((*x)->normal, (*y)->normal) << "seed " << seed;
      EXPECT_EQ((*x)->flags, (*y)->flags) << "seed " << seed;
    }
  }
}

TEST(TorusPatch, DirectionLengthOnlyScalesT) {
  for (std::uint64_t seed : trialSeeds(500)) {
    Trial tr = randomTrial(seed + 3000000);
    tr.tMin = 0.0;
    tr.tMax = kInf;
    const std::optional<PatchHit> base = intersect(tr.patch, tr.ray, 0.0, kInf);
    for (double k : {1e-3, 0.7, 3.0, 1e3}) {
      Ray scaled = tr.ray;
      scaled.dir *= k;
      const std::optional<PatchHit> h = intersect(tr.patch, scaled, 0.0, kInf);
      ASSERT_EQ(h.has_value(), base.has_value()) << "seed " << seed << " k " << k;
      if (!h) continue;
      EXPECT_NEAR(h->t * k, base->t, 1e-12 * base->t) << "seed " << seed;
      EXPECT_LT(glm::length(h->normal - base->normal), 1e-9) << "seed " << seed;
    }
  }
}

// ---- the closed-form cross-check (ORACLES B.4: Ferrari after the shift is nearly as good) ----

// Real roots of the monic quartic x⁴ + a x³ + b x² + c x + d by Ferrari's method in long
// double: depress, solve the resolvent cubic by Cardano/Viète for its largest root m, split
// into two quadratics; then two Newton steps on the quartic.
int ferrari(Ld a, Ld b, Ld c, Ld d, Ld (&out)[4]) {
  const Ld p = b - 3.0L * a * a / 8.0L;
  const Ld q = c - a * b / 2.0L + a * a * a / 8.0L;
  const Ld r = d - a * c / 4.0L + a * a * b / 16.0L - 3.0L * a * a * a * a / 256.0L;
  int n = 0;
  auto quadratic = [&](Ld B, Ld C) {  // y² + B y + C = 0
    const Ld disc = B * B - 4.0L * C;
    if (disc < 0.0L || n > 2) return;
    const Ld s = std::sqrt(disc);
    const Ld qq = -0.5L * (B + (B >= 0.0L ? s : -s));
    if (qq != 0.0L) {
      out[n++] = qq;
      out[n++] = C / qq;
    } else {
      out[n++] = 0.0L;
      out[n++] = 0.0L;
    }
  };
  if (std::abs(q) < 1e-30L) {  // biquadratic
    const Ld disc = p * p - 4.0L * r;
    if (disc >= 0.0L) {
      for (Ld z : {(-p + std::sqrt(disc)) / 2.0L, (-p - std::sqrt(disc)) / 2.0L}) {
        if (z >= 0.0L && n <= 2) {
          out[n++] = std::sqrt(z);
          out[n++] = -std::sqrt(z);
        }
      }
    }
  } else {
    // 8m³ + 8p m² + (2p² − 8r) m − q² = 0 has a root m > 0; take the largest.
    const Ld A = p, B = p * p / 4.0L - r, C = -q * q / 8.0L;
    const Ld P = B - A * A / 3.0L, Q = 2.0L * A * A * A / 27.0L - A * B / 3.0L + C;
    const Ld disc = Q * Q / 4.0L + P * P * P / 27.0L;
    Ld m;
    if (disc > 0.0L) {
      const Ld s = std::sqrt(disc);
      m = std::cbrt(-Q / 2.0L + s) + std::cbrt(-Q / 2.0L - s) - A / 3.0L;
    } else {
      const Ld rr = std::sqrt(-P / 3.0L);
      const Ld arg = std::clamp<Ld>(-Q / (2.0L * rr * rr * rr), -1.0L, 1.0L);
      m = 2.0L * rr * std::cos(std::acos(arg) / 3.0L) - A / 3.0L;
    }
    for (int k = 0; k < 3; ++k) {  // polish m on the cubic
      const Ld f = ((m + A) * m + B) * m + C, df = (3.0L * m + 2.0L * A) * m + B;
      if (df != 0.0L) m -= f / df;
    }
    if (m > 0.0L) {
      const Ld s = std::sqrt(2.0L * m);
      quadratic(-s, p / 2.0L + m + q / (2.0L * s));
      quadratic(s, p / 2.0L + m - q / (2.0L * s));
    }
  }
  for (int k = 0; k < n; ++k) {
    Ld x = out[k] - a / 4.0L;
    for (int it = 0; it < 2; ++it) {
      const Ld f = (((x + a) * x + b) * x + c) * x + d, df = ((4.0L * x + 3.0L * a) * x + 2.0L * b) * x + c;
      if (df != 0.0L) {
        const Ld next = x - f / df;
        if (std::abs(next - x) < 1e-6L) x = next;
      }
    }
    out[k] = x;
  }
  for (int i = 1; i < n; ++i)  // insertion sort (std::sort trips GCC 12's -Warray-bounds here)
    for (int j = i; j > 0 && out[j - 1] > out[j]; --j) std::swap(out[j - 1], out[j]);
  return n;
}

struct FerrariHit {
  bool hit = false;
  Ld t = 0.0L;
  bool ambiguous = false;  // near-double root or a root at a trimming edge before the hit
};

// The first accepted root by Ferrari on the B.1/B.2 quartic, written here from the formulas.
FerrariHit ferrariFirstHit(const TorusPatch& p, const Ray& ray, double tMin, double tMax) {
  FerrariHit out;
  const Ld S = scaleOf(p), R = p.bigRadius / S, r = p.probeRadius / S;
  const LVec dirW = toL(ray.dir);
  const Ld dl = length(dirW);
  const LVec u = (1.0L / dl) * dirW;
  const LVec w = toL(ray.org) - toL(p.center);
  const Ld tShift = -dot(w, u);
  const LVec sw = (1.0L / S) * (w + tShift * u);
  const LVec o{dot(sw, toL(p.e1)), dot(sw, toL(p.e2)), dot(sw, toL(p.axis))};
  const LVec d{dot(u, toL(p.e1)), dot(u, toL(p.e2)), dot(u, toL(p.axis))};
  const Ld K = dot(o, o) - R * R - r * r, f = dot(o, d);
  Ld roots[4];
  const int n = ferrari(4.0L * f, 2.0L * K + 4.0L * f * f + 4.0L * R * R * d.z * d.z,
                        4.0L * f * K + 8.0L * R * R * o.z * d.z, K * K + 4.0L * R * R * (o.z * o.z - r * r), roots);
  for (int k = 0; k < n; ++k) {
    const Ld s = roots[k];
    const Ld t = (s * S + tShift) / dl;
    if (!(t > tMin && t <= tMax) || std::abs(s) > 1.0L) continue;
    if ((k > 0 && roots[k] - roots[k - 1] < 1e-4L) || (k + 1 < n && roots[k + 1] - roots[k] < 1e-4L))
      out.ambiguous = true;
    const LVec x = o + s * d;
    const Ld rho = std::sqrt(x.x * x.x + x.y * x.y);
    const Ld f1 = (rho - R) * (rho - R) + x.z * x.z - r * r, f2 = (rho + R) * (rho + R) + x.z * x.z - r * r;
    if (std::abs(f1) > std::abs(f2)) continue;  // lemon
    const glm::dvec3 world = toD(toL(ray.org) + t * dirW);
    if (insidePatch(p, world, 1e-9) != insidePatch(p, world, -1e-9) || rho < 1e-5L * r) out.ambiguous = true;
    if (!insidePatch(p, world, 0.0)) continue;
    out.hit = true;
    out.t = t;
    return out;
  }
  return out;
}

TEST(TorusPatch, AgreesWithFerrariClosedForm) {
  int compared = 0, hits = 0, skipped = 0;
  double worst = 0.0;
  for (std::uint64_t seed : trialSeeds(3000)) {
    const Trial tr = randomTrial(seed + 5000000);
    const FerrariHit want = ferrariFirstHit(tr.patch, tr.ray, tr.tMin, tr.tMax);
    const std::optional<PatchHit> got = intersect(tr.patch, tr.ray, tr.tMin, tr.tMax);
    if (want.ambiguous || (got && (got->flags & (kHitGrazing | kHitCusp | kHitNearBoundary)) != 0)) {
      ++skipped;
      continue;
    }
    ++compared;
    ASSERT_EQ(got.has_value(), want.hit) << "seed " << seed;
    if (!got) continue;
    ++hits;
    const double err = static_cast<double>(std::abs(got->t - want.t)) * glm::length(tr.ray.dir) / scaleOf(tr.patch);
    worst = std::max(worst, err);
    const double far = glm::length(tr.ray.org - tr.patch.center) / scaleOf(tr.patch);
    EXPECT_LT(err, 1e-10 + 64 * kEps * far) << "seed " << seed;
  }
  std::printf("[torus] Ferrari cross-check: %d compared (%d hits), %d skipped (near-double/edge/flagged), "
              "worst |Δt| %.3g S\n", compared, hits, skipped, worst);
  EXPECT_GT(hits, 800);
}

// ---- hand-made degenerate cases --------------------------------------------------------------

// Rays through interior points of the patch from every side must hit it at or before the
// point ("no holes"), and agree with the oracle.
void expectNoHoles(const TorusPatch& p, std::uint64_t seedBase, int count, double minDistance, double maxDistance,
                   const char* name, Stats& stats) {
  const double S = scaleOf(p);
  for (std::uint64_t seed : trialSeeds(count)) {
    std::mt19937_64 rng(seed + seedBase);
    double theta, phi;
    if (!randomPatchAngles(rng, p, theta, phi)) continue;  // a (nearly) empty spindle patch
    const double margin = 1e-6;
    theta = std::clamp(theta, p.thetaI + margin, p.thetaJ - margin);
    phi = std::clamp(phi, margin, p.phiExtent - margin);
    if (!thetaOnSes(p, theta)) continue;
    const glm::dvec3 target = torusPoint(p, theta, phi);
    const glm::dvec3 org = target + S * logUniform(rng, minDistance, maxDistance) * randomUnit(rng);
    Ray ray{org, (target - org) * logUniform(rng, 0.1, 10.0)};
    const double tTarget = glm::length(target - org) / glm::length(ray.dir);
    const std::string label = std::string(name) + " seed " + std::to_string(seed);
    const std::optional<PatchHit> hit = intersect(p, ray, 0.0, kInf);
    const Oracle oracle = runOracle(p, ray, 0.0, kInf);
    const Verdict v = judge(oracle, 0.0L);
    if (!v.grazing) {
      ASSERT_TRUE(hit.has_value()) << label << ": a hole";
      // The rounded ray passes within ε·|org| of the target; along the ray that is
      // ε·|org|/|n·d|.
      const double far = glm::length(org - p.center) / S;
      const double cosine = std::abs(glm::dot(normalAt(p, target), glm::normalize(ray.dir)));
      EXPECT_LE(hit->t, tTarget + 64 * kEps * (4.0 + far) / std::max(cosine, 1e-12) * S / glm::length(ray.dir))
          << label;
    }
    compareWithOracle(p, ray, 0.0, kInf, oracle, label, stats);
  }
}

void expectNoHoles(const TorusPatch& p, std::uint64_t seedBase, int count, double minDistance, double maxDistance,
                   const char* name) {
  Stats stats;
  expectNoHoles(p, seedBase, count, minDistance, maxDistance, name, stats);
  stats.print(name);
}

TEST(TorusPatch, SpindleTorusPiecesAndCusps) {
  // R = rp/2: cusps at c ± h n with h = √3/2·rp, θc = π/3; [θi, θj] straddles both.
  const double rp = 1.5, R = 0.75, h = std::sqrt(rp * rp - R * R);
  const glm::dvec3 c{0.3, -0.2, 0.1}, n = glm::normalize(glm::dvec3{0.2, 1.0, 0.4});
  const TorusPatch p = makePatch(c, n, {1.0, 0.0, 0.0}, R, rp, -1.4, 1.4, kTwoPi);
  expectNoHoles(p, 100000, 400, 1.2, 50.0, "spindle, both pieces");
  // One piece only, ending at a cusp; and a partial ring.
  expectNoHoles(makePatch(c, n, {1.0, 0.0, 0.0}, R, rp, 0.2, 1.3, 2.0), 200000, 300, 1.2, 50.0, "spindle, one piece");

  // Along the axis from outside: the first SES point is the cusp c + h n (both F1 and F2
  // vanish there and the quartic has a double root), flagged as a cusp.
  for (double k : {1.0, 1e-3, 1e3}) {
    Ray ray{c + 10.0 * n, -k * n};
    const std::optional<PatchHit> hit = intersect(p, ray, 0.0, kInf);
    ASSERT_TRUE(hit.has_value()) << k;
    // A double root: rounding may split it into a pair √(rounding) ≈ 1e-8 apart.
    EXPECT_NEAR(hit->t * k, 10.0 - h, 1e-6);
    EXPECT_TRUE(hit->flags & kHitCusp);  // its normal is undefined (a cone's apex), but unit
    EXPECT_NEAR(glm::length(hit->normal), 1.0, 1e-12);
    // Past the first cusp the axis runs inside the lemon: the next SES point is the other cusp.
    const std::optional<PatchHit> next = intersect(p, ray, (10.0 - h + 1e-4) / k, kInf);
    ASSERT_TRUE(next.has_value());
    EXPECT_NEAR(next->t * k, 10.0 + h, 1e-6);
    EXPECT_TRUE(next->flags & kHitCusp);
  }
  // Oblique rays through a cusp: whatever is hit first must agree with the oracle, and a hit
  // at the cusp carries the flag.
  Stats stats;
  for (std::uint64_t seed : trialSeeds(200)) {
    std::mt19937_64 rng(seed + 300000);
    const glm::dvec3 cuspPoint = c + (rng() % 2 ? h : -h) * n;
    const glm::dvec3 org = cuspPoint + logUniform(rng, 1.2, 20.0) * (R + rp) * randomUnit(rng);
    const Ray ray{org, cuspPoint - org};
    const std::optional<PatchHit> hit = intersect(p, ray, 0.0, kInf);
    if (hit && std::abs(hit->t - 1.0) < 1e-9) {
      EXPECT_TRUE(hit->flags & kHitCusp) << "seed " << seed;
    }
    compareWithOracle(p, ray, 0.0, kInf, runOracle(p, ray, 0.0, kInf), "cusp seed " + std::to_string(seed), stats);
  }
  stats.print("rays through a spindle cusp");

  // θ range entirely inside (−θc, θc): the patch is empty (the lemon side), nothing is hit,
  // and the box is still finite.
  const TorusPatch empty = makePatch(c, n, {1.0, 0.0, 0.0}, R, rp, -0.5, 0.5, kTwoPi);
  const Bounds3d box = bounds(empty);
  for (int k = 0; k < 3; ++k) EXPECT_TRUE(std::isfinite(box.lower[k]) && std::isfinite(box.upper[k]));
  for (std::uint64_t seed : trialSeeds(300)) {
    std::mt19937_64 rng(seed + 400000);
    const glm::dvec3 org = c + 5.0 * randomUnit(rng), target = c + uniform(rng, 0.0, 2.0) * randomUnit(rng);
    EXPECT_FALSE(intersect(empty, Ray{org, target - org}, 0.0, kInf).has_value()) << "seed " << seed;
  }
}

TEST(TorusPatch, RayAlongTheAxis) {
  const glm::dvec3 c{1.0, 2.0, 3.0}, n = glm::normalize(glm::dvec3{-1.0, 0.5, 2.0});
  const double R = 3.0, rp = 1.0;
  const TorusPatch p = makePatch(c, n, {0.0, 1.0, 0.0}, R, rp, -0.8, 0.8, kTwoPi);
  // On the axis itself a ring torus has nothing (ρ = 0 < R − rp).
  EXPECT_FALSE(intersect(p, Ray{c + 20.0 * n, -n}, 0.0, kInf).has_value());
  EXPECT_FALSE(intersect(p, Ray{c - 1e4 * n, n}, 0.0, kInf).has_value());
  // Parallel to the axis at ρ0 = R − rp cos θ0 the ray meets the tube at a = ±rp sin θ0.
  for (double theta0 : {0.0, 0.3, 0.79, -0.5}) {
    const double rho0 = R - rp * std::cos(theta0);
    const glm::dvec3 e = p.e1 * std::cos(1.0) + p.e2 * std::sin(1.0);
    const Ray ray{c + rho0 * e + 20.0 * n, -n};
    const std::optional<PatchHit> hit = intersect(p, ray, 0.0, kInf);
    ASSERT_TRUE(hit.has_value()) << theta0;
    EXPECT_NEAR(hit->t, 20.0 - rp * std::abs(std::sin(theta0)), 1e-13 * 20) << theta0;
    if (theta0 == 0.0) {
      EXPECT_TRUE(hit->flags & kHitGrazing);  // tangent to the inner equator
    }
  }
}

// Rays tangent to the tube at an interior point, along a family of tangent directions
// (meridian, parallel and the asymptotic directions of the saddle in between), then moved by
// ±δ along the normal. The exactly tangent ray is ambiguous: a hit there must be flagged
// grazing; the offset ones must agree with the oracle whenever it is not grazing itself.
TEST(TorusPatch, GrazingRaysTangentToTheTube) {
  const double R = 2.0, rp = 1.0;
  const TorusPatch p = makePatch({0.5, 0.5, -0.5}, {0.0, 0.3, 1.0}, {1.0, 0.0, 0.0}, R, rp, -1.0, 1.0, 2.0);
  const double theta0 = 0.3, phi0 = 1.0;
  const glm::dvec3 x0 = torusPoint(p, theta0, phi0);
  const glm::dvec3 er = std::cos(phi0) * p.e1 + std::sin(phi0) * p.e2;
  const glm::dvec3 ephi = -std::sin(phi0) * p.e1 + std::cos(phi0) * p.e2;
  const glm::dvec3 etheta = std::sin(theta0) * er + std::cos(theta0) * p.axis;
  const glm::dvec3 normal = normalAt(p, x0);
  Stats stats;
  int grazingHits = 0;
  for (int k = 0; k < 24; ++k) {
    const double alpha = kPi * k / 24;
    const glm::dvec3 t = std::cos(alpha) * etheta + std::sin(alpha) * ephi;
    const double L = 7.0;
    const Ray tangent{x0 - L * t, t};
    const std::optional<PatchHit> hit = intersect(p, tangent, 0.0, kInf);
    if (hit && std::abs(hit->t - L) < 1e-4) {
      EXPECT_TRUE(hit->flags & kHitGrazing) << "alpha " << alpha;
      ++grazingHits;
    }
    for (double delta : {1e-12, 1e-9, 1e-6, 1e-3}) {
      for (double side : {-1.0, 1.0}) {
        const Ray ray{tangent.org + side * delta * normal, t};
        const std::string label = "alpha " + std::to_string(alpha) + " delta " + std::to_string(side * delta);
        compareWithOracle(p, ray, 0.0, kInf, runOracle(p, ray, 0.0, kInf), label, stats);
      }
    }
  }
  stats.print("tangent and offset rays");
  std::printf("[torus] exactly tangent rays hitting at the tangent point: %d of 24\n", grazingHits);
  EXPECT_GT(stats.compared, 24 * 8 / 2);
}

// R ≈ rp: the horn torus, and ring/spindle tori a hair away from it (2⁻⁴⁵ relative).
TEST(TorusPatch, HornTorus) {
  const glm::dvec3 c{-0.4, 0.0, 2.0}, n = glm::normalize(glm::dvec3{0.3, -0.2, 1.0});
  const double rp = 1.2;
  int i = 0;
  for (double ratio : {1.0, 1.0 + std::ldexp(1.0, -45), 1.0 - std::ldexp(1.0, -45)}) {
    const TorusPatch p = makePatch(c, n, {1.0, 1.0, 0.0}, ratio * rp, rp, -1.2, 1.2, 5.0);
    const std::string name = "horn R/rp = 1 " + std::string(ratio == 1.0 ? "" : ratio > 1.0 ? "+ 2^-45" : "- 2^-45");
    expectNoHoles(p, 500000 + 1000 * static_cast<std::uint64_t>(i++), 300, 1.2, 50.0, name.c_str());
    // Through the centre in the equatorial plane: the cusp at c is the SES point (θ = 0).
    const glm::dvec3 e = std::cos(0.5) * p.e1 + std::sin(0.5) * p.e2;
    const std::optional<PatchHit> hit = intersect(p, Ray{c - 5.0 * e, e}, 0.0, kInf);
    if (hit) {
      EXPECT_NEAR(hit->t, 5.0, 1e-6) << name;
      EXPECT_TRUE(hit->flags & kHitCusp) << name;
    }
    // Along the axis: the quartic is s⁴ (a quadruple root at the centre) for R = rp.
    const std::optional<PatchHit> axial = intersect(p, Ray{c + 4.0 * n, -n}, 0.0, kInf);
    if (axial) {
      EXPECT_NEAR(axial->t, 4.0, 1e-3) << name;
      EXPECT_TRUE(axial->flags & kHitCusp) << name;
    }
  }
}

// A full ring has no φ seam: rays at φ = 0 exactly and a few ulps either side all hit, and
// are not flagged as near a boundary. A partial ring's φ = 0 edge is flagged.
TEST(TorusPatch, FullRingHasNoSeam) {
  const TorusPatch ring = makePatch({0.0, 0.0, 0.0}, {0.0, 0.0, 1.0}, {1.0, 0.0, 0.0}, 2.0, 1.0, -0.6, 0.9, kTwoPi);
  const TorusPatch partial = makePatch({0.0, 0.0, 0.0}, {0.0, 0.0, 1.0}, {1.0, 0.0, 0.0}, 2.0, 1.0, -0.6, 0.9, 1.0);
  for (double phi : {0.0, 1e-15, -1e-15, kTwoPi - 1e-15, 3.0, kPi}) {
    const glm::dvec3 x = torusPoint(ring, 0.2, phi);
    const glm::dvec3 n = normalAt(ring, x);
    const Ray ray{x + 3.0 * n, -n};  // from the probe side, straight at the point
    const std::optional<PatchHit> hit = intersect(ring, ray, 0.0, kInf);
    ASSERT_TRUE(hit.has_value()) << phi;
    EXPECT_NEAR(hit->t, 3.0, 1e-13) << phi;
    EXPECT_FALSE(hit->flags & kHitNearBoundary) << phi;
  }
  // Just inside the partial ring's φ = 0 edge (arc length below kBoundaryTolerance·S): a hit,
  // flagged as a seam. Exactly on the edge the rounding of the hit point decides.
  for (double phi : {1e-12, 3e-10}) {
    const glm::dvec3 x = torusPoint(partial, 0.2, phi);
    const glm::dvec3 n = normalAt(partial, x);
    const std::optional<PatchHit> edge = intersect(partial, Ray{x + 3.0 * n, -n}, 0.0, kInf);
    ASSERT_TRUE(edge.has_value()) << phi;
    EXPECT_TRUE(edge->flags & kHitNearBoundary) << phi;
  }
  expectNoHoles(ring, 600000, 300, 1.2, 50.0, "full ring");
}

// A camera 1e3..1e4 S away: the origin shift keeps the roots O(1), so no holes and depth
// errors at the level of the rounding of the ray itself.
TEST(TorusPatch, FarCamera) {
  Stats stats;
  for (std::uint64_t seed : trialSeeds(25)) {
    std::mt19937_64 rng(seed + 700000);
    const TorusPatch p = randomPatch(rng);
    expectNoHoles(p, 800000 + 100 * seed, 20, 1e3, 1e4, ("far camera, patch " + std::to_string(seed)).c_str(), stats);
  }
  stats.print("far camera (1e3..1e4 S)");
}

}  // namespace
}  // namespace surftrace::trace

// Real-root isolation (ORACLES B.4) against polynomials built from known roots.
#include "trace/polynomial.hpp"
#include "trace/random_geometry.hpp"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <limits>
#include <random>
#include <string>
#include <vector>

#include <gtest/gtest.h>

namespace surftrace::trace {
namespace {

using namespace testing_random;

using Ld = long double;
constexpr double kEps = std::numeric_limits<double>::epsilon();

// One seed per trial (STYLE §4); SURFTRACE_SEED=<n> reruns trial n alone.
std::vector<std::uint64_t> trialSeeds(int count) {
  if (const char* env = std::getenv("SURFTRACE_SEED")) return {std::strtoull(env, nullptr, 10)};
  std::vector<std::uint64_t> seeds(static_cast<std::size_t>(count));
  for (int i = 0; i < count; ++i) seeds[static_cast<std::size_t>(i)] = static_cast<std::uint64_t>(i);
  return seeds;
}


// Coefficients (ascending) of lead·Π(t − r_k), expanded in long double.
std::vector<Ld> expand(const std::vector<Ld>& roots, Ld lead) {
  std::vector<Ld> c{lead};
  for (Ld r : roots) {
    std::vector<Ld> next(c.size() + 1, 0.0L);
    for (std::size_t k = 0; k < c.size(); ++k) {
      next[k + 1] += c[k];
      next[k] -= r * c[k];
    }
    c = next;
  }
  return c;
}

// Taylor coefficients of p at r: p(r + h) = Σ_k a_k h^k (repeated synthetic division).
std::vector<Ld> taylorAt(std::vector<Ld> c, Ld r) {
  const std::size_t n = c.size();
  for (std::size_t k = 0; k < n; ++k)
    for (std::size_t j = n - 1; j > k; --j) c[j - 1] += r * c[j];
  return c;
}

// How far a root of p may legitimately move when p is perturbed by |δp(t)| <= E:
// min over k of (E/|p^(k)(r)/k!|)^(1/k). k = 1 is the simple-root condition number, k = 2 the
// double-root √ε behaviour, and the minimum picks whichever regime a cluster is in.
Ld rootTolerance(const std::vector<Ld>& exact, Ld r, Ld perturbation) {
  const std::vector<Ld> a = taylorAt(exact, r);
  Ld best = std::numeric_limits<Ld>::infinity();
  for (std::size_t k = 1; k < a.size(); ++k)
    if (a[k] != 0.0L) best = std::min(best, std::pow(perturbation / std::abs(a[k]), 1.0L / static_cast<Ld>(k)));
  return best;
}

Ld magnitudeAt(const std::vector<double>& c, Ld t) {
  Ld m = 0.0L;
  for (std::size_t k = c.size(); k-- > 0;) m = m * std::abs(t) + std::abs(static_cast<Ld>(c[k]));
  return m;
}

struct TrialReport {
  int trials = 0;
  Ld worstRatio = 0.0L;  // error / tolerance
};

// Checks the computed roots against the known ones: every computed root is sorted, inside
// [lo, hi] and near a true root; every true root away from the interval ends has a computed
// root near it. `noise` is the relative size of the perturbation of p (coefficient rounding
// plus evaluation), in units of ε·Σ|c_k||t|^k (Higham's bound for Horner's rule).
void checkRoots(const std::vector<Ld>& trueRoots, const std::vector<double>& c, const std::vector<Ld>& exact, double lo,
                double hi, double noise, const std::string& label, TrialReport& report) {
  // The tangency tolerance is absolute (trace/polynomial.hpp): scale it with p over the
  // interval. The solver treats |p| <= τ as zero, so roots may move as if p were perturbed by τ.
  const Ld tau = 45.0L * kEps * magnitudeAt(c, std::max(std::abs(lo), std::abs(hi)));
  const PolynomialRoots got = realRoots(c, lo, hi, static_cast<double>(tau));
  ASSERT_LE(got.count, static_cast<int>(c.size()) - 1) << label;
  auto tolAt = [&](Ld r) {
    const Ld perturbation = std::max(noise * kEps * magnitudeAt(c, r), tau);
    return rootTolerance(exact, r, perturbation) + 8.0L * kEps * std::abs(r) + 1e-300L;
  };
  for (int k = 0; k < got.count; ++k) {
    const double t = got.value[static_cast<std::size_t>(k)];
    EXPECT_TRUE(t >= lo && t <= hi) << label << " root " << t << " outside [" << lo << ", " << hi << "]";
    if (k > 0) {
      EXPECT_LT(got.value[static_cast<std::size_t>(k - 1)], t) << label << " not sorted";
    }
    Ld bestRatio = std::numeric_limits<Ld>::infinity();
    for (Ld r : trueRoots) bestRatio = std::min(bestRatio, std::abs(static_cast<Ld>(t) - r) / tolAt(r));
    EXPECT_LE(bestRatio, 1.0L) << label << " computed root " << t << " is near no true root";
    report.worstRatio = std::max(report.worstRatio, bestRatio);
  }
  for (Ld r : trueRoots) {
    const Ld tol = tolAt(r);
    if (r < lo + tol || r > hi - tol) continue;  // may legitimately fall either side of an end
    Ld best = std::numeric_limits<Ld>::infinity();
    for (double t : got) best = std::min(best, std::abs(static_cast<Ld>(t) - r));
    EXPECT_LE(best, tol) << label << " true root " << static_cast<double>(r) << " missed (nearest error "
                         << static_cast<double>(best) << ", tolerance " << static_cast<double>(tol) << ")";
    report.worstRatio = std::max(report.worstRatio, best / tol);
  }
  ++report.trials;
}

TEST(PolynomialRoots, ClosedFormLowDegrees) {
  {
    const double c[] = {-1.0, 2.0};
    const PolynomialRoots r = realRoots(c, -10.0, 10.0);
    ASSERT_EQ(r.count, 1);
    EXPECT_EQ(r.value[0], 0.5);
  }
  {
    const double c[] = {2.0, -3.0, 1.0};
    const PolynomialRoots r = realRoots(c, -10.0, 10.0);
    ASSERT_EQ(r.count, 2);
    EXPECT_EQ(r.value[0], 1.0);
    EXPECT_EQ(r.value[1], 2.0);
  }
  {
    // t² − 1e8 t + 1: the textbook formula loses the small root entirely; the stable one
    // gets both to an ulp.
    const double c[] = {1.0, -1e8, 1.0};
    const PolynomialRoots r = realRoots(c, -1e9, 1e9);
    ASSERT_EQ(r.count, 2);
    EXPECT_NEAR(r.value[0], 1e-8, 4 * kEps * 1e-8);
    EXPECT_NEAR(r.value[1], 1e8, 4 * kEps * 1e8);
  }
  {
    const double c[] = {1.0, 0.0, 1.0};  // t² + 1
    EXPECT_EQ(realRoots(c, -10.0, 10.0).count, 0);
  }
  {
    const double c[] = {1.0, -2.0, 1.0};  // (t − 1)²: one tangential root
    const PolynomialRoots r = realRoots(c, -10.0, 10.0);
    ASSERT_EQ(r.count, 1);
    EXPECT_EQ(r.value[0], 1.0);
    EXPECT_TRUE(r.tangent(0));
  }
  {
    const double c[] = {-1.0, 1.0, 0.0, 0.0, 0.0};  // trailing zeros lower the degree
    const PolynomialRoots r = realRoots(c, -10.0, 10.0);
    ASSERT_EQ(r.count, 1);
    EXPECT_EQ(r.value[0], 1.0);
  }
  {
    const double zero[] = {0.0, 0.0, 0.0};
    EXPECT_EQ(realRoots(zero, -1.0, 1.0).count, 0);
    const double constant[] = {3.0};
    EXPECT_EQ(realRoots(constant, -1.0, 1.0).count, 0);
  }
}

TEST(PolynomialRoots, IntervalEndsExactZerosAndBadInput) {
  const double c[] = {0.0, -6.0, 11.0, -6.0, 1.0};  // t(t − 1)(t − 2)(t − 3)
  {
    const PolynomialRoots r = realRoots(c, 0.0, 3.0);
    ASSERT_EQ(r.count, 4);
    for (int k = 0; k < 4; ++k) EXPECT_NEAR(r.value[static_cast<std::size_t>(k)], k, 4 * kEps * 3);
  }
  {
    const PolynomialRoots r = realRoots(c, 0.5, 2.5);
    ASSERT_EQ(r.count, 2);
    EXPECT_NEAR(r.value[0], 1.0, 4 * kEps);
    EXPECT_NEAR(r.value[1], 2.0, 4 * kEps * 2);
  }
  EXPECT_EQ(realRoots(c, 1.0, 1.0).count, 1);
  EXPECT_EQ(realRoots(c, 2.0, 1.0).count, 0);
  EXPECT_EQ(realRoots(c, std::nan(""), 1.0).count, 0);
  EXPECT_EQ(realRoots(c, 0.0, std::numeric_limits<double>::infinity()).count, 0);
  const double nanCoefficient[] = {1.0, std::nan(""), 1.0, 0.0, 1.0};
  EXPECT_EQ(realRoots(nanCoefficient, -1.0, 1.0).count, 0);
  const double six[] = {1.0, 1.0, 1.0, 1.0, 1.0, 1.0};
  EXPECT_EQ(realRoots(six, -1.0, 1.0).count, 0);
}

TEST(PolynomialRoots, MultipleRootsAndInflections) {
  {
    const double c[] = {-1.0, 3.0, -3.0, 1.0};  // (t − 1)³: p' has a double root at 1
    const PolynomialRoots r = realRoots(c, -4.0, 4.0);
    ASSERT_EQ(r.count, 1);
    EXPECT_NEAR(r.value[0], 1.0, 1e-5);
  }
  {
    const double c[] = {1.0, -4.0, 6.0, -4.0, 1.0};  // (t − 1)⁴
    const PolynomialRoots r = realRoots(c, -4.0, 4.0);
    ASSERT_EQ(r.count, 1);
    EXPECT_NEAR(r.value[0], 1.0, 1e-3);
  }
  {
    const double c[] = {0.0, 0.0, 0.0, 0.0, 1.0};  // t⁴: the horn torus through its centre
    const PolynomialRoots r = realRoots(c, -1.0, 1.0);
    ASSERT_EQ(r.count, 1);
    EXPECT_EQ(r.value[0], 0.0);
  }
  {
    // t³ + t: monotone with an inflection at 0; a sloped crossing, not a tangency.
    const double c[] = {1e-20, 1.0, 0.0, 1.0};
    const PolynomialRoots r = realRoots(c, -1.0, 1.0);
    ASSERT_EQ(r.count, 1);
    EXPECT_FALSE(r.tangent(0));
  }
  {
    // (t² − 4)² − 1e-3: four simple roots, two pairs.
    const double c[] = {16.0 - 1e-3, 0.0, -8.0, 0.0, 1.0};
    EXPECT_EQ(realRoots(c, -3.0, 3.0).count, 4);
  }
}

// A double root perturbed by ±δ: a hump that rises above zero gives two roots, one that stays
// below gives none, and one within the tangency tolerance gives exactly one, flagged.
TEST(PolynomialRoots, TangentialDoubleRootReportedOnce) {
  const std::vector<Ld> roots{0.3L, 0.3L, -0.7L, 0.9L};
  const std::vector<Ld> e = expand(roots, 1.0L);
  for (double delta : {-1e-6, -1e-10, -1e-13, 0.0, 1e-16, 1e-13, 1e-10, 1e-6}) {
    std::vector<double> c(e.begin(), e.end());
    c[0] += delta;
    const PolynomialRoots r = realRoots(c, -1.0, 1.0);
    int near = 0, tangents = 0;
    for (int k = 0; k < r.count; ++k) {
      if (std::abs(r.value[static_cast<std::size_t>(k)] - 0.3) < 1e-2) {
        ++near;
        tangents += r.tangent(k) ? 1 : 0;
      }
    }
    // p(0.3 + h) ≈ −0.6h² + δ near the double root (a local maximum); τ = 1e-14.
    if (delta >= 1e-13) {
      EXPECT_EQ(near, 2) << "delta " << delta;
    } else if (std::abs(delta) <= 1e-14) {
      // Within rounding of a double root: either the hump rose above zero in double (two
      // simple roots), or it did not and the tangency rule reports it once.
      EXPECT_TRUE(near == 2 || (near == 1 && tangents == 1)) << "delta " << delta << " near " << near;
    } else {
      EXPECT_EQ(near, 0) << "delta " << delta;
    }
    EXPECT_EQ(r.count - near, 2) << "delta " << delta;
  }
}

// Random products of linear factors, coefficients rounded to double: roots uniform at a
// log-uniform scale, clustered (relative gaps down to 1e-9) and exact double roots.
TEST(PolynomialRoots, MatchesKnownRootsOfRandomProducts) {
  TrialReport report;
  for (std::uint64_t seed : trialSeeds(3000)) {
    std::mt19937_64 rng(seed);
    const int degree = 1 + static_cast<int>(rng() % 4);
    const Ld scale = logUniform(rng, 1e-6, 1e6);
    std::vector<Ld> roots;
    for (int k = 0; k < degree; ++k) {
      const int kind = static_cast<int>(rng() % 6);
      if (k > 0 && kind == 0) {
        roots.push_back(roots.back());  // exact double root
      } else if (k > 0 && kind == 1) {
        roots.push_back(roots.back() + scale * logUniform(rng, 1e-9, 1e-3) * (rng() % 2 ? 1 : -1));
      } else {
        roots.push_back(scale * uniform(rng, -1.0, 1.0));
      }
    }
    const Ld lead = logUniform(rng, 1e-3, 1e3) * (rng() % 2 ? 1.0 : -1.0);
    const std::vector<Ld> exact = expand(roots, lead);
    const std::vector<double> c(exact.begin(), exact.end());
    const std::vector<Ld> exactRounded(c.begin(), c.end());
    double lo = static_cast<double>(-2 * scale), hi = static_cast<double>(2 * scale);
    if (rng() % 4 == 0) {  // an interval that cuts through the root set
      lo = static_cast<double>(scale * uniform(rng, -1.0, 0.5));
      hi = static_cast<double>(lo + scale * uniform(rng, 0.0, 1.5));
    }
    // Rounding the coefficients perturbs p by <= ε/2·Σ|c_k||t|^k, Horner's evaluation by
    // about 2nε·Σ|c_k||t|^k; 32 is a margin over the sum for degree 4.
    checkRoots(roots, c, exact, lo, hi, 32.0, "seed " + std::to_string(seed), report);
  }
  std::printf("[polynomial] random products: %d trials, worst error/tolerance %.3g\n", report.trials,
              static_cast<double>(report.worstRatio));
}

// Roots m_k·2^e with |m_k| < 2^12: every coefficient is exact in double, so the only error
// left is the solver's own (evaluation and stopping), and simple roots must be within a few
// ulps times their condition number.
TEST(PolynomialRoots, ExactDyadicRootsToFewUlps) {
  TrialReport report;
  for (std::uint64_t seed : trialSeeds(3000)) {
    std::mt19937_64 rng(seed + 1000000);
    const int degree = 2 + static_cast<int>(rng() % 3);
    const int exponent = static_cast<int>(rng() % 60) - 40;
    std::vector<Ld> roots;
    for (int k = 0; k < degree; ++k) {
      const int kind = static_cast<int>(rng() % 5);
      Ld m;
      if (k > 0 && kind == 0) {
        m = std::ldexp(roots.back(), -exponent);  // double root
      } else if (k > 0 && kind == 1) {
        m = std::ldexp(roots.back(), -exponent) + 1.0L;  // cluster at a relative gap of ~2^-12
      } else {
        m = static_cast<Ld>(static_cast<int>(rng() % 8191) - 4095);
      }
      roots.push_back(std::ldexp(m, exponent));
    }
    const std::vector<Ld> exact = expand(roots, 1.0L);
    const std::vector<double> c(exact.begin(), exact.end());
    for (std::size_t k = 0; k < c.size(); ++k) ASSERT_EQ(static_cast<Ld>(c[k]), exact[k]) << "seed " << seed;
    const double span = std::ldexp(4096.0, exponent);
    checkRoots(roots, c, exact, -span, span, 8.0, "dyadic seed " + std::to_string(seed), report);
  }
  std::printf("[polynomial] exact dyadic: %d trials, worst error/tolerance %.3g\n", report.trials,
              static_cast<double>(report.worstRatio));
}

// A random monic quartic like the torus's (normalised units): real roots in [−2, 2], or
// complex pairs a ± bi with b from 1e-4 to 1, as exact coefficients (long double) and rounded.
std::vector<Ld> randomQuartic(std::mt19937_64& rng) {
  std::vector<Ld> c{1.0L};
  auto times = [&](std::vector<Ld> q) {  // c ·= q (ascending)
    std::vector<Ld> next(c.size() + q.size() - 1, 0.0L);
    for (std::size_t i = 0; i < c.size(); ++i)
      for (std::size_t j = 0; j < q.size(); ++j) next[i + j] += c[i] * q[j];
    c = next;
  };
  for (int pair = 0; pair < 2; ++pair) {
    if (rng() % 2 == 0) {
      const Ld r1 = uniform(rng, -2.0, 2.0), r2 = uniform(rng, -2.0, 2.0);
      times({r1 * r2, -(r1 + r2), 1.0L});
    } else {
      const Ld a = uniform(rng, -2.0, 2.0), b = logUniform(rng, 1e-4, 1.0);
      times({a * a + b * b, -2.0L * a, 1.0L});
    }
  }
  return c;
}

// firstRoot hands over realRoots' very values, in order, and stops at the one accepted.
TEST(PolynomialRoots, FirstRootVisitsTheRealRootsInOrderAndStopsAtTheAcceptedOne) {
  int visitedTotal = 0;
  for (std::uint64_t seed : trialSeeds(2000)) {
    std::mt19937_64 rng(seed);
    const std::vector<Ld> exact = randomQuartic(rng);
    const std::vector<double> c(exact.begin(), exact.end());
    const double lo = uniform(rng, -2.5, 0.0), hi = lo + uniform(rng, 0.0, 4.0);
    const PolynomialRoots all = realRoots(c, lo, hi);
    const int accept = static_cast<int>(rng() % 5);  // the index to accept; >= count: none
    std::vector<double> visited;
    std::vector<bool> tangents;
    const bool accepted = firstRoot(c, lo, hi, [&](double root, bool tangent) {
      visited.push_back(root);
      tangents.push_back(tangent);
      return static_cast<int>(visited.size()) - 1 == accept;
    });
    ASSERT_EQ(accepted, accept < all.count) << "seed " << seed;
    ASSERT_EQ(static_cast<int>(visited.size()), std::min(accept + 1, all.count)) << "seed " << seed;
    for (std::size_t k = 0; k < visited.size(); ++k) {
      EXPECT_EQ(visited[k], all.value[k]) << "seed " << seed << " root " << k;  // bit for bit
      EXPECT_EQ(tangents[k], all.tangent(static_cast<int>(k))) << "seed " << seed << " root " << k;
    }
    visitedTotal += static_cast<int>(visited.size());
  }
  EXPECT_GT(visitedTotal, 1000);
}

// A proof that |p| stays above the floor holds (p sampled densely in long double) and means
// realRoots finds nothing there; and it is found for most intervals where |p| stays well above.
TEST(PolynomialRoots, AwayFromZeroProofHoldsAndMeansNoRoot) {
  constexpr double kFloor = 1e-9;
  int proved = 0, clearlyAway = 0, provedOfClearlyAway = 0;
  for (std::uint64_t seed : trialSeeds(1500)) {
    std::mt19937_64 rng(seed);
    const std::vector<Ld> exact = randomQuartic(rng);
    const std::vector<double> c(exact.begin(), exact.end());
    const double lo = uniform(rng, -2.5, 1.5), hi = lo + logUniform(rng, 1e-3, 2.0);
    Ld smallest = std::numeric_limits<Ld>::infinity();
    for (int k = 0; k <= 2000; ++k) {
      const Ld t = static_cast<Ld>(lo) + (static_cast<Ld>(hi) - static_cast<Ld>(lo)) * k / 2000;
      Ld v = 0.0L;
      for (int j = 4; j >= 0; --j) v = v * t + static_cast<Ld>(c[static_cast<std::size_t>(j)]);
      smallest = std::min(smallest, std::abs(v));
    }
    const bool yes = provablyAwayFromZero(c, lo, hi, kFloor, 3);
    if (yes) {
      ++proved;
      EXPECT_GT(smallest, kFloor) << "seed " << seed;
      EXPECT_EQ(realRoots(c, lo, hi).count, 0) << "seed " << seed;
    }
    if (smallest > 0.1L) {
      ++clearlyAway;
      provedOfClearlyAway += yes ? 1 : 0;
    }
  }
  std::printf("[polynomial] away from zero: %d proved of 1500; %d of %d intervals with |p| > 0.1\n", proved,
              provedOfClearlyAway, clearlyAway);
  EXPECT_GT(proved, 300);
  EXPECT_GT(provedOfClearlyAway, clearlyAway / 2);
}

}  // namespace
}  // namespace surftrace::trace

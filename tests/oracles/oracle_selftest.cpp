// Tests of the test oracles themselves, against closed-form geometry (ORACLES.md A.1-A.3, D).
#include <gtest/gtest.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <iostream>
#include <numbers>
#include <random>
#include <vector>

#include <glm/geometric.hpp>

#include "oracles/freesasa_oracle.hpp"
#include "oracles/ses_oracle.hpp"

namespace surftrace::oracle {
namespace {

using glm::dvec3;
constexpr double kPi = std::numbers::pi;

dvec3 randomUnit(std::mt19937_64& rng) {
  std::normal_distribution<double> g;
  for (;;) {
    const dvec3 v(g(rng), g(rng), g(rng));
    const double l = glm::length(v);
    if (l > 1e-6) return v / l;
  }
}

// Connolly's form of the probe positions (A.2), deliberately not the (alpha, beta) solve
// that the oracle uses.
bool probePositionsConnolly(const Sphere& ai, const Sphere& aj, const Sphere& ak, double rp,
                            dvec3& pPlus, dvec3& pMinus) {
  const double Ri = ai.r + rp, Rj = aj.r + rp, Rk = ak.r + rp;
  auto circleCentre = [&](const dvec3& c1, double R1, const dvec3& c2, double R2) {
    const double d2 = glm::dot(c2 - c1, c2 - c1);
    return 0.5 * (c1 + c2) + 0.5 * (R1 * R1 - R2 * R2) / d2 * (c2 - c1);
  };
  const dvec3 uij = glm::normalize(aj.c - ai.c), uik = glm::normalize(ak.c - ai.c);
  const dvec3 cij = circleCentre(ai.c, Ri, aj.c, Rj), cik = circleCentre(ai.c, Ri, ak.c, Rk);
  const double sinOmega = glm::length(glm::cross(uij, uik));
  const dvec3 uijk = glm::cross(uij, uik) / sinOmega;
  const dvec3 utb = glm::cross(uijk, uij);
  const dvec3 b = cij + utb * (glm::dot(uik, cik - cij) / sinOmega);
  const double h2 = Ri * Ri - glm::dot(b - ai.c, b - ai.c);
  if (h2 < 0) return false;
  const double h = std::sqrt(h2);
  pPlus = b + h * uijk;
  pMinus = b - h * uijk;
  return true;
}

// A compact, branched random "molecule": bonded steps of 1.53 Å, non-bonded atoms >= 2.5 Å
// apart, confined to a ball holding ~0.045 atoms/Å^3 (near protein heavy-atom density); the
// ball grows a little whenever growth gets stuck.
std::vector<Sphere> randomMolecule(int n, std::uint64_t seed) {
  std::mt19937_64 rng(seed);
  double confine = std::cbrt(3.0 * n / (4.0 * kPi * 0.045));
  const double radii[] = {1.70, 1.55, 1.52, 1.80, 1.70, 1.85};
  std::vector<Sphere> atoms{{dvec3(0.0), 1.70}};
  std::uniform_int_distribution<int> pickRadius(0, 5);
  int failures = 0;
  while (static_cast<int>(atoms.size()) < n) {
    std::uniform_int_distribution<std::size_t> pick(0, atoms.size() - 1);
    // Grow mostly from the newest atom (chain-like), sometimes from any atom (branches).
    const std::size_t from = (rng() % 4 != 0) ? atoms.size() - 1 : pick(rng);
    const dvec3 p = atoms[from].c + 1.53 * randomUnit(rng);
    bool ok = glm::length(p) <= confine;
    for (std::size_t k = 0; k < atoms.size() && ok; ++k)
      if (k != from && glm::length(atoms[k].c - p) < 2.5) ok = false;
    if (ok) {
      atoms.push_back({p, radii[pickRadius(rng)]});
    } else if (++failures > 2000) {
      confine *= 1.05;
      failures = 0;
    }
  }
  return atoms;
}

// ---------------------------------------------------------------------------------------
// Single atom (E12): A is the complement of B(c, r + rp); the SES body is the vdW ball.

TEST(SesOracleSingleAtom, DistanceIsRMinusDistanceToCentre) {
  const Sphere atom{dvec3(0.3, -0.2, 0.1), 1.7};
  const double rp = 1.4, R = atom.r + rp;
  const SesOracle o({atom}, rp);
  EXPECT_TRUE(o.vertices().empty());
  std::mt19937_64 rng(1);
  std::uniform_real_distribution<double> s01(0.0, 1.0);
  for (int trial = 0; trial < 1000; ++trial) {
    const dvec3 u = randomUnit(rng);
    const double s = 4.0 * s01(rng);
    const dvec3 x = atom.c + s * u;
    const auto res = o.distanceToAccessible(x);
    if (s >= R) {
      EXPECT_EQ(res.kind, SesOracle::Result::Inside) << "trial " << trial;
      EXPECT_EQ(res.dist, 0.0);
    } else if (R - s <= o.exactUpTo()) {
      ASSERT_EQ(res.kind, SesOracle::Result::SpherePoint) << "trial " << trial;
      EXPECT_NEAR(res.dist, R - s, 1e-13) << "trial " << trial;
      EXPECT_EQ(res.atoms[0], 0);
      EXPECT_NEAR(glm::length(res.nearest - (atom.c + R * u)), 0.0, 1e-13);
    } else {
      EXPECT_EQ(res.kind, SesOracle::Result::Far) << "trial " << trial;
      EXPECT_GT(res.dist, o.exactUpTo());
      EXPECT_LE(res.dist, R - s + 1e-13);  // a lower bound
    }
  }
}

TEST(SesOracleSingleAtom, SesBodyIsTheVdwBall) {
  const Sphere atom{dvec3(1.0, 2.0, -3.0), 1.55};
  const SesOracle o({atom}, 1.4);
  std::mt19937_64 rng(2);
  for (int trial = 0; trial < 200; ++trial) {
    const dvec3 u = randomUnit(rng);
    EXPECT_TRUE(o.insideSesBody(atom.c + (atom.r - 1e-9) * u)) << "trial " << trial;
    EXPECT_FALSE(o.insideSesBody(atom.c + (atom.r + 1e-9) * u)) << "trial " << trial;
    EXPECT_NEAR(o.distanceToAccessible(atom.c + atom.r * u).dist, 1.4, 1e-14);
  }
}

TEST(SesOracleSingleAtom, MonteCarloVolumeMatchesBall) {
  const Sphere atom{dvec3(0.3, -0.2, 0.1), 1.7};
  const SesOracle o({atom}, 1.4);
  const auto v = sesVolumeMonteCarlo(o, 200000, 7, 2);
  const double exact = 4.0 / 3.0 * kPi * std::pow(atom.r, 3);
  EXPECT_EQ(v.samples, 200000u);
  EXPECT_GT(v.stderr_, 0.0);
  EXPECT_LT(std::abs(v.volume - exact), 4 * v.stderr_)
      << "MC " << v.volume << " +- " << v.stderr_ << " exact " << exact;
  EXPECT_LT(v.stderr_, 1e-3 * exact);  // RQMC should be far better than plain MC here
  const auto again = sesVolumeMonteCarlo(o, 200000, 7, 1);  // independent of thread count
  EXPECT_EQ(again.volume, v.volume);
}

// E1: a duplicated atom changes nothing; the tie shows up as a zero runner-up gap.
TEST(SesOracle, DuplicateAtomIsATie) {
  const Sphere atom{dvec3(0.5, 0.25, -1.0), 1.8};
  const SesOracle one({atom}, 1.4), two({atom, atom}, 1.4);
  std::mt19937_64 rng(8);
  for (int trial = 0; trial < 100; ++trial) {
    const dvec3 x = atom.c + 2.0 * randomUnit(rng);
    const auto a = one.distanceToAccessible(x), b = two.distanceToAccessible(x);
    EXPECT_EQ(a.dist, b.dist) << "trial " << trial;
    EXPECT_EQ(b.kind, SesOracle::Result::SpherePoint);
    EXPECT_EQ(b.runnerUpGap, 0.0);
  }
}

TEST(SesOracle, RejectsBadInput) {
  EXPECT_THROW(SesOracle({{dvec3(0.0), 1.7}}, 0.0), std::invalid_argument);
  EXPECT_THROW(SesOracle({{dvec3(0.0), -1.0}}, 1.4), std::invalid_argument);
  EXPECT_THROW(SesOracle({{dvec3(NAN, 0, 0), 1.0}}, 1.4), std::invalid_argument);
}

// ---------------------------------------------------------------------------------------
// Two atoms: saddle and convex patches built from the A.3 parametrisation.

struct PairGeometry {
  dvec3 cij, n, e1, e2;
  double d, t, R, thetaI, thetaJ;
};

PairGeometry pairGeometry(const Sphere& ai, const Sphere& aj, double rp) {
  PairGeometry g;
  const double Ri = ai.r + rp, Rj = aj.r + rp;
  g.d = glm::length(aj.c - ai.c);
  g.n = (aj.c - ai.c) / g.d;
  g.t = (g.d * g.d + Ri * Ri - Rj * Rj) / (2 * g.d);
  g.cij = ai.c + g.t * g.n;
  g.R = std::sqrt(Ri * Ri - g.t * g.t);
  g.e1 = glm::normalize(glm::cross(g.n, std::abs(g.n.x) < 0.9 ? dvec3(1, 0, 0) : dvec3(0, 1, 0)));
  g.e2 = glm::cross(g.n, g.e1);
  g.thetaI = std::atan2(-g.t, g.R);
  g.thetaJ = std::atan2(g.d - g.t, g.R);
  return g;
}

dvec3 torusPoint(const PairGeometry& g, double rp, double theta, double phi) {
  const dvec3 eRho = std::cos(phi) * g.e1 + std::sin(phi) * g.e2;
  return g.cij + (g.R - rp * std::cos(theta)) * eRho + rp * std::sin(theta) * g.n;
}

const std::vector<Sphere> kPair = {{dvec3(-2.70, 0, 0), 1.7}, {dvec3(2.75, 0, 0), 1.7}};

TEST(SesOracleTwoAtoms, SaddlePointsAreAtProbeRadiusOnTheArc) {
  const double rp = 1.5;
  const SesOracle o(kPair, rp);
  const PairGeometry g = pairGeometry(kPair[0], kPair[1], rp);
  ASSERT_GT(g.R, rp);  // ring torus
  std::mt19937_64 rng(3);
  std::uniform_real_distribution<double> f(0.02, 0.98), phi(-kPi, kPi);
  for (int trial = 0; trial < 2000; ++trial) {
    const double theta = g.thetaI + f(rng) * (g.thetaJ - g.thetaI);
    const double ph = phi(rng);
    const auto res = o.distanceToAccessible(torusPoint(g, rp, theta, ph));
    ASSERT_EQ(res.kind, SesOracle::Result::ArcPoint) << "trial " << trial;
    EXPECT_NEAR(res.dist, rp, 1e-12) << "trial " << trial;
    EXPECT_EQ(res.atoms[0], 0);
    EXPECT_EQ(res.atoms[1], 1);
    const dvec3 probe = g.cij + g.R * (std::cos(ph) * g.e1 + std::sin(ph) * g.e2);
    EXPECT_NEAR(glm::length(res.nearest - probe), 0.0, 1e-12) << "trial " << trial;
    EXPECT_GT(res.runnerUpGap, 0.0);
  }
}

TEST(SesOracleTwoAtoms, ConvexCapPointsAreAtProbeRadiusOnTheSphere) {
  const double rp = 1.5;
  const SesOracle o(kPair, rp);
  const PairGeometry g = pairGeometry(kPair[0], kPair[1], rp);
  std::mt19937_64 rng(4);
  for (int trial = 0; trial < 2000; ++trial) {
    const int i = trial % 2;
    const Sphere& a = kPair[i];
    const double R = a.r + rp;
    // Contact circle on atom i at u.n = t/R (i) or u.(-n) = (d - t)/R (j); the convex cap is
    // the side away from the partner.
    const dvec3 toward = i == 0 ? g.n : -g.n;
    const double limit = (i == 0 ? g.t : g.d - g.t) / R;
    dvec3 u = randomUnit(rng);
    if (glm::dot(u, toward) > limit - 0.02) continue;
    const auto res = o.distanceToAccessible(a.c + a.r * u);
    ASSERT_EQ(res.kind, SesOracle::Result::SpherePoint) << "trial " << trial;
    EXPECT_NEAR(res.dist, rp, 1e-13) << "trial " << trial;
    EXPECT_EQ(res.atoms[0], i);
    EXPECT_NEAR(glm::length(res.nearest - (a.c + R * u)), 0.0, 1e-12);
  }
}

// Spindle case (R < rp, A.3): the apple sheet is the SES, and the axis between the cusps
// c_ij +- h n is covered by the probes of the whole circle.
TEST(SesOracleTwoAtoms, SpindleTorusCuspsAndAppleSheet) {
  const double rp = 1.2;
  const SesOracle o(kPair, rp);
  const PairGeometry g = pairGeometry(kPair[0], kPair[1], rp);
  ASSERT_LT(g.R, rp);
  const double h = std::sqrt(rp * rp - g.R * g.R);
  const double thetaC = std::acos(g.R / rp);
  ASSERT_LT(g.thetaI, -thetaC);
  ASSERT_GT(g.thetaJ, thetaC);
  for (double a : {-h - 0.01, -h + 0.01, -0.3, 0.0, 0.2, h - 1e-6, h + 1e-6, h + 0.05}) {
    const auto res = o.distanceToAccessible(g.cij + a * g.n);
    ASSERT_EQ(res.kind, SesOracle::Result::ArcPoint) << "a = " << a;
    EXPECT_NEAR(res.dist, std::hypot(g.R, a), 1e-13) << "a = " << a;
    EXPECT_EQ(o.insideSesBody(g.cij + a * g.n), std::abs(a) > h) << "a = " << a;
  }
  std::mt19937_64 rng(5);
  std::uniform_real_distribution<double> f(0.02, 0.98), phi(-kPi, kPi);
  for (int trial = 0; trial < 1000; ++trial) {
    const double theta = trial % 2 ? thetaC + f(rng) * (g.thetaJ - thetaC)
                                   : g.thetaI + f(rng) * (-thetaC - g.thetaI);
    const auto res = o.distanceToAccessible(torusPoint(g, rp, theta, phi(rng)));
    ASSERT_EQ(res.kind, SesOracle::Result::ArcPoint) << "trial " << trial;
    EXPECT_NEAR(res.dist, rp, 1e-12) << "trial " << trial;
  }
}

// Ring-torus pair body as a solid of revolution: two spherical caps plus the neck
// pi * Int (R - sqrt(rp^2 - s^2))^2 ds between the contact circles.
TEST(SesOracleTwoAtoms, MonteCarloVolumeMatchesSolidOfRevolution) {
  const double rp = 1.5;
  const SesOracle o(kPair, rp);
  const PairGeometry g = pairGeometry(kPair[0], kPair[1], rp);
  const double r = kPair[0].r, Rx = r + rp;  // equal radii
  const double capHeight = r + g.t * r / Rx;  // from the far pole to the contact plane
  const double cap = kPi * capHeight * capHeight * (3 * r - capHeight) / 3;
  const double s1 = g.t * rp / Rx;  // neck spans s in [-s1, s1] about the circle plane
  auto neckPrimitive = [&](double s) {
    const double root = std::sqrt(rp * rp - s * s);
    return (g.R * g.R + rp * rp) * s - s * s * s / 3 -
           g.R * (s * root + rp * rp * std::asin(s / rp));
  };
  const double exact = 2 * cap + kPi * (neckPrimitive(s1) - neckPrimitive(-s1));
  const auto v = sesVolumeMonteCarlo(o, 400000, 11, 2);
  EXPECT_LT(std::abs(v.volume - exact), 4 * v.stderr_)
      << "MC " << v.volume << " +- " << v.stderr_ << " exact " << exact;
  EXPECT_LT(v.stderr_, 2e-3 * exact);
}

TEST(FreesasaOracle, TwoAtomPairMatchesMsmsFigure) {
  std::vector<Sphere> atoms = kPair;
  roundForPdb(atoms);
  const auto fs = runFreesasa(atoms, 1.5, 1000);
  ASSERT_EQ(fs.perAtom.size(), 2u);
  EXPECT_LT(std::abs(fs.total / 238.258 - 1), 2e-4) << "FreeSASA total " << fs.total;
  // Exact: each extended sphere loses a cap of height R - t, leaving 2 pi R (R + t).
  const double R = 3.2, t = 5.45 / 2;
  EXPECT_LT(std::abs(fs.total / (2 * 2 * kPi * R * (R + t)) - 1), 1e-4);
  std::cout.precision(10);
  std::cout << "FreeSASA L&R 1000 two-atom SAS: " << fs.total << " A^2 (exact "
            << 4 * kPi * R * (R + t) << ")\n";
}

// ---------------------------------------------------------------------------------------
// Three atoms: the probe touching all three is on the SAS; its concave patch is at rp.

TEST(SesOracleThreeAtoms, ProbePositionAndConcavePatch) {
  const double rp = 1.4;
  const std::vector<Sphere> atoms = {
      {dvec3(0.0, 0.0, 0.0), 1.70}, {dvec3(3.0, 0.4, 0.1), 1.55}, {dvec3(1.2, 2.8, -0.3), 1.80}};
  const SesOracle o(atoms, rp);
  dvec3 pp, pm;
  ASSERT_TRUE(probePositionsConnolly(atoms[0], atoms[1], atoms[2], rp, pp, pm));
  ASSERT_GT(glm::length(pp - pm), 2 * rp);  // twin probes do not clip each other
  ASSERT_EQ(o.vertices().size(), 2u);
  for (const dvec3& p : {pp, pm}) {
    double best = 1e300;
    for (const dvec3& v : o.vertices()) best = std::min(best, glm::length(v - p));
    EXPECT_LT(best, 1e-12);
    EXPECT_LT(o.distanceToAccessible(p).dist, 1e-12);  // on the boundary of A
  }
  std::mt19937_64 rng(6);
  std::uniform_real_distribution<double> w(0.1, 1.0);
  for (int trial = 0; trial < 2000; ++trial) {
    const dvec3 p = trial % 2 ? pp : pm;
    dvec3 u(0.0);
    for (const auto& a : atoms) u += w(rng) * (a.c - p) / (a.r + rp);  // cone of contacts
    u = glm::normalize(u);
    const auto res = o.distanceToAccessible(p + rp * u);
    ASSERT_EQ(res.kind, SesOracle::Result::Vertex) << "trial " << trial;
    EXPECT_NEAR(res.dist, rp, 1e-12) << "trial " << trial;
    EXPECT_EQ(res.atoms[0], 0);
    EXPECT_EQ(res.atoms[1], 1);
    EXPECT_EQ(res.atoms[2], 2);
    EXPECT_LT(glm::length(res.nearest - p), 1e-12);
    EXPECT_GT(res.runnerUpGap, 0.0);
    EXPECT_FALSE(o.insideSesBody(p + (rp - 1e-9) * u));
    EXPECT_TRUE(o.insideSesBody(p + (rp + 1e-9) * u));
  }
}

// ---------------------------------------------------------------------------------------
// Random clusters against a brute force over dense samples of the SAS (D.1 "checks done"):
// the oracle never exceeds the sampled minimum, and exceeds it by at most the sampling gap.

TEST(SesOracle, MatchesSampledSasOnRandomClusters) {
  const double rp = 1.4;
  constexpr int kPerSphere = 40000;
  const double golden = kPi * (3 - std::sqrt(5.0));
  double worstGap = 0;
  int kinds[5] = {};
  for (int cluster = 0; cluster < 12; ++cluster) {
    std::mt19937_64 rng(100 + cluster);
    std::uniform_real_distribution<double> pos(-2.5, 2.5), rad(1.2, 2.0);
    std::vector<Sphere> atoms(6);
    for (auto& a : atoms) a = {dvec3(pos(rng), pos(rng), pos(rng)), rad(rng)};
    const SesOracle o(atoms, rp);
    auto inA = [&](const dvec3& y, double tol) {
      for (const auto& a : atoms)
        if (glm::length(y - a.c) < (a.r + rp) * (1 - tol)) return false;
      return true;
    };
    std::vector<dvec3> sas, sasInward;  // samples and the inward normal there
    for (const auto& a : atoms)
      for (int k = 0; k < kPerSphere; ++k) {  // Fibonacci sphere
        const double z = 1 - (2 * k + 1.0) / kPerSphere, rr = std::sqrt(1 - z * z);
        const dvec3 y = a.c + (a.r + rp) * dvec3(rr * std::cos(golden * k),
                                                 rr * std::sin(golden * k), z);
        if (inA(y, 1e-12)) {
          sas.push_back(y);
          sasInward.push_back(glm::normalize(a.c - y));
        }
      }
    ASSERT_FALSE(sas.empty());
    std::uniform_real_distribution<double> box(-6.0, 6.0), offset(0.0, 2.2);
    std::uniform_int_distribution<std::size_t> pickSas(0, sas.size() - 1);
    const auto& vs = o.vertices();
    std::uniform_int_distribution<std::size_t> pickVertex(0, vs.empty() ? 0 : vs.size() - 1);
    for (int q = 0; q < 240; ++q) {
      // A third uniform in a box, a third just inside the SAS, a third near SAS vertices.
      dvec3 x(box(rng), box(rng), box(rng));
      if (q % 3 == 1 || (q % 3 == 2 && vs.empty())) {
        const std::size_t k = pickSas(rng);
        dvec3 v = randomUnit(rng);
        if (glm::dot(v, sasInward[k]) < 0) v = -v;
        x = sas[k] + offset(rng) * v;
      } else if (q % 3 == 2) {
        x = vs[pickVertex(rng)] + offset(rng) * randomUnit(rng);
      }
      const auto res = o.distanceToAccessible(x);
      ++kinds[res.kind];
      const bool xInA = inA(x, 0);
      ASSERT_EQ(res.kind == SesOracle::Result::Inside, xInA) << "cluster " << cluster;
      if (xInA) continue;
      double brute = 1e300;
      for (const auto& y : sas) brute = std::min(brute, glm::length(x - y));
      if (res.kind == SesOracle::Result::Far) {
        EXPECT_GT(brute, o.exactUpTo() - 1e-9) << "cluster " << cluster << " query " << q;
        continue;
      }
      EXPECT_LE(res.dist, brute + 1e-9) << "cluster " << cluster << " query " << q;
      EXPECT_GE(res.dist, brute - 0.08) << "cluster " << cluster << " query " << q;
      worstGap = std::max(worstGap, brute - res.dist);
      EXPECT_NEAR(glm::length(res.nearest - x), res.dist, 1e-12);
      EXPECT_TRUE(inA(res.nearest, 1e-9)) << "cluster " << cluster << " query " << q;
    }
  }
  std::cout << "worst sampled-SAS gap: " << worstGap << " A; kinds inside/sphere/arc/vertex/far "
            << kinds[0] << "/" << kinds[1] << "/" << kinds[2] << "/" << kinds[3] << "/"
            << kinds[4] << "\n";
  for (int k = 0; k < 5; ++k) EXPECT_GE(kinds[k], 20) << "kind " << k << " barely exercised";
}

// The grid-accelerated vertex set equals an O(n^3) brute force with Connolly's formula.
TEST(SesOracle, VerticesMatchBruteForce) {
  const double rp = 1.4;
  const auto atoms = randomMolecule(80, 21);
  const SesOracle o(atoms, rp);
  std::vector<std::pair<std::array<int, 3>, dvec3>> brute;
  const int n = static_cast<int>(atoms.size());
  for (int i = 0; i < n; ++i)
    for (int j = i + 1; j < n; ++j)
      for (int k = j + 1; k < n; ++k) {
        dvec3 ps[2];
        if (!probePositionsConnolly(atoms[i], atoms[j], atoms[k], rp, ps[0], ps[1])) continue;
        for (const dvec3& p : ps) {
          bool ok = true;
          for (int m = 0; m < n && ok; ++m)
            if (m != i && m != j && m != k &&
                glm::length(p - atoms[m].c) < (atoms[m].r + rp) * (1 - 1e-10))
              ok = false;
          if (ok) brute.push_back({{i, j, k}, p});
        }
      }
  ASSERT_EQ(o.vertices().size(), brute.size());
  ASSERT_GT(brute.size(), 20u);
  for (const auto& [t, p] : brute) {
    bool found = false;
    for (std::size_t v = 0; v < o.vertices().size() && !found; ++v)
      found = o.vertexAtoms()[v] == t && glm::length(o.vertices()[v] - p) < 1e-9;
    EXPECT_TRUE(found) << t[0] << " " << t[1] << " " << t[2];
  }
}

// Throughput on a ~300-atom compact molecule (reported, loosely bounded).
TEST(SesOracle, QuerySpeedOn300Atoms) {
  const auto atoms = randomMolecule(300, 31);
  const auto t0 = std::chrono::steady_clock::now();
  const SesOracle o(atoms, 1.4);
  const auto t1 = std::chrono::steady_clock::now();
  std::mt19937_64 rng(32);
  std::uniform_real_distribution<double> u(0.0, 1.0);
  constexpr int kQueries = 100000;
  int inBody = 0;
  for (int q = 0; q < kQueries; ++q) {
    const dvec3 x = o.boxLo() + dvec3(u(rng), u(rng), u(rng)) * (o.boxHi() - o.boxLo());
    inBody += o.insideSesBody(x);
  }
  const auto t2 = std::chrono::steady_clock::now();
  const double build = std::chrono::duration<double>(t1 - t0).count();
  const double rate = kQueries / std::chrono::duration<double>(t2 - t1).count();
  std::cout << "300 atoms: " << o.vertices().size() << " vertices, build " << build
            << " s, " << rate << " queries/s, body fraction "
            << static_cast<double>(inBody) / kQueries << "\n";
  EXPECT_GT(rate, 2e3);  // a floor that holds even in sanitizer builds
}

// ---------------------------------------------------------------------------------------
// FreeSASA plumbing.

TEST(FreesasaOracle, PerAtomAreasSumToTotal) {
  auto atoms = randomMolecule(40, 41);
  roundForPdb(atoms);
  const auto fs = runFreesasa(atoms, 1.4, 200);
  ASSERT_EQ(fs.perAtom.size(), atoms.size());
  double sum = 0;
  for (double a : fs.perAtom) {
    EXPECT_GE(a, 0.0);
    sum += a;
  }
  EXPECT_NEAR(sum, fs.total, 1e-9 * fs.total);
  EXPECT_GT(fs.total, 100.0);
}

TEST(FreesasaOracle, KeepsEveryAtomBeyondPdbNumberingLimits) {
  std::vector<Sphere> atoms;
  for (int i = 0; i < 10050; ++i)  // isolated atoms, 10 Å apart
    atoms.push_back({dvec3(10.0 * (i % 22), 10.0 * (i / 22 % 22), 10.0 * (i / 484)), 1.5});
  const auto fs = runFreesasa(atoms, 1.4, 20);
  ASSERT_EQ(fs.perAtom.size(), atoms.size());
  const double exact = 4 * kPi * 2.9 * 2.9;
  for (std::size_t i = 0; i < atoms.size(); i += 997) EXPECT_NEAR(fs.perAtom[i], exact, 0.02 * exact);
}

TEST(FreesasaOracle, RejectsRadiiTheOccupancyColumnCannotHold) {
  EXPECT_THROW(runFreesasa({{dvec3(0.0), 1.705}}, 1.4), std::invalid_argument);
  EXPECT_THROW(runFreesasa({{dvec3(12345.0, 0, 0), 1.7}}, 1.4), std::invalid_argument);
}

}  // namespace
}  // namespace surftrace::oracle

// The MSS patch list against the skin function from its definition (ORACLES D.3): points
// sampled on every patch of 1CRN, 1GRM and 1VIS at s = 0.3 and 0.5 are certified, by the KKT
// conditions of the skin QP over all atoms, to lie on the skin (|G| <= 1e-9 of the weights'
// scale) in the mixed cell of the patch's own simplex (λ >= 0 on it, no atom does better).
#include <cmath>
#include <iostream>
#include <limits>
#include <random>
#include <span>
#include <string>
#include <vector>

#include <glm/geometric.hpp>
#include <gtest/gtest.h>

#include "build/io/molecule.hpp"
#include "build/mss/mss_area.hpp"
#include "build/mss/mss_builder.hpp"
#include "oracles/skin_certificate.hpp"

namespace surftrace::build {
namespace {

constexpr double kTolerance = 1e-9;  // relative to max w over the simplex (Å²)

struct Sample {
  std::size_t patch;
  glm::dvec3 x;
};

// Up to `per` points on each patch: roots of the quadric along random lines through its
// bounding ball (long double), kept when inside the ball and every cell plane.
std::vector<Sample> samplePatches(const PatchList& p, int per, std::uint64_t seed) {
  std::mt19937_64 rng(seed);
  std::uniform_real_distribution<double> u(-1.0, 1.0);
  std::vector<Sample> out;
  const MssQuadrics& q = p.mss;
  for (std::size_t k = 0; k < q.size(); ++k) {
    int got = 0;
    for (int tries = 0; tries < 200 && got < per; ++tries) {
      const double R = q.boundRadius[k];
      const glm::dvec3 o = R * glm::dvec3(u(rng), u(rng), u(rng));  // relative to the centre
      const glm::dvec3 d = glm::normalize(glm::dvec3(u(rng), u(rng), u(rng)));
      using Real = long double;
      const Real da = glm::dot(d, q.axis[k]), oa = glm::dot(o, q.axis[k]);
      const Real A = q.radialCoeff[k] + q.axialCoeff[k] * da * da;
      const Real B = q.radialCoeff[k] * static_cast<Real>(glm::dot(o, d)) + q.axialCoeff[k] * oa * da;
      const Real C = q.radialCoeff[k] * static_cast<Real>(glm::dot(o, o)) + q.axialCoeff[k] * oa * oa + q.constant[k];
      const Real disc = B * B - A * C;
      if (A == 0 || disc < 0) continue;
      for (const Real t : {(-B - std::sqrt(disc)) / A, (-B + std::sqrt(disc)) / A}) {
        const glm::dvec3 x = q.center[k] + o + static_cast<double>(t) * d;
        if (glm::length(x - q.center[k]) > R) continue;
        bool inside = true;
        for (std::uint32_t c = 0; c < q.cellCount[k] && inside; ++c) {
          const Plane& plane = p.cellPlanes[q.cellBegin[k] + c];
          inside = glm::dot(glm::dvec3(plane), x) + plane.w <= 0.0;
        }
        if (!inside) continue;
        out.push_back({k, x});
        ++got;
      }
    }
  }
  return out;
}

// Certifies up to two points per patch; returns the number of failures (first five reported).
int certifyList(const std::string& name, std::span<const glm::dvec3> centers, std::span<const double> radii, double s,
                bool requireEveryKind) {
  const PatchList p = buildMss(centers, radii, {s});
  const std::vector<Sample> samples = samplePatches(p, 2, 11);
  int byKind[4] = {0, 0, 0, 0};
  double worstValue = 0.0, worstLambda = 0.0, worstGap = 0.0;
  int failures = 0;
  for (const Sample& sample : samples) {
    const glm::uvec4 a = p.mss.atoms[sample.patch];
    const std::uint32_t kind = p.mss.kind[sample.patch];
    std::vector<unsigned> simplex(kind + 1);
    for (std::uint32_t k = 0; k <= kind; ++k) simplex[k] = a[static_cast<int>(k)];
    const oracle::SkinCertificate c = oracle::certifySkinPoint(centers, radii, s, simplex, sample.x);
    ++byKind[kind];
    const double value = std::abs(c.value) / c.scale, lambda = -c.minLambda, gap = -c.minGap / c.scale;
    worstValue = std::max(worstValue, value);
    worstLambda = std::max(worstLambda, lambda);
    worstGap = std::max(worstGap, gap);
    const bool ok = c.solved && value <= kTolerance && lambda <= kTolerance && gap <= kTolerance;
    if (!ok && ++failures <= 5)
      ADD_FAILURE() << name << " s = " << s << ": patch " << sample.patch << " (kind " << kind << ") point is not "
                    << "certified: |G|/w " << value << ", min λ " << -lambda << ", gap/w " << -gap;
  }
  std::cout << "[ stats    ] " << name << " s = " << s << ": " << samples.size() << " points on " << p.mss.size()
            << " patches (by kind " << byKind[0] << " " << byKind[1] << " " << byKind[2] << " " << byKind[3]
            << "); worst |G|/w " << worstValue << ", negative λ " << worstLambda << ", certificate gap/w " << worstGap
            << "\n";
  if (requireEveryKind) {
    for (int kind = 0; kind < 4; ++kind) EXPECT_GT(byKind[kind], 50) << name << " s = " << s << " kind " << kind;
  }
  return failures;
}

TEST(MssOracle, EveryPatchIsSkinInItsOwnMixedCell) {
  for (const char* file : {"structures/1crn.pdb", "paper/1grm.pdb.gz", "paper/1vis.pdb.gz"}) {
    const Molecule m = readMolecule(std::string(SURFTRACE_TEST_DATA) + "/" + file);
    for (double s : {0.3, 0.5}) EXPECT_EQ(certifyList(file, m.centers, m.radii, s, true), 0);
  }
}

// Co-spherical and co-planar atoms (ORACLES E.6): the fullerene, a cube, a lattice.
TEST(MssOracle, DegenerateSetsAreSkinToo) {
  const Molecule fullerene = readMolecule(std::string(SURFTRACE_TEST_DATA) + "/small/fullerene.pdb");
  std::vector<glm::dvec3> cube, lattice;
  for (int k = 0; k < 8; ++k) cube.emplace_back(k & 1 ? 2.8 : 0.0, k & 2 ? 2.8 : 0.0, k & 4 ? 2.8 : 0.0);
  for (int x = 0; x < 4; ++x)
    for (int y = 0; y < 4; ++y)
      for (int z = 0; z < 3; ++z) lattice.emplace_back(3.0 * x, 3.0 * y, 3.0 * z);
  for (double s : {0.3, 0.5}) {
    EXPECT_EQ(certifyList("fullerene", fullerene.centers, std::vector<double>(60, 1.7), s, false), 0);
    EXPECT_EQ(certifyList("cube", cube, std::vector<double>(8, 1.7), s, false), 0);
    EXPECT_EQ(certifyList("lattice", lattice, std::vector<double>(lattice.size(), 1.7), s, false), 0);
  }
}

// The volume from the patches (divergence theorem) against a Monte-Carlo count of points
// the skin QP certifies inside (skinSign), within 3σ; undecided points (on the skin to
// rounding) are rare and counted as half.
TEST(MssOracle, VolumeMatchesMonteCarloOfTheSkinFunction) {
  for (const char* file : {"structures/1crn.pdb", "paper/1grm.pdb.gz"}) {
    const Molecule m = readMolecule(std::string(SURFTRACE_TEST_DATA) + "/" + file);
    for (double s : {0.3, 0.5}) {
      const PatchList p = buildMss(m.centers, m.radii, {s});
      const MssAreas a = computeMssAreas(p, m.centers);
      glm::dvec3 lo(std::numeric_limits<double>::infinity()), hi(-std::numeric_limits<double>::infinity());
      for (std::size_t k = 0; k < p.mss.size(); ++k) {
        lo = glm::min(lo, p.mss.center[k] - p.mss.boundRadius[k]);
        hi = glm::max(hi, p.mss.center[k] + p.mss.boundRadius[k]);
      }
      std::mt19937_64 rng(23);
      std::uniform_real_distribution<double> u(0.0, 1.0);
      const int samples = 60000;
      double inside = 0.0;
      for (int k = 0; k < samples; ++k) {
        const glm::dvec3 x = lo + (hi - lo) * glm::dvec3(u(rng), u(rng), u(rng));
        const int sign = oracle::skinSign(m.centers, m.radii, s, x);
        inside += sign < 0 ? 1.0 : (sign == 0 ? 0.5 : 0.0);
      }
      const double box = (hi.x - lo.x) * (hi.y - lo.y) * (hi.z - lo.z), f = inside / samples;
      const double mc = box * f, sigma = box * std::sqrt(f * (1 - f) / samples);
      std::cout << "[ stats    ] " << file << " s = " << s << ": volume " << a.volume << " Å³, Monte Carlo " << mc << " ± "
                << sigma << " (" << (a.volume - mc) / sigma << " σ)\n";
      EXPECT_NEAR(a.volume, mc, 3 * sigma) << file << " s = " << s;
    }
  }
}

// The certificate can fail: a point of a two-atom neck claimed for one atom's sphere cell, or
// a point off the skin, is rejected (the test above could not pass by construction).
TEST(MssOracle, CertificateRejectsWrongCellsAndPointsOffTheSkin) {
  const double ri = 1.5, rj = 1.2, d = 3.0, s = 0.5;
  const std::vector<glm::dvec3> c{{0, 0, 0}, {d, 0, 0}};
  const std::vector<double> r{ri, rj};
  const PatchList p = buildMss(c, r, {s});
  std::size_t edge = p.mss.size();
  for (std::size_t k = 0; k < p.mss.size(); ++k)
    if (p.mss.kind[k] == static_cast<std::uint32_t>(MssKind::Edge)) edge = k;
  ASSERT_LT(edge, p.mss.size());
  // The waist: the orthocentre plus the waist radius √(−s w_X) across the axis.
  const double wX = p.mss.constant[edge] / (s * (1 - s));
  const glm::dvec3 waist = p.mss.center[edge] + glm::dvec3(0, std::sqrt(-s * wX), 0);
  const std::vector<unsigned> pair{0, 1}, first{0};
  const oracle::SkinCertificate right = oracle::certifySkinPoint(c, r, s, pair, waist);
  EXPECT_LE(std::abs(right.value) / right.scale, 1e-12);
  EXPECT_GE(right.minLambda, 0.0);
  EXPECT_GE(right.minGap / right.scale, -1e-12);
  const oracle::SkinCertificate wrongCell = oracle::certifySkinPoint(c, r, s, first, waist);
  EXPECT_LT(wrongCell.minGap / wrongCell.scale, -1e-3);
  const oracle::SkinCertificate off = oracle::certifySkinPoint(c, r, s, pair, waist + glm::dvec3(0, 0.01, 0));
  EXPECT_GT(std::abs(off.value) / off.scale, 1e-4);
}

}  // namespace
}  // namespace surftrace::build

// SES patches and areas against independent oracles on real molecules: the per-point
// distance to the probe-accessible region (ORACLES D.1), a Monte Carlo volume with the
// same inside test, and FreeSASA's Lee–Richards SAS areas (D.2).
#include <algorithm>
#include <cmath>
#include <cstdio>
#include <numbers>
#include <random>

#include <glm/geometric.hpp>
#include <gtest/gtest.h>

#include "build/core/vector_math.hpp"
#include "build/ses/contour_buildup.hpp"
#include "build/io/molecule.hpp"
#include "build/ses/surface_area.hpp"
#include "oracles/freesasa_oracle.hpp"
#include "oracles/ses_oracle.hpp"

namespace surftrace::build {
namespace {

constexpr double kRp = 1.4;

std::vector<oracle::Sphere> atomsOf(const std::string& file) {
  const Molecule m = readMolecule(std::string(SURFTRACE_TEST_DATA) + "/" + file);
  std::vector<oracle::Sphere> atoms;
  for (std::size_t i = 0; i < m.size(); ++i) atoms.push_back({m.centers[i], m.radii[i]});
  oracle::roundForPdb(atoms);  // so FreeSASA sees exactly the same atoms
  return atoms;
}

PatchList buildFrom(const std::vector<oracle::Sphere>& atoms) {
  std::vector<glm::dvec3> c;
  std::vector<double> r;
  for (const auto& a : atoms) c.push_back(a.c), r.push_back(a.r);
  return buildSes(c, r, SesParams{kRp});
}

class RealMolecule : public testing::TestWithParam<std::string> {};

// Points sampled on every torus and every concave triangle (inside its clipping planes)
// are at distance exactly rp from the probe-accessible region.
TEST_P(RealMolecule, PatchPointsLieOnTheSes) {
  const auto atoms = atomsOf(GetParam());
  const PatchList p = buildFrom(atoms);
  const oracle::SesOracle oracle(atoms, kRp);
  std::mt19937_64 rng(42);
  std::uniform_real_distribution<double> u01(0.0, 1.0);
  int checked = 0;
  double worst = 0.0;

  for (std::size_t t = 0; t < p.tori.size(); ++t) {
    const double R = p.tori.bigRadius[t];
    double lo = p.tori.thetaI[t], hi = p.tori.thetaJ[t];
    for (int s = 0; s < 4; ++s) {
      const double theta = lo + (hi - lo) * u01(rng);
      if (R < kRp && std::abs(theta) < std::acos(R / kRp)) continue;  // spindle: not SES
      const double phi = p.tori.phiExtent[t] * u01(rng);
      const glm::dvec3 n = p.tori.axis[t], e1 = p.tori.e1[t], e2 = glm::cross(n, e1);
      const glm::dvec3 er = std::cos(phi) * e1 + std::sin(phi) * e2;
      const glm::dvec3 x = p.tori.center[t] + (R - kRp * std::cos(theta)) * er + kRp * std::sin(theta) * n;
      const double err = std::abs(oracle.distanceToAccessible(x).dist - kRp);
      worst = std::max(worst, err);
      ASSERT_LT(err, 1e-9) << "torus " << t << " atoms " << p.tori.atomI[t] << "," << p.tori.atomJ[t];
      ++checked;
    }
  }
  for (std::size_t c = 0; c < p.concave.size(); ++c) {
    for (int s = 0; s < 4; ++s) {
      double w[3] = {u01(rng), u01(rng), u01(rng)};
      const glm::dvec3 dir = glm::normalize(w[0] * p.concave.dirI[c] + w[1] * p.concave.dirJ[c] + w[2] * p.concave.dirK[c]);
      const glm::dvec3 x = p.concave.probe[c] + kRp * dir;
      bool clipped = false;
      for (std::uint32_t k = 0; k < p.concave.clipCount[c]; ++k) {
        const Plane& pl = p.clipPlanes[p.concave.clipBegin[c] + k];
        clipped = clipped || glm::dot(glm::dvec3(pl), x) + pl.w > 0.0;
      }
      if (clipped) continue;
      const double err = std::abs(oracle.distanceToAccessible(x).dist - kRp);
      worst = std::max(worst, err);
      ASSERT_LT(err, 1e-9) << "concave " << c;
      ++checked;
    }
  }
  // Convex patches: the fraction of each vdW sphere that the oracle finds on the SES,
  // summed over the atoms, estimates the convex area (a binomial count per atom).
  std::normal_distribution<double> g;
  double sampled = 0.0, variance = 0.0, stored = 0.0;
  const int perAtom = 200;
  for (std::size_t k = 0; k < p.convex.size(); ++k) {
    int onSes = 0;
    for (int s = 0; s < perAtom; ++s) {
      const glm::dvec3 dir = glm::normalize(glm::dvec3(g(rng), g(rng), g(rng)));
      const glm::dvec3 x = p.convex.center[k] + p.convex.radius[k] * dir;
      const auto r = oracle.distanceToAccessible(x);
      if (r.kind == oracle::SesOracle::Result::SpherePoint && r.atoms[0] == static_cast<int>(p.convex.atom[k])) {
        EXPECT_LT(std::abs(r.dist - kRp), 1e-9) << "convex patch of atom " << p.convex.atom[k];
        ++onSes;
        ++checked;
      }
    }
    const double sphere = 4 * std::numbers::pi * p.convex.radius[k] * p.convex.radius[k];
    const double f = static_cast<double>(onSes) / perAtom;
    sampled += f * sphere;
    variance += sphere * sphere * std::max(f * (1 - f), 1.0 / perAtom) / perAtom;
    stored += p.convex.area[k];
  }
  EXPECT_NEAR(stored, sampled, 5 * std::sqrt(variance)) << "convex area: patches vs oracle sampling";
  EXPECT_GT(checked, 100);
  RecordProperty("points", checked);
  RecordProperty("worst_error", std::to_string(worst));
}

// Every atom the oracle finds exposed (a sphere point of it is at distance rp) has a convex
// patch, and every concave patch's probe position is one of the oracle's SAS vertices.
TEST_P(RealMolecule, ConcavePatchesAreTheOraclesVertices) {
  const auto atoms = atomsOf(GetParam());
  const PatchList p = buildFrom(atoms);
  const oracle::SesOracle oracle(atoms, kRp);
  EXPECT_EQ(p.concave.size(), oracle.vertices().size());
  for (std::size_t c = 0; c < p.concave.size(); ++c) {
    const auto r = oracle.distanceToAccessible(p.concave.probe[c]);
    EXPECT_LT(r.dist, 1e-9) << "probe " << c << " is not on the SAS";
  }
}

// SAS areas against FreeSASA (Lee–Richards, 1000 slices per atom): total within 1e-4
// relative and each atom within 0.05 Å² (FreeSASA's own error is about 2e-5).
TEST_P(RealMolecule, SasAreaMatchesFreesasa) {
  const auto atoms = atomsOf(GetParam());
  const SurfaceAreas a = computeAreas(buildFrom(atoms));
  const oracle::FreesasaResult f = oracle::runFreesasa(atoms, kRp, 1000);
  ASSERT_EQ(f.perAtom.size(), atoms.size());
  EXPECT_NEAR(a.sas / f.total, 1.0, 1e-4) << "ours " << a.sas << " FreeSASA " << f.total;
  double worst = 0.0;
  for (std::size_t i = 0; i < atoms.size(); ++i) {
    worst = std::max(worst, std::abs(a.sasPerAtom[i] - f.perAtom[i]));
    EXPECT_NEAR(a.sasPerAtom[i], f.perAtom[i], 0.05) << "atom " << i;
  }
  RecordProperty("sas_ours", std::to_string(a.sas));
  RecordProperty("sas_freesasa", std::to_string(f.total));
  RecordProperty("worst_atom_error", std::to_string(worst));
  std::printf("%s: SAS ours %.4f, FreeSASA L&R 1000 %.4f (rel %.2e), worst atom %.4f Å²\n", GetParam().c_str(), a.sas,
              f.total, a.sas / f.total - 1.0, worst);
}

INSTANTIATE_TEST_SUITE_P(Ses, RealMolecule,
                         testing::Values("paper/1grm.pdb.gz", "structures/1crn.pdb", "structures/1ubq.pdb.gz"),
                         [](const auto& param) {
                           std::string name = param.param.substr(param.param.find('/') + 1);
                           return name.substr(0, name.find('.'));
                         });

// The SES volume from the divergence theorem against a Monte Carlo estimate with the
// oracle's inside test: agreement within 4 standard errors.
TEST(SesVolume, MatchesMonteCarlo) {
  const auto atoms = atomsOf("paper/1grm.pdb.gz");
  const SurfaceAreas a = computeAreas(buildFrom(atoms));
  const oracle::SesOracle oracle(atoms, kRp);
  const oracle::VolumeEstimate mc = oracle::sesVolumeMonteCarlo(oracle, 200000, 7);
  std::printf("1GRM SES volume: patches %.3f Å³, Monte Carlo %.3f ± %.3f Å³\n", a.sesVolume, mc.volume, mc.stderr_);
  EXPECT_NEAR(a.sesVolume, mc.volume, 4 * mc.stderr_);
}

// Every concave patch's area (sphere minus caps by Gauss–Bonnet, summed into the SES
// area and volume) against sampling: directions drawn uniformly in a cap around the
// triangle, counted when inside the triangle's cone and on the kept side of every clipping
// plane. 1AF6 has patches where clipping circles and an edge's great circle cross at one
// point; eleven of them came out up to 6 sr too large before arcs were joined by position.
TEST(ConcaveArea, EveryPatchOf1af6MatchesSampling) {
  const Molecule m = readMolecule(std::string(SURFTRACE_TEST_DATA) + "/paper/1af6.pdb.gz");
  const PatchList p = buildSes(m.centers, m.radii, SesParams{kRp});
  const SurfaceAreas areas = computeAreas(p);
  const auto& cv = p.concave;
  std::mt19937_64 rng(20261121);
  std::uniform_real_distribution<double> uni(0.0, 1.0);
  constexpr int kSamples = 4000;
  double sum = 0.0, worstSigmas = 0.0;
  for (std::size_t c = 0; c < cv.size(); ++c) {
    const glm::dvec3 d[3] = {cv.dirI[c], cv.dirJ[c], cv.dirK[c]};
    glm::dvec3 edge[3];
    for (int e = 0; e < 3; ++e) {
      edge[e] = glm::cross(d[e], d[(e + 1) % 3]);
      if (glm::dot(edge[e], d[(e + 2) % 3]) < 0.0) edge[e] = -edge[e];
    }
    // Bounding cap: around the corners' mean, through the farthest corner when that is
    // less than 90° away (a convex cap then holds the triangle), else the whole sphere.
    const glm::dvec3 g = glm::normalize(d[0] + d[1] + d[2]);
    double cosBeta = std::min({glm::dot(g, d[0]), glm::dot(g, d[1]), glm::dot(g, d[2])}) - 1e-9;
    if (!(cosBeta > 0.0)) cosBeta = -1.0;
    const glm::dvec3 e1 = perpendicularTo(g), e2 = glm::cross(g, e1);
    int in = 0;
    for (int k = 0; k < kSamples; ++k) {
      const double z = 1.0 - uni(rng) * (1.0 - cosBeta), phi = 2.0 * std::numbers::pi * uni(rng);
      const double r = std::sqrt(std::max(0.0, 1.0 - z * z));
      const glm::dvec3 w = z * g + r * (std::cos(phi) * e1 + std::sin(phi) * e2);
      bool inside = glm::dot(w, edge[0]) >= 0.0 && glm::dot(w, edge[1]) >= 0.0 && glm::dot(w, edge[2]) >= 0.0;
      const glm::dvec3 x = cv.probe[c] + kRp * w;
      for (std::uint32_t q = 0; inside && q < cv.clipCount[c]; ++q) {
        const Plane& pl = p.clipPlanes[cv.clipBegin[c] + q];
        inside = glm::dot(glm::dvec3(pl), x) + pl.w <= 0.0;
      }
      in += inside ? 1 : 0;
    }
    const double capArea = 2.0 * std::numbers::pi * (1.0 - cosBeta) * kRp * kRp;
    const double f = static_cast<double>(in) / kSamples;
    const double estimate = capArea * f;
    // Binomial error, floored at one sample's worth so that empty and full counts tolerate
    // the patches whose area is a sliver of the cap (or nearly all of it).
    const double sigma = capArea * std::max(std::sqrt(f * (1.0 - f) / kSamples), 1.0 / kSamples);
    // The patch's area: the per-atom split gives it back as a third to each of its atoms;
    // recompute it alone through the same total instead, from a one-patch list.
    PatchList one;
    one.params = p.params;
    one.concave.probe = {cv.probe[c]};
    one.concave.dirI = {cv.dirI[c]};
    one.concave.dirJ = {cv.dirJ[c]};
    one.concave.dirK = {cv.dirK[c]};
    one.concave.atomI = {0};
    one.concave.atomJ = {0};
    one.concave.atomK = {0};
    one.concave.component = {0};
    one.concave.clipBegin = {0};
    one.concave.clipCount = {cv.clipCount[c]};
    one.clipPlanes.assign(p.clipPlanes.begin() + cv.clipBegin[c], p.clipPlanes.begin() + cv.clipBegin[c] + cv.clipCount[c]);
    one.params.atomCount = 1;
    const double area = computeAreas(one).sesConcave;
    sum += area;
    worstSigmas = std::max(worstSigmas, std::abs(area - estimate) / sigma);
    ASSERT_NEAR(area, estimate, 6.0 * sigma) << "concave patch " << c << " of 1AF6, " << cv.clipCount[c] << " planes";
  }
  std::printf("1AF6: %zu concave patches, %.3f Å² in all; worst deviation from sampling %.2f sigma\n", cv.size(), sum,
              worstSigmas);
  EXPECT_NEAR(sum, areas.sesConcave, 1e-6 * sum);
}

}  // namespace
}  // namespace surftrace::build

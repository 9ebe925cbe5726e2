// SES construction against formulas and a peer tool (MSMS), and its determinism.
#include "build/ses/contour_buildup.hpp"

#include <cstring>
#include <numbers>
#include <random>
#include <string>

#include <algorithm>
#include <glm/vector_relational.hpp>

#include <gtest/gtest.h>
#include <glm/geometric.hpp>
#include <tbb/global_control.h>

#include "build/spherical_region.hpp"
#include "build/ses/surface_area.hpp"

namespace surftrace::build {
namespace {

constexpr double kPi = std::numbers::pi;

PatchList build(const std::vector<glm::dvec3>& c, const std::vector<double>& r, double rp) {
  return buildSes(c, r, SesParams{rp});
}

TEST(ContourBuildup, SingleAtomIsItsVdwSphere) {
  const PatchList p = build({{1, 2, 3}}, {1.7}, 1.4);
  ASSERT_EQ(p.convex.size(), 1u);
  EXPECT_EQ(p.tori.size(), 0u);
  EXPECT_EQ(p.concave.size(), 0u);
  const SurfaceAreas a = computeAreas(p);
  EXPECT_NEAR(a.sas, 4 * kPi * 3.1 * 3.1, 1e-10);
  EXPECT_NEAR(a.sesTotal(), 4 * kPi * 1.7 * 1.7, 1e-10);
  EXPECT_NEAR(a.sesVolume, 4.0 / 3.0 * kPi * 1.7 * 1.7 * 1.7, 1e-10);
}

// MSMS 2.6.1 on two carbons (r = 1.7) at (−2.70, 0, 0) and (2.75, 0, 0) with rp = 1.5:
// toric 8.144, contact 67.243, SES 75.387, SAS 238.258 Å² (figures from the issue).
TEST(ContourBuildup, TwoAtomsMatchMsms) {
  const PatchList p = build({{-2.70, 0, 0}, {2.75, 0, 0}}, {1.7, 1.7}, 1.5);
  ASSERT_EQ(p.convex.size(), 2u);
  ASSERT_EQ(p.tori.size(), 1u);
  EXPECT_EQ(p.concave.size(), 0u);
  EXPECT_DOUBLE_EQ(p.tori.phiExtent[0], 2 * kPi);
  const SurfaceAreas a = computeAreas(p);
  EXPECT_NEAR(a.sesToroidal, 8.144, 1e-3);
  EXPECT_NEAR(a.sesConvex, 67.243, 1e-3);
  EXPECT_NEAR(a.sesTotal(), 75.387, 1e-3);
  EXPECT_NEAR(a.sas, 238.258, 1e-3);
}

// Two equal atoms: the SES body is a solid of revolution; its volume by a direct
// quadrature of the profile (two spherical caps and the region under the torus arc).
TEST(ContourBuildup, TwoAtomVolumeMatchesSolidOfRevolution) {
  const double r = 1.7, rp = 1.5, d = 5.45;
  const PatchList p = build({{0, 0, 0}, {d, 0, 0}}, {r, r}, rp);
  // Profile ρ(z) along the axis, z from −r to d + r; the torus runs between the contact
  // circles, where the SES is ρ = R − sqrt(rp² − (z − d/2)²), R the probe-circle radius.
  const double Rs = r + rp, t = d / 2, R = std::sqrt(Rs * Rs - t * t);
  const double zc = t * r / Rs;  // contact circle on atom 0 lies at z = zc
  auto rho = [&](double z) {
    if (z <= zc) return std::sqrt(std::max(0.0, r * r - z * z));
    if (z >= d - zc) return std::sqrt(std::max(0.0, r * r - (z - d) * (z - d)));
    return R - std::sqrt(rp * rp - (z - t) * (z - t));
  };
  const int steps = 2000000;
  const double z0 = -r, z1 = d + r, h = (z1 - z0) / steps;
  double volume = 0;
  for (int s = 0; s < steps; ++s) {
    const double z = z0 + (s + 0.5) * h, q = rho(z);
    volume += kPi * q * q * h;
  }
  EXPECT_NEAR(computeAreas(p).sesVolume, volume, 1e-6 * volume);
}

// Four atoms on a regular tetrahedron: every triple has a vertex outside (the other
// atom is far), so 4 concave triangles, 6 tori, and, by symmetry, equal per-atom areas.
TEST(ContourBuildup, TetrahedronIsSymmetric) {
  const double s = 1.5;
  const std::vector<glm::dvec3> c = {{s, s, s}, {s, -s, -s}, {-s, s, -s}, {-s, -s, s}};
  const PatchList p = build(c, {1.8, 1.8, 1.8, 1.8}, 1.4);
  const SurfaceAreas a = computeAreas(p);
  EXPECT_EQ(p.convex.size(), 4u);
  EXPECT_EQ(p.concave.size(), 4u);  // the inward probes sit inside the fourth atom
  for (double v : a.sasPerAtom) EXPECT_NEAR(v, a.sasPerAtom[0], 1e-9);
  for (double v : a.sesPerAtom) EXPECT_NEAR(v, a.sesPerAtom[0], 1e-9);
}

TEST(ContourBuildup, ContainedAndDuplicateAtomsChangeNothing) {
  const std::vector<glm::dvec3> c = {{0, 0, 0}, {3.2, 0.4, 0}, {1.1, 2.9, 0.3}};
  const std::vector<double> r = {1.7, 1.52, 1.55};
  const SurfaceAreas base = computeAreas(build(c, r, 1.4));
  auto withExtra = [&](glm::dvec3 cc, double rr) {
    auto c2 = c;
    auto r2 = r;
    c2.push_back(cc);
    r2.push_back(rr);
    return computeAreas(build(c2, r2, 1.4));
  };
  for (const SurfaceAreas& a : {withExtra(c[0], r[0]), withExtra(c[1] + glm::dvec3(0.1, 0, 0), 1.0),
                                withExtra(c[2], 0.5)}) {
    EXPECT_NEAR(a.sas, base.sas, 1e-9);
    EXPECT_NEAR(a.sesTotal(), base.sesTotal(), 1e-9);
    EXPECT_NEAR(a.sesVolume, base.sesVolume, 1e-9);
  }
}

TEST(ContourBuildup, RejectsBadProbeRadius) {
  EXPECT_THROW(build({{0, 0, 0}}, {1.0}, 0.0), std::invalid_argument);
  EXPECT_THROW(build({{0, 0, 0}}, {1.0}, -1.0), std::invalid_argument);
  EXPECT_THROW(build({{0, 0, 0}}, {1.0}, std::nan("")), std::invalid_argument);
}

std::vector<glm::dvec3> randomCluster(std::uint32_t seed, int n, std::vector<double>& radii) {
  std::mt19937_64 rng(seed);
  std::uniform_real_distribution<double> u(-11.5, 11.5), ur(1.2, 2.0);
  std::vector<glm::dvec3> c;
  for (int i = 0; i < n; ++i) {
    c.emplace_back(u(rng), u(rng), u(rng));
    radii.push_back(ur(rng));
  }
  return c;
}

template <class T> bool sameBits(const std::vector<T>& a, const std::vector<T>& b) {
  return a.size() == b.size() && (a.empty() || std::memcmp(a.data(), b.data(), a.size() * sizeof(T)) == 0);
}

void expectSameBits(const PatchList& a, const PatchList& b) {
  EXPECT_TRUE(sameBits(a.convex.center, b.convex.center));
  EXPECT_TRUE(sameBits(a.convex.radius, b.convex.radius));
  EXPECT_TRUE(sameBits(a.convex.atom, b.convex.atom));
  EXPECT_TRUE(sameBits(a.convex.component, b.convex.component));
  EXPECT_TRUE(sameBits(a.convex.area, b.convex.area));
  EXPECT_TRUE(sameBits(a.convex.vectorArea, b.convex.vectorArea));
  EXPECT_TRUE(sameBits(a.tori.center, b.tori.center));
  EXPECT_TRUE(sameBits(a.tori.axis, b.tori.axis));
  EXPECT_TRUE(sameBits(a.tori.e1, b.tori.e1));
  EXPECT_TRUE(sameBits(a.tori.bigRadius, b.tori.bigRadius));
  EXPECT_TRUE(sameBits(a.tori.thetaI, b.tori.thetaI));
  EXPECT_TRUE(sameBits(a.tori.thetaJ, b.tori.thetaJ));
  EXPECT_TRUE(sameBits(a.tori.phiExtent, b.tori.phiExtent));
  EXPECT_TRUE(sameBits(a.tori.atomI, b.tori.atomI));
  EXPECT_TRUE(sameBits(a.tori.atomJ, b.tori.atomJ));
  EXPECT_TRUE(sameBits(a.tori.component, b.tori.component));
  EXPECT_TRUE(sameBits(a.concave.probe, b.concave.probe));
  EXPECT_TRUE(sameBits(a.concave.dirI, b.concave.dirI));
  EXPECT_TRUE(sameBits(a.concave.dirJ, b.concave.dirJ));
  EXPECT_TRUE(sameBits(a.concave.dirK, b.concave.dirK));
  EXPECT_TRUE(sameBits(a.concave.atomI, b.concave.atomI));
  EXPECT_TRUE(sameBits(a.concave.atomJ, b.concave.atomJ));
  EXPECT_TRUE(sameBits(a.concave.atomK, b.concave.atomK));
  EXPECT_TRUE(sameBits(a.concave.clipBegin, b.concave.clipBegin));
  EXPECT_TRUE(sameBits(a.concave.clipCount, b.concave.clipCount));
  EXPECT_TRUE(sameBits(a.concave.component, b.concave.component));
  EXPECT_TRUE(sameBits(a.clipPlanes, b.clipPlanes));
  EXPECT_EQ(a.componentCount, b.componentCount);
}

TEST(ContourBuildup, IdenticalForAnyThreadCount) {
  for (const double rp : {1.4, 0.6, 3.0}) {
    std::vector<double> r;
    const auto c = randomCluster(7, 600, r);
    PatchList one, all;
    {
      tbb::global_control single(tbb::global_control::max_allowed_parallelism, 1);
      one = build(c, r, rp);
    }
    all = build(c, r, rp);
    expectSameBits(one, all);
    SesBuilder builder;  // the stateful builder gives the same list
    expectSameBits(builder.build(c, r, SesParams{rp}), all);
  }
}

// Atoms on a sphere of radius 8.5 Å, spread evenly (a Fibonacci lattice), as in ORACLES
// E.8: with enough of them the shell seals a cavity that a 1.4 Å probe fits in.
std::vector<glm::dvec3> shell(int atoms) {
  std::vector<glm::dvec3> c;
  const double golden = kPi * (3.0 - std::sqrt(5.0));
  for (int i = 0; i < atoms; ++i) {
    const double y = 1.0 - 2.0 * (i + 0.5) / atoms, ring = std::sqrt(1.0 - y * y), a = golden * i;
    c.push_back(8.5 * glm::dvec3(ring * std::cos(a), y, ring * std::sin(a)));
  }
  return c;
}

// The oracle: can a probe at the shell's centre get out? A flood fill over the grid points
// (spacing 0.1 Å) where a probe fits, from the centre to the edge of the box.
bool probeEscapes(const std::vector<glm::dvec3>& c, double R) {
  const double h = 0.1, lo = -14.0;
  const int n = static_cast<int>(28.0 / h);
  std::vector<char> seen(static_cast<std::size_t>(n) * n * n, 0);
  auto index = [&](int x, int y, int z) { return (static_cast<std::size_t>(z) * n + y) * n + x; };
  auto fits = [&](int x, int y, int z) {
    const glm::dvec3 q(lo + h * x, lo + h * y, lo + h * z);
    return std::all_of(c.begin(), c.end(), [&](const glm::dvec3& a) { return glm::distance(q, a) >= R; });
  };
  std::vector<glm::ivec3> stack = {glm::ivec3(n / 2)};
  seen[index(n / 2, n / 2, n / 2)] = 1;
  const glm::ivec3 steps[6] = {{1, 0, 0}, {-1, 0, 0}, {0, 1, 0}, {0, -1, 0}, {0, 0, 1}, {0, 0, -1}};
  while (!stack.empty()) {
    const glm::ivec3 at = stack.back();
    stack.pop_back();
    for (const glm::ivec3& step : steps) {
      const glm::ivec3 to = at + step;
      if (glm::any(glm::lessThanEqual(to, glm::ivec3(0))) || glm::any(glm::greaterThanEqual(to, glm::ivec3(n - 1)))) return true;
      char& s = seen[index(to.x, to.y, to.z)];
      if (s) continue;
      s = 1;
      if (fits(to.x, to.y, to.z)) stack.push_back(to);
    }
  }
  return false;
}

// A sealed shell has two SES components: the outer surface (0) and the cavity's (1); the
// probes of the cavity's patches are inside the shell. Fewer atoms leave gaps the probe
// gets through, or gaps its ball reaches through: one component. Both as the flood fill
// and the probes' overlaps say.
TEST(ContourBuildup, SealedCavityIsItsOwnComponent) {
  const double r = 1.7, rp = 1.4;
  int sealedShells = 0;
  for (const int atoms : {40, 50, 60, 80}) {
    const auto c = shell(atoms);
    const std::vector<double> radii(c.size(), r);
    const PatchList p = build(c, radii, rp);
    // Sealed for the probe's centre, the cavity is still open where a probe inside and one
    // outside are closer than 2 rp: their balls overlap through the wall, the lens cuts a
    // hole in both their concave patches and the two surfaces are one (ORACLES A.5).
    bool lens = false;
    for (std::size_t v = 0; v < p.concave.size(); ++v)
      for (std::size_t w = 0; w < p.concave.size(); ++w)
        lens = lens || (glm::length(p.concave.probe[v]) < 8.5 && glm::length(p.concave.probe[w]) >= 8.5 &&
                        glm::distance(p.concave.probe[v], p.concave.probe[w]) < 2 * rp);
    const bool sealed = !probeEscapes(c, r + rp) && !lens;
    ASSERT_EQ(p.componentCount, sealed ? 2u : 1u) << atoms << " atoms";
    if (!sealed) continue;
    ++sealedShells;
    for (std::size_t v = 0; v < p.concave.size(); ++v)
      EXPECT_EQ(p.concave.component[v], glm::length(p.concave.probe[v]) < 8.5 ? 1u : 0u) << "concave " << v;
    for (std::size_t t = 0; t < p.tori.size(); ++t) {
      const double phi = 0.5 * p.tori.phiExtent[t];
      const glm::dvec3 e2 = glm::cross(p.tori.axis[t], p.tori.e1[t]);
      const glm::dvec3 probe = p.tori.center[t] + p.tori.bigRadius[t] * (std::cos(phi) * p.tori.e1[t] + std::sin(phi) * e2);
      EXPECT_EQ(p.tori.component[t], glm::length(probe) < 8.5 ? 1u : 0u) << "torus " << t;
    }
  }
  EXPECT_TRUE(probeEscapes(shell(40), 3.1));
  EXPECT_FALSE(probeEscapes(shell(60), 3.1));
  EXPECT_GE(sealedShells, 1);
}

// Separate molecules are separate components; the one reaching furthest in +x is 0.
TEST(ContourBuildup, SeparatePiecesAreSeparateComponents) {
  const PatchList p = build({{0, 0, 0}, {1.5, 0, 0}, {30, 0, 0}, {31.5, 0.5, 0}, {-40, 0, 0}}, {1.7, 1.7, 1.7, 1.7, 1.2}, 1.4);
  EXPECT_EQ(p.componentCount, 3u);
  ASSERT_EQ(p.convex.size(), 5u);
  EXPECT_EQ(p.convex.component[2], 0u);
  EXPECT_EQ(p.convex.component[3], 0u);
  EXPECT_EQ(p.convex.component[0], p.convex.component[1]);
  EXPECT_NE(p.convex.component[0], 0u);
  EXPECT_NE(p.convex.component[4], 0u);
  EXPECT_NE(p.convex.component[4], p.convex.component[0]);
  for (std::size_t t = 0; t < p.tori.size(); ++t)
    EXPECT_EQ(p.tori.component[t], p.convex.component[p.tori.atomI[t] == 0 ? 0 : 2]);
  EXPECT_EQ(build({{1, 2, 3}}, {1.7}, 1.4).componentCount, 1u);
  EXPECT_EQ(build({}, {}, 1.4).componentCount, 0u);
}

// Area and vector area of the sphere minus `caps` by Monte Carlo, within 5 sigma.
void expectMatchesSampling(const std::vector<Cap>& caps, std::mt19937_64& rng, const std::string& what) {
  std::normal_distribution<double> g;
  SphericalRegionScratch scratch;
  const SphericalRegion region = sphereMinusCaps(caps, scratch);
  const int samples = 400000;
  int outside = 0;
  glm::dvec3 w(0.0);
  for (int s = 0; s < samples; ++s) {
    const glm::dvec3 x = glm::normalize(glm::dvec3(g(rng), g(rng), g(rng)));
    bool in = false;
    for (const Cap& c : caps) in = in || glm::dot(x, c.axis) > c.cosRadius;
    if (!in) ++outside, w += x;
  }
  const double frac = static_cast<double>(outside) / samples;
  const double sigma = 4 * kPi * std::sqrt(frac * (1 - frac) / samples);
  EXPECT_NEAR(region.area, 4 * kPi * frac, 5 * sigma + 1e-12) << what;
  const glm::dvec3 wEstimate = w * (4 * kPi / samples);
  // Per component, Var(4π u_c 1[outside]) <= (4π)² frac.
  const double sigmaW = 4 * kPi * std::sqrt(frac / samples);
  for (int c = 0; c < 3; ++c) EXPECT_NEAR(region.vectorArea[c], wEstimate[c], 5 * sigmaW + 1e-12) << what;
}

// Area by Gauss–Bonnet against a dense Monte Carlo count on the unit sphere.
TEST(SphericalRegion, AreaMatchesSampling) {
  for (std::uint32_t seed = 0; seed < 20; ++seed) {
    std::mt19937_64 rng(seed);
    std::normal_distribution<double> g;
    std::uniform_real_distribution<double> u(-0.6, 0.95);
    std::vector<Cap> caps;
    const int count = 1 + static_cast<int>(seed % 6);
    for (int k = 0; k < count; ++k) caps.push_back({glm::normalize(glm::dvec3(g(rng), g(rng), g(rng))), u(rng)});
    expectMatchesSampling(caps, rng, "seed " + std::to_string(seed));
  }
}

// Three or more circles through one point (up to rounding), as where a clipping circle of
// a concave patch passes through a corner, or two clipping circles of mirror-image probes
// meet on an edge. Rounding then decides which cap an arc enters there.
TEST(SphericalRegion, CirclesThroughCommonPoints) {
  for (std::uint32_t seed = 0; seed < 40; ++seed) {
    std::mt19937_64 rng(1000 + seed);
    std::normal_distribution<double> g;
    std::uniform_real_distribution<double> uni(0.0, 1.0);
    // Every circle passes through X and Y: axis in the plane of m = X + Y and k = X × Y.
    const glm::dvec3 x = glm::normalize(glm::dvec3(g(rng), g(rng), g(rng)));
    const glm::dvec3 y = glm::normalize(glm::dvec3(g(rng), g(rng), g(rng)));
    const glm::dvec3 m = glm::normalize(x + y), k = glm::normalize(glm::cross(x, y));
    std::vector<Cap> caps;
    const int through = 3 + static_cast<int>(seed % 3);
    for (int c = 0; c < through; ++c) {
      const double t = 2.0 * kPi * uni(rng);
      const glm::dvec3 axis = glm::normalize(std::cos(t) * m + std::sin(t) * k);
      caps.push_back({axis, glm::dot(axis, x)});
    }
    for (int c = 0; c < static_cast<int>(seed % 3); ++c)
      caps.push_back({glm::normalize(glm::dvec3(g(rng), g(rng), g(rng))), 0.3 + 0.6 * uni(rng)});
    expectMatchesSampling(caps, rng, "seed " + std::to_string(seed));
  }
}

// A concave patch of 1AON (three edge hemispheres, two clipping caps whose circles meet
// an edge's great circle at the same two points to 3e-15): the area came out 1.83 sr too
// large when arcs were joined by the caps they enter.
TEST(SphericalRegion, ConcavePatchOf1AonWithTriplePoints) {
  const std::vector<Cap> caps = {
      {{0x1.18163c6f5c9e4p-5, -0x1.cd4fc1d4802e3p-2, -0x1.c8c42db1542ccp-1}, 0.0},
      {{0x1.54eacd43e68f5p-1, 0x1.02a690d67f59ap-2, -0x1.676faeec32bcfp-1}, 0.0},
      {{0x1.228dcfef73613p-1, -0x1.5281ffb0df877p-1, -0x1.f688753f133bp-2}, 0.0},
      {{-0x1.af0d1e06ab07ep-4, 0x1.9df2f22385c5ap-1, 0x1.28751ac61a0d8p-1}, 0x1.c7390fa819393p-1},
      {{0x1.0ae3790f9c2c4p-1, 0x1.a8a136b1c67a6p-1, -0x1.9be785f86d941p-3}, 0x1.52e5acc6913e5p-1}};
  std::mt19937_64 rng(7);
  for (int mask = 1; mask < 32; ++mask) {
    std::vector<Cap> subset;
    for (int c = 0; c < 5; ++c)
      if (mask >> c & 1) subset.push_back(caps[static_cast<std::size_t>(c)]);
    expectMatchesSampling(subset, rng, "subset " + std::to_string(mask));
  }
}

}  // namespace
}  // namespace surftrace::build

// Cavities located, against oracles that never read the patch list's labels: a brute-force
// grid of accessible probe centres flood-filled from outside (its sealed pockets are the
// cavities), the SES oracle (ORACLES D.1), and points sampled on the patches' own equations.
#include <algorithm>
#include <cmath>
#include <cstdio>
#include <map>
#include <numbers>
#include <set>
#include <string>
#include <vector>

#include <glm/geometric.hpp>
#include <gtest/gtest.h>

#include "build/cavities.hpp"
#include "build/io/molecule.hpp"
#include "build/ses/contour_buildup.hpp"
#include "build/ses/surface_area.hpp"
#include "build/surface_components.hpp"
#include "oracles/ses_oracle.hpp"

namespace surftrace::build {
namespace {

constexpr double kProbe = 1.4;

Molecule load(const std::string& file) { return readMolecule(std::string(SURFTRACE_TEST_DATA) + "/" + file); }

PatchList ses(const Molecule& m) { return buildSes(m.centers, m.radii, SesParams{kProbe}); }

// Accessible probe centres (outside every ball of radius r_i + rp) on a grid of spacing h,
// flood-filled (6-neighbours) from the padded box's corner: what the fill does not reach
// falls into sealed pockets, numbered in `pocket`.
struct ProbeGrid {
  glm::dvec3 origin{0.0};
  double h = 0.0;
  int n[3] = {0, 0, 0};
  std::vector<int> label;  // -2 blocked, -1 reached from outside, >= 0 the pocket
  std::vector<std::vector<glm::dvec3>> pockets;
  std::vector<bool> undecided;   // per pocket: within h·√3 of 2 rp from the outside
  std::size_t outerPockets = 0;  // sealed, but within 2 rp of the outside: left out
  glm::dvec3 at(std::size_t idx) const {
    const std::size_t i = idx % n[0], j = idx / n[0] % n[1], k = idx / n[0] / n[1];
    return origin + h * glm::dvec3(i, j, k);
  }
};

ProbeGrid probeGrid(const Molecule& m, double h) {
  ProbeGrid g;
  g.h = h;
  glm::dvec3 lo(1e300), hi(-1e300);
  for (std::size_t a = 0; a < m.size(); ++a) {
    lo = glm::min(lo, m.centers[a] - (m.radii[a] + kProbe));
    hi = glm::max(hi, m.centers[a] + (m.radii[a] + kProbe));
  }
  g.origin = lo - 2.0 * h;
  for (int k = 0; k < 3; ++k) g.n[k] = static_cast<int>(std::ceil((hi[k] - lo[k]) / h)) + 5;
  const std::size_t total = static_cast<std::size_t>(g.n[0]) * g.n[1] * g.n[2];
  g.label.assign(total, -3);  // -3: accessible, not yet reached
  for (std::size_t a = 0; a < m.size(); ++a) {
    const double R = m.radii[a] + kProbe;
    int from[3], to[3];
    for (int k = 0; k < 3; ++k) {
      from[k] = std::max(0, static_cast<int>(std::floor((m.centers[a][k] - R - g.origin[k]) / h)));
      to[k] = std::min(g.n[k] - 1, static_cast<int>(std::ceil((m.centers[a][k] + R - g.origin[k]) / h)));
    }
    for (int k = from[2]; k <= to[2]; ++k)
      for (int j = from[1]; j <= to[1]; ++j)
        for (int i = from[0]; i <= to[0]; ++i) {
          const std::size_t idx = (static_cast<std::size_t>(k) * g.n[1] + j) * g.n[0] + i;
          const glm::dvec3 d = g.origin + h * glm::dvec3(i, j, k) - m.centers[a];
          if (glm::dot(d, d) < R * R) g.label[idx] = -2;
        }
  }
  auto fill = [&](std::size_t seed, int value, std::vector<glm::dvec3>* points) {
    std::vector<std::size_t> stack{seed};
    g.label[seed] = value;
    while (!stack.empty()) {
      const std::size_t idx = stack.back();
      stack.pop_back();
      if (points) points->push_back(g.at(idx));
      const int c[3] = {static_cast<int>(idx % g.n[0]), static_cast<int>(idx / g.n[0] % g.n[1]),
                        static_cast<int>(idx / g.n[0] / g.n[1])};
      for (int dz = -1; dz <= 1; ++dz)
        for (int dy = -1; dy <= 1; ++dy)
          for (int dx = -1; dx <= 1; ++dx) {
            const int x = c[0] + dx, y = c[1] + dy, z = c[2] + dz;
            if (x < 0 || y < 0 || z < 0 || x >= g.n[0] || y >= g.n[1] || z >= g.n[2]) continue;
            const std::size_t next = (static_cast<std::size_t>(z) * g.n[1] + y) * g.n[0] + x;
            if (g.label[next] == -3) g.label[next] = value, stack.push_back(next);
          }
    }
  };
  fill(0, -1, nullptr);
  std::vector<std::vector<glm::dvec3>> sealed;
  for (std::size_t idx = 0; idx < total; ++idx)
    if (g.label[idx] == -3) {
      sealed.emplace_back();
      fill(idx, -4, &sealed.back());
    }
  // Probe centres closer than 2 rp have overlapping probe balls: the void about one runs into
  // the void about the other, so their surfaces are one SES component (its probe balls cut
  // each other's concave patches; ORACLES A.5) although no probe passes between them. So a
  // sealed pocket within 2 rp of an outside point belongs to the outer surface (this also
  // takes in a pocket sealed only on the grid, by a channel finer than h), and pockets within
  // 2 rp of each other are one cavity. Grid points sample the accessible region from inside,
  // up to h·√3/2 from its edge each, so distances within h·√3 of 2 rp decide nothing: pockets
  // that near the outside are kept apart as `undecided` (they may be a cavity or the
  // outside's), and pockets that near each other are not merged (the test's subset rule holds
  // whether or not the SES joins them).
  const int reach = static_cast<int>(std::ceil(2.0 * kProbe / h));
  std::vector<int> parent(sealed.size());
  for (std::size_t v = 0; v < sealed.size(); ++v) parent[v] = static_cast<int>(v);
  auto find = [&](int v) {
    while (parent[static_cast<std::size_t>(v)] != v) v = parent[static_cast<std::size_t>(v)] = parent[static_cast<std::size_t>(parent[static_cast<std::size_t>(v)])];
    return v;
  };
  const double band = h * std::sqrt(3.0);
  std::vector<bool> outer(sealed.size(), false), undecided(sealed.size(), false);
  for (std::size_t v = 0; v < sealed.size(); ++v)
    for (const glm::dvec3& p : sealed[v]) {
      const int c[3] = {static_cast<int>(std::lround((p.x - g.origin.x) / h)), static_cast<int>(std::lround((p.y - g.origin.y) / h)),
                        static_cast<int>(std::lround((p.z - g.origin.z) / h))};
      for (int k = -reach; k <= reach && !outer[v]; ++k)
        for (int j = -reach; j <= reach && !outer[v]; ++j)
          for (int i = -reach; i <= reach && !outer[v]; ++i) {
            const int x = c[0] + i, y = c[1] + j, z = c[2] + k;
            if (x < 0 || y < 0 || z < 0 || x >= g.n[0] || y >= g.n[1] || z >= g.n[2]) continue;
            const std::size_t idx = (static_cast<std::size_t>(z) * g.n[1] + y) * g.n[0] + x;
            if (g.label[idx] != -1) continue;
            const double d = glm::distance(g.at(idx), p);
            if (d < 2.0 * kProbe - band) outer[v] = true;
            else if (d < 2.0 * kProbe + band) undecided[v] = true;
          }
      if (outer[v]) break;
    }
  for (std::size_t v = 0; v < sealed.size(); ++v)
    for (std::size_t w = v + 1; w < sealed.size(); ++w) {
      double d = 1e300;
      for (std::size_t a = 0; a < sealed[v].size(); ++a)
        for (std::size_t b = 0; b < sealed[w].size(); ++b) d = std::min(d, glm::distance(sealed[v][a], sealed[w][b]));
      if (d < 2.0 * kProbe - band) parent[static_cast<std::size_t>(find(static_cast<int>(w)))] = find(static_cast<int>(v));
    }
  std::vector<bool> rootOuter(sealed.size(), false);
  for (std::size_t v = 0; v < sealed.size(); ++v)
    if (outer[v]) rootOuter[static_cast<std::size_t>(find(static_cast<int>(v)))] = true;
  std::map<int, std::size_t> pocketOfRoot;
  for (std::size_t v = 0; v < sealed.size(); ++v) {
    const int root = find(static_cast<int>(v));
    if (rootOuter[static_cast<std::size_t>(root)]) {
      ++g.outerPockets;
      continue;
    }
    if (!pocketOfRoot.count(root)) {
      pocketOfRoot[root] = g.pockets.size(), g.pockets.emplace_back();
      g.undecided.push_back(false);
    }
    g.undecided[pocketOfRoot[root]] = g.undecided[pocketOfRoot[root]] || undecided[v];
    std::vector<glm::dvec3>& into = g.pockets[pocketOfRoot[root]];
    into.insert(into.end(), sealed[v].begin(), sealed[v].end());
  }
  return g;
}

// The atoms a probe at accessible point g touches when moved straight towards the nearest
// ball r_i + rp: the ball about g of that radius holds no other ball's point, so the segment
// stays accessible and its end touches i. Exact whatever the grid: each such atom lines the
// pocket. Ties within 1e-9 Å are all taken.
std::vector<std::uint32_t> nearestAtoms(const Molecule& m, const glm::dvec3& g) {
  double best = 1e300;
  std::vector<double> gap(m.size());
  for (std::size_t a = 0; a < m.size(); ++a) best = std::min(best, gap[a] = glm::distance(g, m.centers[a]) - m.radii[a] - kProbe);
  std::vector<std::uint32_t> out;
  for (std::size_t a = 0; a < m.size(); ++a)
    if (gap[a] <= best + 1e-9) out.push_back(static_cast<std::uint32_t>(a));
  return out;
}

bool contains(const std::vector<std::uint32_t>& sorted, std::uint32_t x) { return std::binary_search(sorted.begin(), sorted.end(), x); }

// Pockets matched to cavities by their exactly touched atoms.
struct Matching {
  std::vector<int> cavityOfPocket;               // -1: no cavity lists every atom the pocket touches
  std::vector<std::vector<int>> pocketsOfCavity;
};

Matching matchPockets(const Molecule& m, const ProbeGrid& g, const std::vector<Cavity>& cavities) {
  Matching out{std::vector<int>(g.pockets.size(), -1), std::vector<std::vector<int>>(cavities.size())};
  for (std::size_t v = 0; v < g.pockets.size(); ++v) {
    std::set<std::uint32_t> touched;
    for (const glm::dvec3& p : g.pockets[v])
      for (const std::uint32_t a : nearestAtoms(m, p)) touched.insert(a);
    for (std::size_t c = 0; c < cavities.size(); ++c)
      if (std::all_of(touched.begin(), touched.end(), [&](std::uint32_t a) { return contains(cavities[c].atoms, a); })) {
        out.cavityOfPocket[v] = static_cast<int>(c);
        out.pocketsOfCavity[c].push_back(static_cast<int>(v));
        break;
      }
  }
  return out;
}

class CavitiesOnProteins : public ::testing::TestWithParam<const char*> {};

// Lining atoms against the probe grid (h = 0.15 Å). Every pocket the grid finds (other than
// the undecided ones) must be one cavity: the atoms its points touch exactly (nearestAtoms)
// are all among that cavity's lining atoms; this half is exact. Every lining atom of a cavity
// must come within r_i + rp + 1.5 Å of one of its pockets' grid points: a probe rolling along
// two atoms can pass through a tunnel of the accessible region thinner than the grid for
// about a probe radius (1MBN: three probes touching atoms 14, 37, 80 and 1024 lie 1.37 Å from
// the nearest grid point of their cavity), so this half only catches atoms from elsewhere.
// A cavity without a pocket must be small: under 30 Å³ of void.
TEST_P(CavitiesOnProteins, LiningAtomsMatchTheProbeGridOracle) {
  const Molecule m = load(GetParam());
  const std::vector<Cavity> cavities = locateCavities(ses(m));
  ASSERT_FALSE(cavities.empty());
  const ProbeGrid g = probeGrid(m, 0.15);
  const Matching match = matchPockets(m, g, cavities);
  std::size_t undecided = 0;
  for (std::size_t v = 0; v < g.pockets.size(); ++v)
    if (g.undecided[v]) ++undecided;
    else EXPECT_GE(match.cavityOfPocket[v], 0) << "pocket " << v << " of " << g.pockets.size() << " (" << g.pockets[v].size()
                                         << " points near " << g.pockets[v][0].x << " " << g.pockets[v][0].y << " "
                                         << g.pockets[v][0].z << ") is in no cavity";
  std::size_t matched = 0;
  for (std::size_t c = 0; c < cavities.size(); ++c) {
    const Cavity& cav = cavities[c];
    if (match.pocketsOfCavity[c].empty()) {
      EXPECT_LT(cav.volume, 30.0) << "cavity " << c << " of void " << cav.volume << " Å³ has no grid pocket";
      continue;
    }
    ++matched;
    for (const std::uint32_t a : cav.atoms) {
      double gap = 1e300;
      for (const int v : match.pocketsOfCavity[c])
        for (const glm::dvec3& p : g.pockets[static_cast<std::size_t>(v)])
          gap = std::min(gap, glm::distance(p, m.centers[a]) - m.radii[a] - kProbe);
      EXPECT_LE(gap, 1.5) << "cavity " << c << " lists atom " << a << ", " << gap << " Å beyond touching its pockets";
    }
  }
  EXPECT_GE(matched, 1u);
  std::printf("%s: %zu cavities, %zu grid pockets (%zu undecided; besides %zu within 2 rp of the outside), %zu cavities matched\n",
              GetParam(), cavities.size(), g.pockets.size(), undecided, g.outerPockets, matched);
}

// The centroid lies in its box and in the cavity's void: the SES oracle puts it within rp of
// an accessible probe centre (outside the SES body), and that centre touches only the
// cavity's lining atoms (so it is the cavity's, not the outside's).
TEST_P(CavitiesOnProteins, CentroidIsInsideTheBoxAndTheVoid) {
  const Molecule m = load(GetParam());
  const std::vector<Cavity> cavities = locateCavities(ses(m));
  std::vector<oracle::Sphere> spheres;
  for (std::size_t a = 0; a < m.size(); ++a) spheres.push_back({m.centers[a], m.radii[a]});
  const oracle::SesOracle ses(spheres, kProbe);
  for (std::size_t c = 0; c < cavities.size(); ++c) {
    const Cavity& cav = cavities[c];
    for (int k = 0; k < 3; ++k) {
      EXPECT_LE(cav.boxLower[k], cav.centroid[k]) << "cavity " << c;
      EXPECT_GE(cav.boxUpper[k], cav.centroid[k]) << "cavity " << c;
    }
    const auto r = ses.distanceToAccessible(cav.centroid);
    EXPECT_LT(r.dist, kProbe) << "cavity " << c << ": its centroid is in the SES body";
    for (const std::uint32_t a : nearestAtoms(m, r.nearest))
      EXPECT_TRUE(contains(cav.atoms, a)) << "cavity " << c << ": the probe nearest its centroid touches atom " << a;
  }
}

INSTANTIATE_TEST_SUITE_P(Proteins, CavitiesOnProteins,
                         ::testing::Values("structures/1crn.pdb", "structures/1ubq.pdb.gz", "structures/1mbn.pdb.gz"));

// Points sampled on the patches' own equations (tori over θ and φ, concave triangles as
// directions inside the cone and every clipping half-space, convex parts as exposed
// directions whose probe position reaches a pocket of the cavity in a straight accessible
// line) lie in the cavity's box, and the box's faces are reached by them to within 0.05 Å:
// the box is the patches' own, not a loose one.
TEST(Cavities, BoxHoldsSampledSurfacePointsTightly) {
  const Molecule m = load("structures/1mbn.pdb.gz");
  const PatchList p = ses(m);
  const std::vector<Cavity> cavities = locateCavities(p);
  const ProbeGrid g = probeGrid(m, 0.15);
  const Matching match = matchPockets(m, g, cavities);
  std::map<std::uint32_t, std::size_t> byLabel;
  for (std::size_t c = 0; c < cavities.size(); ++c) byLabel[cavities[c].component] = c;
  std::vector<glm::dvec3> lo(cavities.size(), glm::dvec3(1e300)), hi(cavities.size(), glm::dvec3(-1e300));
  auto add = [&](std::size_t c, const glm::dvec3& x, const char* what) {
    const double slack = 1e-9 * (1.0 + glm::length(x));
    for (int k = 0; k < 3; ++k)
      ASSERT_TRUE(x[k] >= cavities[c].boxLower[k] - slack && x[k] <= cavities[c].boxUpper[k] + slack)
          << what << " point (" << x.x << ", " << x.y << ", " << x.z << ") outside cavity " << c << "'s box";
    lo[c] = glm::min(lo[c], x), hi[c] = glm::max(hi[c], x);
  };
  const double rp = kProbe;
  for (std::size_t t = 0; t < p.tori.size(); ++t) {
    if (!byLabel.count(p.tori.component[t])) continue;
    const std::size_t c = byLabel[p.tori.component[t]];
    const double R = p.tori.bigRadius[t];
    const glm::dvec3 n = p.tori.axis[t], e1 = p.tori.e1[t], e2 = glm::cross(n, e1);
    for (int i = 0; i <= 96; ++i)
      for (int j = 0; j <= 96; ++j) {
        const double th = p.tori.thetaI[t] + (p.tori.thetaJ[t] - p.tori.thetaI[t]) * i / 96.0;
        const double rho = R - rp * std::cos(th);
        if (rho < 0.0) continue;  // a spindle's inner part is not on the SES
        const double phi = p.tori.phiExtent[t] * j / 96.0;
        add(c, p.tori.center[t] + rho * (std::cos(phi) * e1 + std::sin(phi) * e2) + rp * std::sin(th) * n, "torus");
      }
  }
  // Fibonacci directions on the unit sphere.
  std::vector<glm::dvec3> dirs;
  const int kDirs = 20000;
  for (int i = 0; i < kDirs; ++i) {
    const double z = 1.0 - (2.0 * i + 1.0) / kDirs, r = std::sqrt(1.0 - z * z), a = i * std::numbers::pi * (3.0 - std::sqrt(5.0));
    dirs.emplace_back(r * std::cos(a), r * std::sin(a), z);
  }
  const auto& cv = p.concave;
  for (std::size_t v = 0; v < cv.size(); ++v) {
    if (!byLabel.count(cv.component[v])) continue;
    const std::size_t c = byLabel[cv.component[v]];
    glm::dvec3 gij = glm::cross(cv.dirI[v], cv.dirJ[v]), gjk = glm::cross(cv.dirJ[v], cv.dirK[v]), gki = glm::cross(cv.dirK[v], cv.dirI[v]);
    if (glm::dot(gij, cv.dirK[v]) < 0.0) gij = -gij, gjk = -gjk, gki = -gki;
    for (const glm::dvec3& u : dirs) {
      if (glm::dot(u, gij) < 0.0 || glm::dot(u, gjk) < 0.0 || glm::dot(u, gki) < 0.0) continue;
      const glm::dvec3 x = cv.probe[v] + rp * u;
      bool kept = true;
      for (std::uint32_t q = 0; q < cv.clipCount[v]; ++q) {
        const Plane& pl = p.clipPlanes[cv.clipBegin[v] + q];
        kept = kept && glm::dot(glm::dvec3(pl), x) + pl.w <= 0.0;
      }
      if (kept) add(c, x, "concave");
    }
  }
  auto accessible = [&](const glm::dvec3& x, std::size_t skip) {
    for (std::size_t a = 0; a < m.size(); ++a)
      if (a != skip && glm::distance(x, m.centers[a]) < m.radii[a] + rp - 1e-9) return false;
    return true;
  };
  for (std::size_t c = 0; c < cavities.size(); ++c) {
    std::vector<glm::dvec3> pocketPoints;
    for (const int v : match.pocketsOfCavity[c])
      for (const glm::dvec3& q : g.pockets[static_cast<std::size_t>(v)]) pocketPoints.push_back(q);
    if (pocketPoints.empty()) continue;
    for (const std::uint32_t a : cavities[c].atoms) {
      for (const glm::dvec3& u : dirs) {
        const glm::dvec3 s = m.centers[a] + (m.radii[a] + rp) * u;
        if (!accessible(s, a)) continue;
        // A pocket point within 0.3 Å joined to s by an accessible segment: s is the cavity's.
        bool joined = false;
        for (const glm::dvec3& q : pocketPoints) {
          if (glm::distance(q, s) > 0.3) continue;
          joined = true;
          for (int step = 1; step < 8 && joined; ++step) joined = accessible(s + (q - s) * (step / 8.0), ~std::size_t{0});
          if (joined) break;
        }
        if (joined) {
          const glm::dvec3 x = m.centers[a] + m.radii[a] * u;
          add(c, x, "convex");
        }
      }
    }
  }
  for (std::size_t c = 0; c < cavities.size(); ++c)
    for (int k = 0; k < 3; ++k) {
      EXPECT_NEAR(lo[c][k], cavities[c].boxLower[k], 0.05) << "cavity " << c << " axis " << k;
      EXPECT_NEAR(hi[c][k], cavities[c].boxUpper[k], 0.05) << "cavity " << c << " axis " << k;
    }
}

// The cavities alone: a valid list whose components are the cavities, with every torus and
// concave patch of theirs; the areas are the cavities' less the parts on convex patches of
// one-atom walls (labelled by the outside, left out), so never more.
TEST(Cavities, CavityComponentsKeepTheCavitiesAndTheirAreas) {
  const Molecule m = load("structures/1mbn.pdb.gz");
  const PatchList p = ses(m);
  const std::vector<Cavity> cavities = locateCavities(p);
  const PatchList alone = cavityComponents(p);
  EXPECT_NO_THROW(alone.validate());
  ASSERT_EQ(alone.componentCount, cavities.size());
  const SurfaceAreas a = computeAreas(alone);
  for (std::size_t c = 0; c < cavities.size(); ++c) EXPECT_LE(a.components[c].area, cavities[c].area * (1 + 1e-12)) << c;
  std::set<std::uint32_t> labels;
  for (const Cavity& c : cavities) labels.insert(c.component);
  EXPECT_EQ(alone.tori.size(), static_cast<std::size_t>(std::count_if(p.tori.component.begin(), p.tori.component.end(),
                                                                       [&](std::uint32_t l) { return labels.count(l) > 0; })));
  EXPECT_EQ(alone.concave.size(), static_cast<std::size_t>(std::count_if(p.concave.component.begin(), p.concave.component.end(),
                                                                         [&](std::uint32_t l) { return labels.count(l) > 0; })));
  for (std::size_t k = 0; k < alone.tori.size(); ++k)
    EXPECT_TRUE(contains(cavities[alone.tori.component[k]].atoms, alone.tori.atomI[k]));
}

// The skin carries no component labels: no cavities to locate, said so.
TEST(Cavities, SkinIsRefused) {
  PatchList p;
  p.params.surface = SurfaceKind::Mss;
  EXPECT_THROW(locateCavities(p), std::invalid_argument);
}

// GroEL–GroES (1AON): as many cavities as `area` counts (318), each located.
TEST(Cavities, GroelHasItsCavitiesLocated) {
  const Molecule m = load("paper/1aon.pdb.gz");
  const std::vector<Cavity> cavities = locateCavities(ses(m));
  EXPECT_EQ(cavities.size(), 318u);
  for (const Cavity& c : cavities) {
    EXPECT_FALSE(c.atoms.empty());
    EXPECT_GT(c.volume, 0.0);
    for (int k = 0; k < 3; ++k) EXPECT_TRUE(c.boxLower[k] <= c.centroid[k] && c.centroid[k] <= c.boxUpper[k]) << c.component;
  }
}

}  // namespace
}  // namespace surftrace::build

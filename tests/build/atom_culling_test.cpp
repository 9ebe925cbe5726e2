// Atoms left out before a surface is built (atom_culling.hpp, buildSurface): balls inside
// another ball change nothing (oracles: the build without them, the builder's own burial of
// the same input, FreeSASA), near-coincident atoms merge within the stated distance, clusters
// are refused, and the work stays linear in the atom count for 200,000 coincident atoms.
#include <algorithm>
#include <cmath>
#include <numbers>
#include <random>
#include <stdexcept>
#include <string>
#include <vector>

#include <gtest/gtest.h>

#include "build/atom_culling.hpp"
#include "build/io/molecule.hpp"
#include "build/mss/mss_area.hpp"
#include "build/ses/contour_buildup.hpp"
#include "build/ses/surface_area.hpp"
#include "build/surface.hpp"
#include "oracles/freesasa_oracle.hpp"
#include "patch_compare.hpp"

namespace surftrace::build {
namespace {

constexpr double kRp = 1.4;

Molecule crambin() { return readMolecule(std::string(SURFTRACE_TEST_DATA) + "/structures/1crn.pdb"); }

// m with atom (c, r) inserted before index `at` (its record empty: no line).
void insertAtom(Molecule& m, std::size_t at, const glm::dvec3& c, double r) {
  m.centers.insert(m.centers.begin() + static_cast<std::ptrdiff_t>(at), c);
  m.radii.insert(m.radii.begin() + static_cast<std::ptrdiff_t>(at), r);
  m.atoms.insert(m.atoms.begin() + static_cast<std::ptrdiff_t>(at), AtomRecord{});
}

// Crambin with balls strictly inside some of its atoms' balls inserted among them (at the
// start, in the middle, at the end), each inside with a margin of 0.1 Å so that rounding the
// centres to the PDB's 1e-3 Å keeps it inside; and where each original atom went.
struct WithInserted {
  Molecule base, with;
  std::vector<std::size_t> originalAt;  // index in `with` of base atom i
  std::vector<std::size_t> inserted;    // indices in `with` of the inserted atoms
  std::size_t copy = 0;                 // index in `with` of the identical copy of atom 100
};
WithInserted crambinWithContainedAtoms() {
  WithInserted w;
  w.base = crambin();
  w.with = w.base;
  const std::size_t n = w.base.size();
  // Inserted from the back, so that the positions still to come stay valid: balls inside
  // atoms spread over the chain, an identical copy of atom 100 (of two equal balls the later
  // goes) and a ball inside atom 7 at its centre.
  struct Insert {
    std::size_t host;
    glm::dvec3 shift;
    double shrink;
  };
  const Insert inserts[] = {{n - 1, {0.1, -0.1, 0.0}, 0.4}, {200, {0.1, -0.1, 0.0}, 0.4}, {151, {0.0, 0.2, 0.0}, 0.4},
                            {150, {0.1, 0.0, 0.1}, 0.4},    {100, {0.0, 0.0, 0.0}, 0.0}, {40, {-0.1, 0.1, 0.0}, 0.4},
                            {7, {0.0, 0.0, 0.0}, 0.5},      {3, {0.1, -0.1, 0.0}, 0.4},  {0, {0.0, 0.0, -0.1}, 0.4}};
  for (const Insert& in : inserts)
    insertAtom(w.with, in.host + 1, w.base.centers[in.host] + in.shift, w.base.radii[in.host] - in.shrink);
  for (std::size_t i = 0; i < w.with.size(); ++i) w.with.atoms[i].line = static_cast<int>(i + 1);
  // Where the base atoms went, matching in order (the copy of atom 100 comes after it).
  std::size_t k = 0;
  for (std::size_t i = 0; i < w.with.size(); ++i) {
    if (k < n && w.with.centers[i] == w.base.centers[k] && w.with.radii[i] == w.base.radii[k]) {
      w.originalAt.push_back(i);
      ++k;
    } else {
      w.inserted.push_back(i);
      if (w.with.centers[i] == w.base.centers[100]) w.copy = i;
    }
  }
  EXPECT_EQ(w.originalAt.size(), n);
  EXPECT_EQ(w.inserted.size(), 9u);
  return w;
}

// The list built for the base molecule, with its atom indices moved to where the base atoms
// sit in the larger input: what the larger input's list must be, array for array.
PatchList renumbered(PatchList list, const WithInserted& w) {
  auto move = [&](std::uint32_t& a) { a = static_cast<std::uint32_t>(w.originalAt[a]); };
  for (auto* ids : {&list.convex.atom, &list.tori.atomI, &list.tori.atomJ, &list.concave.atomI, &list.concave.atomJ,
                    &list.concave.atomK})
    for (std::uint32_t& a : *ids) move(a);
  list.params.atomCount = static_cast<std::uint32_t>(w.with.size());
  list.params.inputCrc32 = w.with.inputCrc32;
  return list;
}

TEST(AtomCulling, ContainedAtomsChangeNoSesPatchAreaOrVolume) {
  const WithInserted w = crambinWithContainedAtoms();
  const SurfaceRequest request{SurfaceKind::Ses, kRp};
  std::vector<std::string> notes;
  const PatchList got = buildSurface(w.with, request, &notes);
  // Oracle 1: the build without the inserted atoms, renumbered: the same patches, bit for bit.
  test::expectSamePatchLists(got, renumbered(buildSurface(w.base, request), w), "crambin with contained atoms");
  // Oracle 2: contour-buildup on every atom, which buries contained atoms itself.
  PatchList everyAtom = buildSes(w.with.centers, w.with.radii, SesParams{kRp});
  everyAtom.params.radiiSet = got.params.radiiSet;
  everyAtom.params.inputCrc32 = got.params.inputCrc32;
  test::expectSamePatchLists(got, everyAtom, "culled vs contour-buildup's own burial");
  // Areas: the totals bit for bit, every input atom reported, 0 for the ones left out.
  const SurfaceAreas a = computeAreas(got), b = computeAreas(buildSurface(w.base, request));
  EXPECT_EQ(a.sas, b.sas);
  EXPECT_EQ(a.sesTotal(), b.sesTotal());
  EXPECT_EQ(a.sesVolume, b.sesVolume);
  ASSERT_EQ(a.sasPerAtom.size(), w.with.size());
  for (std::size_t i = 0; i < w.base.size(); ++i) {
    EXPECT_EQ(a.sasPerAtom[w.originalAt[i]], b.sasPerAtom[i]) << "atom " << i;
    EXPECT_EQ(a.sesPerAtom[w.originalAt[i]], b.sesPerAtom[i]) << "atom " << i;
  }
  for (const std::size_t i : w.inserted) EXPECT_EQ(a.sasPerAtom[i], 0.0) << "inserted atom " << i;
  ASSERT_EQ(notes.size(), 1u);
  EXPECT_NE(notes[0].find("9 atoms lie inside another atom's ball (each with the probe radius added)"), std::string::npos)
      << notes[0];
  EXPECT_NE(notes[0].find("per-atom areas 0"), std::string::npos) << notes[0];
}

// The SAS per atom against FreeSASA (Lee–Richards, 1000 slices), which knows nothing of
// culling: the inserted atoms get 0 there too, the others what they get without them. (Not
// the identical copy: FreeSASA gives both of two equal atoms the area of one.)
TEST(AtomCulling, ContainedAtomsMatchFreesasa) {
  WithInserted w = crambinWithContainedAtoms();
  const auto at = static_cast<std::ptrdiff_t>(w.copy);
  w.with.centers.erase(w.with.centers.begin() + at);
  w.with.radii.erase(w.with.radii.begin() + at);
  w.with.atoms.erase(w.with.atoms.begin() + at);
  std::erase(w.inserted, w.copy);
  for (std::size_t& i : w.inserted) i -= i > w.copy ? 1 : 0;
  std::vector<oracle::Sphere> atoms;
  for (std::size_t i = 0; i < w.with.size(); ++i) atoms.push_back({w.with.centers[i], w.with.radii[i]});
  oracle::roundForPdb(atoms);
  for (std::size_t i = 0; i < atoms.size(); ++i) w.with.centers[i] = atoms[i].c;
  const SurfaceAreas a = computeAreas(buildSurface(w.with, {SurfaceKind::Ses, kRp}));
  const oracle::FreesasaResult f = oracle::runFreesasa(atoms, kRp, 1000);
  ASSERT_EQ(f.perAtom.size(), atoms.size());
  EXPECT_NEAR(a.sas / f.total, 1.0, 1e-4) << "ours " << a.sas << " FreeSASA " << f.total;
  for (std::size_t i = 0; i < atoms.size(); ++i) EXPECT_NEAR(a.sasPerAtom[i], f.perAtom[i], 0.05) << "atom " << i;
  for (const std::size_t i : w.inserted) EXPECT_EQ(f.perAtom[i], 0.0) << "FreeSASA, inserted atom " << i;
}

TEST(AtomCulling, ContainedAtomsChangeNoVdwOrSasSpheresOrUnionArea) {
  const WithInserted w = crambinWithContainedAtoms();
  for (const SurfaceKind kind : {SurfaceKind::Vdw, SurfaceKind::Sas}) {
    const SurfaceRequest request{kind, kRp};
    const PatchList got = buildSurface(w.with, request);
    test::expectSamePatchLists(got, renumbered(buildSurface(w.base, request), w), surfaceKindName(kind));
  }
  // The union of the vdW balls (the skin at s = 1) from the culled spheres, against the union
  // of every ball (Gauss–Bonnet on each sphere minus its neighbours' caps).
  const PatchList balls = buildSurface(w.with, {SurfaceKind::Mss, kRp, 1.0});
  const MssAreas got = unionOfBallsAreas(balls), all = unionOfBallsAreas(w.with.centers, w.with.radii);
  EXPECT_NEAR(got.total(), all.total(), 1e-9 * all.total());
  EXPECT_NEAR(got.volume, all.volume, 1e-9 * all.volume);
  ASSERT_EQ(got.perAtom.size(), w.with.size());
  for (std::size_t i = 0; i < w.with.size(); ++i) EXPECT_NEAR(got.perAtom[i], all.perAtom[i], 1e-9) << "atom " << i;
}

// A ball inside another still shapes the skin (ORACLES E.3: r = 0.5 at 1.5 from the centre of
// r = 2 reaches 2.118 at s = 0.5), so the skin keeps it.
TEST(AtomCulling, SkinKeepsContainedBalls) {
  Molecule m;
  m.source = "tangent";
  m.centers = {{0, 0, 0}, {1.5, 0, 0}};
  m.radii = {2.0, 0.5};
  const CullResult vdw = cullAtoms(m.centers, m.radii, {});
  EXPECT_EQ(vdw.kept, std::vector<std::uint32_t>({0}));
  EXPECT_EQ(vdw.contained, 1u);
  const PatchList skin = buildSurface(m, {SurfaceKind::Mss, kRp, 0.5});
  EXPECT_TRUE(std::any_of(skin.mss.atoms.begin(), skin.mss.atoms.end(), [](const glm::uvec4& s) { return s.x == 1 || s.y == 1; }))
      << "the contained ball has no skin patch";
  EXPECT_EQ(buildSurface(m, {SurfaceKind::Mss, kRp, 1.0}).convex.size(), 1u);  // the union of balls does not
}

// n atoms within `jitter` (uniform in a cube) of one point, radius r (or uniform in [r, r + dr]).
Molecule cluster(std::size_t n, double jitter, double r, double dr, glm::dvec3 at = {10, 20, 30}) {
  Molecule m;
  m.source = "cluster";
  std::mt19937_64 rng(12345);
  std::uniform_real_distribution<double> u(-1.0, 1.0), v(0.0, 1.0);
  for (std::size_t i = 0; i < n; ++i) {
    m.centers.push_back(at + jitter * glm::dvec3(u(rng), u(rng), u(rng)));
    m.radii.push_back(r + dr * v(rng));
  }
  return m;
}

// 200,000 atoms within 1e-9 Å of one point: no ball contains another, but all merge into the
// first, so the SES is that one sphere; each atom looks at one candidate, not at 199,999.
TEST(AtomCulling, TwoHundredThousandCoincidentAtomsMergeInLinearWork) {
  const std::size_t n = 200000;
  const Molecule m = cluster(n, 1e-9, 1.7, 0.0);
  const CullResult cull = cullAtoms(m.centers, m.radii, {kRp});
  EXPECT_EQ(cull.kept, std::vector<std::uint32_t>({0}));
  EXPECT_EQ(cull.contained, 0u);
  EXPECT_EQ(cull.merged, n - 1);
  EXPECT_LE(cull.mergedDistance, 4e-9);
  EXPECT_FALSE(cull.cluster);
  EXPECT_LE(cull.candidates, 2 * n) << "work per atom is not bounded";
  std::vector<std::string> notes;
  const PatchList p = buildSurface(m, {SurfaceKind::Ses, kRp}, &notes);
  EXPECT_EQ(p.params.atomCount, n);
  ASSERT_EQ(p.convex.size(), 1u);
  EXPECT_EQ(p.convex.atom[0], 0u);
  EXPECT_EQ(p.tori.size() + p.concave.size(), 0u);
  const SurfaceAreas a = computeAreas(p);
  const double r = 1.7, R = r + kRp;
  // The union of the balls lies between the first ball and that ball grown by the spread.
  EXPECT_NEAR(a.sas, 4 * std::numbers::pi * R * R, 1e-9);
  EXPECT_NEAR(a.sesTotal(), 4 * std::numbers::pi * r * r, 1e-9);
  ASSERT_EQ(a.sasPerAtom.size(), n);
  EXPECT_EQ(std::count(a.sasPerAtom.begin(), a.sasPerAtom.end(), 0.0), static_cast<std::ptrdiff_t>(n - 1));
  ASSERT_EQ(notes.size(), 1u);
  EXPECT_NE(notes[0].find("199999 atoms lie within 1e-05 Å of a kept atom's ball"), std::string::npos) << notes[0];
  EXPECT_NE(notes[0].find("moved onto its keeper"), std::string::npos) << notes[0];
  // The skin merges them the same way.
  const PatchList skin = buildSurface(m, {SurfaceKind::Mss, kRp, 0.5});
  EXPECT_EQ(skin.params.atomCount, n);
  EXPECT_EQ(skin.mss.size(), 1u);
}

// Radii in [1.5, 2]: nearly every ball lies inside a larger one, found among the first few
// candidates because the largest are listed first. Spread over 1e-9 Å, one ball is left; over
// 1e-4 Å, those within 1e-4 Å of the largest radius are left too: a cluster, resolved by the
// merge distance the error names.
TEST(AtomCulling, TwoHundredThousandNestedAtomsDropInLinearWork) {
  const std::size_t n = 200000;
  for (const double jitter : {1e-9, 1e-4}) {
    const Molecule m = cluster(n, jitter, 1.5, 0.5);
    const CullResult cull = cullAtoms(m.centers, m.radii, {kRp});
    EXPECT_EQ(cull.contained + cull.merged + cull.kept.size(), n);
    EXPECT_GT(cull.contained, n - 100) << "jitter " << jitter;
    EXPECT_LE(cull.candidates, jitter < 1e-6 ? 2 * n : (kMaxClusterAtoms + 64) * n) << "jitter " << jitter;
    SurfaceRequest request{SurfaceKind::Ses, kRp};
    if (jitter < 1e-6) {
      EXPECT_EQ(cull.kept.size(), 1u);
      EXPECT_FALSE(cull.cluster);
    } else {
      ASSERT_TRUE(cull.cluster);
      EXPECT_LE(cull.cluster->spread, 1e-3);
      try {
        buildSurface(m, request);
        FAIL() << "the cluster left was built";
      } catch (const std::invalid_argument& e) {
        const std::string what = e.what();
        request.mergeWithin = std::stod(what.substr(what.find("--merge-within ") + 15));
        EXPECT_LE(request.mergeWithin, 2e-3) << what;
      }
    }
    const SurfaceAreas a = computeAreas(buildSurface(m, request));
    const double rMax = *std::max_element(m.radii.begin(), m.radii.end());
    EXPECT_NEAR(a.sesTotal(), 4 * std::numbers::pi * rMax * rMax, 1e-2) << "jitter " << jitter;
  }
}

// 200,000 equal atoms spread over 1e-4 Å: merging within 1e-5 Å leaves thousands, a cluster
// no builder should take on. The error says how many, where, and what merge distance
// resolves it; with that distance they merge into one. Linear work either way.
TEST(AtomCulling, AClusterThatDoesNotMergeIsRefusedWithTheDistanceThatMergesIt) {
  const std::size_t n = 200000;
  const Molecule m = cluster(n, 1e-4, 1.7, 0.0);
  const CullResult cull = cullAtoms(m.centers, m.radii, {kRp});
  ASSERT_TRUE(cull.cluster);
  EXPECT_GT(cull.kept.size(), kMaxClusterAtoms);
  EXPECT_EQ(cull.cluster->atoms, n);
  EXPECT_LE(cull.cluster->spread, 4e-4);
  EXPECT_LE(cull.candidates, (kMaxClusterAtoms + 64) * n);
  std::string suggested = "none";
  try {
    buildSurface(m, {SurfaceKind::Ses, kRp});
    FAIL() << "a 200,000-atom cluster was built";
  } catch (const std::invalid_argument& e) {
    const std::string what = e.what();
    EXPECT_NE(what.find("cluster: 200000 atoms lie within 0.5 Å of atom 1 near ("), std::string::npos) << what;
    EXPECT_NE(what.find("near-coincident cluster"), std::string::npos) << what;
    suggested = what.substr(what.find("--merge-within ") + 15);
  }
  EXPECT_THROW(buildSurface(m, {SurfaceKind::Mss, kRp, 0.5}), std::invalid_argument);
  SurfaceRequest merged{SurfaceKind::Ses, kRp};
  merged.mergeWithin = std::stod(suggested);
  EXPECT_GE(merged.mergeWithin, 2 * cull.cluster->spread);
  EXPECT_LE(merged.mergeWithin, 4 * cull.cluster->spread);
  const PatchList p = buildSurface(m, merged);
  EXPECT_EQ(p.convex.size(), 1u);
  EXPECT_EQ(p.params.atomCount, n);
}

// Clusters inside a protein: copies of three atoms within 1e-9 Å of them merge into them,
// and the surface is the protein's, bit for bit; 40 copies within 1e-3 Å of one atom are
// refused, naming its line.
TEST(AtomCulling, ClustersInsideAProtein) {
  const Molecule base = crambin();
  Molecule m = base;
  std::mt19937_64 rng(7);
  std::uniform_real_distribution<double> u(-1e-9, 1e-9);
  for (const std::size_t host : {5u, 120u, 300u})
    for (int k = 0; k < 100; ++k) {
      m.centers.push_back(base.centers[host] + glm::dvec3(u(rng), u(rng), u(rng)));
      m.radii.push_back(base.radii[host]);
      m.atoms.push_back(base.atoms[host]);
    }
  std::vector<std::string> notes;
  PatchList got = buildSurface(m, {SurfaceKind::Ses, kRp}, &notes);
  EXPECT_EQ(got.params.atomCount, m.size());
  got.params.atomCount = static_cast<std::uint32_t>(base.size());
  test::expectSamePatchLists(got, buildSurface(base, {SurfaceKind::Ses, kRp}), "crambin with merged copies");
  ASSERT_EQ(notes.size(), 1u);
  EXPECT_NE(notes[0].find("300 atoms lie within 1e-05 Å"), std::string::npos) << notes[0];

  Molecule crowded = base;
  for (int k = 0; k < 40; ++k) {
    crowded.centers.push_back(base.centers[10] + glm::dvec3(1e-3 * std::sin(k), 1e-3 * std::cos(k), 1e-4 * k / 40.0));
    crowded.radii.push_back(base.radii[10]);
    crowded.atoms.push_back(base.atoms[10]);
  }
  try {
    buildSurface(crowded, {SurfaceKind::Ses, kRp});
    FAIL() << "a 41-atom cluster was built";
  } catch (const std::invalid_argument& e) {
    const std::string what = e.what();
    const std::string line = "line " + std::to_string(base.atoms[10].line);
    EXPECT_NE(what.find("41 atoms lie within 0.5 Å of " + line), std::string::npos) << what;
  }
}

// 216 clusters of k atoms within 1e-4 Å of one another, on a 6 x 6 x 6 grid of 3 Å whose
// points jitter by 0.3 Å; each cluster's first atom at its centre, the others within 2.5e-5 Å
// per axis of it (Hausdorff distance < 4.4e-5 Å). Lines number the atoms.
Molecule gridOfClusters(int k) {
  Molecule m;
  m.source = "clusters";
  std::mt19937_64 rng(29), rngIn(31);  // the clusters' centres do not depend on k
  std::uniform_real_distribution<double> jitter(-0.3, 0.3), spread(-2.5e-5, 2.5e-5);
  for (int x = 0; x < 6; ++x)
    for (int y = 0; y < 6; ++y)
      for (int z = 0; z < 6; ++z) {
        const glm::dvec3 centre = 3.0 * glm::dvec3(x, y, z) + glm::dvec3(jitter(rng), jitter(rng), jitter(rng));
        for (int a = 0; a < k; ++a) {
          m.centers.push_back(a == 0 ? centre : centre + glm::dvec3(spread(rngIn), spread(rngIn), spread(rngIn)));
          m.radii.push_back(1.7);
          m.atoms.emplace_back();
          m.atoms.back().line = static_cast<int>(m.centers.size());
        }
      }
  return m;
}

// Near-coincident clusters cost the builders about k^2.5 each (1,000 clusters of 8 atoms within
// 1e-4 Å: 32 s for the SES), so more than kMaxClusterAtoms (2) atoms within kClusterRadius
// (0.5 Å) are refused, and the work stays linear however the atoms cluster. A pair (a clash)
// is built, exactly: its SAS area is the union of the extended balls' (Gauss–Bonnet), and its
// SES body holds the lone atoms' and lies inside theirs grown by 1e-4 Å (adding or growing balls
// only grows the SES body). Three are refused, naming where and how many, with the merge
// distance that resolves them; merged, the surface is the lone atoms' bit for bit.
TEST(AtomCulling, NearCoincidentTriplesAreRefusedAndPairsBuiltExactly) {
  const Molecule singles = gridOfClusters(1), pairs = gridOfClusters(2), triples = gridOfClusters(3);
  const SurfaceRequest ses{SurfaceKind::Ses, kRp}, skin{SurfaceKind::Mss, kRp, 0.5};
  ASSERT_EQ(kMaxClusterAtoms, 2u);
  ASSERT_EQ(kClusterRadius, 0.5);

  const SurfaceAreas a = computeAreas(buildSurface(pairs, ses)), lone = computeAreas(buildSurface(singles, ses));
  // (Over the atoms kept: a few pairs lie within 1e-5 Å and merge, which moves the SAS by up to
  // ~1e-4 Å² each.)
  const CullResult cull = cullAtoms(pairs.centers, pairs.radii, {kRp});
  EXPECT_GT(cull.kept.size(), singles.size() * 3 / 2);
  std::vector<glm::dvec3> keptCentres;
  std::vector<double> extended;
  for (const std::uint32_t i : cull.kept) keptCentres.push_back(pairs.centers[i]), extended.push_back(pairs.radii[i] + kRp);
  const double unionArea = unionOfBallsAreas(keptCentres, extended).total();
  EXPECT_NEAR(a.sas, unionArea, 1e-9 * unionArea);
  Molecule grown = singles;
  for (double& r : grown.radii) r += 1e-4;
  const SurfaceAreas outer = computeAreas(buildSurface(grown, ses));
  EXPECT_GE(a.sesVolume, lone.sesVolume * (1 - 1e-12));
  EXPECT_LE(a.sesVolume, outer.sesVolume * (1 + 1e-12));
  EXPECT_EQ(a.components.size(), lone.components.size());
  EXPECT_LT(lone.sesVolume, outer.sesVolume);
  // The skin takes pairs too.
  EXPECT_GT(buildSurface(pairs, skin).mss.size(), buildSurface(singles, skin).mss.size());

  for (const SurfaceRequest& request : {ses, skin}) {
    const std::string kind = surfaceKindName(request.surface);
    std::string what = "no error";
    try {
      buildSurface(triples, request);
    } catch (const std::invalid_argument& e) {
      what = e.what();
    }
    EXPECT_EQ(what.find("clusters: 3 atoms lie within 0.5 Å of line "), 0u) << kind << ": " << what;
    EXPECT_NE(what.find(" kept atoms lie in such clusters in all, the farthest "), std::string::npos) << what;
    EXPECT_NE(what.find("a near-coincident cluster (more than 2 atoms there; a real structure has one)"),
              std::string::npos)
        << what;
    const std::size_t at = what.find("--merge-within ");
    ASSERT_NE(at, std::string::npos) << what;
    SurfaceRequest merged = request;
    merged.mergeWithin = std::stod(what.substr(at + 15));
    EXPECT_LE(merged.mergeWithin, 2e-4) << what;
    std::vector<std::string> notes;
    PatchList got = buildSurface(triples, merged, &notes);
    ASSERT_EQ(got.params.atomCount, triples.size());
    // The keepers are the clusters' first atoms, the lone atoms' centres: index 3c for atom c.
    for (auto* ids : {&got.convex.atom, &got.tori.atomI, &got.tori.atomJ, &got.concave.atomI, &got.concave.atomJ,
                      &got.concave.atomK})
      for (std::uint32_t& i : *ids) {
        EXPECT_EQ(i % 3, 0u);
        i /= 3;
      }
    for (glm::uvec4& simplex : got.mss.atoms)
      for (int c = 0; c < 4; ++c)
        if (simplex[c] != ~0u) {
          EXPECT_EQ(simplex[c] % 3, 0u);
          simplex[c] /= 3;
        }
    for (std::uint32_t& i : got.cellPlaneAtom)
      if (i != ~0u) i /= 3;
    // The skin's atoms are all the input's: the keepers' are the singles'.
    if (!got.skinAtoms.center.empty()) {
      ASSERT_EQ(got.skinAtoms.size(), triples.size());
      for (std::size_t c = 0; c < singles.size(); ++c) {
        got.skinAtoms.center[c] = got.skinAtoms.center[3 * c];
        got.skinAtoms.weight[c] = got.skinAtoms.weight[3 * c];
      }
      got.skinAtoms.center.resize(singles.size());
      got.skinAtoms.weight.resize(singles.size());
    }
    got.params.atomCount = static_cast<std::uint32_t>(singles.size());
    test::expectSamePatchLists(got, buildSurface(singles, request), kind + " of the merged clusters");
    ASSERT_EQ(notes.size(), 1u) << kind;
    EXPECT_NE(notes[0].find("432 atoms lie within"), std::string::npos) << notes[0];
  }
}

TEST(AtomCulling, MergeDistanceBelowTheSmallestIsAnError) {
  SurfaceRequest r{SurfaceKind::Ses, kRp};
  r.mergeWithin = 1e-6;
  EXPECT_THROW(buildSurface(crambin(), r), std::invalid_argument);
}

// Frame after frame: culling changes as atoms move into and out of others' balls (a full
// build then) and stays while others move (a partial update); every frame equals a fresh
// buildSurface of it.
TEST(AtomCulling, SurfaceBuilderCullsEachFrameAsAFreshBuildDoes) {
  const Molecule base = crambin();
  for (const SurfaceRequest request : {SurfaceRequest{SurfaceKind::Ses, kRp}, SurfaceRequest{SurfaceKind::Mss, kRp, 0.5}}) {
    Molecule m = base;
    // Atom 51: inside base atom 50 (now 52); atom 0: a copy of base atom 20 (now 21).
    insertAtom(m, 50, base.centers[50] + glm::dvec3(0.2, 0, 0), base.radii[50] - 0.5);
    insertAtom(m, 0, base.centers[20] + glm::dvec3(0, 0, 1e-9), base.radii[20]);
    SurfaceBuilder builder(request);
    test::expectSamePatchLists(builder.build(m), buildSurface(m, request), "frame 0");
    std::vector<Molecule> frames;
    Molecule f = m;
    f.centers[51] += glm::dvec3(0, 3.0, 0);  // out of its host: kept now
    frames.push_back(f);
    for (const std::size_t i : {100u, 101u, 102u}) f.centers[i] += glm::dvec3(0.05, 0, 0);  // others move
    frames.push_back(f);
    f.centers[0] += glm::dvec3(0.3, 0, 0);  // the copy moves away from atom 20: kept now
    frames.push_back(f);
    f.centers[0] = f.centers[21];  // and exactly onto it: the lower index stays
    f.centers[150] += glm::dvec3(0, 0, 0.05);
    frames.push_back(f);
    for (std::size_t k = 0; k < frames.size(); ++k) {
      const std::string where = std::string(surfaceKindName(request.surface)) + " frame " + std::to_string(k + 1);
      test::expectSamePatchLists(builder.update(frames[k]), buildSurface(frames[k], request), where);
      // Partial updates: frame 2, and frame 4 for the SES, where atom 21 now lies inside atom 0
      // (contour-buildup buries it); the skin merges it, which changes the atoms built.
      if (k == 1 || (k == 3 && request.surface == SurfaceKind::Ses)) {
        EXPECT_LT(builder.lastRecomputed(), m.size()) << where;
      }
    }
  }
}

}  // namespace
}  // namespace surftrace::build

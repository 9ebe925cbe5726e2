// SesBuilder::update against a full rebuild: every array equal, bit for bit.
#include <cstring>
#include <random>
#include <string>
#include <vector>

#include <glm/geometric.hpp>
#include <gtest/gtest.h>
#include <tbb/global_control.h>

#include "build/ses/contour_buildup.hpp"
#include "build/io/molecule.hpp"
#include "patch_compare.hpp"

namespace surftrace::build {
namespace {

constexpr double kRp = 1.4;

Molecule model(const std::string& file, int number) {
  ReadOptions options;
  options.model = number;
  return readMolecule(std::string(SURFTRACE_TEST_DATA) + "/" + file, options);
}

using test::expectSamePatchLists;

// Moves `atoms` to their positions in `to` and checks the update against a rebuild.
void moveAndCheck(SesBuilder& builder, std::vector<glm::dvec3>& current, const std::vector<double>& radii,
                  const std::vector<std::uint32_t>& atoms, const std::vector<glm::dvec3>& to, const std::string& where) {
  std::vector<glm::dvec3> where_;
  for (const std::uint32_t a : atoms) {
    current[a] = to[a];
    where_.push_back(to[a]);
  }
  const PatchList& updated = builder.update(atoms, where_);
  updated.validate();
  expectSamePatchLists(updated, buildSes(current, radii, SesParams{kRp}), where);
}

// 1D3Z (ubiquitin, NMR, 1231 atoms with hydrogens): residues move, one after another,
// from model 1 to their model 2..4 coordinates, as in a trajectory where a few residues
// are flexible.
TEST(PartialUpdate, NmrResiduesMoveBetweenModels) {
  const Molecule first = model("ensembles/1d3z.pdb.gz", 1);
  std::vector<glm::dvec3> current = first.centers;
  SesBuilder builder;
  builder.build(current, first.radii, SesParams{kRp});
  for (const int next : {2, 3, 4}) {
    const Molecule m = model("ensembles/1d3z.pdb.gz", next);
    ASSERT_EQ(m.size(), first.size());
    for (std::size_t i = 0; i < m.size(); ++i) ASSERT_EQ(m.atoms[i].name, first.atoms[i].name);
    // The flexible C-terminal tail (72-76), a loop (7-10) and a buried core residue (26).
    for (const std::vector<int>& residues : std::vector<std::vector<int>>{{72, 73, 74, 75, 76}, {7, 8, 9, 10}, {26}, {45}}) {
      std::vector<std::uint32_t> atoms;
      for (std::size_t i = 0; i < m.size(); ++i)
        if (std::find(residues.begin(), residues.end(), m.atoms[i].residueNumber) != residues.end())
          atoms.push_back(static_cast<std::uint32_t>(i));
      ASSERT_FALSE(atoms.empty());
      moveAndCheck(builder, current, first.radii, atoms, m.centers,
                   "model " + std::to_string(next) + ", residue " + std::to_string(residues[0]));
      const SesUpdateStats& stats = builder.lastUpdate();
      EXPECT_FALSE(stats.full);
      EXPECT_LT(stats.owners, m.size() / 2);
      EXPECT_LT(stats.contours, m.size() / 2);
    }
  }
  // Then the whole of model 5 at once (every atom moves: a full build).
  const Molecule m5 = model("ensembles/1d3z.pdb.gz", 5);
  current = m5.centers;
  expectSamePatchLists(builder.update(current), buildSes(current, first.radii, SesParams{kRp}), "model 5");
  EXPECT_TRUE(builder.lastUpdate().full);
}

// Whole frames one after another (every atom moves: full rebuilds by one builder, which keeps
// its arrays' memory from frame to frame), each followed by a partial update of a few atoms:
// every result equals a fresh buildSes, bit for bit, so nothing of an earlier frame stays.
TEST(PartialUpdate, WholeFramesOneAfterAnother) {
  const Molecule first = model("ensembles/1grm_elNemo_mode7.pdb.gz", 1);
  SesBuilder builder;
  builder.build(first.centers, first.radii, SesParams{kRp});
  for (const int frame : {6, 11, 2, 11}) {
    const Molecule m = model("ensembles/1grm_elNemo_mode7.pdb.gz", frame);
    std::vector<glm::dvec3> current = m.centers;
    expectSamePatchLists(builder.update(current), buildSes(current, first.radii, SesParams{kRp}),
                      "whole frame " + std::to_string(frame));
    EXPECT_TRUE(builder.lastUpdate().full);
    std::vector<glm::dvec3> to = current;
    std::vector<std::uint32_t> atoms;
    for (std::uint32_t a = 0; a < 20; ++a) atoms.push_back(a), to[a] += glm::dvec3(0.2, -0.1, 0.15);
    moveAndCheck(builder, current, first.radii, atoms, to, "after whole frame " + std::to_string(frame));
  }
}

// The elNemo normal-mode frames of gramicidin: every atom moves a little from frame to
// frame; here random halves of a residue range follow the mode.
TEST(PartialUpdate, NormalModeFramesInPieces) {
  const Molecule first = model("ensembles/1grm_elNemo_mode7.pdb.gz", 1);
  std::vector<glm::dvec3> current = first.centers;
  SesBuilder builder;
  builder.build(current, first.radii, SesParams{kRp});
  std::mt19937_64 rng(5);
  for (int frame = 2; frame <= 11; ++frame) {
    const Molecule m = model("ensembles/1grm_elNemo_mode7.pdb.gz", frame);
    ASSERT_EQ(m.size(), first.size());
    std::vector<std::uint32_t> atoms;
    for (std::size_t i = 0; i < m.size(); ++i)
      if (rng() % 10 == 0) atoms.push_back(static_cast<std::uint32_t>(i));
    moveAndCheck(builder, current, first.radii, atoms, m.centers, "frame " + std::to_string(frame));
  }
}

// Random subsets of atoms take random small steps (0.01 to 0.5 Å), including steps that
// bury or expose atoms and change which circles and vertices exist.
TEST(PartialUpdate, RandomSmallMovesOfRandomSubsets) {
  const Molecule m = model("ensembles/1d3z.pdb.gz", 1);
  std::vector<glm::dvec3> current = m.centers;
  SesBuilder builder;
  builder.build(current, m.radii, SesParams{kRp});
  std::mt19937_64 rng(11);
  std::uniform_real_distribution<double> step(0.01, 0.5);
  std::normal_distribution<double> g;
  for (int round = 0; round < 25; ++round) {
    const std::size_t count = 1 + rng() % 40;
    std::vector<std::uint32_t> atoms;
    std::vector<glm::dvec3> to = current;
    // Mostly a compact patch (a residue and its neighbours in sequence), sometimes anywhere.
    const bool compact = round % 3 != 0;
    const std::size_t start = rng() % m.size();
    for (std::size_t k = 0; k < count; ++k) {
      const auto a = static_cast<std::uint32_t>(compact ? (start + k) % m.size() : rng() % m.size());
      atoms.push_back(a);
      to[a] = current[a] + step(rng) * glm::normalize(glm::dvec3(g(rng), g(rng), g(rng)));
    }
    std::sort(atoms.begin(), atoms.end());
    atoms.erase(std::unique(atoms.begin(), atoms.end()), atoms.end());
    moveAndCheck(builder, current, m.radii, atoms, to, "round " + std::to_string(round));
  }
}

// An atom leaves for 1000 Å away (a free sphere there, its old neighbours exposed), then
// comes back: the list equals the rebuilds, and finally the original list.
TEST(PartialUpdate, AtomFarAwayAndBack) {
  const Molecule m = model("ensembles/1d3z.pdb.gz", 1);
  std::vector<glm::dvec3> current = m.centers;
  SesBuilder builder;
  const PatchList original = builder.build(current, m.radii, SesParams{kRp});
  for (const std::uint32_t atom : {0u, 300u, 615u, 1230u}) {
    std::vector<glm::dvec3> to = current;
    const glm::dvec3 home = current[atom];
    to[atom] = home + glm::dvec3(1000.0, -250.0, 30.0);
    moveAndCheck(builder, current, m.radii, {atom}, to, "atom " + std::to_string(atom) + " away");
    to[atom] = home;
    moveAndCheck(builder, current, m.radii, {atom}, to, "atom " + std::to_string(atom) + " back");
  }
  expectSamePatchLists(builder.patches(), original, "all back home");
}

// Burial by containment changes with the move: a hydrogen moved onto its heavy atom is
// buried (its neighbours' contours change), moved off again it is exposed.
TEST(PartialUpdate, BurialChanges) {
  const Molecule m = model("ensembles/1d3z.pdb.gz", 1);
  std::vector<glm::dvec3> current = m.centers;
  SesBuilder builder;
  builder.build(current, m.radii, SesParams{kRp});
  std::size_t h = 0;
  while (m.atoms[h].element != "H") ++h;
  std::size_t heavy = h;
  while (m.atoms[heavy].element == "H") --heavy;  // the preceding heavy atom
  std::vector<glm::dvec3> to = current;
  const glm::dvec3 home = current[h];
  to[h] = current[heavy] + glm::dvec3(0.05, 0.0, 0.0);
  moveAndCheck(builder, current, m.radii, {static_cast<std::uint32_t>(h)}, to, "hydrogen inside");
  to[h] = current[heavy];  // coincident centres
  moveAndCheck(builder, current, m.radii, {static_cast<std::uint32_t>(h)}, to, "hydrogen coincident");
  to[h] = home;
  moveAndCheck(builder, current, m.radii, {static_cast<std::uint32_t>(h)}, to, "hydrogen home");
}

// The same updates with one thread give the same lists.
TEST(PartialUpdate, SingleThreadGivesTheSameList) {
  const Molecule m1 = model("ensembles/1d3z.pdb.gz", 1), m2 = model("ensembles/1d3z.pdb.gz", 2);
  std::vector<std::uint32_t> atoms;
  std::vector<glm::dvec3> where;
  for (std::size_t i = 0; i < m1.size(); ++i) {
    if (m1.atoms[i].residueNumber >= 60 && m1.atoms[i].residueNumber <= 64) {
      atoms.push_back(static_cast<std::uint32_t>(i));
      where.push_back(m2.centers[i]);
    }
  }
  SesBuilder all;
  all.build(m1.centers, m1.radii, SesParams{kRp});
  const PatchList& fromAll = all.update(atoms, where);
  tbb::global_control single(tbb::global_control::max_allowed_parallelism, 1);
  SesBuilder one;
  one.build(m1.centers, m1.radii, SesParams{kRp});
  expectSamePatchLists(one.update(atoms, where), fromAll, "1 thread vs all");
}

TEST(PartialUpdate, Contract) {
  SesBuilder builder;
  const std::vector<glm::dvec3> c = {{0, 0, 0}, {3, 0, 0}};
  const std::vector<double> r = {1.7, 1.7};
  EXPECT_THROW(builder.update(c), std::logic_error);
  builder.build(c, r, SesParams{kRp});
  const std::vector<std::uint32_t> bad = {2};
  const std::vector<glm::dvec3> one = {{1, 1, 1}};
  EXPECT_THROW(builder.update(bad, one), std::invalid_argument);
  const std::vector<std::uint32_t> first = {0};
  const std::vector<glm::dvec3> nan = {{std::nan(""), 0, 0}};
  EXPECT_THROW(builder.update(first, nan), std::invalid_argument);
  EXPECT_THROW(builder.update(first, std::vector<glm::dvec3>{}), std::invalid_argument);
  // Nothing moves: nothing changes.
  const PatchList before = builder.patches();
  builder.update(c);
  EXPECT_EQ(builder.lastUpdate().moved, 0u);
  expectSamePatchLists(builder.patches(), before, "no move");
  // A repeated index takes its last position.
  const std::vector<std::uint32_t> twice = {1, 1};
  const std::vector<glm::dvec3> positions = {{9, 9, 9}, {2.5, 0.5, 0}};
  builder.update(twice, positions);
  expectSamePatchLists(builder.patches(), buildSes(std::vector<glm::dvec3>{{0, 0, 0}, {2.5, 0.5, 0}}, r, SesParams{kRp}),
                    "repeated index");
}

}  // namespace
}  // namespace surftrace::build

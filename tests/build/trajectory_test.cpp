// A topology bound to a trajectory, surfaces frame after frame, flexible atoms, and atom
// selections, on the AdK DIMS trajectory (adk.psf + adk_dims.dcd, 3341 atoms, 98 frames).
// Oracles: fresh builds of each frame's molecule (buildSurface, nothing kept between frames),
// the trajectory file's raw frames, and selections filtered atom by atom from the records.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <stdexcept>

#include "build/io/atom_selection.hpp"
#include "build/io/error.hpp"
#include "build/io/trajectory.hpp"
#include "build/surface.hpp"
#include "patch_compare.hpp"

namespace surftrace::build {
namespace {

const std::string kData = SURFTRACE_TEST_DATA;
const std::string kPsf = kData + "/trajectories/adk_dims/adk.psf.gz";
const std::string kDcd = kData + "/trajectories/adk_dims/adk_dims.dcd";

TEST(Trajectory, BindsTheSelectedAtomsToTheirFileIndices) {
  ReadOptions options;
  options.keepHydrogens = false;
  Trajectory t(kPsf, kDcd, options);
  EXPECT_EQ(t.frameCount(), 98u);  // the header says 500: frames are counted from the file size
  EXPECT_EQ(t.molecule().fileAtomCount, 3341u);
  const auto heavy = static_cast<std::size_t>(std::count_if(t.molecule().atoms.begin(), t.molecule().atoms.end(),
                                                            [](const AtomRecord& a) { return a.element != "H"; }));
  EXPECT_EQ(t.molecule().size(), heavy);
  EXPECT_LT(t.molecule().size(), 3341u);
  auto source = openTrajectory(kDcd);
  Frame raw;
  for (std::size_t k : {0u, 57u, 97u}) {
    t.load(k);
    source->read(k, raw);
    for (std::size_t i = 0; i < t.molecule().size(); ++i)
      ASSERT_EQ(t.molecule().centers[i], raw.positions[t.fileIndex()[i]]) << "frame " << k << " atom " << i;
  }
  EXPECT_THROW(t.load(98), InputError);
}

TEST(Trajectory, AtomCountsMustAgree) {
  try {
    Trajectory t(kPsf, kData + "/trajectories/sampletrajectory/sampletrajectory.dcd");
    FAIL() << "a 115-atom trajectory was accepted for a 3341-atom topology";
  } catch (const InputError& e) {
    const std::string what = e.what();
    EXPECT_NE(what.find("115 atoms"), std::string::npos) << what;
    EXPECT_NE(what.find("3341"), std::string::npos) << what;
    EXPECT_NE(what.find("sampletrajectory.dcd"), std::string::npos) << what;
  }
}

// Frame after frame with one SurfaceBuilder equals a fresh build of every frame.
void expectBuilderEqualsFreshBuilds(const SurfaceRequest& request, std::size_t frames, std::size_t stride) {
  Trajectory t(kPsf, kDcd);
  SurfaceBuilder builder(request);
  for (std::size_t n = 0; n < frames; ++n) {
    t.load(n * stride);
    const PatchList got = n == 0 ? builder.build(t.molecule()) : builder.update(t.molecule());
    test::expectSamePatchLists(got, buildSurface(t.molecule(), request), "frame " + std::to_string(n * stride));
    EXPECT_GT(got.patchCount(), 0u);
  }
}

TEST(SurfaceBuilder, SesFrameAfterFrameEqualsFreshBuilds) {
  expectBuilderEqualsFreshBuilds({SurfaceKind::Ses, 1.4, 0.5, false}, 4, 7);
  expectBuilderEqualsFreshBuilds({SurfaceKind::Ses, 1.4, 0.5, true}, 2, 30);
}
TEST(SurfaceBuilder, SkinFrameAfterFrameEqualsFreshBuilds) {
  expectBuilderEqualsFreshBuilds({SurfaceKind::Mss, 1.4, 0.5, false}, 3, 11);
  expectBuilderEqualsFreshBuilds({SurfaceKind::Mss, 1.4, 1.0, false}, 2, 11);
  expectBuilderEqualsFreshBuilds({SurfaceKind::Sas, 1.4, 0.5, false}, 2, 11);
}

// --flexible: the selected atoms take each frame's positions, the rest stay at the first frame;
// the partial update equals a fresh build of that molecule and recomputes only part of it.
void expectFlexibleEqualsFreshBuilds(const SurfaceRequest& request) {
  Trajectory t(kPsf, kDcd);
  const Molecule reference = t.molecule();
  const std::vector<std::uint32_t> flexible = selectAtoms(reference, "resid 122-135");
  ASSERT_GT(flexible.size(), 150u);
  ASSERT_LT(flexible.size(), reference.size() / 8);  // the builders rebuild in full past 1/8
  Molecule current = reference;
  SurfaceBuilder builder(request);
  builder.build(current);
  for (std::size_t k = 5; k < 98; k += 23) {
    t.load(k);
    for (std::uint32_t i : flexible) current.centers[i] = t.molecule().centers[i];
    const PatchList got = builder.update(current, flexible);
    EXPECT_LT(builder.lastRecomputed(), reference.size()) << "a partial update recomputed every atom";
    test::expectSamePatchLists(got, buildSurface(current, request), "flexible frame " + std::to_string(k));
  }
}

TEST(SurfaceBuilder, FlexibleAtomsSesEqualsFreshBuilds) { expectFlexibleEqualsFreshBuilds({SurfaceKind::Ses, 1.4, 0.5, false}); }
TEST(SurfaceBuilder, FlexibleAtomsSkinEqualsFreshBuilds) { expectFlexibleEqualsFreshBuilds({SurfaceKind::Mss, 1.4, 0.5, false}); }

TEST(SurfaceBuilder, UpdateBeforeBuildIsAnError) {
  SurfaceBuilder builder(SurfaceRequest{});
  Molecule m;
  EXPECT_THROW(builder.update(m), std::logic_error);
}

// Selections against a filter of the records, term by term.
TEST(AtomSelection, EachTermSelectsWhatTheRecordsSay) {
  Trajectory t(kPsf, kDcd);
  const Molecule& m = t.molecule();
  const auto brute = [&](auto&& keep) {
    std::vector<std::uint32_t> out;
    for (std::size_t i = 0; i < m.size(); ++i)
      if (keep(m.atoms[i], i)) out.push_back(static_cast<std::uint32_t>(i));
    return out;
  };
  EXPECT_EQ(selectAtoms(m, "resid 10-20 30"),
            brute([](const AtomRecord& a, std::size_t) { return (a.residueNumber >= 10 && a.residueNumber <= 20) || a.residueNumber == 30; }));
  EXPECT_EQ(selectAtoms(m, "name CA"), brute([](const AtomRecord& a, std::size_t) { return a.name == "CA"; }));
  EXPECT_EQ(selectAtoms(m, "resname GLY ALA, atom 1-5"),
            brute([](const AtomRecord& a, std::size_t i) { return a.residue == "GLY" || a.residue == "ALA" || i < 5; }));
  EXPECT_EQ(selectAtoms(m, "chain 4AKE").size(), m.size());  // the PSF's segment id
  EXPECT_EQ(selectAtoms(m, "segid 4AKE").size(), m.size());
  EXPECT_EQ(selectAtoms(m, "name CA").size(), 214u);
  for (const char* bad : {"", "resid", "resid 20-10", "resid x", "colour red", "chain Q", "atom 99999"})
    EXPECT_THROW(selectAtoms(m, bad), std::invalid_argument) << "'" << bad << "'";
}

}  // namespace
}  // namespace surftrace::build

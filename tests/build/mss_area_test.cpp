// The skin's areas (computeMssAreas) against the adaptive integration it replaced (issue 22),
// patch by patch, against a two-atom skin integrated along its profile of revolution, and
// against itself under another thread count.
#include <algorithm>
#include <cmath>
#include <cstring>
#include <numbers>
#include <string>
#include <vector>

#include <boost/math/quadrature/gauss_kronrod.hpp>
#include <gtest/gtest.h>
#include <tbb/global_control.h>

#include "build/io/molecule.hpp"
#include "build/mss/mss_area.hpp"
#include "build/mss/mss_builder.hpp"

namespace surftrace::build {
namespace {

Molecule molecule(const std::string& file) { return readMolecule(std::string(SURFTRACE_TEST_DATA) + "/" + file); }

// Every patch, the totals, the volume, the closure and the per-atom shares of `got` against
// `want`. A patch may differ by 1e-9 of itself plus 1e-10 of its sphere of bounds (2π·bound²,
// the scale of the old per-piece tolerance): tiny patches are resolved absolutely, not to 1e-9
// of themselves, by either integration.
void expectSameAreas(const PatchList& p, const MssAreas& got, const MssAreas& want, const std::string& where) {
  ASSERT_EQ(got.perPatch.size(), want.perPatch.size());
  double worstPatch = 0.0;
  std::size_t failures = 0;
  for (std::size_t k = 0; k < want.perPatch.size(); ++k) {
    const double scale = 2.0 * std::numbers::pi * p.mss.boundRadius[k] * p.mss.boundRadius[k];
    const double diff = std::abs(got.perPatch[k] - want.perPatch[k]);
    worstPatch = std::max(worstPatch, diff / (1e-9 * std::abs(want.perPatch[k]) + 1e-10 * scale));
    if (diff > 1e-9 * std::abs(want.perPatch[k]) + 1e-10 * scale && ++failures <= 5)
      ADD_FAILURE() << where << " patch " << k << " kind " << p.mss.kind[k] << ": " << got.perPatch[k] << " vs "
                    << want.perPatch[k];
  }
  const double total = want.total();
  for (std::size_t kind = 0; kind < kMssKindCount; ++kind)
    EXPECT_NEAR(got.byKind[kind], want.byKind[kind], 1e-11 * total) << where << " kind " << kind;
  EXPECT_NEAR(got.total(), total, 1e-11 * total) << where;
  EXPECT_NEAR(got.volume, want.volume, 1e-11 * std::abs(want.volume)) << where;
  EXPECT_LT(got.closure, 1e-8 * total) << where;
  double worstAtom = 0.0;
  for (std::size_t i = 0; i < want.perAtom.size(); ++i) {
    const double diff = std::abs(got.perAtom[i] - want.perAtom[i]);
    worstAtom = std::max(worstAtom, diff / std::max(want.perAtom[i], 1e-3));
    EXPECT_LE(diff, 1e-9 * std::max(want.perAtom[i], 1e-3)) << where << " atom " << i;
  }
  std::cout << "[ stats    ] " << where << ": total " << got.total() << " vs " << total << " (rel "
            << std::abs(got.total() - total) / total << "), volume rel " << std::abs(got.volume - want.volume) / want.volume
            << ", worst patch " << worstPatch << " of its tolerance, worst atom rel " << worstAtom << ", error estimates "
            << got.areaErrorEstimate << " / " << want.areaErrorEstimate << "\n";
}

// Against the old integration at its own tolerance (the values of the integration in h this
// replaced agree with it to the same margin) and at a tighter one (a high-order reference), over
// every patch of real molecules at shrink factors from a thin to an almost van der Waals skin.
TEST(MssAreas, MatchesTheAdaptiveReferencePatchByPatch) {
  for (const char* file : {"structures/1crn.pdb", "paper/1grm.pdb.gz", "paper/1vis.pdb.gz"}) {
    const Molecule m = molecule(file);
    for (double s : {0.1, 0.3, 0.5, 0.9}) {
      const PatchList p = buildMss(m.centers, m.radii, {s});
      const MssAreas got = computeMssAreas(p, m.centers);
      const std::string where = std::string(file) + " s = " + std::to_string(s);
      expectSameAreas(p, got, computeMssAreasAdaptive(p, m.centers, 1e-10), where + " (old, 1e-10)");
      if (std::strcmp(file, "structures/1crn.pdb") == 0)
        expectSameAreas(p, got, computeMssAreasAdaptive(p, m.centers, 1e-12), where + " (reference, 1e-12)");
    }
  }
}

// Two atoms on the x axis: the skin is a surface of revolution whose profile is, cell by cell
// (ORACLES C.3, C.4), q(x) = r(x)² = r_i² − x² up to the plane x = s·x_X, s(u²/(1 − s) − w_X)
// with u = x − x_X up to x = (1 − s)d + s·x_X, then r_j² − (x − d)². Area 2π∫√(q + q′²/4) dx and
// volume π∫q dx over where q ≥ 0, integrated numerically with breakpoints at the cell planes
// and where the neck pinches (q = 0 inside the edge's cell: the grown balls apart).
struct ProfileValues {
  double area, volume;
};

ProfileValues twoAtomProfile(double ri, double rj, double d, double s) {
  const double wi = ri * ri / s, wj = rj * rj / s;
  const double alpha = 0.5 + (wi - wj) / (2 * d * d), wX = alpha * alpha * d * d - wi, xX = alpha * d;
  const double cutI = s * xX, cutJ = (1 - s) * d + s * xX;
  using Kronrod = boost::math::quadrature::gauss_kronrod<double, 31>;
  ProfileValues out{0.0, 0.0};
  auto add = [&](double a, double b, auto q, auto dq) {
    if (!(b > a)) return;
    out.area += 2 * std::numbers::pi *
                Kronrod::integrate([&](double x) { return std::sqrt(std::max(0.0, q(x) + 0.25 * dq(x) * dq(x))); }, a, b, 15,
                                   1e-14);
    out.volume += std::numbers::pi * Kronrod::integrate([&](double x) { return std::max(0.0, q(x)); }, a, b, 20, 1e-14);
  };
  add(-ri, std::min(cutI, ri), [&](double x) { return ri * ri - x * x; }, [&](double x) { return -2 * x; });
  add(std::max(cutJ, d - rj), d + rj, [&](double x) { return rj * rj - (x - d) * (x - d); },
      [&](double x) { return -2 * (x - d); });
  auto neck = [&](double x) { return s * ((x - xX) * (x - xX) / (1 - s) - wX); };
  auto dneck = [&](double x) { return 2 * s * (x - xX) / (1 - s); };
  if (wX <= 0.0) {
    add(cutI, cutJ, neck, dneck);
  } else {  // two sheets: q < 0 for |x − x_X| < √((1 − s) w_X)
    const double gap = std::sqrt((1 - s) * wX);
    add(cutI, std::min(cutJ, xX - gap), neck, dneck);
    add(std::max(cutI, xX + gap), cutJ, neck, dneck);
  }
  return out;
}

TEST(MssAreas, TwoAtomsMatchTheirProfileOfRevolution) {
  for (const auto& [ri, rj] : {std::pair{1.6, 1.2}, std::pair{1.7, 1.7}, std::pair{1.9, 1.0}}) {
    for (double s : {0.3, 0.5, 0.7}) {
      const double contact = (ri + rj) / std::sqrt(s);
      for (double factor : {0.6, 0.9, 0.999, 1.0, 1.001, 1.1}) {
        const double d = contact * factor;
        const std::vector<glm::dvec3> c{{0.25, -0.5, 1.0}, {0.25 + d, -0.5, 1.0}};
        const std::vector<double> r{ri, rj};
        const PatchList p = buildMss(c, r, {s});
        const MssAreas a = computeMssAreas(p, c);
        const ProfileValues want = twoAtomProfile(ri, rj, d, s);
        const std::string where = "r " + std::to_string(ri) + ", " + std::to_string(rj) + " s " + std::to_string(s) +
                                  " d/contact " + std::to_string(factor);
        EXPECT_NEAR(a.total(), want.area, 1e-10 * want.area) << where;
        EXPECT_NEAR(a.volume, want.volume, 1e-10 * want.volume) << where;
        EXPECT_LT(a.closure, 1e-9 * want.area) << where;
        EXPECT_LT(a.areaErrorEstimate, 1e-9 * want.area) << where;
        EXPECT_NEAR(a.perAtom[0] + a.perAtom[1], a.total(), 1e-12 * want.area) << where;
        // The old integration to the same values.
        const MssAreas old = computeMssAreasAdaptive(p, c);
        EXPECT_NEAR(a.total(), old.total(), 1e-10 * want.area) << where;
        EXPECT_NEAR(a.perAtom[0], old.perAtom[0], 1e-9 * want.area) << where;
      }
    }
  }
}

// Each patch is integrated alone and the sums run in patch order, so the thread count cannot
// change a bit of the result.
TEST(MssAreas, SameValuesForAnyThreadCount) {
  const Molecule m = molecule("paper/1vis.pdb.gz");
  const PatchList p = buildMss(m.centers, m.radii, {0.5});
  MssAreas one, two;
  {
    tbb::global_control limit(tbb::global_control::max_allowed_parallelism, 1);
    one = computeMssAreas(p, m.centers);
  }
  {
    tbb::global_control limit(tbb::global_control::max_allowed_parallelism, 2);
    two = computeMssAreas(p, m.centers);
  }
  EXPECT_EQ(std::memcmp(one.byKind, two.byKind, sizeof one.byKind), 0);
  EXPECT_EQ(one.volume, two.volume);
  EXPECT_EQ(one.areaErrorEstimate, two.areaErrorEstimate);
  EXPECT_EQ(one.volumeErrorEstimate, two.volumeErrorEstimate);
  EXPECT_EQ(one.closure, two.closure);
  EXPECT_EQ(one.perPatch, two.perPatch);
  EXPECT_EQ(one.perAtom, two.perAtom);
}

}  // namespace
}  // namespace surftrace::build



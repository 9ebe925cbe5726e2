// Transparency: every crossing of a ray with the surface (trace/layers.hpp) against point
// oracles of the body sampled along the ray (SES: ORACLES D.1; vdW: the union of balls; skin:
// the certified sign of D.3), against a plain loop over the patches, and the composited colour
// against its formula.
#include <algorithm>
#include <cmath>
#include <cstdio>
#include <functional>
#include <map>
#include <numbers>
#include <random>
#include <sstream>
#include <string>
#include <vector>

#include <glm/geometric.hpp>
#include <gtest/gtest.h>

#include "build/atom_spheres.hpp"
#include "build/io/molecule.hpp"
#include "build/mss/mss_builder.hpp"
#include "build/ses/contour_buildup.hpp"
#include "build/sphere_blockers.hpp"
#include "build/surface.hpp"
#include "build/surface_components.hpp"
#include "oracles/ray_march.hpp"
#include "oracles/ses_oracle.hpp"
#include "oracles/skin_certificate.hpp"
#include "trace/layers.hpp"
#include "trace/render.hpp"
#include "view/shading.hpp"

namespace surftrace::trace {
namespace {

constexpr double kRp = 1.4;
// The march samples the body every kStep Å and bisects each change of side. Two crossings
// closer than a step (a ray that just clips a thin part of the body, or grazes it) can hide
// from it; a ray is compared only where both lists keep their crossings more than
// kSeparation apart (and, for its crossings, the ray is not within kGrazing of tangent).
constexpr double kStep = 0.01;
constexpr double kSeparation = 5 * kStep;
constexpr double kGrazing = 0.05;
constexpr double kTTolerance = 1e-6;  // Å: the oracle's roots are bisected to long-double resolution

const build::Molecule& molecule(const std::string& file) {
  static std::map<std::string, build::Molecule> cache;
  auto it = cache.find(file);
  if (it == cache.end()) it = cache.emplace(file, build::readMolecule(std::string(SURFTRACE_TEST_DATA) + "/" + file)).first;
  return it->second;
}

glm::dvec3 randomUnit(std::mt19937_64& rng) {
  std::normal_distribution<double> n(0.0, 1.0);
  glm::dvec3 d;
  do d = {n(rng), n(rng), n(rng)};
  while (glm::length(d) < 1e-3);
  return glm::normalize(d);
}

// A ray from outside the box through a random point of its middle half, with its span over
// the box (a little grown).
struct BoxRay {
  Ray ray;
  double tEnd;
};
BoxRay randomRay(std::mt19937_64& rng, const glm::dvec3& lo, const glm::dvec3& hi) {
  std::uniform_real_distribution<double> u(0.25, 0.75);
  const glm::dvec3 target = lo + glm::dvec3(u(rng), u(rng), u(rng)) * (hi - lo);
  const glm::dvec3 d = randomUnit(rng);
  const double reach = glm::length(hi - lo) + 1.0;
  return {Ray{target - reach * d, d}, 2.0 * reach};
}

// Sorted and far enough apart to compare.
bool separated(const std::vector<double>& t) {
  for (std::size_t i = 1; i < t.size(); ++i)
    if (t[i] - t[i - 1] < kSeparation) return false;
  return true;
}

struct Tally {
  int compared = 0, masked = 0;
};

// Compares the scene's crossings of `ray` with the sign changes of inside(x) (true in the
// body), sampled every kStep over [0, tEnd].
void compareCrossings(const PatchScene& scene, const BoxRay& r, const std::function<int(const glm::dvec3&)>& side,
                      Tally& tally, const std::string& what) {
  const std::vector<SceneHit> layers = scene.intersectLayers1(r.ray, kMaxLayers);
  std::vector<double> ours;
  bool grazing = false;
  for (const SceneHit& h : layers) {
    ours.push_back(h.hit.t);
    grazing = grazing || std::abs(glm::dot(h.hit.normal, r.ray.dir)) < kGrazing;
  }
  bool undecided = false;
  auto f = [&](long double t) -> long double {
    const int s = side(r.ray.org + static_cast<double>(t) * r.ray.dir);
    undecided = undecided || s == 0;
    return s;
  };
  const int steps = static_cast<int>(r.tEnd / kStep);
  std::vector<double> oracle;
  for (long double t : oracles::marchRoots(f, 0.0L, static_cast<long double>(r.tEnd), steps)) oracle.push_back(static_cast<double>(t));
  if (grazing || undecided || !separated(ours) || !separated(oracle)) {
    ++tally.masked;
    return;
  }
  ++tally.compared;
  std::ostringstream listed;
  listed.precision(10);
  for (const SceneHit& h : layers) listed << " " << h.hit.t << " (kind " << static_cast<int>(h.kind) << " patch " << h.patch << ")";
  listed << " vs oracle";
  for (double t : oracle) listed << " " << t;
  ASSERT_EQ(ours.size(), oracle.size()) << what << ":" << listed.str();
  for (std::size_t i = 0; i < ours.size(); ++i)
    EXPECT_NEAR(ours[i], oracle[i], kTTolerance) << what << " crossing " << i;
  // Crossings alternate entering and leaving, starting outside: the outward normal faces
  // against the ray on entry and along it on exit.
  for (std::size_t i = 0; i < layers.size(); ++i)
    EXPECT_EQ(glm::dot(layers[i].hit.normal, r.ray.dir) > 0.0, i % 2 == 1) << what << " crossing " << i;
}

std::vector<oracle::Sphere> oracleAtoms(const build::Molecule& m) {
  std::vector<oracle::Sphere> atoms;
  for (std::size_t i = 0; i < m.size(); ++i) atoms.push_back({m.centers[i], m.radii[i]});
  return atoms;
}

void boxOf(const build::Molecule& m, double grow, glm::dvec3& lo, glm::dvec3& hi) {
  lo = glm::dvec3(1e300);
  hi = glm::dvec3(-1e300);
  for (std::size_t i = 0; i < m.size(); ++i) {
    lo = glm::min(lo, m.centers[i] - (m.radii[i] + grow));
    hi = glm::max(hi, m.centers[i] + (m.radii[i] + grow));
  }
}

// ---------------------------------------------------------------------------------------
// The SES: sign changes of dist(x, A) − rp (ORACLES D.1; cavities are part of both).

class SesCrossings : public testing::TestWithParam<std::string> {};

TEST_P(SesCrossings, CountAndPlaceMatchTheSesOracle) {
  const build::Molecule& m = molecule(GetParam());
  const build::PatchList list = build::buildSes(m.centers, m.radii, build::SesParams{kRp});
  // The atoms: buried ones, which have no sphere in the list, hide parts of their neighbours'.
  const PatchScene scene(ScenePatches::fromPatchList(list, m.centers, m.radii));
  const oracle::SesOracle oracle(oracleAtoms(m), kRp);
  const auto side = [&](const glm::dvec3& x) {
    const double d = oracle.distanceToAccessible(x).dist;
    return d >= kRp ? 1 : -1;
  };
  glm::dvec3 lo, hi;
  boxOf(m, 0.0, lo, hi);
  std::mt19937_64 rng(21);
  Tally tally;
  std::size_t most = 0;
  for (int i = 0; i < 120; ++i) {
    const BoxRay r = randomRay(rng, lo, hi);
    compareCrossings(scene, r, side, tally, GetParam() + " ray " + std::to_string(i));
    most = std::max(most, scene.intersectLayers1(r.ray, kMaxLayers).size());
    if (HasFatalFailure()) return;
  }
  std::printf("%s: %d rays compared, %d masked, up to %zu crossings\n", GetParam().c_str(), tally.compared, tally.masked, most);
  EXPECT_GE(tally.compared, 100) << "too many rays masked";
  EXPECT_GE(most, 4u) << "the rays should cross several layers";
}

INSTANTIATE_TEST_SUITE_P(Molecules, SesCrossings, testing::Values("structures/1crn.pdb", "small/1grm_single.pdb"),
                         [](const testing::TestParamInfo<std::string>& p) { return p.index == 0 ? std::string("1crn") : std::string("1grm"); });

// ---------------------------------------------------------------------------------------
// The vdW balls: a hit on a sphere inside another ball is not a crossing.

TEST(VdwCrossings, CountAndPlaceMatchTheUnionOfBalls) {
  const build::Molecule& m = molecule("structures/1crn.pdb");
  const build::PatchList list = build::atomSpheres(m.centers, m.radii, 0.0, build::SurfaceKind::Vdw);
  const PatchScene scene(ScenePatches::fromPatchList(list));
  const auto side = [&](const glm::dvec3& x) {
    for (std::size_t i = 0; i < m.size(); ++i)
      if (glm::length(x - m.centers[i]) < m.radii[i]) return 1;
    return -1;
  };
  glm::dvec3 lo, hi;
  boxOf(m, 0.0, lo, hi);
  std::mt19937_64 rng(5);
  Tally tally;
  for (int i = 0; i < 150; ++i) {
    compareCrossings(scene, randomRay(rng, lo, hi), side, tally, "vdW ray " + std::to_string(i));
    if (HasFatalFailure()) return;
  }
  EXPECT_GE(tally.compared, 120) << "too many rays masked";
}

TEST(VdwCrossings, TwoOverlappingBallsAlongTheirAxisAreTwoCrossings) {
  const glm::dvec3 centers[] = {{0, 0, 0}, {2, 0, 0}};
  const double radii[] = {1.5, 1.5};
  const PatchScene scene(ScenePatches::fromPatchList(build::atomSpheres(centers, radii, 0.0, build::SurfaceKind::Vdw)));
  const std::vector<SceneHit> layers = scene.intersectLayers1(Ray{{-10, 0.1, 0}, {1, 0, 0}}, 16);
  ASSERT_EQ(layers.size(), 2u);  // the whole spheres have 4 roots: the two inside the other ball are hidden
  EXPECT_NEAR(layers[0].hit.t, 10.0 - std::sqrt(1.5 * 1.5 - 0.01), 1e-12);
  EXPECT_NEAR(layers[1].hit.t, 12.0 + std::sqrt(1.5 * 1.5 - 0.01), 1e-12);
}

// ---------------------------------------------------------------------------------------
// The skin: the certified sign of G (ORACLES D.3) on 1CRN, and two atoms against the analytic
// profile (ORACLES E.4: a neck iff d < (r1 + r2)/√s).

TEST(SkinCrossings, CountAndPlaceMatchTheSkinOracle) {
  const build::Molecule& m = molecule("structures/1crn.pdb");
  const double s = 0.5;
  const build::PatchList list = build::buildMss(m.centers, m.radii, {s});
  const PatchScene scene(ScenePatches::fromPatchList(list));
  const auto side = [&](const glm::dvec3& x) { return -oracle::skinSign(m.centers, m.radii, s, x); };
  glm::dvec3 lo, hi;
  boxOf(m, 0.0, lo, hi);
  std::mt19937_64 rng(9);
  Tally tally;
  for (int i = 0; i < 40; ++i) {
    compareCrossings(scene, randomRay(rng, lo, hi), side, tally, "skin ray " + std::to_string(i));
    if (HasFatalFailure()) return;
  }
  EXPECT_GE(tally.compared, 30) << "too many rays masked";
}

TEST(SkinCrossings, TwoAtomsMatchTheAnalyticProfile) {
  const double r = 1.5, s = 0.5;
  const double neck = 2.0 * r / std::sqrt(s);  // the skin pinches at this distance
  for (const double d : {0.8 * neck, 1.2 * neck}) {
    const glm::dvec3 centers[] = {{0, 0, 0}, {d, 0, 0}};
    const double radii[] = {r, r};
    const PatchScene scene(ScenePatches::fromPatchList(build::buildMss(centers, radii, {s})));
    // Along the axis: in at −r, out at d + r, and in between only where the balls part.
    const std::vector<SceneHit> axis = scene.intersectLayers1(Ray{{-10, 0, 0}, {1, 0, 0}}, 16);
    ASSERT_EQ(axis.size(), d < neck ? 2u : 4u) << "d = " << d;
    EXPECT_NEAR(axis.front().hit.t, 10.0 - r, 1e-9);
    EXPECT_NEAR(axis.back().hit.t, 10.0 + d + r, 1e-9);
    // Across the middle: through the neck or through nothing.
    const std::vector<SceneHit> across = scene.intersectLayers1(Ray{{d / 2, -10, 0.01}, {0, 1, 0}}, 16);
    EXPECT_EQ(across.size(), d < neck ? 2u : 0u) << "d = " << d;
  }
}

// ---------------------------------------------------------------------------------------
// The BVH's crossings against a plain loop over every patch.

TEST(Crossings, MatchAPlainLoopOverThePatches) {
  const build::Molecule& m = molecule("small/1grm_single.pdb");
  const build::PatchList list = build::buildSes(m.centers, m.radii, build::SesParams{kRp});
  const PatchScene scene(ScenePatches::fromPatchList(list, m.centers, m.radii));
  const SphereClip clip(scene.patches());
  glm::dvec3 lo, hi;
  boxOf(m, 0.0, lo, hi);
  std::mt19937_64 rng(3);
  for (int i = 0; i < 200; ++i) {
    const BoxRay r = randomRay(rng, lo, hi);
    for (const std::size_t cap : {std::size_t{3}, std::size_t{kMaxLayers}}) {
      const std::vector<SceneHit> got = scene.intersectLayers1(r.ray, cap);
      const std::vector<SceneHit> want = crossingsAll(scene.patches(), clip, r.ray, cap);
      ASSERT_EQ(got.size(), want.size()) << "ray " << i << " cap " << cap;
      for (std::size_t k = 0; k < got.size(); ++k) {
        EXPECT_NEAR(got[k].hit.t, want[k].hit.t, 1e-9) << "ray " << i << " crossing " << k;
        EXPECT_EQ(got[k].kind, want[k].kind) << "ray " << i << " crossing " << k;
        EXPECT_EQ(got[k].patch, want[k].patch) << "ray " << i << " crossing " << k;
      }
    }
  }
}

// ---------------------------------------------------------------------------------------
// A closed surface: every ray that enters it leaves it, so each pixel crosses it an even
// number of times. With --drop-cavities the outer surface alone is drawn (1VIS, 512², the
// render command's front view): 62 pixels once crossed it an odd number of times.

TEST(Crossings, EveryPixelCrossesTheOuterSesAnEvenNumberOfTimes) {
  const build::Molecule& m = molecule("paper/1vis.pdb.gz");
  build::SurfaceRequest request;
  request.probeRadius = kRp;
  const build::PatchList all = build::buildSurface(m, request);
  const build::PatchList list = build::outerComponent(all);
  // The saddle arcs stay with the spheres whose edge they leave open: none of the whole SES's,
  // a few of the outer one's (those that also line a cavity).
  std::vector<glm::dvec4> atoms;
  for (std::size_t i = 0; i < m.size(); ++i) atoms.push_back(glm::dvec4(m.centers[i], m.radii[i]));
  EXPECT_TRUE(build::sphereBlockers(all, atoms).arcs.empty());
  const build::SphereBlockers outer = build::sphereBlockers(list, atoms);
  std::size_t open = 0;
  for (std::size_t i = 0; i + 1 < outer.arcBegin.size(); ++i) open += outer.arcBegin[i + 1] > outer.arcBegin[i];
  std::printf("1VIS outer SES: %zu of %zu spheres keep their saddle arcs\n", open, list.convex.size());
  EXPECT_GT(open, 0u);
  EXPECT_LT(open, list.convex.size() / 20);
  const PatchScene scene(ScenePatches::fromPatchList(list, m.centers, m.radii));
  view::RenderOptions o;
  o.camera.width = o.camera.height = 512;
  o.camera = view::frameSpheres(o.camera, m.centers, request.reach(m.radii), view::namedViewDirection("front"));
  o.opacity = 0.4;
  o.maxLayers = kMaxLayers;  // every crossing: none dropped
  const view::FrameBuffers fb = render(scene, o, {});
  const view::Camera::Frame frame = o.camera.frame();
  std::size_t odd = 0, covered = 0, most = 0;
  for (int y = 0; y < o.camera.height; ++y)
    for (int x = 0; x < o.camera.width; ++x) {
      const std::size_t p = static_cast<std::size_t>(y) * o.camera.width + x;
      covered += fb.layers[p] > 0;
      most = std::max<std::size_t>(most, fb.layers[p]);
      if (fb.layers[p] % 2 == 0) continue;
      if (++odd > 12) continue;
      std::ostringstream listed;
      listed.precision(12);
      for (const SceneHit& h : scene.intersectLayers1(frame.ray(x + 0.5, y + 0.5), kMaxLayers))
        listed << " " << h.hit.t << " (kind " << static_cast<int>(h.kind) << " patch " << h.patch << ", n.d "
               << glm::dot(h.hit.normal, glm::normalize(frame.ray(x + 0.5, y + 0.5).dir)) << ")";
      ADD_FAILURE() << "pixel " << x << "," << y << ": " << fb.layers[p] << " crossings:" << listed.str();
    }
  std::printf("1VIS outer SES at 512²: %zu covered pixels, up to %zu crossings, %zu odd\n", covered, most, odd);
  EXPECT_EQ(odd, 0u);
  EXPECT_GT(covered, 50000u);
  EXPECT_GE(most, 10u);
}

// SphereClip decides per sphere, when a hit first asks, whether its saddle arcs bound its kept
// part; build::addSaddleArcs decides for every sphere up front. On the 1VIS outer SES (spheres
// that also line a dropped cavity keep their arcs) both say the same for random points of
// every sphere, asked in a random order of the spheres, among them points that only the arcs
// drop (so a SphereClip that skipped the arcs would differ; testing them on every sphere would
// only be slower: a sphere whose edges are all on arcs keeps every free point).
TEST(SaddleArcs, CheckedOnFirstUseAsWhenAllAreCheckedUpFront) {
  const build::Molecule& m = molecule("paper/1vis.pdb.gz");
  build::SurfaceRequest request;
  request.probeRadius = kRp;
  const build::PatchList list = build::outerComponent(build::buildSurface(m, request));
  std::vector<glm::dvec4> atoms;
  for (std::size_t i = 0; i < m.size(); ++i) atoms.push_back(glm::dvec4(m.centers[i], m.radii[i]));
  const build::SphereBlockers upFront = build::sphereBlockers(list, atoms);
  const SphereClip clip(ScenePatches::fromPatchList(list, m.centers, m.radii));
  std::vector<std::uint32_t> order(list.convex.size());
  for (std::uint32_t i = 0; i < order.size(); ++i) order[i] = i;
  std::mt19937_64 rng(5);
  std::shuffle(order.begin(), order.end(), rng);
  std::size_t points = 0, onPatch = 0, droppedByArcs = 0;
  for (const std::uint32_t i : order) {
    const glm::dvec3 c = list.convex.center[i];
    const double rho = list.convex.radius[i];
    // Denser on the spheres that keep arcs: their dropped parts are small.
    const bool keepsArcs = !upFront.arcBegin.empty() && upFront.arcBegin[i + 1] > upFront.arcBegin[i];
    for (int k = 0; k < (keepsArcs ? 5000 : 50); ++k) {
      const glm::dvec3 x = c + rho * randomUnit(rng);
      const bool expected = build::onConvexPatch(upFront, i, c, rho, x, kBoundaryTolerance);
      ASSERT_EQ(clip.onPatch(i, x), expected) << "sphere " << i << " point " << k;
      ++points;
      onPatch += expected;
      droppedByArcs += !expected && build::onConvexPatch(upFront, i, c, rho, x, kBoundaryTolerance, false);
    }
  }
  std::printf("1VIS outer SES: %zu points, %zu on a patch, %zu dropped by saddle arcs alone\n", points, onPatch,
              droppedByArcs);
  EXPECT_GT(onPatch, points / 50);
  EXPECT_GT(droppedByArcs, 50u);
}

// The blocker lists against brute force over every pair: the atoms whose grown balls meet each
// grown sphere, its own atom left out, nearest (centre distance minus grown radius) first, ties
// by index. Atoms on both sides of the origin and far apart cross many grid cells, and pairs of
// atoms at one place (ties) and a cluster dense in one cell are there too.
TEST(SphereBlockers, ListsAreTheMeetingBallsNearestFirstByBruteForce) {
  std::mt19937_64 rng(36);
  std::uniform_real_distribution<double> coord(-25.0, 25.0), radius(1.0, 2.0);
  std::vector<glm::dvec4> atoms;
  for (int k = 0; k < 400; ++k) atoms.push_back({coord(rng), coord(rng), 0.2 * coord(rng), radius(rng)});
  for (int k = 0; k < 40; ++k) atoms.push_back({1e3 + 0.1 * coord(rng), -1e3, 0.0, radius(rng)});
  atoms.push_back(atoms[7]);  // a tie: two blockers at one place
  for (const build::SurfaceKind kind : {build::SurfaceKind::Ses, build::SurfaceKind::Vdw}) {
    build::SurfaceParams params;
    params.surface = kind;
    params.probeRadius = kRp;
    // Every second atom has a sphere (radius its own), as an SES list has its exposed atoms'.
    std::vector<glm::dvec3> centers;
    std::vector<double> radii;
    std::vector<std::uint32_t> sphereAtoms;
    for (std::uint32_t k = 0; k < atoms.size(); k += 2) {
      centers.push_back(glm::dvec3(atoms[k]));
      radii.push_back(atoms[k].w);
      sphereAtoms.push_back(k);
    }
    const build::SphereBlockers b = build::sphereBlockers(params, centers, radii, sphereAtoms, atoms);
    const double g = kind == build::SurfaceKind::Ses ? kRp : 0.0, h = kind == build::SurfaceKind::Vdw ? 0.0 : kRp;
    std::size_t total = 0;
    for (std::uint32_t i = 0; i < centers.size(); ++i) {
      std::vector<std::pair<double, std::uint32_t>> expected;
      for (std::uint32_t k = 0; k < atoms.size(); ++k) {
        const double d = glm::length(glm::dvec3(atoms[k]) - centers[i]);
        if (k != sphereAtoms[i] && d < radii[i] + g + atoms[k].w + h) expected.emplace_back(d - (atoms[k].w + h), k);
      }
      std::sort(expected.begin(), expected.end());
      std::vector<std::uint32_t> want, got(b.list.begin() + b.begin[i], b.list.begin() + b.begin[i + 1]);
      for (const auto& e : expected) want.push_back(e.second);
      ASSERT_EQ(got, want) << "sphere " << i << (kind == build::SurfaceKind::Ses ? " (SES)" : " (vdW)");
      total += want.size();
    }
    EXPECT_GT(total, 2 * centers.size());  // the cloud is dense enough that most spheres have blockers
  }
}

// A sphere whose free part is two polar caps (a ring of 12 balls covers its equator) and saddle
// arcs that bound the northern one alone (the northern half of each ball's circle): a point is
// on the patch iff it lies outside every ball (brute force) and north of the equator. Without
// arcs, both caps are.
TEST(SaddleArcs, KeepOnlyThePartsOfASphereTheyBound) {
  constexpr int kRing = 12;
  const double D = 1.2, alpha = std::numbers::pi / 6.0;  // each ball's cap: 30° about its direction
  const double h = std::cos(alpha), w = std::sqrt(D * D + 1.0 - 2.0 * D * h);
  std::vector<glm::dvec4> atoms{{0.0, 0.0, 0.0, 1.0}};
  std::vector<build::SaddleArc> arcs;
  std::vector<glm::uvec2> arcAtoms;
  for (int k = 0; k < kRing; ++k) {
    const double a = 2.0 * std::numbers::pi * k / kRing;
    const glm::dvec3 n(std::cos(a), std::sin(a), 0.0), e2 = glm::cross(n, glm::dvec3(0, 0, 1));
    atoms.push_back(glm::dvec4(D * n, w));
    // φ from the equator (−e2) over the north pole (z) to the equator again.
    arcs.push_back({h * n, -e2, glm::dvec3(0, 0, 1), std::sin(alpha), std::numbers::pi});
    arcAtoms.push_back({0u, static_cast<std::uint32_t>(k + 1)});
  }
  build::SurfaceParams params;
  params.surface = build::SurfaceKind::Vdw;
  const glm::dvec3 center(0.0);
  const double radius = 1.0;
  const std::uint32_t sphereAtom = 0;
  build::SphereBlockers whole = build::sphereBlockers(params, {&center, 1}, {&radius, 1}, {&sphereAtom, 1}, atoms);
  build::SphereBlockers north = whole;
  build::addSaddleArcs(north, {&center, 1}, {&radius, 1}, {&sphereAtom, 1}, arcs, arcAtoms);
  EXPECT_EQ(north.arcs.size(), arcs.size());  // the southern cap's edge is on no arc: the sphere keeps them
  std::mt19937_64 rng(11);
  int free = 0, kept = 0;
  for (int i = 0; i < 4000; ++i) {
    const glm::dvec3 x = randomUnit(rng);
    bool outside = true;
    for (std::size_t k = 1; k < atoms.size(); ++k) outside = outside && glm::length(x - glm::dvec3(atoms[k])) > atoms[k].w;
    free += outside;
    kept += outside && x.z > 0.0;
    EXPECT_EQ(build::onConvexPatch(whole, 0, center, radius, x, 0.0), outside) << "point " << i;
    EXPECT_EQ(build::onConvexPatch(north, 0, center, radius, x, 0.0), outside && x.z > 0.0) << "point " << i;
  }
  EXPECT_GT(kept, 400);
  EXPECT_GT(free - kept, 400);  // the southern cap, dropped
  // Whole circles bound both caps: the sphere needs no test, and no sphere keeps arcs.
  for (build::SaddleArc& a : arcs) a.extent = 2.0 * std::numbers::pi;
  build::SphereBlockers both = whole;
  build::addSaddleArcs(both, {&center, 1}, {&radius, 1}, {&sphereAtom, 1}, arcs, arcAtoms);
  EXPECT_TRUE(both.arcBegin.empty());
}

TEST(LayerList, MergesHitsWithinTheDistanceAndKeepsTheNearest) {
  std::vector<SceneHit> storage(3);
  LayerList list(storage, 0.1);
  auto hit = [](double t, std::uint32_t patch) { return SceneHit{PatchKind::Convex, patch, PatchHit{t, {0, 0, 1}, 0}}; };
  list.insert(hit(5.0, 0));
  list.insert(hit(1.0, 1));
  list.insert(hit(1.05, 2));  // a seam duplicate of 1.0
  list.insert(hit(0.97, 3));  // nearer: replaces 1.0
  list.insert(hit(3.0, 4));
  list.insert(hit(9.0, 5));   // beyond the 3 nearest
  ASSERT_EQ(list.size(), 3u);
  EXPECT_EQ(list[0].patch, 3u);
  EXPECT_EQ(list[1].patch, 4u);
  EXPECT_EQ(list[2].patch, 0u);
  list.insert(hit(2.0, 6));  // drops the farthest
  EXPECT_EQ(list[2].patch, 4u);
}

// ---------------------------------------------------------------------------------------
// Compositing.

view::RenderOptions smallView(int size) {
  view::RenderOptions o;
  o.camera.width = o.camera.height = size;
  o.camera.eye = {0, 0, 20};
  o.camera.lookAt = {0, 0, 0};
  o.camera.up = {0, 1, 0};
  o.camera.fovY = 20.0;
  o.background = {0.2f, 0.3f, 0.9f};
  return o;
}

// One sphere: front and back crossing, C = α c_front + α(1 − α) c_back + (1 − α)² background.
TEST(Compositing, OneSphereMatchesTheFormula) {
  const glm::dvec3 centers[] = {{0, 0, 0}};
  const double radii[] = {2.0};
  const build::PatchList list = build::atomSpheres(centers, radii, 0.0, build::SurfaceKind::Vdw);
  const PatchScene scene(ScenePatches::fromPatchList(list));
  view::RenderOptions o = smallView(32);
  o.opacity = 0.3;
  const glm::vec3 colors[] = {{0.9f, 0.5f, 0.1f}};
  o.color = view::ColorMode::Element;
  const view::FrameBuffers fb = render(scene, o, colors);
  const view::Camera::Frame frame = o.camera.frame();
  int covered = 0;
  for (int y = 0; y < 32; ++y)
    for (int x = 0; x < 32; ++x) {
      const std::size_t p = static_cast<std::size_t>(y) * 32 + x;
      const Ray ray = frame.ray(x + 0.5, y + 0.5);
      // The two roots of |org + t d|² = r², independently of the intersector.
      const glm::dvec3 d = glm::normalize(ray.dir);
      const double b = glm::dot(ray.org, d), c = glm::dot(ray.org, ray.org) - 4.0, disc = b * b - c;
      if (disc < 1e-6) {  // misses (or grazes: left out)
        if (disc < -1e-6) {
          EXPECT_EQ(fb.layers[p], 0u);
          EXPECT_EQ(fb.rgba[4 * p + 3], 0.0f);
        }
        continue;
      }
      ++covered;
      const glm::dvec3 front = ray.org + (-b - std::sqrt(disc)) * d, back = ray.org + (-b + std::sqrt(disc)) * d;
      const glm::vec3 cf = view::shade(colors[0], front / 2.0, -d, o.lighting);
      const glm::vec3 cb = view::shade(colors[0], back / 2.0, -d, o.lighting);
      const float a = 0.3f;
      const glm::vec3 want = a * cf + a * (1 - a) * cb + (1 - a) * (1 - a) * o.background;
      EXPECT_EQ(fb.layers[p], 2u) << x << "," << y;
      for (int ch = 0; ch < 3; ++ch) EXPECT_NEAR(fb.rgba[4 * p + ch], want[ch], 2e-5) << x << "," << y << " channel " << ch;
      EXPECT_NEAR(fb.rgba[4 * p + 3], 1 - (1 - a) * (1 - a), 1e-6);
      EXPECT_NEAR(fb.depth[p], glm::length(front - ray.org), 1e-5);
    }
  EXPECT_GT(covered, 100);
}

// Opacity 1 is the opaque render, bit for bit; below 1 the buffers are still the nearest
// crossing's, the opaque render's.
TEST(Compositing, OpacityOneIsTheOpaqueRenderAndBuffersAreTheNearestCrossing) {
  const build::Molecule& m = molecule("structures/1crn.pdb");
  const build::PatchList list = build::buildSes(m.centers, m.radii, build::SesParams{kRp});
  const PatchScene scene(ScenePatches::fromPatchList(list));
  view::RenderOptions o;
  o.camera.width = o.camera.height = 64;
  std::vector<double> reach(m.radii);
  for (double& r : reach) r += kRp;
  o.camera = view::frameSpheres(o.camera, m.centers, reach, {0, 0, -1});
  o.shadows = true;
  const std::vector<glm::vec3> colors(m.size(), glm::vec3(0.7f));
  const view::FrameBuffers opaque = render(scene, o, colors);
  o.opacity = 1.0;
  o.maxLayers = 3;
  const view::FrameBuffers one = render(scene, o, colors);
  EXPECT_EQ(one.rgba, opaque.rgba);
  EXPECT_EQ(one.depth, opaque.depth);
  EXPECT_TRUE(one.layers.empty());

  o.opacity = 0.5;
  const view::FrameBuffers half = render(scene, o, colors);
  std::size_t differ = 0, covered = 0;
  for (std::size_t p = 0; p < half.pixels(); ++p) {
    EXPECT_EQ(half.kind[p] != 0, half.layers[p] > 0);
    covered += half.kind[p] != 0;
    // A seam pixel may name the other patch of one point.
    if (half.patchId[p] != opaque.patchId[p] || half.depth[p] != opaque.depth[p]) ++differ;
    if (std::isfinite(opaque.depth[p])) {
      EXPECT_NEAR(half.depth[p], opaque.depth[p], 1e-5) << p;
    }
  }
  EXPECT_GT(covered, 500u);
  EXPECT_LE(differ, covered / 1000);
}

}  // namespace
}  // namespace surftrace::trace

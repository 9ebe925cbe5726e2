// Neighbour grid against an O(n^2) oracle on real and adversarial inputs, its allocation-free
// rebuild, its cell budget and concurrent queries.
#include "build/neighbour_grid.hpp"

#include <algorithm>
#include <atomic>
#include <cmath>
#include <cstdint>
#include <cstdlib>
#include <limits>
#include <map>
#include <new>
#include <random>
#include <span>
#include <string>
#include <string_view>
#include <tuple>
#include <vector>

#include <glm/common.hpp>
#include <glm/vec3.hpp>
#include <gtest/gtest.h>
#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>
#include <zlib.h>

// Every allocation in this test binary is counted, so that a test can show that a rebuild
// allocates nothing at all (not merely that the grid's own vectors kept their buffers).
namespace {
std::atomic<std::size_t> gAllocations{0};
}  // namespace

// Not inlined, neither new nor delete: GCC's -Wmismatched-new-delete would otherwise see a
// malloc() pointer reach operator delete, or an operator new pointer reach free().
[[gnu::noinline]] void* operator new(std::size_t size) {
  gAllocations.fetch_add(1, std::memory_order_relaxed);
  if (void* p = std::malloc(size == 0 ? 1 : size)) return p;
  throw std::bad_alloc();
}
[[gnu::noinline]] void operator delete(void* p) noexcept { std::free(p); }
[[gnu::noinline]] void operator delete(void* p, std::size_t) noexcept { std::free(p); }
// The nothrow pair too (std::stable_sort's temporary buffer uses it): otherwise ASan's own
// nothrow new would hand its pointers to the free() above, an alloc-dealloc mismatch.
[[gnu::noinline]] void* operator new(std::size_t size, const std::nothrow_t&) noexcept {
  gAllocations.fetch_add(1, std::memory_order_relaxed);
  return std::malloc(size == 0 ? 1 : size);
}
[[gnu::noinline]] void operator delete(void* p, const std::nothrow_t&) noexcept { std::free(p); }

namespace surftrace::build {
namespace {

using Index = std::uint32_t;

struct Atoms {
  std::vector<glm::dvec3> centers;
  std::vector<double> radii;
  std::size_t size() const { return centers.size(); }
};

// Bondi radii for the common elements, 1.8 Å for the rest: enough for grid tests, and
// independent of the molecule reader.
double elementRadius(std::string_view element) {
  if (element == "H") return 1.2;
  if (element == "C") return 1.7;
  if (element == "N") return 1.55;
  if (element == "O") return 1.52;
  return 1.8;
}

std::string_view trim(std::string_view s) {
  while (!s.empty() && s.front() == ' ') s.remove_prefix(1);
  while (!s.empty() && (s.back() == ' ' || s.back() == '\n' || s.back() == '\r')) s.remove_suffix(1);
  return s;
}

// ATOM/HETATM records of the first model of a gzipped PDB file: x, y, z from columns
// 31-54, the element from columns 77-78 (else the first letter of the atom name).
Atoms readPdbGz(const std::string& path) {
  Atoms atoms;
  gzFile file = gzopen(path.c_str(), "rb");
  if (file == nullptr) return atoms;
  char buffer[512];
  while (gzgets(file, buffer, sizeof buffer) != nullptr) {
    const std::string_view line(buffer);
    if (line.starts_with("ENDMDL")) break;
    if (!line.starts_with("ATOM  ") && !line.starts_with("HETATM")) continue;
    if (line.size() < 54) continue;
    const auto field = [&](std::size_t begin) {
      return std::strtod(std::string(line.substr(begin, 8)).c_str(), nullptr);
    };
    atoms.centers.emplace_back(field(30), field(38), field(46));
    std::string_view element = line.size() >= 78 ? trim(line.substr(76, 2)) : std::string_view();
    if (element.empty()) element = trim(line.substr(12, 4)).substr(0, 1);
    atoms.radii.push_back(elementRadius(element));
  }
  gzclose(file);
  return atoms;
}

const Atoms& paperMolecule(const std::string& name) {
  static std::map<std::string, Atoms> cache;
  auto it = cache.find(name);
  if (it == cache.end()) {
    const std::string path = std::string(SURFTRACE_TEST_DATA) + "/paper/" + name + ".pdb.gz";
    it = cache.emplace(name, readPdbGz(path)).first;
  }
  return it->second;
}

// The documented predicates, written out independently of the grid.
bool oracleNeighbour(const Atoms& a, std::size_t i, std::size_t j, double rp) {
  const double dx = a.centers[i].x - a.centers[j].x;
  const double dy = a.centers[i].y - a.centers[j].y;
  const double dz = a.centers[i].z - a.centers[j].z;
  const double s = (a.radii[i] + a.radii[j]) + 2.0 * rp;
  return dx * dx + dy * dy + dz * dz < s * s;
}

std::vector<Index> oracleNeighbours(const Atoms& a, std::size_t i, double rp) {
  std::vector<Index> out;
  for (std::size_t j = 0; j < a.size(); ++j) {
    if (j != i && oracleNeighbour(a, i, j, rp)) out.push_back(static_cast<Index>(j));
  }
  return out;
}

// All lists at once, testing each pair once; lists come out in increasing order.
std::vector<std::vector<Index>> oracleAllNeighbours(const Atoms& a, double rp) {
  std::vector<std::vector<Index>> lists(a.size());
  for (std::size_t i = 0; i < a.size(); ++i) {
    for (std::size_t j = i + 1; j < a.size(); ++j) {
      if (oracleNeighbour(a, i, j, rp)) {
        lists[i].push_back(static_cast<Index>(j));
        lists[j].push_back(static_cast<Index>(i));
      }
    }
  }
  return lists;
}

std::vector<Index> oracleAtomsNear(const Atoms& a, const glm::dvec3& p, double reach) {
  std::vector<Index> out;
  for (std::size_t j = 0; j < a.size(); ++j) {
    const double dx = p.x - a.centers[j].x;
    const double dy = p.y - a.centers[j].y;
    const double dz = p.z - a.centers[j].z;
    const double s = a.radii[j] + reach;
    if (s > 0.0 && dx * dx + dy * dy + dz * dz < s * s) out.push_back(static_cast<Index>(j));
  }
  return out;
}

void expectCellBudget(const NeighbourGrid& grid) {
  EXPECT_GE(grid.cellCount(), 1u);
  EXPECT_LE(grid.cellCount(), std::max<std::size_t>(1, 2 * grid.atomCount()));
}

std::vector<Index> neighboursOf(const NeighbourGrid& grid, std::size_t i) {
  std::vector<Index> out;
  grid.neighbours(static_cast<Index>(i), out);
  return out;
}

// Builds the grid and compares every atom's list with the oracle.
void expectMatchesOracle(const Atoms& a, double rp) {
  NeighbourGrid grid;
  grid.build(a.centers, a.radii, rp);
  ASSERT_EQ(grid.atomCount(), a.size());
  expectCellBudget(grid);
  const auto want = oracleAllNeighbours(a, rp);
  for (std::size_t i = 0; i < a.size(); ++i) {
    ASSERT_EQ(neighboursOf(grid, i), want[i]) << "atom " << i << ", rp " << rp;
  }
}

// ---------------------------------------------------------------------------------------
// Real molecules.

class NeighbourGridMolecule : public testing::TestWithParam<std::tuple<const char*, double>> {};

TEST_P(NeighbourGridMolecule, MatchesBruteForce) {
  const auto [name, rp] = GetParam();
  const Atoms& a = paperMolecule(name);
  ASSERT_GT(a.size(), 0u) << "cannot read " << name;
  expectMatchesOracle(a, rp);
}

std::string moleculeTestName(const testing::TestParamInfo<NeighbourGridMolecule::ParamType>& p) {
  return std::string(std::get<0>(p.param)) + "_rp" + std::to_string(static_cast<int>(10 * std::get<1>(p.param)));
}

INSTANTIATE_TEST_SUITE_P(NeighbourGrid, NeighbourGridMolecule,
                         testing::Combine(testing::Values("1vis", "1af6", "1grm"),
                                          testing::Values(0.0, 1.4, 3.0)),
                         moleculeTestName);

// 1AON has 58870 atoms: the full O(n^2) oracle would take 3.5e9 pair tests, so a fixed
// random sample of query atoms is checked against all others.
TEST(NeighbourGrid, MatchesBruteForceOnSampleOf1aon) {
  const Atoms& a = paperMolecule("1aon");
  ASSERT_EQ(a.size(), 58870u);
  std::mt19937_64 rng(1);
  std::uniform_int_distribution<std::size_t> pick(0, a.size() - 1);
  std::vector<std::size_t> sample(2000);
  for (auto& i : sample) i = pick(rng);
  NeighbourGrid grid(a.size());
  for (double rp : {0.0, 1.4, 3.0}) {
    grid.build(a.centers, a.radii, rp);
    expectCellBudget(grid);
    for (std::size_t i : sample) {
      ASSERT_EQ(neighboursOf(grid, i), oracleNeighbours(a, i, rp)) << "atom " << i << ", rp " << rp;
    }
  }
}

TEST(NeighbourGrid, AtomsNearMatchesBruteForce) {
  const Atoms& a = paperMolecule("1vis");
  ASSERT_GT(a.size(), 0u);
  NeighbourGrid grid;
  grid.build(a.centers, a.radii, 1.4);
  glm::dvec3 lo = a.centers[0];
  glm::dvec3 hi = a.centers[0];
  for (const auto& c : a.centers) {
    lo = glm::min(lo, c);
    hi = glm::max(hi, c);
  }
  std::mt19937_64 rng(2);
  std::uniform_real_distribution<double> u(0.0, 1.0);
  // Reaches below -r_max find nothing, -1.5 only the larger atoms, 100 nearly all of them.
  for (double reach : {-5.0, -1.5, 0.0, 1.4, 7.3, 100.0}) {
    for (int trial = 0; trial < 300; ++trial) {
      glm::dvec3 p;
      for (int k = 0; k < 3; ++k) p[k] = lo[k] - 10.0 + (hi[k] - lo[k] + 20.0) * u(rng);
      if (trial % 50 == 0) p = a.centers[static_cast<std::size_t>(trial)];  // exactly on an atom
      std::vector<Index> got;
      grid.atomsNear(p, reach, got);
      ASSERT_EQ(got, oracleAtomsNear(a, p, reach)) << "reach " << reach << ", trial " << trial;
      // The unordered query: the same atoms, each once, in any order.
      std::vector<Index> unordered;
      grid.atomsNearUnordered(p, reach, unordered);
      std::sort(unordered.begin(), unordered.end());
      ASSERT_EQ(unordered, got) << "unordered, reach " << reach << ", trial " << trial;
    }
  }
  // Far outside the bounding box, and far enough that the query box overflows.
  for (const glm::dvec3& p : {glm::dvec3(1e6, 0, 0), glm::dvec3(-1e300, 1e300, 0)}) {
    std::vector<Index> got;
    grid.atomsNear(p, 10.0, got);
    EXPECT_TRUE(got.empty());
    grid.atomsNear(p, 1e308, got);
    EXPECT_EQ(got, oracleAtomsNear(a, p, 1e308));
  }
}

TEST(NeighbourGrid, QueriesAppendToOutput) {
  const Atoms& a = paperMolecule("1vis");
  NeighbourGrid grid;
  grid.build(a.centers, a.radii, 1.4);
  std::vector<Index> out = {99999, 7};
  grid.neighbours(100, out);
  std::vector<Index> want = {99999, 7};
  for (Index j : oracleNeighbours(a, 100, 1.4)) want.push_back(j);
  EXPECT_EQ(out, want);
  grid.atomsNear(a.centers[5], 0.0, out);
  for (Index j : oracleAtomsNear(a, a.centers[5], 0.0)) want.push_back(j);
  EXPECT_EQ(out, want);
}

TEST(NeighbourGrid, ReportsWhatItWasBuiltWith) {
  const Atoms& a = paperMolecule("1vis");
  NeighbourGrid grid(10);
  EXPECT_EQ(grid.capacity(), 10u);
  grid.build(a.centers, a.radii, 1.4);
  EXPECT_EQ(grid.atomCount(), a.size());
  EXPECT_GE(grid.capacity(), a.size());
  EXPECT_EQ(grid.probeRadius(), 1.4);
  EXPECT_EQ(grid.maxRadius(), *std::max_element(a.radii.begin(), a.radii.end()));
  const glm::ivec3 dims = grid.cellDims();
  EXPECT_EQ(grid.cellCount(), static_cast<std::size_t>(dims.x) * static_cast<std::size_t>(dims.y) *
                                  static_cast<std::size_t>(dims.z));
  EXPECT_GT(grid.cellSize(), 0.0);
}

// ---------------------------------------------------------------------------------------
// The boundary: |d| = r_i + r_j + 2 rp exactly is not a neighbour (strict <).

// (0.75, 1, 3) has length 13/4 exactly, and every square and sum here is exact in double.
TEST(NeighbourGrid, PairAtExactlyTheReachIsNotANeighbour) {
  const glm::dvec3 offsets[] = {glm::dvec3(0.0), glm::dvec3(1e4, -2e4, 3e4), glm::dvec3(-0.125, 7.5, 0.0625)};
  for (const glm::dvec3& o : offsets) {
    // 2^-45 relative to the coordinates' magnitude, so the perturbation survives o + v.
    const double eps = std::ldexp(1.0, -45) * (1.0 + std::max({std::abs(o.x), std::abs(o.y), std::abs(o.z)}));
    for (double scale : {1.0, 1.0 - eps, 1.0 + eps}) {
      Atoms a;
      a.centers = {o, o + scale * glm::dvec3(0.75, 1.0, 3.0)};
      a.radii = {1.0, 1.25};  // 1 + 1.25 + 2 * 0.5 = 3.25 = 13/4
      NeighbourGrid grid;
      grid.build(a.centers, a.radii, 0.5);
      const bool inside = scale < 1.0;
      EXPECT_EQ(neighboursOf(grid, 0), inside ? std::vector<Index>{1} : std::vector<Index>{})
          << "scale - 1 = " << scale - 1.0;
      EXPECT_EQ(neighboursOf(grid, 1), inside ? std::vector<Index>{0} : std::vector<Index>{});
      std::vector<Index> near;
      grid.atomsNear(a.centers[0], 2.0, near);  // r_1 + 2 = 3.25 again
      const std::vector<Index> both = {0, 1};
      const std::vector<Index> self = {0};
      EXPECT_EQ(near, inside ? both : self);
    }
  }
}

// A cubic lattice with spacing equal to the reach puts every atom on a cell boundary
// (the cell edge is 2 r_max + 2 rp = the spacing) and every axial pair exactly at reach.
TEST(NeighbourGrid, LatticeAtExactlyTheReachOnCellBoundaries) {
  Atoms a;
  for (int z = 0; z < 12; ++z)
    for (int y = 0; y < 12; ++y)
      for (int x = 0; x < 12; ++x) {
        a.centers.emplace_back(2.0 * x - 8.0, 2.0 * y, 2.0 * z + 4.0);
        a.radii.push_back(0.5);
      }
  NeighbourGrid grid;
  grid.build(a.centers, a.radii, 0.5);
  EXPECT_EQ(grid.cellSize(), 2.0);
  for (std::size_t i = 0; i < a.size(); ++i) EXPECT_TRUE(neighboursOf(grid, i).empty()) << i;

  const double rp = 0.5 + std::ldexp(1.0, -40);  // now only the 6 axial pairs are inside
  grid.build(a.centers, a.radii, rp);
  for (std::size_t i = 0; i < a.size(); ++i) {
    const auto got = neighboursOf(grid, i);
    ASSERT_EQ(got, oracleNeighbours(a, i, rp)) << i;
    const int x = static_cast<int>(i % 12), y = static_cast<int>(i / 12 % 12), z = static_cast<int>(i / 144);
    const auto interior = [](int k) { return k > 0 && k < 11 ? 2u : 1u; };
    EXPECT_EQ(got.size(), interior(x) + interior(y) + interior(z)) << i;
  }
}

// ---------------------------------------------------------------------------------------
// Adversarial inputs.

TEST(NeighbourGrid, NoAtoms) {
  NeighbourGrid grid;
  grid.build({}, {}, 1.4);
  EXPECT_EQ(grid.atomCount(), 0u);
  EXPECT_EQ(grid.cellCount(), 1u);
  std::vector<Index> out;
  grid.atomsNear(glm::dvec3(0.0), 100.0, out);
  EXPECT_TRUE(out.empty());

  const Atoms& a = paperMolecule("1vis");  // and empty again after a real frame
  grid.build(a.centers, a.radii, 1.4);
  grid.build({}, {}, 1.4);
  EXPECT_EQ(grid.atomCount(), 0u);
  EXPECT_EQ(grid.cellCount(), 1u);
  grid.atomsNear(a.centers[0], 100.0, out);
  EXPECT_TRUE(out.empty());
}

TEST(NeighbourGrid, OneAtom) {
  Atoms a;
  a.centers = {glm::dvec3(3.0, -2.0, 1e5)};
  a.radii = {1.7};
  NeighbourGrid grid;
  grid.build(a.centers, a.radii, 1.4);
  expectCellBudget(grid);
  EXPECT_TRUE(neighboursOf(grid, 0).empty());
  std::vector<Index> out;
  grid.atomsNear(glm::dvec3(3.0, -2.0, 1e5 + 3.0), 1.4, out);
  EXPECT_EQ(out, std::vector<Index>{0});
}

TEST(NeighbourGrid, CoincidentAtoms) {
  Atoms a;
  for (int i = 0; i < 500; ++i) {
    a.centers.emplace_back(1.5, -2.25, 8.0);
    a.radii.push_back(1.0 + 0.001 * i);
  }
  for (double rp : {0.0, 1.4}) expectMatchesOracle(a, rp);
  NeighbourGrid grid;
  grid.build(a.centers, a.radii, 0.0);
  EXPECT_EQ(grid.cellCount(), 1u);
  EXPECT_EQ(neighboursOf(grid, 17).size(), 499u);
}

TEST(NeighbourGrid, AllAtomsInOneCell) {
  Atoms a;
  std::mt19937_64 rng(4);
  std::uniform_real_distribution<double> u(-0.25, 0.25);
  for (int i = 0; i < 1500; ++i) {
    a.centers.emplace_back(u(rng), u(rng), u(rng));
    a.radii.push_back(1.5);
  }
  expectMatchesOracle(a, 1.4);
}

// One atom 1e6 Å away stretches the bounding box: the grid must stay within 2n cells, exact,
// and useful (cells no coarser than twice the reach, not 1e6 / cbrt(2n) Å).
TEST(NeighbourGrid, HugeOutlier) {
  Atoms a = paperMolecule("1vis");
  a.centers.emplace_back(1e6, -1e6, 1e6);
  a.radii.push_back(1.8);
  expectMatchesOracle(a, 1.4);
  NeighbourGrid grid;
  grid.build(a.centers, a.radii, 1.4);
  EXPECT_LE(grid.cellSize(), 2.0 * (2.0 * grid.maxRadius() + 2.0 * 1.4));

  a.centers.back() = glm::dvec3(a.centers[0].x, a.centers[0].y + 1e6, a.centers[0].z);
  expectMatchesOracle(a, 0.0);
}

// Outliers in every direction, fewer and more than the grid's trimmed share of n / 1000
// per side and axis.
TEST(NeighbourGrid, ScatteredOutliers) {
  for (int outliers : {5, 60}) {
    Atoms a = paperMolecule("1af6");
    std::mt19937_64 rng(static_cast<std::uint64_t>(outliers));
    std::normal_distribution<double> g(0.0, 1.0);
    std::uniform_real_distribution<double> distance(1e3, 1e6);
    for (int k = 0; k < outliers; ++k) {
      const glm::dvec3 dir(g(rng), g(rng), g(rng));
      a.centers.push_back(a.centers[0] + distance(rng) / std::sqrt(dir.x * dir.x + dir.y * dir.y + dir.z * dir.z) * dir);
      a.radii.push_back(1.5);
    }
    // Two outliers close together, so that they are each other's neighbours far out.
    a.centers.push_back(a.centers.back() + glm::dvec3(1.0, 0.0, 0.0));
    a.radii.push_back(1.5);
    SCOPED_TRACE(outliers);
    expectMatchesOracle(a, 1.4);
  }
}

// Translated far from the origin, where coordinates keep only about six decimals.
TEST(NeighbourGrid, FarFromOrigin) {
  Atoms a = paperMolecule("1vis");
  for (auto& c : a.centers) c += glm::dvec3(3e9, -7e9, 1e10);
  expectMatchesOracle(a, 1.4);
}

// Coordinates whose bounding box overflows double: one cell, still exact.
TEST(NeighbourGrid, ExtentOverflowsDouble) {
  Atoms a;
  a.centers = {{-1.5e308, 0, 0}, {1.5e308, 0, 0}, {0, 0, 0}, {1, 0, 0}, {1.5e308, 0, 2}};
  a.radii = {1.0, 1.0, 1.0, 1.0, 1.0};
  expectMatchesOracle(a, 1.4);
}

TEST(NeighbourGrid, AtomsOnALineAndInAPlane) {
  Atoms line;
  Atoms plane;
  for (int i = 0; i < 2000; ++i) {
    line.centers.emplace_back(0.7 * i, 5.0, -3.0);
    line.radii.push_back(1.0 + 0.5 * (i % 3));
    plane.centers.emplace_back(1.1 * (i % 40), -2.0, 1.3 * (i / 40));
    plane.radii.push_back(1.5);
  }
  expectMatchesOracle(line, 1.4);
  expectMatchesOracle(plane, 1.4);
}

// Several hundred thousand atoms at protein density: within budget, and a sample exact.
TEST(NeighbourGrid, ManyAtoms) {
  Atoms a;
  std::mt19937_64 rng(5);
  std::uniform_real_distribution<double> u(0.0, 180.0);
  std::uniform_real_distribution<double> r(1.2, 1.8);
  for (int i = 0; i < 300000; ++i) {
    a.centers.emplace_back(u(rng), u(rng), u(rng));
    a.radii.push_back(r(rng));
  }
  NeighbourGrid grid(a.size());
  grid.build(a.centers, a.radii, 1.4);
  expectCellBudget(grid);
  for (std::size_t i = 0; i < a.size(); i += 1500) {
    ASSERT_EQ(neighboursOf(grid, i), oracleNeighbours(a, i, 1.4)) << i;
  }
}

// ---------------------------------------------------------------------------------------
// Rebuilds, capacity, threads, contract checks.

// A trajectory frame must not allocate: build() with n <= capacity makes no allocation of
// any kind, whatever the positions, probe radius or atom count.
TEST(NeighbourGrid, RebuildWithinCapacityDoesNotAllocate) {
  const Atoms& a = paperMolecule("1af6");
  ASSERT_GT(a.size(), 0u);
  std::vector<Atoms> frames(3, a);  // jittered, stretched, with an outlier
  std::mt19937_64 rng(6);
  std::normal_distribution<double> jitter(0.0, 0.5);
  for (auto& c : frames[0].centers) c += glm::dvec3(jitter(rng), jitter(rng), jitter(rng));
  for (auto& c : frames[1].centers) c *= glm::dvec3(3.0, 0.2, 1.0);
  frames[2].centers[42] = glm::dvec3(-1e6, 0, 0);
  const std::span<const glm::dvec3> half(a.centers.data(), a.size() / 2);
  const std::span<const double> halfRadii(a.radii.data(), a.size() / 2);

  NeighbourGrid grid(a.size());
  const std::size_t before = gAllocations.load();
  grid.build(a.centers, a.radii, 1.4);
  for (const Atoms& f : frames) grid.build(f.centers, f.radii, 1.4);
  grid.build(a.centers, a.radii, 0.0);
  grid.build(a.centers, a.radii, 3.0);
  grid.build(half, halfRadii, 1.4);
  grid.build({}, {}, 1.4);
  grid.build(frames[0].centers, frames[0].radii, 1.4);
  const std::size_t allocations = gAllocations.load() - before;
  EXPECT_EQ(allocations, 0u);
  EXPECT_EQ(grid.capacity(), a.size());

  // The last frame is still answered exactly.
  for (std::size_t i = 0; i < a.size(); i += 97) {
    ASSERT_EQ(neighboursOf(grid, i), oracleNeighbours(frames[0], i, 1.4)) << i;
  }
}

TEST(NeighbourGrid, GrowsBeyondCapacity) {
  const Atoms& a = paperMolecule("1vis");
  NeighbourGrid grid(100);
  const std::size_t before = gAllocations.load();
  grid.build(a.centers, a.radii, 1.4);
  EXPECT_GT(gAllocations.load(), before);
  EXPECT_GE(grid.capacity(), a.size());
  for (std::size_t i = 0; i < a.size(); i += 31) {
    ASSERT_EQ(neighboursOf(grid, i), oracleNeighbours(a, i, 1.4)) << i;
  }
}

TEST(NeighbourGrid, ConcurrentQueriesMatchSerial) {
  const Atoms& a = paperMolecule("1af6");
  NeighbourGrid grid;
  grid.build(a.centers, a.radii, 1.4);
  std::vector<std::vector<Index>> serial(a.size());
  std::vector<std::vector<Index>> parallel(a.size());
  for (std::size_t i = 0; i < a.size(); ++i) serial[i] = neighboursOf(grid, i);
  tbb::parallel_for(tbb::blocked_range<std::size_t>(0, a.size(), 64),
                    [&](const tbb::blocked_range<std::size_t>& range) {
                      std::vector<Index> scratch;
                      for (std::size_t i = range.begin(); i != range.end(); ++i) {
                        scratch.clear();
                        grid.neighbours(static_cast<Index>(i), scratch);
                        grid.atomsNear(a.centers[i], 0.5, scratch);  // exercised, not checked
                        parallel[i] = neighboursOf(grid, i);
                      }
                    });
  EXPECT_EQ(parallel, serial);
}

TEST(NeighbourGridDeathTest, RejectsBadProbeRadius) {
  GTEST_FLAG_SET(death_test_style, "threadsafe");
  const std::vector<glm::dvec3> c = {glm::dvec3(0.0)};
  const std::vector<double> r = {1.0};
  NeighbourGrid grid;
  EXPECT_DEATH(grid.build(c, r, -0.1), "probeRadius");
  EXPECT_DEATH(grid.build(c, r, std::numeric_limits<double>::quiet_NaN()), "probeRadius");
  EXPECT_DEATH(grid.build(c, r, std::numeric_limits<double>::infinity()), "probeRadius");
}

}  // namespace
}  // namespace surftrace::build

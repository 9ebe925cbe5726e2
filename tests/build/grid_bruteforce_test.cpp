// Neighbour grid against an O(n²) brute force on real molecules and adversarial inputs.
#include <random>

#include <glm/geometric.hpp>
#include <gtest/gtest.h>

#include "build/io/molecule.hpp"
#include "build/neighbour_grid.hpp"

namespace surftrace::build {
namespace {

void expectBruteForce(const std::vector<glm::dvec3>& c, const std::vector<double>& r, double rp, std::size_t stride = 1) {
  NeighbourGrid grid(c.size());
  grid.build(c, r, rp);
  EXPECT_LE(grid.cellCount(), std::max<std::size_t>(1, 2 * c.size()));
  std::vector<std::uint32_t> got, want;
  for (std::size_t i = 0; i < c.size(); i += stride) {
    got.clear();
    want.clear();
    grid.neighbours(static_cast<std::uint32_t>(i), got);
    for (std::size_t j = 0; j < c.size(); ++j)
      if (j != i && glm::distance(c[i], c[j]) < r[i] + r[j] + 2 * rp) want.push_back(static_cast<std::uint32_t>(j));
    ASSERT_EQ(got, want) << "atom " << i;
  }
}

TEST(NeighbourGridBruteForce, RealMolecules) {
  for (const char* file : {"paper/1vis.pdb.gz", "paper/1grm.pdb.gz"}) {
    const Molecule m = readMolecule(std::string(SURFTRACE_TEST_DATA) + "/" + file);
    for (double rp : {0.0, 1.4, 3.0}) expectBruteForce(m.centers, m.radii, rp, 3);
  }
}

TEST(NeighbourGridBruteForce, AdversarialInputs) {
  std::mt19937_64 rng(3);
  std::uniform_real_distribution<double> u(-20, 20);
  std::vector<glm::dvec3> c;
  std::vector<double> r;
  for (int i = 0; i < 300; ++i) c.emplace_back(u(rng), u(rng), u(rng)), r.push_back(1.5);
  auto outlier = c;
  auto rOut = r;
  outlier.emplace_back(1e6, -1e6, 1e6);
  rOut.push_back(1.5);
  expectBruteForce(outlier, rOut, 1.4);                       // a huge outlier atom
  expectBruteForce({{1, 1, 1}}, {1.0}, 1.4);                   // one atom
  expectBruteForce({{1, 1, 1}, {1, 1, 1}, {1, 1, 1}}, {1.0, 2.0, 1.0}, 1.4);  // coincident
  std::vector<glm::dvec3> oneCell(50, glm::dvec3(0.0));
  for (std::size_t i = 0; i < oneCell.size(); ++i) oneCell[i].x = 1e-3 * static_cast<double>(i);
  expectBruteForce(oneCell, std::vector<double>(oneCell.size(), 1.0), 0.0);  // all in one cell
  // Exactly at reach: |d| = r_i + r_j + 2 rp is not a neighbour (strict <).
  NeighbourGrid grid(2);
  const std::vector<glm::dvec3> pair = {{0, 0, 0}, {4.0, 0, 0}};
  const std::vector<double> radii = {1.0, 1.0};
  grid.build(pair, radii, 1.0);
  std::vector<std::uint32_t> out;
  grid.neighbours(0, out);
  EXPECT_TRUE(out.empty());
}

}  // namespace
}  // namespace surftrace::build

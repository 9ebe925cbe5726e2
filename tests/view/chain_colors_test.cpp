// The chain palette: 24 colours far apart in CIELAB, 1AON's 21 chains each its own, and the
// stated rule beyond 24 chains.
#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <map>
#include <set>
#include <string>
#include <vector>

#include <glm/vec3.hpp>

#include "build/io/molecule.hpp"
#include "view/atom_colors.hpp"

namespace surftrace::view {
namespace {

// The palette's numbers read as sRGB colours (as published) to CIELAB under D65, written out
// from the definitions: IEC 61966-2-1's decoding, the sRGB primaries' XYZ matrix, and CIE 1976 L*a*b*.
glm::dvec3 cielab(const glm::vec3& srgb) {
  double linear[3];
  for (int c = 0; c < 3; ++c) {
    const double v = srgb[c];
    linear[c] = v <= 0.04045 ? v / 12.92 : std::pow((v + 0.055) / 1.055, 2.4);
  }
  const double x = (0.4124 * linear[0] + 0.3576 * linear[1] + 0.1805 * linear[2]) / 0.95047;
  const double y = 0.2126 * linear[0] + 0.7152 * linear[1] + 0.0722 * linear[2];
  const double z = (0.0193 * linear[0] + 0.1192 * linear[1] + 0.9505 * linear[2]) / 1.08883;
  const auto f = [](double t) { return t > 216.0 / 24389.0 ? std::cbrt(t) : t * 24389.0 / 27.0 / 116.0 + 16.0 / 116.0; };
  return {116.0 * f(y) - 16.0, 500.0 * (f(x) - f(y)), 200.0 * (f(y) - f(z))};
}

double deltaE(const glm::vec3& a, const glm::vec3& b) {
  const glm::dvec3 d = cielab(a) - cielab(b);
  return std::sqrt(d.x * d.x + d.y * d.y + d.z * d.z);
}

// Colours this far apart (CIE 1976 ΔE) are told apart at a glance; tab10 alone reaches 24, the
// 24 colours 23.1.
constexpr double kMinDistance = 23.0;

// The sRGB colour an image shows for a linear colour the renderer was given (the colour of a
// pixel lit at full intensity): IEC 61966-2-1's encoding, written out.
glm::vec3 displayed(const glm::vec3& linear) {
  glm::vec3 shown;
  for (int c = 0; c < 3; ++c) {
    const double v = linear[c];
    shown[c] = static_cast<float>(v <= 0.0031308 ? 12.92 * v : 1.055 * std::pow(v, 1.0 / 2.4) - 0.055);
  }
  return shown;
}

double smallestDistance(const std::vector<glm::vec3>& colours, std::size_t& a, std::size_t& b) {
  double least = INFINITY;
  for (std::size_t i = 0; i < colours.size(); ++i)
    for (std::size_t j = i + 1; j < colours.size(); ++j)
      if (const double d = deltaE(colours[i], colours[j]); d < least) least = d, a = i, b = j;
  return least;
}

TEST(ChainColors, PaletteHasTwentyFourColoursFarApart) {
  std::vector<glm::vec3> palette;
  for (std::size_t k = 0; k < kChainPaletteSize; ++k) palette.push_back(chainColor(k));
  ASSERT_GE(palette.size(), 24u);
  std::size_t a = 0, b = 0;
  const double least = smallestDistance(palette, a, b);
  std::printf("smallest CIELAB distance between palette colours: %.2f (%zu, %zu)\n", least, a, b);
  EXPECT_GT(least, kMinDistance) << "chains " << a << " and " << b;
  // Every colour is one a shaded surface can show: nothing near black.
  for (std::size_t k = 0; k < palette.size(); ++k) EXPECT_GE(cielab(palette[k]).x, 35.0) << "colour " << k;
}

// The distances between the colours as an image shows them: atomColors gives the linear colours
// the renderer shades, which an 8-bit image encodes back to sRGB.
TEST(ChainColors, EveryChainOf1aonHasItsOwnColour) {
  const build::Molecule m = build::readMolecule(SURFTRACE_TEST_DATA "/paper/1aon.pdb.gz");
  std::vector<glm::vec3> colours = atomColors(m, ColorMode::Chain, glm::vec3(0.8f));
  for (glm::vec3& c : colours) c = displayed(c);
  std::map<std::string, glm::vec3> byChain;
  for (std::size_t i = 0; i < m.size(); ++i) {
    const auto [it, added] = byChain.emplace(m.atoms[i].chain, colours[i]);
    ASSERT_TRUE(added || it->second == colours[i]) << "chain " << m.atoms[i].chain << " has two colours (atom " << i << ")";
  }
  ASSERT_EQ(byChain.size(), 21u);
  std::vector<std::string> names;
  std::vector<glm::vec3> distinct;
  for (const auto& [chain, colour] : byChain) names.push_back(chain), distinct.push_back(colour);
  std::size_t a = 0, b = 0;
  const double least = smallestDistance(distinct, a, b);
  std::printf("1AON: smallest CIELAB distance between two chains' colours as displayed: %.2f (%s, %s)\n", least, names[a].c_str(),
              names[b].c_str());
  EXPECT_GT(least, kMinDistance) << "chains " << names[a] << " and " << names[b];
}

// Beyond 24 chains (README, `render`): the 24 colours again, darkened to 60 %, then lightened
// 45 % of the way to white, then the cycle repeats.
TEST(ChainColors, BeyondTwentyFourTheColoursComeBackDarkerThenLighter) {
  for (std::size_t k = 0; k < kChainPaletteSize; ++k) {
    const glm::vec3 c = chainColor(k), darker = chainColor(k + 24), lighter = chainColor(k + 48);
    for (int i = 0; i < 3; ++i) {
      EXPECT_FLOAT_EQ(darker[i], 0.6f * c[i]) << "chain " << k + 24;
      EXPECT_FLOAT_EQ(lighter[i], c[i] + 0.45f * (1.0f - c[i])) << "chain " << k + 48;
    }
    EXPECT_LT(cielab(darker).x, cielab(c).x - 5.0) << k;
    EXPECT_EQ(chainColor(k + 72), c) << "the cycle repeats after 72";
  }
}

}  // namespace
}  // namespace surftrace::view

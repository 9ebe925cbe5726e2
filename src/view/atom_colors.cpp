// One colour per atom for the element, chain, B-factor and uniform colour schemes.
#include "view/atom_colors.hpp"

#include <cmath>
#include <limits>
#include <map>
#include <unordered_map>

#include <glm/common.hpp>

namespace surftrace::view {

namespace {

glm::vec3 elementColor(const std::string& element) {
  // Jmol's CPK colours for the elements of biomolecules; anything else is pink.
  static const std::unordered_map<std::string, glm::vec3> table = {
      {"H", {1.00f, 1.00f, 1.00f}}, {"C", {0.56f, 0.56f, 0.56f}}, {"N", {0.19f, 0.31f, 0.97f}},
      {"O", {1.00f, 0.05f, 0.05f}}, {"S", {1.00f, 1.00f, 0.19f}}, {"P", {1.00f, 0.50f, 0.00f}},
      {"F", {0.56f, 0.88f, 0.31f}}, {"Cl", {0.12f, 0.94f, 0.12f}}, {"Br", {0.65f, 0.16f, 0.16f}},
      {"I", {0.58f, 0.00f, 0.58f}}, {"Fe", {0.88f, 0.40f, 0.20f}}, {"Zn", {0.49f, 0.50f, 0.69f}},
      {"Mg", {0.54f, 1.00f, 0.00f}}, {"Ca", {0.24f, 1.00f, 0.00f}}, {"Na", {0.67f, 0.36f, 0.95f}},
      {"K", {0.56f, 0.25f, 0.83f}}, {"Mn", {0.61f, 0.48f, 0.78f}}, {"Cu", {0.78f, 0.50f, 0.20f}},
      {"Se", {1.00f, 0.63f, 0.00f}}};
  const auto it = table.find(element);
  return it == table.end() ? glm::vec3(1.0f, 0.08f, 0.58f) : it->second;
}

constexpr glm::vec3 kChainPalette[] = {
    {0.12f, 0.47f, 0.71f}, {1.00f, 0.50f, 0.05f}, {0.17f, 0.63f, 0.17f}, {0.84f, 0.15f, 0.16f},
    {0.58f, 0.40f, 0.74f}, {0.55f, 0.34f, 0.29f}, {0.89f, 0.47f, 0.76f}, {0.50f, 0.50f, 0.50f},
    {0.74f, 0.74f, 0.13f}, {0.09f, 0.75f, 0.81f}};

}  // namespace

std::vector<glm::vec3> atomColors(const build::Molecule& m, ColorMode mode, const glm::vec3& uniform) {
  std::vector<glm::vec3> colors(m.size(), uniform);
  switch (mode) {
    case ColorMode::Patch:
    case ColorMode::Uniform: break;
    case ColorMode::Element:
      for (std::size_t i = 0; i < m.size(); ++i) colors[i] = elementColor(m.atoms[i].element);
      break;
    case ColorMode::Chain: {
      std::map<std::string, std::size_t> order;
      for (std::size_t i = 0; i < m.size(); ++i) {
        const auto it = order.emplace(m.atoms[i].chain, order.size()).first;
        colors[i] = kChainPalette[it->second % std::size(kChainPalette)];
      }
      break;
    }
    case ColorMode::BFactor: {
      double lo = std::numeric_limits<double>::infinity(), hi = -lo;
      for (const auto& a : m.atoms)
        if (std::isfinite(a.bFactor)) lo = std::min(lo, a.bFactor), hi = std::max(hi, a.bFactor);
      for (std::size_t i = 0; i < m.size(); ++i) {
        const double b = m.atoms[i].bFactor;
        if (!std::isfinite(b)) {
          colors[i] = {0.5f, 0.5f, 0.5f};
          continue;
        }
        const float x = hi > lo ? static_cast<float>((b - lo) / (hi - lo)) : 0.5f;
        const glm::vec3 blue(0.23f, 0.30f, 0.75f), white(0.87f, 0.87f, 0.87f), red(0.71f, 0.02f, 0.15f);
        colors[i] = x < 0.5f ? glm::mix(blue, white, 2.0f * x) : glm::mix(white, red, 2.0f * x - 1.0f);
      }
      break;
    }
  }
  return colors;
}

}  // namespace surftrace::view

// Colour schemes and the Blinn–Phong headlight model shared by the Embree and GL paths.
#include "view/shading.hpp"

#include <algorithm>
#include <cmath>
#include <stdexcept>

#include <glm/geometric.hpp>

namespace surftrace::view {

ColorMode parseColorMode(const std::string& name) {
  if (name == "patch") return ColorMode::Patch;
  if (name == "element") return ColorMode::Element;
  if (name == "chain") return ColorMode::Chain;
  if (name == "bfactor") return ColorMode::BFactor;
  if (name == "uniform") return ColorMode::Uniform;
  if (name == "residue") return ColorMode::Residue;
  if (name == "hydrophobicity") return ColorMode::Hydrophobicity;
  if (name == "rainbow") return ColorMode::Rainbow;
  if (name == "value") return ColorMode::Value;
  throw std::invalid_argument("unknown colour scheme '" + name +
                              "': use patch, element, chain, residue, hydrophobicity, rainbow, bfactor, value or uniform");
}

const char* colorModeName(ColorMode mode) {
  switch (mode) {
    case ColorMode::Patch: return "patch";
    case ColorMode::Element: return "element";
    case ColorMode::Chain: return "chain";
    case ColorMode::BFactor: return "bfactor";
    case ColorMode::Uniform: return "uniform";
    case ColorMode::Residue: return "residue";
    case ColorMode::Hydrophobicity: return "hydrophobicity";
    case ColorMode::Rainbow: return "rainbow";
    case ColorMode::Value: return "value";
  }
  return "?";
}

glm::vec3 shade(const glm::vec3& base, const glm::dvec3& normal, const glm::dvec3& towardsEye, const Lighting& light) {
  const float nl = static_cast<float>(std::max(0.0, glm::dot(normal, towardsEye)));
  // Integer exponents (the default 32) by repeated squaring: powf was 1.5% of a frame.
  float highlight;
  if (light.shininess == std::floor(light.shininess) && light.shininess >= 0.0f && light.shininess <= 1024.0f) {
    highlight = 1.0f;
    float base2 = nl;
    for (unsigned e = static_cast<unsigned>(light.shininess); e != 0; e >>= 1, base2 *= base2)
      if (e & 1u) highlight *= base2;
  } else {
    highlight = std::pow(nl, light.shininess);
  }
  const float spec = light.specular * highlight;
  return glm::min(base * (light.ambient + light.diffuse * nl) + glm::vec3(spec), glm::vec3(1.0f));
}

}  // namespace surftrace::view

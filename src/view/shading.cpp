// Colour schemes and the lighting models shared by the Embree and GL paths.
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

LightingPreset parseLightingPreset(const std::string& name) {
  if (name == "headlight") return LightingPreset::Headlight;
  if (name == "simple") return LightingPreset::Simple;
  if (name == "soft") return LightingPreset::Soft;
  if (name == "full") return LightingPreset::Full;
  throw std::invalid_argument("unknown lighting '" + name + "': use headlight, simple, soft or full");
}

const char* lightingPresetName(LightingPreset preset) {
  switch (preset) {
    case LightingPreset::Headlight: return "headlight";
    case LightingPreset::Simple: return "simple";
    case LightingPreset::Soft: return "soft";
    case LightingPreset::Full: return "full";
  }
  return "?";
}

Lighting lightingFor(LightingPreset preset) {
  Lighting l;
  if (preset == LightingPreset::Headlight) return l;
  // A surface facing the eye gets 0.3 + 0.65·cos 45° + 0.25·cos 46° = 0.93 of its colour,
  // near the headlight's 0.25 + 0.75 = 1, so colours read the same.
  l.preset = preset;
  l.ambient = 0.3f;
  l.diffuse = 0.65f;
  l.fill = 0.25f;
  l.specular = 0.2f;
  l.shininess = 32.0f;
  if (preset == LightingPreset::Simple) return l;
  // An 8° disc: penumbrae about a seventh of the occluder's distance wide.
  l.keyRadius = 8.0 * 3.14159265358979323846 / 180.0;
  // Few rays, then the edge-aware filter (Embree): noise σ of the ambient visibility and of the
  // key light's in a penumbra on a flat floor (tests/trace/lighting_test.cpp) Soft 0.0058 and
  // 0.014, Full 0.0020 and 0.0088 (32 and 128 rays each unfiltered: 0.022 and 0.026, 0.0074
  // and 0.012), nearer a 1024-ray oracle on average.
  l.shadowRays = preset == LightingPreset::Soft ? 4 : 32;
  l.occlusionRays = preset == LightingPreset::Soft ? 8 : 64;
  l.filterPasses = 4;
  return l;
}

LightDirections lightDirections(const glm::dvec3& right, const glm::dvec3& up, const glm::dvec3& forward) {
  auto world = [&](const glm::vec3& c) {
    return glm::normalize(static_cast<double>(c.x) * right + static_cast<double>(c.y) * up - static_cast<double>(c.z) * forward);
  };
  return {world(kKeyLightCamera), world(kFillLightCamera)};
}

namespace {

// x^shininess; integer exponents (the default 32) by repeated squaring: powf was 1.5% of a frame.
float highlight(float x, float shininess) {
  if (shininess == std::floor(shininess) && shininess >= 0.0f && shininess <= 1024.0f) {
    float h = 1.0f;
    float base2 = x;
    for (unsigned e = static_cast<unsigned>(shininess); e != 0; e >>= 1, base2 *= base2)
      if (e & 1u) h *= base2;
    return h;
  }
  return std::pow(x, shininess);
}

}  // namespace

glm::vec3 shade(const glm::vec3& base, const glm::dvec3& normal, const glm::dvec3& towardsEye, const Lighting& light) {
  const float nl = static_cast<float>(std::max(0.0, glm::dot(normal, towardsEye)));
  const float spec = light.specular * highlight(nl, light.shininess);
  return glm::min(base * (light.ambient + light.diffuse * nl) + glm::vec3(spec), glm::vec3(1.0f));
}

glm::vec3 shade(const glm::vec3& base, const glm::dvec3& normal, const glm::dvec3& towardsEye, const Lighting& light,
                const LightDirections& lights, float keyVisibility, float ambientVisibility) {
  if (!light.keyFill()) return shade(base, normal, towardsEye, light);
  const double nk = glm::dot(normal, lights.key);
  const float key = static_cast<float>(std::max(0.0, nk));
  const float fill = static_cast<float>(std::max(0.0, glm::dot(normal, lights.fill)));
  float spec = 0.0f;
  if (nk > 0.0) {
    const float nh = static_cast<float>(std::max(0.0, glm::dot(normal, glm::normalize(lights.key + towardsEye))));
    spec = light.specular * keyVisibility * highlight(nh, light.shininess);
  }
  const float diffuse = light.ambient * ambientVisibility + light.diffuse * key * keyVisibility +
                        light.fill * fill * ambientVisibility;
  return glm::min(base * diffuse + glm::vec3(spec), glm::vec3(1.0f));
}

namespace {
constexpr double kPi = 3.14159265358979323846;
constexpr double kGoldenFraction = 0.6180339887498948482;
}  // namespace

glm::dvec2 latticePoint(int i, int n, const glm::dvec2& rotation) {
  const double u = (i + 0.5) / n + rotation.x, v = i * kGoldenFraction + rotation.y;
  return {u - std::floor(u), v - std::floor(v)};
}

void tangentFrame(const glm::dvec3& n, glm::dvec3& t, glm::dvec3& b) {
  t = std::abs(n.x) < 0.9 ? glm::normalize(glm::cross(n, glm::dvec3(1, 0, 0)))
                          : glm::normalize(glm::cross(n, glm::dvec3(0, 1, 0)));
  b = glm::cross(n, t);
}

glm::dvec3 keyDiscDirection(const glm::dvec3& key, const glm::dvec3& t, const glm::dvec3& b, double radius,
                            const glm::dvec2& q) {
  const double r = std::tan(radius) * std::sqrt(q.x), phi = 2.0 * kPi * q.y;
  return glm::normalize(key + r * std::cos(phi) * t + r * std::sin(phi) * b);
}

glm::dvec3 fibonacciSphere(int i, int n) {
  const double z = 1.0 - (2.0 * i + 1.0) / n, rho = std::sqrt(std::max(0.0, 1.0 - z * z));
  const double phi = 2.0 * kPi * (i * kGoldenFraction - std::floor(i * kGoldenFraction));
  return {rho * std::cos(phi), rho * std::sin(phi), z};
}

}  // namespace surftrace::view

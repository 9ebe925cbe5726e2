// Colour schemes and the Blinn–Phong headlight model shared by the Embree and GL paths.
#pragma once

#include <string>

#include <glm/vec3.hpp>

namespace surftrace::view {

enum class ColorMode { Patch, Element, Chain, BFactor, Uniform, Residue, Hydrophobicity, Rainbow, Value };
ColorMode parseColorMode(const std::string& name);  // throws std::invalid_argument
const char* colorModeName(ColorMode mode);

// Blinn–Phong with a white headlight at the eye (so the half vector is the light
// direction): c = base·(ambient + diffuse·max(0, n·l)) + specular·max(0, n·l)^shininess.
// The GL fragment shaders use these same numbers.
struct Lighting {
  float ambient = 0.25f;
  float diffuse = 0.75f;
  float specular = 0.25f;
  float shininess = 32.0f;
};
glm::vec3 shade(const glm::vec3& base, const glm::dvec3& normal, const glm::dvec3& towardsEye, const Lighting& light);

}  // namespace surftrace::view

// Colour schemes and the Blinn–Phong headlight model shared by the Embree and GL paths.
#pragma once

#include <span>
#include <string>
#include <vector>

#include <glm/vec3.hpp>

#include "build/io/molecule.hpp"

namespace surftrace::trace {

enum class ColorMode { Patch, Element, Chain, BFactor, Uniform };
ColorMode parseColorMode(const std::string& name);  // throws std::invalid_argument
const char* colorModeName(ColorMode mode);

// Lindow et al. 2010 colour the patch kinds: convex green, toroidal yellow, concave red.
inline constexpr glm::vec3 kConvexColor{0.30f, 0.75f, 0.30f};
inline constexpr glm::vec3 kToroidalColor{0.90f, 0.80f, 0.25f};
inline constexpr glm::vec3 kConcaveColor{0.85f, 0.25f, 0.20f};

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

// One colour per atom for the element, chain, B-factor and uniform schemes (CPK-style
// element colours as in Jmol; chains from a fixed palette in order of appearance;
// B-factors on a blue–white–red ramp between their minimum and maximum).
std::vector<glm::vec3> atomColors(const build::Molecule& molecule, ColorMode mode, const glm::vec3& uniform);

}  // namespace surftrace::trace

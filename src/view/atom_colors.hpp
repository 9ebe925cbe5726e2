// One colour per atom for the element, chain, B-factor and uniform colour schemes.
#pragma once

#include <vector>

#include <glm/vec3.hpp>

#include "build/io/molecule.hpp"
#include "view/shading.hpp"

namespace surftrace::view {

// CPK-style element colours as in Jmol; chains from a fixed palette in order of appearance;
// B-factors on a blue–white–red ramp between their minimum and maximum. Every atom gets
// `uniform` under the uniform and patch schemes.
std::vector<glm::vec3> atomColors(const build::Molecule& molecule, ColorMode mode, const glm::vec3& uniform);

}  // namespace surftrace::view

// The GLSL of the ray-casting programs (Lindow et al. 2010, Sect. 5): files in src/gl/shaders, embedded at build time.
//
// Every fragment shader rebuilds the exact pixel-centre ray of view::Camera::ray and
// intersects one patch with the same formulas and the same patch tests as the double
// precision intersectors in src/trace (sphere_patch.cpp, torus_patch.cpp,
// concave_patch.cpp), in float on origin-shifted coordinates. Records: shaders/gpu_shared.h.
#include "gl/shaders.hpp"

#include <stdexcept>

namespace surftrace::gl {
namespace {

std::string stage(const std::string& name) {
  for (std::size_t i = 0; i < kShaderFileCount; ++i)
    if (name == kShaderFiles[i].name) return kShaderFiles[i].text;
  throw std::logic_error("GL shader stage '" + name + "' was not embedded: add its kind to src/gl/CMakeLists.txt");
}

}  // namespace

ProgramSources programSources(const std::string& shader) {
  return ProgramSources{stage("vertex.vert"), stage(shader + ".geom"), stage(shader + ".frag")};
}

ProgramSources imagePassSources(const std::string& name) {
  return ProgramSources{stage(name + ".vert"), "", stage(name + ".frag")};
}

}  // namespace surftrace::gl

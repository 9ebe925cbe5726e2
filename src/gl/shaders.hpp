// The GLSL of the ray-casting programs (Lindow et al. 2010, Sect. 5): files in src/gl/shaders, embedded at build time.
#pragma once

#include <cstddef>
#include <string>

namespace surftrace::gl {

// An assembled program stage: "vertex.vert", "<kind>.geom", "<kind>.frag" (src/gl/CMakeLists.txt).
struct ShaderFile {
  const char* name;
  const char* text;
};
extern const ShaderFile kShaderFiles[];  // gl/shader_sources.cpp, generated
extern const std::size_t kShaderFileCount;

struct ProgramSources {
  std::string vertex, geometry, fragment;
};

// The three stages of a kind's program (`shader` of its row in gl/gpu_kinds.hpp): a
// trivial vertex shader (one point per patch, gl_PrimitiveIDIn indexes the patch records),
// a geometry shader emitting the rasterisation primitive bounding the patch's projection,
// and a fragment shader that builds the pixel-centre ray of view::Camera and intersects the
// patch exactly. Throws std::logic_error if the library was built without that shader.
ProgramSources programSources(const std::string& shader);
// A full-screen image pass ("peel"): "<name>.vert" and "<name>.frag", no geometry stage.
ProgramSources imagePassSources(const std::string& name);

}  // namespace surftrace::gl

// GLSL sources of the ray-casting programs (Lindow et al. 2010, Sect. 5), one per patch kind.
#pragma once

#include <string>

namespace surftrace::gl {

enum class ProgramKind { Sphere, Torus, Concave };

struct ProgramSources {
  std::string vertex, geometry, fragment;
};

// The three stages of a kind's program: a trivial vertex shader (one point per patch,
// gl_PrimitiveIDIn indexes the patch records), a geometry shader emitting the
// rasterisation primitive bounding the patch's projection, and a fragment shader that
// builds the pixel-centre ray of view::Camera and intersects the patch exactly.
ProgramSources programSources(ProgramKind kind);

}  // namespace surftrace::gl

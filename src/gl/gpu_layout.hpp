// The patch list as the GPU sees it: the compact std430/std140 records of Lindow et al. 2010, Sect. 5.3.
#pragma once

#include <cstddef>
#include <cstdint>
#include <vector>

#include <glm/vec2.hpp>
#include <glm/vec3.hpp>
#include <glm/vec4.hpp>

#include "build/patch_list.hpp"

namespace surftrace::gl {

// Shader storage bindings (std430) and the one uniform block (std140). The GLSL side is in
// shaders.cpp; tests/gl/gl_layout_test.cpp checks these offsets against what GL reports.
enum Binding : unsigned {
  kSphereBinding = 0,       // vec4 spheres[]: centre, radius
  kSphereAtomBinding = 1,   // uint sphereAtoms[]
  kTorusBinding = 2,        // GpuTorus tori[]
  kTorusAtomBinding = 3,    // uvec2 torusAtoms[]: atom i, atom j
  kConcaveBinding = 4,      // GpuConcave concaves[]
  kConcaveAtomBinding = 5,  // uvec4 concaveAtoms[]: atoms i, j, k, unused
  kAtomColorBinding = 6,    // vec4 atomColors[]
  kFragmentCountBinding = 7,  // uint fragmentCounts[2 n]: fragments shaded, hits (statistics only)
  kFrameBinding = 0,        // uniform block Frame
  kClipPlaneUnit = 0,       // samplerBuffer clipPlanes (RGBA32F: n, w)
};

// A sphere is one vec4 (centre, radius).
using GpuSphere = glm::vec4;

// A saddle in four vectors: the torus, its frame and the patch limits (ORACLES A.3).
struct GpuTorus {
  glm::vec4 centerR;    // centre c, big radius R
  glm::vec4 axisRp;     // unit axis n (atom i → j), tube (probe) radius rp
  glm::vec4 e1Phi;      // unit e1 ⊥ n (φ = 0), φ extent in (0, 2π]
  glm::vec4 theta;      // θi, θj, unused, unused
};

// A concave triangle in four vectors: the probe and its three contact directions (ORACLES
// A.4). Its clipping planes are texels [clipBegin, clipBegin + clipCount) of the clip-plane
// texture buffer; the indices are stored as floats, exact below 2²⁴ (checked at upload).
struct GpuConcave {
  glm::vec4 probeRp;     // probe centre p, probe radius rp
  glm::vec4 dirIBegin;   // unit contact direction u_i, clipBegin
  glm::vec4 dirJCount;   // u_j, clipCount
  glm::vec4 dirK;        // u_k, unused
};

static_assert(sizeof(GpuSphere) == 16);
static_assert(sizeof(GpuTorus) == 64 && offsetof(GpuTorus, axisRp) == 16 && offsetof(GpuTorus, e1Phi) == 32 &&
              offsetof(GpuTorus, theta) == 48);
static_assert(sizeof(GpuConcave) == 64 && offsetof(GpuConcave, dirIBegin) == 16 &&
              offsetof(GpuConcave, dirJCount) == 32 && offsetof(GpuConcave, dirK) == 48);

// Everything that changes per frame but not per patch: camera, shading, depth mapping (std140).
struct GpuFrame {
  glm::vec4 eyeProjection;   // eye (origin-shifted), projection (0 perspective, 1 orthographic)
  glm::vec4 forwardTan;      // unit forward, tan(fovY/2)
  glm::vec4 rightAspect;     // unit right, W/H
  glm::vec4 upHalfHeight;    // unit true up, orthoHeight/2
  glm::vec4 viewport;        // W, H, near plane of the rasterised boxes (Å), 1/(depth range in Å)
  glm::vec4 lighting;        // ambient, diffuse, specular, shininess
  glm::vec4 background;      // rgb, unused
  glm::vec4 kindColor[3];    // convex, toroidal, concave
  glm::uvec4 idBase;         // global id of the first sphere (0), torus, concave; colour mode (0 = patch)
  glm::uvec4 counts;         // atom colours, torus method (0 quartic, 1 sphere tracing), max steps, plain march (1)
  glm::vec4 traceParams;     // sphere-tracing stop distance (Å), primitive (0 box, 1 cylinder), count fragments (1), unused
};
static_assert(sizeof(GpuFrame) == 13 * 16);
static_assert(offsetof(GpuFrame, kindColor) == 112 && offsetof(GpuFrame, idBase) == 160 &&
              offsetof(GpuFrame, counts) == 176 && offsetof(GpuFrame, traceParams) == 192);

// The upload of one patch list, every coordinate shifted by −origin in double before it is
// rounded to float (ORACLES D.4: float32 keeps 7 digits, so molecules far from the
// coordinate origin would otherwise lose their surface detail).
struct GpuPatches {
  glm::dvec3 origin{0.0};
  std::vector<GpuSphere> spheres;
  std::vector<std::uint32_t> sphereAtoms;
  std::vector<GpuTorus> tori;
  std::vector<glm::uvec2> torusAtoms;
  std::vector<GpuConcave> concave;
  std::vector<glm::uvec4> concaveAtoms;
  std::vector<glm::vec4> clipPlanes;  // n, w + n·origin
  // Bounding sphere of every patch (double, unshifted): sets the depth range.
  glm::dvec3 boundsCenter{0.0};
  double boundsRadius = 0.0;
};

// Throws std::invalid_argument for an MSS list (not drawn by the GL path yet) or for more
// clipping planes than a float index holds exactly.
GpuPatches packPatches(const build::PatchList& patches, const glm::dvec3& origin);

}  // namespace surftrace::gl

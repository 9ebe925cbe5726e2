// Spheres: a screen-aligned rectangle around the exact projection (Lindow et al. 2010, Sect. 5.2); the ray–sphere hit of sphere_patch.cpp.
//
// One file per patch kind: its records and atoms (bound to kRecordBinding and kAtomBinding
// for its draw), its geometry stage (SURFTRACE_GEOMETRY_STAGE) and its fragment stage
// (SURFTRACE_FRAGMENT_STAGE). gl/gpu_kinds.hpp holds the kind's row.
layout(std430, binding = kRecordBinding) readonly buffer Spheres { vec4 spheres[]; };  // centre, radius
layout(std430, binding = kAtomBinding) readonly buffer SphereAtoms { uint sphereAtoms[]; };

#ifdef SURFTRACE_GEOMETRY_STAGE
layout(triangle_strip, max_vertices = 4) out;

void main() {
  uint index = uint(gl_PrimitiveIDIn);
  vec4 s = spheres[index];
  emitSphereRect(s.xyz, s.w, index);
}
#endif

#ifdef SURFTRACE_FRAGMENT_STAGE
void main() {
  countFragment(globalId(kConvexKind, patchIndex), 0u);
  vec3 org, dir;
  cameraRay(org, dir);
  float t;
  vec3 n;
  if (!sphereHit(spheres[patchIndex], org, dir, t, n)) discard;
  writeHit(dir, t, n, kConvexKind, globalId(kConvexKind, patchIndex), sphereAtoms[patchIndex]);
}
#endif

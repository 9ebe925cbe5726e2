// The ball-and-stick model's balls: as sphere.glsl (the same rectangle and ray–sphere hit), kind kBallKind.
//
// One file per patch kind: its records and atoms (bound to kRecordBinding and kAtomBinding
// for its draw), its geometry stage (SURFTRACE_GEOMETRY_STAGE) and its fragment stage
// (SURFTRACE_FRAGMENT_STAGE). gl/gpu_kinds.hpp holds the kind's row.
layout(std430, binding = kRecordBinding) readonly buffer Balls { vec4 balls[]; };  // centre, radius (the model's balls)
layout(std430, binding = kAtomBinding) readonly buffer BallAtoms { uint ballAtoms[]; };

#ifdef SURFTRACE_GEOMETRY_STAGE
layout(triangle_strip, max_vertices = 4) out;

void main() {
  uint index = uint(gl_PrimitiveIDIn);
  vec4 s = balls[index];
  emitSphereRect(s.xyz, s.w, index);
}
#endif

#ifdef SURFTRACE_FRAGMENT_STAGE
void main() {
  countFragment(globalId(kBallKind, patchIndex), 0u);
  vec3 org, dir;
  cameraRay(org, dir);
  float t;
  vec3 n;
  if (!sphereHit(balls[patchIndex], org, dir, t, n)) discard;
  writeHit(dir, t, n, kBallKind, globalId(kBallKind, patchIndex), ballAtoms[patchIndex]);
}
#endif

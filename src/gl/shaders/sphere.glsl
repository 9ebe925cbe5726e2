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
  vec4 s = spheres[patchIndex];
  vec3 org, dir;
  cameraRay(org, dir);
  // ORACLES B.5 (sphere_patch.cpp): f is the ray's closest point to the centre, so the
  // discriminant r² − |f|² keeps the small term that b² − (|oc|² − r²) would cancel.
  vec3 oc = org - s.xyz;
  float b = dot(oc, dir);
  vec3 f = oc - b * dir;
  float rr = s.w * s.w;
  float disc = rr - dot(f, f);
  if (!(disc >= 0.0)) discard;
  float root = sqrt(disc);
  float q = -b - (b >= 0.0 ? root : -root);
  float r2 = q != 0.0 ? (dot(oc, oc) - rr) / q : 0.0;
  float tNear = min(q, r2), tFar = max(q, r2);
  float t, side;
  if (tNear > 0.0) {
    t = tNear;
    side = -1.0;
  } else if (tFar > 0.0) {
    t = tFar;
    side = 1.0;
  } else {
    discard;
  }
  vec3 n = normalize(f + (side * root) * dir);
  writeHit(dir, t, n, kConvexKind, globalId(kConvexKind, patchIndex), sphereAtoms[patchIndex]);
}
#endif

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
layout(std430, binding = kBlockerBinding) readonly buffer Blockers { vec4 blockers[]; };
layout(std430, binding = kBlockerListBinding) readonly buffer BlockerList { uint blockerList[]; };

// build::onConvexPatch in float: x on sphere i is hidden where the point y pushed out by the
// grow distance g lies inside a grown blocker by more than kBlockerTolerance of its radius.
// The tolerance keeps a sphere a little past its seam, where the neighbouring patch's hit
// is the same crossing within the merge distance (float rounding of y is ~1e-6 of the
// coordinates, far below it).
const float kBlockerTolerance = 1e-4;
bool onConvexPatch(uint i, vec4 s, vec3 x) {
  float grow = peel.merge.z;
  vec3 y = s.xyz + ((s.w + grow) / s.w) * (x - s.xyz);
  for (uint k = blockerList[i]; k < blockerList[i + 1u]; ++k) {
    vec4 o = blockers[blockerList[k]];
    if (length(y - o.xyz) < o.w * (1.0 - kBlockerTolerance)) return false;
  }
  return true;
}

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
  // The nearer root beyond peelAfter() (0 outside peeling) that lies on the convex patch; the
  // whole sphere outside peeling.
  float after = peelAfter();
  for (int k = 0; k < 2; ++k) {
    float t = k == 0 ? tNear : tFar;
    float side = k == 0 ? -1.0 : 1.0;
    if (!(t > after)) continue;
    if (peel.flags.z != 0u && !onConvexPatch(patchIndex, s, org + t * dir)) continue;
    vec3 n = normalize(f + (side * root) * dir);
    writeHit(dir, t, n, kConvexKind, globalId(kConvexKind, patchIndex), sphereAtoms[patchIndex]);
    return;
  }
  discard;
}
#endif

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

// Distance from p to the saddle arc at blockers[a]: c + R (cos φ e1 + sin φ e2), φ in [0, Δφ].
float distanceToArc(uint a, vec3 p) {
  vec4 cR = blockers[a], e1 = blockers[a + 1u], e2 = blockers[a + 2u];
  vec3 q = p - cR.xyz;
  float phi = atan(dot(q, e2.xyz), dot(q, e1.xyz));
  if (phi < 0.0) phi += kTwoPi;
  if (phi <= e1.w) return length(q - cR.w * (cos(phi) * e1.xyz + sin(phi) * e2.xyz));
  return min(length(q - cR.w * e1.xyz), length(q - cR.w * (cos(e1.w) * e1.xyz + sin(e1.w) * e2.xyz)));
}

// build::onConvexPatch's saddle-arc test (sphere_blockers.cpp, onKeptPart): the nearest point
// of the blockers' circles to y (on grown sphere i, centre c, radius G) lies on a saddle arc
// of the list, else y is on a part of the sphere the list dropped (--drop-cavities).
bool onKeptPart(uint i, vec3 c, float G, vec3 y) {
  uint m = blockerList[0] / 2u;  // n + 1
  uint arcLo = blockerList[m + i], arcHi = blockerList[m + i + 1u];
  if (arcLo == arcHi) return true;
  vec3 u = (y - c) / G;
  float best = 1e30;
  vec3 edge = vec3(0.0);
  for (uint k = blockerList[i]; k < blockerList[i + 1u]; ++k) {
    vec4 o = blockers[blockerList[k]];
    vec3 axis = o.xyz - c;
    float D = length(axis);
    if (!(D > 0.0)) continue;
    vec3 n = axis / D;
    float h = (D * D + G * G - o.w * o.w) / (2.0 * D * G);
    if (!(abs(h) < 1.0)) continue;
    float cosAlpha = clamp(dot(n, u), -1.0, 1.0);
    float gap = abs(acos(cosAlpha) - acos(h));
    if (!(gap < best)) continue;
    vec3 side = u - cosAlpha * n;
    float sl = length(side);
    if (!(sl > 1e-6)) return true;  // y on a blocker's axis: every point of its circle is as near
    best = gap;
    edge = c + G * (h * n + sqrt(1.0 - h * h) * (side / sl));
  }
  if (best == 1e30) return true;
  for (uint a = arcLo; a < arcHi; a += 3u)
    if (distanceToArc(a, edge) < 1e-4 * G) return true;
  return false;
}

bool onConvexPatch(uint i, vec4 s, vec3 x) {
  float grow = peel.merge.z;
  vec3 y = s.xyz + ((s.w + grow) / s.w) * (x - s.xyz);
  for (uint k = blockerList[i]; k < blockerList[i + 1u]; ++k) {
    vec4 o = blockers[blockerList[k]];
    if (length(y - o.xyz) < o.w * (1.0 - kBlockerTolerance)) return false;
  }
  return onKeptPart(i, s.xyz, s.w + grow, y);
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

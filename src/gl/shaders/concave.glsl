// Concave triangles: the box of the spherical triangle in the frame of its mean direction; the probe-sphere hit with cone and clipping-plane tests of concave_patch.cpp.
//
// One file per patch kind: its records and atoms (bound to kRecordBinding and kAtomBinding
// for its draw), its geometry stage (SURFTRACE_GEOMETRY_STAGE) and its fragment stage
// (SURFTRACE_FRAGMENT_STAGE). gl/gpu_kinds.hpp holds the kind's row.
layout(std430, binding = kRecordBinding) readonly buffer Concaves { GpuConcave concaves[]; };
layout(std430, binding = kAtomBinding) readonly buffer ConcaveAtoms { uvec4 concaveAtoms[]; };  // atoms i, j, k, unused

#ifdef SURFTRACE_GEOMETRY_STAGE
layout(triangle_strip, max_vertices = 12) out;

// Box of the minor great-circle arc a→b on the unit sphere (concave_patch.cpp extendByArc):
// the extreme of coordinate k on the arc's circle lies on the arc iff it is on b's side of
// a and a's side of b.
void extendByArc(vec3 a, vec3 b, inout vec3 lo, inout vec3 hi) {
  vec3 m = cross(a, b);
  float mm = dot(m, m);
  if (!(mm > 0.0)) return;
  vec3 ta = cross(m, a), tb = cross(b, m);
  for (int k = 0; k < 3; ++k) {
    float extreme = sqrt(max(0.0, 1.0 - m[k] * m[k] / mm));
    if (ta[k] >= 0.0 && tb[k] >= 0.0) hi[k] = max(hi[k], extreme);
    if (ta[k] <= 0.0 && tb[k] <= 0.0) lo[k] = min(lo[k], -extreme);
  }
}

void main() {
  uint index = uint(gl_PrimitiveIDIn);
  GpuConcave C = concaves[index];
  vec3 p = C.probeRp.xyz;
  float rp = C.probeRp.w;
  // Frame: m the cone's mean direction, a1 towards u_i; the triangle is tight in it.
  vec3 m = normalize(C.dirIBegin.xyz + C.dirJCount.xyz + C.dirK.xyz);
  vec3 a1 = C.dirIBegin.xyz - dot(C.dirIBegin.xyz, m) * m;
  a1 = dot(a1, a1) > 1e-12 ? normalize(a1) : normalize(cross(m, abs(m.x) < 0.9 ? vec3(1, 0, 0) : vec3(0, 1, 0)));
  vec3 a2 = cross(m, a1);
  mat3 toLocal = transpose(mat3(a1, a2, m));
  vec3 u[3] = vec3[3](toLocal * C.dirIBegin.xyz, toLocal * C.dirJCount.xyz, toLocal * C.dirK.xyz);
  vec3 lo = min(min(u[0], u[1]), u[2]), hi = max(max(u[0], u[1]), u[2]);
  extendByArc(u[0], u[1], lo, hi);
  extendByArc(u[1], u[2], lo, hi);
  extendByArc(u[2], u[0], lo, hi);
  // A pole ±e_k inside the cone is an extreme too (g: inward face normals).
  vec3 g0 = cross(u[0], u[1]), g1 = cross(u[1], u[2]), g2 = cross(u[2], u[0]);
  if (dot(g0, u[2]) < 0.0) { g0 = -g0; g1 = -g1; g2 = -g2; }
  for (int k = 0; k < 3; ++k) {
    if (g0[k] >= 0.0 && g1[k] >= 0.0 && g2[k] >= 0.0) hi[k] = 1.0;
    if (g0[k] <= 0.0 && g1[k] <= 0.0 && g2[k] <= 0.0) lo[k] = -1.0;
  }
  // Float rounding of the frame and of the arc extremes: widen by 1e-3 of the probe radius.
  float pad = 1e-3;
  lo = max(lo - pad, vec3(-1.0 - pad));
  hi = min(hi + pad, vec3(1.0 + pad));
  vec3 base = p + rp * (lo.x * a1 + lo.y * a2 + lo.z * m);
  vec3 E[3] = vec3[3](rp * (hi.x - lo.x) * a1, rp * (hi.y - lo.y) * a2, rp * (hi.z - lo.z) * m);
  if (useCylinder()) {
    // The cylinder about the axis p → p + m (Sect. 5.2): the triangle's directions u have
    // m·u in [lo.z, hi.z] and distance from the axis at most the box corner's, and at most
    // sqrt(1 − lo.z²) when lo.z >= 0 (|u| = 1).
    float corner = length(max(abs(lo.xy), abs(hi.xy)));
    float radial = lo.z >= 0.0 ? min(corner, sqrt(1.0 - lo.z * lo.z) + pad) : corner;
    emitCylinderOrBox(p + rp * lo.z * m, m, rp * (hi.z - lo.z), rp * radial, base, E, index);
  } else {
    emitBox(base, E, index);
  }
}
#endif

#ifdef SURFTRACE_FRAGMENT_STAGE
layout(binding = kClipPlaneUnit) uniform samplerBuffer clipPlanes;  // n, w: keep n·x + w <= 0

void main() {
  countFragment(globalId(kConcaveKind, patchIndex), 0u);
  GpuConcave C = concaves[patchIndex];
  vec3 org, dir;
  cameraRay(org, dir);
  vec3 p = C.probeRp.xyz, uI = C.dirIBegin.xyz, uJ = C.dirJCount.xyz, uK = C.dirK.xyz;
  float rp = C.probeRp.w, rr = rp * rp;
  // ORACLES B.5 as in concave_patch.cpp: both roots from the closest point f.
  vec3 op = org - p;
  float b = dot(op, dir);
  vec3 f = op - b * dir;
  float disc = rr - dot(f, f);
  if (!(disc >= 0.0)) discard;
  float root = sqrt(disc);
  float q = -b - (b >= 0.0 ? root : -root);
  float r2 = q != 0.0 ? (dot(op, op) - rr) / q : 0.0;
  float tNear = min(q, r2), tFar = max(q, r2);
  // Inward cone faces (ORACLES A.4); one sign orients all three.
  vec3 gij = cross(uI, uJ), gjk = cross(uJ, uK), gki = cross(uK, uI);
  if (dot(gij, uK) < 0.0) { gij = -gij; gjk = -gjk; gki = -gki; }
  int begin = int(C.dirIBegin.w), count = int(C.dirJCount.w);
  // The visible root is usually the far one, but both are tested in ascending t.
  // Beyond peelAfter(): 0 outside peeling, the previous layer's t plus the merge distance.
  float after = peelAfter();
  for (int side = 0; side < 2; ++side) {
    float t = side == 0 ? tNear : tFar;
    if (!(t > after)) continue;
    vec3 v = f + (side == 0 ? -root : root) * dir;
    if (dot(gij, v) < 0.0 || dot(gjk, v) < 0.0 || dot(gki, v) < 0.0) continue;
    vec3 x = p + v;
    bool kept = true;
    for (int k = 0; k < count; ++k) {
      vec4 plane = texelFetch(clipPlanes, begin + k);
      if (dot(plane.xyz, x) + plane.w > 0.0) {
        kept = false;
        break;
      }
    }
    if (!kept) continue;
    // The atom of the nearest contact direction (ScenePatches::atomOf).
    float di = dot(v, uI), dj = dot(v, uJ), dk = dot(v, uK);
    uvec4 atoms = concaveAtoms[patchIndex];
    uint atom = di >= dj && di >= dk ? atoms.x : (dj >= dk ? atoms.y : atoms.z);
    writeHit(dir, t, normalize(-v), kConcaveKind, globalId(kConcaveKind, patchIndex), atom);
    return;
  }
  discard;
}
#endif

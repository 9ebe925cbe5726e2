// The ball-and-stick model's sticks: capped cylinders, ray-cast in the rectangle around their
// bounding ball; the ray–cylinder hit of trace/stick_patch.cpp in float.
layout(std430, binding = kRecordBinding) readonly buffer Sticks { vec4 sticks[]; };  // [2i] a, radius; [2i + 1] b
layout(std430, binding = kAtomBinding) readonly buffer StickAtoms { uvec2 stickAtoms[]; };

#ifdef SURFTRACE_GEOMETRY_STAGE
layout(triangle_strip, max_vertices = 4) out;

void main() {
  uint index = uint(gl_PrimitiveIDIn);
  vec4 a = sticks[2u * index], b = sticks[2u * index + 1u];
  emitSphereRect(0.5 * (a.xyz + b.xyz), sqrt(0.25 * dot(b.xyz - a.xyz, b.xyz - a.xyz) + a.w * a.w), index);
}
#endif

#ifdef SURFTRACE_FRAGMENT_STAGE
void main() {
  countFragment(globalId(kStickKind, patchIndex), 0u);
  vec4 a = sticks[2u * patchIndex];
  vec3 b = sticks[2u * patchIndex + 1u].xyz;
  vec3 org, dir;
  cameraRay(org, dir);
  float L = length(b - a.xyz);
  vec3 u = (b - a.xyz) / L;
  vec3 oa = org - a.xyz;
  float h0 = dot(oa, u), dh = dot(dir, u);
  vec3 oPerp = oa - h0 * u, dPerp = dir - dh * u;
  float A = dot(dPerp, dPerp), rr = a.w * a.w;
  const float kNoHit = 3.0e38;
  float best = kNoHit;
  vec3 n = vec3(0.0);
  if (A > 0.0) {
    // The shadow's closest point f to the axis keeps the small term r² − |f|² (as the sphere).
    float tc = -dot(oPerp, dPerp) / A;
    vec3 f = oPerp + tc * dPerp;
    float disc = rr - dot(f, f);
    if (disc >= 0.0) {
      float half_ = sqrt(disc / A);
      for (int k = 0; k < 2; ++k) {
        float sgn = k == 0 ? -1.0 : 1.0;
        float t = tc + sgn * half_;
        float h = h0 + t * dh;
        if (t > 0.0 && t < best && h >= 0.0 && h <= L) {
          best = t;
          n = normalize(f + (sgn * half_) * dPerp);
        }
      }
    }
  }
  if (dh != 0.0) {
    for (int k = 0; k < 2; ++k) {
      float cap = k == 0 ? 0.0 : L;
      float t = (cap - h0) / dh;
      vec3 p = oPerp + t * dPerp;
      if (t > 0.0 && t < best && dot(p, p) <= rr) {
        best = t;
        n = k == 0 ? -u : u;
      }
    }
  }
  if (!(best < kNoHit)) discard;
  // Each half takes its atom (atomOf in stick_patch.hpp).
  uvec2 atoms = stickAtoms[patchIndex];
  float hHit = h0 + best * dh;
  writeHit(dir, best, n, kStickKind, globalId(kStickKind, patchIndex), 2.0 * hHit <= L ? atoms.x : atoms.y);
}
#endif

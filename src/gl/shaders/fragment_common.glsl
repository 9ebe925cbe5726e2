// Fragment-stage helpers: the camera ray, shading, writing a hit to the render targets.

flat in uint patchIndex;
layout(std430, binding = kAtomColorBinding) readonly buffer AtomColors { vec4 atomColors[]; };
layout(location = 0) out vec4 outColor;
layout(location = 1) out vec2 outDepth;    // ray distance t, view-space z
layout(location = 2) out vec4 outNormal;
layout(location = 3) out uvec4 outIds;     // kind, global patch id, atom, flags

// view::Camera::ray through the pixel centre: gl_FragCoord is (x + 0.5, y + 0.5) with y up,
// the camera's sy runs down, so sy = H − gl_FragCoord.y.
void cameraRay(out vec3 org, out vec3 dir) {
  float sx = gl_FragCoord.x, sy = frame.viewport.y - gl_FragCoord.y;
  float x = 2.0 * sx / frame.viewport.x - 1.0, y = 2.0 * sy / frame.viewport.y - 1.0;
  vec3 f = frame.forwardTan.xyz, r = frame.rightAspect.xyz, u = frame.upHalfHeight.xyz;
  float aspect = frame.rightAspect.w;
  if (frame.eyeProjection.w == 0.0) {
    float h = frame.forwardTan.w;
    org = frame.eyeProjection.xyz;
    dir = normalize(f + (x * h * aspect) * r - (y * h) * u);
  } else {
    float h = frame.upHalfHeight.w;
    org = frame.eyeProjection.xyz + (x * h * aspect) * r - (y * h) * u;
    dir = f;
  }
}

// view::shade. Key-fill model (shading.z = 1): key and fill lights and an ambient term, no
// shadows or occlusion (S = A = 1). Headlight: Blinn–Phong with the light at the eye (half
// vector = light direction).
vec3 shade(vec3 base, vec3 n, vec3 towardsEye) {
  if (frame.shading.z != 0u) {
    vec3 k = frame.keyLight.xyz;
    float nk = dot(n, k);
    float spec = nk > 0.0 ? frame.lighting.z * pow(max(0.0, dot(n, normalize(k + towardsEye))), frame.lighting.w) : 0.0;
    float diffuse = frame.lighting.x + frame.lighting.y * max(0.0, nk) + frame.fillLight.w * max(0.0, dot(n, frame.fillLight.xyz));
    return min(base * diffuse + vec3(spec), vec3(1.0));
  }
  float nl = max(0.0, dot(n, towardsEye));
  float spec = frame.lighting.z * pow(nl, frame.lighting.w);
  return min(base * (frame.lighting.x + frame.lighting.y * nl) + vec3(spec), vec3(1.0));
}

// The global patch id (view::PatchIdOrder) of patch `index` of a kind.
uint globalId(uint kind, uint index) { return frame.kinds[kind - 1u].first.x + index; }

// Optional per-patch statistics (GlOptions::countFragments): fragments shaded, hits.
layout(std430, binding = kFragmentCountBinding) buffer FragmentCounts { uint fragmentCounts[]; };
void countFragment(uint patchId, uint what) {
  if (frame.traceParams.z != 0.0) atomicAdd(fragmentCounts[2u * patchId + what], 1u);
}

// Depth peeling (gl_renderer.cpp): pass k keeps the nearest hit strictly behind layer k − 1 by
// the merge distance, and in front of the opaque geometry. Outside peeling both bounds are off
// and a hit counts for t > 0, the opaque draw's test.
layout(std140, binding = kPeelBinding) uniform Peel { GpuPeel peel; };
layout(binding = kPreviousLayerUnit) uniform sampler2D previousLayer;
layout(binding = kOpaqueDepthUnit) uniform sampler2D opaqueDepth;

// The ray distance beyond which a hit is the next layer: 0, or layer k − 1's t plus the merge
// distance (+inf where layer k − 1 is empty: the pixel has no more layers).
float peelAfter() {
  if (peel.flags.x == 0u) return 0.0;
  float t = texelFetch(previousLayer, ivec2(gl_FragCoord.xy), 0).r;
  return t + (peel.merge.x + peel.merge.y * t);
}

// Whether the opaque geometry hides a hit at t.
bool behindOpaque(float t) {
  return peel.flags.y != 0u && t >= texelFetch(opaqueDepth, ivec2(gl_FragCoord.xy), 0).r;
}

void writeHit(vec3 dir, float t, vec3 n, uint kind, uint patchId, uint atom) {
  if (behindOpaque(t)) discard;
  countFragment(patchId, 1u);
  vec3 base = frame.shading.x == 0u ? frame.kinds[kind - 1u].color.rgb
              : (atom < frame.shading.y ? atomColors[atom].rgb : vec3(1.0, 0.0, 1.0));
  outColor = vec4(shade(base, n, -dir), 1.0);
  outDepth = vec2(t, t * dot(dir, frame.forwardTan.xyz));
  outNormal = vec4(n, 0.0);
  outIds = uvec4(kind, patchId, atom, 0u);
  // Linear in t: per pixel the same order as the ray distance, which is what occludes.
  gl_FragDepth = clamp(t * frame.viewport.w, 0.0, 1.0);
}

// The first hit in t > 0 of the ray with the whole sphere s (centre, radius), as
// sphere_patch.cpp (ORACLES B.5): f is the ray's closest point to the centre, so the
// discriminant r² − |f|² keeps the small term that b² − (|oc|² − r²) would cancel.
bool sphereHit(vec4 s, vec3 org, vec3 dir, out float t, out vec3 n) {
  vec3 oc = org - s.xyz;
  float b = dot(oc, dir);
  vec3 f = oc - b * dir;
  float rr = s.w * s.w;
  float disc = rr - dot(f, f);
  t = 0.0;
  n = vec3(0.0);
  if (!(disc >= 0.0)) return false;
  float root = sqrt(disc);
  float q = -b - (b >= 0.0 ? root : -root);
  float r2 = q != 0.0 ? (dot(oc, oc) - rr) / q : 0.0;
  float tNear = min(q, r2), tFar = max(q, r2);
  float side;
  if (tNear > 0.0) {
    t = tNear;
    side = -1.0;
  } else if (tFar > 0.0) {
    t = tFar;
    side = 1.0;
  } else {
    return false;
  }
  n = normalize(f + (side * root) * dir);
  return true;
}

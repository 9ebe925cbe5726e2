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

// The light maps (gl_renderer.cpp, renderLightMaps): depth maps of the whole scene along the
// key light's disc and along directions over the sphere, drawn before the frame.
layout(std430, binding = kLightMapBinding) readonly buffer LightMaps { GpuLightMap lightMaps[]; };
layout(binding = kLightMapUnit) uniform sampler2DArrayShadow lightDepth;

// The depth bias, in texels: a point's own surface, stored at the texel centres around it,
// lies up to the slope tan θ (θ between n and the light) per texel nearer the light, and the
// point is pushed off the surface by kNormalOffset texels, which covers the curvature within a
// texel. Chosen on 1CRN against Embree (tests/gl/gl_lighting_test.cpp): less bias lets the
// surface shadow itself (the wide key lookup at 0.5 slope texels: mean colour error 0.025
// against 0.009), more lets light into contact shadows; the flat floor shows no acne.
const float kBiasTexels = 0.1;
const float kBiasSlopeTexels = 0.5;
const float kMaxSlope = 8.0;
const float kNormalOffset = 0.25;
const float kWideSlopeTexels = 1.5;

// The fraction of the bilinear footprint of p (a point pushed off the surface) in map i where
// the stored surface lies no nearer the light than p's depth less the bias (depth units): where
// p is lit.
float lightMapPasses(uint i, vec3 p, float bias) {
  GpuLightMap m = lightMaps[i];
  vec3 q = vec3(dot(m.toMapX.xyz, p) + m.toMapX.w, dot(m.toMapY.xyz, p) + m.toMapY.w, dot(m.toMapZ.xyz, p) + m.toMapZ.w);
  return texture(lightDepth, vec4(q.xy, float(i), q.z - bias));
}

// The same over four bilinear lookups a texel apart on each side (a 4×4-texel footprint): the
// key light's maps step by 1/keyMaps across a penumbra, each step an edge one texel wide; the
// wider footprint blends neighbouring steps, so the penumbra reads smooth. Its texels lie up to
// kWideSlopeTexels farther (in slopes) than the plain lookup's: the bias grows by as much.
float lightMapPassesWide(uint i, vec3 p, float bias) {
  GpuLightMap m = lightMaps[i];
  vec3 q = vec3(dot(m.toMapX.xyz, p) + m.toMapX.w, dot(m.toMapY.xyz, p) + m.toMapY.w, dot(m.toMapZ.xyz, p) + m.toMapZ.w);
  float texel = 1.0 / float(textureSize(lightDepth, 0).x), r = q.z - bias;
  return 0.25 * (texture(lightDepth, vec4(q.xy + vec2(-texel, -texel), float(i), r)) +
                 texture(lightDepth, vec4(q.xy + vec2(texel, -texel), float(i), r)) +
                 texture(lightDepth, vec4(q.xy + vec2(-texel, texel), float(i), r)) +
                 texture(lightDepth, vec4(q.xy + vec2(texel, texel), float(i), r)));
}

// The bias of a map for a surface of normal n, in depth units: cosine is n·d > 0, slopeTexels
// the texels per slope (kBiasSlopeTexels, more for the wide lookup).
float lightMapBias(float cosine, float slopeTexels) {
  float slope = min(sqrt(max(0.0, 1.0 - cosine * cosine)) / cosine, kMaxSlope);
  return (kBiasTexels + slopeTexels * slope) * frame.lightMapScale.x * frame.lightMapScale.y;
}

// S and A of view::shade at x (normal n) from the light maps, as trace/render.cpp's Shader
// estimates them with rays: S the fraction of the key light's maps (directions over its disc)
// in which x is lit and n·d > 0; A the cosine-weighted fraction of the ambient maps' directions
// (n·d > 0) in which x is lit. A map holds only the surface nearest its light, the last exit of
// a ray from x through the molecule, so the occlusion distance of the rays cannot be honoured
// (an occluder whose far side lies beyond it would count as none): A counts every occluder,
// as ChimeraX's multi-shadow lighting does (README, Lighting: how much that differs).
vec2 lightVisibility(vec3 x, vec3 n) {
  uint keyMaps = frame.lightMaps.x, ambientMaps = frame.lightMaps.y;
  if (keyMaps + ambientMaps == 0u) return vec2(1.0);
  vec3 p = x + (kNormalOffset * frame.lightMapScale.x) * n;
  float key = 1.0;
  if (keyMaps > 0u) {
    float lit = 0.0;
    for (uint i = 0u; i < keyMaps; ++i) {
      float c = dot(n, lightMaps[i].direction.xyz);
      if (c > 0.0) lit += lightMapPassesWide(i, p, lightMapBias(c, kBiasSlopeTexels + kWideSlopeTexels));
    }
    key = lit / float(keyMaps);
  }
  float ambient = 1.0;
  if (ambientMaps > 0u) {
    float open = 0.0, total = 0.0;
    for (uint i = keyMaps; i < keyMaps + ambientMaps; ++i) {
      float c = dot(n, lightMaps[i].direction.xyz);
      if (!(c > 0.0)) continue;
      open += c * lightMapPasses(i, p, lightMapBias(c, kBiasSlopeTexels));
      total += c;
    }
    ambient = total > 0.0 ? open / total : 1.0;
  }
  return vec2(key, ambient);
}

// view::shade. Key-fill model (shading.z = 1): key and fill lights and an ambient term, the
// key light times S and the ambient and fill terms times A (lightVisibility; 1 without light
// maps). Headlight: Blinn–Phong with the light at the eye (half vector = light direction).
vec3 shade(vec3 base, vec3 x, vec3 n, vec3 towardsEye) {
  if (frame.shading.z != 0u) {
    vec3 k = frame.keyLight.xyz;
    float nk = dot(n, k);
    // The key light's visibility matters only where it shines (n·k > 0), as in trace/render.cpp.
    vec2 sa = lightVisibility(x, n);
    float s = nk > 0.0 ? sa.x : 1.0, a = sa.y;
    float spec = nk > 0.0 ? s * frame.lighting.z * pow(max(0.0, dot(n, normalize(k + towardsEye))), frame.lighting.w) : 0.0;
    float diffuse = frame.lighting.x * a + frame.lighting.y * max(0.0, nk) * s +
                    frame.fillLight.w * max(0.0, dot(n, frame.fillLight.xyz)) * a;
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
  vec3 org, unused;
  cameraRay(org, unused);
  outColor = vec4(shade(base, org + t * dir, n, -dir), 1.0);
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

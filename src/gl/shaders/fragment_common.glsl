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

// The light maps (gl_renderer.cpp, drawLightMaps): depth maps of the whole scene along the
// key light's disc and along directions over the sphere, drawn before the frame. Each texel
// holds the exact ray-cast depth of the surface nearest the light at its centre.
layout(std430, binding = kLightMapBinding) readonly buffer LightMaps { GpuLightMap lightMaps[]; };
layout(binding = kLightMapUnit) uniform sampler2DArray lightDepth;

// Receiver-plane lookups: each texel around a point is compared with the depth of the point's
// own tangent plane at that texel's centre (from the exact normal), not with the point's depth
// less a bias of a fixed number of texels, which both let light into contact shadows and
// penumbrae and still left grazing lit surfaces shadowed by themselves. The point's own
// surface, stored exactly at the texel centres, leaves that plane only by its curvature, so
// the bias covers the curvature (kBiasCurvature·d²/cos³θ, d the texel's distance in Å: a
// concave patch of radius R lies d²/(2R cos³θ) above the plane in depth; 0.6 Å⁻¹ is chosen on
// 1CRN against Embree, between 1/2R of the probe, 0.36, which lets concave patches shadow
// themselves, and 1.0, which lets light into creases) and float rounding (kBiasAngstrom).
// Past kMaxSlope the plane is kept at that slope.
const float kBiasAngstrom = 0.01;
const float kBiasCurvature = 0.6;
const float kMaxSlope = 8.0;

// The lit fraction of map i at x (normal n, cosine = n·d > 0) over the 2×2 texels around x,
// weighted bilinearly; outside a map (nothing drawn there) is lit. A wider footprint (4×4,
// once used to blend the key maps' steps across a penumbra) compares texels twice as far,
// where the curvature bias is four times larger: measured on 1CRN (soft, curvature bias 0.36),
// the colour p99 against Embree was 0.049 with it, 0.029 without.
float lightMapLit(uint i, vec3 x, vec3 n, float cosine) {
  GpuLightMap m = lightMaps[i];
  int size = textureSize(lightDepth, 0).x;
  vec3 q = vec3(dot(m.toMapX.xyz, x) + m.toMapX.w, dot(m.toMapY.xyz, x) + m.toMapY.w, dot(m.toMapZ.xyz, x) + m.toMapZ.w);
  float texel = m.direction.w, depthScale = frame.lightMapScale.y;
  // The tangent plane's depth per texel along u and v: n·(a·right + c·forward) = 0 with
  // forward = −d, so c = a·(n·right)/cosine.
  vec2 slope = vec2(dot(n, normalize(m.toMapX.xyz)), dot(n, normalize(m.toMapY.xyz))) / cosine;
  float steep = length(slope);
  if (steep > kMaxSlope) slope *= kMaxSlope / steep;
  vec2 gradient = slope * (texel * depthScale);
  // A curved surface leaves its tangent plane by s²/2R along the normal at s Å along it: at d
  // Å in the map, s = d/cos θ at most and the depth differs by s²/(2R cos θ): d²/(2R cos³ θ).
  float c = max(cosine, 1.0 / sqrt(1.0 + kMaxSlope * kMaxSlope));
  float curve = 1.0 / (c * c * c);
  vec2 s = q.xy - 0.5;
  vec2 b = floor(s), f = s - b;
  float lit = 0.0;
  for (int j = 0; j <= 1; ++j) {
    float wy = j == 0 ? 1.0 - f.y : f.y;
    int ty = int(b.y) + j;
    for (int k = 0; k <= 1; ++k) {
      float wx = k == 0 ? 1.0 - f.x : f.x;
      int tx = int(b.x) + k;
      if (tx < 0 || ty < 0 || tx >= size || ty >= size) {
        lit += wx * wy;
        continue;
      }
      vec2 offset = vec2(float(tx), float(ty)) - s;  // texels from x to the texel's centre
      float d2 = dot(offset, offset) * texel * texel;
      float plane = q.z + dot(gradient, offset) - (kBiasAngstrom + kBiasCurvature * d2 * curve) * depthScale;
      if (texelFetch(lightDepth, ivec3(tx, ty, int(i)), 0).r >= plane) lit += wx * wy;
    }
  }
  return lit;
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
  float key = 1.0;
  if (keyMaps > 0u) {
    float lit = 0.0;
    for (uint i = 0u; i < keyMaps; ++i) {
      float c = dot(n, lightMaps[i].direction.xyz);
      if (c > 0.0) lit += lightMapLit(i, x, n, c);
    }
    key = lit / float(keyMaps);
  }
  float ambient = 1.0;
  if (ambientMaps > 0u) {
    float open = 0.0, total = 0.0;
    for (uint i = keyMaps; i < keyMaps + ambientMaps; ++i) {
      float c = dot(n, lightMaps[i].direction.xyz);
      if (!(c > 0.0)) continue;
      open += c * lightMapLit(i, x, n, c);
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

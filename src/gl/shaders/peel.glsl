// Depth peeling's image passes (gl_renderer.cpp): a full-screen triangle that composites one
// peeled layer front to back, and the resolve over the opaque colour or the background.
//
// The colour is trace/render.cpp's: C = Σ_k α(1 − α)^k c_k + (1 − α)^n under, coverage
// 1 − (1 − α)^n. The composite step draws (α c_k, α) with the blend (1 − A_dst, 1) (the
// "under" operator), so the target holds Σ α(1 − α)^k c_k and A = 1 − (1 − α)^k; its second
// target counts the layers (additive blend). The resolve writes C + (1 − A) under.
layout(std140, binding = kPeelBinding) uniform Peel { GpuPeel peel; };

#ifdef SURFTRACE_VERTEX_STAGE
void main() {
  // (−1, −1), (3, −1), (−1, 3): one triangle covers the viewport.
  vec2 p = vec2(float((gl_VertexID & 1) << 2) - 1.0, float((gl_VertexID & 2) << 1) - 1.0);
  gl_Position = vec4(p, 0.0, 1.0);
}
#endif

#ifdef SURFTRACE_FRAGMENT_STAGE
layout(binding = kLayerColorUnit) uniform sampler2D layerColor;
layout(binding = kLayerDepthUnit) uniform sampler2D layerDepth;
layout(binding = kAccumulatedUnit) uniform sampler2D accumulated;
layout(binding = kOpaqueColorUnit) uniform sampler2D opaqueColor;
layout(binding = kOpaqueDepthUnit) uniform sampler2D opaqueDepth;
layout(location = 0) out vec4 outColor;
layout(location = 1) out float outLayers;

void main() {
  ivec2 p = ivec2(gl_FragCoord.xy);
  if (peel.flags.w == 0u) {
    float t = texelFetch(layerDepth, p, 0).r;
    if (isinf(t)) discard;  // no layer here
    // Layer 0 is drawn over the opaque geometry (the ball-and-stick model) in the main
    // targets: where no surface lies in front of it, what is there is the opaque hit itself.
    if (peel.flags.y != 0u && t >= texelFetch(opaqueDepth, p, 0).r) discard;
    float alpha = peel.merge.w;
    outColor = vec4(alpha * texelFetch(layerColor, p, 0).rgb, alpha);
    outLayers = 1.0;
    return;
  }
  vec4 c = texelFetch(accumulated, p, 0);
  vec4 under = peel.flags.y != 0u ? texelFetch(opaqueColor, p, 0) : vec4(frame.background.rgb, 0.0);
  outColor = vec4(c.rgb + (1.0 - c.a) * under.rgb, c.a + (1.0 - c.a) * under.a);
  outLayers = 0.0;
}
#endif

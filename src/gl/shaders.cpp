// GLSL sources of the ray-casting programs (Lindow et al. 2010, Sect. 5), one per patch kind.
//
// Every fragment shader rebuilds the exact pixel-centre ray of view::Camera::ray and
// intersects one patch with the same formulas and the same patch tests as the double
// precision intersectors in src/trace (sphere_patch.cpp, torus_patch.cpp,
// concave_patch.cpp), in float on origin-shifted coordinates. Record layouts: gpu_layout.hpp.
#include "gl/shaders.hpp"

namespace surftrace::gl {
namespace {

// Declarations every stage shares: the per-frame uniform block (std140, GpuFrame).
constexpr const char* kHeader = R"glsl(#version 450 core
layout(std140, binding = 0) uniform Frame {
  vec4 eyeProjection;   // eye (origin-shifted), projection (0 perspective, 1 orthographic)
  vec4 forwardTan;      // unit forward, tan(fovY/2)
  vec4 rightAspect;     // unit right, W/H
  vec4 upHalfHeight;    // unit true up, orthoHeight/2
  vec4 viewport;        // W, H, near plane (Å), 1/(depth range)
  vec4 lighting;        // ambient, diffuse, specular, shininess
  vec4 background;
  vec4 kindColor[3];
  uvec4 idBase;         // first global id of spheres, tori, concave; colour mode (0 = patch)
  uvec4 counts;         // atom colours, torus method (0 quartic, 1 sphere tracing), max steps, plain march
  vec4 traceParams;     // sphere-tracing stop distance (Å), primitive (0 box, 1 cylinder), count fragments
} frame;
const float kTwoPi = 6.283185307179586;
const float kHalfPi = 1.5707963267948966;
)glsl";

// The patch records (std430, gpu_layout.hpp), read by the geometry and fragment stages.
constexpr const char* kBuffers = R"glsl(
struct Torus { vec4 centerR; vec4 axisRp; vec4 e1Phi; vec4 theta; };
struct Concave { vec4 probeRp; vec4 dirIBegin; vec4 dirJCount; vec4 dirK; };
layout(std430, binding = 0) readonly buffer Spheres { vec4 spheres[]; };
layout(std430, binding = 1) readonly buffer SphereAtoms { uint sphereAtoms[]; };
layout(std430, binding = 2) readonly buffer Tori { Torus tori[]; };
layout(std430, binding = 3) readonly buffer TorusAtoms { uvec2 torusAtoms[]; };
layout(std430, binding = 4) readonly buffer Concaves { Concave concaves[]; };
layout(std430, binding = 5) readonly buffer ConcaveAtoms { uvec4 concaveAtoms[]; };
layout(std430, binding = 6) readonly buffer AtomColors { vec4 atomColors[]; };
)glsl";

// One point per patch; the geometry shader finds its record through gl_PrimitiveIDIn.
constexpr const char* kVertex = R"glsl(
void main() {}
)glsl";

constexpr const char* kGeometryCommon = R"glsl(
layout(points) in;
flat out uint patchIndex;

bool orthographic() { return frame.eyeProjection.w != 0.0; }

// (right, up, forward) coordinates of x relative to the eye.
vec3 viewOf(vec3 x) {
  vec3 v = x - frame.eyeProjection.xyz;
  return vec3(dot(v, frame.rightAspect.xyz), dot(v, frame.upHalfHeight.xyz), dot(v, frame.forwardTan.xyz));
}

// Clip coordinates whose NDC are the camera's image coordinates (2 sx/W − 1, 1 − 2 sy/H),
// so the viewport maps a patch onto the pixels whose centre rays can reach it. The
// perspective z (z/w = 1 − 2 near/vz) clips only at the near plane: depth comes from
// gl_FragDepth, never from this z.
vec4 clipOf(vec3 x) {
  vec3 v = viewOf(x);
  if (orthographic())
    return vec4(v.x / (frame.upHalfHeight.w * frame.rightAspect.w), v.y / frame.upHalfHeight.w, 0.0, 1.0);
  float h = frame.forwardTan.w;
  return vec4(v.x / (h * frame.rightAspect.w), v.y / h, v.z - 2.0 * frame.viewport.z, v.z);
}

void emitRect(vec2 lo, vec2 hi, uint index) {
  patchIndex = index; gl_Position = vec4(lo.x, lo.y, 0.0, 1.0); EmitVertex();
  patchIndex = index; gl_Position = vec4(hi.x, lo.y, 0.0, 1.0); EmitVertex();
  patchIndex = index; gl_Position = vec4(lo.x, hi.y, 0.0, 1.0); EmitVertex();
  patchIndex = index; gl_Position = vec4(hi.x, hi.y, 0.0, 1.0); EmitVertex();
  EndPrimitive();
}

// Image-plane coordinates: (x/z, y/z) in perspective, (x, y) orthographic, in view units;
// NDC = image / imageScale().
vec2 imageScale() {
  return orthographic() ? vec2(frame.upHalfHeight.w * frame.rightAspect.w, frame.upHalfHeight.w)
                        : vec2(frame.forwardTan.w * frame.rightAspect.w, frame.forwardTan.w);
}

// Support function, in image direction nu (unit), of the projection of the disk with view
// coordinates centre C, unit normal a and radius r: max nu·x over the projected disk. In
// perspective the lines nu·x = c through the eye are planes (nu, −c)·v = 0; tangency to
// the disk, (nu·C − c C.z)² = r² (1 + c² − (nu·a − c a.z)²), is a quadratic in c whose
// larger root is the support (the disk must lie in front of the eye: C.z > r |a × z|).
// The discriminant is expanded so that the (nu·C C.z)² terms cancel exactly.
float diskSupport(vec3 C, vec3 a, float r, vec2 nu) {
  float alpha = dot(nu, C.xy), gamma = dot(nu, a.xy);
  if (orthographic()) return alpha + r * sqrt(max(0.0, 1.0 - gamma * gamma));
  float beta = C.z, az2 = 1.0 - a.z * a.z;
  float A2 = beta * beta - r * r * az2;
  float b = alpha * beta + r * r * gamma * a.z;
  float K = 2.0 * alpha * beta * gamma * a.z + beta * beta * (1.0 - gamma * gamma) + alpha * alpha * az2 -
            r * r * (az2 - gamma * gamma);
  return (b + r * sqrt(max(K, 0.0))) / A2;
}

// The rasterisation primitive of Lindow et al. 2010, Sect. 5.2, Fig. 6, for a patch inside
// the cylinder of the given radius around the segment base → base + h·axis (axis unit): the
// quadrilateral bounded by the two silhouette lines of the cylinder (the projections of
// its two silhouette generators) and, across the projected axis, by the extreme points of
// the two projected caps: the trapezoid spanned through the extreme cap points. Every
// line's offset is the exact support of the projected cylinder (the larger of its caps'
// supports, the cylinder being their convex hull) plus 1/64 pixel, so the quad covers the
// projection whatever the directions are; where the four lines do not bound a convex quad
// (axis seen end-on, eye within the cylinder's radius) the four directions become ±x, ±y:
// the projection's bounding rectangle. Q: the corners in NDC, counter-clockwise. Returns
// false where a cap reaches the eye plane (eye inside or beside the cylinder).
bool cylinderQuad(vec3 base, vec3 axis, float h, float radius, out vec2 Q[4]) {
  bool ortho = orthographic();
  vec3 a = vec3(dot(axis, frame.rightAspect.xyz), dot(axis, frame.upHalfHeight.xyz), dot(axis, frame.forwardTan.xyz));
  vec3 C0 = viewOf(base), C1 = viewOf(base + h * axis);
  if (!ortho && min(C0.z, C1.z) - radius * sqrt(max(0.0, 1.0 - a.z * a.z)) <= frame.viewport.z) return false;
  vec2 scale = imageScale();
  vec2 pixel = 2.0 / frame.viewport.xy * scale;  // one pixel in image units
  vec2 slack = pixel / 64.0;
  vec2 nu[4];
  bool trapezoid = false;
  vec2 d = ortho ? C1.xy - C0.xy : C1.xy / C1.z - C0.xy / C0.z;  // projected axis
  if (dot(d, d) > 1e-12 * dot(pixel, pixel)) {
    vec2 dn = normalize(d);
    nu[0] = -dn;
    nu[2] = dn;
    if (ortho) {
      // Silhouette generators at ±(axis × view direction): sides parallel to the axis.
      nu[1] = vec2(dn.y, -dn.x);  // −d, right of d, d, left of d
      nu[3] = -nu[1];
      trapezoid = true;
    } else {
      // Tangent planes through the eye (the view origin): normals n with n·a = 0 and
      // n·(eye − C0) = radius; the cylinder lies on n·v <= 0, the image side nu·x <= c.
      vec3 w = -C0;
      vec3 wp = w - dot(w, a) * a;
      float D = length(wp);
      if (D > radius * 1.0001) {
        vec3 wh = wp / D, bh = cross(a, wh);
        float cs = radius / D, sn = sqrt(max(0.0, 1.0 - cs * cs));
        vec3 n0 = cs * wh + sn * bh, n1 = cs * wh - sn * bh;
        if (length(n0.xy) > 1e-6 && length(n1.xy) > 1e-6) {
          vec2 s0 = normalize(n0.xy), s1 = normalize(n1.xy);
          bool s0Left = d.x * s0.y - d.y * s0.x > 0.0;
          nu[1] = s0Left ? s1 : s0;  // −d, right of d, d, left of d
          nu[3] = s0Left ? s0 : s1;
          trapezoid = true;
        }
      }
    }
  }
  float off[4];
  vec2 V[4];
  bool valid = trapezoid;
  if (trapezoid) {
    for (int k = 0; k < 4; ++k)
      off[k] = max(diskSupport(C0, a, radius, nu[k]), diskSupport(C1, a, radius, nu[k])) + dot(abs(nu[k]), slack);
    for (int k = 0; valid && k < 4; ++k) {
      int j = (k + 1) % 4;
      float det = nu[k].x * nu[j].y - nu[k].y * nu[j].x;  // > 0: a left turn below π
      if (!(det > 1e-4)) valid = false;
      else V[k] = vec2(off[k] * nu[j].y - off[j] * nu[k].y, nu[k].x * off[j] - nu[j].x * off[k]) / det;
    }
    // Each corner must satisfy the two other lines, or one line cuts the quad short.
    for (int k = 0; valid && k < 4; ++k)
      for (int j = 0; j < 4; ++j)
        if (!(dot(nu[j], V[k]) <= off[j] + 0.25 * dot(abs(nu[j]), pixel))) valid = false;
    for (int k = 0; valid && k < 4; ++k)
      if (!all(lessThan(abs(V[k] / scale), vec2(64.0)))) valid = false;
  }
  if (!valid) {
    // The projection's bounding rectangle.
    nu[0] = vec2(1.0, 0.0); nu[1] = vec2(0.0, 1.0); nu[2] = vec2(-1.0, 0.0); nu[3] = vec2(0.0, -1.0);
    for (int k = 0; k < 4; ++k)
      off[k] = max(diskSupport(C0, a, radius, nu[k]), diskSupport(C1, a, radius, nu[k])) + dot(abs(nu[k]), slack);
    V[0] = vec2(off[0], -off[3]); V[1] = vec2(off[0], off[1]); V[2] = vec2(-off[2], off[1]); V[3] = vec2(-off[2], -off[3]);
  }
  for (int k = 0; k < 4; ++k) Q[k] = V[k] / scale;
  return true;
}

void emitQuad(vec2 Q[4], uint index) {
  patchIndex = index; gl_Position = vec4(Q[0], 0.0, 1.0); EmitVertex();
  patchIndex = index; gl_Position = vec4(Q[1], 0.0, 1.0); EmitVertex();
  patchIndex = index; gl_Position = vec4(Q[3], 0.0, 1.0); EmitVertex();
  patchIndex = index; gl_Position = vec4(Q[2], 0.0, 1.0); EmitVertex();
  EndPrimitive();
}

bool useCylinder() { return frame.traceParams.y != 0.0; }

// The faces of the box {base + Σ u_k E_k : u ∈ [0,1]³} (E_k mutually orthogonal) that face
// the eye: together they cover exactly the box's projection (the tight primitive of
// Lindow et al. Sect. 5.2, Fig. 6, for a box around the patch), and the near plane clips
// what lies behind the eye. With the eye inside the box every pixel may see the patch.
void emitBox(vec3 base, vec3 E[3], uint index) {
  vec3 eye = frame.eyeProjection.xyz;
  int side[3];
  bool inside = !orthographic();
  for (int k = 0; k < 3; ++k) {
    if (orthographic()) {
      float f = dot(frame.forwardTan.xyz, E[k]);
      side[k] = f > 0.0 ? 0 : (f < 0.0 ? 1 : -1);
    } else {
      float u = dot(eye - base, E[k]) / dot(E[k], E[k]);
      side[k] = u < 0.0 ? 0 : (u > 1.0 ? 1 : -1);
      // A small band around the box counts as inside: a face seen almost edge-on from
      // within rounding of its plane could otherwise drop pixels.
      if (u < -1e-4 || u > 1.0 + 1e-4) inside = false;
    }
  }
  if (inside) {
    emitRect(vec2(-1.0), vec2(1.0), index);
    return;
  }
  for (int k = 0; k < 3; ++k) {
    if (side[k] < 0) continue;
    vec3 f0 = base + float(side[k]) * E[k], a = E[(k + 1) % 3], b = E[(k + 2) % 3];
    patchIndex = index; gl_Position = clipOf(f0); EmitVertex();
    patchIndex = index; gl_Position = clipOf(f0 + a); EmitVertex();
    patchIndex = index; gl_Position = clipOf(f0 + b); EmitVertex();
    patchIndex = index; gl_Position = clipOf(f0 + a + b); EmitVertex();
    EndPrimitive();
  }
}

// The cylinder's quad where it is available, else the box (eye inside or beside the cylinder).
void emitCylinderOrBox(vec3 base, vec3 axis, float h, float radius, vec3 boxBase, vec3 E[3], uint index) {
  vec2 Q[4];
  if (cylinderQuad(base, axis, h, radius, Q)) emitQuad(Q, index);
  else emitBox(boxBase, E, index);
}
)glsl";

constexpr const char* kFragmentCommon = R"glsl(
flat in uint patchIndex;
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

// view::shade: Blinn–Phong with the headlight at the eye (half vector = light direction).
vec3 shade(vec3 base, vec3 n, vec3 towardsEye) {
  float nl = max(0.0, dot(n, towardsEye));
  float spec = frame.lighting.z * pow(nl, frame.lighting.w);
  return min(base * (frame.lighting.x + frame.lighting.y * nl) + vec3(spec), vec3(1.0));
}

// Optional per-patch statistics (GlOptions::countFragments): fragments shaded, hits.
layout(std430, binding = 7) buffer FragmentCounts { uint fragmentCounts[]; };
void countFragment(uint patchId, uint what) {
  if (frame.traceParams.z != 0.0) atomicAdd(fragmentCounts[2u * patchId + what], 1u);
}

void writeHit(vec3 dir, float t, vec3 n, uint kind, uint patchId, uint atom) {
  countFragment(patchId, 1u);
  vec3 base = frame.idBase.w == 0u ? frame.kindColor[kind - 1u].rgb
              : (atom < frame.counts.x ? atomColors[atom].rgb : vec3(1.0, 0.0, 1.0));
  outColor = vec4(shade(base, n, -dir), 1.0);
  outDepth = vec2(t, t * dot(dir, frame.forwardTan.xyz));
  outNormal = vec4(n, 0.0);
  outIds = uvec4(kind, patchId, atom, 0u);
  // Linear in t: per pixel the same order as the ray distance, which is what occludes.
  gl_FragDepth = clamp(t * frame.viewport.w, 0.0, 1.0);
}
)glsl";

// ---------------------------------------------------------------------------------------
// Spheres: a screen-aligned rectangle around the exact projection (Sect. 5.2).

constexpr const char* kSphereGeometry = R"glsl(
layout(triangle_strip, max_vertices = 4) out;

// Image-plane extent (x/z) of a circle of radius r at (a, z) seen from the origin: the two
// tangent lines, the centre direction rotated by ±asin(r/|c|). Needs z > r.
vec2 tangentRange(float a, float z, float r) {
  float t = sqrt(a * a + z * z - r * r);
  float x1 = (a * t - z * r) / (z * t + a * r), x2 = (a * t + z * r) / (z * t - a * r);
  return vec2(min(x1, x2), max(x1, x2));
}

void main() {
  uint index = uint(gl_PrimitiveIDIn);
  vec4 s = spheres[index];
  vec3 c = viewOf(s.xyz);
  // A little wider than the sphere: float rounding must never cut off a pixel centre.
  float r = s.w * (1.0 + 1e-4);
  vec2 lo, hi;
  if (orthographic()) {
    vec2 scale = vec2(frame.upHalfHeight.w * frame.rightAspect.w, frame.upHalfHeight.w);
    lo = (c.xy - r) / scale;
    hi = (c.xy + r) / scale;
  } else if (c.z > r + frame.viewport.z) {
    float h = frame.forwardTan.w;
    vec2 rx = tangentRange(c.x, c.z, r) / (h * frame.rightAspect.w), ry = tangentRange(c.y, c.z, r) / h;
    lo = vec2(rx.x, ry.x);
    hi = vec2(rx.y, ry.y);
  } else {
    lo = vec2(-1.0);  // the sphere reaches the eye plane: any pixel may see it
    hi = vec2(1.0);
  }
  vec2 pixel = 2.0 / frame.viewport.xy;  // one pixel of slack on each side
  lo = max(lo - pixel, vec2(-1.0));
  hi = min(hi + pixel, vec2(1.0));
  if (lo.x < hi.x && lo.y < hi.y) emitRect(lo, hi, index);
}
)glsl";

constexpr const char* kSphereFragment = R"glsl(
void main() {
  countFragment(frame.idBase.x + patchIndex, 0u);
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
  writeHit(dir, t, n, 1u, frame.idBase.x + patchIndex, sphereAtoms[patchIndex]);
}
)glsl";

// ---------------------------------------------------------------------------------------
// Tori: the box of the saddle in its own frame (meridian box swept over the φ sector).

constexpr const char* kTorusGeometry = R"glsl(
layout(triangle_strip, max_vertices = 12) out;

float rhoMin, rhoMax, aMin, aMax;

// Meridian box of θ ∈ [lo, hi]: ρ = R − rp cos θ, a = rp sin θ (torus_patch.cpp bounds).
void addInterval(float lo, float hi, float R, float rp) {
  float cosMax = lo <= 0.0 && hi >= 0.0 ? 1.0 : max(cos(lo), cos(hi));
  float cosMin = min(cos(lo), cos(hi));
  rhoMin = min(rhoMin, max(0.0, R - rp * cosMax));
  rhoMax = max(rhoMax, max(0.0, R - rp * cosMin));
  aMin = min(aMin, rp * sin(lo));
  aMax = max(aMax, rp * sin(hi));
}

void main() {
  uint index = uint(gl_PrimitiveIDIn);
  Torus T = tori[index];
  vec3 c = T.centerR.xyz, ax = T.axisRp.xyz, e1 = T.e1Phi.xyz, e2 = cross(ax, e1);
  float R = T.centerR.w, rp = T.axisRp.w, thetaI = T.theta.x, thetaJ = T.theta.y;
  rhoMin = 1e30; rhoMax = 0.0; aMin = 1e30; aMax = -1e30;
  if (R >= rp) {
    addInterval(thetaI, thetaJ, R, rp);
  } else {
    // Spindle: only |θ| >= θc is on the SES (ORACLES A.3), up to two intervals.
    float thetaC = acos(R / rp);
    if (thetaI <= -thetaC) addInterval(thetaI, min(thetaJ, -thetaC), R, rp);
    if (thetaJ >= thetaC) addInterval(max(thetaI, thetaC), thetaJ, R, rp);
    if (!(aMin <= aMax)) return;  // the θ range misses the SES sheet: nothing to draw
  }
  // The φ sector [0, Δφ] as ψ ∈ [−β, β] about its mid direction em: x' = ρ cos ψ,
  // y' = ρ sin ψ; this box is tight for every sector width.
  float beta = 0.5 * min(T.e1Phi.w, kTwoPi);
  vec3 em = cos(beta) * e1 + sin(beta) * e2, en = -sin(beta) * e1 + cos(beta) * e2;
  float xMax = rhoMax, xMin = beta <= kHalfPi ? rhoMin * cos(beta) : rhoMax * cos(beta);
  float yMax = rhoMax * (beta <= kHalfPi ? sin(beta) : 1.0);
  // Float rounding of the frame and of cos/sin: widen by 1e-3 of the torus.
  float pad = 1e-3 * (R + rp);
  vec3 base = c + (xMin - pad) * em - (yMax + pad) * en + (aMin - pad) * ax;
  vec3 E[3] = vec3[3]((xMax - xMin + 2.0 * pad) * em, (2.0 * yMax + 2.0 * pad) * en, (aMax - aMin + 2.0 * pad) * ax);
  // The cylinder of the torus axis around the saddle's ρ <= ρmax, a ∈ [aMin, aMax].
  if (useCylinder()) emitCylinderOrBox(c + (aMin - pad) * ax, ax, aMax - aMin + 2.0 * pad, rhoMax + pad, base, E, index);
  else emitBox(base, E, index);
}
)glsl";

constexpr const char* kTorusFragment = R"glsl(
const int kRootIterations = 40;   // bracketed Newton: bisection alone needs 24 in float
const int kPolishSteps = 2;       // Newton steps on the own tube after the quartic
const float kPolishRadius = 1e-3; // their trust region (normalised units)
const float kSpherePad = 1e-5;    // widening of the patch's bounding sphere (float rounding)

float S, invS, Rn, rn;  // the torus in units of S = R + rp (ORACLES B.1)

float poly(float c[5], int n, float x) {
  float v = c[n];
  for (int k = n - 1; k >= 0; --k) v = v * x + c[k];
  return v;
}

float signOf(float v) { return v > 0.0 ? 1.0 : (v < 0.0 ? -1.0 : 0.0); }

// The root of c (degree n) in [a, b], where it changes sign: Newton kept inside the
// bracket, bisecting whenever it leaves it (STYLE §3.4).
float bracketedRoot(float c[5], int n, float a, float b, float fa) {
  float dc[5] = float[5](0.0, 0.0, 0.0, 0.0, 0.0);
  for (int k = 0; k < n; ++k) dc[k] = float(k + 1) * c[k + 1];
  float x = 0.5 * (a + b);
  for (int it = 0; it < kRootIterations; ++it) {
    float f = poly(c, n, x);
    if (f == 0.0) return x;
    if (signOf(f) == signOf(fa)) a = x; else b = x;
    float df = poly(dc, n - 1, x);
    float next = df != 0.0 ? x - f / df : 0.5 * (a + b);
    if (!(next > a && next < b)) next = 0.5 * (a + b);
    // Newton converges from one side, so the bracket need not shrink: stop on the step.
    if (abs(next - x) <= 2e-7 * max(1.0, abs(x)) || b - a <= 1e-7 * max(1.0, abs(x))) return next;
    x = next;
  }
  return x;
}

// Roots of c (degree n) in [lo, hi], ascending, given the ascending roots of its derivative:
// between consecutive critical points c is monotone, so each piece holds at most one root.
int rootsBetween(float c[5], int n, float lo, float hi, float crit[4], int m, out float roots[4]) {
  int count = 0;
  float a = lo, fa = poly(c, n, lo);
  if (fa == 0.0) roots[count++] = lo;
  for (int k = 0; k <= m && count < 4; ++k) {
    float b = k < m ? clamp(crit[k], lo, hi) : hi;
    float fb = poly(c, n, b);
    if (fb == 0.0) roots[count++] = b;
    else if (signOf(fa) * signOf(fb) < 0.0) roots[count++] = bracketedRoot(c, n, a, b, fa);
    a = b;
    fa = fb;
  }
  return count;
}

// All real roots of the monic quartic in [lo, hi] by recursive isolation on its derivatives
// (ORACLES B.4, method ii): no resolvent-cubic branches, every root bracketed.
int quarticRoots(float c[5], float lo, float hi, out float roots[4]) {
  float q3[5], q2[5];
  for (int k = 0; k < 5; ++k) q3[k] = k < 4 ? float(k + 1) * c[k + 1] : 0.0;
  for (int k = 0; k < 5; ++k) q2[k] = k < 4 ? float(k + 1) * q3[k + 1] : 0.0;
  // The quadratic q2 = 12 s² + 6 c3 s + 2 c2 in closed form (stable roots, ORACLES B.5);
  // its roots split the cubic's interval.
  float r2[4] = float[4](0.0, 0.0, 0.0, 0.0), r3[4];
  int n2 = 0;
  float A = q2[2], B = q2[1], Cq = q2[0], disc = B * B - 4.0 * A * Cq;
  if (disc > 0.0) {
    float qq = -0.5 * (B + (B >= 0.0 ? sqrt(disc) : -sqrt(disc)));
    float x1 = qq / A, x2 = qq != 0.0 ? Cq / qq : x1;
    float first = min(x1, x2), second = max(x1, x2);
    if (first > lo && first < hi) r2[n2++] = first;
    if (second > lo && second < hi) r2[n2++] = second;
  }
  int n3 = rootsBetween(q3, 3, lo, hi, r2, n2, r3);
  return rootsBetween(c, 4, lo, hi, r3, n3, roots);
}

// The saddle test of a point x on the torus (normalised local frame), as clipLocal in
// torus_patch.cpp: SES sheet of a spindle torus, θ limits, φ sector.
bool insidePatch(vec3 x, float rho, Torus T) {
  if (Rn < rn) {
    // |x|² = h² + 2ρR on the apple, h² − 2ρR on the lemon; the tolerance keeps the cusp.
    float h2 = (rn - Rn) * (rn + Rn);
    if (dot(x, x) < h2 - 2e-4 * Rn * rn) return false;
  }
  float theta = atan(x.z, Rn - rho);
  if (theta < T.theta.x || theta > T.theta.y) return false;
  if (T.e1Phi.w < kTwoPi) {
    float phi = atan(x.y, x.x);
    if (phi < 0.0) phi += kTwoPi;
    if (phi > T.e1Phi.w) return false;
  }
  return true;
}

// Newton on the signed tube distance D = |x − P| − rn, Lipschitz 1 with slope n·d, so it is
// as well conditioned as the geometry allows (the quartic's slope also carries F2).
float polishOnTube(vec3 o, vec3 d, float s, float lo, float hi) {
  for (int k = 0; k < kPolishSteps; ++k) {
    vec3 x = o + s * d;
    float rho = length(x.xy);
    if (!(rho > 0.0)) break;
    vec3 g = vec3((rho - Rn) / rho * x.xy, x.z);
    float len = length(g);
    float D = len - rn, slope = dot(g, d) / len;
    if (D == 0.0 || !(abs(slope) > 0.0)) break;
    float next = s - D / slope;
    if (!(next >= lo && next <= hi && abs(next - s) <= kPolishRadius)) break;
    vec3 y = o + next * d;
    float rhoY = length(y.xy);
    if (!(abs(length(vec2(rhoY - Rn, y.z)) - rn) < abs(D))) break;
    s = next;
  }
  return s;
}

bool castQuartic(vec3 o, vec3 d, Torus T, float lo, float hi, out float sHit) {
  // ORACLES B.2: the monic quartic (|x|² − R² − r²)² + 4R²(z² − r²) along o + s d.
  float R2 = Rn * Rn;
  float K = dot(o, o) - R2 - rn * rn, f = dot(o, d);
  float c[5] = float[5](K * K + 4.0 * R2 * (o.z * o.z - rn * rn), 4.0 * f * K + 8.0 * R2 * o.z * d.z,
                        2.0 * K + 4.0 * f * f + 4.0 * R2 * d.z * d.z, 4.0 * f, 1.0);
  float roots[4];
  int n = quarticRoots(c, lo, hi, roots);
  for (int k = 0; k < n; ++k) {
    float s = roots[k];
    vec3 x = o + s * d;
    float rho = length(x.xy);
    // B.4 step 2.1: a root nearer the lemon factor F2 is inside the probe, not SES.
    float zr = (x.z - rn) * (x.z + rn);
    float f1 = (rho - Rn) * (rho - Rn) + zr, f2 = (rho + Rn) * (rho + Rn) + zr;
    if (abs(f1) > abs(f2)) continue;
    s = polishOnTube(o, d, s, lo, hi);
    x = o + s * d;
    if (insidePatch(x, length(x.xy), T)) {
      sHit = s;
      return true;
    }
  }
  return false;
}

// Inside the tube, x lies in the probe ball B(P, rn) of its own meridian; the ball lies
// inside the tube, so no root of the tube comes before the ball's far side along the ray.
float probeBallExit(vec3 x, vec3 d, float rho, float s, float eps) {
  vec3 P = rho > 0.0 ? vec3(Rn * x.xy / rho, 0.0) : vec3(Rn, 0.0, 0.0);
  vec3 v = x - P;
  float b = dot(v, d), cc = dot(v, v) - rn * rn;
  return s + max(-b + sqrt(max(b * b - cc, 0.0)), eps);
}

// Sphere tracing (Lindow et al. 2010, Sect. 5.2, at most `maxSteps` steps for the whole
// ray): outside the tube, step by the distance to it; inside, jump to the far side of the
// probe ball. Both are the largest steps that cannot pass a root. A root outside the
// patch limits is stepped over and the march goes on. `plain` steps by |D| inside too:
// the textbook march, which crawls away from a rejected entry point (the saddle is
// usually the tube's exit root, seen from the probe's side).
bool sphereTrace(vec3 o, vec3 d, Torus T, float lo, float hi, float eps, int maxSteps, bool plain, out float sHit) {
  float s = lo;
  for (int step = 0; step < maxSteps && s <= hi; ++step) {
    vec3 x = o + s * d;
    float rho = length(x.xy);
    vec2 q = vec2(rho - Rn, x.z);
    float dist = length(q), D = dist - rn;
    if (abs(D) < eps) {
      if (insidePatch(x, rho, T)) {
        sHit = s;
        return true;
      }
      vec3 g = vec3(rho > 0.0 ? q.x * x.xy / rho : vec2(0.0), q.y) / max(dist, 1e-30);
      float cosine = dot(g, d);
      if (cosine < 0.0 && !plain) s = probeBallExit(x, d, rho, s, eps);  // entering: cross the ball
      else s += 2.0 * eps / max(abs(cosine), 0.05);                      // step off the surface
    } else if (D > 0.0 || plain) {
      s += max(abs(D), eps);
    } else {
      s = probeBallExit(x, d, rho, s, eps);
    }
  }
  return false;
}

void main() {
  countFragment(frame.idBase.y + patchIndex, 0u);
  Torus T = tori[patchIndex];
  vec3 org, dir;
  cameraRay(org, dir);
  vec3 c = T.centerR.xyz, ax = T.axisRp.xyz, e1 = T.e1Phi.xyz, e2 = cross(ax, e1);
  float R = T.centerR.w, rp = T.axisRp.w;
  S = R + rp;
  invS = 1.0 / S;
  Rn = R * invS;
  rn = rp * invS;
  // ORACLES B.1: shift the origin to the ray's closest approach to the centre and work in
  // units of S, so the roots are O(1) wherever the camera is.
  vec3 w = org - c;
  float tShift = -dot(w, dir);
  vec3 sh = (w + tShift * dir) * invS;
  // The saddle lies in |x|² <= R² + rp² (ρ <= R on it) and in the slab of its θ range.
  float sphere2 = (Rn * Rn + rn * rn) * (1.0 + kSpherePad);
  float o2 = dot(sh, sh);
  if (!(o2 <= sphere2)) discard;
  float halfChord = sqrt(sphere2 - o2);
  float lo = max(-halfChord, -tShift * invS), hi = halfChord;
  vec3 o = vec3(dot(sh, e1), dot(sh, e2), dot(sh, ax));
  vec3 d = normalize(vec3(dot(dir, e1), dot(dir, e2), dot(dir, ax)));
  float aLo = rn * sin(T.theta.x) - 1e-5, aHi = rn * sin(T.theta.y) + 1e-5;
  if (d.z != 0.0) {
    float s1 = (aLo - o.z) / d.z, s2 = (aHi - o.z) / d.z;
    lo = max(lo, min(s1, s2));
    hi = min(hi, max(s1, s2));
  } else if (o.z < aLo || o.z > aHi) {
    discard;
  }
  if (!(lo <= hi)) discard;
  float s;
  bool found = frame.counts.y == 0u
                   ? castQuartic(o, d, T, lo, hi, s)
                   : sphereTrace(o, d, T, lo, hi, frame.traceParams.x * invS, int(frame.counts.z), frame.counts.w != 0u, s);
  if (!found) discard;
  float t = s * S + tShift;
  if (!(t > 0.0)) discard;
  vec3 x = o + s * d;
  float rho = length(x.xy);
  // Outward SES normal (P − x)/rp (ORACLES A.3); at a cusp the average, ∓axis.
  vec3 nl = rho > 0.0 ? normalize(vec3(Rn * x.xy / rho, 0.0) - x) : vec3(0.0, 0.0, x.z >= 0.0 ? -1.0 : 1.0);
  vec3 n = normalize(nl.x * e1 + nl.y * e2 + nl.z * ax);
  // The atom whose contact circle is nearer along the axis (ScenePatches::atomOf).
  float a = x.z * S, aI = rp * sin(T.theta.x), aJ = rp * sin(T.theta.y);
  uvec2 atoms = torusAtoms[patchIndex];
  writeHit(dir, t, n, 2u, frame.idBase.y + patchIndex, a - aI <= aJ - a ? atoms.x : atoms.y);
}
)glsl";

// ---------------------------------------------------------------------------------------
// Concave triangles: the box of the spherical triangle in the frame of its mean direction.

constexpr const char* kConcaveGeometry = R"glsl(
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
  Concave C = concaves[index];
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
)glsl";

constexpr const char* kConcaveFragment = R"glsl(
layout(binding = 0) uniform samplerBuffer clipPlanes;  // n, w: keep n·x + w <= 0

void main() {
  countFragment(frame.idBase.z + patchIndex, 0u);
  Concave C = concaves[patchIndex];
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
  for (int side = 0; side < 2; ++side) {
    float t = side == 0 ? tNear : tFar;
    if (!(t > 0.0)) continue;
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
    writeHit(dir, t, normalize(-v), 3u, frame.idBase.z + patchIndex, atom);
    return;
  }
  discard;
}
)glsl";

}  // namespace

ProgramSources programSources(ProgramKind kind) {
  ProgramSources s;
  s.vertex = std::string(kHeader) + kVertex;
  const std::string geometry = std::string(kHeader) + kBuffers + kGeometryCommon;
  const std::string fragment = std::string(kHeader) + kBuffers + kFragmentCommon;
  switch (kind) {
    case ProgramKind::Sphere:
      s.geometry = geometry + kSphereGeometry;
      s.fragment = fragment + kSphereFragment;
      break;
    case ProgramKind::Torus:
      s.geometry = geometry + kTorusGeometry;
      s.fragment = fragment + kTorusFragment;
      break;
    case ProgramKind::Concave:
      s.geometry = geometry + kConcaveGeometry;
      s.fragment = fragment + kConcaveFragment;
      break;
  }
  return s;
}

}  // namespace surftrace::gl

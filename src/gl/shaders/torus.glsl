// Tori: the box of the saddle in its own frame (meridian box swept over the φ sector); the quartic or sphere tracing of torus_patch.cpp.
//
// One file per patch kind: its records and atoms (bound to kRecordBinding and kAtomBinding
// for its draw), its geometry stage (SURFTRACE_GEOMETRY_STAGE) and its fragment stage
// (SURFTRACE_FRAGMENT_STAGE). gl/gpu_kinds.hpp holds the kind's row.
layout(std430, binding = kRecordBinding) readonly buffer Tori { GpuTorus tori[]; };
layout(std430, binding = kAtomBinding) readonly buffer TorusAtoms { uvec2 torusAtoms[]; };  // atom i, atom j

#ifdef SURFTRACE_GEOMETRY_STAGE
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
  GpuTorus T = tori[index];
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
#endif

#ifdef SURFTRACE_FRAGMENT_STAGE
const int kRootIterations = 40;   // bracketed Newton: bisection alone needs 24 in float
const int kPolishSteps = 12;      // Newton–bisection steps on the own tube after the quartic
const float kPolishRadius = 0.05; // their reach from the quartic's root (normalised units)
const float kPolishTolerance = 2e-6; // |D| at a root of the tube (normalised; float D: ~1e-7)
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
bool insidePatch(vec3 x, float rho, GpuTorus T) {
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

// The signed tube distance D = |x − P| − rn at s and its slope n·d: Lipschitz 1, so it is as
// well conditioned as the geometry allows (the quartic's slope also carries F2).
float tubeDistance(vec3 o, vec3 d, float s, out float slope) {
  vec3 x = o + s * d;
  float rho = length(x.xy);
  vec3 g = vec3(rho > 0.0 ? (rho - Rn) / rho * x.xy : vec2(-Rn, 0.0), x.z);
  float len = length(g);
  slope = len > 0.0 ? dot(g, d) / len : 0.0;
  return len - rn;
}

// The root of D near the quartic's root s. The float quartic's coefficients carry errors of
// ~1e-7, and where its roots cluster (a ray nearly tangent to the tube, or passing near two of
// its sheets) its root can lie 0.003–0.03 (0.01–0.1 Å) off the tube: a layer there is one
// that Embree does not have, and the next pass, whose isolation starts beyond it, finds the
// same crossing again. Newton on D, safeguarded by bisection once a step has crossed the root
// (STYLE §3.4), within kPolishRadius of the quartic's root. False when D does not vanish
// there (to kPolishTolerance): the float quartic's root is none of the tube's (a near-double
// root that rounding made real).
bool polishOnTube(vec3 o, vec3 d, float lo, float hi, inout float s) {
  float slope, D = tubeDistance(o, d, s, slope);
  float s0 = s, a = s, b = s, Da = D;
  bool bracketed = false;
  for (int k = 0; k < kPolishSteps && D != 0.0; ++k) {
    float next = abs(slope) > 0.0 ? s - D / slope : s;
    if (bracketed && !(next > min(a, b) && next < max(a, b))) next = 0.5 * (a + b);
    if (!bracketed && !(next >= lo && next <= hi && abs(next - s0) <= kPolishRadius)) break;
    float slopeNext, Dnext = tubeDistance(o, d, next, slopeNext);
    if (!bracketed && signOf(Dnext) != signOf(D)) {
      bracketed = true;
      a = s;
      Da = D;
      b = next;
    } else if (bracketed) {
      if (signOf(Dnext) == signOf(Da)) a = next, Da = Dnext;
      else b = next;
    }
    // Float D is noisy at ~1e-7, so Newton's steps need not shrink below that: stop on D too.
    bool converged = abs(next - s) <= 1e-7 * max(1.0, abs(s)) || abs(Dnext) <= 0.1 * kPolishTolerance;
    s = next;
    D = Dnext;
    slope = slopeNext;
    if (converged) break;
  }
  return abs(D) <= kPolishTolerance;
}

// Peeling passes `after`, the s beyond which a root is the next layer (sAfter <= lo outside
// peeling): roots are isolated beyond it, but polished within [lo, hi], and a root that the
// polish brings back to `after` or before is the previous layer found again: near a double root
// the float quartic's root can lie 0.01–0.1 Å off, and a polish clamped at `after` would leave
// it there as a layer of its own.
bool castQuartic(vec3 o, vec3 d, GpuTorus T, float lo, float hi, bool peeling, float after, out float sHit) {
  // ORACLES B.2: the monic quartic (|x|² − R² − r²)² + 4R²(z² − r²) along o + s d.
  float R2 = Rn * Rn;
  float K = dot(o, o) - R2 - rn * rn, f = dot(o, d);
  float c[5] = float[5](K * K + 4.0 * R2 * (o.z * o.z - rn * rn), 4.0 * f * K + 8.0 * R2 * o.z * d.z,
                        2.0 * K + 4.0 * f * f + 4.0 * R2 * d.z * d.z, 4.0 * f, 1.0);
  float roots[4];
  int n = quarticRoots(c, peeling ? max(lo, after) : lo, hi, roots);
  for (int k = 0; k < n; ++k) {
    float s = roots[k];
    vec3 x = o + s * d;
    float rho = length(x.xy);
    // B.4 step 2.1: a root nearer the lemon factor F2 is inside the probe, not SES.
    float zr = (x.z - rn) * (x.z + rn);
    float f1 = (rho - Rn) * (rho - Rn) + zr, f2 = (rho + Rn) * (rho + Rn) + zr;
    if (abs(f1) > abs(f2)) continue;
    if (!polishOnTube(o, d, lo, hi, s)) continue;
    if (peeling && !(s > after)) continue;
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
bool sphereTrace(vec3 o, vec3 d, GpuTorus T, float lo, float hi, float eps, int maxSteps, bool plain, out float sHit) {
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
  countFragment(globalId(kToroidalKind, patchIndex), 0u);
  GpuTorus T = tori[patchIndex];
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
  // Peeling: the roots beyond the previous layer by the merge distance (peelAfter()).
  float after = peelAfter();
  bool peeling = peel.flags.x != 0u;
  float sAfter = (after - tShift) * invS;
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
  bool found = frame.torusTrace.x == 0u
                   ? castQuartic(o, d, T, lo, hi, peeling, sAfter, s)
                   : sphereTrace(o, d, T, peeling ? max(lo, sAfter) : lo, hi, frame.traceParams.x * invS, int(frame.torusTrace.y), frame.torusTrace.z != 0u, s);
  if (!found) discard;
  float t = s * S + tShift;
  if (!(t > after)) discard;
  vec3 x = o + s * d;
  float rho = length(x.xy);
  // Outward SES normal (P − x)/rp (ORACLES A.3); at a cusp the average, ∓axis.
  vec3 nl = rho > 0.0 ? normalize(vec3(Rn * x.xy / rho, 0.0) - x) : vec3(0.0, 0.0, x.z >= 0.0 ? -1.0 : 1.0);
  vec3 n = normalize(nl.x * e1 + nl.y * e2 + nl.z * ax);
  // The atom whose contact circle is nearer along the axis (ScenePatches::atomOf).
  float a = x.z * S, aI = rp * sin(T.theta.x), aJ = rp * sin(T.theta.y);
  uvec2 atoms = torusAtoms[patchIndex];
  writeHit(dir, t, n, kToroidalKind, globalId(kToroidalKind, patchIndex), a - aI <= aJ - a ? atoms.x : atoms.y);
}
#endif

// Geometry-stage helpers: view coordinates, the rasterisation primitives (Lindow et al. 2010, Sect. 5.2).

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

// Image-plane extent (x/z) of a circle of radius r at (a, z) seen from the origin: the two
// tangent lines, the centre direction rotated by ±asin(r/|c|). Needs z > r.
vec2 tangentRange(float a, float z, float r) {
  float t = sqrt(a * a + z * z - r * r);
  float x1 = (a * t - z * r) / (z * t + a * r), x2 = (a * t + z * r) / (z * t - a * r);
  return vec2(min(x1, x2), max(x1, x2));
}

// A screen-aligned rectangle around the exact projection of the sphere (centre, radius)
// (Lindow et al. 2010, Sect. 5.2), a pixel wider on each side; the whole image where the
// sphere reaches the eye plane.
void emitSphereRect(vec3 centre, float radius, uint index) {
  vec3 c = viewOf(centre);
  // A little wider than the sphere: float rounding must never cut off a pixel centre.
  float r = radius * (1.0 + 1e-4);
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

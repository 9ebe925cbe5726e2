// Molecular skin: the screen rectangle of the patch's bounding ball; the quadric hit inside the mixed cell of mss_patch.cpp (ORACLES B.5, C.3, C.4).
//
// One file for the four MSS kinds (their rows in gl/gpu_kinds.hpp share it; the record says
// which kind it is): its records and atoms (bound to kRecordBinding and kAtomBinding for its
// draw), its geometry stage (SURFTRACE_GEOMETRY_STAGE) and its fragment stage
// (SURFTRACE_FRAGMENT_STAGE).
layout(std430, binding = kRecordBinding) readonly buffer Skins { GpuSkin skins[]; };
layout(std430, binding = kAtomBinding) readonly buffer SkinAtoms { uvec4 skinAtoms[]; };  // the simplex
// The skin's atoms and the grid over them (gl::GpuPatches::skinAtoms, skinGrid).
layout(std430, binding = kSkinAtomBinding) readonly buffer SkinBalls {
  uvec4 skinGrid;       // atom count (0: the list has none), cells along x, y, z
  vec4 skinGridCorner;  // the grid's corner (origin-shifted), cell edge
  vec4 skinGridReach;   // the largest vdW radius, unused
  vec4 skinBalls[];     // per atom: centre (origin-shifted), r²
};
layout(std430, binding = kSkinGridBinding) readonly buffer SkinGridCells { uint skinGridCells[]; };

#ifdef SURFTRACE_GEOMETRY_STAGE
layout(triangle_strip, max_vertices = 12) out;

void main() {
  uint index = uint(gl_PrimitiveIDIn);
  GpuSkin P = skins[index];
  vec3 c = P.centerBound.xyz, a = P.axisConstant.xyz;
  float hLo = P.coefficients.z, hHi = P.coefficients.w, rho = uintBitsToFloat(P.cell.w);
  if (!(hLo < hHi)) return;
  if (P.coefficients.y == 0.0) {
    // A sphere (convex or concave): radius² = −constant/radial, its screen rectangle.
    emitSphereRect(c, sqrt(max(0.0, -P.axisConstant.w / P.coefficients.x)), index);
    return;
  }
  // A hyperboloid: the box along its axis, eye-facing faces.
  vec3 e1 = normalize(abs(a.x) < 0.9 ? cross(a, vec3(1.0, 0.0, 0.0)) : cross(a, vec3(0.0, 1.0, 0.0)));
  vec3 e2 = cross(a, e1);
  vec3 E[3] = vec3[3]((hHi - hLo) * a, 2.0 * rho * e1, 2.0 * rho * e2);
  emitBox(c + hLo * a - rho * e1 - rho * e2, E, index);
}
#endif

#ifdef SURFTRACE_FRAGMENT_STAGE
layout(binding = kClipPlaneUnit) uniform samplerBuffer clipPlanes;  // n, w: keep n·x + w <= 0

// The atom whose ball owns the skin point x (origin-shifted), as trace/mss_patch.cpp skinOwner:
// of all atoms the least |x − c_i|² − r_i², the lower index on a tie, searched within the
// bound the simplex's atoms give (|x − c_j| <= r_j + √π); the simplex's lowest atom when the
// list has no atoms.
float skinPower(uint i, vec3 x) {
  vec3 d = x - skinBalls[i].xyz;
  return dot(d, d) - skinBalls[i].w;
}

uint skinOwner(uvec4 atoms, vec3 x) {
  uint best = atoms.x;
  float least = uintBitsToFloat(0x7f800000u);  // +inf
  for (int k = 0; k < 4 && atoms[k] != 0xffffffffu; ++k) {
    if (atoms[k] >= skinGrid.x) return atoms.x;
    float p = skinPower(atoms[k], x);
    if (p < least) {
      least = p;
      best = atoms[k];
    }
  }
  // The cells that may hold such an atom (a millimetre-ångström more for the float binning).
  float reach = sqrt(max(least, 0.0)) + skinGridReach.x + 1e-3;
  ivec3 dims = ivec3(skinGrid.yzw);
  vec3 corner = skinGridCorner.xyz;
  float edge = skinGridCorner.w;
  ivec3 lo = clamp(ivec3(floor((x - reach - corner) / edge)), ivec3(0), dims - 1);
  ivec3 hi = clamp(ivec3(floor((x + reach - corner) / edge)), ivec3(0), dims - 1);
  uint cells = uint(dims.x * dims.y * dims.z);
  for (int cz = lo.z; cz <= hi.z; ++cz) {
    for (int cy = lo.y; cy <= hi.y; ++cy) {
      for (int cx = lo.x; cx <= hi.x; ++cx) {
        uint cell = uint((cz * dims.y + cy) * dims.x + cx);
        for (uint e = skinGridCells[cell]; e < skinGridCells[cell + 1u]; ++e) {
          uint j = skinGridCells[cells + 1u + e];
          float p = skinPower(j, x);
          if (p < least || (p == least && j < best)) {
            least = p;
            best = j;
          }
        }
      }
    }
  }
  return best;
}

void main() {
  GpuSkin P = skins[patchIndex];
  uint kind = P.cell.x;
  countFragment(globalId(kind, patchIndex), 0u);
  vec3 org, dir;
  cameraRay(org, dir);
  vec3 c = P.centerBound.xyz, a = P.axisConstant.xyz;
  float R = P.centerBound.w, radial = P.coefficients.x, axial = P.coefficients.y, constant = P.axisConstant.w;
  // The ray from its closest approach to the centre (t = t0 + u): |o| <= R where it matters.
  vec3 oc = org - c;
  float t0 = -dot(oc, dir);
  vec3 o = oc + t0 * dir;
  if (dot(o, o) > R * R * 1.0001) discard;
  float da = dot(dir, a), oa = dot(o, a);
  float A = radial + axial * da * da;
  float B = radial * dot(o, dir) + axial * oa * da;
  float C = radial * dot(o, o) + axial * oa * oa + constant;
  float u[2];
  int count = 0;
  if (abs(A) <= 1e-6 * (abs(radial) + abs(axial))) {
    if (B != 0.0) u[count++] = -C / (2.0 * B);  // along an asymptote: f linear in u
  } else {
    float disc = B * B - A * C;
    if (disc < 0.0) discard;
    float q = -(B + (B >= 0.0 ? sqrt(disc) : -sqrt(disc)));
    if (q == 0.0) {
      u[count++] = 0.0;
    } else {
      u[count++] = min(q / A, C / q);
      u[count++] = max(q / A, C / q);
    }
  }
  // Accept roots a hair outside the cell: the skin is C¹ across cell facets (ORACLES C.4).
  float slack = 1e-5 * (R + length(c));
  int begin = int(P.cell.y), planes = int(P.cell.z);
  // Beyond peelAfter(): 0 outside peeling, the previous layer's t plus the merge distance.
  float after = peelAfter();
  for (int k = 0; k < count; ++k) {
    float t = t0 + u[k];
    if (!(t > after)) continue;
    vec3 x = o + u[k] * dir;  // relative to the centre
    if (dot(x, x) > R * R * 1.0002) continue;
    bool kept = true;
    for (int m = 0; m < planes; ++m) {
      vec4 plane = texelFetch(clipPlanes, begin + m);
      if (dot(plane.xyz, x + c) + plane.w > slack) {
        kept = false;
        break;
      }
    }
    if (!kept) continue;
    vec3 g = radial * x + (axial * dot(x, a)) * a;
    vec3 n = dot(g, g) > 0.0 ? normalize(g) : -dir;  // a cone's apex: any normal
    writeHit(dir, t, n, kind, globalId(kind, patchIndex), skinOwner(skinAtoms[patchIndex], x + c));
    return;
  }
  discard;
}
#endif

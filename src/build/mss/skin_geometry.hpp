// The geometry of the molecular skin (Edelsbrunner 1999; ORACLES C.1-C.4) as pure functions of
// the weighted points: orthocentres of Delaunay simplices, the planes between neighbouring mixed
// cells, and the skin quadric of each cell.
//
// Every function takes a simplex's atoms in ascending order and computes from them alone, so the
// two mixed cells on either side of a facet compute that facet's plane with the same arithmetic
// in the same order: the cells of a patch list tile space without gaps or overlaps bit for bit.
#pragma once

#include <array>
#include <cmath>
#include <cstdint>
#include <span>
#include <stdexcept>

#include <glm/geometric.hpp>
#include <glm/vec3.hpp>
#include <glm/vec4.hpp>

namespace surftrace::build::mss {

// The skin's weighted points: z_i = c_i and w_i = r_i²/s (ORACLES C.1), w kept as the double
// fl(fl(r²)/s). Every predicate and every patch is a function of these doubles exactly.
struct WeightedPoints {
  std::span<const glm::dvec3> z;
  std::span<const double> w;
  double s = 0.5;
};

// The weight of an atom of radius r at shrink factor s, w = fl(fl(r²)/s): the one expression the
// builder and the patch-list file (which derives the skin's patches from these weights) share.
inline double skinWeight(double r, double s) { return r * r / s; }

// A Delaunay simplex: 1 to 4 atoms, ascending.
struct Simplex {
  std::array<std::uint32_t, 4> atom{};
  int size = 0;

  std::uint32_t operator[](int k) const { return atom[k]; }
  // This simplex with atom a added, kept ascending.
  Simplex with(std::uint32_t a) const {
    Simplex out;
    out.size = size + 1;
    int o = 0;
    bool placed = false;
    for (int k = 0; k < size; ++k) {
      if (!placed && a < atom[k]) {
        out.atom[o++] = a;
        placed = true;
      }
      out.atom[o++] = atom[k];
    }
    if (!placed) out.atom[o] = a;
    return out;
  }
  // This simplex without its k-th atom.
  Simplex without(int k) const {
    Simplex out;
    out.size = size - 1;
    for (int m = 0, o = 0; m < size; ++m)
      if (m != k) out.atom[o++] = atom[m];
    return out;
  }
};

// The orthocentre z_X (the point of aff(X) with equal power to every ball of X) and the
// orthosphere weight w_X = π_i(z_X) (ORACLES C.2). Computed relative to the lowest atom.
struct Orthocentre {
  glm::dvec3 z;
  double w;
};

// A simplex is too flat for the double formulas below when its determinant is below
// kFlatSimplex of the product of the lengths it is computed from (a tetrahedron's volume
// against its three edges; a triangle's squared area against its squared edges; a facet
// direction against the offset it is the part of): the double result then carries a relative
// error up to about u/kFlatSimplex ~ 1e-10, and below it the exact versions answer. Such
// simplices are the slivers of nearly co-spherical atoms: four atoms of a square moved by ±δ
// make a tetrahedron of volume ~δ² whose orthocentre stays at a finite place, while in double
// its determinant (~1e-21 at δ = 1e-11, rounding ~1e-15) has no correct digit, so its
// orthocentre and the side of its fourth atom were noise and the mixed cells next to it lost
// their planes (issue 18). The test reads the simplex's atoms alone, so every cell that
// computes a facet's plane takes the same branch and gets the same bits.
inline constexpr double kFlatSimplex = 1e-6;

// The orthocentre and the unnormalised direction of facetNormal in rational arithmetic from
// the input doubles, rounded once (skin_geometry.cpp). The builder never makes a simplex of
// dependent points; for one (from a damaged file) they throw std::invalid_argument.
Orthocentre exactOrthocentre(const WeightedPoints& p, const Simplex& x);
glm::dvec3 exactFacetDirection(const WeightedPoints& p, const Simplex& x, std::uint32_t a);

inline Orthocentre orthocentre(const WeightedPoints& p, const Simplex& x) {
  const glm::dvec3 z0 = p.z[x[0]];
  const double w0 = p.w[x[0]];
  if (x.size == 1) return {z0, -w0};
  // 2 e_k·y = |e_k|² − w_k + w_0 for y = z_X − z_0 in span(e_k), e_k = z_k − z_0.
  std::array<glm::dvec3, 3> e;
  std::array<double, 3> b;
  for (int k = 1; k < x.size; ++k) {
    e[k - 1] = p.z[x[k]] - z0;
    b[k - 1] = 0.5 * (glm::dot(e[k - 1], e[k - 1]) - p.w[x[k]] + w0);
  }
  glm::dvec3 y;
  if (x.size == 2) {
    y = e[0] * (b[0] / glm::dot(e[0], e[0]));
  } else if (x.size == 3) {
    // y = c0 e0 + c1 e1 with the 2×2 Gram system.
    const double g00 = glm::dot(e[0], e[0]), g01 = glm::dot(e[0], e[1]), g11 = glm::dot(e[1], e[1]);
    const double det = g00 * g11 - g01 * g01;
    if (!(det > kFlatSimplex * g00 * g11)) return exactOrthocentre(p, x);
    const double c0 = (b[0] * g11 - b[1] * g01) / det;
    const double c1 = (g00 * b[1] - g01 * b[0]) / det;
    y = c0 * e[0] + c1 * e[1];
  } else {
    // e_k·y = b_k: Cramer with the rows e_0, e_1, e_2.
    const glm::dvec3 c12 = glm::cross(e[1], e[2]), c20 = glm::cross(e[2], e[0]), c01 = glm::cross(e[0], e[1]);
    const double det = glm::dot(e[0], c12);
    const double volumeScale = glm::length(e[0]) * glm::length(e[1]) * glm::length(e[2]);
    if (!(std::abs(det) > kFlatSimplex * volumeScale)) return exactOrthocentre(p, x);
    y = (b[0] * c12 + b[1] * c20 + b[2] * c01) / det;
  }
  return {z0 + y, glm::dot(y, y) - w0};
}

// The unit normal of the facet between the mixed cells of X and X ∪ {a}: the part of
// z_a − z_{X[0]} orthogonal to aff(X), pointing from μ_X into μ_{X∪{a}} (ORACLES C.4).
// The double formula is trusted when the part of z_a − z_{X[0]} orthogonal to aff(X) is not
// below kFlatSimplex of the lengths it is computed from (the simplex X ∪ {a} is not flat), and
// for a triangle when the triangle itself is not.
inline glm::dvec3 facetNormal(const WeightedPoints& p, const Simplex& x, std::uint32_t a) {
  const glm::dvec3 z0 = p.z[x[0]];
  const glm::dvec3 d = p.z[a] - z0;
  glm::dvec3 v = d;
  if (x.size == 2) {
    const glm::dvec3 e = p.z[x[1]] - z0;
    v -= e * (glm::dot(v, e) / glm::dot(e, e));
    if (!(glm::dot(v, v) > kFlatSimplex * kFlatSimplex * glm::dot(d, d))) v = exactFacetDirection(p, x, a);
  } else if (x.size == 3) {
    const glm::dvec3 e1 = p.z[x[1]] - z0, e2 = p.z[x[2]] - z0;
    const glm::dvec3 n = glm::cross(e1, e2);
    const double nn = glm::dot(n, n), vn = glm::dot(v, n);
    if (nn > kFlatSimplex * kFlatSimplex * glm::dot(e1, e1) * glm::dot(e2, e2) &&
        std::abs(vn) > kFlatSimplex * std::sqrt(glm::dot(d, d) * nn))
      v = n * (vn / nn);
    else
      v = exactFacetDirection(p, x, a);
  }
  return glm::normalize(v);
}

// The plane n·x + d <= 0 of μ_X's side of its facet with μ_{X∪{a}}: normal facetNormal(X, a),
// through (1 − s) z_{X[0]} + s z_{X∪{a}}. The cell of X ∪ {a} uses the same plane negated.
// zY is orthocentre(X ∪ {a}).z, passed in by callers that have it (the same bits either way).
inline glm::dvec4 facetPlane(const WeightedPoints& p, const Simplex& x, std::uint32_t a, const glm::dvec3& zY) {
  const glm::dvec3 n = facetNormal(p, x, a);
  const glm::dvec3 point = (1.0 - p.s) * p.z[x[0]] + p.s * zY;
  return {n, -glm::dot(n, point)};
}

inline glm::dvec4 facetPlane(const WeightedPoints& p, const Simplex& x, std::uint32_t a) {
  return facetPlane(p, x, a, orthocentre(p, x.with(a)).z);
}

// The skin in μ_X as f(x) = radial·|x − z|² + axial·((x − z)·axis)² + constant, f < 0 inside
// the body, and f = (1 − s)·G(x) for the skin function G of ORACLES D.3 (CGAL's value):
//   vertex   (1 − s)|d|²              − s(1 − s) w_i   sphere of radius r_i
//   edge     (1 − s)|d|² − (d·t)²     + s(1 − s) w_X   hyperboloid about the edge t
//   triangle −s|d|²      + (d·m)²     + s(1 − s) w_X   hyperboloid about the normal m
//   tetra    −s|d|²                   + s(1 − s) w_X   concave sphere, radius √((1 − s) w_X)
struct SkinQuadric {
  glm::dvec3 center;
  glm::dvec3 axis;  // unit; (0, 0, 1) for the spheres, whose axial coefficient is 0
  double radial, axial, constant;
  double weight;    // w_X
};

inline SkinQuadric skinQuadric(const WeightedPoints& p, const Simplex& x, const Orthocentre& o) {
  const double s = p.s;
  SkinQuadric q{o.z, glm::dvec3(0, 0, 1), 0, 0, s * (1.0 - s) * o.w, o.w};
  switch (x.size) {
    case 1: q.radial = 1.0 - s; break;
    case 2:
      q.axis = glm::normalize(p.z[x[1]] - p.z[x[0]]);
      q.radial = 1.0 - s;
      q.axial = -1.0;
      break;
    case 3:
      q.axis = glm::normalize(glm::cross(p.z[x[1]] - p.z[x[0]], p.z[x[2]] - p.z[x[0]]));
      q.radial = -s;
      q.axial = 1.0;
      break;
    default: q.radial = -s; break;
  }
  return q;
}

// Radius of a ball about z_X that holds every skin point of μ_X:
// |x − z_X|² <= (1 − s) W + (1 − 2s) w_X with W = max_{a∈X} w_a (from y ∈ δ_X and the
// quadric; equals r_i for a vertex and √((1 − s) w_X) for a tetrahedron when it is tight).
inline double skinBoundRadius(const WeightedPoints& p, const Simplex& x, double wX) {
  double wMax = p.w[x[0]];
  for (int k = 1; k < x.size; ++k) wMax = std::max(wMax, p.w[x[k]]);
  return std::sqrt(std::max(0.0, (1.0 - p.s) * wMax + (1.0 - 2.0 * p.s) * wX));
}

// What the builder stores of the patch of simplex X: its quadric and its bounding radius. The
// patch-list file derives them again with this same function, so they come back bit for bit.
struct SkinPatch {
  SkinQuadric quadric;
  double boundRadius;
};
inline SkinPatch skinPatch(const WeightedPoints& p, const Simplex& x) {
  const SkinQuadric q = skinQuadric(p, x, orthocentre(p, x));
  return {q, skinBoundRadius(p, x, q.weight)};
}

// The plane of μ_X's cell (centre zX = z_X) across from the cell of X ∖ {a} when a ∈ X (that
// facet's plane negated; X has 2 atoms or more), or of X ∪ {a} when a ∉ X (X has 3 atoms or
// fewer). The builder's planes and the file's derived planes are both this function.
inline glm::dvec4 cellPlane(const WeightedPoints& p, const Simplex& x, const glm::dvec3& zX, std::uint32_t a) {
  for (int k = 0; k < x.size; ++k)
    if (x[k] == a) return -facetPlane(p, x.without(k), a, zX);
  return facetPlane(p, x, a);
}

}  // namespace surftrace::build::mss

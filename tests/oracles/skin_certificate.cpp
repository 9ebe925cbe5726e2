// KKT certificate of the skin QP on a given support (see skin_certificate.hpp), in long double.
#include "oracles/skin_certificate.hpp"

#include <algorithm>
#include <cmath>
#include <limits>

namespace surftrace::oracle {
namespace {

using Real = long double;

struct V3 {
  Real x, y, z;
};
V3 sub(const glm::dvec3& a, const glm::dvec3& b) {
  return {static_cast<Real>(a.x) - b.x, static_cast<Real>(a.y) - b.y, static_cast<Real>(a.z) - b.z};
}
Real dot(const V3& a, const V3& b) { return a.x * b.x + a.y * b.y + a.z * b.z; }

// Gaussian elimination with partial pivoting on an n×n system (n <= 5).
bool solve(int n, Real (&a)[5][5], Real (&b)[5], Real (&x)[5]) {
  for (int c = 0; c < n; ++c) {
    int p = c;
    for (int r = c + 1; r < n; ++r)
      if (std::abs(a[r][c]) > std::abs(a[p][c])) p = r;
    if (a[p][c] == 0) return false;
    for (int k = 0; k < n; ++k) std::swap(a[c][k], a[p][k]);
    std::swap(b[c], b[p]);
    for (int r = 0; r < n; ++r) {
      if (r == c) continue;
      const Real f = a[r][c] / a[c][c];
      for (int k = 0; k < n; ++k) a[r][k] -= f * a[c][k];
      b[r] -= f * b[c];
    }
  }
  for (int c = 0; c < n; ++c) x[c] = b[c] / a[c][c];
  return true;
}

}  // namespace

SkinCertificate certifySkinPoint(std::span<const glm::dvec3> centers, std::span<const double> radii, double s,
                                 std::span<const unsigned> simplex, const glm::dvec3& x) {
  SkinCertificate out;
  const int n = static_cast<int>(simplex.size());
  const Real S = s;
  auto weight = [&](unsigned i) { return static_cast<Real>(radii[i]) * radii[i] / S; };
  // Stationarity on X: 2(1 − s) Σ_b λ_b y_a·y_b + s π_a = ν for a ∈ X, Σ λ = 1.
  Real a[5][5] = {}, b[5] = {}, l[5] = {};
  Real scale = 0;
  for (int i = 0; i < n; ++i) {
    const V3 yi = sub(centers[simplex[i]], x);
    for (int j = 0; j < n; ++j) a[i][j] = 2 * (1 - S) * dot(yi, sub(centers[simplex[j]], x));
    a[i][n] = -1;
    b[i] = -S * (dot(yi, yi) - weight(simplex[i]));
    a[n][i] = 1;
    scale = std::max(scale, weight(simplex[i]));
  }
  b[n] = 1;
  out.scale = static_cast<double>(scale);
  if (!solve(n + 1, a, b, l)) return out;
  out.solved = true;
  V3 yl{0, 0, 0};
  Real value = 0, minLambda = std::numeric_limits<Real>::infinity();
  for (int i = 0; i < n; ++i) {
    const V3 yi = sub(centers[simplex[i]], x);
    yl = {yl.x + l[i] * yi.x, yl.y + l[i] * yi.y, yl.z + l[i] * yi.z};
    value += l[i] * S * (dot(yi, yi) - weight(simplex[i]));
    minLambda = std::min(minLambda, l[i]);
  }
  value += (1 - S) * dot(yl, yl);
  const Real nu = l[n];
  Real minGap = std::numeric_limits<Real>::infinity();
  for (std::size_t j = 0; j < centers.size(); ++j) {
    const V3 yj = sub(centers[j], x);
    minGap = std::min(minGap, 2 * (1 - S) * dot(yj, yl) + S * (dot(yj, yj) - weight(static_cast<unsigned>(j))) - nu);
  }
  out.value = static_cast<double>(value);
  out.minLambda = static_cast<double>(minLambda);
  out.minGap = static_cast<double>(minGap);
  return out;
}

}  // namespace surftrace::oracle

// KKT certificate of the skin QP on a given support (see skin_certificate.hpp), in long double.
#include "oracles/skin_certificate.hpp"

#include <algorithm>
#include <utility>
#include <vector>
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

int skinSign(std::span<const glm::dvec3> centers, std::span<const double> radii, double s, const glm::dvec3& x) {
  const std::size_t n = centers.size();
  const Real S = s;
  // key_i = |y_i|² − r_i²: negative inside atom i's ball (then G <= F(e_i) = key_i < 0).
  // π_i = |y_i|² − r_i²/s: all positive means outside every grown ball (G >= s min π > 0).
  std::vector<std::pair<Real, unsigned>> order(n);
  bool outsideAllGrown = true;
  for (std::size_t i = 0; i < n; ++i) {
    const V3 y = sub(centers[i], x);
    const Real yy = dot(y, y), rr = static_cast<Real>(radii[i]) * radii[i];
    if (yy < rr) return -1;
    if (yy - rr / S <= 0) outsideAllGrown = false;
    order[i] = {yy - rr, static_cast<unsigned>(i)};
  }
  if (outsideAllGrown) return 1;
  std::sort(order.begin(), order.end());
  auto weight = [&](unsigned i) { return static_cast<Real>(radii[i]) * radii[i] / S; };
  for (std::size_t K = std::min<std::size_t>(8, n);; K = std::min(n, 2 * K)) {
    // The best KKT point over supports of 1..4 of the K nearest.
    Real best = std::numeric_limits<Real>::infinity();
    Real bestL[4] = {};
    unsigned bestS[4] = {};
    int bestN = 0;
    unsigned sup[4];
    auto consider = [&](int m) {
      Real a[5][5] = {}, b[5] = {}, l[5] = {};
      for (int i = 0; i < m; ++i) {
        const V3 yi = sub(centers[sup[i]], x);
        for (int j = 0; j < m; ++j) a[i][j] = 2 * (1 - S) * dot(yi, sub(centers[sup[j]], x));
        a[i][m] = -1;
        b[i] = -S * (dot(yi, yi) - weight(sup[i]));
        a[m][i] = 1;
      }
      b[m] = 1;
      if (!solve(m + 1, a, b, l)) return;
      V3 yl{0, 0, 0};
      Real value = 0;
      for (int i = 0; i < m; ++i) {
        if (l[i] < 0) return;
        const V3 yi = sub(centers[sup[i]], x);
        yl = {yl.x + l[i] * yi.x, yl.y + l[i] * yi.y, yl.z + l[i] * yi.z};
        value += l[i] * S * (dot(yi, yi) - weight(sup[i]));
      }
      value += (1 - S) * dot(yl, yl);
      if (value < best) {
        best = value;
        bestN = m;
        for (int i = 0; i < m; ++i) bestL[i] = l[i], bestS[i] = sup[i];
      }
    };
    const unsigned k = static_cast<unsigned>(K);
    for (unsigned i = 0; i < k; ++i) {
      sup[0] = order[i].second;
      consider(1);
      for (unsigned j = i + 1; j < k; ++j) {
        sup[1] = order[j].second;
        consider(2);
        for (unsigned l = j + 1; l < k; ++l) {
          sup[2] = order[l].second;
          consider(3);
          for (unsigned m = l + 1; m < k; ++m) {
            sup[3] = order[m].second;
            consider(4);
          }
        }
      }
    }
    if (best < 0) return -1;
    // Lower bound by convexity at λ0 = the best point: F(λ0) + min_j g_j − Σ λ0_i g_i.
    V3 yl{0, 0, 0};
    for (int i = 0; i < bestN; ++i) {
      const V3 yi = sub(centers[bestS[i]], x);
      yl = {yl.x + bestL[i] * yi.x, yl.y + bestL[i] * yi.y, yl.z + bestL[i] * yi.z};
    }
    auto gradient = [&](unsigned j) {
      const V3 yj = sub(centers[j], x);
      return 2 * (1 - S) * dot(yj, yl) + S * (dot(yj, yj) - weight(j));
    };
    Real minG = std::numeric_limits<Real>::infinity(), dotG = 0;
    for (std::size_t j = 0; j < n; ++j) minG = std::min(minG, gradient(static_cast<unsigned>(j)));
    for (int i = 0; i < bestN; ++i) dotG += bestL[i] * gradient(bestS[i]);
    if (best + minG - dotG > 0) return 1;
    if (K == n || K >= 16) return 0;
  }
}

}  // namespace surftrace::oracle

// Brute-force dist(x, A) over sphere, arc and vertex candidates (ORACLES.md A.1, A.2, D.1).
#include "oracles/ses_oracle.hpp"

#include <algorithm>
#include <cmath>
#include <random>
#include <stdexcept>
#include <string>
#include <thread>

#include <glm/geometric.hpp>

namespace surftrace::oracle {
namespace {

constexpr double kInf = std::numeric_limits<double>::infinity();

bool finite(const glm::dvec3& v) {
  return std::isfinite(v.x) && std::isfinite(v.y) && std::isfinite(v.z);
}

// Any unit vector perpendicular to the unit vector n.
glm::dvec3 anyPerpendicular(const glm::dvec3& n) {
  const glm::dvec3 a = std::abs(n.x) <= std::abs(n.y) && std::abs(n.x) <= std::abs(n.z)
                           ? glm::dvec3(1, 0, 0)
                           : (std::abs(n.y) <= std::abs(n.z) ? glm::dvec3(0, 1, 0)
                                                             : glm::dvec3(0, 0, 1));
  return glm::normalize(glm::cross(n, a));
}

}  // namespace

SesOracle::Grid::Grid(const std::vector<glm::dvec3>& points, double cellSize) {
  if (points.empty()) return;
  glm::dvec3 lo = points[0], hi = points[0];
  for (const auto& p : points) {
    lo = glm::min(lo, p);
    hi = glm::max(hi, p);
  }
  // Cap the cell count at ~32 per point (and >= 1 per axis) so that a sparse, spread-out
  // input cannot allocate a huge grid; growing the cell only makes queries scan more.
  const glm::dvec3 ext = hi - lo;
  const double maxCells = 32.0 * static_cast<double>(points.size()) + 64.0;
  double h = cellSize;
  auto cells = [&](double hh) {
    return (std::floor(ext.x / hh) + 1) * (std::floor(ext.y / hh) + 1) *
           (std::floor(ext.z / hh) + 1);
  };
  while (cells(h) > maxCells) h *= 1.25;
  lo_ = lo;
  inv_ = 1.0 / h;
  nx_ = static_cast<int>(std::floor(ext.x / h)) + 1;
  ny_ = static_cast<int>(std::floor(ext.y / h)) + 1;
  nz_ = static_cast<int>(std::floor(ext.z / h)) + 1;
  auto cellOf = [&](const glm::dvec3& p) {
    auto idx = [&](double v, double l, int n) {
      return std::clamp(static_cast<int>((v - l) * inv_), 0, n - 1);
    };
    return (idx(p.z, lo_.z, nz_) * ny_ + idx(p.y, lo_.y, ny_)) * nx_ + idx(p.x, lo_.x, nx_);
  };
  const std::size_t nCells = static_cast<std::size_t>(nx_) * ny_ * nz_;
  start_.assign(nCells + 1, 0);
  std::vector<int> cellOfPoint(points.size());
  for (std::size_t i = 0; i < points.size(); ++i) {
    cellOfPoint[i] = cellOf(points[i]);
    ++start_[cellOfPoint[i] + 1];
  }
  for (std::size_t c = 0; c < nCells; ++c) start_[c + 1] += start_[c];
  items_.resize(points.size());
  std::vector<int> fill(start_.begin(), start_.end() - 1);
  for (std::size_t i = 0; i < points.size(); ++i)
    items_[fill[cellOfPoint[i]]++] = static_cast<int>(i);
}

SesOracle::SesOracle(std::vector<Sphere> atoms, double probeRadius, double exactMargin)
    : atoms_(std::move(atoms)), rp_(probeRadius), margin_(exactMargin) {
  if (!(std::isfinite(rp_) && rp_ > 0))
    throw std::invalid_argument("SesOracle: probe radius must be finite and > 0");
  if (!(std::isfinite(margin_) && margin_ >= 0))
    throw std::invalid_argument("SesOracle: exactMargin must be finite and >= 0");
  std::vector<glm::dvec3> centres;
  centres.reserve(atoms_.size());
  R_.reserve(atoms_.size());
  for (std::size_t i = 0; i < atoms_.size(); ++i) {
    const Sphere& a = atoms_[i];
    if (!finite(a.c) || !(std::isfinite(a.r) && a.r >= 0))
      throw std::invalid_argument("SesOracle: atom " + std::to_string(i) +
                                  " has a non-finite centre or a negative/non-finite radius");
    R_.push_back(a.r + rp_);
    maxR_ = std::max(maxR_, a.r + rp_);
    centres.push_back(a.c);
    const glm::dvec3 lo = a.c - a.r, hi = a.c + a.r;
    boxLo_ = i == 0 ? lo : glm::min(boxLo_, lo);
    boxHi_ = i == 0 ? hi : glm::max(boxHi_, hi);
  }
  atomGrid_ = Grid(centres, 0.5 * (maxR_ + margin_));
  findVertices();
  vertexGrid_ = Grid(vertices_, exactUpTo());
}

bool SesOracle::inAccessible(const glm::dvec3& y, const int* near, std::size_t count, int a,
                             int b, int c) const {
  for (std::size_t n = 0; n < count; ++n) {
    const int m = near[n];
    if (m == a || m == b || m == c) continue;
    const glm::dvec3 d = y - atoms_[m].c;
    const double Rm = R_[m] * (1 - kRelTol);
    if (glm::dot(d, d) < Rm * Rm) return false;
  }
  return true;
}

// A.2: probe positions touching atoms i, j, k; kept when no other extended sphere contains
// them (relative tolerance kRelTol, so ties with cospherical atoms, E6, are kept).
void SesOracle::findVertices() {
  const int n = static_cast<int>(atoms_.size());
  // Pairs whose SAS circle exists (A.1): |R_i - R_j| < d < R_i + R_j; only j > i.
  std::vector<std::vector<int>> nb(n);
  for (int i = 0; i < n; ++i) {
    atomGrid_.forEachNear(atoms_[i].c, R_[i] + maxR_, [&](int j) {
      if (j > i) {
        const double d = glm::length(atoms_[j].c - atoms_[i].c);
        if (std::abs(R_[i] - R_[j]) < d && d < R_[i] + R_[j]) nb[i].push_back(j);
      }
      return true;
    });
    std::sort(nb[i].begin(), nb[i].end());
  }
  circleStart_.assign(n + 1, 0);
  for (int i = 0; i < n; ++i) {
    for (int j : nb[i]) {
      const glm::dvec3 cij = atoms_[j].c - atoms_[i].c;
      const double d = glm::length(cij);
      const double Ri = R_[i], Rj = R_[j];
      const double t = (d * d + Ri * Ri - Rj * Rj) / (2 * d);
      // Product form of the circle radius: no cancellation near tangency (A.1).
      const double rho =
          std::sqrt(((Ri + Rj) * (Ri + Rj) - d * d) * (d * d - (Ri - Rj) * (Ri - Rj))) /
          (2 * d);
      const glm::dvec3 axis = cij / d;
      circles_.push_back({atoms_[i].c + t * axis, axis, rho, j});
    }
    circleStart_[i + 1] = static_cast<int>(circles_.size());
  }
  std::vector<char> isNbOfJ(n, 0);
  std::vector<int> near;
  auto tryVertex = [&](const glm::dvec3& p, int i, int j, int k) {
    near.clear();
    atomGrid_.forEachNear(p, maxR_, [&](int m) {
      near.push_back(m);
      return true;
    });
    if (inAccessible(p, near.data(), near.size(), i, j, k)) {
      vertices_.push_back(p);
      vertexAtoms_.push_back({i, j, k});
    }
  };
  for (int i = 0; i < n; ++i) {
    const glm::dvec3 ci = atoms_[i].c;
    const double Ri2 = R_[i] * R_[i];
    for (int j : nb[i]) {
      for (int k : nb[j]) isNbOfJ[k] = 1;
      for (int k : nb[i]) {
        if (k <= j || !isNbOfJ[k]) continue;
        const glm::dvec3 a = atoms_[j].c - ci, b = atoms_[k].c - ci;
        const glm::dvec3 axb = glm::cross(a, b);
        const double s2 = glm::dot(axb, axb);  // = |a|^2 |b|^2 - (a.b)^2, the Gram determinant
        const double aa = glm::dot(a, a), bb = glm::dot(b, b), ab = glm::dot(a, b);
        if (std::sqrt(s2) <= 1e-12 * std::sqrt(aa * bb)) continue;  // collinear (E5)
        const double u = 0.5 * (aa + Ri2 - R_[j] * R_[j]);
        const double v = 0.5 * (bb + Ri2 - R_[k] * R_[k]);
        const double alpha = (bb * u - ab * v) / s2, beta = (aa * v - ab * u) / s2;
        const glm::dvec3 q = alpha * a + beta * b;
        const double h2 = Ri2 - glm::dot(q, q);
        // Accept h2 slightly below 0 as a tangential (h = 0) position: it is within rounding
        // of all three spheres, and dropping it would lose the E7(b) ring vertex.
        if (h2 < -1e-12 * Ri2) continue;
        const double h = std::sqrt(std::max(h2, 0.0));
        const glm::dvec3 m = axb / std::sqrt(s2);
        tryVertex(ci + q + h * m, i, j, k);
        if (h > 0) tryVertex(ci + q - h * m, i, j, k);
      }
      for (int k : nb[j]) isNbOfJ[k] = 0;
    }
  }
}

namespace {
// Per-thread query buffers, so that queries allocate nothing once warm and stay const.
struct QueryScratch {
  std::vector<int> near;        // atom indices
  std::vector<double> dist;     // |x - c_i| for near[]
  std::vector<int> shell;       // atoms with a sphere point within L
  std::vector<double> lowerBound;  // per atom: | |x - c_i| - R_i |, valid where inShell
  std::vector<char> inShell;    // per atom; reset to 0 before each query returns
};
}  // namespace

SesOracle::Result SesOracle::distanceToAccessible(const glm::dvec3& x) const {
  const double L = exactUpTo();
  thread_local QueryScratch scratch;
  QueryScratch& q = scratch;
  if (q.inShell.size() < atoms_.size()) {
    q.inShell.resize(atoms_.size(), 0);
    q.lowerBound.resize(atoms_.size(), 0);
  }
  q.near.clear();
  q.dist.clear();
  q.shell.clear();
  // Atoms whose extended sphere comes within L of x. Every candidate within L of x lies on
  // such spheres, and only these atoms can contain a point within L of x, so checking
  // candidates against them alone decides membership in A exactly.
  bool inA = true;
  double deepest = -kInf;  // max_i (R_i - |x - c_i|): dist(x, A) is at least this
  atomGrid_.forEachNear(x, maxR_ + L, [&](int i) {
    const glm::dvec3 d = x - atoms_[i].c;
    const double lim = (R_[i] + L) * (1 + 1e-9);
    const double d2 = glm::dot(d, d);
    if (d2 < lim * lim) {
      const double s = std::sqrt(d2);
      q.near.push_back(i);
      q.dist.push_back(s);
      if (d2 < R_[i] * R_[i]) inA = false;
      deepest = std::max(deepest, R_[i] - s);
    }
    return true;
  });

  Result res;
  if (inA) {
    res.kind = Result::Inside;
    res.dist = 0;
    res.nearest = x;
    res.runnerUpGap = std::min(L, -deepest);
    return res;
  }

  double best = kInf, second = kInf;
  auto offer = [&](double d, Result::Kind kind, int a, int b, int c, const glm::dvec3& y) {
    if (d < best) {
      second = best;
      best = d;
      res.kind = kind;
      res.nearest = y;
      res.atoms[0] = a;
      res.atoms[1] = b;
      res.atoms[2] = c;
    } else if (d < second) {
      second = d;
    }
  };
  const int* nearData = q.near.data();
  const std::size_t nearCount = q.near.size();

  // Sphere points (2-faces): y_i = c_i + R_i (x - c_i)/|x - c_i|, distance | |x-c_i| - R_i |.
  // The antipodal critical point is a maximum and never the minimiser (D.1).
  for (std::size_t n = 0; n < nearCount; ++n) {
    const int i = q.near[n];
    const double s = q.dist[n];
    const double d = std::abs(s - R_[i]);
    if (d > L) continue;
    q.shell.push_back(i);
    q.inShell[i] = 1;
    q.lowerBound[i] = d;
    if (d >= second) continue;
    const glm::dvec3 dir = s > 0 ? (x - atoms_[i].c) / s : glm::dvec3(1, 0, 0);
    const glm::dvec3 y = atoms_[i].c + R_[i] * dir;
    if (inAccessible(y, nearData, nearCount, i, -1, -1))
      offer(d, Result::SpherePoint, i, -1, -1, y);
  }

  // Arc points (1-faces, A.1): the point of the SAS circle of (i, j) nearest to x. Both
  // atoms must be in the shell, since an arc point lies on both spheres; for the same reason
  // its distance is at least max(lowerBound_i, lowerBound_j), which prunes most pairs.
  for (int i : q.shell) {
    const double lbI = q.lowerBound[i];
    if (lbI >= second) continue;
    for (int c = circleStart_[i]; c < circleStart_[i + 1]; ++c) {
      const Circle& circle = circles_[c];
      const int j = circle.j;
      if (!q.inShell[j] || q.lowerBound[j] >= second) continue;
      const glm::dvec3 w = x - circle.centre;
      const double axial = glm::dot(w, circle.n);
      const glm::dvec3 wPerp = w - axial * circle.n;
      const double radial = std::sqrt(glm::dot(wPerp, wPerp));
      const double dr = radial - circle.rho;
      const double dd = std::sqrt(axial * axial + dr * dr);
      if (dd > L || dd >= second) continue;
      // On the axis every circle point is equally near; any one will do (its arc endpoints
      // are vertex candidates anyway).
      const glm::dvec3 dir = radial > 0 ? wPerp / radial : anyPerpendicular(circle.n);
      const glm::dvec3 y = circle.centre + circle.rho * dir;
      if (inAccessible(y, nearData, nearCount, i, j, -1))
        offer(dd, Result::ArcPoint, i, j, -1, y);
    }
  }
  for (int i : q.shell) q.inShell[i] = 0;

  // SAS vertices (0-faces), valid by construction.
  vertexGrid_.forEachNear(x, L, [&](int v) {
    const glm::dvec3 dv = x - vertices_[v];
    const double d2 = glm::dot(dv, dv);
    if (d2 <= L * L && d2 < second * second) {
      const auto& t = vertexAtoms_[v];
      offer(std::sqrt(d2), Result::Vertex, t[0], t[1], t[2], vertices_[v]);
    }
    return true;
  });

  if (best <= L) {
    res.dist = best;
    res.runnerUpGap = std::min(second, L) - best;
    return res;
  }
  // No point of A within L: dist(x, A) > L. Report a lower bound that still exceeds L.
  res = Result{};
  res.kind = Result::Far;
  res.dist = std::max(std::nextafter(L, kInf), deepest);
  res.nearest = x;
  res.runnerUpGap = 0;
  return res;
}

VolumeEstimate sesVolumeMonteCarlo(const SesOracle& oracle, std::size_t samples,
                                   std::uint64_t seed, int threads, int replicas) {
  if (samples == 0 || replicas < 1)
    throw std::invalid_argument("sesVolumeMonteCarlo: need samples > 0 and replicas >= 1");
  const std::size_t nRep = std::min<std::size_t>(static_cast<std::size_t>(replicas), samples);
  const std::size_t perRep = samples / nRep;
  const glm::dvec3 lo = oracle.boxLo(), ext = oracle.boxHi() - oracle.boxLo();
  const double boxVolume = ext.x * ext.y * ext.z;
  if (oracle.atoms().empty() || !(boxVolume > 0)) return {0.0, 0.0, perRep * nRep};

  // Roberts' R3 sequence: alpha_k = g^-k with g the real root of g^4 = g + 1.
  constexpr double g = 1.2207440846057596;
  const glm::dvec3 alpha(1 / g, 1 / (g * g), 1 / (g * g * g));
  std::mt19937_64 rng(seed);
  std::uniform_real_distribution<double> uni(0.0, 1.0);
  std::vector<glm::dvec3> shift(nRep);
  for (auto& s : shift) s = glm::dvec3(uni(rng), uni(rng), uni(rng));

  std::vector<std::size_t> hits(nRep, 0);
  auto runReplicas = [&](std::size_t first, std::size_t step) {
    for (std::size_t r = first; r < nRep; r += step) {
      std::size_t h = 0;
      for (std::size_t k = 0; k < perRep; ++k) {
        glm::dvec3 u = shift[r] + static_cast<double>(k + 1) * alpha;
        u -= glm::floor(u);
        if (oracle.insideSesBody(lo + u * ext)) ++h;
      }
      hits[r] = h;
    }
  };
  const std::size_t nThreads =
      std::clamp<std::size_t>(threads < 1 ? 1 : static_cast<std::size_t>(threads), 1, nRep);
  std::vector<std::thread> pool;
  for (std::size_t t = 1; t < nThreads; ++t) pool.emplace_back(runReplicas, t, nThreads);
  runReplicas(0, nThreads);
  for (auto& th : pool) th.join();

  std::vector<double> v(nRep);
  double mean = 0;
  for (std::size_t r = 0; r < nRep; ++r) {
    v[r] = boxVolume * static_cast<double>(hits[r]) / static_cast<double>(perRep);
    mean += v[r];
  }
  mean /= static_cast<double>(nRep);
  double se;
  if (nRep > 1) {
    double ss = 0;
    for (double vi : v) ss += (vi - mean) * (vi - mean);
    se = std::sqrt(ss / static_cast<double>(nRep - 1) / static_cast<double>(nRep));
  } else {  // one replica: fall back to the binomial (plain Monte Carlo) error
    const double p = mean / boxVolume;
    se = boxVolume * std::sqrt(p * (1 - p) / static_cast<double>(perRep));
  }
  return {mean, se, perRep * nRep};
}

}  // namespace surftrace::oracle

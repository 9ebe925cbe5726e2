// Independent brute-force SES oracle (ORACLES.md D.1): dist(x, A) to the probe-accessible set.
//
// Independence is the point: this file and ses_oracle.cpp use only glm and the standard
// library, never SurfTrace's own geometry code, so a shared bug cannot hide in both.
//
// Definitions (ORACLES.md, notation): atom i has centre c_i, vdW radius r_i, extended radius
// R_i = r_i + rp. A = {c : |c - c_i| >= R_i for all i} is the set of accessible probe centres;
// the SES body is {x : dist(x, A) >= rp} and the SES is {x : dist(x, A) = rp}.
//
// Cavity policy: A here contains EVERY accessible probe position, including probes trapped in
// closed internal pockets. So the SES body of this oracle excludes buried cavities that a
// probe fits into (they get their own inward-facing SES component), exactly as A.5/D.1
// define it. A builder that drops inner components must be compared on points whose nearest
// accessible probe is in the outer component only.
#pragma once

#include <array>
#include <cstddef>
#include <cstdint>
#include <limits>
#include <vector>

#include <glm/vec3.hpp>

namespace surftrace::oracle {

struct Sphere {  // a vdW atom
  glm::dvec3 c;
  double r;
};

class SesOracle {
 public:
  // Throws std::invalid_argument on a non-finite centre, a negative or non-finite radius, or
  // a probe radius that is not finite and > 0.
  //
  // `exactMargin` (>= 0, Å) sets how far the query is exact: dist(x, A) is exact whenever it
  // is <= exactUpTo() = probeRadius + exactMargin. Larger margins cost query time.
  //
  // The constructor precomputes every valid SAS vertex (probe position touching three atoms
  // with no atom interior to it) with a uniform grid: ~0.1 s for 3000 atoms.
  SesOracle(std::vector<Sphere> atoms, double probeRadius, double exactMargin = 0.5);

  struct Result {
    // Far: x is deeper than exactUpTo() inside the union of extended spheres; dist is then
    // only a lower bound on dist(x, A), but always > exactUpTo() (so > rp: inside the body).
    enum Kind { Inside /* x in A, dist = 0 */, SpherePoint, ArcPoint, Vertex, Far };

    double dist = 0;          // dist(x, A): exact when <= exactUpTo(), else a lower bound
    glm::dvec3 nearest{0.0};  // the minimiser y in A (x itself for Inside; x for Far)
    Kind kind = Inside;
    // Atoms defining the minimising feature, ascending, -1 where unused: sphere {i,-1,-1},
    // arc {i,j,-1}, vertex {i,j,k}. For a vertex, `nearest` is the probe position, which
    // tells p+ from p-.
    int atoms[3] = {-1, -1, -1};
    // Distance of the runner-up valid candidate (another feature) minus dist. 0 on patch
    // seams, cusps and self-intersection curves: mark such points ambiguous (D.1). It is a
    // lower bound when the runner-up lies beyond exactUpTo(): then it equals
    // exactUpTo() - dist. For Inside it is a lower bound on the distance from x to the
    // SAS (clamped to exactUpTo()); for Far it is 0.
    double runnerUpGap = std::numeric_limits<double>::infinity();
  };

  // dist(x, A) and the feature of A that realises it (D.1). Thread-safe: const, with
  // per-thread scratch buffers (no allocation once warm).
  Result distanceToAccessible(const glm::dvec3& x) const;

  // x in the SES body, i.e. dist(x, A) >= rp. Buried cavities are NOT in the body (see top).
  bool insideSesBody(const glm::dvec3& x) const { return distanceToAccessible(x).dist >= rp_; }

  // All valid SAS vertices, and for each the three atoms (ascending) that it touches. Ties
  // (cospherical atoms, E6) produce one entry per triple, possibly at the same position.
  const std::vector<glm::dvec3>& vertices() const { return vertices_; }
  const std::vector<std::array<int, 3>>& vertexAtoms() const { return vertexAtoms_; }

  const std::vector<Sphere>& atoms() const { return atoms_; }
  double probeRadius() const { return rp_; }
  double exactUpTo() const { return rp_ + margin_; }
  // Axis-aligned box enclosing all vdW spheres; it contains the whole SES body.
  glm::dvec3 boxLo() const { return boxLo_; }
  glm::dvec3 boxHi() const { return boxHi_; }

  // Relative tolerance of the "candidate lies in A" test, |y - c_k| >= R_k (1 - kRelTol).
  static constexpr double kRelTol = 1e-10;

  // A uniform grid over points (CSR layout): a cell holds the indices of the points in it.
  class Grid {
   public:
    Grid() = default;
    Grid(const std::vector<glm::dvec3>& points, double cellSize);
    // Calls f(index) for every point whose cell meets the cube of half-width `reach` around
    // x (a superset of the points within `reach`). Stops early when f returns false.
    template <class F>
    void forEachNear(const glm::dvec3& x, double reach, F&& f) const;

   private:
    glm::dvec3 lo_{0.0};
    double inv_ = 1;
    int nx_ = 0, ny_ = 0, nz_ = 0;
    std::vector<int> start_;  // size cells+1
    std::vector<int> items_;
  };

 private:
  void findVertices();
  // True when y lies in A up to kRelTol, ignoring atoms a, b, c (-1 for none), checking
  // only the atoms in `near`.
  bool inAccessible(const glm::dvec3& y, const int* near, std::size_t count, int a, int b,
                    int c) const;

  std::vector<Sphere> atoms_;
  std::vector<double> R_;  // extended radii
  double rp_;
  double margin_;
  double maxR_ = 0;
  glm::dvec3 boxLo_{0.0}, boxHi_{0.0};
  Grid atomGrid_;
  // SAS circles (A.1) of the pairs (i, j > i) whose circle exists, CSR by i.
  struct Circle {
    glm::dvec3 centre, n;
    double rho;
    int j;
  };
  std::vector<int> circleStart_;
  std::vector<Circle> circles_;
  std::vector<glm::dvec3> vertices_;
  std::vector<std::array<int, 3>> vertexAtoms_;
  Grid vertexGrid_;
};

// Monte Carlo estimate of the SES body volume (D.2, "independent SES volume"), sampling the
// box boxLo()..boxHi() with the insideSesBody test. Randomised quasi-Monte Carlo: `replicas`
// independent uniform random shifts (Cranley-Patterson) of Roberts' R3 low-discrepancy
// sequence, samples/replicas points each. Each replica is an unbiased estimate; `volume` is
// their mean and `stderr_` the standard error of that mean (1 sigma, from the spread of the
// replicas), so |V_exact - volume| <= 4 stderr_ is a valid check. The result depends only on
// (samples, seed, replicas), never on `threads`. Buried cavities are excluded from the body.
struct VolumeEstimate {
  double volume;
  double stderr_;
  std::size_t samples;
};
VolumeEstimate sesVolumeMonteCarlo(const SesOracle& oracle, std::size_t samples,
                                   std::uint64_t seed, int threads = 1, int replicas = 32);

template <class F>
void SesOracle::Grid::forEachNear(const glm::dvec3& x, double reach, F&& f) const {
  if (items_.empty()) return;
  // Clamp in double before converting, so far-away queries cannot overflow the int cast.
  auto range = [&](double v, double lo, int n, int& i0, int& i1) {
    const double a = (v - reach - lo) * inv_, b = (v + reach - lo) * inv_;
    if (!(b >= 0) || !(a < n)) return false;  // also rejects NaN
    i0 = a <= 0 ? 0 : static_cast<int>(a);
    i1 = b >= n - 1 ? n - 1 : static_cast<int>(b);
    return true;
  };
  int x0, x1, y0, y1, z0, z1;
  if (!range(x.x, lo_.x, nx_, x0, x1) || !range(x.y, lo_.y, ny_, y0, y1) ||
      !range(x.z, lo_.z, nz_, z0, z1))
    return;
  for (int iz = z0; iz <= z1; ++iz)
    for (int iy = y0; iy <= y1; ++iy) {
      const int row = (iz * ny_ + iy) * nx_;
      for (int k = start_[row + x0]; k < start_[row + x1 + 1]; ++k)
        if (!f(items_[k])) return;
    }
}

}  // namespace surftrace::oracle

// Certificate oracle for the molecular skin (ORACLES D.3): is x on the skin, in the mixed
// cell of a given Delaunay simplex X? Straight from the definition, no Voronoi diagram:
//
//   G(x) = min_{λ ∈ Δ} (1 − s)|Σ λ_i y_i|² + s Σ λ_i π_i(x),   y_i = z_i − x,
//
// a convex quadratic programme over the simplex of all atoms. Solve its KKT system on the
// support X; the result is THE minimum (KKT conditions are sufficient for a convex QP) iff
// λ >= 0 and every atom j satisfies 2(1 − s) y_j·y_λ + s π_j >= ν. Then G(x) is the value,
// and X is the support of λ*: the simplex whose mixed cell holds x. Uses glm and the standard
// library only, never SurfTrace's geometry.
#pragma once

#include <span>
#include <vector>

#include <glm/vec3.hpp>

namespace surftrace::oracle {

struct SkinCertificate {
  bool solved = false;        // the KKT system on X is regular
  double value = 0.0;         // F(λ) on X (Å²); = G(x) when certified
  double minLambda = 0.0;     // smallest λ_a, a ∈ X (>= 0: x's convex weights lie in δ_X)
  double minGap = 0.0;        // min_j (∂F/∂λ_j − ν) over all atoms (>= 0: globally optimal)
  double scale = 1.0;         // max w_a, a ∈ X: the scale of value and minGap (Å²)
};

// Atoms (centres, radii), weights w_i = r_i²/s; `simplex` lists 1..4 atom indices.
SkinCertificate certifySkinPoint(std::span<const glm::dvec3> centers, std::span<const double> radii, double s,
                                 std::span<const unsigned> simplex, const glm::dvec3& x);

// The sign of G(x) (inside the skin body: −1, outside: +1), decided with a certificate: any λ
// with F(λ) < 0 proves inside; for the best λ0 found, convexity gives
// G >= F(λ0) + min_j ∂_jF(λ0) − λ0·∇F(λ0), and a positive bound proves outside. λ0 is the
// best KKT point over supports of up to four of the K atoms with smallest |y_i|² − r_i²
// (K = 8, then 16, until one of the two proofs holds). 0 when neither proof holds (x on the
// skin to rounding, or a support beyond the 16 nearest). Cheap exits: inside an atom ball, outside every grown ball.
int skinSign(std::span<const glm::dvec3> centers, std::span<const double> radii, double s, const glm::dvec3& x);

}  // namespace surftrace::oracle

// Random numbers for the intersector tests: uniform and log-uniform scales (STYLE §4), unit vectors.
#pragma once

#include <cmath>
#include <random>

#include <glm/geometric.hpp>
#include <glm/vec3.hpp>

namespace surftrace::trace::testing_random {

inline double uniform(std::mt19937_64& rng, double lo, double hi) {
  return std::uniform_real_distribution<double>(lo, hi)(rng);
}
inline double logUniform(std::mt19937_64& rng, double lo, double hi) {
  return std::exp(uniform(rng, std::log(lo), std::log(hi)));
}
inline glm::dvec3 randomUnit(std::mt19937_64& rng) {
  std::normal_distribution<double> n;
  for (;;) {
    const glm::dvec3 v(n(rng), n(rng), n(rng));
    const double l = glm::length(v);
    if (l > 1e-6) return v / l;
  }
}

}  // namespace surftrace::trace::testing_random

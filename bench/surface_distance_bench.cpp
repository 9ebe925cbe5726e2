// Queries of the surface distance fields (build/mesh/surface_distance.hpp) at points near the
// surface, one thread: what a mesher pays per sample. Points are drawn about the atoms and kept
// where |signedDistance| < 1 Å; "random" visits them in random order (cache-cold), "slabs" in
// 2 Å slabs of z then y, as a grid sweep would.
#include <algorithm>
#include <cmath>
#include <map>
#include <memory>
#include <random>
#include <string>
#include <tuple>
#include <vector>

#include <benchmark/benchmark.h>
#include <glm/geometric.hpp>

#include "build/mesh/surface_distance.hpp"
#include "build/mss/mss_builder.hpp"
#include "build/ses/contour_buildup.hpp"
#include "paper_molecules.hpp"

namespace {

using surftrace::build::mesh::SurfaceDistance;

struct Field {
  surftrace::build::PatchList list;
  std::unique_ptr<SurfaceDistance> field;
  std::vector<glm::dvec3> random, slabs;
};

// One field per molecule and surface, built on first use (the SES of 1AON takes seconds).
const Field& field(const std::string& name, bool skin) {
  static std::map<std::pair<std::string, bool>, Field> cache;
  auto it = cache.find({name, skin});
  if (it != cache.end()) return it->second;
  const auto& m = surftrace::bench::paperMolecule(name + ".pdb.gz");
  Field f;
  f.list = skin ? surftrace::build::buildMss(m.centers, m.radii, {0.5}) : surftrace::build::buildSes(m.centers, m.radii, {1.4});
  f.field = surftrace::build::mesh::makeSurfaceDistance(f.list, m.centers, m.radii);
  std::mt19937_64 rng(12);
  std::normal_distribution<double> normal(0.0, 1.0);
  std::uniform_real_distribution<double> shell(-1.0, 3.0);
  std::uniform_int_distribution<std::size_t> pick(0, m.size() - 1);
  while (f.random.size() < 20000) {
    const std::size_t i = pick(rng);
    const glm::dvec3 d = glm::normalize(glm::dvec3(normal(rng), normal(rng), normal(rng)));
    const glm::dvec3 x = m.centers[i] + (m.radii[i] + shell(rng)) * d;
    if (std::abs(f.field->signedDistance(x)) < 1.0) f.random.push_back(x);
  }
  f.slabs = f.random;
  std::sort(f.slabs.begin(), f.slabs.end(), [](const glm::dvec3& a, const glm::dvec3& b) {
    return std::tuple(std::floor(a.z / 2), std::floor(a.y / 2), a.x) < std::tuple(std::floor(b.z / 2), std::floor(b.y / 2), b.x);
  });
  return cache.emplace(std::pair{name, skin}, std::move(f)).first->second;
}

void BM_SignedDistance(benchmark::State& state, const std::string& name, bool skin, bool slabs) {
  const Field& f = field(name, skin);
  const std::vector<glm::dvec3>& points = slabs ? f.slabs : f.random;
  std::size_t k = 0;
  for (auto _ : state) {
    benchmark::DoNotOptimize(f.field->signedDistance(points[k]));
    k = k + 1 == points.size() ? 0 : k + 1;
  }
  state.counters["queries_per_s"] = benchmark::Counter(1.0, benchmark::Counter::kIsIterationInvariantRate);
}

void BM_Closest(benchmark::State& state, const std::string& name, bool skin) {
  const Field& f = field(name, skin);
  std::size_t k = 0;
  for (auto _ : state) {
    benchmark::DoNotOptimize(f.field->closest(f.random[k]).point);
    k = k + 1 == f.random.size() ? 0 : k + 1;
  }
  state.counters["queries_per_s"] = benchmark::Counter(1.0, benchmark::Counter::kIsIterationInvariantRate);
}

}  // namespace

BENCHMARK_CAPTURE(BM_SignedDistance, 1aon_ses_random, std::string("1aon"), false, false)->Unit(benchmark::kNanosecond);
BENCHMARK_CAPTURE(BM_SignedDistance, 1aon_ses_slabs, std::string("1aon"), false, true)->Unit(benchmark::kNanosecond);
BENCHMARK_CAPTURE(BM_Closest, 1aon_ses, std::string("1aon"), false)->Unit(benchmark::kNanosecond);
BENCHMARK_CAPTURE(BM_SignedDistance, 1grm_skin_random, std::string("1grm"), true, false)->Unit(benchmark::kNanosecond);
BENCHMARK_CAPTURE(BM_Closest, 1grm_skin, std::string("1grm"), true)->Unit(benchmark::kNanosecond);

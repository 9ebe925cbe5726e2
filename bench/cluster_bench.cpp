// Near-coincident clusters: 1,000 clusters of k atoms within 1e-4 Å of one another (k = 1 ... 16),
// spread over a 10 x 10 x 10 grid of 3 Å, through buildSurface as `build` and `area` run it:
// the atoms culled and merged, then either the surface built (SES, or the skin at s = 0.5) or
// the clusters refused with the merge distance that resolves them. The work should grow with
// the atom count only: a builder that takes clusters on pays about k^2.5 per cluster.
#include <cstddef>
#include <random>
#include <stdexcept>

#include <benchmark/benchmark.h>
#include <tbb/global_control.h>

#include "build/io/molecule.hpp"
#include "build/surface.hpp"

namespace {

using namespace surftrace::build;

// The clusters' centres jitter by up to 0.3 Å about the grid points, so that no two clusters
// sit in a symmetric (cospherical) arrangement; within a cluster the first atom is at the
// centre and the others within 2.5e-5 Å per axis of it (all within 1e-4 Å of one another).
Molecule clusters(int k) {
  Molecule m;
  m.source = "clusters";
  std::mt19937_64 rng(29), rngIn(31);  // the clusters' centres do not depend on k
  std::uniform_real_distribution<double> jitter(-0.3, 0.3), spread(-2.5e-5, 2.5e-5);
  for (int x = 0; x < 10; ++x)
    for (int y = 0; y < 10; ++y)
      for (int z = 0; z < 10; ++z) {
        const glm::dvec3 centre = 3.0 * glm::dvec3(x, y, z) + glm::dvec3(jitter(rng), jitter(rng), jitter(rng));
        for (int a = 0; a < k; ++a) {
          m.centers.push_back(a == 0 ? centre : centre + glm::dvec3(spread(rngIn), spread(rngIn), spread(rngIn)));
          m.radii.push_back(1.7);
        }
      }
  return m;
}

// range(0) = k, range(1) = 0 for the SES (probe 1.4 Å), 1 for the skin at s = 0.5. One thread.
void BM_NearCoincidentClusters(benchmark::State& state) {
  tbb::global_control threads(tbb::global_control::max_allowed_parallelism, 1);
  const Molecule m = clusters(static_cast<int>(state.range(0)));
  const SurfaceRequest request = state.range(1) == 0 ? SurfaceRequest{SurfaceKind::Ses, 1.4}
                                                     : SurfaceRequest{SurfaceKind::Mss, 1.4, 0.5};
  bool refused = false;
  std::size_t patches = 0;
  for (auto _ : state) {
    try {
      patches = buildSurface(m, request).patchCount();
    } catch (const std::invalid_argument&) {
      refused = true;
    }
    benchmark::DoNotOptimize(patches);
  }
  state.counters["atoms"] = static_cast<double>(m.size());
  state.counters["refused"] = refused ? 1.0 : 0.0;
  state.counters["patches"] = static_cast<double>(patches);
}

BENCHMARK(BM_NearCoincidentClusters)
    ->ArgsProduct({benchmark::CreateDenseRange(1, 16, 1), {0, 1}})
    ->ArgNames({"k", "skin"})
    ->Unit(benchmark::kMillisecond)
    ->UseRealTime()
    ->Iterations(1)
    ->Repetitions(5)
    ->ReportAggregatesOnly(true);

}  // namespace

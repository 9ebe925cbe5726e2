// The skin's areas and volume (computeMssAreas) on the paper's molecules at 1 and 2 threads and
// s = 0.3, 0.5, against the adaptive integration it replaced (issue 22), per hyperboloid patch.
#include <string>

#include <benchmark/benchmark.h>
#include <tbb/global_control.h>

#include "build/mss/mss_area.hpp"
#include "build/mss/mss_builder.hpp"
#include "paper_molecules.hpp"

namespace {

using surftrace::build::MssAreas;
using surftrace::build::PatchList;

template <bool kAdaptive>
void mssAreas(benchmark::State& state, const std::string& name) {
  const auto& m = surftrace::bench::paperMolecule(name);
  const PatchList p = surftrace::build::buildMss(m.centers, m.radii, {static_cast<double>(state.range(1)) / 100.0});
  tbb::global_control threads(tbb::global_control::max_allowed_parallelism, static_cast<std::size_t>(state.range(0)));
  double hyperboloids = 0;
  for (std::uint32_t k : p.mss.kind) hyperboloids += k == 1 || k == 2;
  for (auto _ : state) {
    const MssAreas a = kAdaptive ? surftrace::build::computeMssAreasAdaptive(p, m.centers)
                                 : surftrace::build::computeMssAreas(p, m.centers);
    benchmark::DoNotOptimize(a.total());
  }
  state.counters["hyperboloids"] = hyperboloids;
  state.counters["us_per_hyperboloid"] =
      benchmark::Counter(hyperboloids * 1e-6, benchmark::Counter::kIsIterationInvariantRate | benchmark::Counter::kInvert);
}

void BM_MssAreas(benchmark::State& state, const std::string& name) { mssAreas<false>(state, name); }
void BM_MssAreasAdaptive(benchmark::State& state, const std::string& name) { mssAreas<true>(state, name); }

}  // namespace

#define SURFTRACE_AREA_BENCH(fn, tag, file)                                               \
  BENCHMARK_CAPTURE(fn, tag, std::string(file))                                                    \
      ->ArgsProduct({{1, 2}, {30, 50}})                                                               \
      ->ArgNames({"threads", "s100"})                                                              \
      ->Unit(benchmark::kMillisecond)                                                              \
      ->UseRealTime()                                                                              \
      ->Repetitions(5)                                                                             \
      ->ReportAggregatesOnly(true)

SURFTRACE_AREA_BENCH(BM_MssAreas, 1vis, "1vis.pdb.gz");
SURFTRACE_AREA_BENCH(BM_MssAreas, 1aon, "1aon.pdb.gz");
// The old integration, the test oracle, for comparison (1VIS only: 1AON takes ~40 s a run).
SURFTRACE_AREA_BENCH(BM_MssAreasAdaptive, 1vis, "1vis.pdb.gz");

// SES construction time on the paper's molecules at 1 and 2 threads (Lindow et al. 2010,
// Table 1 reports contour-buildup times for 1VIS, 1AF6 and 1AON).
#include <map>
#include <string>

#include <benchmark/benchmark.h>
#include <tbb/global_control.h>

#include "build/contour_buildup.hpp"
#include "build/molecule.hpp"

namespace {

const surftrace::build::Molecule& molecule(const std::string& name) {
  static std::map<std::string, surftrace::build::Molecule> cache;
  auto it = cache.find(name);
  if (it == cache.end())
    it = cache.emplace(name, surftrace::build::readMolecule(std::string(SURFTRACE_TEST_DATA) + "/paper/" + name)).first;
  return it->second;
}

void BM_BuildSes(benchmark::State& state, const std::string& name) {
  const auto& m = molecule(name);
  tbb::global_control threads(tbb::global_control::max_allowed_parallelism, static_cast<std::size_t>(state.range(0)));
  std::size_t patches = 0;
  for (auto _ : state) {
    const auto p = surftrace::build::buildSes(m.centers, m.radii, surftrace::build::SesParams{1.4});
    patches = p.patchCount();
    benchmark::DoNotOptimize(patches);
  }
  state.counters["atoms"] = static_cast<double>(m.size());
  state.counters["patches"] = static_cast<double>(patches);
  state.counters["atoms_per_s"] = benchmark::Counter(static_cast<double>(m.size()), benchmark::Counter::kIsIterationInvariantRate);
}

}  // namespace

BENCHMARK_CAPTURE(BM_BuildSes, 1vis, std::string("1vis.pdb.gz"))->Arg(1)->Arg(2)->Unit(benchmark::kMillisecond)->UseRealTime()->Repetitions(5)->ReportAggregatesOnly(true);
BENCHMARK_CAPTURE(BM_BuildSes, 1j4n, std::string("1j4n.pdb.gz"))->Arg(1)->Arg(2)->Unit(benchmark::kMillisecond)->UseRealTime()->Repetitions(5)->ReportAggregatesOnly(true);
BENCHMARK_CAPTURE(BM_BuildSes, 1af6, std::string("1af6.pdb.gz"))->Arg(1)->Arg(2)->Unit(benchmark::kMillisecond)->UseRealTime()->Repetitions(5)->ReportAggregatesOnly(true);
BENCHMARK_CAPTURE(BM_BuildSes, 1aon, std::string("1aon.pdb.gz"))->Arg(1)->Arg(2)->Unit(benchmark::kMillisecond)->UseRealTime()->Repetitions(5)->ReportAggregatesOnly(true);

// Benchmarks of the build stages on the molecules of Lindow et al. 2010 (tests/data/paper);
// this file holds BENCHMARK_MAIN and the neighbour grid's benchmarks.
#include <cstdint>
#include <string>
#include <vector>

#include <benchmark/benchmark.h>

#include "build/io/molecule.hpp"
#include "build/neighbour_grid.hpp"
#include "paper_molecules.hpp"

namespace {

using surftrace::build::NeighbourGrid;

constexpr double kProbeRadius = 1.4;

// The molecules as the tools read them (first model, no water, Bondi radii), so that these
// timings and the SES and MSS benchmarks' are for the same atoms.
const surftrace::build::Molecule& molecule(const std::string& name) {
  return surftrace::bench::paperMolecule(name + ".pdb.gz");
}

void BM_GridBuild(benchmark::State& state, const std::string& name) {
  const auto& atoms = molecule(name);
  NeighbourGrid grid(atoms.centers.size());
  for (auto _ : state) {
    grid.build(atoms.centers, atoms.radii, kProbeRadius);
    benchmark::ClobberMemory();
  }
  const auto n = static_cast<double>(atoms.centers.size());
  state.counters["atoms/s"] = benchmark::Counter(n * static_cast<double>(state.iterations()),
                                                 benchmark::Counter::kIsRate);
  state.counters["cells"] = static_cast<double>(grid.cellCount());
  state.counters["cellSize"] = grid.cellSize();
}

void BM_GridAllNeighbours(benchmark::State& state, const std::string& name) {
  const auto& atoms = molecule(name);
  NeighbourGrid grid(atoms.centers.size());
  grid.build(atoms.centers, atoms.radii, kProbeRadius);
  const auto n = static_cast<std::uint32_t>(atoms.centers.size());
  std::vector<std::uint32_t> out;
  std::size_t found = 0;
  for (auto _ : state) {
    found = 0;
    for (std::uint32_t i = 0; i < n; ++i) {
      out.clear();
      grid.neighbours(i, out);
      found += out.size();
    }
    benchmark::DoNotOptimize(found);
  }
  state.counters["atoms/s"] = benchmark::Counter(
      static_cast<double>(n) * static_cast<double>(state.iterations()), benchmark::Counter::kIsRate);
  state.counters["nbrs/atom"] = static_cast<double>(found) / static_cast<double>(n);
}

#define SURFTRACE_GRID_BENCH(fn, mol)                                              \
  BENCHMARK_CAPTURE(fn, mol, std::string(#mol))                                     \
      ->Unit(benchmark::kMillisecond)                                               \
      ->Repetitions(5)                                                              \
      ->ReportAggregatesOnly(true)

SURFTRACE_GRID_BENCH(BM_GridBuild, 1vis);
SURFTRACE_GRID_BENCH(BM_GridBuild, 1af6);
SURFTRACE_GRID_BENCH(BM_GridBuild, 1aon);
SURFTRACE_GRID_BENCH(BM_GridAllNeighbours, 1vis);
SURFTRACE_GRID_BENCH(BM_GridAllNeighbours, 1af6);
SURFTRACE_GRID_BENCH(BM_GridAllNeighbours, 1aon);

}  // namespace

BENCHMARK_MAIN();

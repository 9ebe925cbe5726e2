// MSS construction time on the paper's molecules at 1 and 2 threads and s = 0.3, 0.5
// (Lindow et al. 2010, Table 1: 1VIS 451 ms, 1AF6 2113, 1AON 9924 on one 2.53 GHz core), frame
// after frame with one builder, and the partial update of a few moved atoms.
#include <random>
#include <string>
#include <vector>

#include <benchmark/benchmark.h>
#include <glm/geometric.hpp>
#include <tbb/global_control.h>

#include "build/io/molecule.hpp"
#include "paper_molecules.hpp"
#include "build/mss/mss_builder.hpp"

namespace {

using surftrace::build::MssBuilder;
using surftrace::build::MssParams;

using surftrace::bench::paperMolecule;

void countKinds(benchmark::State& state, const surftrace::build::PatchList& p) {
  double count[4] = {0, 0, 0, 0};
  for (std::uint32_t k : p.mss.kind) ++count[k];
  state.counters["convex"] = count[0];
  state.counters["edge"] = count[1];
  state.counters["face"] = count[2];
  state.counters["concave"] = count[3];
}

// One build from scratch: range(0) threads, range(1) = 100 s.
void BM_BuildMss(benchmark::State& state, const std::string& name) {
  const auto& m = paperMolecule(name);
  tbb::global_control threads(tbb::global_control::max_allowed_parallelism, static_cast<std::size_t>(state.range(0)));
  const MssParams params{static_cast<double>(state.range(1)) / 100.0};
  surftrace::build::PatchList last;
  for (auto _ : state) {
    last = surftrace::build::buildMss(m.centers, m.radii, params);
    benchmark::DoNotOptimize(last.mss.size());
  }
  state.counters["atoms"] = static_cast<double>(m.size());
  state.counters["atoms_per_s"] = benchmark::Counter(static_cast<double>(m.size()), benchmark::Counter::kIsIterationInvariantRate);
  countKinds(state, last);
}

// Frame after frame, every atom moved (up to 0.3 Å), one builder that keeps its memory.
void BM_TrajectoryMss(benchmark::State& state, const std::string& name) {
  const auto& m = paperMolecule(name);
  tbb::global_control threads(tbb::global_control::max_allowed_parallelism, static_cast<std::size_t>(state.range(0)));
  const MssParams params{static_cast<double>(state.range(1)) / 100.0};
  std::mt19937_64 rng(7);
  std::uniform_real_distribution<double> u(-0.3, 0.3);
  std::vector<glm::dvec3> moved(m.centers);
  for (auto& c : moved) c += glm::dvec3(u(rng), u(rng), u(rng)) * (1.0 / std::sqrt(3.0));
  MssBuilder builder;
  builder.build(m.centers, m.radii, params);
  bool there = false;
  for (auto _ : state) {
    there = !there;
    benchmark::DoNotOptimize(builder.update(there ? moved : m.centers).mss.size());
  }
  state.counters["atoms"] = static_cast<double>(m.size());
  state.counters["atoms_per_s"] = benchmark::Counter(static_cast<double>(m.size()), benchmark::Counter::kIsIterationInvariantRate);
}

// 1% of the atoms, consecutive (a few flexible residues), move back and forth by up to 0.3 Å.
void BM_UpdateMss(benchmark::State& state, const std::string& name) {
  const auto& m = paperMolecule(name);
  tbb::global_control threads(tbb::global_control::max_allowed_parallelism, static_cast<std::size_t>(state.range(0)));
  const std::size_t count = m.size() / 100, start = m.size() / 3;
  std::vector<std::uint32_t> moved;
  for (std::size_t k = 0; k < count; ++k) moved.push_back(static_cast<std::uint32_t>(start + k));
  std::mt19937_64 rng(1);
  std::uniform_real_distribution<double> u(-0.3, 0.3);
  std::vector<glm::dvec3> home, away;
  for (const std::uint32_t a : moved) {
    home.push_back(m.centers[a]);
    away.push_back(m.centers[a] + glm::dvec3(u(rng), u(rng), u(rng)) * (1.0 / std::sqrt(3.0)));
  }
  MssBuilder builder;
  builder.build(m.centers, m.radii, MssParams{0.5});
  bool there = false;
  for (auto _ : state) {
    there = !there;
    benchmark::DoNotOptimize(builder.update(moved, there ? away : home).mss.size());
  }
  state.counters["atoms"] = static_cast<double>(m.size());
  state.counters["moved"] = static_cast<double>(moved.size());
  state.counters["recomputed"] = static_cast<double>(builder.lastUpdate().recomputed);
}

}  // namespace

#define SURFTRACE_MSS_BENCH(fn, tag, file)                                                        \
  BENCHMARK_CAPTURE(fn, tag, std::string(file))                                                   \
      ->ArgsProduct({{1, 2}, {30, 50}})                                                           \
      ->ArgNames({"threads", "s100"})                                                             \
      ->Unit(benchmark::kMillisecond)                                                             \
      ->UseRealTime()                                                                             \
      ->Repetitions(5)                                                                            \
      ->ReportAggregatesOnly(true)

SURFTRACE_MSS_BENCH(BM_BuildMss, 1vis, "1vis.pdb.gz");
SURFTRACE_MSS_BENCH(BM_BuildMss, 1af6, "1af6.pdb.gz");
SURFTRACE_MSS_BENCH(BM_BuildMss, 1aon, "1aon.pdb.gz");
SURFTRACE_MSS_BENCH(BM_BuildMss, 1j4n, "1j4n.pdb.gz");
SURFTRACE_MSS_BENCH(BM_TrajectoryMss, 1aon, "1aon.pdb.gz");
BENCHMARK_CAPTURE(BM_UpdateMss, 1af6, std::string("1af6.pdb.gz"))
    ->Arg(1)
    ->Arg(2)
    ->ArgNames({"threads"})
    ->Unit(benchmark::kMillisecond)
    ->UseRealTime()
    ->Repetitions(5)
    ->ReportAggregatesOnly(true);

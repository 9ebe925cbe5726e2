// SES construction time on the paper's molecules at 1 and 2 threads (Lindow et al. 2010,
// Table 1 reports contour-buildup times for 1VIS, 1AF6 and 1AON), and the partial update
// of a few moved atoms against a full rebuild.
#include <random>
#include <string>
#include <vector>

#include <benchmark/benchmark.h>
#include <glm/geometric.hpp>
#include <tbb/global_control.h>

#include "build/ses/contour_buildup.hpp"
#include "build/io/molecule.hpp"
#include "paper_molecules.hpp"

namespace {

using surftrace::build::SesBuilder;
using surftrace::build::SesParams;

using surftrace::bench::paperMolecule;

void BM_BuildSes(benchmark::State& state, const std::string& name) {
  const auto& m = paperMolecule(name);
  tbb::global_control threads(tbb::global_control::max_allowed_parallelism, static_cast<std::size_t>(state.range(0)));
  std::size_t patches = 0;
  for (auto _ : state) {
    const auto p = surftrace::build::buildSes(m.centers, m.radii, SesParams{1.4});
    patches = p.patchCount();
    benchmark::DoNotOptimize(patches);
  }
  state.counters["atoms"] = static_cast<double>(m.size());
  state.counters["patches"] = static_cast<double>(patches);
  state.counters["atoms_per_s"] = benchmark::Counter(static_cast<double>(m.size()), benchmark::Counter::kIsIterationInvariantRate);
}

// Frame after frame of a trajectory in which every atom moves (a full rebuild per frame),
// with one SesBuilder that keeps its memory: the MD use case. Frames alternate between the
// structure and a copy with every atom moved by up to 0.3 Å.
void BM_TrajectorySes(benchmark::State& state, const std::string& name) {
  const auto& m = paperMolecule(name);
  tbb::global_control threads(tbb::global_control::max_allowed_parallelism, static_cast<std::size_t>(state.range(0)));
  std::mt19937_64 rng(7);
  std::uniform_real_distribution<double> u(-0.3, 0.3);
  std::vector<glm::dvec3> moved(m.centers);
  for (auto& c : moved) c += glm::dvec3(u(rng), u(rng), u(rng)) * (1.0 / std::sqrt(3.0));
  SesBuilder builder;
  builder.build(m.centers, m.radii, SesParams{1.4});
  bool there = false;
  for (auto _ : state) {
    there = !there;
    const auto& p = builder.update(there ? moved : m.centers);
    benchmark::DoNotOptimize(p.patchCount());
  }
  state.counters["atoms"] = static_cast<double>(m.size());
  state.counters["atoms_per_s"] = benchmark::Counter(static_cast<double>(m.size()), benchmark::Counter::kIsIterationInvariantRate);
}

// A trajectory step in which 1% of the atoms move: either a stretch of consecutive atoms
// (a few flexible residues; range(1) = 0) or atoms scattered over the whole molecule
// (range(1) = 1, the worst case for locality). Each iteration moves them by up to 0.3 Å
// and the next one moves them back, so every iteration is an update of the same size.
// Compare with BM_BuildSes on the same molecule (a full rebuild per frame).
void BM_UpdateSes(benchmark::State& state, const std::string& name) {
  const auto& m = paperMolecule(name);
  tbb::global_control threads(tbb::global_control::max_allowed_parallelism, static_cast<std::size_t>(state.range(0)));
  const std::size_t count = m.size() / 100;
  std::mt19937_64 rng(1);
  std::vector<std::uint32_t> moved;
  if (state.range(1) == 0) {
    const std::size_t start = m.size() / 3;  // inside chain A of 1AF6, away from its ends
    for (std::size_t k = 0; k < count; ++k) moved.push_back(static_cast<std::uint32_t>(start + k));
  } else {
    for (std::size_t k = 0; k < count; ++k) moved.push_back(static_cast<std::uint32_t>(k * 100 + rng() % 100));
  }
  std::uniform_real_distribution<double> u(-0.3, 0.3);
  std::vector<glm::dvec3> home, away;
  for (const std::uint32_t a : moved) {
    home.push_back(m.centers[a]);
    away.push_back(m.centers[a] + glm::dvec3(u(rng), u(rng), u(rng)) * (1.0 / std::sqrt(3.0)));
  }
  SesBuilder builder;
  builder.build(m.centers, m.radii, SesParams{1.4});
  bool there = false;
  std::size_t owners = 0, contours = 0;
  for (auto _ : state) {
    there = !there;
    const auto& p = builder.update(moved, there ? away : home);
    benchmark::DoNotOptimize(p.patchCount());
    owners = builder.lastUpdate().owners;
    contours = builder.lastUpdate().contours;
  }
  state.counters["atoms"] = static_cast<double>(m.size());
  state.counters["moved"] = static_cast<double>(moved.size());
  state.counters["recomputed"] = static_cast<double>(std::max(owners, contours));
}

}  // namespace

BENCHMARK_CAPTURE(BM_BuildSes, 1vis, std::string("1vis.pdb.gz"))->Arg(1)->Arg(2)->Unit(benchmark::kMillisecond)->UseRealTime()->Repetitions(5)->ReportAggregatesOnly(true);
BENCHMARK_CAPTURE(BM_BuildSes, 1j4n, std::string("1j4n.pdb.gz"))->Arg(1)->Arg(2)->Unit(benchmark::kMillisecond)->UseRealTime()->Repetitions(5)->ReportAggregatesOnly(true);
BENCHMARK_CAPTURE(BM_BuildSes, 1af6, std::string("1af6.pdb.gz"))->Arg(1)->Arg(2)->Unit(benchmark::kMillisecond)->UseRealTime()->Repetitions(5)->ReportAggregatesOnly(true);
BENCHMARK_CAPTURE(BM_BuildSes, 1aon, std::string("1aon.pdb.gz"))->Arg(1)->Arg(2)->Unit(benchmark::kMillisecond)->UseRealTime()->Repetitions(5)->ReportAggregatesOnly(true);
BENCHMARK_CAPTURE(BM_TrajectorySes, 1af6, std::string("1af6.pdb.gz"))->Arg(1)->Arg(2)->Unit(benchmark::kMillisecond)->UseRealTime()->Repetitions(5)->ReportAggregatesOnly(true);
BENCHMARK_CAPTURE(BM_TrajectorySes, 1aon, std::string("1aon.pdb.gz"))->Arg(1)->Arg(2)->Unit(benchmark::kMillisecond)->UseRealTime()->Repetitions(5)->ReportAggregatesOnly(true);
BENCHMARK_CAPTURE(BM_UpdateSes, 1af6, std::string("1af6.pdb.gz"))
    ->ArgsProduct({{1, 2}, {0, 1}})
    ->ArgNames({"threads", "scattered"})
    ->Unit(benchmark::kMillisecond)
    ->UseRealTime()
    ->Repetitions(5)
    ->ReportAggregatesOnly(true);

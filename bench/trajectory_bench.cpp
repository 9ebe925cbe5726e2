// Dynamic surfaces frame after frame, as in Lindow et al. 2010, Table 3 (8 cores and a GTX 280:
// SES 110 / 33 / 20 frames/s for 1.2k / 4.5k / 6.5k atoms; MSS(0.5) 25 / 7-8 / 5-6 frames/s;
// partial updates with 500 of 4,500 atoms flexible 2.5x over full ones).
//
// Each iteration is one frame of a real MD trajectory (AdK DIMS: 3341 atoms, 98 frames; the
// cobrotoxin protein: 937 atoms, 3 frames), cycled through in order with one SurfaceBuilder, as
// `surftrace trajectory` does: read the frame, update the surface (every atom moved; or only
// the --flexible site, a partial update), and optionally ray-trace it with Embree on one shared
// device. Frames/s = items_per_second.
//   surftrace_trajectory_bench --benchmark_filter='Adk' --benchmark_repetitions=5 --benchmark_report_aggregates_only
#include <memory>
#include <string>
#include <vector>

#include <benchmark/benchmark.h>
#include <tbb/global_control.h>

#include "build/io/atom_selection.hpp"
#include "build/io/trajectory.hpp"
#include "build/surface.hpp"
#include "trace/patch_scene.hpp"
#include "trace/render.hpp"
#include "view/atom_colors.hpp"
#include "view/camera.hpp"

namespace {

using namespace surftrace;

const std::string kData = SURFTRACE_TEST_DATA;

struct Case {
  std::string topology, trajectory, site;
};
const Case kAdk{kData + "/trajectories/adk_dims/adk.psf.gz", kData + "/trajectories/adk_dims/adk_dims.dcd",
                "resid 122-135"};  // the LID domain's hinge, 7% of the atoms
const Case kCobrotoxin{kData + "/trajectories/cobrotoxin/cobrotoxin.pdb.gz",
                       kData + "/trajectories/cobrotoxin/cobrotoxin.xtc", "resid 25-35"};

// args: threads, surface (0 SES, 1 MSS s = 0.5), flexible site (0/1), image size (0: build only).
void BM_Trajectory(benchmark::State& state, const Case& c) {
  tbb::global_control threads(tbb::global_control::max_allowed_parallelism, static_cast<std::size_t>(state.range(0)));
  const bool mss = state.range(1) == 1, flexible = state.range(2) == 1;
  const int size = static_cast<int>(state.range(3));
  build::Trajectory t(c.topology, c.trajectory);
  const build::Molecule reference = t.molecule();
  const std::vector<std::uint32_t> site = flexible ? build::selectAtoms(reference, c.site) : std::vector<std::uint32_t>{};
  const build::SurfaceRequest request{mss ? build::SurfaceKind::Mss : build::SurfaceKind::Ses, 1.4, 0.5, false};
  build::SurfaceBuilder builder(request);
  build::Molecule current = reference;
  builder.build(current);
  view::RenderOptions ro;
  ro.camera.width = ro.camera.height = size > 0 ? size : 1;
  std::vector<double> reach(reference.radii);
  for (double& r : reach) r += 1.4;
  ro.camera = view::frameSpheres(ro.camera, reference.centers, reach, glm::dvec3(0, 0, -1));
  const auto colors = view::atomColors(reference, ro.color, glm::vec3(0.8f));
  const trace::EmbreeDevice device;
  std::size_t frame = 0, recomputed = 0, patches = 0;
  for (auto _ : state) {
    frame = (frame + 1) % t.frameCount();
    t.load(frame);
    if (flexible)
      for (std::uint32_t i : site) current.centers[i] = t.molecule().centers[i];
    else
      current.centers = t.molecule().centers;
    const build::PatchList list = flexible ? builder.update(current, site) : builder.update(current);
    recomputed += builder.lastRecomputed();
    patches = list.patchCount();
    if (size > 0) {
      const trace::PatchScene scene(trace::ScenePatches::fromPatchList(list), device);
      benchmark::DoNotOptimize(trace::render(scene, ro, colors).rays);
    }
  }
  state.SetItemsProcessed(state.iterations());
  state.counters["atoms"] = static_cast<double>(reference.size());
  state.counters["moved"] = static_cast<double>(flexible ? site.size() : reference.size());
  state.counters["recomputed"] = static_cast<double>(recomputed) / static_cast<double>(state.iterations());
  state.counters["patches"] = static_cast<double>(patches);
}

void arguments(benchmark::internal::Benchmark* b) {
  b->ArgNames({"threads", "mss", "flexible", "size"});
  for (int threads : {1, 2})
    for (int mss : {0, 1})
      for (int flexible : {0, 1}) b->Args({threads, mss, flexible, 0});
  for (int mss : {0, 1})
    for (int size : {512, 1024}) b->Args({2, mss, 0, size});
  b->Unit(benchmark::kMillisecond)->UseRealTime()->MinTime(1.0);
}

BENCHMARK_CAPTURE(BM_Trajectory, Adk, kAdk)->Apply(arguments);
BENCHMARK_CAPTURE(BM_Trajectory, Cobrotoxin, kCobrotoxin)->Apply(arguments);

}  // namespace

// Embree reference renderer: scene build and frame time at 1024×1024, one sample per pixel,
// for the paper's molecules: the SES, the molecular skin at s = 0.5 and 0.3 (Lindow et al.
// 2010, Table 2), and, as a spheres-only lower bound, the vdW surface; and the image-space
// effects' cost against the frame (BM_Effects).
#include <chrono>
#include <map>
#include <memory>
#include <string>

#include <benchmark/benchmark.h>
#include <tbb/global_control.h>

#include "build/atom_spheres.hpp"
#include "build/mss/mss_builder.hpp"
#include "build/ses/contour_buildup.hpp"
#include "build/io/molecule.hpp"
#include "trace/render.hpp"
#include "view/image_effects.hpp"

namespace {

using namespace surftrace;

struct Prepared {
  build::Molecule molecule;
  build::PatchList vdw, ses, skin05, skin03;  // range(1) = 0, 1, 2, 3
  const build::PatchList& surface(std::int64_t k) const {
    return k == 0 ? vdw : k == 1 ? ses : k == 2 ? skin05 : skin03;
  }
};

const Prepared& prepared(const std::string& name) {
  static std::map<std::string, Prepared> cache;
  auto it = cache.find(name);
  if (it == cache.end()) {
    Prepared p;
    p.molecule = build::readMolecule(std::string(SURFTRACE_TEST_DATA) + "/paper/" + name);
    p.ses = build::buildSes(p.molecule.centers, p.molecule.radii, build::SesParams{1.4});
    p.vdw = build::atomSpheres(p.molecule.centers, p.molecule.radii, 0.0, build::SurfaceKind::Vdw);
    p.skin05 = build::buildMss(p.molecule.centers, p.molecule.radii, build::MssParams{0.5});
    p.skin03 = build::buildMss(p.molecule.centers, p.molecule.radii, build::MssParams{0.3});
    it = cache.emplace(name, std::move(p)).first;
  }
  return it->second;
}

trace::ScenePatches patchesFor(const Prepared& p, std::int64_t surface) {
  return trace::ScenePatches::fromPatchList(p.surface(surface));
}

view::Camera frontCamera(const Prepared& p, int size) {
  view::Camera c;
  c.width = c.height = size;
  std::vector<double> reach(p.molecule.radii);
  for (double& r : reach) r += 1.4;
  return view::frameSpheres(c, p.molecule.centers, reach, view::namedViewDirection("front"));
}

// range(0): threads; range(1): 0 vdW, 1 SES, 2 MSS at s = 0.5, 3 MSS at s = 0.3. Every surface
// is seen by the same camera (framed on the atoms grown by 1.4 Å).
void BM_SceneBuild(benchmark::State& state, const std::string& name) {
  const Prepared& p = prepared(name);
  tbb::global_control threads(tbb::global_control::max_allowed_parallelism, static_cast<std::size_t>(state.range(0)));
  for (auto _ : state) {
    trace::PatchScene scene(patchesFor(p, state.range(1)));
    benchmark::DoNotOptimize(scene.buildSeconds());
  }
}

void BM_Frame(benchmark::State& state, const std::string& name) {
  const Prepared& p = prepared(name);
  tbb::global_control threads(tbb::global_control::max_allowed_parallelism, static_cast<std::size_t>(state.range(0)));
  const trace::PatchScene scene(patchesFor(p, state.range(1)));
  view::RenderOptions o;
  o.camera = frontCamera(p, 1024);
  std::size_t rays = 0;
  for (auto _ : state) {
    const view::FrameBuffers f = trace::render(scene, o, {});
    rays = f.rays;
    benchmark::DoNotOptimize(f.depth.data());
  }
  state.counters["rays_per_s"] = benchmark::Counter(static_cast<double>(rays), benchmark::Counter::kIsIterationInvariantRate);
  state.counters["patches"] = static_cast<double>(scene.patches().size());
}

// The image-space effects on a 1024² SES frame, after the engine: range(0) threads, range(1)
// 0 none (a copy of the frame, the floor), 1 silhouettes, 2 silhouettes + creases, 3 depth
// darkening, 4 depth cueing, 5 all. Counter frame_ms: the frame's time (rendered once here,
// same threads), to divide the effect's time by; restoring the colour (effect 0) is in every row.
void BM_Effects(benchmark::State& state, const std::string& name) {
  const Prepared& p = prepared(name);
  tbb::global_control threads(tbb::global_control::max_allowed_parallelism, static_cast<std::size_t>(state.range(0)));
  const trace::PatchScene scene(patchesFor(p, 1));
  view::RenderOptions o;
  o.camera = frontCamera(p, 1024);
  const auto start = std::chrono::steady_clock::now();
  const view::FrameBuffers frame = trace::render(scene, o, {});
  const double frameSeconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  view::ImageEffects e;
  const std::int64_t k = state.range(1);
  e.silhouettes = k == 1 || k == 2 || k == 5;
  e.creaseAngle = k == 2 || k == 5 ? 60.0 : 0.0;
  e.depthDarkening = k == 3 || k == 5;
  e.depthCue = k == 4 || k == 5;
  view::FrameBuffers f = frame;
  for (auto _ : state) {
    f.rgba = frame.rgba;  // the colour the effects change: 16 MB, in every row (effect 0 alone)
    view::applyImageEffects(f, e, o.camera, o.background);
    benchmark::DoNotOptimize(f.rgba.data());
  }
  state.counters["frame_ms"] = 1e3 * frameSeconds;
}

}  // namespace

BENCHMARK_CAPTURE(BM_Effects, 1vis, std::string("1vis.pdb.gz"))
    ->ArgsProduct({{2}, {0, 1, 2, 3, 4, 5}})->ArgNames({"threads", "effect"})
    ->Unit(benchmark::kMillisecond)->UseRealTime()->Repetitions(5)->ReportAggregatesOnly(true);
BENCHMARK_CAPTURE(BM_Effects, 1aon, std::string("1aon.pdb.gz"))
    ->ArgsProduct({{2}, {0, 1, 2, 3, 4, 5}})->ArgNames({"threads", "effect"})
    ->Unit(benchmark::kMillisecond)->UseRealTime()->Repetitions(5)->ReportAggregatesOnly(true);

#define SURFTRACE_RENDER_BENCH(name, file)                                                                 \
  BENCHMARK_CAPTURE(BM_SceneBuild, name, std::string(file))                                                \
      ->ArgsProduct({{1, 2}, {0, 1, 2, 3}})->ArgNames({"threads", "surface"})                                        \
      ->Unit(benchmark::kMillisecond)->UseRealTime()->Repetitions(5)->ReportAggregatesOnly(true);          \
  BENCHMARK_CAPTURE(BM_Frame, name, std::string(file))                                                     \
      ->ArgsProduct({{1, 2}, {0, 1, 2, 3}})->ArgNames({"threads", "surface"})                                        \
      ->Unit(benchmark::kMillisecond)->UseRealTime()->Iterations(1)->Repetitions(5)->ReportAggregatesOnly(true)

SURFTRACE_RENDER_BENCH(1vis, "1vis.pdb.gz");
SURFTRACE_RENDER_BENCH(1af6, "1af6.pdb.gz");
SURFTRACE_RENDER_BENCH(1aon, "1aon.pdb.gz");

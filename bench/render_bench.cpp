// Embree reference renderer: scene build and frame time at 1024×1024, one sample per pixel,
// for the paper's molecules: the SES, the molecular skin at s = 0.5 and 0.3 (Lindow et al.
// 2010, Table 2), and, as a spheres-only lower bound, the vdW surface.
#include <map>
#include <memory>
#include <string>

#include <benchmark/benchmark.h>
#include <tbb/global_control.h>

#include "build/mss/mss_builder.hpp"
#include "build/ses/contour_buildup.hpp"
#include "build/io/molecule.hpp"
#include "trace/render.hpp"

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

}  // namespace

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

// surftrace_frame_bench: the Embree frame of a patch list (.stp from `surftrace build`), opaque
// or transparent, frame after frame in one process, each frame's wall time and the process's
// CPU time over it (user + system, every thread). On a shared machine the CPU time is the figure
// that survives the load; reading the list and building the scene are left out of both.
#include <sys/resource.h>

#include <algorithm>
#include <chrono>
#include <cstdio>
#include <exception>
#include <string>
#include <vector>

#include <CLI/CLI.hpp>
#include <tbb/global_control.h>

#include "build/io/molecule.hpp"
#include "build/io/stp_file.hpp"
#include "trace/patch_scene.hpp"
#include "trace/render.hpp"
#include "view/camera.hpp"

namespace {

double cpuSeconds() {
  rusage u{};
  getrusage(RUSAGE_SELF, &u);
  return static_cast<double>(u.ru_utime.tv_sec + u.ru_stime.tv_sec) +
         1e-6 * static_cast<double>(u.ru_utime.tv_usec + u.ru_stime.tv_usec);
}

double median(std::vector<double> v) {
  std::sort(v.begin(), v.end());
  const std::size_t n = v.size();
  return n % 2 == 1 ? v[n / 2] : 0.5 * (v[n / 2 - 1] + v[n / 2]);
}

}  // namespace

int main(int argc, char** argv) {
  using namespace surftrace;
  CLI::App app{"Embree frame times (wall and CPU) of a patch list, opaque or transparent"};
  std::string structure, patchesPath, view = "front";
  int size = 1024, frames = 5, threads = 2, maxLayers = 16;
  double opacity = 1.0;
  app.add_option("structure", structure,
                 "the structure the list was built from: its atoms frame the camera (radius + 1.4 Å) and clip the "
                 "spheres of a transparent SES")
      ->required();
  app.add_option("patches", patchesPath, "patch list (.stp) from `surftrace build`")->required();
  app.add_option("--size", size, "image width and height in pixels")->capture_default_str();
  app.add_option("--frames", frames, "timed frames")->capture_default_str();
  app.add_option("--threads", threads, "worker threads")->capture_default_str();
  app.add_option("--opacity", opacity, "surface opacity in (0, 1]")->capture_default_str();
  app.add_option("--max-layers", maxLayers, "with --opacity below 1: the most layers")->capture_default_str();
  app.add_option("--view", view, "front, back, left, right, top, bottom or x,y,z")->capture_default_str();
  CLI11_PARSE(app, argc, argv);
  try {
    const build::Molecule molecule = build::readMolecule(structure);
    const build::PatchList list = build::readPatchList(patchesPath);
    tbb::global_control limit(tbb::global_control::max_allowed_parallelism, static_cast<std::size_t>(threads));
    view::RenderOptions options;
    options.camera.width = options.camera.height = size;
    options.opacity = opacity;
    options.maxLayers = maxLayers;
    std::vector<double> reach(molecule.radii);
    for (double& r : reach) r += 1.4;
    options.camera = view::frameSpheres(options.camera, molecule.centers, reach, view::namedViewDirection(view));
    // As the Embree engine makes it: a transparent frame with every atom gets them for its spheres' clip.
    const bool transparent = opacity < 1.0 && molecule.size() == list.params.atomCount;
    const trace::PatchScene scene(transparent ? trace::ScenePatches::fromPatchList(list, molecule.centers, molecule.radii)
                                              : trace::ScenePatches::fromPatchList(list));
    std::vector<double> wall, cpu;
    for (int f = 0; f < frames; ++f) {
      const double cpu0 = cpuSeconds();
      const auto t0 = std::chrono::steady_clock::now();
      const view::FrameBuffers frame = trace::render(scene, options, {});
      wall.push_back(std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count());
      cpu.push_back(cpuSeconds() - cpu0);
      std::printf("frame %d: wall %.1f ms, cpu %.1f ms, %zu rays\n", f, 1e3 * wall.back(), 1e3 * cpu.back(), frame.rays);
    }
    std::printf("{\"patches\": \"%s\", \"size\": %d, \"threads\": %d, \"opacity\": %g, \"max_layers\": %d, \"frames\": %d, "
                "\"median_wall_ms\": %.1f, \"median_cpu_ms\": %.1f}\n",
                patchesPath.c_str(), size, threads, opacity, maxLayers, frames, 1e3 * median(wall), 1e3 * median(cpu));
    return 0;
  } catch (const std::exception& e) {
    std::fprintf(stderr, "surftrace_frame_bench: %s\n", e.what());
    return 1;
  }
}

// surftrace_gl_bench: median GL frame time of a patch list (or a structure, built as SES first).
#include <chrono>
#include <cstdio>
#include <exception>
#include <string>

#include <CLI/CLI.hpp>

#include "build/ses/contour_buildup.hpp"
#include "build/io/molecule.hpp"
#include "build/patch_list.hpp"
#include "gl/gl_context.hpp"
#include "gl/gl_renderer.hpp"
#include "view/camera.hpp"

namespace {

bool endsWith(const std::string& s, const std::string& suffix) {
  return s.size() >= suffix.size() && s.compare(s.size() - suffix.size(), suffix.size(), suffix) == 0;
}

}  // namespace

int main(int argc, char** argv) {
  using namespace surftrace;
  CLI::App app{"Median GL frame time of a patch list (.stp) or of a structure's SES"};
  std::string input, method = "quartic", view = "front", projection = "perspective", primitive = "box";
  int size = 1024, frames = 10, steps = 30;
  double probe = 1.4;
  app.add_option("input", input, "patch list (.stp) or structure file (PDB, mmCIF, PQR, XYZR, XYZ)")->required();
  app.add_option("--size", size, "image width and height in pixels")->capture_default_str();
  app.add_option("--frames", frames, "timed frames")->capture_default_str();
  app.add_option("--method", method, "torus intersection: quartic | sphere-tracing")->capture_default_str();
  app.add_option("--primitive", primitive, "torus/concave rasterisation primitive: box | cylinder (the paper's)")->capture_default_str();
  app.add_option("--steps", steps, "sphere-tracing steps")->capture_default_str();
  app.add_option("--probe", probe, "probe radius when building from a structure (Å)")->capture_default_str();
  app.add_option("--view", view, "front, back, left, right, top, bottom or x,y,z")->capture_default_str();
  app.add_option("--projection", projection, "perspective | orthographic")->capture_default_str();
  CLI11_PARSE(app, argc, argv);
  try {
    build::PatchList patches;
    double buildSeconds = 0.0;
    if (endsWith(input, ".stp")) {
      patches = build::readPatchList(input);
    } else {
      const build::Molecule molecule = build::readMolecule(input);
      const auto t0 = std::chrono::steady_clock::now();
      patches = build::buildSes(molecule.centers, molecule.radii, build::SesParams{probe});
      buildSeconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
    }
    view::RenderOptions options;
    options.camera.width = options.camera.height = size;
    if (projection == "orthographic") {
      options.camera.projection = view::Projection::Orthographic;
    } else if (projection != "perspective") {
      throw std::invalid_argument("unknown projection '" + projection + "'");
    }
    options.camera = view::frameSpheres(options.camera, patches.convex.center, patches.convex.radius,
                                         view::namedViewDirection(view));
    gl::GlOptions glOptions;
    glOptions.torus = gl::parseTorusMethod(method);
    glOptions.primitive = gl::parsePrimitive(primitive);
    glOptions.maxSteps = steps;
    const gl::GlContext context;
    const gl::GlTimings t = gl::benchmarkGl(context, patches, options, {}, glOptions, frames);
    std::printf(
        "{\"input\": \"%s\", \"renderer\": \"%s\", \"size\": %d, \"method\": \"%s\", \"primitive\": \"%s\", \"spheres\": %zu, \"tori\": %zu, "
        "\"concave\": %zu, \"build_s\": %.3f, \"frames\": %d, \"median_frame_s\": %.5f, \"median_draw_s\": %.5f, "
        "\"min_draw_s\": %.5f, \"fps\": %.2f}\n",
        input.c_str(), t.renderer.c_str(), size, method.c_str(), primitive.c_str(), patches.convex.size(), patches.tori.size(),
        patches.concave.size(), buildSeconds, t.frames, t.medianFrameSeconds, t.medianDrawSeconds, t.minDrawSeconds,
        1.0 / t.medianFrameSeconds);
    return 0;
  } catch (const std::exception& e) {
    std::fprintf(stderr, "surftrace_gl_bench: %s\n", e.what());
    return 1;
  }
}

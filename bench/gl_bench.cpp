// surftrace_gl_bench: median GL frame time of a patch list (or a structure, built as the SES or
// the skin first), and with --count-fragments the fragments each kind's primitive makes the
// fragment shader run against the ones that hit the patch (the primitive's overdraw).
#include <chrono>
#include <cstdio>
#include <exception>
#include <cstdint>
#include <string>
#include <vector>

#include <CLI/CLI.hpp>

#include "build/io/molecule.hpp"
#include "build/io/stp_file.hpp"
#include "build/surface.hpp"
#include "build/patch_list.hpp"
#include "gl/gl_context.hpp"
#include "gl/gl_renderer.hpp"
#include "view/camera.hpp"
#include "view/patch_kind.hpp"

namespace {

bool endsWith(const std::string& s, const std::string& suffix) {
  return s.size() >= suffix.size() && s.compare(s.size() - suffix.size(), suffix.size(), suffix) == 0;
}

}  // namespace

int main(int argc, char** argv) {
  using namespace surftrace;
  CLI::App app{"Median GL frame time of a patch list (.stp) or of a structure's SES or skin"};
  std::string input, method = "quartic", view = "front", projection = "perspective", primitive = "box", surface = "ses";
  int size = 1024, frames = 10, steps = 30;
  double probe = 1.4, shrink = 0.5;
  bool countFragments = false;
  app.add_option("input", input, "patch list (.stp) or structure file (PDB, mmCIF, PQR, XYZR, XYZ)")->required();
  app.add_option("--size", size, "image width and height in pixels")->capture_default_str();
  app.add_option("--frames", frames, "timed frames")->capture_default_str();
  app.add_option("--method", method, "torus intersection: quartic | sphere-tracing")->capture_default_str();
  app.add_option("--primitive", primitive, "torus/concave rasterisation primitive: box | cylinder (the paper's)")->capture_default_str();
  app.add_option("--steps", steps, "sphere-tracing steps")->capture_default_str();
  app.add_option("--probe", probe, "probe radius when building from a structure (Å)")->capture_default_str();
  app.add_option("--surface", surface, "surface to build from a structure: ses | mss")->capture_default_str();
  app.add_option("--shrink", shrink, "MSS shrink factor when building from a structure")->capture_default_str();
  app.add_flag("--count-fragments", countFragments, "also report fragments shaded and hits per patch kind (one more frame)");
  app.add_option("--view", view, "front, back, left, right, top, bottom or x,y,z")->capture_default_str();
  app.add_option("--projection", projection, "perspective | orthographic")->capture_default_str();
  double opacity = 1.0;
  int maxLayers = 16;
  app.add_option("--opacity", opacity, "surface opacity in (0, 1]: below 1 the frame peels its layers")->capture_default_str();
  app.add_option("--max-layers", maxLayers, "with --opacity below 1: the most layers peeled")->capture_default_str();
  CLI11_PARSE(app, argc, argv);
  try {
    build::PatchList patches;
    std::vector<glm::dvec4> atoms;  // every atom, for the spheres' blockers (transparency)
    double buildSeconds = 0.0;
    if (endsWith(input, ".stp")) {
      patches = build::readPatchList(input);
    } else {
      const build::Molecule molecule = build::readMolecule(input);
      const auto t0 = std::chrono::steady_clock::now();
      patches = build::buildSurface(molecule, {build::parseSurfaceKind(surface), probe, shrink, false});
      buildSeconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
      for (std::size_t i = 0; i < molecule.size(); ++i) atoms.push_back(glm::dvec4(molecule.centers[i], molecule.radii[i]));
    }
    view::RenderOptions options;
    options.camera.width = options.camera.height = size;
    options.opacity = opacity;
    options.maxLayers = maxLayers;
    if (projection == "orthographic") {
      options.camera.projection = view::Projection::Orthographic;
    } else if (projection != "perspective") {
      throw std::invalid_argument("unknown projection '" + projection + "'");
    }
    const bool skin = patches.params.surface == build::SurfaceKind::Mss;
    options.camera = view::frameSpheres(options.camera, skin ? patches.mss.center : patches.convex.center,
                                         skin ? patches.mss.boundRadius : patches.convex.radius,
                                         view::namedViewDirection(view));
    gl::GlOptions glOptions;
    glOptions.torus = gl::parseTorusMethod(method);
    glOptions.primitive = gl::parsePrimitive(primitive);
    glOptions.maxSteps = steps;
    const gl::GlContext context;
    const build::SphereBlockers blockers = build::sphereBlockers(patches, atoms);
    const gl::GlTimings t = gl::benchmarkGl(context, patches, options, {}, glOptions, frames, &blockers);
    std::string fragmentStats;
    if (countFragments) {
      gl::GlOptions counted = glOptions;
      counted.countFragments = true;
      gl::GlRenderer renderer(context);
      renderer.upload(patches, options.camera.lookAt);
      renderer.draw(options, {}, counted);
      const std::vector<glm::uvec2> counts = renderer.fragmentCounts();
      const view::PatchIdOrder ids(patches);
      for (const view::PatchKindInfo& k : view::kPatchKinds) {
        std::uint64_t shaded = 0, hits = 0;
        for (std::uint32_t i = 0; i < ids.count(k.kind); ++i) {
          shaded += counts[ids.globalId(k.kind, i)].x;
          hits += counts[ids.globalId(k.kind, i)].y;
        }
        if (ids.count(k.kind) == 0) continue;
        fragmentStats += ", \"" + std::string(k.name) + "\": {\"fragments\": " + std::to_string(shaded) +
                         ", \"hits\": " + std::to_string(hits) + "}";
      }
    }
    std::printf(
        "{\"input\": \"%s\", \"renderer\": \"%s\", \"size\": %d, \"method\": \"%s\", \"primitive\": \"%s\", \"spheres\": %zu, \"tori\": %zu, "
        "\"concave\": %zu, \"build_s\": %.3f, \"frames\": %d, \"median_frame_s\": %.5f, \"median_draw_s\": %.5f, "
        "\"min_draw_s\": %.5f, \"fps\": %.2f, \"opacity\": %g, \"peel_passes\": %d%s}\n",
        input.c_str(), t.renderer.c_str(), size, method.c_str(), primitive.c_str(), patches.convex.size(), patches.tori.size(),
        patches.concave.size(), buildSeconds, t.frames, t.medianFrameSeconds, t.medianDrawSeconds, t.minDrawSeconds,
        1.0 / t.medianFrameSeconds, opacity, t.peelPasses, fragmentStats.c_str());
    return 0;
  } catch (const std::exception& e) {
    std::fprintf(stderr, "surftrace_gl_bench: %s\n", e.what());
    return 1;
  }
}

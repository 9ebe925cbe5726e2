// Image options shared by `render` and `trajectory` (image_options.hpp).
#include "image_options.hpp"

#include <unistd.h>

#include <cmath>
#include <cstdio>
#include <sstream>
#include <stdexcept>
#include <vector>

#include "option_checks.hpp"
#include "view/camera.hpp"

namespace surftrace::tools {
namespace {

glm::vec3 parseColor(const std::string& option, const std::string& text) {
  const glm::dvec3 c = parseVector(option, text);
  if (c.x < 0 || c.y < 0 || c.z < 0 || c.x > 1 || c.y > 1 || c.z > 1)
    throw std::invalid_argument(option + " '" + text + "': colour components must be in [0, 1]");
  return glm::vec3(c);
}

void parseSize(const std::string& text, int& width, int& height) {
  std::istringstream in(text);
  char x = 0;
  if (!(in >> width >> x >> height) || (x != 'x' && x != 'X') || in.peek() != EOF || width < 1 || height < 1 ||
      width > 32768 || height > 32768)
    throw std::invalid_argument("--size '" + text + "': expected WIDTHxHEIGHT, each 1..32768, e.g. 1024x768");
}

void applyExplicitCamera(ImageSetup& setup) {
  view::Camera& camera = setup.render.camera;
  if (setup.lookAt) camera.lookAt = *setup.lookAt;
  if (setup.eye) camera.eye = *setup.eye;
  if (setup.up) camera.up = *setup.up;
  camera.validate();
}

}  // namespace

glm::dvec3 parseVector(const std::string& option, const std::string& text) {
  std::istringstream in(text);
  glm::dvec3 v;
  char c1 = 0, c2 = 0;
  if (!(in >> v.x >> c1 >> v.y >> c2 >> v.z) || c1 != ',' || c2 != ',' || in.peek() != EOF || !std::isfinite(v.x) ||
      !std::isfinite(v.y) || !std::isfinite(v.z))
    throw std::invalid_argument(option + " '" + text + "': expected three finite numbers x,y,z");
  return v;
}

void addImageOptions(CLI::App& cmd, ImageOptions& o) {
  cmd.add_option("--size", o.size, "Image size WIDTHxHEIGHT")->default_val("1024x1024");
  cmd.add_option("--view", o.view,
                 "Direction to look along for automatic framing: front (−z), back, left, right, top, bottom, or x,y,z")
      ->default_val("front");
  cmd.add_option("--eye", o.eye, "Explicit eye position x,y,z (Å); overrides the framing's eye");
  cmd.add_option("--look-at", o.lookAt, "Explicit look-at point x,y,z (Å)");
  cmd.add_option("--up", o.up, "Explicit up vector x,y,z");
  cmd.add_option("--fov", o.fov, "Vertical field of view in degrees (perspective)")->default_val(30.0);
  cmd.add_flag("--ortho", o.ortho, "Orthographic projection (framed to fit the molecule)");
  cmd.add_option("--color", o.color, "Colouring: patch (SES: convex green, toroidal yellow, concave red; MSS: "
                                     "convex green, edge hyperboloids red, face ones yellow, concave blue), element, "
                                     "chain, bfactor, uniform")
      ->check(CLI::IsMember({"patch", "element", "chain", "bfactor", "uniform"}))
      ->default_val("patch");
  cmd.add_option("--uniform-color", o.uniformColor, "Colour r,g,b in [0,1] for --color uniform")
      ->default_val("0.8,0.8,0.8");
  cmd.add_option("--background", o.background, "Background colour r,g,b in [0,1]")->default_val("1,1,1");
  cmd.add_option("--spp", o.spp, "Samples per pixel for anti-aliasing (a k×k grid; buffers use the pixel centre)")
      ->check(wholeIn(1, 1024))
      ->default_val(1);
  cmd.add_flag("--shadows", o.shadows, "Ray-traced shadows from a key light above-left of the eye");
  cmd.add_option("--ao", o.ao, "Ambient-occlusion rays per pixel (0 = off)")->check(wholeIn(0, 4096))->default_val(0);
  cmd.add_option("--ao-distance", o.aoDistance, "Ambient-occlusion ray length in Å")
      ->check(positive())
      ->default_val(8.0);
}

ImageSetup resolveImageOptions(const ImageOptions& o) {
  ImageSetup setup;
  view::RenderOptions& ro = setup.render;
  parseSize(o.size, ro.camera.width, ro.camera.height);
  ro.camera.projection = o.ortho ? view::Projection::Orthographic : view::Projection::Perspective;
  ro.camera.fovY = o.fov;
  ro.color = view::parseColorMode(o.color);
  ro.background = parseColor("--background", o.background);
  setup.uniformColor = parseColor("--uniform-color", o.uniformColor);
  ro.samplesPerPixel = o.spp;
  ro.shadows = o.shadows;
  ro.aoSamples = o.ao;
  ro.aoDistance = o.aoDistance;
  setup.viewDirection = view::namedViewDirection(o.view);
  if (!(o.fov > 0.0 && o.fov < 180.0))
    throw std::invalid_argument("--fov " + std::to_string(o.fov) + ": the field of view must be in (0, 180) degrees");
  if (!o.eye.empty()) setup.eye = parseVector("--eye", o.eye);
  if (!o.lookAt.empty()) setup.lookAt = parseVector("--look-at", o.lookAt);
  if (!o.up.empty()) setup.up = parseVector("--up", o.up);
  return setup;
}

void frameSurface(ImageSetup& setup, const build::PatchList& list, const build::Molecule& molecule) {
  view::Camera& camera = setup.render.camera;
  if (list.params.surface == build::SurfaceKind::Mss) {
    camera = view::frameSpheres(camera, list.mss.center, list.mss.boundRadius, setup.viewDirection);
  } else {
    std::vector<double> reach(molecule.radii);
    if (list.params.surface != build::SurfaceKind::Vdw)
      for (double& r : reach) r += list.params.probeRadius;
    camera = view::frameSpheres(camera, molecule.centers, reach, setup.viewDirection);
  }
  applyExplicitCamera(setup);
}

void frameSpheres(ImageSetup& setup, std::span<const glm::dvec3> centers, std::span<const double> reach) {
  setup.render.camera = view::frameSpheres(setup.render.camera, centers, reach, setup.viewDirection);
  applyExplicitCamera(setup);
}

view::SphereFraming framingOf(const ImageSetup& setup) {
  return view::SphereFraming(setup.render.camera, setup.viewDirection);
}

void frameSpheres(ImageSetup& setup, const view::SphereFraming& framing) {
  setup.render.camera = framing.frame(setup.render.camera);
  applyExplicitCamera(setup);
}

ProgressBar::ProgressBar(bool enabled, std::string label)
    : enabled_(enabled && isatty(STDERR_FILENO)), label_(std::move(label)) {}

void ProgressBar::update(double fraction) {
  if (!enabled_) return;
  std::lock_guard lock(mutex_);
  const int percent = static_cast<int>(100.0 * fraction);
  if (percent <= last_) return;
  last_ = percent;
  const int bars = percent / 4;
  std::fprintf(stderr, "\r%s [%-25s] %3d%%", label_.c_str(), std::string(static_cast<std::size_t>(bars), '#').c_str(),
               percent);
  if (percent >= 100) std::fprintf(stderr, "\n");
}

void ProgressBar::items(std::size_t done, std::size_t total, const char* unit) {
  if (!enabled_ || total == 0) return;
  std::lock_guard lock(mutex_);
  const double seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start_).count();
  const double rate = seconds > 0.0 ? static_cast<double>(done) / seconds : 0.0;
  const double left = rate > 0.0 ? static_cast<double>(total - done) / rate : 0.0;
  const int bars = static_cast<int>(25 * done / total);
  std::fprintf(stderr, "\r%s [%-25s] %zu/%zu %s, %.1f %s/s, ETA %02d:%02d ", label_.c_str(),
               std::string(static_cast<std::size_t>(bars), '#').c_str(), done, total, unit, rate, unit,
               static_cast<int>(left) / 60, static_cast<int>(left) % 60);
  if (done >= total) std::fprintf(stderr, "\n");
}

}  // namespace surftrace::tools

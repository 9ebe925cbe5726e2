// Image options shared by `render` and `trajectory` (image_options.hpp).
#include "image_options.hpp"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <sstream>
#include <stdexcept>
#include <vector>

#include <nlohmann/json.hpp>

#include "option_checks.hpp"
#include "surftrace/files.hpp"

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

view::Camera readCameraFile(const std::string& path) { return readCamera(path, "--camera " + path); }

void addEffectOptions(CLI::App& cmd, ImageOptions& o) {
  const char* group = "Image-space effects (both engines; from the pixel-centre buffers)";
  cmd.add_flag("--silhouettes", o.silhouettes,
               "Draw silhouette lines: on the nearer side of every depth jump larger than --silhouette-depth-jump "
               "and of the outline against the background")
      ->group(group);
  cmd.add_option("--silhouette-width", o.silhouetteWidth, "Silhouette and crease line width in pixels")
      ->check(wholeIn(1, 64))
      ->default_val(2)
      ->group(group);
  cmd.add_option("--silhouette-color", o.silhouetteColor, "Silhouette and crease line colour r,g,b in [0,1]")
      ->default_val("0,0,0")
      ->group(group);
  cmd.add_option("--silhouette-depth-jump", o.silhouetteJump,
                 "Smallest jump in view depth (Å) within the line width that makes a silhouette")
      ->check(numberIn(0, HUGE_VAL))
      ->default_val(2.0)
      ->group(group);
  cmd.add_option("--crease-angle", o.creaseAngle,
                 "Draw crease lines where the normal turns by more than this many degrees within the line width on "
                 "one surface (0 = no creases)")
      ->check(numberIn(0, 179))
      ->default_val(0.0)
      ->group(group);
  cmd.add_flag("--depth-darkening", o.depthDarkening,
               "Darken what lies behind its surroundings: unsharp masking of the depth buffer (Luft, Colditz, "
               "Deussen 2006), colour + strength·min(0, G∗D − D), D in Å")
      ->group(group);
  cmd.add_option("--depth-darkening-sigma", o.darkeningSigma, "Depth darkening: the Gaussian's σ in pixels")
      ->check(numberIn(0.1, 256))
      ->default_val(8.0)
      ->group(group);
  cmd.add_option("--depth-darkening-strength", o.darkeningStrength,
                 "Depth darkening: λ, the colour removed per Å that a pixel lies behind its surroundings")
      ->check(numberIn(0, HUGE_VAL))
      ->default_val(0.03)
      ->group(group);
  cmd.add_flag("--depth-cue", o.depthCue,
               "Depth-dependent lighting: fade surfaces linearly towards the background with view depth, from "
               "none at --depth-cue-start to --depth-cue-strength at --depth-cue-end")
      ->group(group);
  cmd.add_option("--depth-cue-strength", o.depthCueStrength, "Depth cueing: the background's share at the far end")
      ->check(numberIn(0, 1))
      ->default_val(0.6)
      ->group(group);
  cmd.add_option("--depth-cue-start", o.depthCueStart,
                 "Depth cueing: view depth (Å from the eye) where the fading starts (default: the camera's near "
                 "plane, tight around the scene)")
      ->check(numberIn(0, HUGE_VAL))
      ->group(group);
  cmd.add_option("--depth-cue-end", o.depthCueEnd,
                 "Depth cueing: view depth (Å) of full strength (default: the camera's far plane)")
      ->check(numberIn(0, HUGE_VAL))
      ->group(group);
}

}  // namespace

view::ImageEffects resolveEffects(const ImageOptions& o) {
  view::ImageEffects e;
  e.silhouettes = o.silhouettes;
  e.lineWidth = o.silhouetteWidth;
  e.lineColor = parseColor("--silhouette-color", o.silhouetteColor);
  e.silhouetteJump = o.silhouetteJump;
  e.creaseAngle = o.creaseAngle;
  e.depthDarkening = o.depthDarkening;
  e.darkeningSigma = o.darkeningSigma;
  e.darkeningStrength = o.darkeningStrength;
  e.depthCue = o.depthCue;
  e.depthCueStrength = o.depthCueStrength;
  e.depthCueStart = o.depthCueStart;
  e.depthCueEnd = o.depthCueEnd;
  if (e.depthCueStart && e.depthCueEnd && !(*e.depthCueEnd > *e.depthCueStart))
    throw std::invalid_argument("--depth-cue-end must lie beyond --depth-cue-start");
  e.validate();
  return e;
}

glm::dvec3 parseVector(const std::string& option, const std::string& text) {
  std::istringstream in(text);
  glm::dvec3 v;
  char c1 = 0, c2 = 0;
  if (!(in >> v.x >> c1 >> v.y >> c2 >> v.z) || c1 != ',' || c2 != ',' || in.peek() != EOF || !std::isfinite(v.x) ||
      !std::isfinite(v.y) || !std::isfinite(v.z))
    throw std::invalid_argument(option + " '" + text + "': expected three finite numbers x,y,z");
  return v;
}

namespace {
// --ball-and-stick and its sizes (pipeline.hpp: BallAndStick).
void addBallAndStickOptions(CLI::App& cmd, ImageOptions& o) {
  cmd.add_flag("--ball-and-stick", o.ballAndStick,
               "Draw the atoms as balls and their covalent bonds (the file's CONECT records, else distance: "
               "d < r_cov,i + r_cov,j + 0.4 Å) as sticks, opaque, with the surface: under it with --opacity < 1 "
               "(Lindow et al. 2010, Fig. 9 right), alone with --opacity 0");
  cmd.add_option("--ball-scale", o.ballScale, "With --ball-and-stick: a ball's radius over its atom's radius (> 0)")
      ->check(positive())
      ->default_val(0.25);
  cmd.add_option("--stick-radius", o.stickRadius,
                 "With --ball-and-stick: the sticks' radius in Å (> 0); each half takes its atom's colour")
      ->check(positive())
      ->default_val(0.15);
}
}  // namespace

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
  cmd.add_option("--spp", o.spp,
                 "Anti-aliasing: colour samples per pixel, rounded up to a k×k grid (2 to 4 take 2×2 = 4 samples, 5 "
                 "to 9 take 3×3 = 9); the buffers (depth, normal, ids) keep the pixel centre's")
      ->check(wholeIn(1, 1024))
      ->default_val(1);
  cmd.add_flag("--shadows", o.shadows, "Ray-traced shadows from a key light above-left of the eye");
  cmd.add_option("--ao", o.ao, "Ambient-occlusion rays per pixel (0 = off)")->check(wholeIn(0, 4096))->default_val(0);
  cmd.add_option("--ao-distance", o.aoDistance, "Ambient-occlusion ray length in Å")
      ->check(positive())
      ->default_val(8.0);
  cmd.add_option("--opacity", o.opacity,
                 "Surface opacity in [0, 1]: below 1 every layer the ray crosses (up to --max-layers, nearest first) "
                 "is blended front to back over the background (engine embree exactly; engine gl by depth peeling); "
                 "0 draws no surface, only the --ball-and-stick model")
      ->check(CLI::Validator([](std::string& text) { return detail::checkNumber(text, 0.0, 1.0, false, false); },
                             "NUMBER in [0, 1]", "opacity"))
      ->default_val(1.0);
  cmd.add_option("--max-layers", o.maxLayers,
                 "With --opacity below 1: the most layers composited per ray, the nearest ones (the rest are dropped)")
      ->check(wholeIn(1, 1024))
      ->default_val(16);
  cmd.add_option("--camera", o.camera,
                 "Use this camera (JSON, instead of framing): one written by --camera-out, or another program's with "
                 "only width, height, view_matrix and projection_matrix (OpenGL conventions, column-major; any "
                 "perspective or orthographic projection, off-centre too; see the README's conventions table)")
      ->check(CLI::ExistingFile);
  cmd.add_option("--camera-out", o.cameraOut,
                 "Write the camera used as JSON: eye, look_at, up, projection, fov_y_degrees/ortho_height, near and "
                 "far tight around the scene, and the OpenGL view_matrix and projection_matrix (column-major), for "
                 "another renderer to draw the same view; - for the standard output");
  addEffectOptions(cmd, o);
  addBallAndStickOptions(cmd, o);
  for (const char* name : {"--view", "--eye", "--look-at", "--up", "--fov", "--ortho"})
    o.framingOptions.push_back(cmd.get_option(name));
  o.sizeOption = cmd.get_option("--size");
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
  ro.opacity = o.opacity;
  ro.maxLayers = o.maxLayers;
  if (o.opacity == 0.0 && !o.ballAndStick)
    throw std::invalid_argument("--opacity 0 draws no surface, and nothing else was asked for: add --ball-and-stick "
                                "or give an opacity above 0");
  ro.effects = resolveEffects(o);
  setup.framing.direction = view::namedViewDirection(o.view);
  if (!(o.fov > 0.0 && o.fov < 180.0))
    throw std::invalid_argument("--fov " + std::to_string(o.fov) + ": the field of view must be in (0, 180) degrees");
  if (!o.eye.empty()) setup.framing.eye = parseVector("--eye", o.eye);
  if (!o.lookAt.empty()) setup.framing.lookAt = parseVector("--look-at", o.lookAt);
  if (!o.up.empty()) {
    setup.framing.up = parseVector("--up", o.up);
    if (*setup.framing.up == glm::dvec3(0.0)) throw std::invalid_argument("--up '" + o.up + "': the up vector must not be zero");
  }
  if (!o.camera.empty()) {
    for (const CLI::Option* option : o.framingOptions)
      if (option && option->count() > 0)
        throw std::invalid_argument(option->get_name() + " cannot be combined with --camera " + o.camera +
                                    ", which fixes the whole view (edit the file, or drop --camera)");
    setup.framing.fixed = readCameraFile(o.camera);
    const view::Camera& c = *setup.framing.fixed;
    if (o.sizeOption && o.sizeOption->count() > 0 && (c.width != ro.camera.width || c.height != ro.camera.height))
      throw std::invalid_argument("--size " + o.size + " disagrees with --camera " + o.camera + " (" +
                                  std::to_string(c.width) + "x" + std::to_string(c.height) +
                                  "): drop --size, the camera fixes it");
    ro.camera = c;
  }
  if (!o.cameraOut.empty()) {
    build::prepareOutputPath(o.cameraOut, "--camera-out");
    setup.cameraOut = o.cameraOut;
  }
  checkImageFitsInMemory(o.size, ro.camera.width, ro.camera.height);
  return setup;
}

void writeCameraOut(const ImageSetup& setup) {
  if (!setup.cameraOut.empty()) writeCamera(setup.cameraOut, setup.render.camera);
}

void checkImageFitsInMemory(const std::string& sizeText, int width, int height) {
  // The frame's buffers (colour, depth, view depth, normal, kind, patch and atom ids, flags:
  // 52 bytes a pixel) and, while a file is written, its pixels and encoded bytes again.
  constexpr double kBytesPerPixel = 52.0 + 52.0 + 60.0;
  const double needed = kBytesPerPixel * static_cast<double>(width) * static_cast<double>(height);
  const long pages = sysconf(_SC_PHYS_PAGES), pageSize = sysconf(_SC_PAGE_SIZE);
  if (pages <= 0 || pageSize <= 0) return;  // unknown: let the allocation decide
  const double memory = static_cast<double>(pages) * static_cast<double>(pageSize);
  if (needed > memory) {
    char text[256];
    std::snprintf(text, sizeof text,
                  "--size %s: an image of %dx%d pixels needs about %.1f GiB for its buffers, more than this "
                  "machine's %.1f GiB of memory; render it smaller",
                  sizeText.c_str(), width, height, needed / 0x1p30, memory / 0x1p30);
    throw std::invalid_argument(text);
  }
}

void frameSurface(ImageSetup& setup, const build::PatchList& list, const build::Molecule& molecule) {
  setup.render.camera = surftrace::frameSurface(setup.render.camera, setup.framing, list, molecule);
}

void frameSpheres(ImageSetup& setup, std::span<const glm::dvec3> centers, std::span<const double> reach) {
  setup.render.camera = surftrace::frameSpheres(setup.render.camera, setup.framing, centers, reach);
}

view::SphereFraming framingOf(const ImageSetup& setup) { return sphereFraming(setup.render.camera, setup.framing); }

void frameSpheres(ImageSetup& setup, const view::SphereFraming& framing) {
  setup.render.camera = surftrace::frameSpheres(setup.render.camera, setup.framing, framing);
}

}  // namespace surftrace::tools

// Image options shared by `render` and `trajectory` (image_options.hpp).
#include "image_options.hpp"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <sstream>
#include <stdexcept>
#include <vector>

#include <embree3/rtcore_config.h>

#include <nlohmann/json.hpp>

#include "build/io/output_file.hpp"
#include "build/io/text_fields.hpp"
#include "build/mss/mss_area.hpp"
#include "build/surface.hpp"
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

// The end of every framing: the imported camera or the framed one with --eye/--look-at/--up,
// and a depth range from the spheres that hold the scene.
void finishCamera(ImageSetup& setup, std::span<const view::SphereCover> covers) {
  view::Camera& camera = setup.render.camera;
  if (setup.imported) {
    camera = *setup.imported;
  } else {
    applyExplicitCamera(setup);
  }
  if (!camera.hasDepthRange()) camera = view::withDepthRange(camera, covers);
  camera.validate();
}

view::Camera readCameraFile(const std::string& path) {
  const std::string text = build::text::readTextFile(path, path);
  try {
    return view::cameraFromJson(text);
  } catch (const std::exception& e) {
    throw std::invalid_argument("--camera " + path + ": " + e.what());
  }
}

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
  setup.viewDirection = view::namedViewDirection(o.view);
  if (!(o.fov > 0.0 && o.fov < 180.0))
    throw std::invalid_argument("--fov " + std::to_string(o.fov) + ": the field of view must be in (0, 180) degrees");
  if (!o.eye.empty()) setup.eye = parseVector("--eye", o.eye);
  if (!o.lookAt.empty()) setup.lookAt = parseVector("--look-at", o.lookAt);
  if (!o.up.empty()) {
    setup.up = parseVector("--up", o.up);
    if (*setup.up == glm::dvec3(0.0)) throw std::invalid_argument("--up '" + o.up + "': the up vector must not be zero");
  }
  if (!o.camera.empty()) {
    for (const CLI::Option* option : o.framingOptions)
      if (option && option->count() > 0)
        throw std::invalid_argument(option->get_name() + " cannot be combined with --camera " + o.camera +
                                    ", which fixes the whole view (edit the file, or drop --camera)");
    setup.imported = readCameraFile(o.camera);
    const view::Camera& c = *setup.imported;
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
  if (setup.cameraOut.empty()) return;
  const auto json = nlohmann::json::parse(view::cameraToJson(setup.render.camera));
  build::writeFileAtomically(setup.cameraOut, json.dump(2) + "\n");
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
  view::Camera& camera = setup.render.camera;
  if (list.params.surface == build::SurfaceKind::Mss) {
    // Two bounds of the skin, each loose somewhere: its patches' balls (tight for s near 1,
    // but for small s a hyperboloid's ball grows as r/√s), and the hull of the atom centres
    // grown by the largest radius (every ball of the skin's construction is centred in that
    // hull, and shrunk to radius² <= Σλ_i r_i² <= r_max²; tight as s -> 0). A patch list read
    // without its structure has the first alone.
    // A patch of a near-degenerate simplex whose cell is a sliver (build::mssPatchIsNegligible:
    // four nearly co-spherical atoms) holds next to no skin, but its ball about a far,
    // ill-conditioned orthocentre would move the view (issue 18): such patches are left out.
    std::vector<glm::dvec3> centers;
    std::vector<double> radii;
    centers.reserve(list.mss.size());
    radii.reserve(list.mss.size());
    for (std::size_t k = 0; k < list.mss.size(); ++k) {
      if (build::mssPatchIsNegligible(list, k)) continue;
      centers.push_back(list.mss.center[k]);
      radii.push_back(list.mss.boundRadius[k]);
    }
    if (centers.empty()) {  // nothing but slivers (not a skin the builder writes): keep them all
      centers = list.mss.center;
      radii = list.mss.boundRadius;
    }
    const view::SphereCover patches{centers, radii};
    if (molecule.centers.empty()) {
      if (!setup.imported) camera = view::frameSphereCovers(camera, {&patches, 1}, setup.viewDirection);
      finishCamera(setup, {&patches, 1});
    } else {
      const std::vector<double> grown = build::SurfaceRequest::of(list.params).reach(molecule.radii);
      const view::SphereCover covers[] = {patches, {molecule.centers, grown}};
      if (!setup.imported) camera = view::frameSphereCovers(camera, covers, setup.viewDirection);
      finishCamera(setup, covers);
    }
  } else {
    const std::vector<double> reach = build::SurfaceRequest::of(list.params).reach(molecule.radii);
    if (!setup.imported) camera = view::frameSpheres(camera, molecule.centers, reach, setup.viewDirection);
    const view::SphereCover cover{molecule.centers, reach};
    finishCamera(setup, {&cover, 1});
  }
}

void frameSpheres(ImageSetup& setup, std::span<const glm::dvec3> centers, std::span<const double> reach) {
  if (!setup.imported) setup.render.camera = view::frameSpheres(setup.render.camera, centers, reach, setup.viewDirection);
  const view::SphereCover cover{centers, reach};
  finishCamera(setup, {&cover, 1});
}

view::SphereFraming framingOf(const ImageSetup& setup) {
  return view::SphereFraming(setup.render.camera, setup.viewDirection);
}

void frameSpheres(ImageSetup& setup, const view::SphereFraming& framing) {
  if (!setup.imported) setup.render.camera = framing.frame(setup.render.camera);
  // Every sphere lies in the framing's box: its corners bound the depth range.
  const std::vector<glm::dvec3> corners = framing.boxCorners();
  const std::vector<double> zero(corners.size(), 0.0);
  const view::SphereCover cover{corners, zero};
  finishCamera(setup, {&cover, 1});
}

view::ImageMetadata imageMetadata(const ImageRecord& r, const view::Camera& camera) {
  view::ImageMetadata meta;
  meta["surftrace:renderer"] = r.engine == "gl"
                                   ? std::string(kSoftware) + " gl: " + r.glContext
                                   : std::string(kSoftware) + " embree " + RTC_VERSION_STRING + " (double-precision patches)";
  meta["surftrace:engine"] = r.engine;
  meta["surftrace:camera"] = view::cameraToJson(camera);
  meta["surftrace:surface"] = r.surface;
  meta["surftrace:probe_radius"] = std::to_string(r.probeRadius);
  if (r.shrinkFactor) meta["surftrace:shrink_factor"] = std::to_string(*r.shrinkFactor);
  meta["surftrace:input"] = r.input;
  if (!r.trajectory.empty()) meta["surftrace:trajectory"] = r.trajectory;
  if (r.frame) meta["surftrace:frame"] = std::to_string(*r.frame);
  if (r.timePs) meta["surftrace:time_ps"] = std::to_string(*r.timePs);
  meta["surftrace:color"] = r.color;
  // Every setting that changes pixels is recorded, so that `compare` can tell two images made
  // alike from two made differently (tools/image_settings.hpp reads them back).
  auto triple = [](const glm::dvec3& v) {
    return detail::shortNumber(v.x) + "," + detail::shortNumber(v.y) + "," + detail::shortNumber(v.z);
  };
  if (r.color == "uniform") meta["surftrace:uniform_color"] = triple(r.uniformColor);
  meta["surftrace:background"] = triple(r.background);
  meta["surftrace:lighting"] = nlohmann::json{{"model", "Blinn-Phong headlight"},
                                              {"ambient", r.lighting.ambient},
                                              {"diffuse", r.lighting.diffuse},
                                              {"specular", r.lighting.specular},
                                              {"shininess", r.lighting.shininess},
                                              {"shadows", r.shadows},
                                              {"ao_samples", r.aoSamples},
                                              {"ao_distance", r.aoDistance}}
                                   .dump();
  meta["surftrace:samples_per_pixel"] = std::to_string(r.samplesPerPixel);
  meta["surftrace:command"] = r.commandLine;
  if (r.opacity < 1.0) {
    meta["surftrace:opacity"] = std::to_string(r.opacity);
    meta["surftrace:max_layers"] = std::to_string(r.maxLayers);
  }
  if (r.effects.any()) meta["surftrace:effects"] = r.effects.json(camera);
  if (r.ballAndStick)
    meta["surftrace:ball_and_stick"] = "{\"ball_scale\": " + detail::shortNumber(r.ballScale) +
                                       ", \"stick_radius\": " + detail::shortNumber(r.stickRadius) +
                                       ", \"bonds\": " + std::to_string(r.bonds) + "}";
  for (const auto& [key, value] : r.engineSettings) meta[key] = value;
  meta["Software"] = kSoftware;
  return meta;
}

}  // namespace surftrace::tools

// Image options shared by `render` and `trajectory` (image_options.hpp).
#include "image_options.hpp"

#include <algorithm>
#include <array>
#include <cctype>
#include <cmath>
#include <cstdio>
#include <sstream>
#include <stdexcept>
#include <vector>

#include <nlohmann/json.hpp>

#include "option_checks.hpp"
#include "view/color_map.hpp"
#include "view/image_io.hpp"
#include "view/srgb.hpp"
#include "surftrace/files.hpp"

namespace surftrace::tools {
namespace {

// --color-range LO:HI, both finite, LO < HI.
std::array<double, 2> parseRange(const std::string& text) {
  std::istringstream in(text);
  double lo = 0.0, hi = 0.0;
  char colon = 0;
  if (!(in >> lo >> colon >> hi) || colon != ':' || in.peek() != EOF || !std::isfinite(lo) || !std::isfinite(hi))
    throw std::invalid_argument("--color-range '" + text + "': expected LO:HI, two finite numbers, e.g. 0:80 or -4.5:4.5");
  if (!(lo < hi)) throw std::invalid_argument("--color-range '" + text + "': LO must be below HI");
  return {lo, hi};
}

// --color-select 'SEL=#rrggbb': the selection up to the last '=', then the colour in hex.
view::ColorOverride parseColorSelect(const std::string& text) {
  const auto eq = text.rfind('=');
  const std::string selection = eq == std::string::npos ? "" : text.substr(0, eq);
  const std::optional<glm::dvec3> color = parseHexColor(eq == std::string::npos ? "" : text.substr(eq + 1));
  if (selection.find_first_not_of(" \t") == std::string::npos || !color)
    throw std::invalid_argument("--color-select '" + text + "': expected SELECTION=#rrggbb, e.g. 'resname HEM=#ff0000' "
                                "(quote it for the shell)");
  view::ColorOverride o;
  o.selection = selection;
  o.color = glm::vec3(*color);
  return o;
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
  cmd.add_option("--silhouette-width", o.silhouetteWidth,
                 "Silhouette and crease line width as a fraction of the image height, in (0, 0.25] (0.002: 1 px at "
                 "512 px, 4 px at 2048 px), so that every size of the same view looks alike; lines are anti-aliased")
      ->check(numberIn(1e-6, 0.25))
      ->default_val(0.002)
      ->group(group);
  cmd.add_option("--silhouette-color", o.silhouetteColor,
                 "Silhouette and crease line colour r,g,b in [0,1] or #rrggbb (sRGB)")
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
               "Deussen 2006), colour + strength·min(0, G∗D − D)/R, D in Å, R the scene's depth range")
      ->group(group);
  // σ was once in pixels (0.1 to 256): every such value is refused with the option that takes
  // pixels now, rather than read as a fraction of the image.
  CLI::Option* sigma = cmd.add_option("--depth-darkening-sigma", o.darkeningSigma,
                 "Depth darkening: the Gaussian's σ as a fraction of the image height, below 0.1, so that any image "
                 "size looks the same (0.015 is 7.7 px of a 512² image; for pixels, --depth-darkening-sigma-px)")
      ->check(CLI::Validator(
          [](std::string& text) {
            const std::string bad = detail::checkNumber(text, 0.0, HUGE_VAL, true, false);
            if (!bad.empty()) return bad;
            if (std::strtod(text.c_str(), nullptr) < 0.1) return std::string();
            return "expected a fraction of the image height in (0, 0.1), e.g. 0.015, got '" + text +
                   "'; for a σ in pixels give --depth-darkening-sigma-px " + text;
          },
          "FRACTION", "fraction of the image height"))
      ->default_val(0.015)
      ->group(group);
  cmd.add_option("--depth-darkening-sigma-px", o.darkeningSigmaPx,
                 "Depth darkening: the Gaussian's σ in pixels, in place of --depth-darkening-sigma")
      ->check(numberIn(0.1, 256))
      ->excludes(sigma)
      ->group(group);
  cmd.add_option("--depth-darkening-strength", o.darkeningStrength,
                 "Depth darkening: the colour removed where a pixel lies behind its surroundings by the whole depth "
                 "range R (the camera's near to far plane: tight around the scene, the same in every trajectory "
                 "frame)")
      ->check(numberIn(0, HUGE_VAL))
      ->default_val(1.0)
      ->group(group);
  cmd.add_option("--depth-darkening-range", o.darkeningRange,
                 "Depth darkening: R in Å, in place of the camera's depth range (e.g. the same R for several "
                 "molecules; 1 gives --depth-darkening-strength in colour per Å)")
      ->check(positive())
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

// The colour scheme's options, checked against one another before any work.
void resolveColorOptions(const ImageOptions& o, ImageSetup& setup) {
  view::ColorScheme& s = setup.colors;
  s.mode = setup.render.color;
  s.uniform = setup.uniformColor;
  s.map = o.colorMap;
  const bool mapped = view::usesColorMap(s.mode);
  if (!o.colorMap.empty() && !mapped)
    throw std::invalid_argument("--color-map applies to --color bfactor, value, hydrophobicity and rainbow, not to --color " +
                                o.color);
  if (!o.colorRange.empty()) {
    if (!mapped || s.mode == view::ColorMode::Rainbow)
      throw std::invalid_argument("--color-range applies to --color bfactor, value and hydrophobicity, not to --color " +
                                  o.color);
    s.range = parseRange(o.colorRange);
  }
  if (s.mode == view::ColorMode::Value && o.values.empty())
    throw std::invalid_argument("--color value needs --values FILE: a CSV with a header `atom,NAME` or "
                                "`chain,resid[,icode],NAME` and a number per atom or residue");
  if (!o.values.empty() && s.mode != view::ColorMode::Value)
    throw std::invalid_argument("--values " + o.values + " is read by --color value only (not --color " + o.color + ")");
  setup.valuesPath = o.values;
  if ((o.legend || !o.legendFile.empty()) && !mapped)
    throw std::invalid_argument(std::string(o.legend ? "--legend" : "--legend-file") +
                                " shows a colour map: it needs --color bfactor, value, hydrophobicity or rainbow, not "
                                "--color " + o.color);
  setup.legend = o.legend;
  if (!o.legendFile.empty()) {
    view::checkImageOutputName(o.legendFile, "--legend-file", view::ImageContent::Colour);
    build::prepareOutputPath(o.legendFile, "--legend-file", build::OutputContent::Binary);
    setup.legendFile = o.legendFile;
  }
  if (!o.colorSelect.empty() && s.mode == view::ColorMode::Patch)
    throw std::invalid_argument("--color-select paints atoms, but --color patch colours by patch kind: choose a scheme "
                                "that colours by atom (e.g. --color uniform or element)");
  for (const std::string& text : o.colorSelect) s.overrides.push_back(parseColorSelect(text));
  setup.colorSelect = o.colorSelect;
}

}  // namespace

std::vector<glm::vec3> colorAtoms(ImageSetup& setup, const build::Molecule& molecule) {
  std::optional<view::AtomValues> values;
  view::ColorScheme scheme = setup.colors;
  if (!setup.valuesPath.empty()) {
    values = view::readAtomValues(setup.valuesPath, molecule);
    scheme.values = &*values;
    if (values->unmatchedRows > 0)
      std::fprintf(stderr, "surftrace: note: --values %s: %zu of %zu rows name no atom of %s (first: %s)\n",
                   setup.valuesPath.c_str(), values->unmatchedRows, values->rows, molecule.source.c_str(),
                   values->firstUnmatched.c_str());
  }
  view::AtomColoring coloring = view::colorAtoms(molecule, scheme);
  setup.colorLegend = coloring.legend;
  if (const auto& l = coloring.legend) {
    if (setup.legend) {
      view::checkLegendFits(setup.render.camera.width, setup.render.camera.height, *l);
      setup.render.legend = l;
    }
    if (scheme.mode == view::ColorMode::Rainbow)
      std::printf("colour map %s: each chain's residues from the N terminus (0) to the C terminus (1)", l->map.c_str());
    else
      std::printf("colour map %s: %s from %.6g to %.6g (%s)", l->map.c_str(), l->label.c_str(), l->lo, l->hi,
                  l->rangeFromData ? "the data's min..max; set it with --color-range" : "--color-range");
    if (l->missing > 0) std::printf("; %zu atoms without a value are grey 0.5,0.5,0.5", l->missing);
    std::printf("\n");
  }
  for (std::size_t k = 0; k < coloring.overridden.size(); ++k)
    std::printf("--color-select %s: %zu atoms\n", setup.colorSelect[k].c_str(), coloring.overridden[k]);
  return std::move(coloring.colors);
}

void describeColors(const ImageSetup& setup, ImageRecord& record) {
  record.backgroundAlpha = setup.render.backgroundAlpha;
  record.colorMap = setup.colorLegend;
  record.valuesFile = setup.valuesPath;
  record.colorSelect = setup.colorSelect;
  record.legendInImage = setup.render.legend.has_value();
  record.legendFile = setup.legendFile;
}

void writeLegendFile(const ImageSetup& setup) {
  if (setup.legendFile.empty() || !setup.colorLegend) return;
  const view::FrameBuffers legend = view::legendImage(
      *setup.colorLegend, setup.render.background,
      view::legendScale(setup.render.camera.width, setup.render.camera.height));
  view::writePng(setup.legendFile, legend,
                 {{"surftrace:color_map", setup.colorLegend->map},
                  {"surftrace:color_range", std::to_string(setup.colorLegend->lo) + ":" + std::to_string(setup.colorLegend->hi)},
                  {"surftrace:color_label", setup.colorLegend->label}});
}

view::ImageEffects resolveEffects(const ImageOptions& o) {
  view::ImageEffects e;
  e.silhouettes = o.silhouettes;
  e.lineWidth = o.silhouetteWidth;
  e.lineColor = parseColor("--silhouette-color", o.silhouetteColor);
  e.silhouetteJump = o.silhouetteJump;
  e.creaseAngle = o.creaseAngle;
  e.depthDarkening = o.depthDarkening;
  e.darkeningSigma = o.darkeningSigma;
  e.darkeningSigmaPx = o.darkeningSigmaPx;
  e.darkeningStrength = o.darkeningStrength;
  e.darkeningRange = o.darkeningRange;
  e.depthCue = o.depthCue;
  e.depthCueStrength = o.depthCueStrength;
  e.depthCueStart = o.depthCueStart;
  e.depthCueEnd = o.depthCueEnd;
  if (e.depthCueStart && e.depthCueEnd && !(*e.depthCueEnd > *e.depthCueStart))
    throw std::invalid_argument("--depth-cue-end must lie beyond --depth-cue-start");
  e.validate();
  return e;
}

std::optional<glm::dvec3> parseHexColor(const std::string& text) {
  if (text.size() != 7 || text[0] != '#' ||
      !std::all_of(text.begin() + 1, text.end(), [](char c) { return std::isxdigit(static_cast<unsigned char>(c)); }))
    return std::nullopt;
  glm::dvec3 c;
  for (int k = 0; k < 3; ++k) c[k] = std::stoi(text.substr(1 + 2 * static_cast<std::size_t>(k), 2), nullptr, 16) / 255.0;
  return c;
}

namespace {
// "x,y,z": three finite numbers and nothing else; parseVector and parseColor word their own errors.
std::optional<glm::dvec3> parseTriple(const std::string& text) {
  std::istringstream in(text);
  glm::dvec3 v;
  char c1 = 0, c2 = 0;
  if (!(in >> v.x >> c1 >> v.y >> c2 >> v.z) || c1 != ',' || c2 != ',' || in.peek() != EOF || !std::isfinite(v.x) ||
      !std::isfinite(v.y) || !std::isfinite(v.z))
    return std::nullopt;
  return v;
}
}  // namespace

glm::vec3 parseColor(const std::string& option, const std::string& text) {
  if (const auto hex = parseHexColor(text)) return glm::vec3(*hex);
  const auto c = parseTriple(text);
  if (!c || !(c->x >= 0 && c->x <= 1) || !(c->y >= 0 && c->y <= 1) || !(c->z >= 0 && c->z <= 1))
    throw std::invalid_argument(option + " '" + text + "': expected r,g,b, each in [0, 1], or #rrggbb (sRGB, as a "
                                "picker or a web page gives them)");
  return glm::vec3(*c);
}

glm::dvec4 parseBackground(const std::string& text) {
  if (const auto hex = parseHexColor(text)) return {*hex, 1.0};
  std::istringstream in(text);
  std::vector<double> v;
  std::string item;
  while (std::getline(in, item, ',')) {
    char* end = nullptr;
    const double x = std::strtod(item.c_str(), &end);
    if (item.empty() || *end != '\0' || !std::isfinite(x)) v.assign(5, 0.0);
    v.push_back(x);
  }
  if ((v.size() != 3 && v.size() != 4) || std::any_of(v.begin(), v.end(), [](double x) { return x < 0.0 || x > 1.0; }))
    throw std::invalid_argument("--background '" + text + "': expected r,g,b or r,g,b,a, each in [0, 1] (a: the "
                                "background's alpha, 0 transparent), or #rrggbb");
  return {v[0], v[1], v[2], v.size() == 4 ? v[3] : 1.0};
}

glm::dvec3 parseVector(const std::string& option, const std::string& text) {
  if (const auto v = parseTriple(text)) return *v;
  throw std::invalid_argument(option + " '" + text + "': expected three finite numbers x,y,z");
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
  cmd.add_option("--color", o.color,
                 "Colouring: patch (SES: convex green, toroidal yellow, concave red; MSS: convex green, edge "
                 "hyperboloids red, face ones yellow, concave blue), element (Jmol), chain (24 distinct colours in order "
                 "of appearance; chains 25-48 take them darker, 49-72 lighter, and so on in turn), residue (RasMol amino), "
                 "hydrophobicity (Kyte-Doolittle), rainbow (N to C terminus along each chain), bfactor, value (--values), "
                 "uniform")
      ->check(CLI::IsMember({"patch", "element", "chain", "residue", "hydrophobicity", "rainbow", "bfactor", "value",
                             "uniform"}))
      ->default_val("patch");
  cmd.add_option("--uniform-color", o.uniformColor, "Colour r,g,b in [0,1] or #rrggbb (sRGB) for --color uniform")
      ->default_val("0.8,0.8,0.8");
  cmd.add_option("--color-map", o.colorMap,
                 "Colour map of bfactor, value, hydrophobicity and rainbow: viridis, magma, cividis (perceptually "
                 "uniform), coolwarm (diverging), rainbow; default coolwarm for bfactor and hydrophobicity, viridis for "
                 "value, rainbow for rainbow")
      ->check(CLI::IsMember(view::ColorMap::names()));
  cmd.add_option("--color-range", o.colorRange,
                 "The numbers LO:HI that the colour map's ends stand for (outside: the ends); default the data's "
                 "min:max (printed)");
  cmd.add_option("--values", o.values,
                 "CSV of a number per atom for --color value: header `atom,NAME` (0-based atom index in the file, as "
                 "MDAnalysis's atom.index) or `chain,resid,NAME` or `chain,resid,icode,NAME`, one row per atom or "
                 "residue; atoms without a value are grey 0.5,0.5,0.5")
      ->check(CLI::ExistingFile);
  cmd.add_option("--color-select", o.colorSelect,
                 "'SELECTION=#rrggbb': paint the selected atoms (MDAnalysis-style selection, as --flexible) this "
                 "colour over the scheme; repeatable, applied in order");
  cmd.add_flag("--legend", o.legend,
               "Draw the colour map's legend (bar, range, label) into the bottom-right corner of the image");
  cmd.add_option("--legend-file", o.legendFile, "Write the colour map's legend as its own PNG");
  cmd.add_option("--background", o.background,
                 "Background colour r,g,b in [0,1] or #rrggbb (sRGB, as every colour given: a PNG shows these bytes), "
                 "or r,g,b,a with a the background's alpha (below 1: a PNG with an alpha channel; the EXR's A)")
      ->default_val("1,1,1");
  cmd.add_option("--spp", o.spp,
                 "Anti-aliasing: colour samples per pixel, rounded up to a k×k grid (2 to 4 take 2×2 = 4 samples, 5 "
                 "to 9 take 3×3 = 9); the buffers (depth, normal, ids) keep the pixel centre's")
      ->check(wholeIn(1, 1024))
      ->default_val(1);
  cmd.add_option("--lighting", o.lighting,
                 "headlight: Blinn-Phong from the eye (pockets read as bumps); simple: a key light 45° above left of "
                 "the eye, a fill light below right and ambient light; soft: simple with soft shadows from the key "
                 "light (an 8° disc, 4 rays) and ambient occlusion (8 rays within --ao-distance; --ao N sets N), "
                 "smoothed by an edge-aware filter; full: soft with 32 shadow and 64 occlusion rays. With --engine "
                 "gl, soft and full are drawn from light maps (depth maps along the key disc and over the sphere), "
                 "which count occluders at any distance")
      ->check(CLI::IsMember({"headlight", "simple", "soft", "full"}))
      ->default_val("headlight");
  cmd.add_flag("--shadows", o.shadows,
               "Ray-traced shadows from a key light above-left of the eye (headlight: ×0.6 where it is blocked; "
               "--lighting simple: the key light's terms dropped there)");
  cmd.add_option("--ao", o.ao, "Ambient-occlusion rays per pixel (0 = off, or the --lighting preset's)")
      ->check(wholeIn(0, 4096))
      ->default_val(0);
  cmd.add_option("--ao-distance", o.aoDistance,
                 "Ambient-occlusion ray length in Å (Embree; --engine gl's light maps count occluders at any distance)")
      ->check(positive())
      ->default_val(8.0);
  cmd.add_option("--opacity", o.opacity,
                 "Surface opacity in [0, 1]: below 1 every layer the ray crosses (up to --max-layers, nearest first) "
                 "is blended front to back over the background (engine embree exactly; engine gl by depth peeling); "
                 "0 draws no surface, only the --ball-and-stick model. The inner surfaces of buried cavities show "
                 "through a transparent surface unless --drop-cavities leaves them out")
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
  const glm::dvec4 background = parseBackground(o.background);
  ro.background = view::srgbToLinear(glm::vec3(background));  // given in sRGB; the renderers' is linear
  ro.backgroundAlpha = static_cast<float>(background.w);
  setup.uniformColor = parseColor("--uniform-color", o.uniformColor);
  resolveColorOptions(o, setup);
  ro.samplesPerPixel = o.spp;
  ro.lighting = view::lightingFor(view::parseLightingPreset(o.lighting));
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

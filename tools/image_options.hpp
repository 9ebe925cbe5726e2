// The options that say what an image looks like (size, view, camera, colours, samples,
// shadows, ambient occlusion, image-space effects), shared by `render` and `trajectory`.
#pragma once

#include <chrono>
#include <mutex>
#include <optional>
#include <span>
#include <string>
#include <utility>
#include <vector>

#include <CLI/CLI.hpp>
#include <glm/vec3.hpp>
#include <glm/vec4.hpp>

#include "commands.hpp"
#include "progress_bar.hpp"
#include "surftrace/camera.hpp"
#include "surftrace/image.hpp"
#include "view/atom_colors.hpp"

namespace surftrace::tools {

struct ImageOptions {
  std::string size = "1024x1024";
  std::string view = "front";
  std::string eye, lookAt, up;
  double fov = 30.0;
  bool ortho = false;
  std::string color = "patch";
  std::string uniformColor = "0.8,0.8,0.8";
  std::string background = "1,1,1";
  // The schemes that map numbers to colours (view/atom_colors.hpp) and what paints over them.
  std::string colorMap;                  // --color-map (default: the scheme's)
  std::string colorRange;                // --color-range LO:HI (default: the data's min..max)
  std::string values;                    // --values FILE, for --color value
  std::vector<std::string> colorSelect;  // --color-select 'SEL=#rrggbb', in order
  bool legend = false;                   // --legend: the colour bar drawn into the image
  std::string legendFile;                // --legend-file FILE: the colour bar as its own image
  int spp = 1;
  std::string lighting = "headlight";
  bool shadows = false;
  int ao = 0;
  double aoDistance = 8.0;
  double opacity = 1.0;  // --opacity: below 1 the surface is transparent (every layer composited)
  int maxLayers = 16;    // --max-layers: the nearest layers a transparent ray composites
  // --ball-and-stick: the atoms' balls and the bonds' sticks, opaque, drawn with the surface
  // (under it when --opacity < 1; alone at --opacity 0).
  bool ballAndStick = false;
  double ballScale = 0.25;    // --ball-scale: a ball's radius over its atom's
  double stickRadius = 0.15;  // --stick-radius, Å
  // Image-space effects (view/image_effects.hpp), applied after either engine.
  bool silhouettes = false;
  double silhouetteWidth = 0.002;  // fraction of the image height
  std::string silhouetteColor = "0,0,0";
  double silhouetteJump = 2.0;
  double creaseAngle = 0.0;
  bool depthDarkening = false;
  double darkeningSigma = 0.015;                // fraction of the image height
  std::optional<double> darkeningSigmaPx;       // --depth-darkening-sigma-px
  double darkeningStrength = 1.0;               // colour per depth range
  std::optional<double> darkeningRange;         // --depth-darkening-range, Å
  bool depthCue = false;
  double depthCueStrength = 0.6;
  std::optional<double> depthCueStart, depthCueEnd;
  std::string camera;     // --camera FILE: the camera instead of framing
  std::string cameraOut;  // --camera-out FILE
  // The options that --camera replaces (named in the error when given with it).
  std::vector<CLI::Option*> framingOptions;
  CLI::Option* sizeOption = nullptr;
};

void addImageOptions(CLI::App& cmd, ImageOptions& options);

// The image options checked and parsed (std::invalid_argument naming the option otherwise);
// the camera is framed later, when the surface is known.
struct ImageSetup {
  view::RenderOptions render;
  // --view, --eye, --look-at, --up; --camera (Framing::fixed: used as it is, no framing; its
  // depth range is taken from the scene when the file has none).
  Framing framing;
  glm::vec3 uniformColor{0.8f};
  std::string cameraOut;
  // The colour scheme's options, checked; the molecule's colours come from colorAtoms.
  view::ColorScheme colors;
  std::string valuesPath;
  bool legend = false;
  std::string legendFile;
  std::vector<std::string> colorSelect;        // as given, for the record
  std::optional<view::ColorLegend> colorLegend;  // set by colorAtoms for the mapped schemes
  std::size_t missingColors = 0;
};
ImageSetup resolveImageOptions(const ImageOptions& options);
// The effect options checked and parsed (std::invalid_argument naming the option otherwise).
view::ImageEffects resolveEffects(const ImageOptions& options);

// std::invalid_argument, naming `sizeText` and how much memory is needed, when an image of
// width x height pixels would not fit in this machine's memory (checked before allocating).
void checkImageFitsInMemory(const std::string& sizeText, int width, int height);

// Frames render.camera on what the surface can reach, as `render` does for a structure: the
// skin lies in its patches' bounding balls and in the hull of the atoms grown by the largest
// radius (the tighter of the two is taken along each axis); r + rp bounds the SES and the
// SAS; r the vdW balls (build::SurfaceRequest::reach). Then --eye, --look-at and --up override the framing, and the camera is validated.
void frameSurface(ImageSetup& setup, const build::PatchList& list, const build::Molecule& molecule);
// The same over spheres given by `centers` and `reach` (a patch list's convex patches).
void frameSpheres(ImageSetup& setup, std::span<const glm::dvec3> centers, std::span<const double> reach);
// The same over spheres that come in pieces (every frame of a trajectory): add them to
// framingOf(setup) or to copies of it, merge, and frame the camera on the result.
view::SphereFraming framingOf(const ImageSetup& setup);
void frameSpheres(ImageSetup& setup, const view::SphereFraming& framing);
// Every framing function above ends the same way: an imported camera (--camera) replaces the
// framing, --eye/--look-at/--up override it, and the camera gets its depth range (near, far)
// tight around what frames it.

// The atoms' colours under the options' scheme (--color, --color-map, --color-range, --values,
// --color-select), printed in a line that says the map, the range and where it comes from; the
// legend goes into setup.render when --legend asks for it. Throws std::invalid_argument (the
// scheme has no data in `molecule`, a selection selects nothing) and build::InputError (--values).
std::vector<glm::vec3> colorAtoms(ImageSetup& setup, const build::Molecule& molecule);
// What colorAtoms chose, into the image's record (surftrace:color_map, :color_select, :color_legend).
void describeColors(const ImageSetup& setup, ImageRecord& record);
// Writes --legend-file (if given), whole or not at all.
void writeLegendFile(const ImageSetup& setup);

// Writes the camera to --camera-out (if given), whole or not at all.
void writeCameraOut(const ImageSetup& setup);

glm::dvec3 parseVector(const std::string& option, const std::string& text);
// Colours as given: sRGB numbers in [0, 1] (decoded to linear where they enter the frame).
// '#rrggbb' as three numbers, or nothing when `text` is not of that form.
std::optional<glm::dvec3> parseHexColor(const std::string& text);
// r,g,b, each in [0, 1], or #rrggbb; std::invalid_argument naming `option`.
glm::vec3 parseColor(const std::string& option, const std::string& text);
// --background: r,g,b or #rrggbb (alpha 1), or r,g,b,a, each in [0, 1].
glm::dvec4 parseBackground(const std::string& text);

// ImageRecord and imageMetadata: surftrace/image.hpp.

}  // namespace surftrace::tools

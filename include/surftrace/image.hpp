// Stages "colour", "effects" and "write": the atoms' colours, the frame buffers an engine
// fills, the record of how an image was made (its metadata, which `compare` reads back), and
// the PNG and EXR files, encoded in memory and written whole or not at all.
#pragma once

#include <cstddef>
#include <optional>
#include <span>
#include <string>
#include <utility>
#include <vector>

#include <glm/vec3.hpp>

#include "surftrace/camera.hpp"
#include "surftrace/molecule.hpp"
#include "view/atom_colors.hpp"
#include "view/color_map.hpp"
#include "view/frame_buffers.hpp"
#include "view/image_effects.hpp"
#include "view/image_io.hpp"
#include "view/patch_kind.hpp"
#include "view/render_options.hpp"
#include "view/shading.hpp"
#include "view/srgb.hpp"

namespace surftrace {

using view::ColorMode;
using view::ImageContent;
using view::checkImageOutputName;  // an image file name checked before the work: its format holds what it must
using view::EncodedImage;
using view::FrameBuffers;
using view::ImageEffects;
using view::ImageMetadata;
using view::Lighting;
using view::LightingPreset;
using view::lightingFor;  // a --lighting preset (headlight, simple, soft, full) -> its numbers
using view::RenderOptions;
using view::applyImageEffects;  // silhouettes, creases, depth darkening and cueing, on any engine's buffers
using view::atomColors;         // (molecule, scheme, uniform colour) -> one colour per atom, linear
using view::srgbToLinear;       // a colour as given (sRGB) -> the linear one RenderOptions::background and engines take
using view::linearToSrgb;
using view::colorAtoms;         // (molecule, ColorScheme) -> colours, legend; maps, ranges, values, selections
using view::ColorScheme;
using view::ColorLegend;
using view::ColorMap;           // viridis, magma, cividis, coolwarm, rainbow: t in [0, 1] -> colour
using view::readAtomValues;     // (CSV path, molecule) -> one number per atom, for ColorMode::Value
using view::legendImage;        // the colour bar as its own image
using view::parseColorMode;
using view::PatchKind;       // what each pixel shows: the patch kinds, stored in EXRs
using view::kPatchKinds;
using view::patchCount;      // (patch list, kind) -> how many patches of that kind
using view::readExr;            // an EXR's buffers and metadata, as writeImage wrote them

// What an image records about how it was made: its metadata (surftrace:* keys), for `compare`
// and for people. The one place `render`, `trajectory` and programs write it.
struct ImageRecord {
  std::string engine;      // "embree" or "gl" (EngineDescription::name)
  std::string renderer;    // the engine and its version or context (EngineDescription::renderer)
  std::vector<std::pair<std::string, std::string>> engineSettings;  // the engine's own, as metadata keys
  std::string surface;     // "ses", "mss", "vdw" or "sas"
  double probeRadius = 0;
  std::optional<double> shrinkFactor;  // the skin's
  std::string input, trajectory;
  std::optional<std::size_t> frame;
  std::optional<double> timePs;
  std::string color;
  glm::dvec3 uniformColor{0.8};        // recorded with color "uniform"
  glm::dvec3 background{1.0};
  double backgroundAlpha = 1.0;        // recorded as the background's fourth number when below 1
  // The colour map, its range and label (surftrace:color_map) for the schemes that map numbers;
  // the --values file; the --color-select paintings in order; where the legend went
  // (surftrace:color_legend: drawn into the image, and/or its own file).
  std::optional<view::ColorLegend> colorMap;
  std::string valuesFile;
  std::vector<std::string> colorSelect;
  bool legendInImage = false;
  std::string legendFile;
  Lighting lighting;                   // the headlight's terms; recorded with shadows and AO
  bool shadows = false;
  int aoSamples = 0;
  double aoDistance = 8.0;
  int samplesPerPixel = 1;
  std::string commandLine;
  double opacity = 1.0;  // recorded (with maxLayers) only when below 1
  int maxLayers = 16;
  ImageEffects effects;  // recorded as surftrace:effects when any is on
  // The ball-and-stick model's settings, recorded as surftrace:ball_and_stick when it is drawn.
  bool ballAndStick = false;
  double ballScale = 0.25, stickRadius = 0.15;
  std::size_t bonds = 0;
};
ImageMetadata imageMetadata(const ImageRecord& record, const Camera& camera);

// An image's files encoded in memory: `png` and/or `exr` (an empty name: not written).
struct EncodedFiles {
  std::string png, exr;
  EncodedImage pngBytes, exrBytes;
};
// The image to `png` and/or `exr` in memory, with its metadata; `pngLevel` is zlib's level
// (the pixels do not depend on it).
EncodedFiles encodeImage(const std::string& png, const std::string& exr, const FrameBuffers& image,
                         const ImageRecord& record, const Camera& camera, int pngLevel = view::kDefaultPngLevel);
// Each encoded file whole or not at all ("-": the standard output; a device or FIFO in place).
void writeFiles(const EncodedFiles& files);
// Both at once.
void writeImage(const std::string& png, const std::string& exr, const FrameBuffers& image, const ImageRecord& record,
                const Camera& camera);

}  // namespace surftrace

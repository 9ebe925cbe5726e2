// Writing and reading rendered frames through OpenImageIO: PNG colour, multi-channel EXR, and
// the channels of any image file another program wrote.
#pragma once

#include <map>
#include <string>
#include <vector>

#include "view/frame_buffers.hpp"

namespace surftrace::view {

// String attributes stored with an image ("surftrace:camera" holds cameraToJson, etc.).
using ImageMetadata = std::map<std::string, std::string>;

// An image file encoded in memory, to be written whole (build::writeFileAtomically).
using EncodedImage = std::vector<unsigned char>;

// zlib's level for PNGs: 6, zlib's own default, unless the caller asks for speed. The level
// changes only the size and the time to encode, never a pixel: `trajectory` writes level 1
// (README, Benchmarks).
inline constexpr int kDefaultPngLevel = 6;

// What "surftrace:encoding" says of an image's colour: 8-bit images (PNG, JPEG, TIFF, ...) hold
// the sRGB encoding of the linear colour the renderer computed, which EXRs hold as it is.
inline constexpr const char* kSrgbEncoding = "sRGB (IEC 61966-2-1) of the linear colour; alpha linear";
inline constexpr const char* kLinearEncoding = "linear";

// 8-bit RGB PNG of the colour buffer (already composited over the background), encoded in
// memory; RGBA, straight alpha, when the frame's background is transparent
// (FrameBuffers::transparentBackground). The colour goes through the standard sRGB transfer
// function (IEC 61966-2-1), rounded to the nearest code; alpha stays linear. The file says so:
// oiio:ColorSpace "sRGB" (a PNG's sRGB chunk) and surftrace:encoding kSrgbEncoding. `path` only
// chooses the format and names the file in errors; a float format (OpenEXR, HDR) gets the
// linear colour as floats.
EncodedImage encodePng(const std::string& path, const FrameBuffers& frame, const ImageMetadata& metadata,
                       int compressionLevel = kDefaultPngLevel);
// encodePng, written whole to `path`.
void writePng(const std::string& path, const FrameBuffers& frame, const ImageMetadata& metadata,
              int compressionLevel = kDefaultPngLevel);

// What an output image holds: the colour (PNG or any 8-bit format OpenImageIO writes) or every
// buffer (OpenEXR, the one format with named float and integer channels that writeExr needs).
enum class ImageContent { Colour, Buffers };

// Checks, before any work, that an image named `path` can be written: its extension names a
// format OpenImageIO encodes into memory (Colour), or it is an OpenEXR (Buffers). Otherwise
// std::invalid_argument naming `option`, the path, the extension and what to give instead.
// "-" (the standard output) and a device, FIFO or socket (/dev/null) without a known extension
// take the default format: PNG for the colour, OpenEXR for the buffers.
void checkImageOutputName(const std::string& path, const std::string& option, ImageContent content);

// OpenEXR with every buffer, one pixel per ray through the pixel centre:
//   R G B A (half-free float colour and coverage), depth.t (ray distance, Å),
//   depth.z (view-space z, Å), N.X N.Y N.Z (world-space unit normal), as 32-bit floats;
//   patch.kind, patch.id, atom.id, flags as 32-bit unsigned integers (misses: id 2³²−1);
//   and seam.distance (FrameBuffers::seamDistance, Å, float) when the frame records it.
void writeExr(const std::string& path, const FrameBuffers& frame, const ImageMetadata& metadata);
// The same EXR, encoded in memory.
EncodedImage encodeExr(const std::string& path, const FrameBuffers& frame, const ImageMetadata& metadata);

// Reads an EXR written by writeExr (or by the GL path) back; seamDistance stays empty when
// the file has no seam.distance channel. Throws std::runtime_error
// naming the file and the missing channel when it is not such a file.
FrameBuffers readExr(const std::string& path, ImageMetadata* metadata = nullptr);

// Whether `path` is an image with every channel writeExr writes (a SurfTrace EXR), as opposed
// to another program's buffers. Throws std::runtime_error when it cannot be read.
bool hasFrameBufferChannels(const std::string& path);

// The channels of any image file OpenImageIO reads (EXR, PFM, TIFF, PNG, ...), each as float:
// floating-point channels as they are, integer ones normalised to [0, 1] (a 16-bit PNG's
// 65535 is 1.0). Rows come in the order the file stores them, which is what a program that
// wrote a buffer as it was (glReadPixels' rows, bottom first) put there: for a PFM, a format
// defined bottom row first, that is the file's order, not the top-first order in which
// OpenImageIO turns it into an image.
struct ImageChannels {
  std::string path;
  std::string format;             // OpenImageIO's name for the file format ("openexr", "pnm", ...)
  int width = 0, height = 0;
  std::vector<std::string> names;
  std::vector<std::string> types;  // per channel, as stored: "float", "half", "uint16", ...
  std::vector<float> values;       // names.size() per pixel, row by row, stored order

  std::size_t pixels() const { return static_cast<std::size_t>(width) * static_cast<std::size_t>(height); }
  // The channel called `name`, or -1.
  int find(const std::string& name) const;
  bool isFloat(int channel) const;  // float, half or double in the file (not normalised integers)
  float at(std::size_t pixel, int channel) const { return values[pixel * names.size() + static_cast<std::size_t>(channel)]; }
  // "R, G, B" for messages.
  std::string nameList() const;
};

// Throws std::runtime_error naming the file when OpenImageIO cannot read it (or it is deep).
ImageChannels readImageChannels(const std::string& path);

}  // namespace surftrace::view

// Writing and reading rendered frames through OpenImageIO: PNG colour, multi-channel EXR, and
// the channels of any image file another program wrote.
#include "view/image_io.hpp"

#include <sys/resource.h>
#include <unistd.h>

#include <algorithm>
#include <array>
#include <cctype>
#include <cmath>
#include <cstdint>
#include <cstdio>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <span>
#include <stdexcept>
#include <system_error>

#include <OpenImageIO/filesystem.h>
#include <OpenImageIO/imageio.h>

#include "build/io/output_file.hpp"
#include "view/srgb.hpp"

namespace surftrace::view {
namespace {

namespace oiio = OIIO;

constexpr const char* kFloatChannels[] = {"R", "G", "B", "A", "depth.t", "depth.z", "N.X", "N.Y", "N.Z"};
constexpr const char* kUintChannels[] = {"patch.kind", "patch.id", "atom.id", "flags"};
constexpr int kFloatCount = 9, kUintCount = 4, kChannels = kFloatCount + kUintCount;
// Written after the others when the frame records it (FrameBuffers::seamDistance).
constexpr const char* kSeamChannel = "seam.distance";

// The bytes before a PFM's pixels: "PF" or "Pf", the width, the height and the scale, each
// followed by one white-space byte (0 when the file does not read so: OpenImageIO decides).
std::uintmax_t pfmHeaderSize(const std::string& path) {
  std::ifstream in(path, std::ios::binary);
  char head[256] = {};
  in.read(head, sizeof head);
  const std::size_t n = static_cast<std::size_t>(in.gcount());
  std::size_t at = 0;
  for (int token = 0; token < 4; ++token) {
    while (at < n && std::isspace(static_cast<unsigned char>(head[at]))) ++at;
    if (at == n) return 0;
    while (at < n && !std::isspace(static_cast<unsigned char>(head[at]))) ++at;
    if (at == n) return 0;
    ++at;  // the one white-space byte after the token
  }
  return at;
}

// Refuses an image whose header claims more pixels than can be read, before anything is
// allocated for them: a 20-byte PFM header may claim 100000x100000 pixels (std::bad_alloc, or
// minutes of paging), and an EXR's data window is as easily forged. Checked as `--size` is,
// against the memory this process may have (this machine's, or less under ulimit -v), and for
// a PFM, whose pixels are stored raw, against the file's own size.
void checkPixelsFit(const std::string& path, const oiio::ImageSpec& spec, const std::string& format,
                    double bytesPerPixel) {
  const double pixels = static_cast<double>(spec.width) * static_cast<double>(spec.height);
  const std::string claim = std::to_string(spec.width) + "x" + std::to_string(spec.height) + " pixels of " +
                            std::to_string(spec.nchannels) + (spec.nchannels == 1 ? " channel" : " channels");
  char text[200];
  const long pages = sysconf(_SC_PHYS_PAGES), pageSize = sysconf(_SC_PAGE_SIZE);
  double memory = pages > 0 && pageSize > 0 ? static_cast<double>(pages) * static_cast<double>(pageSize) : HUGE_VAL;
  rlimit limit{};
  const bool limited = getrlimit(RLIMIT_AS, &limit) == 0 && limit.rlim_cur != RLIM_INFINITY &&
                       static_cast<double>(limit.rlim_cur) < memory;
  if (limited) memory = static_cast<double>(limit.rlim_cur);
  const double needed = bytesPerPixel * pixels;
  if (needed > memory) {
    std::snprintf(text, sizeof text, "about %.1f GiB to read, more than %s %.1f GiB", needed / 0x1p30,
                  limited ? "the memory limit's (ulimit -v)" : "this machine's", memory / 0x1p30);
    throw std::runtime_error(path + ": not enough memory to hold the image it describes: its header claims " + claim +
                             ", which need " + text + " (a damaged or forged header, or an image too large for this "
                             "machine)");
  }
  if (format == "pnm" && spec.format == oiio::TypeDesc::FLOAT) {
    const double stored = 4.0 * pixels * spec.nchannels;
    std::error_code ec;
    const auto size = std::filesystem::file_size(path, ec);
    const std::uintmax_t header = ec ? 0 : std::min<std::uintmax_t>(pfmHeaderSize(path), size);
    if (!ec && stored > static_cast<double>(size - header)) {
      std::snprintf(text, sizeof text, "%.0f bytes of floats; it holds %ju after its header", stored,
                    static_cast<std::uintmax_t>(size - header));
      throw std::runtime_error(path + ": cannot read its pixels: the file is cut short or damaged (its header promises " +
                               claim + ", " + text + ")");
    }
  }
}

void addMetadata(oiio::ImageSpec& spec, const ImageMetadata& metadata) {
  for (const auto& [key, value] : metadata) spec.attribute(key, value);
}

// Encodes the image with OpenImageIO into memory (the format from the extension of `path`),
// for build::writeFileAtomically: every write checked, the file whole or not there at all.
// (OpenImageIO's own file writers let a full disk pass.)
// "-" (the standard output) and /dev/null have no extension: `standardFormat` is their format.
EncodedImage encode(const std::string& path, const oiio::ImageSpec& spec, oiio::TypeDesc type, const void* pixels,
                    const char* standardFormat) {
  auto out = oiio::ImageOutput::create(path);
  if (!out && build::isWrittenInPlace(path)) {
    static_cast<void>(oiio::geterror());  // clears OpenImageIO's record of the failed lookup
    out = oiio::ImageOutput::create(standardFormat);
  }
  if (!out) throw std::runtime_error(path + ": cannot write this image format (" + oiio::geterror() + ")");
  if (!out->supports("ioproxy"))
    throw std::runtime_error(path + ": OpenImageIO's " + out->format_name() + " writer cannot write to memory");
  std::vector<unsigned char> bytes;
  oiio::Filesystem::IOVecOutput proxy(bytes);
  if (!out->set_ioproxy(&proxy) || !out->open(path, spec))
    throw std::runtime_error(path + ": cannot encode the image: " + out->geterror());
  if (!out->write_image(type, pixels) || !out->close())
    throw std::runtime_error(path + ": cannot encode the image: " + out->geterror());
  return bytes;
}

// Why OpenImageIO could not read the pixels of `path`: its own words when it has some (the
// reader's, else its global ones), else what the file's size says (a PFM cut short gives none).
std::string readFailure(const std::string& path, oiio::ImageInput& in) {
  std::string why = in.geterror();
  if (why.empty()) why = oiio::geterror();
  if (why.empty()) {
    const oiio::ImageSpec& spec = in.spec();
    std::error_code error;
    const auto bytes = std::filesystem::file_size(path, error);
    why = "cannot read its pixels: the file is cut short or damaged (its header promises " + std::to_string(spec.width) +
          "x" + std::to_string(spec.height) + " pixels of " + std::to_string(spec.nchannels) + (spec.nchannels == 1 ? " channel" : " channels") +
          (error ? std::string(")") : "; it holds " + std::to_string(bytes) + " bytes)");
  }
  return path + ": " + why;
}

// round(255 · sRGB(clamp(v, 0, 1))), exactly and without a pow per channel (a 4K frame has 25
// million): code k is reached where the encoded value passes (k − ½)/255, so the code is the
// count of the 255 linear thresholds srgbToLinear((k + ½)/255) that v reaches. A table of that
// count at every 1/4096 gives the start; no bucket of 1/4096 holds more than two thresholds
// (their narrowest gap, near 0, is 1/(255 · 12.92)). NaN, which no clamp orders, is black.
unsigned char srgbByte(float v) {
  constexpr int kBuckets = 4096;
  struct Tables {
    std::array<double, 255> thresholds{};
    std::array<unsigned char, kBuckets + 1> start{};
  };
  static const Tables tables = [] {
    Tables t;
    for (std::size_t k = 0; k < t.thresholds.size(); ++k)
      t.thresholds[k] = srgbToLinear((static_cast<double>(k) + 0.5) / 255.0);
    for (std::size_t i = 0; i < t.start.size(); ++i)
      t.start[i] = static_cast<unsigned char>(
          std::upper_bound(t.thresholds.begin(), t.thresholds.end(), static_cast<double>(i) / kBuckets) - t.thresholds.begin());
    return t;
  }();
  if (std::isnan(v) || v <= 0.0f) return 0;
  if (v >= 1.0f) return 255;
  const double x = v;
  unsigned code = tables.start[static_cast<std::size_t>(x * kBuckets)];
  while (code < tables.thresholds.size() && tables.thresholds[code] <= x) ++code;
  return static_cast<unsigned char>(code);
}

unsigned char linearByte(float v) {
  return std::isnan(v) ? 0 : static_cast<unsigned char>(std::lround(255.0f * std::clamp(v, 0.0f, 1.0f)));
}

// OpenImageIO's name for the format it writes `path` in: "png" for "-" and /dev/null, as
// encode() does; "" when it has none (encode() says why).
std::string outputFormat(const std::string& path) {
  const auto out = oiio::ImageOutput::create(path);
  static_cast<void>(oiio::geterror());  // clears OpenImageIO's record of a failed lookup
  if (!out) return build::isWrittenInPlace(path) ? "png" : "";
  return out->format_name();
}

void writeEncoded(const std::string& path, const EncodedImage& bytes) {
  build::writeFileAtomically(path, std::as_bytes(std::span<const unsigned char>(bytes)));
}

}  // namespace

void checkImageOutputName(const std::string& path, const std::string& option, ImageContent content) {
  std::error_code ec;
  if (std::filesystem::is_directory(path, ec)) return;  // build::prepareOutputPath says what is wrong
  const std::string extension = std::filesystem::path(path).extension().string();
  const std::string named = option + " " + path + ": ";
  // The writer that encode() will ask for, chosen by the extension as it will be.
  auto out = oiio::ImageOutput::create(path);
  if (!out && build::isWrittenInPlace(path)) {  // "-", /dev/null: the default format (encode)
    static_cast<void>(oiio::geterror());
    return;
  }
  if (!out || !out->supports("ioproxy")) {
    static_cast<void>(oiio::geterror());  // clears OpenImageIO's record of the failed lookup
    const std::string what = extension.empty() ? "the name has no extension to choose an image format by"
                                               : extension + " is not an image format SurfTrace can write";
    const std::string want = content == ImageContent::Buffers ? "name it .exr" : "name it .png (or .exr, .tif, .jpg)";
    throw std::invalid_argument(named + what + "; " + want +
                                ". (SurfTrace writes images; the surface itself, as analytic patches, is `surftrace "
                                "build -o FILE.stp`.)");
  }
  if (content == ImageContent::Buffers && std::string(out->format_name()) != "openexr")
    throw std::invalid_argument(named + option + " needs an .exr name: it writes every buffer (depth, normal, ids, " +
                                "flags) in named float and integer channels, which only OpenEXR holds: name it .exr (-o " +
                                "writes the colour image in other formats)");
}

EncodedImage encodePng(const std::string& path, const FrameBuffers& f, const ImageMetadata& metadata,
                       int compressionLevel) {
  // RGB over an opaque background; RGBA over a transparent one, with the colour made straight
  // (unassociated, as PNG stores it) here rather than by OpenImageIO from 8-bit values.
  const int channels = f.transparentBackground ? 4 : 3;
  // A float format named by -o (OpenEXR, Radiance HDR) keeps the linear colour: the sRGB curve
  // is for 8-bit pixels, where it spends the codes where the eye tells levels apart.
  const std::string format = outputFormat(path);
  const bool linear = format == "openexr" || format == "hdr";
  oiio::ImageSpec spec(f.width, f.height, channels, linear ? oiio::TypeDesc::FLOAT : oiio::TypeDesc::UINT8);
  spec.attribute("png:compressionLevel", compressionLevel);
  if (f.transparentBackground) {
    spec.alpha_channel = 3;
    spec.attribute("oiio:UnassociatedAlpha", 1);
  }
  addMetadata(spec, metadata);
  // OpenImageIO's PNG writer turns "sRGB" into the file's sRGB chunk (with gAMA and cHRM), which
  // viewers and browsers honour; the text attribute says the same for people and scripts. Not
  // for TIFF: OpenImageIO 2.4 writes it as an EXIF directory, and into memory that directory
  // spoils the file ("TIFF directory is missing required ImageLength field").
  if (format != "tiff") spec.attribute("oiio:ColorSpace", linear ? "Linear" : "sRGB");
  spec.attribute("surftrace:encoding", linear ? kLinearEncoding : kSrgbEncoding);
  std::vector<float> straight(static_cast<std::size_t>(channels) * f.pixels());
  for (std::size_t p = 0; p < f.pixels(); ++p) {
    const float alpha = f.rgba[4 * p + 3];
    const float scale = f.transparentBackground && alpha > 0.0f ? 1.0f / alpha : 1.0f;
    for (int c = 0; c < 3; ++c) straight[static_cast<std::size_t>(channels) * p + static_cast<std::size_t>(c)] = f.rgba[4 * p + c] * scale;
    if (f.transparentBackground) straight[static_cast<std::size_t>(channels) * p + 3] = alpha;
  }
  if (linear) return encode(path, spec, oiio::TypeDesc::FLOAT, straight.data(), "png");
  // Colour through the sRGB curve; alpha, a coverage and not a colour, stays linear.
  std::vector<unsigned char> pixels(straight.size());
  for (std::size_t i = 0; i < straight.size(); ++i)
    pixels[i] = f.transparentBackground && i % 4 == 3 ? linearByte(straight[i]) : srgbByte(straight[i]);
  return encode(path, spec, oiio::TypeDesc::UINT8, pixels.data(), "png");
}

void writePng(const std::string& path, const FrameBuffers& f, const ImageMetadata& metadata, int compressionLevel) {
  writeEncoded(path, encodePng(path, f, metadata, compressionLevel));
}

EncodedImage encodeExr(const std::string& path, const FrameBuffers& f, const ImageMetadata& metadata) {
  const bool seam = !f.seamDistance.empty();
  const int channels = kChannels + (seam ? 1 : 0);
  oiio::ImageSpec spec(f.width, f.height, channels, oiio::TypeDesc::FLOAT);
  spec.channelnames.assign(std::begin(kFloatChannels), std::end(kFloatChannels));
  spec.channelnames.insert(spec.channelnames.end(), std::begin(kUintChannels), std::end(kUintChannels));
  spec.channelformats.assign(kFloatCount, oiio::TypeDesc::FLOAT);
  spec.channelformats.insert(spec.channelformats.end(), kUintCount, oiio::TypeDesc::UINT32);
  if (seam) {
    spec.channelnames.emplace_back(kSeamChannel);
    spec.channelformats.push_back(oiio::TypeDesc::FLOAT);
  }
  spec.alpha_channel = 3;
  spec.z_channel = 5;
  spec.attribute("compression", "zip");
  addMetadata(spec, metadata);
  // Native per-channel layout: 9 floats, 4 uint32, then the seam distance's float per pixel,
  // all 4 bytes wide.
  const std::size_t stride = static_cast<std::size_t>(channels);
  std::vector<std::uint32_t> pixels(stride * f.pixels());
  for (std::size_t p = 0; p < f.pixels(); ++p) {
    const float values[kFloatCount] = {f.rgba[4 * p], f.rgba[4 * p + 1], f.rgba[4 * p + 2], f.rgba[4 * p + 3],
                                       f.depth[p], f.viewZ[p], f.normal[3 * p], f.normal[3 * p + 1], f.normal[3 * p + 2]};
    std::memcpy(&pixels[stride * p], values, sizeof values);
    pixels[stride * p + 9] = f.kind[p];
    pixels[stride * p + 10] = f.patchId[p];
    pixels[stride * p + 11] = f.atomId[p];
    pixels[stride * p + 12] = f.flags[p];
    if (seam) std::memcpy(&pixels[stride * p + 13], &f.seamDistance[p], sizeof(float));
  }
  return encode(path, spec, oiio::TypeUnknown, pixels.data(), "openexr");
}

void writeExr(const std::string& path, const FrameBuffers& f, const ImageMetadata& metadata) {
  writeEncoded(path, encodeExr(path, f, metadata));
}

FrameBuffers readExr(const std::string& path, ImageMetadata* metadata) {
  auto in = oiio::ImageInput::open(path);
  if (!in) throw std::runtime_error(path + ": cannot read: " + oiio::geterror());
  const oiio::ImageSpec& spec = in->spec();
  auto channel = [&](const char* name, oiio::TypeDesc type) {
    for (int c = 0; c < spec.nchannels; ++c)
      if (spec.channelnames[static_cast<std::size_t>(c)] == name) {
        if (spec.channelformat(c) != type)
          throw std::runtime_error(path + ": channel " + name + " has type " + spec.channelformat(c).c_str() +
                                   ", expected " + type.c_str());
        return c;
      }
    throw std::runtime_error(path + ": no channel '" + name + "'; is this a surftrace EXR?");
  };
  // The frame's 4 bytes a channel, and each channel read through a buffer of its own.
  checkPixelsFit(path, spec, in->format_name(), 4.0 * spec.nchannels + 4.0);
  FrameBuffers f;
  f.reset(spec.width, spec.height);
  const std::size_t n = f.pixels();
  // Read each channel on its own in its own type, so that integer ids are not normalised.
  auto readFloat = [&](const char* name, std::vector<float>& dst, int stride, int offset) {
    const int c = channel(name, oiio::TypeDesc::FLOAT);
    std::vector<float> tmp(n);
    if (!in->read_image(0, 0, c, c + 1, oiio::TypeDesc::FLOAT, tmp.data()))
      throw std::runtime_error(readFailure(path, *in));
    for (std::size_t p = 0; p < n; ++p) dst[stride * p + static_cast<std::size_t>(offset)] = tmp[p];
  };
  auto readUint = [&](const char* name, std::vector<std::uint32_t>& dst) {
    const int c = channel(name, oiio::TypeDesc::UINT32);
    if (!in->read_image(0, 0, c, c + 1, oiio::TypeDesc::UINT32, dst.data()))
      throw std::runtime_error(readFailure(path, *in));
  };
  for (int c = 0; c < 4; ++c) readFloat(kFloatChannels[c], f.rgba, 4, c);
  readFloat("depth.t", f.depth, 1, 0);
  readFloat("depth.z", f.viewZ, 1, 0);
  for (int c = 0; c < 3; ++c) readFloat(kFloatChannels[6 + c], f.normal, 3, c);
  readUint("patch.kind", f.kind);
  readUint("patch.id", f.patchId);
  readUint("atom.id", f.atomId);
  readUint("flags", f.flags);
  // An image from before the channel existed, or from the GL path, leaves it empty.
  if (std::find(spec.channelnames.begin(), spec.channelnames.end(), kSeamChannel) != spec.channelnames.end()) {
    f.seamDistance.resize(n);
    readFloat(kSeamChannel, f.seamDistance, 1, 0);
  }
  if (metadata)
    for (const auto& attr : spec.extra_attribs)
      if (attr.type() == oiio::TypeDesc::STRING) (*metadata)[attr.name().string()] = attr.get_string();
  return f;
}

bool hasFrameBufferChannels(const std::string& path) {
  auto in = oiio::ImageInput::open(path);
  if (!in) throw std::runtime_error(path + ": cannot read: " + oiio::geterror());
  const std::vector<std::string>& names = in->spec().channelnames;
  auto has = [&](const char* name) { return std::find(names.begin(), names.end(), name) != names.end(); };
  return std::all_of(std::begin(kFloatChannels), std::end(kFloatChannels), has) &&
         std::all_of(std::begin(kUintChannels), std::end(kUintChannels), has);
}

int ImageChannels::find(const std::string& name) const {
  const auto it = std::find(names.begin(), names.end(), name);
  return it == names.end() ? -1 : static_cast<int>(it - names.begin());
}

bool ImageChannels::isFloat(int channel) const {
  const std::string& t = types[static_cast<std::size_t>(channel)];
  return t == "float" || t == "half" || t == "double";
}

std::string ImageChannels::nameList() const {
  std::string text;
  for (const std::string& n : names) text += (text.empty() ? "" : ", ") + n;
  return text;
}

ImageChannels readImageChannels(const std::string& path) {
  auto in = oiio::ImageInput::open(path);
  if (!in) throw std::runtime_error(path + ": cannot read: " + oiio::geterror());
  const oiio::ImageSpec& spec = in->spec();
  if (spec.deep) throw std::runtime_error(path + ": a deep image (several samples per pixel); expected one value per pixel");
  if (spec.nchannels <= 0 || spec.width <= 0 || spec.height <= 0)
    throw std::runtime_error(path + ": an empty image (" + std::to_string(spec.width) + "x" + std::to_string(spec.height) +
                             ", " + std::to_string(spec.nchannels) + " channels)");
  // Every channel as float, and OpenImageIO's own buffer of the file's pixels while it reads.
  checkPixelsFit(path, spec, in->format_name(), 8.0 * spec.nchannels);
  ImageChannels image;
  image.path = path;
  image.format = in->format_name();
  image.width = spec.width, image.height = spec.height;
  for (int c = 0; c < spec.nchannels; ++c) {
    image.names.push_back(spec.channelnames.size() > static_cast<std::size_t>(c) ? spec.channelnames[static_cast<std::size_t>(c)]
                                                                                 : "channel " + std::to_string(c));
    image.types.emplace_back(spec.channelformat(c).c_str());
  }
  image.values.resize(image.pixels() * image.names.size());
  if (!in->read_image(0, 0, 0, spec.nchannels, oiio::TypeDesc::FLOAT, image.values.data()))
    throw std::runtime_error(readFailure(path, *in));
  // A PFM stores its bottom row first and OpenImageIO hands its rows over top first: turn them
  // back, so that a buffer written as it was reads as it was.
  if (image.format == "pnm" && spec.format == oiio::TypeDesc::FLOAT) {
    const std::size_t row = static_cast<std::size_t>(image.width) * image.names.size();
    for (int y = 0; y < image.height / 2; ++y)
      std::swap_ranges(image.values.begin() + static_cast<std::ptrdiff_t>(row * static_cast<std::size_t>(y)),
                       image.values.begin() + static_cast<std::ptrdiff_t>(row * static_cast<std::size_t>(y + 1)),
                       image.values.begin() + static_cast<std::ptrdiff_t>(row * static_cast<std::size_t>(image.height - 1 - y)));
  }
  return image;
}

}  // namespace surftrace::view

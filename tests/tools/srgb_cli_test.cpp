// `render -o`: 8-bit images hold the sRGB encoding of the linear colour that the EXR holds, and
// say so; float images named by -o keep the linear colour.
#include <algorithm>
#include <cmath>
#include <cstdint>
#include <filesystem>
#include <fstream>
#include <iterator>
#include <string>
#include <vector>

#include <OpenImageIO/imageio.h>
#include <gtest/gtest.h>

#include "oracles/srgb.hpp"
#include "run_tool.hpp"
#include "temp_dir.hpp"
#include "view/image_io.hpp"

namespace surftrace::tools::test {
namespace {

namespace fs = std::filesystem;

const std::string kCrambin = std::string(SURFTRACE_TEST_DATA) + "/structures/1crn.pdb";

using ::surftrace::test::srgbCode;

// The 8-bit codes of an image file as OpenImageIO reads them, with no conversion.
std::vector<unsigned char> codes(const fs::path& path, int channels, OIIO::ImageSpec* spec) {
  auto in = OIIO::ImageInput::open(path.string());
  if (!in) return {};
  *spec = in->spec();
  std::vector<unsigned char> px(static_cast<std::size_t>(spec->width) * static_cast<std::size_t>(spec->height) *
                                static_cast<std::size_t>(channels));
  if (spec->nchannels != channels || !in->read_image(0, 0, 0, channels, OIIO::TypeDesc::UINT8, px.data())) return {};
  return px;
}

// The chunk types of a PNG file, in order, read from its bytes (PNG specification, section 5).
std::vector<std::string> pngChunks(const fs::path& path) {
  std::ifstream in(path, std::ios::binary);
  const std::vector<unsigned char> b((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
  std::vector<std::string> types;
  for (std::size_t at = 8; at + 8 <= b.size();) {
    const std::size_t length = (std::size_t{b[at]} << 24) | (std::size_t{b[at + 1]} << 16) | (std::size_t{b[at + 2]} << 8) | b[at + 3];
    types.emplace_back(b.begin() + static_cast<std::ptrdiff_t>(at + 4), b.begin() + static_cast<std::ptrdiff_t>(at + 8));
    at += 12 + length;
  }
  return types;
}

TEST(SrgbCli, EightBitImagesHoldTheSrgbEncodingOfTheExrColour) {
  const fs::path dir = ::surftrace::test::testTempDir();
  const fs::path png = dir / "a.png", tif = dir / "a.tif", exr = dir / "a.exr";
  const Result r = runTool("render " + kCrambin + " --size 96x80 --quiet --exr " + exr.string() + " -o " + png.string());
  ASSERT_EQ(r.status, 0) << r.output;
  ASSERT_EQ(runTool("render " + kCrambin + " --size 96x80 --quiet -o " + tif.string()).status, 0);
  const view::FrameBuffers f = view::readExr(exr.string());
  for (const fs::path& path : {png, tif}) {
    OIIO::ImageSpec spec;
    const std::vector<unsigned char> px = codes(path, 3, &spec);
    ASSERT_EQ(px.size(), 3 * f.pixels()) << path;
    std::size_t wrong = 0, midTones = 0;
    for (std::size_t p = 0; p < f.pixels(); ++p)
      for (int c = 0; c < 3; ++c) {
        const double linear = f.rgba[4 * p + static_cast<std::size_t>(c)];
        const int code = px[3 * p + static_cast<std::size_t>(c)];
        wrong += std::abs(code - srgbCode(linear)) > 1;
        // Where the two encodings part most: a linear 8-bit code would be 40 or more darker.
        midTones += linear > 0.1 && linear < 0.6 && code - std::lround(255.0 * linear) >= 40;
      }
    EXPECT_EQ(wrong, 0u) << path;
    EXPECT_GT(midTones, 500u) << path << ": too few mid-tones to tell sRGB from linear";
  }
  // The PNG's own sRGB chunk (which browsers and viewers honour) comes before its pixels, and its
  // text says what the codes are (a TIFF keeps no such text).
  const std::vector<std::string> chunks = pngChunks(png);
  const auto srgb = std::find(chunks.begin(), chunks.end(), "sRGB"), idat = std::find(chunks.begin(), chunks.end(), "IDAT");
  EXPECT_NE(srgb, chunks.end()) << "no sRGB chunk";
  EXPECT_LT(srgb, idat);
  OIIO::ImageSpec spec;
  ASSERT_FALSE(codes(png, 3, &spec).empty());
  EXPECT_EQ(spec.get_string_attribute("oiio:ColorSpace"), "sRGB");
  EXPECT_EQ(spec.get_string_attribute("surftrace:encoding"), std::string(view::kSrgbEncoding));
}

// Colours are given in sRGB and decoded where they enter, so an unshaded one comes out of the
// 8-bit image as the bytes it went in as: the background, as #rrggbb or as r,g,b numbers (k/255
// gives code k), and in the EXR as its linear value (the standard's decoding).
TEST(SrgbCli, BackgroundComesOutAsTheSrgbBytesGiven) {
  const fs::path dir = ::surftrace::test::testTempDir();
  struct Case {
    std::string given;
    int bytes[3];
  };
  const std::vector<Case> cases = {{"'#808080'", {128, 128, 128}},
                                   {"'#1a7fe6'", {26, 127, 230}},
                                   {"0.2,0.4,0.6", {51, 102, 153}},
                                   {"0.003921569,0.5019608,0.9960785", {1, 128, 254}}};
  for (const Case& c : cases) {
    const fs::path png = dir / "bg.png", exr = dir / "bg.exr";
    const Result r = runTool("render " + kCrambin + " --size 64x48 --quiet --background " + c.given + " --exr " +
                             exr.string() + " -o " + png.string());
    ASSERT_EQ(r.status, 0) << c.given << ": " << r.output;
    const view::FrameBuffers f = view::readExr(exr.string());
    OIIO::ImageSpec spec;
    const std::vector<unsigned char> px = codes(png, 3, &spec);
    ASSERT_EQ(px.size(), 3 * f.pixels());
    std::size_t background = 0, wrong = 0, wrongLinear = 0;
    for (std::size_t p = 0; p < f.pixels(); ++p) {
      if (f.kind[p] != 0) continue;
      ++background;
      for (std::size_t k = 0; k < 3; ++k) {
        wrong += px[3 * p + k] != c.bytes[k];
        wrongLinear += std::abs(f.rgba[4 * p + k] - ::surftrace::test::linearFromSrgb(c.bytes[k] / 255.0)) > 1e-6;
      }
    }
    EXPECT_GT(background, 500u) << c.given;
    EXPECT_EQ(wrong, 0u) << c.given << ": background pixels not the bytes given (first: " << int(px[0]) << ","
                         << int(px[1]) << "," << int(px[2]) << ")";
    EXPECT_EQ(wrongLinear, 0u) << c.given << ": the EXR's background is not the linear value of the colour given";
  }
}

// `-o NAME.exr` writes the colour alone, as floats: the linear values of the --exr buffers.
TEST(SrgbCli, FloatColourImageKeepsTheLinearColour) {
  const fs::path dir = ::surftrace::test::testTempDir();
  const fs::path colour = dir / "colour.exr", exr = dir / "buffers.exr";
  const Result r = runTool("render " + kCrambin + " --size 64x64 --quiet --exr " + exr.string() + " -o " + colour.string());
  ASSERT_EQ(r.status, 0) << r.output;
  const view::FrameBuffers f = view::readExr(exr.string());
  auto in = OIIO::ImageInput::open(colour.string());
  ASSERT_TRUE(in);
  ASSERT_EQ(in->spec().nchannels, 3);
  EXPECT_EQ(in->spec().get_string_attribute("surftrace:encoding"), view::kLinearEncoding);
  std::vector<float> rgb(3 * f.pixels());
  ASSERT_TRUE(in->read_image(0, 0, 0, 3, OIIO::TypeDesc::FLOAT, rgb.data()));
  std::size_t wrong = 0;
  for (std::size_t p = 0; p < f.pixels(); ++p)
    for (std::size_t c = 0; c < 3; ++c) wrong += std::abs(rgb[3 * p + c] - f.rgba[4 * p + c]) > 1e-6f;
  EXPECT_EQ(wrong, 0u);
}

}  // namespace
}  // namespace surftrace::tools::test

// Camera rays and framing against their defining formulas; EXR/PNG round trips.
#include <algorithm>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <limits>
#include <random>
#include <set>
#include <string>
#include <vector>

#include <OpenImageIO/imageio.h>
#include <glm/geometric.hpp>
#include <gtest/gtest.h>

#include "oracles/srgb.hpp"
#include "temp_dir.hpp"
#include "view/camera.hpp"
#include "view/image_io.hpp"

namespace surftrace::view {
namespace {

constexpr double kPi = 3.14159265358979323846;

// The corner and centre rays follow from the field of view alone.
TEST(Camera, PerspectiveRaysSpanTheFieldOfView) {
  Camera c;
  c.eye = {1, 2, 3};
  c.lookAt = {1, 2, -7};
  c.fovY = 60.0;
  c.width = 200;
  c.height = 100;
  const Ray centre = c.ray(100.0, 50.0);
  EXPECT_NEAR(glm::length(centre.dir - glm::dvec3(0, 0, -1)), 0.0, 1e-15);
  // Top edge centre: the angle to the axis is fov/2; it points up (+y).
  const Ray top = c.ray(100.0, 0.0);
  EXPECT_NEAR(std::acos(glm::dot(top.dir, centre.dir)), 30.0 * kPi / 180.0, 1e-12);
  EXPECT_GT(top.dir.y, 0.0);
  // Right edge: tan(angle) = aspect·tan(fov/2).
  const Ray right = c.ray(200.0, 50.0);
  EXPECT_NEAR(std::tan(std::acos(glm::dot(right.dir, centre.dir))), 2.0 * std::tan(30.0 * kPi / 180.0), 1e-12);
  EXPECT_GT(right.dir.x, 0.0);
  EXPECT_NEAR(c.pixelFootprint(10.0), 2.0 * 10.0 * std::tan(30.0 * kPi / 180.0) / 100.0, 1e-15);
}

TEST(Camera, OrthographicRaysAreParallel) {
  Camera c;
  c.projection = Projection::Orthographic;
  c.eye = {0, 0, 10};
  c.lookAt = {0, 0, 0};
  c.orthoHeight = 8.0;
  c.width = c.height = 64;
  const Ray a = c.ray(0.0, 0.0), b = c.ray(64.0, 64.0);
  EXPECT_EQ(a.dir, b.dir);
  EXPECT_NEAR(a.org.x, -4.0, 1e-14);
  EXPECT_NEAR(a.org.y, 4.0, 1e-14);
  EXPECT_NEAR(b.org.x, 4.0, 1e-14);
  EXPECT_NEAR(b.org.y, -4.0, 1e-14);
}

// After framing, every sphere projects inside the image and the camera is outside all.
TEST(Camera, FramingKeepsEverySphereInView) {
  std::mt19937_64 rng(5);
  std::uniform_real_distribution<double> u(-20.0, 20.0), r(0.5, 3.0);
  std::vector<glm::dvec3> centers;
  std::vector<double> radii;
  for (int i = 0; i < 200; ++i) centers.push_back({u(rng), u(rng) * 0.3, u(rng) + 100.0}), radii.push_back(r(rng));
  for (const char* view : {"front", "back", "left", "right", "top", "bottom", "1,2,3"}) {
    for (Projection proj : {Projection::Perspective, Projection::Orthographic}) {
      Camera c;
      c.width = 300;
      c.height = 200;
      c.projection = proj;
      c = frameSpheres(c, centers, radii, namedViewDirection(view));
      c.validate();
      const glm::dvec3 f = c.forward(), rt = c.right(), up = c.trueUp();
      for (std::size_t i = 0; i < centers.size(); ++i) {
        const glm::dvec3 v = centers[i] - c.eye;
        const double z = glm::dot(v, f);
        ASSERT_GT(z, radii[i]) << view;
        double sx, sy;  // normalised image coordinates in [-1, 1] (for the sphere's centre)
        if (proj == Projection::Perspective) {
          const double h = std::tan(0.5 * c.fovY * kPi / 180.0);
          sx = glm::dot(v, rt) / z / (h * 1.5);
          sy = glm::dot(v, up) / z / h;
        } else {
          sx = glm::dot(v, rt) / (0.5 * c.orthoHeight * 1.5);
          sy = glm::dot(v, up) / (0.5 * c.orthoHeight);
        }
        EXPECT_LE(std::abs(sx), 1.0) << view;
        EXPECT_LE(std::abs(sy), 1.0) << view;
      }
    }
  }
}

// Several covers of one scene: with one cover it is frameSpheres; a second, looser cover
// (one ball around everything) changes nothing; where each cover is loose along a different
// axis, the camera frames the box both allow, and every sphere of the scene stays in view.
TEST(Camera, FramingSeveralCoversTakesTheTightestOfEach) {
  std::mt19937_64 rng(9);
  std::uniform_real_distribution<double> u(-10.0, 10.0), r(0.5, 2.0);
  std::vector<glm::dvec3> centers;
  std::vector<double> radii;
  for (int i = 0; i < 100; ++i) centers.push_back({u(rng), u(rng), u(rng)}), radii.push_back(r(rng));
  // Loose along x: every sphere widened by 30 in x (a row of balls along x). Loose along y:
  // the same along y. The scene lies in both.
  std::vector<glm::dvec3> wideX, wideY;
  std::vector<double> wideRadii;
  for (std::size_t i = 0; i < centers.size(); ++i)
    for (int k = -6; k <= 6; ++k) {
      wideX.push_back(centers[i] + glm::dvec3(5.0 * k, 0, 0));
      wideY.push_back(centers[i] + glm::dvec3(0, 5.0 * k, 0));
      wideRadii.push_back(radii[i] + 5.0);
    }
  const std::vector<glm::dvec3> one{glm::dvec3(0.0)};
  const std::vector<double> huge{100.0};
  for (Projection proj : {Projection::Perspective, Projection::Orthographic}) {
    Camera c;
    c.width = 200;
    c.height = 200;
    c.projection = proj;
    const glm::dvec3 front = namedViewDirection("front");
    const Camera plain = frameSpheres(c, centers, radii, front);
    const SphereCover scene{centers, radii}, ball{one, huge};
    const Camera single = frameSphereCovers(c, {&scene, 1}, front);
    EXPECT_EQ(single.eye, plain.eye);
    EXPECT_EQ(single.lookAt, plain.lookAt);
    EXPECT_EQ(single.orthoHeight, plain.orthoHeight);
    const SphereCover withBall[] = {ball, scene};
    const Camera loose = frameSphereCovers(c, withBall, front);
    EXPECT_EQ(loose.eye, plain.eye);
    EXPECT_EQ(loose.lookAt, plain.lookAt);

    const SphereCover x{wideX, wideRadii}, y{wideY, wideRadii};
    const Camera onlyX = frameSphereCovers(c, {&x, 1}, front), onlyY = frameSphereCovers(c, {&y, 1}, front);
    const SphereCover both[] = {x, y};
    const Camera tight = frameSphereCovers(c, both, front);
    // As near as the better cover alone (the look-at point moves a little, to the centre of
    // the box both allow), a smaller window than either, and still holding every sphere.
    if (proj == Projection::Perspective) {
      const double best = std::min(glm::distance(onlyX.eye, onlyX.lookAt), glm::distance(onlyY.eye, onlyY.lookAt));
      EXPECT_LE(glm::distance(tight.eye, tight.lookAt), 1.01 * best);
    } else {
      EXPECT_LT(tight.orthoHeight, onlyX.orthoHeight);
      EXPECT_LT(tight.orthoHeight, onlyY.orthoHeight);
    }
    const glm::dvec3 f = tight.forward(), rt = tight.right(), up = tight.trueUp();
    for (std::size_t i = 0; i < centers.size(); ++i) {
      const glm::dvec3 v = centers[i] - tight.eye;
      const double z = glm::dot(v, f);
      ASSERT_GT(z, radii[i]);
      // The sphere's silhouette inside the image: its centre's offset plus its radius.
      if (proj == Projection::Perspective) {
        const double h = std::tan(0.5 * tight.fovY * kPi / 180.0);
        EXPECT_LE(std::abs(glm::dot(v, rt)) + radii[i] * std::sqrt(1 + h * h), h * z);
        EXPECT_LE(std::abs(glm::dot(v, up)) + radii[i] * std::sqrt(1 + h * h), h * z);
      } else {
        EXPECT_LE(std::abs(glm::dot(v, rt)) + radii[i], 0.5 * tight.orthoHeight);
        EXPECT_LE(std::abs(glm::dot(v, up)) + radii[i], 0.5 * tight.orthoHeight);
      }
    }
  }
}

// Spheres framed in pieces (the frames of a trajectory, each on its own thread) give one camera,
// bit for bit, whatever the pieces and their order: the one framing them all at once gives (the
// same look-at point and window; the eye to rounding, as frameSpheres measures each sphere from
// the look-at point); and the perspective fit is tight: some sphere touches the margin-narrowed
// frustum.
TEST(Camera, FramingInPiecesEqualsFramingAllAtOnce) {
  std::mt19937_64 rng(11);
  std::uniform_real_distribution<double> u(-30.0, 30.0), r(0.5, 3.5);
  std::vector<glm::dvec3> centers;
  std::vector<double> radii;
  for (int i = 0; i < 300; ++i) centers.push_back({u(rng) + 40.0, u(rng) * 0.5, u(rng) - 7.0}), radii.push_back(r(rng));
  for (const char* view : {"front", "left", "top", "1,2,3"}) {
    for (Projection proj : {Projection::Perspective, Projection::Orthographic}) {
      Camera c;
      c.width = 320;
      c.height = 200;
      c.projection = proj;
      const glm::dvec3 direction = namedViewDirection(view);
      const Camera whole = frameSpheres(c, centers, radii, direction);
      SphereFraming pieces[3] = {SphereFraming(c, direction), SphereFraming(c, direction), SphereFraming(c, direction)};
      SphereFraming inOrder(c, direction);
      for (std::size_t i = 0; i < centers.size(); ++i) {
        pieces[(i * 7) % 3].add(centers[i], radii[i]);
        inOrder.add(centers[i], radii[i]);
      }
      SphereFraming merged(c, direction);
      for (int k : {2, 0, 1}) merged.merge(pieces[k]);
      const Camera framed = merged.frame(c);
      EXPECT_EQ(framed.eye, inOrder.frame(c).eye) << view;
      EXPECT_LT(glm::length(framed.eye - whole.eye), 1e-12 * glm::length(whole.eye - whole.lookAt)) << view;
      EXPECT_EQ(framed.lookAt, whole.lookAt) << view;
      EXPECT_EQ(framed.up, whole.up) << view;
      EXPECT_EQ(framed.orthoHeight, whole.orthoHeight) << view;
      if (proj != Projection::Perspective) continue;
      // The margin-narrowed frustum holds every sphere, and one of them touches it.
      const double hy = std::tan(0.5 * c.fovY * kPi / 180.0) / kFramingMargin, hx = hy * 1.6;
      const glm::dvec3 f = whole.forward(), rt = whole.right(), up = whole.trueUp();
      double slack = std::numeric_limits<double>::infinity();
      for (std::size_t i = 0; i < centers.size(); ++i) {
        const glm::dvec3 v = centers[i] - whole.eye;
        const double z = glm::dot(v, f);
        const double sx = hx * z - std::abs(glm::dot(v, rt)) - radii[i] * std::sqrt(1.0 + hx * hx);
        const double sy = hy * z - std::abs(glm::dot(v, up)) - radii[i] * std::sqrt(1.0 + hy * hy);
        EXPECT_GE(std::min(sx, sy), -1e-9) << view << " sphere " << i;
        slack = std::min({slack, sx, sy});
      }
      EXPECT_LT(slack, 1e-9) << view;
    }
  }
  EXPECT_TRUE(SphereFraming(Camera{}, {0, 0, -1}).empty());
  EXPECT_THROW(SphereFraming(Camera{}, {0, 0, -1}).frame(Camera{}), std::invalid_argument);
}

TEST(Camera, RejectsImpossibleSettings) {
  Camera c;
  c.lookAt = c.eye;
  EXPECT_THROW(c.validate(), std::invalid_argument);
  c = Camera{};
  c.up = c.lookAt - c.eye;
  EXPECT_THROW(c.validate(), std::invalid_argument);
  c = Camera{};
  c.fovY = 180.0;
  EXPECT_THROW(c.validate(), std::invalid_argument);
  c = Camera{};
  c.width = 0;
  EXPECT_THROW(c.validate(), std::invalid_argument);
  c = Camera{};
  c.eye.x = std::nan("");
  EXPECT_THROW(c.validate(), std::invalid_argument);
  EXPECT_THROW(namedViewDirection("sideways"), std::invalid_argument);
  EXPECT_THROW(namedViewDirection("0,0,0"), std::invalid_argument);
  EXPECT_THROW(namedViewDirection("1,2"), std::invalid_argument);
}

TEST(Camera, JsonRoundTripIsExact) {
  Camera c;
  c.projection = Projection::Orthographic;
  c.eye = {0.1, -2.0 / 3.0, 1e5 + 1.0 / 7.0};
  c.lookAt = {std::sqrt(2.0), 0.0, -1.0 / 3.0};
  c.up = {0.0, 1.0, 1e-3};
  c.fovY = 33.3333333;
  c.orthoHeight = 12.345678901234567;
  c.width = 321;
  c.height = 123;
  const Camera d = cameraFromJson(cameraToJson(c));
  EXPECT_EQ(d.eye, c.eye);
  EXPECT_EQ(d.lookAt, c.lookAt);
  EXPECT_EQ(d.up, c.up);
  EXPECT_EQ(d.fovY, c.fovY);
  EXPECT_EQ(d.orthoHeight, c.orthoHeight);
  EXPECT_EQ(d.width, c.width);
  EXPECT_EQ(d.height, c.height);
  EXPECT_EQ(d.projection, c.projection);
}

FrameBuffers randomFrame(int w, int h) {
  std::mt19937_64 rng(9);
  std::uniform_real_distribution<float> u(-100.0f, 100.0f);
  FrameBuffers f;
  f.width = w;
  f.height = h;
  const std::size_t n = f.pixels();
  for (std::size_t i = 0; i < 4 * n; ++i) f.rgba.push_back(u(rng));
  for (std::size_t i = 0; i < n; ++i) {
    f.depth.push_back(i % 7 ? u(rng) : std::numeric_limits<float>::infinity());
    f.viewZ.push_back(u(rng));
    f.kind.push_back(static_cast<std::uint32_t>(i % 4));
    f.patchId.push_back(i % 5 ? static_cast<std::uint32_t>(rng()) : ~0u);  // ids beyond 2^24 must survive
    f.atomId.push_back(static_cast<std::uint32_t>(rng()));
    f.flags.push_back(static_cast<std::uint32_t>(i % 8));
  }
  for (std::size_t i = 0; i < 3 * n; ++i) f.normal.push_back(u(rng));
  return f;
}

// Every channel survives the EXR round trip bit for bit, integer ids included.
TEST(ImageIo, ExrRoundTripIsExact) {
  const auto path = (surftrace::test::testTempDir() / "surftrace_roundtrip.exr").string();
  const FrameBuffers f = randomFrame(37, 23);
  writeExr(path, f, {{"surftrace:camera", "{\"x\":1}"}});
  ImageMetadata meta;
  const FrameBuffers g = readExr(path, &meta);
  EXPECT_EQ(g.width, f.width);
  EXPECT_EQ(g.height, f.height);
  EXPECT_EQ(g.rgba, f.rgba);
  EXPECT_EQ(g.depth, f.depth);
  EXPECT_EQ(g.viewZ, f.viewZ);
  EXPECT_EQ(g.normal, f.normal);
  EXPECT_EQ(g.kind, f.kind);
  EXPECT_EQ(g.patchId, f.patchId);
  EXPECT_EQ(g.atomId, f.atomId);
  EXPECT_EQ(g.flags, f.flags);
  EXPECT_EQ(meta["surftrace:camera"], "{\"x\":1}");
  std::filesystem::remove(path);
}

// The 8-bit code of a linear colour value (the oracle's sRGB formula).
unsigned char srgbCode(float linear) { return static_cast<unsigned char>(surftrace::test::srgbCode(linear)); }

TEST(ImageIo, PngHoldsTheSrgbEncodingOfTheClampedColour) {
  const auto path = (surftrace::test::testTempDir() / "surftrace_colour.png").string();
  FrameBuffers f = randomFrame(256, 128);
  // Every tenth of [0, 1], out-of-range values, the linear segment's end (0.0031308) and a
  // fine sweep of [0, 1] that meets every one of the 256 codes.
  const float special[] = {-0.5f, 0.0f, 0.001f, 0.0031308f, 0.004f, 0.1f, 0.2f, 0.5f, 0.9f, 1.0f, 1.5f};
  for (std::size_t p = 0; p < f.pixels(); ++p)
    for (int c = 0; c < 4; ++c)
      f.rgba[4 * p + c] = p < std::size(special) ? special[p]
                                                  : static_cast<float>((p - std::size(special)) * 3 + c) /
                                                        static_cast<float>(3 * (f.pixels() - std::size(special)));
  writePng(path, f, {});
  auto in = OIIO::ImageInput::open(path);
  ASSERT_TRUE(in);
  ASSERT_EQ(in->spec().nchannels, 3);
  EXPECT_EQ(in->spec().get_string_attribute("oiio:ColorSpace"), "sRGB");
  EXPECT_EQ(in->spec().get_string_attribute("surftrace:encoding"), kSrgbEncoding);
  std::vector<unsigned char> px(3 * f.pixels());
  ASSERT_TRUE(in->read_image(0, 0, 0, 3, OIIO::TypeDesc::UINT8, px.data()));
  std::set<int> codes;
  for (std::size_t p = 0; p < f.pixels(); ++p)
    for (int c = 0; c < 3; ++c) {
      EXPECT_EQ(px[3 * p + c], srgbCode(f.rgba[4 * p + c])) << "pixel " << p << " value " << f.rgba[4 * p + c];
      codes.insert(px[3 * p + c]);
    }
  EXPECT_EQ(codes.size(), 256u);
  EXPECT_EQ(px[3 * 7], 188) << "linear 0.5 is sRGB code 188 (0.7354 · 255)";
  std::filesystem::remove(path);
}

// A transparent background: the straight colour through the sRGB curve, alpha linear.
TEST(ImageIo, PngAlphaStaysLinear) {
  const auto path = (surftrace::test::testTempDir() / "surftrace_alpha.png").string();
  FrameBuffers f = randomFrame(16, 16);
  f.transparentBackground = true;
  for (std::size_t p = 0; p < f.pixels(); ++p) {
    const float alpha = static_cast<float>(p) / static_cast<float>(f.pixels() - 1);
    for (int c = 0; c < 3; ++c) f.rgba[4 * p + c] = alpha * 0.25f * static_cast<float>(c + 1);  // premultiplied
    f.rgba[4 * p + 3] = alpha;
  }
  writePng(path, f, {});
  OIIO::ImageSpec asStored;  // the file's straight colour, which OpenImageIO would premultiply
  asStored.attribute("oiio:UnassociatedAlpha", 1);
  auto in = OIIO::ImageInput::open(path, &asStored);
  ASSERT_TRUE(in);
  ASSERT_EQ(in->spec().nchannels, 4);
  std::vector<unsigned char> px(4 * f.pixels());
  ASSERT_TRUE(in->read_image(0, 0, 0, 4, OIIO::TypeDesc::UINT8, px.data()));
  for (std::size_t p = 1; p < f.pixels(); ++p) {
    const float alpha = f.rgba[4 * p + 3];
    EXPECT_EQ(px[4 * p + 3], static_cast<unsigned char>(std::lround(255.0f * alpha))) << p;
    for (int c = 0; c < 3; ++c) EXPECT_NEAR(px[4 * p + c], srgbCode(f.rgba[4 * p + c] / alpha), 1) << p;
  }
  std::filesystem::remove(path);
}

// zlib's level changes the bytes and the time, never the pixels: a frame written at level 1
// (trajectory frames) and at the default level reads back the same, sRGB-encoded colour for colour.
TEST(ImageIo, PngLevelChangesTheBytesNotThePixels) {
  FrameBuffers f = randomFrame(64, 48);
  for (std::size_t p = 0; p < f.pixels(); ++p)
    for (int c = 0; c < 4; ++c) f.rgba[4 * p + c] = static_cast<float>((p / 7 + 3 * c) % 13) / 12.0f;
  const auto dir = surftrace::test::testTempDir();
  std::vector<std::vector<unsigned char>> decoded;
  std::vector<std::uintmax_t> sizes;
  for (int level : {1, kDefaultPngLevel, 9}) {
    const auto path = (dir / ("surftrace_level" + std::to_string(level) + ".png")).string();
    writePng(path, f, {{"surftrace:frame", "7"}}, level);
    sizes.push_back(std::filesystem::file_size(path));
    auto in = OIIO::ImageInput::open(path);
    ASSERT_TRUE(in);
    EXPECT_EQ(in->spec().get_string_attribute("surftrace:frame"), "7");
    std::vector<unsigned char> px(3 * f.pixels());
    ASSERT_TRUE(in->read_image(0, 0, 0, 3, OIIO::TypeDesc::UINT8, px.data()));
    for (std::size_t p = 0; p < f.pixels(); ++p)
      for (int c = 0; c < 3; ++c)
        ASSERT_EQ(px[3 * p + c], srgbCode(f.rgba[4 * p + c]))
            << "level " << level << " pixel " << p;
    decoded.push_back(std::move(px));
    std::filesystem::remove(path);
  }
  EXPECT_EQ(decoded[0], decoded[1]);
  // The level reached zlib: the files differ (level 1 is the largest).
  EXPECT_GT(sizes[0], sizes[1]);
  EXPECT_GE(sizes[1], sizes[2]);
}

TEST(ImageIo, ForeignFileIsAClearError) {
  const auto path = (surftrace::test::testTempDir() / "surftrace_foreign.png").string();
  FrameBuffers f = randomFrame(4, 4);
  writePng(path, f, {});
  try {
    readExr(path);
    FAIL() << "expected an error";
  } catch (const std::runtime_error& e) {
    EXPECT_NE(std::string(e.what()).find(path), std::string::npos) << e.what();
  }
  std::filesystem::remove(path);
}

}  // namespace
}  // namespace surftrace::view


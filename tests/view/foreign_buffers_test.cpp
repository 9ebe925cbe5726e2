// Another renderer's buffers (issue 20): window, view-z and ray depth, both row origins, view and
// world normals, signed and unorm, from cameras that GL programs build (centred, off-centre,
// orthographic), against the reference camera's own rays. The buffers come from
// oracles/gl_sphere_buffers.hpp, which knows only the two matrices.
#include <cmath>
#include <filesystem>
#include <functional>
#include <limits>
#include <string>
#include <vector>

#include <OpenImageIO/imageio.h>
#include <glm/ext/matrix_clip_space.hpp>
#include <glm/ext/matrix_transform.hpp>
#include <glm/geometric.hpp>
#include <gtest/gtest.h>

#include "oracles/gl_sphere_buffers.hpp"
#include "temp_dir.hpp"
#include "view/camera.hpp"
#include "view/foreign_buffers.hpp"
#include "view/image_compare.hpp"
#include "view/image_io.hpp"

namespace surftrace::view {
namespace {

constexpr double kInf = std::numeric_limits<double>::infinity();
constexpr int kWidth = 48, kHeight = 32;

std::string temp(const std::string& name) { return (::surftrace::test::testTempDir() / name).string(); }

const std::vector<glm::dvec4> kSpheres = {{1.0, 2.0, -3.0, 2.5}, {2.6, 0.8, -1.5, 1.5}, {-0.6, 3.1, -3.6, 1.8}};

struct GlCamera {
  const char* name;
  glm::dmat4 view, projection;
};

// A GL program's cameras: glm::perspective, an off-centre glm::frustum with non-square pixels,
// an off-centre glm::ortho.
std::vector<GlCamera> glCameras() {
  const glm::dmat4 view = glm::lookAt(glm::dvec3(6.0, 4.0, 12.0), glm::dvec3(0.0, 1.0, -2.0), glm::dvec3(0.1, 1.0, 0.0));
  return {{"perspective", view, glm::perspective(glm::radians(40.0), double(kWidth) / kHeight, 5.0, 30.0)},
          {"off-centre frustum", view, glm::frustum(-0.9, 2.1, -1.3, 0.8, 3.0, 40.0)},
          {"off-centre ortho", view, glm::ortho(-5.0, 7.0, -4.0, 3.5, 2.0, 30.0)}};
}

// The reference: each pixel's nearest sphere along SurfTrace's own ray, as a renderer of ours
// would record it (ray distance, view z, world normal, kind and id).
FrameBuffers referenceFrame(const Camera& camera) {
  FrameBuffers f;
  f.reset(camera.width, camera.height);
  const Camera::Frame frame = camera.frame();
  for (int y = 0; y < camera.height; ++y)
    for (int x = 0; x < camera.width; ++x) {
      const Ray r = frame.ray(x + 0.5, y + 0.5);
      double best = kInf;
      std::size_t id = 0;
      for (std::size_t i = 0; i < kSpheres.size(); ++i) {
        const glm::dvec3 oc = glm::dvec3(kSpheres[i]) - r.org;
        const double along = glm::dot(oc, r.dir), perp2 = glm::dot(oc, oc) - along * along, rr = kSpheres[i].w * kSpheres[i].w;
        if (perp2 > rr) continue;
        const double t = along - std::sqrt(rr - perp2);
        if (t > 0.0 && t < best) best = t, id = i;
      }
      if (!std::isfinite(best)) continue;
      const std::size_t p = static_cast<std::size_t>(y) * kWidth + static_cast<std::size_t>(x);
      const glm::dvec3 hit = r.org + best * r.dir, n = (hit - glm::dvec3(kSpheres[id])) / kSpheres[id].w;
      f.depth[p] = static_cast<float>(best);
      f.viewZ[p] = static_cast<float>(glm::dot(hit - camera.eye, frame.forward));
      for (int k = 0; k < 3; ++k) f.normal[3 * p + static_cast<std::size_t>(k)] = static_cast<float>(n[k]);
      f.kind[p] = 1;
      f.patchId[p] = static_cast<std::uint32_t>(id);
    }
  return f;
}

// A buffer of one value per pixel (or three), stored from the given origin.
ImageChannels buffer(const std::string& name, const test::GlSphereBuffers& gl, RowOrigin origin,
                     const std::vector<std::string>& channels, const std::function<glm::dvec3(std::size_t)>& value) {
  ImageChannels image;
  image.path = name;
  image.format = "memory";
  image.width = gl.width, image.height = gl.height;
  image.names = channels;
  image.types.assign(channels.size(), "float");
  for (int row = 0; row < gl.height; ++row) {
    const int y = origin == RowOrigin::TopLeft ? row : gl.height - 1 - row;
    for (int x = 0; x < gl.width; ++x) {
      const glm::dvec3 v = value(static_cast<std::size_t>(y) * static_cast<std::size_t>(gl.width) + static_cast<std::size_t>(x));
      for (std::size_t c = 0; c < channels.size(); ++c) image.values.push_back(static_cast<float>(v[static_cast<int>(c)]));
    }
  }
  return image;
}

ImageChannels depthBuffer(const test::GlSphereBuffers& gl, DepthConvention convention, RowOrigin origin) {
  const std::vector<double>& v = convention == DepthConvention::Window ? gl.window
                                 : convention == DepthConvention::ViewZ ? gl.viewZ
                                                                        : gl.ray;
  return buffer(std::string("depth.") + conventionName(convention), gl, origin, {"Y"},
                [&](std::size_t p) { return glm::dvec3(v[p]); });
}

FrameComparison compareForeign(const ForeignFrame& foreign, const FrameBuffers& ref, const Camera& camera) {
  return compareFrames(foreign.frame, ref, &camera, foreign.carried);
}

bool passes(const FrameComparison& c) { return CompareThresholds::preset("foreign").violations(c).empty(); }

// Each convention gives the ray distance the reference traced, pixel by pixel, for each camera.
TEST(CompareForeignBuffers, EachDepthConventionGivesTheReferenceRayDistance) {
  for (const GlCamera& glc : glCameras()) {
    SCOPED_TRACE(glc.name);
    const Camera camera = cameraFromMatrices(kWidth, kHeight, glc.view, glc.projection);
    const FrameBuffers ref = referenceFrame(camera);
    const test::GlSphereBuffers gl = test::drawSpheresGl(kWidth, kHeight, glc.view, glc.projection, kSpheres);
    for (DepthConvention convention : {DepthConvention::Window, DepthConvention::ViewZ, DepthConvention::Ray}) {
      SCOPED_TRACE(conventionName(convention));
      const ForeignFrame foreign = foreignFrame(depthBuffer(gl, convention, RowOrigin::TopLeft), nullptr,
                                                {"", convention, RowOrigin::TopLeft, NormalSpace::View, NormalEncoding::Signed},
                                                camera);
      std::size_t hits = 0;
      for (std::size_t p = 0; p < ref.pixels(); ++p) {
        if (gl.edge[p] < 1e-3 || (!gl.hit(p) && std::isfinite(ref.depth[p]))) continue;  // within rounding of a silhouette
        ASSERT_EQ(std::isfinite(foreign.frame.depth[p]), std::isfinite(ref.depth[p])) << "pixel " << p;
        if (!std::isfinite(ref.depth[p])) continue;
        ++hits;
        // float32 buffers: window depth resolves these depth ranges to about 1e-5 Å.
        EXPECT_NEAR(foreign.frame.depth[p], ref.depth[p], 1e-4) << "pixel " << p;
        EXPECT_NEAR(foreign.frame.viewZ[p], ref.viewZ[p], 1e-4) << "pixel " << p;
      }
      EXPECT_GT(hits, 200u);
      const FrameComparison c = compareForeign(foreign, ref, camera);
      EXPECT_TRUE(passes(c)) << c.summary();
      EXPECT_LT(c.depthP99, 1e-4);
    }
    // Read as the wrong convention, the same numbers are other distances (in perspective, where
    // view z and ray distance differ off the axis).
    if (camera.projection == Projection::Perspective) {
      const ForeignFrame wrong = foreignFrame(depthBuffer(gl, DepthConvention::ViewZ, RowOrigin::TopLeft), nullptr,
                                              {"", DepthConvention::Ray, RowOrigin::TopLeft, {}, {}}, camera);
      EXPECT_FALSE(passes(compareForeign(wrong, ref, camera)));
    }
  }
}

// Rows stored bottom first (glReadPixels) read right only as bottom-left; one row off fails.
TEST(CompareForeignBuffers, RowOriginDecidesWhichRowIsTheTop) {
  const GlCamera glc = glCameras()[1];
  const Camera camera = cameraFromMatrices(kWidth, kHeight, glc.view, glc.projection);
  const FrameBuffers ref = referenceFrame(camera);
  const test::GlSphereBuffers gl = test::drawSpheresGl(kWidth, kHeight, glc.view, glc.projection, kSpheres);
  for (RowOrigin stored : {RowOrigin::BottomLeft, RowOrigin::TopLeft}) {
    SCOPED_TRACE(originName(stored));
    const ImageChannels depth = depthBuffer(gl, DepthConvention::Window, stored);
    const RowOrigin other = stored == RowOrigin::BottomLeft ? RowOrigin::TopLeft : RowOrigin::BottomLeft;
    const FrameComparison right = compareForeign(foreignFrame(depth, nullptr, {"", {}, stored, {}, {}}, camera), ref, camera);
    const FrameComparison wrong = compareForeign(foreignFrame(depth, nullptr, {"", {}, other, {}, {}}, camera), ref, camera);
    EXPECT_TRUE(passes(right)) << right.summary();
    EXPECT_FALSE(passes(wrong)) << wrong.summary();
    EXPECT_GT(wrong.coverageFraction, 0.05);
    // Shifted by one row: the sphere's depth slope shows.
    ImageChannels shifted = depth;
    const std::size_t row = static_cast<std::size_t>(kWidth);
    std::copy(depth.values.begin() + static_cast<std::ptrdiff_t>(row), depth.values.end(), shifted.values.begin());
    const FrameComparison off = compareForeign(foreignFrame(shifted, nullptr, {"", {}, stored, {}, {}}, camera), ref, camera);
    EXPECT_FALSE(passes(off)) << off.summary();
  }
}

// Normals in view or world space, signed or unorm; each misread fails the 1° limit.
TEST(CompareForeignBuffers, NormalsInEitherSpaceAndEncoding) {
  for (const GlCamera& glc : glCameras()) {
    SCOPED_TRACE(glc.name);
    const Camera camera = cameraFromMatrices(kWidth, kHeight, glc.view, glc.projection);
    const FrameBuffers ref = referenceFrame(camera);
    const test::GlSphereBuffers gl = test::drawSpheresGl(kWidth, kHeight, glc.view, glc.projection, kSpheres);
    const ImageChannels depth = depthBuffer(gl, DepthConvention::Window, RowOrigin::BottomLeft);
    for (NormalSpace space : {NormalSpace::View, NormalSpace::World})
      for (NormalEncoding encoding : {NormalEncoding::Signed, NormalEncoding::Unorm}) {
        SCOPED_TRACE(std::string(spaceName(space)) + " " + encodingName(encoding));
        const std::vector<glm::dvec3>& n = space == NormalSpace::View ? gl.viewNormal : gl.worldNormal;
        const ImageChannels normals = buffer("normals", gl, RowOrigin::BottomLeft, {"R", "G", "B"}, [&](std::size_t p) {
          return encoding == NormalEncoding::Unorm ? 0.5 * n[p] + 0.5 : n[p];
        });
        const ForeignBufferOptions options{"", DepthConvention::Window, RowOrigin::BottomLeft, space, encoding};
        const ForeignFrame foreign = foreignFrame(depth, &normals, options, camera);
        ASSERT_TRUE(foreign.carried.normal);
        const FrameComparison c = compareForeign(foreign, ref, camera);
        EXPECT_TRUE(passes(c)) << c.summary();
        EXPECT_LT(c.normalP99Degrees, 1e-3);
        ForeignBufferOptions otherSpace = options, otherEncoding = options;
        otherSpace.normalSpace = space == NormalSpace::View ? NormalSpace::World : NormalSpace::View;
        otherEncoding.normalEncoding = encoding == NormalEncoding::Signed ? NormalEncoding::Unorm : NormalEncoding::Signed;
        EXPECT_GT(compareForeign(foreignFrame(depth, &normals, otherSpace, camera), ref, camera).normalP99Degrees, 5.0);
        EXPECT_GT(compareForeign(foreignFrame(depth, &normals, otherEncoding, camera), ref, camera).normalP99Degrees, 5.0);
      }
    // Without normals they are not compared, and a normal limit is neither passed nor failed.
    const FrameComparison none = compareForeign(foreignFrame(depth, nullptr, {}, camera), ref, camera);
    EXPECT_FALSE(none.compared.normal);
    EXPECT_FALSE(none.compared.kind);
    EXPECT_FALSE(none.compared.patchId);
    const CompareThresholds exactLimits = CompareThresholds::preset("exact");
    const auto unjudged = exactLimits.notCompared(none);
    ASSERT_EQ(unjudged.size(), 4u);
    EXPECT_NE(unjudged[0].find("normal"), std::string::npos) << unjudged[0];
    EXPECT_NE(unjudged[1].find("patch-kind"), std::string::npos) << unjudged[1];
    EXPECT_NE(unjudged[3].find("colour"), std::string::npos) << unjudged[3];
    for (const std::string& v : exactLimits.violations(none))
      EXPECT_EQ(v.find("patch"), std::string::npos) << "a limit on what the test lacks was judged: " << v;
    EXPECT_NE(none.summary().find("patch kind       not compared"), std::string::npos) << none.summary();
    EXPECT_NE(none.json().find("\"compared\": false"), std::string::npos) << none.json();
  }
}

void writeWithOiio(const std::string& path, int width, int height, const std::vector<std::string>& names,
                   OIIO::TypeDesc type, const void* pixels) {
  auto out = OIIO::ImageOutput::create(path);
  ASSERT_TRUE(out) << OIIO::geterror();
  OIIO::ImageSpec spec(width, height, static_cast<int>(names.size()), type);
  spec.channelnames = names;
  ASSERT_TRUE(out->open(path, spec)) << out->geterror();
  ASSERT_TRUE(out->write_image(type, pixels)) << out->geterror();
  ASSERT_TRUE(out->close());
}

// Files keep the rows in the order they were written: a PFM's first row (its bottom, by the
// format's definition, which OpenImageIO turns top first) as much as an EXR's or a TIFF's.
TEST(CompareForeignBuffers, FilesKeepTheRowsInTheOrderWritten) {
  const int w = 3, h = 4;
  std::vector<float> rows(static_cast<std::size_t>(w * h));
  for (int y = 0; y < h; ++y)
    for (int x = 0; x < w; ++x) rows[static_cast<std::size_t>(y * w + x)] = static_cast<float>(10 * y + x);
  const std::string pfm = temp("rows.pfm"), exr = temp("rows.exr"), tif = temp("rows.tif");
  test::writePfm(pfm, w, h, 1, rows);
  writeWithOiio(exr, w, h, {"Z"}, OIIO::TypeDesc::FLOAT, rows.data());
  writeWithOiio(tif, w, h, {"Y"}, OIIO::TypeDesc::FLOAT, rows.data());
  for (const std::string& path : {pfm, exr, tif}) {
    const ImageChannels image = readImageChannels(path);
    ASSERT_EQ(image.width, w);
    ASSERT_EQ(image.height, h);
    ASSERT_EQ(image.names.size(), 1u) << path;
    EXPECT_TRUE(image.isFloat(0)) << path << " " << image.types[0];
    EXPECT_EQ(image.values, rows) << path;
  }
  // OpenImageIO itself shows the PFM with its first row at the bottom.
  auto in = OIIO::ImageInput::open(pfm);
  std::vector<float> shown(rows.size());
  ASSERT_TRUE(in->read_image(0, 0, 0, 1, OIIO::TypeDesc::FLOAT, shown.data()));
  EXPECT_EQ(shown[0], 30.0f);
}

// A 16-bit PNG holds window depth as GL's 16-bit depth does (unorm); Å must be float.
TEST(CompareForeignBuffers, SixteenBitPngHoldsWindowDepthOnly) {
  const GlCamera glc = glCameras()[0];
  const Camera camera = cameraFromMatrices(kWidth, kHeight, glc.view, glc.projection);
  const FrameBuffers ref = referenceFrame(camera);
  const test::GlSphereBuffers gl = test::drawSpheresGl(kWidth, kHeight, glc.view, glc.projection, kSpheres);
  std::vector<std::uint16_t> unorm(gl.pixels());
  for (int row = 0; row < kHeight; ++row)
    for (int x = 0; x < kWidth; ++x) {
      const std::size_t p = static_cast<std::size_t>(kHeight - 1 - row) * kWidth + static_cast<std::size_t>(x);
      unorm[static_cast<std::size_t>(row) * kWidth + static_cast<std::size_t>(x)] =
          static_cast<std::uint16_t>(std::lround(65535.0 * gl.window[p]));
    }
  const std::string png = temp("depth16.png");
  writeWithOiio(png, kWidth, kHeight, {"Y"}, OIIO::TypeDesc::UINT16, unorm.data());
  const ImageChannels image = readImageChannels(png);
  EXPECT_FALSE(image.isFloat(0));
  const FrameComparison c = compareForeign(foreignFrame(image, nullptr, {}, camera), ref, camera);
  EXPECT_EQ(c.coverageMismatch, 0u) << c.summary();
  // Half a step of 1/65535 in window depth, at the far end of this scene's depth range.
  const double n = camera.zNear, f = camera.zFar, z = 18.0;
  const double step = 0.5 / 65535.0 * 2.0 * z * z * (f - n) / (2.0 * f * n);
  EXPECT_LT(c.depthMax, 1.2 * step / std::cos(glm::radians(35.0))) << c.summary();
  EXPECT_GT(c.depthMax, 1e-5) << "the PNG was not quantised?";
  try {
    foreignFrame(image, nullptr, {"", DepthConvention::ViewZ, {}, {}, {}}, camera);
    FAIL() << "view-z depth in a 16-bit channel was accepted";
  } catch (const std::runtime_error& e) {
    EXPECT_NE(std::string(e.what()).find("holds uint16 values"), std::string::npos) << e.what();
  }
}

// Errors say what was found and what was expected.
TEST(CompareForeignBuffers, ErrorsNameWhatWasFoundAndExpected) {
  const GlCamera glc = glCameras()[1];
  const Camera camera = cameraFromMatrices(kWidth, kHeight, glc.view, glc.projection);
  const test::GlSphereBuffers gl = test::drawSpheresGl(kWidth, kHeight, glc.view, glc.projection, kSpheres);
  auto message = [&](const ImageChannels& depth, const ImageChannels* normals, const ForeignBufferOptions& o,
                     const Camera& cam) -> std::string {
    try {
      foreignFrame(depth, normals, o, cam);
    } catch (const std::exception& e) {
      return e.what();
    }
    return "(no error)";
  };
  const ImageChannels rgb = buffer("colour.exr", gl, RowOrigin::TopLeft, {"R", "G", "B"}, [&](std::size_t p) {
    return glm::dvec3(gl.window[p]);
  });
  EXPECT_EQ(message(rgb, nullptr, {}, camera),
            "colour.exr: no depth channel among its channels R, G, B; expected one named Z, depth or Y, or a "
            "one-channel image: name it with --test-depth-channel");
  EXPECT_EQ(message(rgb, nullptr, {"depth.t", {}, {}, {}, {}}, camera),
            "colour.exr: no channel 'depth.t' (--test-depth-channel); its channels are R, G, B");
  EXPECT_EQ(foreignFrame(rgb, nullptr, {"G", {}, RowOrigin::TopLeft, {}, {}}, camera).depthChannel, "G");
  const ImageChannels depth = depthBuffer(gl, DepthConvention::Window, RowOrigin::TopLeft);
  Camera small = camera;
  small.width = kWidth / 2;
  EXPECT_EQ(message(depth, nullptr, {}, small),
            "depth.window (depth) is 48x32, but the reference is 24x32: the buffers must be the reference camera's size");
  const ImageChannels oneChannel = depthBuffer(gl, DepthConvention::Ray, RowOrigin::TopLeft);
  EXPECT_EQ(message(depth, &oneChannel, {}, camera),
            "depth.ray: no normal channels among its channels Y; expected R, G, B (or N.X, N.Y, N.Z, or X, Y, Z)");
  Camera noRange = camera;
  noRange.zNear = noRange.zFar = 0.0;
  EXPECT_NE(message(depth, nullptr, {}, noRange).find("has no near and far"), std::string::npos);
  EXPECT_EQ(message(depth, nullptr, {"", DepthConvention::ViewZ, {}, {}, {}}, noRange), "(no error)");
}

}  // namespace
}  // namespace surftrace::view

// `surftrace compare TEST REFERENCE.exr` with another renderer's buffers (issue 20, item 4): the
// reference is rendered from a camera that a GL program wrote (its two matrices), and the
// buffers are drawn from those matrices alone (oracles/gl_sphere_buffers.hpp: brute-force
// ray-sphere through inverse(P·V)), in each convention, file format and row order.
#include <cmath>
#include <filesystem>
#include <fstream>
#include <limits>
#include <string>
#include <vector>

#include <OpenImageIO/imageio.h>
#include <glm/ext/matrix_clip_space.hpp>
#include <glm/ext/matrix_transform.hpp>
#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

#include "oracles/gl_sphere_buffers.hpp"
#include "run_tool.hpp"
#include "temp_dir.hpp"
#include "view/camera.hpp"
#include "view/image_io.hpp"

namespace surftrace::tools {
namespace {

namespace oracle = ::surftrace::test;  // (tools::test is run_tool.hpp's)
using test::Result;
Result run(const std::string& args) { return test::runTool(args); }
std::string temp(const std::string& name) { return (::surftrace::test::testTempDir() / name).string(); }
bool has(const Result& r, const std::string& text) { return r.output.find(text) != std::string::npos; }

nlohmann::json matrixJson(const glm::dmat4& m) {
  nlohmann::json a = nlohmann::json::array();
  for (int c = 0; c < 4; ++c)
    for (int r = 0; r < 4; ++r) a.push_back(m[c][r]);
  return a;
}

const std::vector<glm::dvec4> kAtoms = {{1.0, 2.0, -3.0, 2.5}, {2.6, 0.8, -1.5, 1.5}, {-0.6, 3.1, -3.6, 1.8}};
constexpr int kWidth = 64, kHeight = 40;

// A GL program's camera written as matrices only, the vdW reference rendered from it, and what
// the program draws of the same atoms.
struct Scene {
  std::string reference;
  oracle::GlSphereBuffers gl;
};

Scene makeScene(const std::string& name, const glm::dmat4& projection) {
  const glm::dmat4 view = glm::lookAt(glm::dvec3(6.0, 4.0, 12.0), glm::dvec3(0.0, 1.0, -2.0), glm::dvec3(0.1, 1.0, 0.0));
  const std::string xyzr = temp(name + ".xyzr"), cam = temp(name + "_camera.json");
  std::ofstream atoms(xyzr);
  for (const glm::dvec4& a : kAtoms) atoms << a.x << " " << a.y << " " << a.z << " " << a.w << "\n";
  atoms.close();
  std::ofstream(cam) << nlohmann::json{{"width", kWidth}, {"height", kHeight}, {"view_matrix", matrixJson(view)},
                                       {"projection_matrix", matrixJson(projection)}}
                            .dump();
  Scene s{temp(name + "_ref.exr"), oracle::drawSpheresGl(kWidth, kHeight, view, projection, kAtoms)};
  const Result r = run("render " + xyzr + " --input-format xyzr --surface vdw --quiet --exr " + s.reference + " --camera " + cam);
  EXPECT_EQ(r.status, 0) << r.output;
  return s;
}

Scene frustumScene() { return makeScene("frustum", glm::frustum(-0.9, 2.1, -1.3, 0.8, 3.0, 40.0)); }

// `channels` values per pixel of the image (row 0 at the top), stored from `origin`'s row first.
template <class F>
std::vector<float> stored(const oracle::GlSphereBuffers& gl, int channels, bool bottomFirst, F value) {
  std::vector<float> out;
  for (int row = 0; row < gl.height; ++row) {
    const int y = bottomFirst ? gl.height - 1 - row : row;
    for (int x = 0; x < gl.width; ++x) {
      const glm::dvec3 v = value(static_cast<std::size_t>(y) * static_cast<std::size_t>(gl.width) + static_cast<std::size_t>(x));
      for (int c = 0; c < channels; ++c) out.push_back(static_cast<float>(v[c]));
    }
  }
  return out;
}

void writeImage(const std::string& path, int width, int height, const std::vector<std::string>& names,
                const std::vector<float>& values, OIIO::TypeDesc type = OIIO::TypeDesc::FLOAT) {
  auto out = OIIO::ImageOutput::create(path);
  ASSERT_TRUE(out) << OIIO::geterror();
  OIIO::ImageSpec spec(width, height, static_cast<int>(names.size()), type);
  spec.channelnames = names;
  ASSERT_TRUE(out->open(path, spec)) << out->geterror();
  ASSERT_TRUE(out->write_image(OIIO::TypeDesc::FLOAT, values.data())) << out->geterror();  // converted to `type`
  ASSERT_TRUE(out->close());
}

// Window depth from an off-centre frustum, rows bottom first in a PFM (glReadPixels' buffer
// written as it is): passes as bottom-left (the default), fails upside down or one row off.
TEST(CompareForeign, WindowDepthFromAnOffCentreFrustum) {
  const Scene s = frustumScene();
  const std::string pfm = temp("frustum_window.pfm"), shifted = temp("frustum_window_shifted.pfm");
  const std::vector<float> depth = stored(s.gl, 1, true, [&](std::size_t p) { return glm::dvec3(s.gl.window[p]); });
  oracle::writePfm(pfm, kWidth, kHeight, 1, depth);
  std::vector<float> up(depth.begin() + kWidth, depth.end());
  up.insert(up.end(), depth.end() - kWidth, depth.end());
  oracle::writePfm(shifted, kWidth, kHeight, 1, up);

  const Result ok = run("compare " + pfm + " " + s.reference + " --depth-convention window --test-origin bottom-left");
  EXPECT_EQ(ok.status, 0) << ok.output;
  EXPECT_TRUE(has(ok, "--preset foreign")) << ok.output;
  EXPECT_TRUE(has(ok, "depth   channel Y, window depth for near 3, far 40 Å, rows from the bottom-left")) << ok.output;
  EXPECT_TRUE(has(ok, "coverage mismatch 0 of")) << ok.output;
  EXPECT_TRUE(has(ok, "not compared: normal p99 < 1° (the test image carries no normals)")) << ok.output;
  EXPECT_TRUE(has(ok, "PASS (foreign, on what the test carries)")) << ok.output;
  const Result byDefault = run("compare " + pfm + " " + s.reference);
  EXPECT_EQ(byDefault.status, 0) << byDefault.output;

  const Result flipped = run("compare " + pfm + " " + s.reference + " --test-origin top-left");
  EXPECT_EQ(flipped.status, 2) << flipped.output;
  EXPECT_TRUE(has(flipped, "FAIL (foreign")) << flipped.output;
  EXPECT_TRUE(has(flipped, "hint: with --test-origin bottom-left the coverage mismatch would be 0%")) << flipped.output;
  const Result oneRowOff = run("compare " + shifted + " " + s.reference + " --test-origin bottom-left");
  EXPECT_EQ(oneRowOff.status, 2) << oneRowOff.output;
  EXPECT_TRUE(has(oneRowOff, "depth p99")) << oneRowOff.output;
}

// An orthographic GL camera (off-centre glm::ortho): window depth is linear in view z.
TEST(CompareForeign, WindowDepthFromAnOrthographicCamera) {
  const Scene s = makeScene("ortho", glm::ortho(-5.0, 7.0, -4.0, 3.5, 2.0, 30.0));
  const std::string pfm = temp("ortho_window.pfm");
  oracle::writePfm(pfm, kWidth, kHeight, 1, stored(s.gl, 1, true, [&](std::size_t p) { return glm::dvec3(s.gl.window[p]); }));
  const Result ok = run("compare " + pfm + " " + s.reference + " --depth-convention window --test-origin bottom-left");
  EXPECT_EQ(ok.status, 0) << ok.output;
  // Window depths in [0, 1] lie nearer than near (2 Å): no view z can be that.
  const Result asViewZ = run("compare " + pfm + " " + s.reference + " --depth-convention view-z --test-origin bottom-left");
  EXPECT_EQ(asViewZ.status, 1) << asViewZ.output;
}

// View z in an EXR's Z channel (beside colour) and ray distance in a float TIFF, rows top first.
TEST(CompareForeign, ViewZInAnExrAndRayDistanceInAFloatTiff) {
  const Scene s = frustumScene();
  const std::string exr = temp("frustum_viewz.exr"), tif = temp("frustum_ray.tif");
  std::vector<float> rgbz;  // grey colour beside the depth
  for (int y = 0; y < kHeight; ++y)
    for (int x = 0; x < kWidth; ++x) {
      const std::size_t p = static_cast<std::size_t>(y) * kWidth + static_cast<std::size_t>(x);
      rgbz.insert(rgbz.end(), {0.5f, 0.5f, 0.5f, static_cast<float>(s.gl.viewZ[p])});
    }
  writeImage(exr, kWidth, kHeight, {"R", "G", "B", "Z"}, rgbz);
  writeImage(tif, kWidth, kHeight, {"Y"}, stored(s.gl, 1, false, [&](std::size_t p) { return glm::dvec3(s.gl.ray[p]); }));

  const Result viewZ = run("compare " + exr + " " + s.reference + " --depth-convention view-z --test-origin top-left");
  EXPECT_EQ(viewZ.status, 0) << viewZ.output;
  EXPECT_TRUE(has(viewZ, "depth   channel Z, view-z depth")) << viewZ.output;
  const Result ray = run("compare " + tif + " " + s.reference + " --depth-convention ray --test-origin top-left");
  EXPECT_EQ(ray.status, 0) << ray.output;
  // Each read as the other convention: off the view axis they differ by 1/cos of the angle.
  EXPECT_EQ(run("compare " + exr + " " + s.reference + " --depth-convention ray --test-origin top-left").status, 2);
  EXPECT_EQ(run("compare " + tif + " " + s.reference + " --depth-convention view-z --test-origin top-left").status, 2);
  EXPECT_EQ(run("compare " + tif + " " + s.reference + " --depth-convention ray --test-origin bottom-left").status, 2);
}

// Normals in view space (PFM), world space (EXR with SurfTrace's channel names) and unorm view
// space (16-bit PNG); each misread fails the normal limit.
TEST(CompareForeign, NormalsInViewAndWorldSpaceSignedAndUnorm) {
  const Scene s = frustumScene();
  const std::string depth = temp("normals_depth.pfm"), view = temp("normals_view.pfm"), world = temp("normals_world.exr"),
                    unorm = temp("normals_unorm.png");
  oracle::writePfm(depth, kWidth, kHeight, 1, stored(s.gl, 1, true, [&](std::size_t p) { return glm::dvec3(s.gl.window[p]); }));
  oracle::writePfm(view, kWidth, kHeight, 3, stored(s.gl, 3, true, [&](std::size_t p) { return s.gl.viewNormal[p]; }));
  writeImage(world, kWidth, kHeight, {"N.X", "N.Y", "N.Z"},
             stored(s.gl, 3, false, [&](std::size_t p) { return s.gl.worldNormal[p]; }));
  writeImage(unorm, kWidth, kHeight, {"R", "G", "B"},
             stored(s.gl, 3, false, [&](std::size_t p) { return 0.5 * s.gl.viewNormal[p] + 0.5; }), OIIO::TypeDesc::UINT16);
  const std::string base = "compare " + depth + " " + s.reference + " --test-origin bottom-left --test-normal ";

  const Result inView = run(base + view + " --normal-space view");
  EXPECT_EQ(inView.status, 0) << inView.output;
  EXPECT_TRUE(has(inView, "normals " + view + ", view space, signed")) << inView.output;
  EXPECT_FALSE(has(inView, "not compared: normal")) << inView.output;
  const Result viewAsWorld = run(base + view + " --normal-space world");
  EXPECT_EQ(viewAsWorld.status, 2) << viewAsWorld.output;
  EXPECT_TRUE(has(viewAsWorld, "normal p99")) << viewAsWorld.output;

  // The EXR's rows are top first, and one --test-origin holds for both files: so a top-first
  // depth buffer goes with it.
  const std::string topDepth = temp("normals_depth_top.exr");
  writeImage(topDepth, kWidth, kHeight, {"depth"},
             stored(s.gl, 1, false, [&](std::size_t p) { return glm::dvec3(s.gl.window[p]); }));
  const std::string top = "compare " + topDepth + " " + s.reference + " --test-origin top-left --test-normal ";
  EXPECT_EQ(run(top + world + " --normal-space world").status, 0);
  EXPECT_EQ(run(top + world + " --normal-space view").status, 2);
  const Result png = run(top + unorm + " --normal-space view --normal-encoding unorm");
  EXPECT_EQ(png.status, 0) << png.output;
  EXPECT_EQ(run(top + unorm + " --normal-space view").status, 2);
}

// Limits on what the buffers do not carry are "not compared", in the text and the report.
TEST(CompareForeign, LimitsOnWhatTheTestLacksAreNotCompared) {
  const Scene s = frustumScene();
  const std::string pfm = temp("lacks.pfm"), report = temp("lacks.json");
  oracle::writePfm(pfm, kWidth, kHeight, 1, stored(s.gl, 1, true, [&](std::size_t p) { return glm::dvec3(s.gl.window[p]); }));
  const Result gl = run("compare " + pfm + " " + s.reference + " --preset gl-vs-embree --min-patch 0.5 --report " + report);
  EXPECT_EQ(gl.status, 0) << gl.output;
  EXPECT_TRUE(has(gl, "patch kind       not compared (the test image carries no patch kinds)")) << gl.output;
  EXPECT_TRUE(has(gl, "not compared: patch-kind agreement > 99.9% (the test image carries no patch kinds)")) << gl.output;
  EXPECT_TRUE(has(gl, "not compared: patch-id agreement > 50% (the test image carries no patch ids)")) << gl.output;
  EXPECT_TRUE(has(gl, "PASS (gl-vs-embree, on what the test carries)")) << gl.output;
  std::ifstream in(report);
  const nlohmann::json j = nlohmann::json::parse(in);
  EXPECT_EQ(j["patch_kind"]["compared"], false);
  EXPECT_EQ(j["patch_id"]["compared"], false);
  EXPECT_EQ(j["normal_degrees"]["compared"], false);
  EXPECT_FALSE(j["patch_kind"].contains("agreement"));
  EXPECT_EQ(j["depth"]["unit"], "Å");
  EXPECT_LT(j["depth"]["p99"].get<double>(), 1e-4);
  // A limit that fails is still failed beside one not compared.
  const Result tight = run("compare " + pfm + " " + s.reference + " --preset none --max-depth-p99 1e-12 --min-kind 1");
  EXPECT_EQ(tight.status, 2) << tight.output;
  EXPECT_TRUE(has(tight, "not compared: patch-kind agreement")) << tight.output;
  EXPECT_FALSE(has(tight, "  patch-kind agreement")) << tight.output;
}

// Exit 1 with what was found and what was expected: a missing channel, a size mismatch, window
// depth against a reference without near and far, a reference without a camera.
TEST(CompareForeign, ErrorsSayWhatWasFoundAndExpected) {
  const Scene s = frustumScene();
  const std::string rgb = temp("errors_rgb.exr"), small = temp("errors_small.pfm"), pfm = temp("errors.pfm");
  writeImage(rgb, kWidth, kHeight, {"R", "G", "B"}, std::vector<float>(3 * kWidth * kHeight, 0.5f));
  oracle::writePfm(small, kWidth / 2, kHeight, 1, std::vector<float>(kWidth / 2 * kHeight, 1.0f));
  oracle::writePfm(pfm, kWidth, kHeight, 1, stored(s.gl, 1, true, [&](std::size_t p) { return glm::dvec3(s.gl.window[p]); }));

  Result r = run("compare " + rgb + " " + s.reference);
  EXPECT_EQ(r.status, 1) << r.output;
  EXPECT_TRUE(has(r, rgb + ": no depth channel among its channels R, G, B; expected one named Z, depth or Y, or a "
                           "one-channel image: name it with --test-depth-channel"))
      << r.output;
  r = run("compare " + pfm + " " + s.reference + " --test-depth-channel Z");
  EXPECT_EQ(r.status, 1) << r.output;
  EXPECT_TRUE(has(r, pfm + ": no channel 'Z' (--test-depth-channel); its channels are Y")) << r.output;
  r = run("compare " + small + " " + s.reference);
  EXPECT_EQ(r.status, 1) << r.output;
  EXPECT_TRUE(has(r, small + " is 32x40 but " + s.reference + " is 64x40")) << r.output;
  r = run("compare " + pfm + " " + s.reference + " --test-normal " + small);
  EXPECT_EQ(r.status, 1) << r.output;
  EXPECT_TRUE(has(r, small + " is 32x40 but " + s.reference + " is 64x40")) << r.output;
  r = run("compare " + pfm + " " + s.reference + " --test-normal " + pfm);
  EXPECT_EQ(r.status, 1) << r.output;
  EXPECT_TRUE(has(r, "no normal channels among its channels Y; expected R, G, B")) << r.output;

  // The same reference, its camera recorded without near and far (as images were before them).
  view::ImageMetadata meta;
  const view::FrameBuffers ref = view::readExr(s.reference, &meta);
  view::Camera camera = view::cameraFromJson(meta.at("surftrace:camera"));
  camera.zNear = camera.zFar = 0.0;
  meta["surftrace:camera"] = view::cameraToJson(camera);
  const std::string noRange = temp("errors_no_range.exr"), noCamera = temp("errors_no_camera.exr");
  view::writeExr(noRange, ref, meta);
  r = run("compare " + pfm + " " + noRange + " --depth-convention window");
  EXPECT_EQ(r.status, 1) << r.output;
  EXPECT_TRUE(has(r, noRange + ": the reference's camera has no near and far (near 0, far 0): window depth needs")) << r.output;
  const std::string viewZ = temp("errors_viewz.pfm");
  oracle::writePfm(viewZ, kWidth, kHeight, 1, stored(s.gl, 1, true, [&](std::size_t p) { return glm::dvec3(s.gl.viewZ[p]); }));
  EXPECT_EQ(run("compare " + viewZ + " " + noRange + " --depth-convention view-z").status, 0);
  meta.erase("surftrace:camera");
  view::writeExr(noCamera, ref, meta);
  r = run("compare " + pfm + " " + noCamera);
  EXPECT_EQ(r.status, 1) << r.output;
  EXPECT_TRUE(has(r, noCamera + " records no camera (surftrace:camera metadata)")) << r.output;
}

// SurfTrace's own EXR through the same door (its depth.z as view-z, depth.t as ray, its world
// normals): a real molecule's SES against itself, and the vdW surface against it fails.
TEST(CompareForeign, SurftraceBuffersThroughTheForeignDoor) {
  const std::string mol = std::string(SURFTRACE_TEST_DATA) + "/structures/1crn.pdb";
  const std::string ses = temp("door_ses.exr"), vdw = temp("door_vdw.exr"), cam = temp("door_cam.json");
  ASSERT_EQ(run("render " + mol + " --size 80x64 --view 1,0.3,-1 --quiet --exr " + ses + " --camera-out " + cam).status, 0);
  ASSERT_EQ(run("render " + mol + " --surface vdw --quiet --exr " + vdw + " --camera " + cam).status, 0);
  const std::string own = " --test-origin top-left --test-normal " + ses + " --normal-space world";
  Result r = run("compare " + ses + " " + ses + " --test-depth-channel depth.z --depth-convention view-z" + own);
  EXPECT_EQ(r.status, 0) << r.output;
  EXPECT_TRUE(has(r, "normals " + ses + ", world space")) << r.output;
  r = run("compare " + ses + " " + ses + " --test-depth-channel depth.t --depth-convention ray" + own);
  EXPECT_EQ(r.status, 0) << r.output;
  EXPECT_TRUE(has(r, "coverage mismatch 0 of")) << r.output;
  r = run("compare " + vdw + " " + ses + " --test-depth-channel depth.t --depth-convention ray --test-origin top-left");
  EXPECT_EQ(r.status, 2) << r.output;
}

// Values the declared depth convention cannot hold are an error (exit 1) naming the convention
// that fits them: view z declared as window depth, window depth declared as view z.
TEST(CompareForeign, DepthsTheConventionCannotHoldAreAnErrorWithTheOneThatFits) {
  const Scene s = frustumScene();
  const std::string viewZ = temp("impossible_viewz.pfm"), window = temp("impossible_window.pfm");
  oracle::writePfm(viewZ, kWidth, kHeight, 1, stored(s.gl, 1, true, [&](std::size_t p) { return glm::dvec3(s.gl.viewZ[p]); }));
  oracle::writePfm(window, kWidth, kHeight, 1, stored(s.gl, 1, true, [&](std::size_t p) { return glm::dvec3(s.gl.window[p]); }));
  Result r = run("compare " + viewZ + " " + s.reference + " --depth-convention window");
  EXPECT_EQ(r.status, 1) << r.output;
  EXPECT_TRUE(has(r, viewZ + ": channel Y holds ")) << r.output;
  EXPECT_TRUE(has(r, "which --depth-convention window cannot: window depth is in [0, 1]")) << r.output;
  EXPECT_TRUE(has(r, "hint: read as --depth-convention view-z they fit (coverage mismatch 0%")) << r.output;
  r = run("compare " + window + " " + s.reference + " --depth-convention view-z");
  EXPECT_EQ(r.status, 1) << r.output;
  EXPECT_TRUE(has(r, "which --depth-convention view-z cannot: view-z depth lies between the reference camera's near 3 "
                     "and far 40 Å"))
      << r.output;
  EXPECT_TRUE(has(r, "hint: read as --depth-convention window they fit (coverage mismatch 0%")) << r.output;
}

// The usual slips, each failing with a hint that names the reading that fits: unorm normals
// read as signed, world normals read as view ones, normals pointing inwards, ray distance read
// as view z.
TEST(CompareForeign, UsualMistakesFailWithAHint) {
  const Scene s = frustumScene();
  const std::string depth = temp("slips_depth.pfm"), ray = temp("slips_ray.pfm"), world = temp("slips_world.pfm"),
                    inward = temp("slips_inward.pfm"), unorm = temp("slips_unorm.png");
  oracle::writePfm(depth, kWidth, kHeight, 1, stored(s.gl, 1, true, [&](std::size_t p) { return glm::dvec3(s.gl.window[p]); }));
  oracle::writePfm(ray, kWidth, kHeight, 1, stored(s.gl, 1, true, [&](std::size_t p) { return glm::dvec3(s.gl.ray[p]); }));
  oracle::writePfm(world, kWidth, kHeight, 3, stored(s.gl, 3, true, [&](std::size_t p) { return s.gl.worldNormal[p]; }));
  oracle::writePfm(inward, kWidth, kHeight, 3, stored(s.gl, 3, true, [&](std::size_t p) { return -s.gl.viewNormal[p]; }));
  writeImage(unorm, kWidth, kHeight, {"R", "G", "B"},
             stored(s.gl, 3, true, [&](std::size_t p) { return 0.5 * s.gl.viewNormal[p] + 0.5; }), OIIO::TypeDesc::UINT16);
  const std::string base = "compare " + depth + " " + s.reference + " --test-origin bottom-left --test-normal ";

  Result r = run(base + unorm + " --normal-space view");
  EXPECT_EQ(r.status, 2) << r.output;
  EXPECT_TRUE(has(r, "hint: with --normal-encoding unorm the normal p99 would be")) << r.output;
  EXPECT_TRUE(has(r, "unorm normals ((n + 1)/2) read as signed (every component is in [0, 1])")) << r.output;
  r = run(base + world + " --normal-space view");
  EXPECT_EQ(r.status, 2) << r.output;
  EXPECT_TRUE(has(r, "hint: with --normal-space world the normal p99 would be")) << r.output;
  EXPECT_TRUE(has(r, "world normals read as view ones")) << r.output;
  r = run(base + inward + " --normal-space view");
  EXPECT_EQ(r.status, 2) << r.output;
  EXPECT_TRUE(has(r, "hint: negated, the normal p99 would be")) << r.output;
  EXPECT_TRUE(has(r, "the normals point into the surface, against the depth's gradient")) << r.output;
  r = run("compare " + ray + " " + s.reference + " --depth-convention view-z");
  EXPECT_EQ(r.status, 2) << r.output;
  EXPECT_TRUE(has(r, "hint: with --depth-convention ray the depth p99 would be")) << r.output;
  // A failure no other reading mends gives no hint: the rows one off.
  std::vector<float> shifted = stored(s.gl, 1, true, [&](std::size_t p) { return glm::dvec3(s.gl.window[p]); });
  shifted.erase(shifted.begin(), shifted.begin() + kWidth);
  shifted.insert(shifted.end(), kWidth, 1.0f);
  const std::string oneRowOff = temp("slips_shifted.pfm");
  oracle::writePfm(oneRowOff, kWidth, kHeight, 1, shifted);
  r = run("compare " + oneRowOff + " " + s.reference);
  EXPECT_EQ(r.status, 2) << r.output;
  EXPECT_FALSE(has(r, "hint:")) << r.output;
}

// With a view that has no rotation, view and world normals are the same numbers: compare says
// that it cannot check the normals' space; with a rotated view it says nothing.
TEST(CompareForeign, AnUnrotatedViewCannotCheckTheNormalSpace) {
  const glm::dmat4 projection = glm::perspective(glm::radians(40.0), double(kWidth) / kHeight, 5.0, 40.0);
  const glm::dmat4 front = glm::lookAt(glm::dvec3(1.0, 2.0, 20.0), glm::dvec3(1.0, 2.0, -2.0), glm::dvec3(0.0, 1.0, 0.0));
  const std::string xyzr = temp("front.xyzr"), cam = temp("front_camera.json"), ref = temp("front_ref.exr");
  std::ofstream atoms(xyzr);
  for (const glm::dvec4& a : kAtoms) atoms << a.x << " " << a.y << " " << a.z << " " << a.w << "\n";
  atoms.close();
  std::ofstream(cam) << nlohmann::json{{"width", kWidth}, {"height", kHeight}, {"view_matrix", matrixJson(front)},
                                       {"projection_matrix", matrixJson(projection)}}
                            .dump();
  ASSERT_EQ(run("render " + xyzr + " --input-format xyzr --surface vdw --quiet --exr " + ref + " --camera " + cam).status, 0);
  const oracle::GlSphereBuffers gl = oracle::drawSpheresGl(kWidth, kHeight, front, projection, kAtoms);
  const std::string depth = temp("front_depth.pfm"), normal = temp("front_normal.pfm");
  oracle::writePfm(depth, kWidth, kHeight, 1, stored(gl, 1, true, [&](std::size_t p) { return glm::dvec3(gl.window[p]); }));
  oracle::writePfm(normal, kWidth, kHeight, 3, stored(gl, 3, true, [&](std::size_t p) { return gl.worldNormal[p]; }));
  const std::string note = "note      the reference camera's view is not rotated";
  Result r = run("compare " + depth + " " + ref + " --test-normal " + normal + " --normal-space view");
  EXPECT_EQ(r.status, 0) << r.output;
  EXPECT_TRUE(has(r, note)) << r.output;
  EXPECT_TRUE(has(r, "a wrong --normal-space cannot show")) << r.output;
  r = run("compare " + depth + " " + ref);  // no normals judged: nothing to say
  EXPECT_FALSE(has(r, note)) << r.output;

  const Scene s = frustumScene();
  const std::string rotatedDepth = temp("rotated_depth.pfm"), rotatedNormal = temp("rotated_normal.pfm");
  oracle::writePfm(rotatedDepth, kWidth, kHeight, 1, stored(s.gl, 1, true, [&](std::size_t p) { return glm::dvec3(s.gl.window[p]); }));
  oracle::writePfm(rotatedNormal, kWidth, kHeight, 3, stored(s.gl, 3, true, [&](std::size_t p) { return s.gl.viewNormal[p]; }));
  r = run("compare " + rotatedDepth + " " + s.reference + " --test-normal " + rotatedNormal + " --normal-space view");
  EXPECT_EQ(r.status, 0) << r.output;
  EXPECT_FALSE(has(r, note)) << r.output;
}

// NaN in another renderer's depth is counted and judged a mismatch, never taken as background.
TEST(CompareForeign, NanDepthIsAMismatch) {
  const Scene s = frustumScene();
  std::vector<float> depth = stored(s.gl, 1, true, [&](std::size_t p) { return glm::dvec3(s.gl.viewZ[p]); });
  std::size_t made = 0;
  for (std::size_t p = 0; p < depth.size() && made < 7; p += 13)
    if (std::isfinite(depth[p])) depth[p] = std::numeric_limits<float>::quiet_NaN(), ++made;
  ASSERT_EQ(made, 7u);
  const std::string pfm = temp("nan_viewz.pfm"), json = temp("nan_viewz.json");
  oracle::writePfm(pfm, kWidth, kHeight, 1, depth);
  const Result r = run("compare " + pfm + " " + s.reference + " --depth-convention view-z --report " + json);
  EXPECT_EQ(r.status, 2) << r.output;
  EXPECT_TRUE(has(r, "NaN in 7 px of the test (depth 7, normal 0, colour 0)")) << r.output;
  std::ifstream in(json);
  const nlohmann::json j = nlohmann::json::parse(in);
  EXPECT_EQ(j["nan"]["test"]["depth"].get<int>(), 7);
  EXPECT_EQ(j["coverage"]["mismatch"].get<int>(), 0) << "a NaN is not a miss";
}

}  // namespace
}  // namespace surftrace::tools

// `--camera-out` and `--camera` (issue 20): a camera exported by one run and read by another,
// or written by another program as two OpenGL matrices, gives exactly the view it describes.
#include <cmath>
#include <filesystem>
#include <fstream>
#include <string>

#include <glm/ext/matrix_clip_space.hpp>
#include <glm/ext/matrix_transform.hpp>
#include <glm/geometric.hpp>
#include <glm/matrix.hpp>
#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

#include "run_tool.hpp"
#include "temp_dir.hpp"
#include "view/camera.hpp"
#include "view/image_io.hpp"

namespace surftrace::tools {
namespace {

using test::Result;
Result run(const std::string& args) { return test::runTool(args); }
std::string data(const std::string& file) { return std::string(SURFTRACE_TEST_DATA) + "/" + file; }
std::string temp(const std::string& name) { return (::surftrace::test::testTempDir() / name).string(); }

nlohmann::json readJson(const std::string& path) {
  std::ifstream in(path);
  return nlohmann::json::parse(in);
}

void writeText(const std::string& path, const std::string& text) { std::ofstream(path) << text; }

nlohmann::json matrixJson(const glm::dmat4& m) {
  nlohmann::json a = nlohmann::json::array();
  for (int c = 0; c < 4; ++c)
    for (int r = 0; r < 4; ++r) a.push_back(m[c][r]);
  return a;
}

// The exported camera is the one in the image's metadata, its near and far hold the scene,
// and rendering from it (the whole file, or its matrices alone) gives the same image.
TEST(CameraCli, ExportedCameraRendersTheSameImage) {
  const std::string input = data("structures/1crn.pdb");
  const std::string a = temp("cam_a.exr"), b = temp("cam_b.exr"), c = temp("cam_c.exr");
  const std::string cam = temp("cam.json"), matricesOnly = temp("cam_matrices.json");
  const Result first = run("render " + input + " --size 96x64 --view 1,0.3,-1 --quiet --exr " + a + " --camera-out " + cam);
  ASSERT_EQ(first.status, 0) << first.output;
  const nlohmann::json j = readJson(cam);
  EXPECT_EQ(j["format"], "surftrace-camera");
  EXPECT_EQ(j["version"], 1);
  EXPECT_EQ(j["view_matrix"].size(), 16u);
  EXPECT_EQ(j["projection_matrix"].size(), 16u);
  view::ImageMetadata meta;
  const view::FrameBuffers ref = view::readExr(a, &meta);
  const view::Camera recorded = view::cameraFromJson(meta.at("surftrace:camera"));
  const view::Camera exported = view::cameraFromJson(j.dump());
  EXPECT_EQ(recorded.eye, exported.eye);
  EXPECT_EQ(recorded.zNear, exported.zNear);
  EXPECT_EQ(recorded.zFar, exported.zFar);
  // Every surface point seen lies between near and far, and not far inside them.
  double lo = INFINITY, hi = -INFINITY;
  for (std::size_t p = 0; p < ref.pixels(); ++p)
    if (std::isfinite(ref.viewZ[p])) lo = std::min(lo, double(ref.viewZ[p])), hi = std::max(hi, double(ref.viewZ[p]));
  EXPECT_GT(lo, exported.zNear);
  EXPECT_LT(hi, exported.zFar);
  EXPECT_LT(exported.zFar - exported.zNear, 3.0 * (hi - lo) + 10.0) << "the depth range is not tight";

  const Result again = run("render " + input + " --quiet --exr " + b + " --camera " + cam);
  ASSERT_EQ(again.status, 0) << again.output;
  const Result same = run("compare " + b + " " + a + " --preset exact");
  EXPECT_EQ(same.status, 0) << same.output;

  nlohmann::json m = j;
  for (const char* key : {"eye", "look_at", "up", "projection", "fov_y_degrees", "ortho_height", "near", "far"}) m.erase(key);
  writeText(matricesOnly, m.dump());
  const Result foreign = run("render " + input + " --quiet --exr " + c + " --camera " + matricesOnly);
  ASSERT_EQ(foreign.status, 0) << foreign.output;
  const Result close = run("compare " + c + " " + a + " --preset exact --ignore-camera");
  EXPECT_EQ(close.status, 0) << close.output;
}

// Another program's off-centre frustum with non-square pixels: each pixel's depth is the
// distance along the matrices' ray to the one atom's sphere (the vdW surface), computed here
// from the inverse matrices.
TEST(CameraCli, ForeignOffCentreFrustumSeesWhatItsMatricesSee) {
  const std::string xyzr = temp("one_atom.xyzr"), cam = temp("frustum.json"), exr = temp("frustum.exr");
  writeText(xyzr, "1.0 2.0 -3.0 2.5\n");
  const glm::dvec3 centre(1.0, 2.0, -3.0);
  const double radius = 2.5;
  const glm::dmat4 view = glm::lookAt(glm::dvec3(6.0, 4.0, 12.0), glm::dvec3(0.0, 1.0, -2.0), glm::dvec3(0.1, 1.0, 0.0));
  const glm::dmat4 proj = glm::frustum(-0.9, 2.1, -1.3, 0.8, 3.0, 40.0);
  const int width = 40, height = 24;
  writeText(cam, nlohmann::json{{"width", width}, {"height", height}, {"view_matrix", matrixJson(view)},
                                {"projection_matrix", matrixJson(proj)}}
                     .dump());
  const Result r = run("render " + xyzr + " --input-format xyzr --surface vdw --quiet --exr " + exr + " --camera " + cam);
  ASSERT_EQ(r.status, 0) << r.output;
  const view::FrameBuffers image = view::readExr(exr);
  ASSERT_EQ(image.width, width);
  ASSERT_EQ(image.height, height);
  const glm::dmat4 inverse = glm::inverse(proj * view);
  const glm::dvec3 eye = glm::dvec3(glm::inverse(view)[3]);
  std::size_t hits = 0;
  for (int y = 0; y < height; ++y)
    for (int x = 0; x < width; ++x) {
      const double ndcX = 2.0 * (x + 0.5) / width - 1.0, ndcY = 1.0 - 2.0 * (y + 0.5) / height;
      const glm::dvec4 q = inverse * glm::dvec4(ndcX, ndcY, 1.0, 1.0);
      const glm::dvec3 dir = glm::normalize(glm::dvec3(q) / q.w - eye);
      const glm::dvec3 oc = eye - centre;
      const double b = glm::dot(oc, dir), disc = b * b - (glm::dot(oc, oc) - radius * radius);
      const std::size_t p = static_cast<std::size_t>(y) * width + x;
      if (disc < 1e-6) {
        if (disc < -1e-6) {
          EXPECT_FALSE(std::isfinite(image.depth[p])) << x << "," << y;
        }
        continue;
      }
      ++hits;
      ASSERT_TRUE(std::isfinite(image.depth[p])) << x << "," << y;
      EXPECT_NEAR(image.depth[p], -b - std::sqrt(disc), 1e-4) << x << "," << y;
    }
  EXPECT_GT(hits, 50u);
}

TEST(CameraCli, CameraConflictsAndBadFilesAreNamed) {
  const std::string input = data("structures/1crn.pdb"), cam = temp("conflict.json"), png = temp("conflict.png");
  ASSERT_EQ(run("render " + input + " --size 32x32 --quiet -o " + png + " --camera-out " + cam).status, 0);
  Result r = run("render " + input + " --quiet -o " + png + " --camera " + cam + " --view left");
  EXPECT_EQ(r.status, 1);
  EXPECT_NE(r.output.find("--view cannot be combined with --camera"), std::string::npos) << r.output;
  r = run("render " + input + " --quiet -o " + png + " --camera " + cam + " --size 64x64");
  EXPECT_EQ(r.status, 1);
  EXPECT_NE(r.output.find("--size 64x64 disagrees with --camera"), std::string::npos) << r.output;
  const std::string broken = temp("broken.json");
  writeText(broken, nlohmann::json{{"width", 32}, {"height", 32}, {"view_matrix", {1, 0}},
                                   {"projection_matrix", matrixJson(glm::perspective(0.5, 1.0, 1.0, 9.0))}}
                        .dump());
  r = run("render " + input + " --quiet -o " + png + " --camera " + broken);
  EXPECT_EQ(r.status, 1);
  EXPECT_NE(r.output.find("--camera " + broken + ": camera: \"view_matrix\" must be 16 numbers"), std::string::npos)
      << r.output;
  // A key given twice: which was meant cannot be known (nlohmann::json alone keeps the last).
  const std::string twice = temp("twice.json");
  std::string text;
  {
    std::ifstream in(cam);
    std::getline(in, text, '\0');
  }
  ASSERT_EQ(text.front(), '{');
  writeText(twice, "{\"width\": 64," + text.substr(1));
  r = run("render " + input + " --quiet -o " + png + " --camera " + twice);
  EXPECT_EQ(r.status, 1);
  EXPECT_NE(r.output.find("--camera " + twice + ": camera: the key \"width\" is given twice (64, then 32)"),
            std::string::npos)
      << r.output;
}

// A trajectory's camera is fixed for the run; --camera-out writes it, and every frame records it.
TEST(CameraCli, TrajectoryExportsItsOneCamera) {
  const std::string dir = temp("traj_cam"), cam = temp("traj_cam.json");
  const Result r = run("trajectory " + data("trajectories/adk_dims/adk.psf.gz") + " " + data("trajectories/adk_dims/adk_dims.dcd") +
                       " --frames 0:3 --surface vdw --size 64x64 --quiet --exr " + dir + "/%02d.exr --camera-out " + cam);
  ASSERT_EQ(r.status, 0) << r.output;
  const view::Camera exported = view::cameraFromJson(readJson(cam).dump());
  // The exported camera read back by another run draws the same frames.
  const std::string again = temp("traj_cam_again");
  const Result second = run("trajectory " + data("trajectories/adk_dims/adk.psf.gz") + " " +
                            data("trajectories/adk_dims/adk_dims.dcd") + " --frames 2:3 --surface vdw --quiet --exr " +
                            again + "/%02d.exr --camera " + cam);
  ASSERT_EQ(second.status, 0) << second.output;
  // (64x64: at 32x32 the seams mask every pixel of the vdW balls, and a limit over no pixels fails.)
  const Result same = run("compare " + again + "/02.exr " + dir + "/02.exr --preset exact");
  EXPECT_EQ(same.status, 0) << same.output;
  for (const char* frame : {"/00.exr", "/02.exr"}) {
    view::ImageMetadata meta;
    const view::FrameBuffers image = view::readExr(dir + frame, &meta);
    const view::Camera recorded = view::cameraFromJson(meta.at("surftrace:camera"));
    EXPECT_EQ(recorded.eye, exported.eye);
    EXPECT_EQ(recorded.zFar, exported.zFar);
    for (std::size_t p = 0; p < image.pixels(); ++p)
      if (std::isfinite(image.viewZ[p])) {
        EXPECT_GT(image.viewZ[p], exported.zNear);
        EXPECT_LT(image.viewZ[p], exported.zFar);
      }
  }
}

}  // namespace
}  // namespace surftrace::tools

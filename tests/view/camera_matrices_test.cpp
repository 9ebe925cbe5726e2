// Cameras in OpenGL's conventions (issue 20): the exported matrices, cameras imported from
// another program's matrices (off-centre frusta included) and the JSON file, against the
// oracle of a GL program: a pixel centre's ray is the unprojection of its NDC point at clip
// z = −1 and z = +1 through the inverse of projection·view (a general 4x4 inverse).
#include <cmath>
#include <random>
#include <stdexcept>
#include <string>

#include <glm/ext/matrix_clip_space.hpp>
#include <glm/ext/matrix_transform.hpp>
#include <glm/geometric.hpp>
#include <glm/matrix.hpp>
#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

#include "view/camera.hpp"

namespace surftrace::view {
namespace {

constexpr double kPi = 3.14159265358979323846;

glm::dvec3 unproject(const glm::dmat4& inverseViewProjection, double ndcX, double ndcY, double ndcZ) {
  const glm::dvec4 p = inverseViewProjection * glm::dvec4(ndcX, ndcY, ndcZ, 1.0);
  return glm::dvec3(p) / p.w;
}

// Every pixel centre of a coarse grid (and the corners): the camera's ray passes through the
// matrices' near and far points of that pixel, and, for a perspective camera, starts at the eye.
void expectRaysOfTheMatrices(const Camera& camera, const glm::dmat4& view, const glm::dmat4& projection,
                             const std::string& where) {
  const glm::dmat4 inverse = glm::inverse(projection * view);
  const Camera::Frame frame = camera.frame();
  const double scale = std::max(1.0, std::abs(camera.zFar));
  for (int py = 0; py <= camera.height; py += std::max(1, camera.height / 7)) {
    for (int px = 0; px <= camera.width; px += std::max(1, camera.width / 9)) {
      const double sx = std::min(px + 0.5, camera.width - 0.5), sy = std::min(py + 0.5, camera.height - 0.5);
      // Image rows run down, window y up.
      const double ndcX = 2.0 * sx / camera.width - 1.0, ndcY = 1.0 - 2.0 * sy / camera.height;
      const glm::dvec3 nearPoint = unproject(inverse, ndcX, ndcY, -1.0), farPoint = unproject(inverse, ndcX, ndcY, 1.0);
      const Ray ray = frame.ray(sx, sy);
      for (const glm::dvec3& q : {nearPoint, farPoint}) {
        const glm::dvec3 v = q - ray.org;
        const double off = glm::length(v - glm::dot(v, ray.dir) * ray.dir);
        EXPECT_LT(off, 1e-9 * scale) << where << " pixel " << sx << "," << sy;
      }
      // The ray runs from near to far (an orthographic near plane may lie behind the eye's plane).
      EXPECT_GT(glm::dot(farPoint - nearPoint, ray.dir), 0.0) << where;
      if (camera.projection == Projection::Perspective) {
        EXPECT_GT(glm::dot(nearPoint - ray.org, ray.dir), 0.0) << where;
      }
      // The depths along the view axis are near and far.
      const glm::dvec3 f = camera.forward();
      EXPECT_NEAR(glm::dot(nearPoint - camera.eye, f), camera.zNear, 1e-9 * scale) << where;
      EXPECT_NEAR(glm::dot(farPoint - camera.eye, f), camera.zFar, 1e-9 * scale) << where;
    }
  }
}

Camera randomCamera(std::mt19937& rng, Projection projection) {
  std::uniform_real_distribution<double> u(-50.0, 50.0);
  Camera c;
  c.projection = projection;
  c.eye = {u(rng), u(rng), u(rng)};
  c.lookAt = c.eye + glm::normalize(glm::dvec3(u(rng), u(rng), u(rng))) * (60.0 + u(rng));
  c.up = glm::normalize(glm::dvec3(u(rng), u(rng), u(rng)));
  c.fovY = 10.0 + std::abs(u(rng));
  c.orthoHeight = 5.0 + std::abs(u(rng));
  c.width = 40 + static_cast<int>(std::abs(u(rng)) * 10.0);
  c.height = 30 + static_cast<int>(std::abs(u(rng)) * 7.0);
  c.zNear = projection == Projection::Perspective ? 20.0 + std::abs(u(rng)) : -10.0 + u(rng) * 0.1;
  c.zFar = c.zNear + 30.0 + std::abs(u(rng));
  return c;
}

TEST(CameraMatrices, ExportedMatricesAreGlmsAndDefineTheCamerasRays) {
  std::mt19937 rng(7);
  for (Projection projection : {Projection::Perspective, Projection::Orthographic}) {
    for (int k = 0; k < 20; ++k) {
      const Camera c = randomCamera(rng, projection);
      const glm::dmat4 view = glm::lookAt(c.eye, c.lookAt, c.up);
      const double aspect = static_cast<double>(c.width) / c.height;
      const glm::dmat4 proj =
          projection == Projection::Perspective
              ? glm::perspective(c.fovY * kPi / 180.0, aspect, c.zNear, c.zFar)
              : glm::ortho(-0.5 * c.orthoHeight * aspect, 0.5 * c.orthoHeight * aspect, -0.5 * c.orthoHeight,
                           0.5 * c.orthoHeight, c.zNear, c.zFar);
      const glm::dmat4 v = c.viewMatrix(), p = c.projectionMatrix();
      for (int i = 0; i < 4; ++i)
        for (int j = 0; j < 4; ++j) {
          EXPECT_NEAR(v[i][j], view[i][j], 1e-12 * (1.0 + std::abs(view[i][j])));
          EXPECT_NEAR(p[i][j], proj[i][j], 1e-12 * (1.0 + std::abs(proj[i][j])));
        }
      expectRaysOfTheMatrices(c, view, proj, "camera " + std::to_string(k));
    }
  }
}

// Another program's camera: glm::lookAt and an off-centre glm::frustum / glm::ortho with
// non-square pixels, imported from the matrices alone.
TEST(CameraMatrices, ForeignOffCentreFrustaGiveTheMatricesRays) {
  std::mt19937 rng(11);
  std::uniform_real_distribution<double> u(-1.0, 1.0);
  for (int k = 0; k < 40; ++k) {
    const bool perspective = k % 2 == 0;
    const glm::dvec3 eye(30 * u(rng), 30 * u(rng), 30 * u(rng));
    const glm::dvec3 centre = eye + glm::dvec3(u(rng), u(rng), u(rng)) * 40.0;
    const glm::dvec3 up(u(rng), u(rng), u(rng));
    const glm::dmat4 view = glm::lookAt(eye, centre, up);
    const double n = perspective ? 5.0 + 3.0 * u(rng) : -4.0 + u(rng), f = n + 50.0 + 10.0 * u(rng);
    const double l = -2.0 + 0.9 * u(rng), r = 2.0 + 0.9 * u(rng), b = -1.5 + u(rng), t = 1.7 + u(rng);
    const glm::dmat4 proj = perspective ? glm::frustum(l, r, b, t, n, f) : glm::ortho(3 * l, 3 * r, 3 * b, 3 * t, n, f);
    const int width = 64 + k, height = 48 + 2 * k;
    const Camera c = cameraFromMatrices(width, height, view, proj);
    EXPECT_EQ(c.projection, perspective ? Projection::Perspective : Projection::Orthographic);
    EXPECT_NEAR(c.zNear, n, 1e-9 * f);
    EXPECT_NEAR(c.zFar, f, 1e-9 * f);
    ASSERT_TRUE(c.window.has_value());
    expectRaysOfTheMatrices(c, view, proj, "foreign camera " + std::to_string(k));
    // Scaling a projection matrix changes no projection.
    const Camera scaled = cameraFromMatrices(width, height, view, 2.5 * proj);
    EXPECT_LT(glm::length(scaled.ray(3.5, 7.5).dir - c.ray(3.5, 7.5).dir), 1e-14);
    // Its own matrices are the ones it came from.
    const glm::dmat4 p = c.projectionMatrix();
    for (int i = 0; i < 4; ++i)
      for (int j = 0; j < 4; ++j) EXPECT_NEAR(p[i][j], proj[i][j], 1e-9 * (1.0 + std::abs(proj[i][j])));
  }
}

TEST(CameraMatrices, CentredMatricesGiveTheOrdinaryCamera) {
  const glm::dmat4 view = glm::lookAt(glm::dvec3(1, 2, 30), glm::dvec3(1, 2, 0), glm::dvec3(0, 1, 0));
  const glm::dmat4 proj = glm::perspective(40.0 * kPi / 180.0, 640.0 / 480.0, 10.0, 50.0);
  const Camera c = cameraFromMatrices(640, 480, view, proj);
  EXPECT_FALSE(c.window.has_value());
  EXPECT_NEAR(c.fovY, 40.0, 1e-12);
  EXPECT_LT(glm::length(c.eye - glm::dvec3(1, 2, 30)), 1e-12);
  EXPECT_LT(glm::length(c.forward() - glm::dvec3(0, 0, -1)), 1e-15);
}

TEST(CameraMatrices, JsonRoundTripsExactly) {
  std::mt19937 rng(3);
  for (Projection projection : {Projection::Perspective, Projection::Orthographic}) {
    Camera c = randomCamera(rng, projection);
    for (int withWindow = 0; withWindow < 2; ++withWindow) {
      if (withWindow) c.window = ViewWindow{-0.3, 0.7, -0.2, 0.45};
      const Camera d = cameraFromJson(cameraToJson(c));
      EXPECT_EQ(d.eye, c.eye);
      EXPECT_EQ(d.lookAt, c.lookAt);
      EXPECT_EQ(d.up, c.up);
      EXPECT_EQ(d.fovY, c.fovY);
      EXPECT_EQ(d.orthoHeight, c.orthoHeight);
      EXPECT_EQ(d.zNear, c.zNear);
      EXPECT_EQ(d.zFar, c.zFar);
      EXPECT_EQ(d.window.has_value(), c.window.has_value());
      const Ray a = c.ray(12.5, 7.5), b = d.ray(12.5, 7.5);
      EXPECT_EQ(a.org, b.org);
      EXPECT_EQ(a.dir, b.dir);
      // The matrices alone (what another program keeps) give the same rays.
      auto j = nlohmann::json::parse(cameraToJson(c));
      for (const char* key : {"eye", "look_at", "up", "projection", "fov_y_degrees", "ortho_height", "window"}) j.erase(key);
      const Camera m = cameraFromJson(j.dump());
      const Ray e = m.ray(12.5, 7.5);
      EXPECT_LT(glm::length(e.dir - a.dir), 1e-12);
      EXPECT_LT(glm::length(e.org - a.org), 1e-9 * glm::length(a.org) + 1e-12);
    }
  }
}

TEST(CameraMatrices, BadCamerasAreNamed) {
  const glm::dmat4 view = glm::lookAt(glm::dvec3(0, 0, 30), glm::dvec3(0), glm::dvec3(0, 1, 0));
  const glm::dmat4 proj = glm::perspective(0.5, 1.0, 10.0, 50.0);
  auto message = [](auto&& f) {
    try {
      f();
    } catch (const std::invalid_argument& e) {
      return std::string(e.what());
    }
    return std::string("no error");
  };
  EXPECT_NE(message([&] { cameraFromMatrices(64, 64, 2.0 * view, proj); }).find("view_matrix"), std::string::npos);
  glm::dmat4 sheared = view;
  sheared[1][0] = 0.3;
  EXPECT_NE(message([&] { cameraFromMatrices(64, 64, sheared, proj); }).find("not rigid"), std::string::npos);
  glm::dmat4 skew = proj;
  skew[1][0] = 0.1;
  EXPECT_NE(message([&] { cameraFromMatrices(64, 64, view, skew); }).find("glFrustum"), std::string::npos);
  EXPECT_NE(message([&] { cameraFromMatrices(64, 64, view, glm::dmat4(0.0)); }).find("neither"), std::string::npos);
  EXPECT_NE(message([] { cameraFromJson("{\"width\": 4}"); }).find("view_matrix"), std::string::npos);
  EXPECT_NE(message([] { cameraFromJson("[1,2"); }).find("not JSON"), std::string::npos);
  Camera c;
  c.zNear = 1, c.zFar = 100;
  auto j = nlohmann::json::parse(cameraToJson(c));
  j["eye"] = {0, 0, 11};
  EXPECT_NE(message([&] { cameraFromJson(j.dump()); }).find("disagree"), std::string::npos);
  j = nlohmann::json::parse(cameraToJson(c));
  j["version"] = 2;
  EXPECT_NE(message([&] { cameraFromJson(j.dump()); }).find("version"), std::string::npos);
  j = nlohmann::json::parse(cameraToJson(c));
  j.erase("width");
  EXPECT_NE(message([&] { cameraFromJson(j.dump()); }).find("\"width\" is missing"), std::string::npos);
}

// A key given twice is an error naming it, where it is and both values (nlohmann::json alone
// keeps the last: a camera with "width" twice rendered at the second width, silently). The
// same key in two different objects is no repeat.
TEST(CameraMatrices, AKeyGivenTwiceIsNamed) {
  Camera c;
  c.width = 320;
  c.window = ViewWindow{-1.0, 1.0, -1.0, 1.0};
  const std::string json = cameraToJson(c);
  ASSERT_EQ(json.front(), '{');
  auto message = [](const std::string& text) {
    try {
      cameraFromJson(text);
    } catch (const std::invalid_argument& e) {
      return std::string(e.what());
    }
    return std::string("no error");
  };
  EXPECT_EQ(message("{\"width\": 640, " + json.substr(1)),
            "camera: the key \"width\" is given twice (640, then 320): give it once");
  EXPECT_EQ(message(json.substr(0, json.size() - 1) + ", \"eye\": [1, 2, 3]}"),
            "camera: the key \"eye\" is given twice ([0.0,0.0,10.0], then [1,2,3]): give it once");
  const std::size_t left = json.find("\"left\":");
  ASSERT_NE(left, std::string::npos);
  EXPECT_EQ(message(json.substr(0, left) + "\"left\": {\"x\": [7]}, " + json.substr(left)),
            "camera: the key \"window.left\" is given twice ({\"x\":[7]}, then -1.0): give it once");
  // Keys repeated only across objects, or a nested object's keys that an outer key repeats.
  const Camera d = cameraFromJson(json.substr(0, json.size() - 1) + ", \"note\": {\"width\": 1, \"window\": {\"left\": 2}}}");
  EXPECT_EQ(d.width, 320);
  ASSERT_TRUE(d.window);
  EXPECT_EQ(d.window->left, -1.0);
}

TEST(CameraMatrices, DepthRangeHoldsEverySphereTightly) {
  Camera c;
  c.eye = {0, 0, 100};
  c.lookAt = {0, 0, 0};
  const std::vector<glm::dvec3> centers = {{0, 0, 10}, {5, 0, -20}, {0, 3, 0}};
  const std::vector<double> radii = {2.0, 4.0, 1.0};
  const Camera d = withDepthRange(c, centers, radii);
  // Depths along −z from z = 100: nearest 100 − 12 = 88, farthest 120 + 4 = 124.
  EXPECT_LT(d.zNear, 88.0);
  EXPECT_GT(d.zNear, 88.0 - 0.1);
  EXPECT_GT(d.zFar, 124.0);
  EXPECT_LT(d.zFar, 124.0 + 0.1);
  c.eye = {0, 0, 5};  // inside the scene: near stays positive
  const Camera e = withDepthRange(c, centers, radii);
  EXPECT_GT(e.zNear, 0.0);
  c.eye = {0, 0, -40};  // looking away: nothing to see, and still a valid range
  const Camera f = withDepthRange(c, centers, radii);
  EXPECT_GT(f.zNear, 0.0);
  EXPECT_GT(f.zFar, f.zNear);
}

}  // namespace
}  // namespace surftrace::view

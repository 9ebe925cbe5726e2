// The camera: pixel-centre rays in double precision, automatic framing, named views.
#include "view/camera.hpp"

#include <algorithm>
#include <cmath>
#include <limits>
#include <sstream>
#include <stdexcept>

#include <glm/geometric.hpp>
#include <nlohmann/json.hpp>

namespace surftrace::view {
namespace {

constexpr double kPi = 3.14159265358979323846;

bool finite(const glm::dvec3& v) { return std::isfinite(v.x) && std::isfinite(v.y) && std::isfinite(v.z); }

double halfTan(double fovY) { return std::tan(0.5 * fovY * kPi / 180.0); }

}  // namespace

glm::dvec3 Camera::forward() const { return glm::normalize(lookAt - eye); }
glm::dvec3 Camera::right() const { return glm::normalize(glm::cross(forward(), up)); }
glm::dvec3 Camera::trueUp() const { return glm::cross(right(), forward()); }

Camera::Frame Camera::frame() const {
  Frame f;
  f.eye = eye;
  f.forward = forward();
  f.right = right();
  f.up = glm::cross(f.right, f.forward);
  const double aspect = static_cast<double>(width) / height;
  f.perspective = projection == Projection::Perspective;
  const double h = f.perspective ? halfTan(fovY) : 0.5 * orthoHeight;
  f.scaleX = h * aspect;
  f.scaleY = h;
  f.invWidth = 2.0 / width;
  f.invHeight = 2.0 / height;
  return f;
}

Ray Camera::Frame::ray(double sx, double sy) const {
  const double x = sx * invWidth - 1.0, y = sy * invHeight - 1.0;
  if (perspective) return Ray{eye, glm::normalize(forward + (x * scaleX) * right - (y * scaleY) * up)};
  return Ray{eye + (x * scaleX) * right - (y * scaleY) * up, forward};
}

Ray Camera::ray(double sx, double sy) const { return frame().ray(sx, sy); }

double Camera::pixelFootprint(double t) const {
  return projection == Projection::Perspective ? 2.0 * t * halfTan(fovY) / height : orthoHeight / height;
}

void Camera::validate() const {
  auto bad = [](const std::string& what) { throw std::invalid_argument("camera: " + what); };
  if (width <= 0 || height <= 0 || width > 32768 || height > 32768)
    bad("image size " + std::to_string(width) + "x" + std::to_string(height) + " must be between 1x1 and 32768x32768");
  if (!finite(eye) || !finite(lookAt) || !finite(up)) bad("eye, look-at and up must be finite");
  if (!(glm::length(lookAt - eye) > 0.0)) bad("eye and look-at coincide");
  const glm::dvec3 f = lookAt - eye;
  if (!(glm::length(glm::cross(glm::normalize(f), up)) > 1e-9)) bad("up is parallel to the view direction; pick another --up");
  if (projection == Projection::Perspective && !(fovY > 0.0 && fovY < 180.0))
    bad("field of view " + std::to_string(fovY) + " must be in (0, 180) degrees");
  if (projection == Projection::Orthographic && !(orthoHeight > 0.0 && std::isfinite(orthoHeight)))
    bad("orthographic height must be finite and > 0");
}

glm::dvec3 namedViewDirection(const std::string& view) {
  if (view == "front") return {0, 0, -1};
  if (view == "back") return {0, 0, 1};
  if (view == "left") return {1, 0, 0};
  if (view == "right") return {-1, 0, 0};
  if (view == "top") return {0, -1, 0};
  if (view == "bottom") return {0, 1, 0};
  std::istringstream in(view);
  glm::dvec3 d;
  char c1 = 0, c2 = 0;
  if (in >> d.x >> c1 >> d.y >> c2 >> d.z && c1 == ',' && c2 == ',' && in.peek() == EOF && finite(d) &&
      glm::length(d) > 0.0)
    return glm::normalize(d);
  throw std::invalid_argument("unknown view '" + view +
                              "': use front, back, left, right, top, bottom, or a direction x,y,z (not 0,0,0)");
}

SphereFraming::SphereFraming(const Camera& camera, const glm::dvec3& direction, double margin) : margin_(margin) {
  forward_ = glm::normalize(direction);
  const glm::dvec3 worldUp = std::abs(forward_.y) > 0.99 ? glm::dvec3(0, 0, forward_.y > 0 ? 1 : -1) : glm::dvec3(0, 1, 0);
  right_ = glm::normalize(glm::cross(forward_, worldUp));
  up_ = glm::cross(right_, forward_);
  hy_ = halfTan(camera.fovY) / margin;
  hx_ = hy_ * (static_cast<double>(camera.width) / camera.height);
  constexpr double kInf = std::numeric_limits<double>::infinity();
  for (int k = 0; k < 3; ++k) lo_[k] = kInf, hi_[k] = -kInf;
  for (double& f : fit_) f = -kInf;
  inside_ = -kInf;
}

void SphereFraming::add(const glm::dvec3& center, double radius) {
  const double c[3] = {glm::dot(center, right_), glm::dot(center, up_), glm::dot(center, forward_)};
  for (int k = 0; k < 3; ++k) lo_[k] = std::min(lo_[k], c[k] - radius), hi_[k] = std::max(hi_[k], c[k] + radius);
  // A sphere at lateral offset s and depth z (from the look-at plane) fits a half-angle with
  // tangent h when |s| + r·sqrt(1 + h²) <= h·(D + z); with s = c − m and z = c_f − m_f, the
  // bound on D splits into a part of the sphere, kept here, and a part of the look-at point m.
  const double ex = radius * std::sqrt(1.0 + hx_ * hx_) / hx_, ey = radius * std::sqrt(1.0 + hy_ * hy_) / hy_;
  fit_[0] = std::max(fit_[0], c[0] / hx_ + ex - c[2]);
  fit_[1] = std::max(fit_[1], -c[0] / hx_ + ex - c[2]);
  fit_[2] = std::max(fit_[2], c[1] / hy_ + ey - c[2]);
  fit_[3] = std::max(fit_[3], -c[1] / hy_ + ey - c[2]);
  inside_ = std::max(inside_, radius - c[2]);
}

void SphereFraming::merge(const SphereFraming& other) {
  for (int k = 0; k < 3; ++k) lo_[k] = std::min(lo_[k], other.lo_[k]), hi_[k] = std::max(hi_[k], other.hi_[k]);
  for (int k = 0; k < 4; ++k) fit_[k] = std::max(fit_[k], other.fit_[k]);
  inside_ = std::max(inside_, other.inside_);
}

Camera SphereFraming::aim(Camera camera) const {
  if (empty()) throw std::invalid_argument("camera: nothing to frame (no atoms)");
  camera.up = std::abs(forward_.y) > 0.99 ? glm::dvec3(0, 0, forward_.y > 0 ? 1 : -1) : glm::dvec3(0, 1, 0);
  // Centre the projected extent of the spheres (their box in the view frame), so the
  // molecule fills the image rather than its bounding sphere.
  camera.lookAt = 0.5 * (lo_[0] + hi_[0]) * right_ + 0.5 * (lo_[1] + hi_[1]) * up_ + 0.5 * (lo_[2] + hi_[2]) * forward_;
  if (camera.projection == Projection::Orthographic) {
    const double aspect = static_cast<double>(camera.width) / camera.height;
    camera.orthoHeight = margin_ * std::max(hi_[1] - lo_[1], (hi_[0] - lo_[0]) / aspect);
    camera.eye = camera.lookAt - (hi_[2] - lo_[2] + camera.orthoHeight) * forward_;
  }
  return camera;
}

Camera SphereFraming::frame(Camera camera) const {
  camera = aim(camera);
  if (camera.projection == Projection::Orthographic) return camera;
  // Perspective: the nearest eye distance D at which every sphere lies inside the frustum.
  const double m[3] = {0.5 * (lo_[0] + hi_[0]), 0.5 * (lo_[1] + hi_[1]), 0.5 * (lo_[2] + hi_[2])};
  double distance = 0.0;
  distance = std::max(distance, fit_[0] - m[0] / hx_ + m[2]);
  distance = std::max(distance, fit_[1] + m[0] / hx_ + m[2]);
  distance = std::max(distance, fit_[2] - m[1] / hy_ + m[2]);
  distance = std::max(distance, fit_[3] + m[1] / hy_ + m[2]);
  distance = std::max(distance, inside_ + m[2] + 1e-3);  // the eye stays outside every sphere
  camera.eye = camera.lookAt - distance * forward_;
  return camera;
}

Camera frameSpheres(Camera camera, std::span<const glm::dvec3> centers, std::span<const double> radii,
                    const glm::dvec3& direction, double margin) {
  SphereFraming framing(camera, direction, margin);
  for (std::size_t i = 0; i < centers.size(); ++i) framing.add(centers[i], radii[i]);
  camera = framing.aim(camera);
  if (camera.projection == Projection::Orthographic) return camera;
  // The spheres are at hand: measure each from the look-at point, as SphereFraming::frame does
  // from the origin (the same bound, rounded as before it could be gathered in pieces, so that
  // a structure's camera and the reference images made with it stay bit for bit the same).
  // A sphere at lateral offset s and depth z (from the look-at plane) fits a half-angle with
  // tangent h when |s| + r·sqrt(1 + h²) <= h·(D + z).
  const glm::dvec3 f = glm::normalize(direction);
  const glm::dvec3 r = glm::normalize(glm::cross(f, camera.up)), u = glm::cross(r, f);
  const double hy = halfTan(camera.fovY) / margin, hx = hy * (static_cast<double>(camera.width) / camera.height);
  double distance = 0.0;
  for (std::size_t i = 0; i < centers.size(); ++i) {
    const glm::dvec3 v = centers[i] - camera.lookAt;
    const double sx = std::abs(glm::dot(v, r)), sy = std::abs(glm::dot(v, u)), z = glm::dot(v, f);
    distance = std::max(distance, (sx + radii[i] * std::sqrt(1.0 + hx * hx)) / hx - z);
    distance = std::max(distance, (sy + radii[i] * std::sqrt(1.0 + hy * hy)) / hy - z);
    distance = std::max(distance, radii[i] - z + 1e-3);  // the eye stays outside every sphere
  }
  camera.eye = camera.lookAt - distance * f;
  return camera;
}

Camera frameSphereCovers(Camera camera, std::span<const SphereCover> covers, const glm::dvec3& direction,
                         double margin) {
  if (covers.empty() || std::any_of(covers.begin(), covers.end(), [](const SphereCover& c) { return c.centers.empty(); }))
    throw std::invalid_argument("camera: nothing to frame (no atoms)");
  const glm::dvec3 f = glm::normalize(direction);
  camera.up = std::abs(f.y) > 0.99 ? glm::dvec3(0, 0, f.y > 0 ? 1 : -1) : glm::dvec3(0, 1, 0);
  const glm::dvec3 r = glm::normalize(glm::cross(f, camera.up)), u = glm::cross(r, f);
  // Centre the projected extent of the spheres (their box in the view frame), so the
  // molecule fills the image rather than its bounding sphere. The scene lies in every cover,
  // so in the intersection of their boxes.
  constexpr double kInf = std::numeric_limits<double>::infinity();
  double lo[3] = {-kInf, -kInf, -kInf}, hi[3] = {kInf, kInf, kInf};
  for (const SphereCover& cover : covers) {
    double coverLo[3] = {kInf, kInf, kInf}, coverHi[3] = {-kInf, -kInf, -kInf};
    for (std::size_t i = 0; i < cover.centers.size(); ++i) {
      const glm::dvec3& p = cover.centers[i];
      const double c[3] = {glm::dot(p, r), glm::dot(p, u), glm::dot(p, f)};
      for (int k = 0; k < 3; ++k)
        coverLo[k] = std::min(coverLo[k], c[k] - cover.radii[i]), coverHi[k] = std::max(coverHi[k], c[k] + cover.radii[i]);
    }
    for (int k = 0; k < 3; ++k) lo[k] = std::max(lo[k], coverLo[k]), hi[k] = std::min(hi[k], coverHi[k]);
  }
  const glm::dvec3 mid = 0.5 * (lo[0] + hi[0]) * r + 0.5 * (lo[1] + hi[1]) * u + 0.5 * (lo[2] + hi[2]) * f;
  camera.lookAt = mid;
  const double aspect = static_cast<double>(camera.width) / camera.height;
  if (camera.projection == Projection::Orthographic) {
    camera.orthoHeight = margin * std::max(hi[1] - lo[1], (hi[0] - lo[0]) / aspect);
    camera.eye = mid - (hi[2] - lo[2] + camera.orthoHeight) * f;
    return camera;
  }
  // Perspective: the nearest eye distance D at which every sphere of a cover lies inside the
  // frustum. A sphere at lateral offset s and depth z (from the look-at plane) fits a
  // half-angle with tangent h when |s| + r·sqrt(1 + h²) <= h·(D + z). Any one cover holding
  // the scene suffices, so the nearest of the covers' distances is taken.
  const double hy = halfTan(camera.fovY) / margin, hx = hy * aspect;
  double nearest = kInf;
  for (const SphereCover& cover : covers) {
    double distance = 0.0;
    for (std::size_t i = 0; i < cover.centers.size(); ++i) {
      const glm::dvec3 v = cover.centers[i] - mid;
      const double radius = cover.radii[i];
      const double sx = std::abs(glm::dot(v, r)), sy = std::abs(glm::dot(v, u)), z = glm::dot(v, f);
      distance = std::max(distance, (sx + radius * std::sqrt(1.0 + hx * hx)) / hx - z);
      distance = std::max(distance, (sy + radius * std::sqrt(1.0 + hy * hy)) / hy - z);
      distance = std::max(distance, radius - z + 1e-3);  // the eye stays outside every sphere
    }
    nearest = std::min(nearest, distance);
  }
  camera.eye = mid - nearest * f;
  return camera;
}

std::string cameraToJson(const Camera& c) {
  nlohmann::json j;
  j["projection"] = c.projection == Projection::Perspective ? "perspective" : "orthographic";
  j["eye"] = {c.eye.x, c.eye.y, c.eye.z};
  j["look_at"] = {c.lookAt.x, c.lookAt.y, c.lookAt.z};
  j["up"] = {c.up.x, c.up.y, c.up.z};
  j["fov_y_degrees"] = c.fovY;
  j["ortho_height"] = c.orthoHeight;
  j["width"] = c.width;
  j["height"] = c.height;
  j["pixel_centre"] = 0.5;
  return j.dump();
}

Camera cameraFromJson(const std::string& text) {
  const auto j = nlohmann::json::parse(text);
  auto v = [&](const char* key) {
    const auto& a = j.at(key);
    return glm::dvec3(a.at(0).get<double>(), a.at(1).get<double>(), a.at(2).get<double>());
  };
  Camera c;
  const auto projection = j.at("projection").get<std::string>();
  if (projection != "perspective" && projection != "orthographic")
    throw std::invalid_argument("camera: unknown projection '" + projection + "'");
  c.projection = projection == "perspective" ? Projection::Perspective : Projection::Orthographic;
  c.eye = v("eye");
  c.lookAt = v("look_at");
  c.up = v("up");
  c.fovY = j.at("fov_y_degrees").get<double>();
  c.orthoHeight = j.at("ortho_height").get<double>();
  c.width = j.at("width").get<int>();
  c.height = j.at("height").get<int>();
  c.validate();
  return c;
}

}  // namespace surftrace::view

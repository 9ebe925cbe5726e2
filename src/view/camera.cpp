// The camera: pixel-centre rays in double precision, automatic framing, named views.
#include "view/camera.hpp"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <limits>
#include <map>
#include <sstream>
#include <stdexcept>
#include <string>
#include <vector>

#include <glm/ext/matrix_clip_space.hpp>
#include <glm/ext/matrix_transform.hpp>
#include <glm/geometric.hpp>
#include <glm/matrix.hpp>
#include <nlohmann/json.hpp>

namespace surftrace::view {
namespace {

constexpr double kPi = 3.14159265358979323846;

bool finite(const glm::dvec3& v) { return std::isfinite(v.x) && std::isfinite(v.y) && std::isfinite(v.z); }

double halfTan(double fovY) { return std::tan(0.5 * fovY * kPi / 180.0); }

// A number in a message, %.6g: "1e+30", not std::to_string's thirty digits.
std::string shortNumber(double v) {
  char text[32];
  std::snprintf(text, sizeof text, "%.6g", v);
  return text;
}

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
  if (window) {
    f.offCentre = true;
    f.scaleX = 0.5 * (window->right - window->left);
    f.scaleY = 0.5 * (window->top - window->bottom);
    f.centreX = 0.5 * (window->right + window->left);
    f.centreY = 0.5 * (window->top + window->bottom);
  }
  return f;
}

Ray Camera::Frame::ray(double sx, double sy) const {
  const double x = sx * invWidth - 1.0, y = sy * invHeight - 1.0;
  if (offCentre) {
    // A separate branch: the centred camera's rays stay bit for bit what they always were.
    const double u = centreX + x * scaleX, v = centreY - y * scaleY;
    if (perspective) return Ray{eye, glm::normalize(forward + u * right + v * up)};
    return Ray{eye + u * right + v * up, forward};
  }
  if (perspective) return Ray{eye, glm::normalize(forward + (x * scaleX) * right - (y * scaleY) * up)};
  return Ray{eye + (x * scaleX) * right - (y * scaleY) * up, forward};
}

ViewWindow Camera::viewWindow() const {
  if (window) return *window;
  const double h = projection == Projection::Perspective ? halfTan(fovY) : 0.5 * orthoHeight;
  const double w = h * (static_cast<double>(width) / height);
  return ViewWindow{-w, w, -h, h};
}

glm::dmat4 Camera::viewMatrix() const { return glm::lookAtRH(eye, lookAt, up); }

glm::dmat4 Camera::projectionMatrix() const {
  if (!hasDepthRange()) throw std::logic_error("camera: a projection matrix needs a depth range (withDepthRange)");
  const double aspect = static_cast<double>(width) / height;
  if (projection == Projection::Perspective) {
    if (!window) return glm::perspectiveRH_NO(fovY * kPi / 180.0, aspect, zNear, zFar);
    const ViewWindow& w = *window;
    return glm::frustumRH_NO(w.left * zNear, w.right * zNear, w.bottom * zNear, w.top * zNear, zNear, zFar);
  }
  const ViewWindow w = viewWindow();
  return glm::orthoRH_NO(w.left, w.right, w.bottom, w.top, zNear, zFar);
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
    bad("field of view " + shortNumber(fovY) + " must be in (0, 180) degrees");
  if (projection == Projection::Orthographic && !(orthoHeight > 0.0 && std::isfinite(orthoHeight)))
    bad("orthographic height must be finite and > 0");
  if (window) {
    const ViewWindow& w = *window;
    if (!(std::isfinite(w.left) && std::isfinite(w.right) && std::isfinite(w.bottom) && std::isfinite(w.top)))
      bad("the window's edges must be finite");
    if (!(w.left < w.right && w.bottom < w.top)) bad("the window is empty (left >= right or bottom >= top)");
  }
  if (!std::isfinite(zNear) || !std::isfinite(zFar)) bad("near and far must be finite");
  if (zNear != 0.0 || zFar != 0.0) {
    // Seen from far enough, the scene's depth is below a double's resolution at its distance,
    // and near and far round to one number.
    if (!(zNear < zFar))
      bad("near " + shortNumber(zNear) + " must be less than far " + shortNumber(zFar) +
          (zNear == zFar ? " (the eye is so far from the scene, " + shortNumber(glm::length(lookAt - eye)) +
                               " Å, that its depth range cannot be told apart in double precision: bring the eye closer)"
                         : ""));
    if (projection == Projection::Perspective && !(zNear > 0.0))
      bad("a perspective camera's near " + shortNumber(zNear) + " must be > 0");
  }
}

Camera withDepthRange(Camera camera, std::span<const glm::dvec3> centers, std::span<const double> radii) {
  const SphereCover cover{centers, radii};
  return withDepthRange(camera, {&cover, 1});
}

Camera withDepthRange(Camera camera, std::span<const SphereCover> covers) {
  const glm::dvec3 f = camera.forward();
  constexpr double kInf = std::numeric_limits<double>::infinity();
  double lo = -kInf, hi = kInf;
  for (const SphereCover& cover : covers) {
    double coverLo = kInf, coverHi = -kInf;
    for (std::size_t i = 0; i < cover.centers.size(); ++i) {
      const double z = glm::dot(cover.centers[i] - camera.eye, f);
      coverLo = std::min(coverLo, z - cover.radii[i]), coverHi = std::max(coverHi, z + cover.radii[i]);
    }
    lo = std::max(lo, coverLo), hi = std::min(hi, coverHi);
  }
  if (!(lo <= hi) || !std::isfinite(lo) || !std::isfinite(hi))
    throw std::invalid_argument("camera: no spheres to take a depth range from");
  // A margin of 0.1 % of the depth (and 0.01 Å) keeps the scene off the planes.
  const double pad = 1e-3 * (hi - lo) + 1e-2;
  camera.zNear = lo - pad, camera.zFar = hi + pad;
  if (camera.projection == Projection::Perspective) {
    // A scene wholly behind the eye shows nothing; any range holds that.
    if (camera.zFar <= 0.0) camera.zFar = 1.0;
    camera.zNear = std::max(camera.zNear, 1e-4 * camera.zFar);
  }
  return camera;
}

Camera cameraFromMatrices(int width, int height, const glm::dmat4& view, const glm::dmat4& projection) {
  auto bad = [](const std::string& what) { throw std::invalid_argument("camera: " + what); };
  for (int c = 0; c < 4; ++c)
    for (int r = 0; r < 4; ++r)
      if (!std::isfinite(view[c][r]) || !std::isfinite(projection[c][r])) bad("the matrices must hold finite numbers");
  // The view matrix: a rotation (rows right, up, back) and a translation; bottom row 0 0 0 1.
  constexpr double kTol = 1e-6;
  if (view[0][3] != 0.0 || view[1][3] != 0.0 || view[2][3] != 0.0 || view[3][3] != 1.0)
    bad("view_matrix: its bottom row (elements 3, 7, 11, 15 column-major) must be 0 0 0 1");
  const glm::dvec3 right(view[0][0], view[1][0], view[2][0]), up(view[0][1], view[1][1], view[2][1]),
      back(view[0][2], view[1][2], view[2][2]);
  const double offOrtho = std::max({std::abs(glm::dot(right, up)), std::abs(glm::dot(up, back)),
                                    std::abs(glm::dot(right, back)), std::abs(glm::length(right) - 1.0),
                                    std::abs(glm::length(up) - 1.0), std::abs(glm::length(back) - 1.0)});
  if (!(offOrtho <= kTol) || !(glm::dot(glm::cross(right, up), back) > 0.0))
    bad("view_matrix is not rigid (a rotation and a translation, as glm::lookAt makes): its rotation is off by " +
        std::to_string(offOrtho));
  Camera c;
  c.width = width, c.height = height;
  const glm::dvec3 t(view[3][0], view[3][1], view[3][2]);
  c.eye = -(t.x * right + t.y * up + t.z * back);
  c.up = glm::normalize(up);
  const glm::dmat4& p = projection;
  ViewWindow w;
  if (p[0][3] == 0.0 && p[1][3] == 0.0 && p[2][3] < 0.0 && p[3][3] == 0.0) {
    // Perspective, glFrustum: x' = (2n/(r−l)) x + ((r+l)/(r−l)) z, w' = −z; scaled by −p[2][3].
    const double k = -p[2][3];
    if (p[1][0] != 0.0 || p[3][0] != 0.0 || p[0][1] != 0.0 || p[3][1] != 0.0 || p[0][2] != 0.0 || p[1][2] != 0.0)
      bad("projection_matrix: a perspective projection must have the form of glFrustum (elements 1, 2, 4, 6, 12, 13 "
          "column-major zero)");
    const double a = p[2][2] / k, b = p[3][2] / k, sx = p[0][0] / k, sy = p[1][1] / k;
    c.projection = Projection::Perspective;
    c.zNear = b / (a - 1.0), c.zFar = b / (a + 1.0);
    w = ViewWindow{(p[2][0] / k - 1.0) / sx, (p[2][0] / k + 1.0) / sx, (p[2][1] / k - 1.0) / sy, (p[2][1] / k + 1.0) / sy};
    c.fovY = 2.0 * std::atan(0.5 * (w.top - w.bottom)) * 180.0 / kPi;
  } else if (p[0][3] == 0.0 && p[1][3] == 0.0 && p[2][3] == 0.0 && p[3][3] > 0.0) {
    const double k = p[3][3];
    if (p[1][0] != 0.0 || p[2][0] != 0.0 || p[0][1] != 0.0 || p[2][1] != 0.0 || p[0][2] != 0.0 || p[1][2] != 0.0)
      bad("projection_matrix: an orthographic projection must have the form of glOrtho (elements 1, 2, 4, 6, 8, 9 "
          "column-major zero)");
    const double a = p[2][2] / k, b = p[3][2] / k, sx = p[0][0] / k, sy = p[1][1] / k;
    c.projection = Projection::Orthographic;
    c.zNear = (b + 1.0) / a, c.zFar = (b - 1.0) / a;
    w = ViewWindow{(-1.0 - p[3][0] / k) / sx, (1.0 - p[3][0] / k) / sx, (-1.0 - p[3][1] / k) / sy, (1.0 - p[3][1] / k) / sy};
    c.orthoHeight = w.top - w.bottom;
  } else {
    bad("projection_matrix is neither perspective (bottom row 0 0 −w 0) nor orthographic (bottom row 0 0 0 w)");
  }
  if (!(w.left < w.right && w.bottom < w.top))
    bad("projection_matrix maps an empty or mirrored window (its x or y scale is not positive)");
  // A centred window with square pixels is the ordinary camera (fovY or orthoHeight alone).
  const double aspect = static_cast<double>(width) / height;
  const double scale = std::max(w.right - w.left, w.top - w.bottom);
  const bool centred = std::abs(w.left + w.right) <= 1e-12 * scale && std::abs(w.bottom + w.top) <= 1e-12 * scale &&
                       std::abs((w.right - w.left) / (w.top - w.bottom) - aspect) <= 1e-12 * aspect;
  if (!centred) c.window = w;
  // The look-at point: in the middle of the depth range (GL's float path shifts its
  // coordinates there).
  const glm::dvec3 forward = -glm::normalize(back);
  c.lookAt = c.eye + (std::isfinite(c.zFar) && c.zFar > 0.0 ? 0.5 * (std::max(c.zNear, 0.0) + c.zFar) : 1.0) * forward;
  c.validate();
  return c;
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

std::vector<glm::dvec3> SphereFraming::boxCorners() const {
  std::vector<glm::dvec3> corners;
  if (empty()) return corners;
  for (int k = 0; k < 8; ++k)
    corners.push_back((k & 1 ? hi_[0] : lo_[0]) * right_ + (k & 2 ? hi_[1] : lo_[1]) * up_ +
                      (k & 4 ? hi_[2] : lo_[2]) * forward_);
  return corners;
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

namespace {

nlohmann::json matrixJson(const glm::dmat4& m) {
  nlohmann::json a = nlohmann::json::array();
  for (int c = 0; c < 4; ++c)
    for (int r = 0; r < 4; ++r) a.push_back(m[c][r]);
  return a;
}

}  // namespace

std::string cameraToJson(const Camera& c) {
  nlohmann::json j;
  j["format"] = "surftrace-camera";
  j["version"] = 1;
  j["conventions"] =
      "OpenGL: matrices column-major; the eye looks down -z; clip z in [-1, 1] for depths near..far; pixel (x, y) "
      "counted from the top-left image corner, its centre at (x + 0.5, y + 0.5)";
  j["projection"] = c.projection == Projection::Perspective ? "perspective" : "orthographic";
  j["eye"] = {c.eye.x, c.eye.y, c.eye.z};
  j["look_at"] = {c.lookAt.x, c.lookAt.y, c.lookAt.z};
  j["up"] = {c.up.x, c.up.y, c.up.z};
  j["fov_y_degrees"] = c.fovY;
  j["ortho_height"] = c.orthoHeight;
  j["width"] = c.width;
  j["height"] = c.height;
  j["pixel_centre"] = 0.5;
  if (c.window) j["window"] = {{"left", c.window->left}, {"right", c.window->right}, {"bottom", c.window->bottom},
                               {"top", c.window->top}};
  if (c.hasDepthRange()) {
    j["near"] = c.zNear;
    j["far"] = c.zFar;
    j["view_matrix"] = matrixJson(c.viewMatrix());
    j["projection_matrix"] = matrixJson(c.projectionMatrix());
  }
  return j.dump();
}

namespace {

// A JSON text parsed with every object's keys checked to differ. nlohmann::json keeps the last
// of a key given twice, so `"width": 640, ..., "width": 800` would silently render 800 wide;
// which one the writer meant cannot be known, so a repeated key is an error naming it, where
// it is and both its values.
nlohmann::json parseWithoutRepeatedKeys(const std::string& text) {
  struct Level {
    bool object = false;
    std::string key;  // the member being read
    std::map<std::string, std::string> values;
  };
  std::vector<Level> levels;
  std::string repeated, first, second;  // the first key given twice, its path and values
  std::size_t repeatedLevel = 0;         // levels.size() where it is; 0 once its second value is read
  const auto shown = [](const nlohmann::json& value) {
    std::string s = value.dump();
    return s.size() <= 40 ? s : s.substr(0, 37) + "...";
  };
  const auto member = [&](const std::string& value) {
    if (levels.empty() || !levels.back().object) return;
    if (repeatedLevel == levels.size()) second = value, repeatedLevel = 0;
    levels.back().values.emplace(levels.back().key, value);
  };
  using Event = nlohmann::json::parse_event_t;
  const nlohmann::json::parser_callback_t callback = [&](int, Event event, nlohmann::json& parsed) {
    switch (event) {
      case Event::object_start:
      case Event::array_start:
        levels.push_back({event == Event::object_start, {}, {}});
        break;
      case Event::key: {
        Level& top = levels.back();
        top.key = parsed.get<std::string>();
        if (const auto it = top.values.find(top.key); it != top.values.end() && repeated.empty()) {
          for (std::size_t k = 0; k + 1 < levels.size(); ++k)
            if (levels[k].object) repeated += levels[k].key + ".";
          repeated += top.key;
          first = it->second;
          repeatedLevel = levels.size();
        }
        break;
      }
      case Event::object_end:
      case Event::array_end:
        levels.pop_back();
        member(shown(parsed));
        break;
      case Event::value:
        member(shown(parsed));
        break;
    }
    return true;
  };
  nlohmann::json j;
  try {
    j = nlohmann::json::parse(text, callback);
  } catch (const nlohmann::json::parse_error& e) {
    throw std::invalid_argument(std::string("camera: not JSON: ") + e.what());
  }
  if (!repeated.empty())
    throw std::invalid_argument("camera: the key \"" + repeated + "\" is given twice (" + first + ", then " + second +
                                "): give it once");
  return j;
}

}  // namespace

Camera cameraFromJson(const std::string& text) {
  nlohmann::json j = parseWithoutRepeatedKeys(text);
  if (!j.is_object()) throw std::invalid_argument("camera: expected a JSON object");
  auto at = [&](const char* key) -> const nlohmann::json& {
    if (!j.contains(key)) throw std::invalid_argument(std::string("camera: the key \"") + key + "\" is missing");
    return j.at(key);
  };
  auto number = [&](const nlohmann::json& value, const std::string& key) {
    if (!value.is_number()) throw std::invalid_argument("camera: \"" + key + "\" must be a number");
    return value.get<double>();
  };
  auto whole = [&](const char* key) {
    const nlohmann::json& value = at(key);
    if (!value.is_number_integer()) throw std::invalid_argument(std::string("camera: \"") + key + "\" must be a whole number");
    return value.get<int>();
  };
  auto vec = [&](const char* key) {
    const nlohmann::json& a = at(key);
    if (!a.is_array() || a.size() != 3) throw std::invalid_argument(std::string("camera: \"") + key + "\" must be 3 numbers");
    return glm::dvec3(number(a[0], key), number(a[1], key), number(a[2], key));
  };
  auto matrix = [&](const char* key) {
    const nlohmann::json& a = at(key);
    if (!a.is_array() || a.size() != 16)
      throw std::invalid_argument(std::string("camera: \"") + key + "\" must be 16 numbers (column-major)");
    glm::dmat4 m;
    for (int c = 0; c < 4; ++c)
      for (int r = 0; r < 4; ++r) m[c][r] = number(a[static_cast<std::size_t>(4 * c + r)], key);
    return m;
  };
  if (j.contains("version") && !(j["version"].is_number_integer() && j["version"].get<int>() == 1))
    throw std::invalid_argument("camera: version " + j["version"].dump() + " is not one this surftrace reads (1)");
  const bool hasMatrices = j.contains("view_matrix") || j.contains("projection_matrix");
  if (!j.contains("eye")) {
    if (!hasMatrices)
      throw std::invalid_argument("camera: give eye, look_at, up, projection and fov_y_degrees/ortho_height, or "
                                  "view_matrix and projection_matrix");
    return cameraFromMatrices(whole("width"), whole("height"), matrix("view_matrix"), matrix("projection_matrix"));
  }
  Camera c;
  const nlohmann::json& projection = at("projection");
  if (!projection.is_string() || (projection != "perspective" && projection != "orthographic"))
    throw std::invalid_argument("camera: unknown projection " + projection.dump() + ": use perspective or orthographic");
  c.projection = projection == "perspective" ? Projection::Perspective : Projection::Orthographic;
  c.eye = vec("eye");
  c.lookAt = vec("look_at");
  c.up = vec("up");
  c.fovY = number(at("fov_y_degrees"), "fov_y_degrees");
  c.orthoHeight = number(at("ortho_height"), "ortho_height");
  c.width = whole("width");
  c.height = whole("height");
  if (j.contains("window")) {
    const nlohmann::json& w = j["window"];
    if (!w.is_object()) throw std::invalid_argument("camera: \"window\" must be an object");
    auto edge = [&](const char* key) {
      if (!w.contains(key)) throw std::invalid_argument(std::string("camera: window.") + key + " is missing");
      return number(w.at(key), std::string("window.") + key);
    };
    c.window = ViewWindow{edge("left"), edge("right"), edge("bottom"), edge("top")};
  }
  if (j.contains("near") || j.contains("far")) {
    c.zNear = number(at("near"), "near");
    c.zFar = number(at("far"), "far");
  }
  c.validate();
  if (hasMatrices) {
    // Both forms: the matrices must be the ones the named camera makes (a file edited in one
    // place only would otherwise mean two different views).
    if (!c.hasDepthRange()) throw std::invalid_argument("camera: view_matrix and projection_matrix need near and far");
    const glm::dmat4 view = matrix("view_matrix"), proj = matrix("projection_matrix");
    const glm::dmat4 v = c.viewMatrix(), p = c.projectionMatrix();
    double dv = 0.0, dp = 0.0, sv = 1.0, sp = 0.0;
    for (int col = 0; col < 4; ++col)
      for (int r = 0; r < 4; ++r) {
        dv = std::max(dv, std::abs(view[col][r] - v[col][r])), sv = std::max(sv, std::abs(v[col][r]));
        dp = std::max(dp, std::abs(proj[col][r] - p[col][r])), sp = std::max(sp, std::abs(p[col][r]));
      }
    if (!(dv <= 1e-9 * sv) || !(dp <= 1e-9 * sp))
      throw std::invalid_argument("camera: view_matrix/projection_matrix disagree with eye, look_at, up, the projection "
                                  "and near/far (edit one form only by deleting the other)");
  }
  return c;
}

}  // namespace surftrace::view

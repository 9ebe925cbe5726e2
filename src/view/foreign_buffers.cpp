// Another renderer's depth and normal buffers turned into FrameBuffers along the reference's rays.
#include "view/foreign_buffers.hpp"

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdio>
#include <limits>
#include <stdexcept>
#include <utility>

#include <glm/geometric.hpp>

namespace surftrace::view {
namespace {

constexpr double kInf = std::numeric_limits<double>::infinity();

std::string shortNumber(double v) {
  char text[32];
  std::snprintf(text, sizeof text, "%g", v);
  return text;
}

std::string sizeText(int width, int height) { return std::to_string(width) + "x" + std::to_string(height); }

// The depth channel: the one asked for, else Z, depth or Y, else the only one.
int depthChannelOf(const ImageChannels& image, const std::string& asked) {
  if (!asked.empty()) {
    const int c = image.find(asked);
    if (c < 0)
      throw std::runtime_error(image.path + ": no channel '" + asked + "' (--test-depth-channel); its channels are " +
                               image.nameList());
    return c;
  }
  for (const char* name : {"Z", "depth", "Y"})
    if (const int c = image.find(name); c >= 0) return c;
  if (image.names.size() == 1) return 0;
  throw std::runtime_error(image.path + ": no depth channel among its channels " + image.nameList() +
                           "; expected one named Z, depth or Y, or a one-channel image: name it with --test-depth-channel");
}

// The normal's three channels: N.X N.Y N.Z (SurfTrace's names), R G B, X Y Z, or the only three.
std::array<int, 3> normalChannelsOf(const ImageChannels& image) {
  for (const auto& names : {std::array<const char*, 3>{"N.X", "N.Y", "N.Z"}, std::array<const char*, 3>{"R", "G", "B"},
                            std::array<const char*, 3>{"X", "Y", "Z"}}) {
    const std::array<int, 3> c{image.find(names[0]), image.find(names[1]), image.find(names[2])};
    if (c[0] >= 0 && c[1] >= 0 && c[2] >= 0) return c;
  }
  if (image.names.size() == 3) return {0, 1, 2};
  throw std::runtime_error(image.path + ": no normal channels among its channels " + image.nameList() +
                           "; expected R, G, B (or N.X, N.Y, N.Z, or X, Y, Z)");
}

void checkSize(const ImageChannels& image, const Camera& camera, const char* what) {
  if (image.width != camera.width || image.height != camera.height)
    throw std::runtime_error(image.path + " (" + what + ") is " + sizeText(image.width, image.height) +
                             ", but the reference is " + sizeText(camera.width, camera.height) +
                             ": the buffers must be the reference camera's size");
}

}  // namespace

const char* conventionName(DepthConvention c) {
  switch (c) {
    case DepthConvention::Window: return "window";
    case DepthConvention::ViewZ: return "view-z";
    case DepthConvention::Ray: return "ray";
  }
  return "?";
}
const char* originName(RowOrigin o) { return o == RowOrigin::BottomLeft ? "bottom-left" : "top-left"; }
const char* spaceName(NormalSpace s) { return s == NormalSpace::View ? "view" : "world"; }
const char* encodingName(NormalEncoding e) { return e == NormalEncoding::Signed ? "signed" : "unorm"; }

namespace {

// The value of `values` whose name (by `nameOf`) is `name`; `what` names the setting in the error.
template <class Enum, std::size_t N>
Enum named(const std::string& name, const char* what, const Enum (&values)[N], const char* (*nameOf)(Enum)) {
  std::string known;
  for (const Enum v : values) {
    if (name == nameOf(v)) return v;
    known += std::string(known.empty() ? "" : ", ") + nameOf(v);
  }
  throw std::invalid_argument("unknown " + std::string(what) + " '" + name + "': expected one of " + known);
}

}  // namespace

DepthConvention depthConventionNamed(const std::string& name) {
  static constexpr DepthConvention kAll[] = {DepthConvention::Window, DepthConvention::ViewZ, DepthConvention::Ray};
  return named(name, "depth convention", kAll, conventionName);
}
RowOrigin rowOriginNamed(const std::string& name) {
  static constexpr RowOrigin kAll[] = {RowOrigin::BottomLeft, RowOrigin::TopLeft};
  return named(name, "row origin", kAll, originName);
}
NormalSpace normalSpaceNamed(const std::string& name) {
  static constexpr NormalSpace kAll[] = {NormalSpace::View, NormalSpace::World};
  return named(name, "normal space", kAll, spaceName);
}
NormalEncoding normalEncodingNamed(const std::string& name) {
  static constexpr NormalEncoding kAll[] = {NormalEncoding::Signed, NormalEncoding::Unorm};
  return named(name == "snorm" ? std::string("signed") : name, "normal encoding", kAll, encodingName);
}

DepthToRay::DepthToRay(const Camera& camera, DepthConvention convention) : frame_(camera.frame()), convention_(convention) {
  if (convention != DepthConvention::Window) return;
  if (!camera.hasDepthRange())
    throw std::invalid_argument("the reference's camera has no near and far (near " + shortNumber(camera.zNear) +
                                ", far " + shortNumber(camera.zFar) +
                                "): window depth needs the depth range it was written for; re-render the reference "
                                "with this SurfTrace (every image records them), or pass --depth-convention view-z or ray");
  const glm::dmat4 p = camera.projectionMatrix();
  p22_ = p[2][2], p32_ = p[3][2], p23_ = p[2][3], p33_ = p[3][3];
}

bool DepthToRay::background(double value) const {
  if (std::isnan(value)) return false;
  if (std::isinf(value)) return true;
  return convention_ == DepthConvention::Window ? value >= 1.0 : value <= 0.0;
}

double DepthToRay::viewZ(int x, int y, double value) const {
  switch (convention_) {
    case DepthConvention::Window: {
      // glDepthRange(0, 1): ndc z = 2 d − 1 = (p22 z + p32) / (p23 z + p33) for view z; solved for z.
      const double ndc = 2.0 * value - 1.0;
      return -(p32_ - ndc * p33_) / (ndc * p23_ - p22_);
    }
    case DepthConvention::ViewZ: return value;
    case DepthConvention::Ray: {
      const Ray r = frame_.ray(x + 0.5, y + 0.5);
      return glm::dot(r.org - frame_.eye, frame_.forward) + value * glm::dot(r.dir, frame_.forward);
    }
  }
  return kInf;
}

double DepthToRay::rayDistance(int x, int y, double value) const {
  if (background(value)) return kInf;
  if (std::isnan(value)) return value;
  if (convention_ == DepthConvention::Ray) return value;
  // The ray leaves org (the eye, or its plane) with unit dir: its view z grows by dir·forward per Å.
  const Ray r = frame_.ray(x + 0.5, y + 0.5);
  return (viewZ(x, y, value) - glm::dot(r.org - frame_.eye, frame_.forward)) / glm::dot(r.dir, frame_.forward);
}

ForeignFrame foreignFrame(const ImageChannels& depth, const ImageChannels* normals, const ForeignBufferOptions& options,
                          const Camera& camera) {
  checkSize(depth, camera, "depth");
  if (normals) checkSize(*normals, camera, "normals");
  ForeignFrame out;
  const int dc = depthChannelOf(depth, options.depthChannel);
  out.depthChannel = depth.names[static_cast<std::size_t>(dc)];
  if (options.depthConvention != DepthConvention::Window && !depth.isFloat(dc))
    throw std::runtime_error(depth.path + ": channel " + out.depthChannel + " holds " + depth.types[static_cast<std::size_t>(dc)] +
                             " values, read as [0, 1]; " + conventionName(options.depthConvention) +
                             " depth is in Å and needs a float channel (only window depth may be stored as integers)");
  const DepthToRay toRay(camera, options.depthConvention);
  std::array<int, 3> nc{};
  if (normals) nc = normalChannelsOf(*normals);
  const Camera::Frame f = camera.frame();
  const glm::dvec3 back = -f.forward;

  FrameBuffers& frame = out.frame;
  frame.reset(camera.width, camera.height);
  out.carried = TestChannels{normals != nullptr, false, false, false};
  const int w = camera.width, h = camera.height;
  for (int row = 0; row < h; ++row) {
    // The buffer's row `row` is image row y (row 0 at the top).
    const int y = options.origin == RowOrigin::TopLeft ? row : h - 1 - row;
    for (int x = 0; x < w; ++x) {
      const std::size_t src = static_cast<std::size_t>(row) * static_cast<std::size_t>(w) + static_cast<std::size_t>(x);
      const std::size_t p = static_cast<std::size_t>(y) * static_cast<std::size_t>(w) + static_cast<std::size_t>(x);
      const double value = depth.at(src, dc);
      if (toRay.background(value)) continue;
      frame.depth[p] = static_cast<float>(toRay.rayDistance(x, y, value));
      frame.viewZ[p] = static_cast<float>(toRay.viewZ(x, y, value));
      if (!normals) continue;
      glm::dvec3 n(normals->at(src, nc[0]), normals->at(src, nc[1]), normals->at(src, nc[2]));
      if (options.normalEncoding == NormalEncoding::Unorm) n = 2.0 * n - 1.0;
      if (options.negateNormals) n = -n;
      if (options.normalSpace == NormalSpace::View) n = n.x * f.right + n.y * f.up + n.z * back;
      for (int k = 0; k < 3; ++k) frame.normal[3 * p + static_cast<std::size_t>(k)] = static_cast<float>(n[k]);
    }
  }
  return out;
}

std::string impossibleDepths(const ImageChannels& depth, const ForeignBufferOptions& options, const Camera& camera,
                             double nearest, double farthest) {
  const int dc = depthChannelOf(depth, options.depthChannel);
  const DepthConvention convention = options.depthConvention;
  // What the convention holds, with room for float rounding.
  double lo = 0.0, hi = 1.0;
  std::string holds = "window depth is in [0, 1] (background 1.0)";
  if (convention != DepthConvention::Window) {
    if (!camera.hasDepthRange()) return "";
    lo = std::min(camera.zNear, nearest) * (1.0 - 1e-4);
    hi = std::max(camera.zFar, farthest);
    if (convention == DepthConvention::Ray && camera.projection == Projection::Perspective) {
      // The widest ray leaves through a corner: it reaches the far plane after far / cos.
      const Camera::Frame f = camera.frame();
      double cosine = 1.0;
      for (const auto& [sx, sy] : {std::pair{0.0, 0.0}, std::pair{1.0, 0.0}, std::pair{0.0, 1.0}, std::pair{1.0, 1.0}})
        cosine = std::min(cosine, glm::dot(f.ray(sx * camera.width, sy * camera.height).dir, f.forward));
      hi /= cosine;
    }
    hi *= 1.0 + 1e-4;
    holds = std::string(conventionName(convention)) + " depth lies between the reference camera's near " +
            shortNumber(camera.zNear) + " and far " + shortNumber(camera.zFar) + " Å (background +inf or <= 0)";
  }
  std::size_t count = 0;
  double vMin = kInf, vMax = -kInf;
  for (std::size_t p = 0; p < depth.pixels(); ++p) {
    const double v = depth.at(p, dc);
    if (!std::isfinite(v)) continue;  // +inf: background; NaN: counted by compare
    const bool bad = convention == DepthConvention::Window ? (v < 0.0 || v > 1.0) : (v > 0.0 && (v < lo || v > hi));
    if (!bad) continue;
    ++count;
    vMin = std::min(vMin, v), vMax = std::max(vMax, v);
  }
  if (count == 0) return "";
  return depth.path + ": channel " + depth.names[static_cast<std::size_t>(dc)] + " holds " + shortNumber(vMin) +
         (vMax > vMin ? " to " + shortNumber(vMax) : std::string()) + " in " + std::to_string(count) + " of " +
         std::to_string(depth.pixels()) + " px, which --depth-convention " + conventionName(convention) +
         " cannot: " + holds;
}

}  // namespace surftrace::view

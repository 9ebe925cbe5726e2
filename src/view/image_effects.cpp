// Image-space effects on a rendered frame (image_effects.hpp).
#include "view/image_effects.hpp"

#include <algorithm>
#include <cmath>
#include <limits>
#include <stdexcept>

#include <nlohmann/json.hpp>
#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>

namespace surftrace::view {
namespace {

constexpr float kInf = std::numeric_limits<float>::infinity();
constexpr double kPi = 3.14159265358979323846;
// σ as a fraction of the image height stays below 0.1 (3σ already spans 30 % of the image), so
// that no σ once given in pixels (0.1 and up) is silently read as a fraction.
constexpr double kMaxSigmaFraction = 0.1;

std::size_t index(const FrameBuffers& f, int x, int y) {
  return static_cast<std::size_t>(y) * static_cast<std::size_t>(f.width) + static_cast<std::size_t>(x);
}

// Rows [0, height) in parallel; each task gets whole rows.
template <class Fn>
void forRows(int height, Fn&& fn) {
  tbb::parallel_for(tbb::blocked_range<int>(0, height, 8), [&](const tbb::blocked_range<int>& r) {
    for (int y = r.begin(); y != r.end(); ++y) fn(y);
  });
}

// Pixels [0, n) in parallel, in blocks.
template <class Fn>
void forPixels(std::size_t n, Fn&& fn) {
  tbb::parallel_for(tbb::blocked_range<std::size_t>(0, n, 16384), [&](const tbb::blocked_range<std::size_t>& r) {
    for (std::size_t p = r.begin(); p != r.end(); ++p) fn(p);
  });
}

// The view depth with misses at +inf: the farthest value in a window is then +inf whenever
// the window holds a miss, so one max filter finds both kinds of silhouette.
std::vector<float> depthWithMissesFar(const FrameBuffers& f) {
  std::vector<float> z(f.pixels());
  forPixels(z.size(), [&](std::size_t p) { z[p] = f.kind[p] != 0 ? f.viewZ[p] : kInf; });
  return z;
}

// Max over the (2r+1)² window clipped to the image, as two 1-D passes (max is exact, so the
// separable filter equals the 2-D one bit for bit).
std::vector<float> maxFilter(const std::vector<float>& in, int w, int h, int r) {
  std::vector<float> rows(in.size()), out(in.size());
  forRows(h, [&](int y) {
    const float* src = &in[static_cast<std::size_t>(y) * static_cast<std::size_t>(w)];
    float* dst = &rows[static_cast<std::size_t>(y) * static_cast<std::size_t>(w)];
    // Offset by offset over the whole row (the loop the compiler vectorises), not pixel by pixel.
    std::copy(src, src + w, dst);
    for (int k = 1; k <= r && k < w; ++k)
      for (int x = 0; x + k < w; ++x) {
        dst[x] = std::max(dst[x], src[x + k]);
        dst[x + k] = std::max(dst[x + k], src[x]);
      }
  });
  forRows(h, [&](int y) {
    float* dst = &out[static_cast<std::size_t>(y) * static_cast<std::size_t>(w)];
    std::fill(dst, dst + w, -kInf);
    for (int k = std::max(0, y - r); k <= std::min(h - 1, y + r); ++k) {
      const float* src = &rows[static_cast<std::size_t>(k) * static_cast<std::size_t>(w)];
      for (int x = 0; x < w; ++x) dst[x] = std::max(dst[x], src[x]);
    }
  });
  return out;
}

// One pass of the Gaussian along x or y, offset by offset over whole rows (vectorised); the
// window is clipped to the image.
void gaussianPass(const std::vector<float>& in, std::vector<float>& out, int w, int h, const std::vector<float>& g,
                  bool alongX) {
  const int r = static_cast<int>(g.size()) - 1;
  forRows(h, [&](int y) {
    float* dst = &out[static_cast<std::size_t>(y) * static_cast<std::size_t>(w)];
    if (alongX) {
      const float* src = &in[static_cast<std::size_t>(y) * static_cast<std::size_t>(w)];
      for (int x = 0; x < w; ++x) dst[x] = g[0] * src[x];
      for (int k = 1; k <= r && k < w; ++k) {
        const float gk = g[static_cast<std::size_t>(k)];
        for (int x = 0; x + k < w; ++x) dst[x] += gk * src[x + k];
        for (int x = k; x < w; ++x) dst[x] += gk * src[x - k];
      }
    } else {
      std::fill(dst, dst + w, 0.0f);
      for (int k = std::max(0, y - r); k <= std::min(h - 1, y + r); ++k) {
        const float gk = g[static_cast<std::size_t>(std::abs(k - y))];
        const float* src = &in[static_cast<std::size_t>(k) * static_cast<std::size_t>(w)];
        for (int x = 0; x < w; ++x) dst[x] += gk * src[x];
      }
    }
  });
}

// The Gaussian's weight inside the image at each position of a line of n pixels.
std::vector<float> weightInside(int n, const std::vector<float>& g) {
  const int r = static_cast<int>(g.size()) - 1;
  std::vector<float> sum(static_cast<std::size_t>(n));
  for (int i = 0; i < n; ++i) {
    float s = 0.0f;
    for (int k = std::max(0, i - r); k <= std::min(n - 1, i + r); ++k) s += g[static_cast<std::size_t>(std::abs(k - i))];
    sum[static_cast<std::size_t>(i)] = s;
  }
  return sum;
}

}  // namespace

void ImageEffects::validate() const {
  if (lineWidth < 1) throw std::invalid_argument("silhouette width must be at least 1 pixel");
  if (!(silhouetteJump >= 0.0) || !std::isfinite(silhouetteJump))
    throw std::invalid_argument("silhouette depth jump must be finite and >= 0 Å");
  if (!(creaseAngle >= 0.0 && creaseAngle < 180.0)) throw std::invalid_argument("crease angle must be in [0, 180) degrees");
  if (!(darkeningSigma > 0.0 && darkeningSigma < kMaxSigmaFraction))
    throw std::invalid_argument("depth-darkening sigma must be in (0, 0.1): a fraction of the image height (for pixels, "
                                "give the sigma in pixels instead)");
  if (darkeningSigmaPx && !(*darkeningSigmaPx > 0.0 && *darkeningSigmaPx <= 256.0))
    throw std::invalid_argument("depth-darkening sigma in pixels must be in (0, 256]");
  if (!(darkeningStrength >= 0.0) || !std::isfinite(darkeningStrength))
    throw std::invalid_argument("depth-darkening strength must be finite and >= 0");
  if (darkeningRange && !(*darkeningRange > 0.0 && std::isfinite(*darkeningRange)))
    throw std::invalid_argument("depth-darkening range must be finite and > 0 Å");
  if (!(depthCueStrength >= 0.0 && depthCueStrength <= 1.0)) throw std::invalid_argument("depth-cue strength must be in [0, 1]");
  if (depthCueStart && depthCueEnd && !(*depthCueEnd > *depthCueStart))
    throw std::invalid_argument("depth-cue end must lie beyond its start");
}

std::string ImageEffects::json(const Camera& camera) const {
  nlohmann::json j = nlohmann::json::object();
  if (silhouettes) j["silhouettes"] = {{"depth_jump", silhouetteJump}};
  if (lines())
    j["lines"] = {{"width_px", lineWidth}, {"color", {lineColor.x, lineColor.y, lineColor.z}}, {"crease_angle_degrees", creaseAngle}};
  if (depthDarkening) {
    nlohmann::json dark = {{"sigma_px", darkeningSigmaPixels(camera.height)}, {"strength", darkeningStrength}};
    if (!darkeningSigmaPx) dark["sigma_image_height"] = darkeningSigma;
    if (camera.hasDepthRange()) {
      dark["background_depth"] = camera.zFar;
      if (!darkeningRange) dark["range"] = camera.zFar - camera.zNear;
    } else {
      dark["background_depth"] = "the farthest hit";
      if (!darkeningRange) dark["range"] = "the frame's hits";
    }
    if (darkeningRange) dark["range"] = *darkeningRange;
    j["depth_darkening"] = dark;
  }
  if (depthCue) {
    nlohmann::json cue = {{"strength", depthCueStrength}};
    const double start = depthCueStart ? *depthCueStart : camera.zNear, end = depthCueEnd ? *depthCueEnd : camera.zFar;
    if (end > start) {
      cue["start"] = start;
      cue["end"] = end;
    } else {
      cue["range"] = "the frame's hits";
    }
    j["depth_cue"] = cue;
  }
  return j.dump();
}

std::vector<unsigned char> silhouetteMask(const FrameBuffers& f, int width, double jump) {
  const std::vector<float> z = depthWithMissesFar(f);
  const std::vector<float> far = maxFilter(z, f.width, f.height, width);
  std::vector<unsigned char> mask(f.pixels(), 0);
  forPixels(mask.size(), [&](std::size_t p) {
    mask[p] = f.kind[p] != 0 && static_cast<double>(far[p]) - static_cast<double>(z[p]) > jump;
  });
  return mask;
}

std::vector<unsigned char> creaseMask(const FrameBuffers& f, int width, double jump, double angleDegrees) {
  std::vector<unsigned char> mask(f.pixels(), 0);
  if (angleDegrees <= 0.0) return mask;
  const float cosLimit = static_cast<float>(std::cos(angleDegrees * kPi / 180.0));
  forRows(f.height, [&](int y) {
    for (int x = 0; x < f.width; ++x) {
      const std::size_t p = index(f, x, y);
      if (f.kind[p] == 0) continue;
      const float* np = &f.normal[3 * p];
      bool crease = false;
      for (int qy = std::max(0, y - width); qy <= std::min(f.height - 1, y + width) && !crease; ++qy)
        for (int qx = std::max(0, x - width); qx <= std::min(f.width - 1, x + width) && !crease; ++qx) {
          const std::size_t q = index(f, qx, qy);
          if (f.kind[q] == 0 || std::abs(static_cast<double>(f.viewZ[q]) - static_cast<double>(f.viewZ[p])) > jump) continue;
          const float* nq = &f.normal[3 * q];
          crease = np[0] * nq[0] + np[1] * nq[1] + np[2] * nq[2] < cosLimit;
        }
      mask[p] = crease;
    }
  });
  return mask;
}

std::vector<float> depthUnsharpMask(const FrameBuffers& f, double sigma, double backgroundDepth) {
  const int w = f.width, h = f.height;
  const std::size_t n = f.pixels();
  const auto far = static_cast<float>(backgroundDepth);
  // Depths relative to the nearest pixel: a constant buffer becomes exactly zero, so its ΔD is
  // exactly zero (no rounding of c·Σg/Σg), and float keeps more digits of the relief.
  float zRef = far;
  for (std::size_t p = 0; p < n; ++p)
    if (f.kind[p] != 0) zRef = std::min(zRef, f.viewZ[p]);
  std::vector<float> num(n);
  for (std::size_t p = 0; p < n; ++p) num[p] = (f.kind[p] != 0 ? f.viewZ[p] : far) - zRef;
  const int r = std::max(1, static_cast<int>(std::ceil(3.0 * sigma)));
  std::vector<float> g(static_cast<std::size_t>(r) + 1);
  for (int k = 0; k <= r; ++k) g[static_cast<std::size_t>(k)] = static_cast<float>(std::exp(-0.5 * k * k / (sigma * sigma)));
  // Normalised by the weight inside the image, so that the border does not count as depth 0;
  // that weight is separable too: the product of the two lines' weights.
  std::vector<float> numX(n), numXY(n);
  gaussianPass(num, numX, w, h, g, true);
  gaussianPass(numX, numXY, w, h, g, false);
  const std::vector<float> sumX = weightInside(w, g), sumY = weightInside(h, g);
  std::vector<float> delta(n);
  forRows(h, [&](int y) {
    const std::size_t row = static_cast<std::size_t>(y) * static_cast<std::size_t>(w);
    const float inverseY = 1.0f / sumY[static_cast<std::size_t>(y)];
    for (int x = 0; x < w; ++x) {
      const std::size_t p = row + static_cast<std::size_t>(x);
      delta[p] = numXY[p] * (inverseY / sumX[static_cast<std::size_t>(x)]) - num[p];
    }
  });
  return delta;
}

double ImageEffects::darkeningSigmaPixels(int imageHeight) const {
  return darkeningSigmaPx ? *darkeningSigmaPx : darkeningSigma * imageHeight;
}

void sceneDepthRange(const Camera& camera, const FrameBuffers& f, double& nearest, double& farthest) {
  nearest = camera.zNear, farthest = camera.zFar;
  if (camera.hasDepthRange()) return;
  nearest = kInf, farthest = -kInf;
  for (std::size_t p = 0; p < f.pixels(); ++p)
    if (f.kind[p] != 0)
      nearest = std::min(nearest, static_cast<double>(f.viewZ[p])), farthest = std::max(farthest, static_cast<double>(f.viewZ[p]));
}

void darkeningDepths(const ImageEffects& e, const Camera& camera, const FrameBuffers& f, double& background, double& range) {
  double nearest = 0, farthest = 0;
  sceneDepthRange(camera, f, nearest, farthest);
  // No hit and no camera range: nothing to darken, any finite depths do.
  if (!(farthest >= nearest)) nearest = farthest = 0.0;
  background = farthest;
  range = e.darkeningRange ? *e.darkeningRange : farthest - nearest;
  // One depth only (a flat frame without a camera range): ΔD is 0 wherever a hit is, 1 Å keeps
  // the division finite.
  if (!(range > 0.0)) range = 1.0;
}

void depthCueRange(const ImageEffects& e, const Camera& camera, const FrameBuffers& f, double& start, double& end) {
  sceneDepthRange(camera, f, start, end);
  if (e.depthCueStart) start = *e.depthCueStart;
  if (e.depthCueEnd) end = *e.depthCueEnd;
}

void applyImageEffects(FrameBuffers& f, const ImageEffects& e, const Camera& camera, const glm::vec3& background) {
  if (!e.any() || f.pixels() == 0) return;
  const std::size_t n = f.pixels();
  if (e.depthDarkening) {
    double behind = 0, range = 1;
    darkeningDepths(e, camera, f, behind, range);
    const std::vector<float> delta = depthUnsharpMask(f, e.darkeningSigmaPixels(f.height), behind);
    const auto lambda = static_cast<float>(e.darkeningStrength / range);
    forPixels(n, [&](std::size_t p) {
      if (delta[p] < 0.0f)
        for (int c = 0; c < 3; ++c) f.rgba[4 * p + c] = std::max(0.0f, f.rgba[4 * p + c] + lambda * delta[p]);
    });
  }
  if (e.depthCue) {
    double start = 0, end = 0;
    depthCueRange(e, camera, f, start, end);
    const double span = end > start ? end - start : 1.0;
    forPixels(n, [&](std::size_t p) {
      if (f.kind[p] == 0) return;
      const auto fog = static_cast<float>(e.depthCueStrength * std::clamp((f.viewZ[p] - start) / span, 0.0, 1.0));
      for (int c = 0; c < 3; ++c) f.rgba[4 * p + c] = (1.0f - fog) * f.rgba[4 * p + c] + fog * background[c];
    });
  }
  if (e.lines()) {
    std::vector<unsigned char> mask = e.silhouettes ? silhouetteMask(f, e.lineWidth, e.silhouetteJump)
                                                    : std::vector<unsigned char>(n, 0);
    if (e.creaseAngle > 0.0) {
      const std::vector<unsigned char> crease = creaseMask(f, e.lineWidth, e.silhouetteJump, e.creaseAngle);
      for (std::size_t p = 0; p < n; ++p) mask[p] |= crease[p];
    }
    forPixels(n, [&](std::size_t p) {
      if (!mask[p]) return;
      for (int c = 0; c < 3; ++c) f.rgba[4 * p + c] = e.lineColor[c];
      f.rgba[4 * p + 3] = 1.0f;
    });
  }
}

}  // namespace surftrace::view

// Image-space effects on a rendered frame (image_effects.hpp).
#include "view/image_effects.hpp"

#include <algorithm>
#include <cmath>
#include <limits>
#include <stdexcept>

#include <glm/geometric.hpp>
#include <glm/vec2.hpp>
#include <nlohmann/json.hpp>
#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>

#include "view/srgb.hpp"

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

// The view depth with misses at +inf: a neighbour that is a miss then lies deeper than any
// jump, so one comparison finds both kinds of silhouette.
std::vector<float> depthWithMissesFar(const FrameBuffers& f) {
  std::vector<float> z(f.pixels());
  forPixels(z.size(), [&](std::size_t p) { z[p] = f.kind[p] != 0 ? f.viewZ[p] : kInf; });
  return z;
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
  if (!(lineWidth > 0.0 && lineWidth <= 0.25))
    throw std::invalid_argument("line width must be in (0, 0.25]: a fraction of the image height (0.002 is 2 px at 1000 px)");
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
    j["lines"] = {{"width_of_image_height", lineWidth}, {"color", {lineColor.x, lineColor.y, lineColor.z}}, {"crease_angle_degrees", creaseAngle}};
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

namespace {

// A pixel's centre in image coordinates (x right, y down).
glm::dvec2 centreOf(int x, int y) { return {x + 0.5, y + 0.5}; }

// 1 − |n × d| and |n × d| for unit n and d, without the cancellation of 1 − sqrt(1 − c²) near the
// rim, where (n·d)² is tiny and 1 − g is all that matters.
void rimMeasure(const glm::dvec3& n, const glm::dvec3& d, double& g, double& oneMinusG) {
  const double c = glm::dot(n, d), s = std::max(0.0, 1.0 - c * c);
  g = std::sqrt(s);
  oneMinusG = c * c / (1.0 + g);
}

// The overlap of a pixel's extent [d − ½, d + ½] across an edge with the band [0, w] inside it.
float bandOverlap(double d, double w) {
  return static_cast<float>(std::max(0.0, std::min(d + 0.5, w) - std::max(d - 0.5, 0.0)));
}

// One edge pixel's estimate of the jump: the point `at` on it and the unit image direction
// `out` across it (from the near surface to what lies beyond).
struct EdgeEstimate {
  std::size_t pixel;
  glm::dvec2 at, out;
};

}  // namespace

std::vector<float> silhouetteCoverage(const FrameBuffers& f, const Camera& camera, double widthPx, double jump) {
  const int w = f.width, h = f.height;
  std::vector<float> cover(f.pixels(), 0.0f);
  if (f.pixels() == 0 || !(widthPx > 0.0)) return cover;
  const std::vector<float> z = depthWithMissesFar(f);
  const Camera::Frame view = camera.frame();
  auto normalAt = [&](std::size_t p) { return glm::dvec3(f.normal[3 * p], f.normal[3 * p + 1], f.normal[3 * p + 2]); };
  auto rayOf = [&](std::size_t p) {
    return view.ray(static_cast<double>(p % static_cast<std::size_t>(w)) + 0.5, static_cast<double>(p / static_cast<std::size_t>(w)) + 0.5);
  };
  auto rayAt = [&](int x, int y) { return view.ray(x + 0.5, y + 0.5).dir; };
  // Pixel q's view depth less that of the tangent plane of pixel p's hit along q's ray (Å).
  auto offPlane = [&](std::size_t p, std::size_t q) {
    const Ray rp = rayOf(p), rq = rayOf(q);
    const glm::dvec3 n = normalAt(p), at = rp.org + static_cast<double>(f.depth[p]) * rp.dir;
    const double facing = glm::dot(n, rq.dir);
    if (std::abs(facing) < 1e-9) return HUGE_VAL;
    const double t = glm::dot(n, at - rq.org) / facing;
    return static_cast<double>(f.viewZ[q]) - t * glm::dot(rq.dir, view.forward);
  };
  // q lies beyond p: a miss, or deeper by more than the jump where the two hits are not one
  // surface. Near the rim of a smooth surface the depth changes by more than any jump from one
  // pixel to the next, and it is still one surface: its normals differ little, and one of the
  // two tangent planes, or their mean (the trapezoid rule, whose errors of a curved surface
  // cancel), carries on to the other hit within the jump or ¾ of the depth change: towards a
  // rim the slope grows as 1/√(distance), so no fixed tolerance fits every pixel size, and the
  // inner hit's plane misses the outer one by at most ½ the change on a sphere (exactly ½ at
  // the rim itself); two layers, however close their normals, lie off both planes by the whole
  // change, on opposite sides.
  auto beyond = [&](std::size_t p, std::size_t q) {
    const double rise = static_cast<double>(z[q]) - static_cast<double>(z[p]);
    if (!(rise > jump)) return false;
    if (f.kind[q] == 0 || glm::dot(normalAt(p), normalAt(q)) < 0.5) return true;
    const double ep = offPlane(p, q), eq = offPlane(q, p);
    return std::min({std::abs(ep), std::abs(eq), 0.5 * std::abs(ep - eq)}) > std::max(jump, 0.75 * rise);
  };

  // The edge pixels and their estimates, row by row in parallel, then gathered in row order.
  std::vector<std::vector<EdgeEstimate>> rows(static_cast<std::size_t>(h));
  forRows(h, [&](int y) {
    for (int x = 0; x < w; ++x) {
      const std::size_t p = index(f, x, y);
      if (f.kind[p] == 0) continue;
      glm::dvec2 toBeyond(0.0), steps[8];
      int count = 0;
      for (int dy = -1; dy <= 1; ++dy)
        for (int dx = -1; dx <= 1; ++dx) {
          const int qx = x + dx, qy = y + dy;
          if ((dx == 0 && dy == 0) || qx < 0 || qy < 0 || qx >= w || qy >= h || !beyond(p, index(f, qx, qy))) continue;
          steps[count++] = glm::dvec2(dx, dy);
          toBeyond += glm::normalize(glm::dvec2(dx, dy));
        }
      if (count == 0) continue;
      const glm::dvec2 c0 = centreOf(x, y);
      // The reach of the pixels beyond along a direction: a straight jump lies before it.
      auto reach = [&](const glm::dvec2& u) {
        double r = 0.0;
        for (int k = 0; k < count; ++k) r = std::max(r, glm::dot(steps[k], u));
        return r;
      };
      // A rim curves away from its tangent: it may pass beyond a diagonal neighbour's centre
      // along u, but not beyond the farthest neighbour beyond.
      double farthest = 0.0;
      for (int k = 0; k < count; ++k) farthest = std::max(farthest, glm::length(steps[k]));
      EdgeEstimate e{p, c0, glm::length(toBeyond) > 1e-9 ? glm::normalize(toBeyond) : glm::normalize(steps[0])};
      double offset = 0.5 * reach(e.out);
      // The rim: the normal's image direction points across it, and g reaches 1 on it.
      const glm::dvec3 n0 = normalAt(p);
      const glm::dvec2 across(glm::dot(n0, view.right), -glm::dot(n0, view.up));
      if (glm::length(across) > 0.5) {
        const glm::dvec2 u = glm::normalize(across);
        const double limit = reach(u) > 0.0 ? farthest : 0.0;
        // The inner neighbour: the pixel one step against u.
        const int ix = static_cast<int>(std::floor(c0.x - u.x)), iy = static_cast<int>(std::floor(c0.y - u.y));
        if (limit > 0.0 && ix >= 0 && iy >= 0 && ix < w && iy < h && (ix != x || iy != y)) {
          const std::size_t p1 = index(f, ix, iy);
          if (f.kind[p1] != 0 && !beyond(p, p1) && !beyond(p1, p) && glm::dot(normalAt(p1), n0) > 0.5) {
            double g0 = 0, rest0 = 0, g1 = 0, rest1 = 0;
            rimMeasure(n0, rayAt(x, y), g0, rest0);
            rimMeasure(normalAt(p1), rayAt(ix, iy), g1, rest1);
            const double run = glm::dot(c0 - centreOf(ix, iy), u), slope = (rest1 - rest0) / run;
            if (slope > 0.0 && rest0 <= slope * limit) e.out = u, offset = rest0 / slope;
          }
        }
      }
      e.at = c0 + offset * e.out;
      rows[static_cast<std::size_t>(y)].push_back(e);
    }
  });

  // Each edge draws its band into the pixels around it; a pixel takes the largest coverage.
  // Pixels whose centre lies inside the band but beyond the jump (a miss, or deeper) belong to
  // another part of the picture, where the straight edge's extension is wrong: they get none.
  const int reachPx = static_cast<int>(std::ceil(widthPx + 1.5));
  for (const std::vector<EdgeEstimate>& row : rows)
    for (const EdgeEstimate& e : row) {
      const int x0 = static_cast<int>(e.pixel % static_cast<std::size_t>(w)), y0 = static_cast<int>(e.pixel / static_cast<std::size_t>(w));
      const glm::dvec2 along(-e.out.y, e.out.x);
      // Half the length of edge one pixel stands for.
      const double halfLength = 0.5 * (std::abs(along.x) + std::abs(along.y));
      for (int qy = std::max(0, y0 - reachPx); qy <= std::min(h - 1, y0 + reachPx); ++qy)
        for (int qx = std::max(0, x0 - reachPx); qx <= std::min(w - 1, x0 + reachPx); ++qx) {
          const glm::dvec2 v = centreOf(qx, qy) - e.at;
          if (std::abs(glm::dot(v, along)) > halfLength + 0.5) continue;
          const double inside = -glm::dot(v, e.out);
          const std::size_t q = index(f, qx, qy);
          if (inside > 0.0 && (f.kind[q] == 0 || beyond(e.pixel, q))) continue;
          cover[q] = std::max(cover[q], bandOverlap(inside, widthPx));
        }
    }
  return cover;
}

std::vector<float> creaseCoverage(const FrameBuffers& f, double widthPx, double jump, double angleDegrees,
                                  double minLengthPx) {
  const std::size_t n = f.pixels();
  std::vector<float> cover(n, 0.0f);
  if (angleDegrees <= 0.0 || n == 0) return cover;
  // The window's half-width: a crease between two pixels marks r pixels on either side, a band
  // about widthPx wide like a silhouette's.
  const int r = creaseWindowRadius(widthPx);
  // The largest turn of the normal within the window, as the smallest cosine.
  std::vector<float> minCos(n, 1.0f);
  forRows(f.height, [&](int y) {
    for (int x = 0; x < f.width; ++x) {
      const std::size_t p = index(f, x, y);
      if (f.kind[p] == 0) continue;
      const float* np = &f.normal[3 * p];
      float lowest = 1.0f;
      for (int qy = std::max(0, y - r); qy <= std::min(f.height - 1, y + r); ++qy)
        for (int qx = std::max(0, x - r); qx <= std::min(f.width - 1, x + r); ++qx) {
          const std::size_t q = index(f, qx, qy);
          if (f.kind[q] == 0 || std::abs(static_cast<double>(f.viewZ[q]) - static_cast<double>(f.viewZ[p])) > jump) continue;
          const float* nq = &f.normal[3 * q];
          lowest = std::min(lowest, np[0] * nq[0] + np[1] * nq[1] + np[2] * nq[2]);
        }
      minCos[p] = lowest;
    }
  });
  const double strong = angleDegrees, weak = kCreaseWeakRatio * angleDegrees;
  const float strongCos = static_cast<float>(std::cos(strong * kPi / 180.0)),
              weakCos = static_cast<float>(std::cos(weak * kPi / 180.0));
  // Connected pieces of the weak pixels (8-neighbours), each kept when it holds a strong pixel
  // and is long enough.
  std::vector<unsigned char> seen(n, 0);
  std::vector<std::size_t> piece, stack;
  for (std::size_t start = 0; start < n; ++start) {
    if (seen[start] || !(minCos[start] < weakCos)) continue;
    piece.clear();
    stack.assign(1, start);
    seen[start] = 1;
    bool seeded = false;
    int x0 = f.width, x1 = -1, y0 = f.height, y1 = -1;
    while (!stack.empty()) {
      const std::size_t p = stack.back();
      stack.pop_back();
      piece.push_back(p);
      seeded = seeded || minCos[p] < strongCos;
      const int x = static_cast<int>(p % static_cast<std::size_t>(f.width)), y = static_cast<int>(p / static_cast<std::size_t>(f.width));
      x0 = std::min(x0, x), x1 = std::max(x1, x), y0 = std::min(y0, y), y1 = std::max(y1, y);
      for (int qy = std::max(0, y - 1); qy <= std::min(f.height - 1, y + 1); ++qy)
        for (int qx = std::max(0, x - 1); qx <= std::min(f.width - 1, x + 1); ++qx) {
          const std::size_t q = index(f, qx, qy);
          if (!seen[q] && minCos[q] < weakCos) seen[q] = 1, stack.push_back(q);
        }
    }
    const double length = std::hypot(x1 - x0 + 1, y1 - y0 + 1);
    if (!seeded || length < minLengthPx) continue;
    for (std::size_t p : piece) {
      const double turn = std::acos(std::clamp(static_cast<double>(minCos[p]), -1.0, 1.0)) * 180.0 / kPi;
      cover[p] = static_cast<float>(std::clamp((turn - weak) / (strong - weak), 0.0, 1.0));
    }
  }
  return cover;
}

int creaseWindowRadius(double widthPx) { return std::max(1, static_cast<int>(std::lround(0.5 * widthPx))); }

double lineWidthPixels(const ImageEffects& e, int height) { return e.lineWidth * height; }

double creaseMinLengthPixels(const ImageEffects& e, int height) {
  return kCreaseMinLength * std::max(1.0, lineWidthPixels(e, height));
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
    const double widthPx = lineWidthPixels(e, f.height);
    std::vector<float> cover = e.silhouettes ? silhouetteCoverage(f, camera, widthPx, e.silhouetteJump)
                                             : std::vector<float>(n, 0.0f);
    if (e.creaseAngle > 0.0) {
      const std::vector<float> crease =
          creaseCoverage(f, widthPx, e.silhouetteJump, e.creaseAngle, creaseMinLengthPixels(e, f.height));
      for (std::size_t p = 0; p < n; ++p) cover[p] = std::max(cover[p], crease[p]);
    }
    // The line lies over the pixel by its coverage (Porter and Duff's "over"), in linear colour.
    const glm::vec3 line = srgbToLinear(e.lineColor);
    forPixels(n, [&](std::size_t p) {
      const float c = cover[p];
      if (c <= 0.0f) return;
      for (int k = 0; k < 3; ++k) f.rgba[4 * p + k] = c * line[k] + (1.0f - c) * f.rgba[4 * p + k];
      f.rgba[4 * p + 3] = c + (1.0f - c) * f.rgba[4 * p + 3];
    });
  }
}

}  // namespace surftrace::view

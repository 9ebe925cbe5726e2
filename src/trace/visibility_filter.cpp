// Edge-aware smoothing of the per-pixel light visibilities of the soft and full lighting presets.
#include "trace/visibility_filter.hpp"

#include <cmath>
#include <limits>

#include <glm/geometric.hpp>
#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>

namespace surftrace::trace {

void VisibilityPlane::reset(int w, int h) {
  width = w;
  height = h;
  const std::size_t n = static_cast<std::size_t>(w) * static_cast<std::size_t>(h);
  const float nan = std::numeric_limits<float>::quiet_NaN();
  key.assign(n, nan);
  open.assign(n, nan);
  position.assign(n, glm::vec3(0.0f));
  normal.assign(n, glm::vec3(0.0f));
  footprint.assign(n, 0.0f);
  hit.assign(n, 0);
  weight.assign(n, 1.0f);
}

namespace {

// The B3 spline's taps (Dammertz et al. 2010, "Edge-avoiding à-trous wavelet transform").
constexpr float kTap[5] = {1.0f / 16.0f, 1.0f / 4.0f, 3.0f / 8.0f, 1.0f / 4.0f, 1.0f / 16.0f};
// The normal weight (n_p·n_q)^kNormalPower: 0.37 at 10° apart, 0.1 at 15°, 0.01 at 22°.
constexpr int kNormalPower = 64;
// A neighbour this many footprints × step off the tangent plane keeps e^−1 of its weight.
constexpr float kPlaneTolerance = 1.0f;
// The reach is at least this many pixels, so that a coarse image (pixels wider than the reach)
// is still smoothed a little.
constexpr float kLeastReach = 1.5f;

float normalWeight(float c) {
  if (c <= 0.0f) return 0.0f;
  float w = c;
  for (int i = 1; i < kNormalPower; i *= 2) w *= w;  // squared log2(kNormalPower) times: c^64
  return w;
}

// The same tests as the filter's weights, at one step: off the tangent plane by more than 2
// footprints, or normals more than 25° apart.
bool sameSurface(const VisibilityPlane& plane, std::size_t p, std::size_t q) {
  if (!plane.hit[q]) return false;
  const glm::vec3 d = plane.position[q] - plane.position[p];
  const float off = std::max(std::abs(glm::dot(plane.normal[p], d)), std::abs(glm::dot(plane.normal[q], d)));
  return off < 2.0f * plane.footprint[p] && glm::dot(plane.normal[p], plane.normal[q]) > 0.906f;
}

}  // namespace

std::vector<unsigned char> filterEdges(const VisibilityPlane& plane) {
  const int w = plane.width, h = plane.height;
  std::vector<unsigned char> edge(plane.hit.size(), 0);
  tbb::parallel_for(tbb::blocked_range<int>(0, h), [&](const tbb::blocked_range<int>& rows) {
    for (int y = rows.begin(); y < rows.end(); ++y)
      for (int x = 0; x < w; ++x) {
        const std::size_t p = plane.index(x, y);
        if (!plane.hit[p]) continue;
        for (int dy = -1; dy <= 1 && !edge[p]; ++dy)
          for (int dx = -1; dx <= 1; ++dx) {
            const int qx = x + dx, qy = y + dy;
            if (qx < 0 || qx >= w || qy < 0 || qy >= h || !sameSurface(plane, p, plane.index(qx, qy))) {
              edge[p] = 1;
              break;
            }
          }
      }
  });
  return edge;
}

void filterVisibility(VisibilityPlane& plane, int passes, float reach) {
  const int w = plane.width, h = plane.height;
  std::vector<float> key(plane.key.size()), open(plane.open.size());
  for (int pass = 0, step = 1; pass < passes; ++pass, step *= 2) {
    tbb::parallel_for(tbb::blocked_range<int>(0, h), [&](const tbb::blocked_range<int>& rows) {
      for (int y = rows.begin(); y < rows.end(); ++y)
        for (int x = 0; x < w; ++x) {
          const std::size_t p = plane.index(x, y);
          key[p] = plane.key[p];
          open[p] = plane.open[p];
          if (!plane.hit[p]) continue;
          const glm::vec3 xp = plane.position[p], np = plane.normal[p];
          const float scale = 1.0f / (kPlaneTolerance * plane.footprint[p] * static_cast<float>(step));
          const float reachHere = std::max(reach, kLeastReach * plane.footprint[p]);
          const float reachScale = 1.0f / (reachHere * reachHere);
          float sumKey = 0.0f, weightKey = 0.0f, sumOpen = 0.0f, weightOpen = 0.0f;
          for (int dy = -2; dy <= 2; ++dy) {
            const int qy = y + dy * step;
            if (qy < 0 || qy >= h) continue;
            for (int dx = -2; dx <= 2; ++dx) {
              const int qx = x + dx * step;
              if (qx < 0 || qx >= w) continue;
              const std::size_t q = plane.index(qx, qy);
              if (!plane.hit[q]) continue;
              const glm::vec3 d = plane.position[q] - xp;
              // Off either tangent plane (symmetric, so a convex edge seen from either side stops it).
              const float off = std::max(std::abs(glm::dot(np, d)), std::abs(glm::dot(plane.normal[q], d))) * scale;
              const float wq = plane.weight[q] * kTap[dx + 2] * kTap[dy + 2] * normalWeight(glm::dot(np, plane.normal[q])) *
                               std::exp(-off * off - glm::dot(d, d) * reachScale);
              if (!std::isnan(plane.key[q])) {
                sumKey += wq * plane.key[q];
                weightKey += wq;
              }
              if (!std::isnan(plane.open[q])) {
                sumOpen += wq * plane.open[q];
                weightOpen += wq;
              }
            }
          }
          // The pixel itself is always a neighbour with weight > 0 when its value is traced.
          if (!std::isnan(key[p]) && weightKey > 0.0f) key[p] = sumKey / weightKey;
          if (!std::isnan(open[p]) && weightOpen > 0.0f) open[p] = sumOpen / weightOpen;
        }
    });
    plane.key.swap(key);
    plane.open.swap(open);
  }
}

}  // namespace surftrace::trace

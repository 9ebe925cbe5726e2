// Pixel-by-pixel agreement of two frames of the same view (ORACLES D.4 masks): the GL image against the Embree reference.
#pragma once

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <string>
#include <vector>

#include <glm/geometric.hpp>

#include "trace/ray.hpp"
#include "trace/render.hpp"

namespace surftrace::gl::test {

struct Agreement {
  std::size_t pixels = 0;
  std::size_t silhouette = 0;         // reference hit/miss changes within the 3×3 neighbourhood
  std::size_t coverageMismatch = 0;   // hit/miss differs, outside the silhouette band
  double coverageFraction = 0.0;      // of the pixels outside the band
  std::size_t depthSamples = 0;       // both hit, outside the band
  double depthMedian = 0.0, depthP99 = 0.0, depthMax = 0.0;  // |t_gl − t_ref|, Å
  std::size_t kindSamples = 0;        // both hit, reference kind constant over 3×3, not flagged
  std::size_t patchSamples = 0;       // both hit, reference patch id constant over 3×3, not flagged
  double kindAgreement = 1.0, patchAgreement = 1.0;
  double normalP99Degrees = 0.0;

  std::string summary(double sceneSize) const {
    char text[512];
    std::snprintf(text, sizeof text,
                  "coverage mismatch %zu/%zu (%.4f%%, band %zu px); depth median %.2e p99 %.2e max %.2e Å "
                  "(p99 %.2e of scene %.1f Å); kind %.4f%% of %zu; patch %.4f%% of %zu; normal p99 %.3f°",
                  coverageMismatch, pixels - silhouette, 100.0 * coverageFraction, silhouette, depthMedian, depthP99,
                  depthMax, depthP99 / sceneSize, sceneSize, 100.0 * kindAgreement, kindSamples, 100.0 * patchAgreement, patchSamples,
                  normalP99Degrees);
    return text;
  }
};

inline double percentile(std::vector<double> v, double q) {
  if (v.empty()) return 0.0;
  std::sort(v.begin(), v.end());
  const std::size_t i = std::min(v.size() - 1, static_cast<std::size_t>(q * static_cast<double>(v.size() - 1) + 0.5));
  return v[i];
}

inline Agreement compareFrames(const trace::FrameBuffers& gl, const trace::FrameBuffers& ref) {
  Agreement a;
  const int w = ref.width, h = ref.height;
  a.pixels = ref.pixels();
  auto at = [&](int x, int y) { return static_cast<std::size_t>(y) * static_cast<std::size_t>(w) + static_cast<std::size_t>(x); };
  std::vector<double> depth, angle;
  std::size_t kindSame = 0, patchSame = 0;
  for (int y = 0; y < h; ++y)
    for (int x = 0; x < w; ++x) {
      const std::size_t p = at(x, y);
      const bool refHit = ref.kind[p] != 0;
      bool band = false, kindSeam = false, seam = false;
      for (int dy = -1; dy <= 1; ++dy)
        for (int dx = -1; dx <= 1; ++dx) {
          const int nx = std::clamp(x + dx, 0, w - 1), ny = std::clamp(y + dy, 0, h - 1);
          const std::size_t q = at(nx, ny);
          band = band || (ref.kind[q] != 0) != refHit;
          kindSeam = kindSeam || ref.kind[q] != ref.kind[p];
          seam = seam || ref.patchId[q] != ref.patchId[p];
        }
      const bool flagged = (ref.flags[p] & (trace::kHitGrazing | trace::kHitCusp | trace::kHitNearBoundary)) != 0;
      kindSeam = kindSeam || flagged;
      seam = seam || flagged;
      if (band) {
        ++a.silhouette;
        continue;
      }
      const bool glHit = gl.kind[p] != 0;
      if (glHit != refHit) {
        ++a.coverageMismatch;
        continue;
      }
      if (!refHit) continue;
      depth.push_back(std::abs(static_cast<double>(gl.depth[p]) - static_cast<double>(ref.depth[p])));
      const glm::dvec3 ng(gl.normal[3 * p], gl.normal[3 * p + 1], gl.normal[3 * p + 2]);
      const glm::dvec3 nr(ref.normal[3 * p], ref.normal[3 * p + 1], ref.normal[3 * p + 2]);
      if (!kindSeam) {
        ++a.kindSamples;
        kindSame += gl.kind[p] == ref.kind[p];
      }
      if (seam) continue;
      angle.push_back(std::acos(std::clamp(glm::dot(glm::normalize(ng), glm::normalize(nr)), -1.0, 1.0)) * 180.0 / M_PI);
      ++a.patchSamples;
      patchSame += gl.patchId[p] == ref.patchId[p];
    }
  a.coverageFraction = static_cast<double>(a.coverageMismatch) / static_cast<double>(std::max<std::size_t>(1, a.pixels - a.silhouette));
  a.depthSamples = depth.size();
  a.depthMedian = percentile(depth, 0.5);
  a.depthP99 = percentile(depth, 0.99);
  a.depthMax = depth.empty() ? 0.0 : *std::max_element(depth.begin(), depth.end());
  if (a.kindSamples > 0) a.kindAgreement = static_cast<double>(kindSame) / static_cast<double>(a.kindSamples);
  if (a.patchSamples > 0) a.patchAgreement = static_cast<double>(patchSame) / static_cast<double>(a.patchSamples);
  a.normalP99Degrees = percentile(angle, 0.99);
  return a;
}

}  // namespace surftrace::gl::test

// The noise of a per-pixel quantity over a flat floor (the lighting tests' measure of how grainy
// shadows and occlusion are): what a pixel adds to its neighbours' mean.
#pragma once

#include <cmath>
#include <cstddef>
#include <vector>

#include "view/frame_buffers.hpp"

namespace surftrace::test {

struct FloorNoise {
  double sigma = 0.0;
  std::size_t pixels = 0;
};

// The noise of q (one value per pixel of fb) over the pixels whose 3×3 neighbourhood is all
// floor (covered, atom 0) and whose neighbourhood mean is in (lo, hi) (where q is neither all
// open nor all blocked): the standard deviation of q − mean3×3(q), scaled by √(81/72) to that
// of q's noise alone (independent noise of σ in every pixel gives σ).
inline FloorNoise floorNoise(const view::FrameBuffers& fb, const std::vector<double>& q, double lo, double hi) {
  FloorNoise r;
  double sum2 = 0.0;
  for (int y = 1; y + 1 < fb.height; ++y)
    for (int x = 1; x + 1 < fb.width; ++x) {
      double mean = 0.0;
      bool floor = true;
      for (int dy = -1; dy <= 1; ++dy)
        for (int dx = -1; dx <= 1; ++dx) {
          const std::size_t p = static_cast<std::size_t>(y + dy) * fb.width + (x + dx);
          floor = floor && fb.kind[p] != 0 && fb.atomId[p] == 0;
          mean += q[p] / 9.0;
        }
      if (!floor || !(mean > lo && mean < hi)) continue;
      const double d = q[static_cast<std::size_t>(y) * fb.width + x] - mean;
      sum2 += d * d;
      ++r.pixels;
    }
  r.sigma = r.pixels ? std::sqrt(sum2 / r.pixels * 81.0 / 72.0) : 0.0;
  return r;
}

}  // namespace surftrace::test

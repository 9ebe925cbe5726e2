// One rendered frame: colour and the per-pixel buffers (AOVs) every renderer fills alike.
#include "view/frame_buffers.hpp"

#include <limits>

namespace surftrace::view {

void FrameBuffers::reset(int newWidth, int newHeight) {
  width = newWidth;
  height = newHeight;
  const std::size_t n = pixels();
  constexpr float kInf = std::numeric_limits<float>::infinity();
  rgba.assign(4 * n, 0.0f);
  depth.assign(n, kInf);
  viewZ.assign(n, kInf);
  normal.assign(3 * n, 0.0f);
  kind.assign(n, 0u);
  patchId.assign(n, ~0u);
  atomId.assign(n, ~0u);
  flags.assign(n, 0u);
  seamDistance.clear();
  layers.clear();
}

void applyBackgroundAlpha(FrameBuffers& f, const float (&background)[3], float alpha) {
  for (std::size_t p = 0; p < f.pixels(); ++p) {
    const float coverage = f.rgba[4 * p + 3];
    for (int c = 0; c < 3; ++c) f.rgba[4 * p + c] -= (1.0f - coverage) * (1.0f - alpha) * background[c];
    f.rgba[4 * p + 3] = coverage + (1.0f - coverage) * alpha;
  }
  f.transparentBackground = true;
}

}  // namespace surftrace::view

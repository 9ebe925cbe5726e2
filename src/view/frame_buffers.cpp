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

}  // namespace surftrace::view

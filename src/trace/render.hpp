// Tile-parallel rendering of a patch scene into colour and per-pixel buffers.
#pragma once

#include <span>

#include <glm/vec3.hpp>

#include "trace/patch_scene.hpp"
#include "view/frame_buffers.hpp"
#include "view/render_options.hpp"

namespace surftrace::trace {

// The most layers a transparent frame composites (RenderOptions::maxLayers).
inline constexpr int kMaxLayers = 1024;

// `atomColors` (one per atom) is used by every scheme but Patch. Identical output for any
// number of threads: every pixel depends on its own rays only.
view::FrameBuffers render(const PatchScene& scene, const view::RenderOptions& options, std::span<const glm::vec3> atomColors);

}  // namespace surftrace::trace

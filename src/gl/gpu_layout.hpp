// The patch records as the GPU sees them: the compact std430/std140 records of Lindow et al. 2010, Sect. 5.3.
#pragma once

#include <cstddef>
#include <cstdint>

#include <glm/vec4.hpp>

namespace surftrace::gl {

// gl/shaders/gpu_shared.h declares the records, the frame block and the bindings once for
// C++ and GLSL; here its vec4, uvec4 and uint are glm's.
namespace shared {
using vec4 = glm::vec4;
using uvec4 = glm::uvec4;
using uint = std::uint32_t;
#include "gl/shaders/gpu_shared.h"
}  // namespace shared

using shared::GpuConcave;
using shared::GpuFrame;
using shared::GpuKind;
using shared::GpuLightMap;
using shared::GpuPeel;
using shared::GpuSkin;
using shared::GpuTorus;
using shared::kAtomBinding;
using shared::kAtomColorBinding;
using shared::kClipPlaneUnit;
using shared::kFragmentCountBinding;
using shared::kFrameBinding;
using shared::kKindCount;
using shared::kRecordBinding;
using shared::kAccumulatedUnit;
using shared::kBlockerBinding;
using shared::kBlockerListBinding;
using shared::kLayerColorUnit;
using shared::kLayerDepthUnit;
using shared::kLightMapBinding;
using shared::kLightMapUnit;
using shared::kOpaqueColorUnit;
using shared::kOpaqueDepthUnit;
using shared::kPeelBinding;
using shared::kPreviousLayerUnit;
using shared::kSkinAtomBinding;
using shared::kSkinGridBinding;

// A sphere is one vec4 (centre, radius).
using GpuSphere = glm::vec4;

static_assert(sizeof(GpuSphere) == 16);
static_assert(sizeof(GpuTorus) == 64 && offsetof(GpuTorus, axisRp) == 16 && offsetof(GpuTorus, e1Phi) == 32 &&
              offsetof(GpuTorus, theta) == 48);
static_assert(sizeof(GpuConcave) == 64 && offsetof(GpuConcave, dirIBegin) == 16 &&
              offsetof(GpuConcave, dirJCount) == 32 && offsetof(GpuConcave, dirK) == 48);
static_assert(sizeof(GpuSkin) == 64 && offsetof(GpuSkin, axisConstant) == 16 && offsetof(GpuSkin, coefficients) == 32 &&
              offsetof(GpuSkin, cell) == 48);
static_assert(sizeof(GpuPeel) == 32 && offsetof(GpuPeel, merge) == 16);
static_assert(sizeof(GpuKind) == 32 && offsetof(GpuKind, first) == 16);
static_assert(sizeof(GpuFrame) == 7 * 16 + kKindCount * 32 + 7 * 16);
static_assert(sizeof(GpuLightMap) == 64 && offsetof(GpuLightMap, toMapZ) == 32 && offsetof(GpuLightMap, direction) == 48);
static_assert(offsetof(GpuFrame, kinds) == 112 && offsetof(GpuFrame, shading) == 112 + kKindCount * 32 &&
              offsetof(GpuFrame, torusTrace) == 128 + kKindCount * 32 &&
              offsetof(GpuFrame, traceParams) == 144 + kKindCount * 32 &&
              offsetof(GpuFrame, lightMaps) == 192 + kKindCount * 32 &&
              offsetof(GpuFrame, lightMapScale) == 208 + kKindCount * 32);

}  // namespace surftrace::gl

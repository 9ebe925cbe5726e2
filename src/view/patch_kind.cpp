// Patch kinds, their colours and the global patch-id order: what the `patch.kind` and `patch.id` channels mean.
#include "view/patch_kind.hpp"

#include <limits>
#include <stdexcept>

#include "view/srgb.hpp"

namespace surftrace::view {

const char* patchKindName(PatchKind kind) {
  if (kind == PatchKind::None) return "none";
  const std::size_t row = kindRow(kind);
  return row < kPatchKindCount ? kPatchKinds[row].name : "?";
}

glm::vec3 kindColor(PatchKind kind) {
  // Decoded once: Embree asks at every hit.
  static const std::array<glm::vec3, kPatchKindCount> linear = [] {
    std::array<glm::vec3, kPatchKindCount> c{};
    for (std::size_t k = 0; k < kPatchKindCount; ++k) c[k] = srgbToLinear(kPatchKinds[k].color);
    return c;
  }();
  const std::size_t row = kindRow(kind);
  return kind != PatchKind::None && row < kPatchKindCount ? linear[row] : glm::vec3(0.0f);
}

std::size_t patchCount(const build::PatchList& list, PatchKind kind) {
  switch (kind) {
    case PatchKind::Convex: return list.convex.size();
    case PatchKind::Toroidal: return list.tori.size();
    case PatchKind::Concave: return list.concave.size();
    case PatchKind::SkinConvex:
    case PatchKind::SkinEdge:
    case PatchKind::SkinFace:
    case PatchKind::SkinConcave: {
      const auto range = build::mssKindRange(list.mss, mssKindOf(kind));
      return range.second - range.first;
    }
    case PatchKind::Ball:
    case PatchKind::Stick:
    case PatchKind::None: break;
  }
  return 0;
}

PatchIdOrder::PatchIdOrder(const std::array<std::size_t, kPatchKindCount>& counts) {
  std::size_t sum = 0;
  for (std::size_t k = 0; k < kPatchKindCount; ++k) {
    sum += counts[k];
    if (sum >= std::numeric_limits<std::uint32_t>::max())
      throw std::invalid_argument("too many patches for 32-bit patch ids");
    first_[k + 1] = static_cast<std::uint32_t>(sum);
  }
}

namespace {
std::array<std::size_t, kPatchKindCount> countsOf(const build::PatchList& list) {
  std::array<std::size_t, kPatchKindCount> counts{};
  for (std::size_t k = 0; k < kPatchKindCount; ++k) counts[k] = patchCount(list, kPatchKinds[k].kind);
  return counts;
}
}  // namespace

PatchIdOrder::PatchIdOrder(const build::PatchList& list) : PatchIdOrder(countsOf(list)) {}

}  // namespace surftrace::view

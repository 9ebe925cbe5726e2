// Patch kinds, their colours and the global patch-id order: what the `patch.kind` and `patch.id` channels mean.
#pragma once

#include <array>
#include <cstddef>
#include <cstdint>
#include <iterator>

#include <glm/vec3.hpp>

#include "build/patch_list.hpp"

namespace surftrace::view {

// Patch kinds as written to the `patch.kind` image channel (0 = no hit): the one source of the
// kind codes. 1-3 are the SES's, 4-7 the molecular skin's (one per Delaunay simplex dimension,
// kFirstSkinKind + MssKind), 8-9 the ball-and-stick model's. Reference EXRs hold these numbers:
// they never change (pinned below); gl/shaders/gpu_shared.h's are tied to them by static_assert
// (gl/gpu_kinds.hpp), and the renderers' kind tables by their rows' `kind`.
enum class PatchKind : std::uint32_t {
  None = 0,
  Convex = 1,
  Toroidal = 2,
  Concave = 3,
  SkinConvex = 4,
  SkinEdge = 5,
  SkinFace = 6,
  SkinConcave = 7,
  Ball = 8,   // the ball-and-stick model (build/bonds.hpp): an atom's ball
  Stick = 9,  // and a bond's stick
};

// One row per kind that holds patches, in the order of the global patch ids (and of the
// kind codes: row k is kind k + 1). A new kind is a new row here, and a new row in each
// renderer's table (trace/patch_kinds.hpp, gl/gpu_kinds.hpp).
struct PatchKindInfo {
  PatchKind kind;
  const char* name;
  glm::vec3 color;  // sRGB; Lindow et al. 2010's colours: SES convex green, toroidal yellow, concave red;
                    // MSS (Fig. 7) convex green, edge hyperboloids red, face ones yellow, concave blue
};
inline constexpr PatchKindInfo kPatchKinds[] = {
    {PatchKind::Convex, "convex", {0.30f, 0.75f, 0.30f}},
    {PatchKind::Toroidal, "toroidal", {0.90f, 0.80f, 0.25f}},
    {PatchKind::Concave, "concave", {0.85f, 0.25f, 0.20f}},
    {PatchKind::SkinConvex, "skin convex", {0.30f, 0.75f, 0.30f}},
    {PatchKind::SkinEdge, "skin edge", {0.85f, 0.25f, 0.20f}},
    {PatchKind::SkinFace, "skin face", {0.90f, 0.80f, 0.25f}},
    {PatchKind::SkinConcave, "skin concave", {0.25f, 0.40f, 0.85f}},
    {PatchKind::Ball, "ball", {0.55f, 0.55f, 0.60f}},
    {PatchKind::Stick, "stick", {0.70f, 0.70f, 0.72f}},
};
inline constexpr std::size_t kPatchKindCount = std::size(kPatchKinds);

// The row of a kind that holds patches (not None).
constexpr std::size_t kindRow(PatchKind kind) { return static_cast<std::size_t>(kind) - 1; }

// The rows before kSurfaceKindCount are the surface's (what a patch list holds); the rest are
// the ball-and-stick model's, which the renderers take beside the list (build::BallStickModel)
// and draw opaque.
inline constexpr std::size_t kSurfaceKindCount = kindRow(PatchKind::Ball);
constexpr bool isModelKind(PatchKind kind) { return kind == PatchKind::Ball || kind == PatchKind::Stick; }
// The skin's kinds: one row per build::MssKind, in that order, from kFirstSkinKind.
inline constexpr PatchKind kFirstSkinKind = PatchKind::SkinConvex;
// The view kind of an MSS patch kind, and back (for the skin's kinds only).
constexpr PatchKind skinKind(build::MssKind k) {
  return static_cast<PatchKind>(static_cast<std::uint32_t>(kFirstSkinKind) + static_cast<std::uint32_t>(k));
}
constexpr build::MssKind mssKindOf(PatchKind kind) {
  return static_cast<build::MssKind>(static_cast<std::uint32_t>(kind) - static_cast<std::uint32_t>(kFirstSkinKind));
}

// The codes stored in images: a new kind takes the next number, never an old one's.
static_assert(static_cast<std::uint32_t>(PatchKind::None) == 0 && static_cast<std::uint32_t>(PatchKind::Convex) == 1 &&
                  static_cast<std::uint32_t>(PatchKind::Toroidal) == 2 &&
                  static_cast<std::uint32_t>(PatchKind::Concave) == 3 &&
                  static_cast<std::uint32_t>(PatchKind::SkinConvex) == 4 &&
                  static_cast<std::uint32_t>(PatchKind::SkinEdge) == 5 &&
                  static_cast<std::uint32_t>(PatchKind::SkinFace) == 6 &&
                  static_cast<std::uint32_t>(PatchKind::SkinConcave) == 7 &&
                  static_cast<std::uint32_t>(PatchKind::Ball) == 8 && static_cast<std::uint32_t>(PatchKind::Stick) == 9,
              "patch.kind codes are stored in reference EXRs: never renumber them");
// Row k is kind k + 1; the skin's rows are build::kMssKinds' in order; the model's rows are last.
constexpr bool kindTableInOrder() {
  for (std::size_t k = 0; k < kPatchKindCount; ++k) {
    if (static_cast<std::size_t>(kPatchKinds[k].kind) != k + 1) return false;
    if (isModelKind(kPatchKinds[k].kind) != (k >= kSurfaceKindCount)) return false;
  }
  for (std::size_t m = 0; m < build::kMssKindCount; ++m)
    if (kindRow(skinKind(build::kMssKinds[m].kind)) != kindRow(kFirstSkinKind) + m ||
        mssKindOf(skinKind(build::kMssKinds[m].kind)) != build::kMssKinds[m].kind)
      return false;
  return kindRow(kFirstSkinKind) + build::kMssKindCount == kSurfaceKindCount;
}
static_assert(kindTableInOrder(), "view::kPatchKinds: row k is kind k + 1, the skin's rows follow build::kMssKinds, "
                                  "and the model's rows come last");

const char* patchKindName(PatchKind kind);  // "none" for None
// The kind's colour decoded to linear (view/srgb.hpp), as the renderers shade it; black for None.
glm::vec3 kindColor(PatchKind kind);
// How many patches of `kind` the list holds (0 for the model's kinds).
std::size_t patchCount(const build::PatchList& list, PatchKind kind);

// Global patch ids (the `patch.id` channel, GL's fragment counts): the kinds in row order,
// each kind's patches in list order: SES spheres, tori, concave triangles, then the skin's
// kinds (the MSS list is grouped by kind already), then the model's balls and sticks.
class PatchIdOrder {
 public:
  PatchIdOrder() = default;
  // Throws std::invalid_argument when the patches do not fit 32-bit ids.
  explicit PatchIdOrder(const std::array<std::size_t, kPatchKindCount>& counts);
  explicit PatchIdOrder(const build::PatchList& list);

  std::uint32_t first(PatchKind kind) const { return first_[kindRow(kind)]; }
  std::uint32_t count(PatchKind kind) const { return first_[kindRow(kind) + 1] - first_[kindRow(kind)]; }
  std::uint32_t globalId(PatchKind kind, std::uint32_t patch) const {
    return kind == PatchKind::None ? ~0u : first(kind) + patch;
  }
  std::size_t total() const { return first_[kPatchKindCount]; }

 private:
  std::array<std::uint32_t, kPatchKindCount + 1> first_{};
};

}  // namespace surftrace::view

// The patch kinds of the GL renderer, one row each: GPU record, atoms, shader file; and the upload of a patch list.
#pragma once

#include <cstddef>
#include <cstdint>
#include <tuple>
#include <utility>
#include <vector>

#include <glm/vec2.hpp>
#include <glm/vec3.hpp>
#include <glm/vec4.hpp>

#include "build/patch_list.hpp"
#include "gl/gpu_layout.hpp"
#include "view/patch_kind.hpp"

namespace surftrace::gl {

// A row: `kind` (its code in the kind channel and its row of view::kPatchKinds, which gives
// the colour and the place in the global id order), `shader` (shaders/<shader>.glsl holds
// its records' GLSL declaration and its geometry and fragment stages; the program is
// compiled from it), `Record` and `Atoms` (the std430 elements bound to kRecordBinding and
// kAtomBinding for the kind's draw), and how patch i of the list becomes them. The
// renderer's buffers, programs, counts and colours are arrays over these rows, in
// GpuKinds order (= view::kPatchKinds order).
struct GpuSphereKind {
  static constexpr view::PatchKind kind = view::PatchKind::Convex;
  static constexpr const char* shader = "sphere";
  using Record = GpuSphere;
  using Atoms = std::uint32_t;
  static Record record(const build::PatchList& list, std::size_t i, const glm::dvec3& origin);
  static Atoms atoms(const build::PatchList& list, std::size_t i);
  // A ball around the patch (unshifted centre, radius): sets the depth range only.
  static std::pair<glm::dvec3, double> reach(const build::PatchList& list, std::size_t i);
};

struct GpuTorusKind {
  static constexpr view::PatchKind kind = view::PatchKind::Toroidal;
  static constexpr const char* shader = "torus";
  using Record = GpuTorus;
  using Atoms = glm::uvec2;  // atom i, atom j
  static Record record(const build::PatchList& list, std::size_t i, const glm::dvec3& origin);
  static Atoms atoms(const build::PatchList& list, std::size_t i);
  static std::pair<glm::dvec3, double> reach(const build::PatchList& list, std::size_t i);
};

struct GpuConcaveKind {
  static constexpr view::PatchKind kind = view::PatchKind::Concave;
  static constexpr const char* shader = "concave";
  using Record = GpuConcave;
  using Atoms = glm::uvec4;  // atoms i, j, k, unused
  static Record record(const build::PatchList& list, std::size_t i, const glm::dvec3& origin);
  static Atoms atoms(const build::PatchList& list, std::size_t i);
  static std::pair<glm::dvec3, double> reach(const build::PatchList& list, std::size_t i);
};

// The molecular skin: one row per MSS kind (so each has its colour and id range), all drawn
// by shaders/skin.glsl; patch i of the row is patch first + i of the list's kind range. The
// cell planes follow the SES clipping planes in the plane buffer (cellBegin counts from there).
template <build::MssKind K> struct GpuSkinKind {
  static constexpr view::PatchKind kind = view::skinKind(K);
  static constexpr const char* shader = "skin";
  using Record = GpuSkin;
  using Atoms = glm::uvec4;  // the simplex, ascending; unused slots ~0u
  static Record record(const build::PatchList& list, std::size_t i, const glm::dvec3& origin);
  static Atoms atoms(const build::PatchList& list, std::size_t i);
  static std::pair<glm::dvec3, double> reach(const build::PatchList& list, std::size_t i);
};

using GpuKinds = std::tuple<GpuSphereKind, GpuTorusKind, GpuConcaveKind, GpuSkinKind<build::MssKind::Convex>,
                            GpuSkinKind<build::MssKind::Edge>, GpuSkinKind<build::MssKind::Face>,
                            GpuSkinKind<build::MssKind::Concave>>;
inline constexpr std::size_t kGpuKindCount = std::tuple_size_v<GpuKinds>;

template <std::size_t... I> constexpr bool gpuRowsMatchView(std::index_sequence<I...>) {
  return kGpuKindCount == view::kSurfaceKindCount && view::kPatchKindCount == static_cast<std::size_t>(kKindCount) &&
         ((std::tuple_element_t<I, GpuKinds>::kind == view::kPatchKinds[I].kind) && ...);
}
static_assert(gpuRowsMatchView(std::make_index_sequence<kGpuKindCount>{}),
              "gl::GpuKinds must list the surface kinds of view::kPatchKinds, in that order, and gpu_shared.h count them");
static_assert(shared::kBallKind == static_cast<std::uint32_t>(view::PatchKind::Ball) &&
              shared::kStickKind == static_cast<std::uint32_t>(view::PatchKind::Stick));
static_assert(shared::kConvexKind == static_cast<std::uint32_t>(view::PatchKind::Convex) &&
              shared::kToroidalKind == static_cast<std::uint32_t>(view::PatchKind::Toroidal) &&
              shared::kConcaveKind == static_cast<std::uint32_t>(view::PatchKind::Concave) &&
              shared::kSkinConvexKind == static_cast<std::uint32_t>(view::kFirstSkinKind),
              "gpu_shared.h's kind codes are view::PatchKind's (the one table)");

// The records and atoms of one kind, ready for upload.
template <class Kind> struct GpuKindPatches {
  using Row = Kind;
  std::vector<typename Kind::Record> records;
  std::vector<typename Kind::Atoms> atoms;
};
template <class Kinds> struct GpuKindPatchesOf;
template <class... Kind> struct GpuKindPatchesOf<std::tuple<Kind...>> {
  using type = std::tuple<GpuKindPatches<Kind>...>;
};

// The upload of one patch list, every coordinate shifted by −origin in double before it is
// rounded to float (ORACLES D.4: float32 keeps 7 digits, so molecules far from the
// coordinate origin would otherwise lose their surface detail).
struct GpuPatches {
  glm::dvec3 origin{0.0};
  GpuKindPatchesOf<GpuKinds>::type kinds;
  std::vector<glm::vec4> clipPlanes;  // n, w + n·origin: the SES clipping planes, then the MSS cell planes
  // The skin's atoms (build::SkinAtoms) as skin.glsl's owner search reads them: at
  // kSkinAtomBinding a header of three vec4, (n, cells along x, y, z) as uint bits, (the
  // grid's corner − origin, cell edge), (the largest radius, 0, 0, 0), then per atom its vdW
  // ball (centre − origin, r² = s·w); n = 0 when the list has none. At kSkinGridBinding the
  // grid of cubic cells over the centres: cellStart[cells + 1] (x fastest), then the atoms of
  // each cell in turn.
  std::vector<glm::vec4> skinAtoms;
  std::vector<std::uint32_t> skinGrid;
  // Bounding sphere of every patch (double, unshifted): sets the depth range.
  glm::dvec3 boundsCenter{0.0};
  double boundsRadius = 0.0;

  template <class Kind> const GpuKindPatches<Kind>& of() const { return std::get<GpuKindPatches<Kind>>(kinds); }
};

// Throws std::invalid_argument for more clipping planes than a float index holds exactly.
GpuPatches packPatches(const build::PatchList& patches, const glm::dvec3& origin);

}  // namespace surftrace::gl

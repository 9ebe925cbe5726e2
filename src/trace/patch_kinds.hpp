// The patch kinds of the Embree scene, one row each: intersector record, atoms, loader.
#pragma once

#include <cstddef>
#include <cstdint>
#include <memory>
#include <span>
#include <tuple>
#include <vector>

#include <glm/vec2.hpp>
#include <glm/vec3.hpp>

#include "build/bonds.hpp"
#include "build/patch_list.hpp"
#include "trace/concave_patch.hpp"
#include "trace/mss_patch.hpp"
#include "trace/sphere_patch.hpp"
#include "trace/stick_patch.hpp"
#include "trace/torus_patch.hpp"
#include "view/patch_kind.hpp"

namespace surftrace::trace {

// Arrays a scene owns (copied from the patch list): patches hold spans into them.
struct ScenePlanes {
  std::vector<build::Plane> clip;  // concave triangles' self-intersection planes
  std::vector<build::Plane> cell;  // the skin's mixed-cell planes
  // The skin's atoms (which one owns a skin point); behind a pointer, so that patches keep
  // pointing at it when the scene moves.
  std::unique_ptr<const SkinAtomBalls> skinAtoms;
};

// A row: `kind` (the image channel's code), `Patch` (the intersector's record: its file
// provides bounds(), intersect() and atomOf()), `Atoms` (what atomOf needs besides the
// patch), and how patch i of the list is loaded. Every loop over the kinds of a scene
// (ids, bounds, the plain loop, the Embree geometries) goes through SceneKinds, in this
// order: the global patch-id order of view/patch_kind.hpp.
struct SphereKind {
  static constexpr view::PatchKind kind = view::PatchKind::Convex;
  using Patch = SpherePatch;
  using Atoms = std::uint32_t;
  static Patch patch(const build::PatchList& list, std::size_t i, const ScenePlanes&) {
    return SpherePatch{list.convex.center[i], list.convex.radius[i]};
  }
  static Atoms atoms(const build::PatchList& list, std::size_t i) { return list.convex.atom[i]; }
};

struct TorusKind {
  static constexpr view::PatchKind kind = view::PatchKind::Toroidal;
  using Patch = TorusPatch;
  using Atoms = glm::uvec2;  // the atoms of the contact circles at θi and θj
  static Patch patch(const build::PatchList& list, std::size_t i, const ScenePlanes&) {
    return torusPatch(list.tori, i, list.params.probeRadius);
  }
  static Atoms atoms(const build::PatchList& list, std::size_t i) { return {list.tori.atomI[i], list.tori.atomJ[i]}; }
};

struct ConcaveKind {
  static constexpr view::PatchKind kind = view::PatchKind::Concave;
  using Patch = ConcavePatch;
  using Atoms = glm::uvec3;  // the atoms of the contact directions i, j, k
  static Patch patch(const build::PatchList& list, std::size_t i, const ScenePlanes& planes) {
    ConcavePatch c = concavePatch(list, i);
    // Re-point the clipping planes at the scene's own copy.
    c.clipPlanes = std::span<const build::Plane>(planes.clip).subspan(list.concave.clipBegin[i], list.concave.clipCount[i]);
    return c;
  }
  static Atoms atoms(const build::PatchList& list, std::size_t i) {
    return {list.concave.atomI[i], list.concave.atomJ[i], list.concave.atomK[i]};
  }
};

// The molecular skin: one row per MSS kind, all with the quadric intersector; patch i of the
// row is patch first + i of the list's kind range.
template <build::MssKind K> struct SkinKind {
  static constexpr view::PatchKind kind = view::skinKind(K);
  using Patch = MssPatch;
  using Atoms = glm::uvec4;  // the simplex, ascending; unused slots ~0u
  static Patch patch(const build::PatchList& list, std::size_t i, const ScenePlanes& planes) {
    const std::size_t k = build::mssKindRange(list.mss, K).first + i;
    MssPatch p = mssPatch(list, k);
    p.cellPlanes = std::span<const build::Plane>(planes.cell).subspan(list.mss.cellBegin[k], list.mss.cellCount[k]);
    p.atomBalls = planes.skinAtoms.get();
    return p;
  }
  static Atoms atoms(const build::PatchList& list, std::size_t i) {
    return list.mss.atoms[build::mssKindRange(list.mss, K).first + i];
  }
};

// The ball-and-stick model's rows: loaded from a build::BallStickModel (`fromModel`), not from
// the patch list, and opaque to transparent rays (render.cpp).
struct BallKind {
  static constexpr view::PatchKind kind = view::PatchKind::Ball;
  static constexpr bool fromModel = true;
  using Patch = SpherePatch;
  using Atoms = std::uint32_t;
  static std::size_t count(const build::BallStickModel& m) { return m.centers.size(); }
  static Patch patch(const build::BallStickModel& m, std::size_t i) { return SpherePatch{m.centers[i], m.ballRadii[i]}; }
  static Atoms atoms(const build::BallStickModel&, std::size_t i) { return static_cast<Atoms>(i); }
};

struct StickKind {
  static constexpr view::PatchKind kind = view::PatchKind::Stick;
  static constexpr bool fromModel = true;
  using Patch = StickPatch;
  using Atoms = glm::uvec2;  // the bond's atoms
  static std::size_t count(const build::BallStickModel& m) { return m.bonds.size(); }
  static Patch patch(const build::BallStickModel& m, std::size_t i) {
    return StickPatch{m.centers[m.bonds[i].x], m.centers[m.bonds[i].y], m.stickRadius};
  }
  static Atoms atoms(const build::BallStickModel& m, std::size_t i) { return m.bonds[i]; }
};

// Whether a row is the model's (its patches come from a build::BallStickModel).
template <class Kind> constexpr bool isModelRow() {
  if constexpr (requires { Kind::fromModel; }) return Kind::fromModel;
  else return false;
}

using SceneKinds = std::tuple<SphereKind, TorusKind, ConcaveKind, SkinKind<build::MssKind::Convex>,
                              SkinKind<build::MssKind::Edge>, SkinKind<build::MssKind::Face>,
                              SkinKind<build::MssKind::Concave>, BallKind, StickKind>;

// The patches of one kind in the intersector's form, with their atoms.
template <class Kind> struct KindPatches {
  using Row = Kind;
  std::vector<typename Kind::Patch> patches;
  std::vector<typename Kind::Atoms> atoms;
};

template <class Kinds> struct KindPatchesOf;
template <class... Kind> struct KindPatchesOf<std::tuple<Kind...>> {
  using type = std::tuple<KindPatches<Kind>...>;
};
using SceneKindPatches = KindPatchesOf<SceneKinds>::type;

// Every row's kind is the row of the same place in view::kPatchKinds.
template <std::size_t... I> constexpr bool rowsMatchView(std::index_sequence<I...>) {
  return std::tuple_size_v<SceneKinds> == view::kPatchKindCount &&
         ((std::tuple_element_t<I, SceneKinds>::kind == view::kPatchKinds[I].kind) && ...);
}
static_assert(rowsMatchView(std::make_index_sequence<std::tuple_size_v<SceneKinds>>{}),
              "trace::SceneKinds must list the kinds of view::kPatchKinds, in that order");

}  // namespace surftrace::trace

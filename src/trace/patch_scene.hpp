// The patch list as an Embree 3 scene of user geometry: one geometry per patch kind.
#pragma once

#include <cstdint>
#include <memory>
#include <span>
#include <string>
#include <tuple>
#include <vector>

#include "build/patch_list.hpp"
#include "trace/patch_kinds.hpp"
#include "trace/ray.hpp"
#include "view/patch_kind.hpp"

namespace surftrace::trace {

// Hits name their kind in the shared vocabulary of the image channels.
using view::PatchKind;

// A hit in double precision, with the patch it belongs to.
struct SceneHit {
  PatchKind kind = PatchKind::None;
  std::uint32_t patch = 0;  // index within its kind
  PatchHit hit;
  bool valid() const { return kind != PatchKind::None; }
};

// The patches a scene holds, in the intersectors' own form, one KindPatches per row of
// SceneKinds (trace/patch_kinds.hpp). The SES holds the three kinds; the vdW and SAS
// surfaces (build::atomSpheres) hold spheres only.
struct ScenePatches {
  build::SurfaceParams params;  // what surface the patches make (which spheres clip which: layers.hpp)
  // Every atom (centre, vdW radius) when the caller gives them: the SES list holds spheres of
  // exposed atoms only, but buried atoms hide parts of them too (trace/layers.hpp).
  std::vector<glm::dvec4> atoms;
  ScenePlanes planes;  // the patches' plane spans point in here
  SceneKindPatches kinds;
  view::PatchIdOrder ids;

  // Patches hold spans into `planes`: moving keeps them valid, copying would not.
  ScenePatches() = default;
  ScenePatches(ScenePatches&&) = default;
  ScenePatches& operator=(ScenePatches&&) = default;
  ScenePatches(const ScenePatches&) = delete;
  ScenePatches& operator=(const ScenePatches&) = delete;

  // `centers` and `radii` (all the atoms, or none) only matter to transparency. `model`, when
  // given, adds the ball-and-stick model's balls and sticks (rows BallKind, StickKind).
  static ScenePatches fromPatchList(const build::PatchList& patches, std::span<const glm::dvec3> centers = {},
                                    std::span<const double> radii = {}, const build::BallStickModel* model = nullptr);

  template <class Kind> const KindPatches<Kind>& of() const { return std::get<KindPatches<Kind>>(kinds); }
  // f(const KindPatches<Kind>&) for every row, in SceneKinds order.
  template <class F> void forEachKind(F&& f) const {
    std::apply([&](const auto&... k) { (f(k), ...); }, kinds);
  }

  std::size_t size() const { return ids.total(); }
  // Global patch id (view::PatchIdOrder): spheres first, then tori, then concave triangles, ...,
  // then the model's balls and sticks.
  std::uint32_t globalId(PatchKind kind, std::uint32_t patch) const { return ids.globalId(kind, patch); }
  // The atom a hit belongs to: its sphere's atom, the nearer contact atom of a torus or
  // concave triangle (atomOf of the kind's intersector).
  std::uint32_t atomOf(const SceneHit& hit, const glm::dvec3& x) const;
  Bounds3d bounds() const;

  // The hit a plain loop over every patch finds (no BVH): the scene's test oracle.
  SceneHit intersectAll(const Ray& ray, double tMin, double tMax) const;
  // The double-precision hit on one given patch in (tMin, tMax].
  SceneHit intersectPatch(PatchKind kind, std::uint32_t patch, const Ray& ray, double tMin, double tMax) const;
};

// One Embree device (its thread pool and settings), created once and shared by the scenes of
// many frames (a trajectory builds a scene per frame). Copies share the device. Scenes built
// on one device must not be committed concurrently (errors are reported per device).
class EmbreeDevice {
 public:
  EmbreeDevice();
  struct Impl;
  const std::shared_ptr<Impl>& impl() const { return impl_; }

 private:
  std::shared_ptr<Impl> impl_;
};

class PatchScene {
 public:
  // A scene of the patches on `device` (a fresh device unless one is given).
  explicit PatchScene(ScenePatches patches, const EmbreeDevice& device = EmbreeDevice());
  ~PatchScene();
  PatchScene(const PatchScene&) = delete;
  PatchScene& operator=(const PatchScene&) = delete;

  const ScenePatches& patches() const { return patches_; }
  // patches().bounds(), made once with the scene: a frame asks for it (its ray offsets scale
  // with it), and walking every patch's box again costs a tenth of a 1024² SES frame.
  const Bounds3d& bounds() const { return bounds_; }
  double buildSeconds() const { return buildSeconds_; }

  // Nearest hit of up to 16 rays traced as one coherent Embree packet (valid[i] != 0 marks
  // the active lanes). Embree traverses with the rays rounded to float (after moving their
  // origins to the scene's box), while the intersectors work on the double rays and the
  // nearest hit is kept in double beside Embree's float tfar: hits are exact and ordered in
  // double, and do not depend on how far the camera is from the coordinate origin.
  void intersect16(const Ray (&rays)[16], const bool (&valid)[16], double tMin, SceneHit (&hits)[16]) const;
  SceneHit intersect1(const Ray& ray, double tMin, double tMax) const;
  // Every crossing of up to 16 rays with the surface (transparency), nearest first: lane i's
  // are layers[i·maxLayers, i·maxLayers + count[i]), at most the nearest maxLayers, seam
  // duplicates merged and the whole spheres' hidden parts left out (trace/layers.hpp); of each
  // ball and stick of the model only the nearest crossing, where the ray enters it. One
  // traversal per packet: the callbacks collect every root of every patch they are handed,
  // and shorten the ray to the farthest kept crossing once maxLayers are kept.
  void intersectLayers16(const Ray (&rays)[16], const bool (&valid)[16], std::size_t maxLayers,
                         std::span<SceneHit> layers, std::size_t (&count)[16]) const;
  std::vector<SceneHit> intersectLayers1(const Ray& ray, std::size_t maxLayers) const;
  bool occluded(const Ray& ray, double tMin, double tMax) const;

 private:
  struct Embree;
  ScenePatches patches_;
  std::unique_ptr<Embree> embree_;
  Bounds3d bounds_;
  double buildSeconds_ = 0.0;
};

}  // namespace surftrace::trace

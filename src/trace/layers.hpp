// Every crossing of a ray with the surface, in order (transparency): the layer list and the
// test that keeps a whole sphere's hit only where it lies on its convex patch.
#pragma once

#include <atomic>
#include <cstdint>
#include <memory>
#include <span>
#include <type_traits>
#include <vector>

#include <glm/vec3.hpp>
#include <glm/vec4.hpp>

#include "build/sphere_blockers.hpp"
#include "trace/patch_scene.hpp"

namespace surftrace::trace {

// Two hits closer than this along the ray (Å) are one crossing: where two patches meet at a
// seam, both report the point (their trimming tests overlap by kBoundaryTolerance on purpose,
// so that no ray slips through between them). The intersectors agree on a seam point to
// ~1e-10 Å (ORACLES D.1's quartic error) and the patches meet tangentially (SES, skin) or at
// a crease (vdW, SAS), so 1e-6 Å merges every seam duplicate of a ray that is not grazing
// (|cos| > 1e-4). Two true crossings closer than this, a ray that grazes the surface, count
// as one: the two layers would be one point anyway.
inline constexpr double kLayerMergeDistance = 1e-6;

// The whole spheres of a scene draw their hidden part too; SphereClip keeps a sphere's hit only
// on its convex patch: the test and its data are build::SphereBlockers (build/sphere_blockers.hpp),
// which the GL engine shares. The atoms are ScenePatches::atoms; without them the scene's own
// spheres stand in (complete for vdW and SAS, not for the SES: see sphere_blockers.hpp).
class SphereClip {
 public:
  SphereClip() = default;
  explicit SphereClip(const ScenePatches& patches);
  SphereClip(SphereClip&&) = default;
  SphereClip& operator=(SphereClip&&) = default;

  // Whether the hit x on sphere `sphere` (index among the scene's spheres) is on its patch.
  // Points within a relative kBoundaryTolerance of a grown neighbour count as outside it.
  bool onPatch(std::uint32_t sphere, const glm::dvec3& x) const;
  // How far (Å) the point x of sphere `sphere`, on its patch, is from the patch's edge
  // (build::convexPatchEdgeDistance).
  double edgeDistance(std::uint32_t sphere, const glm::dvec3& x) const;

 private:
  std::vector<glm::dvec4> spheres_;  // the scene's spheres: centre, radius ρ
  build::SphereBlockers blockers_;   // with every saddle arc (build::attachSaddleArcs)
  // Per sphere with arcs: whether its saddle arcs bound its kept part (build::freeEdgeCovered,
  // an O(blockers²) check), found when a hit on its free part first asks: 0 not yet, 1 no
  // (covered), 2 yes.
  // A frame's rays meet a fraction of the spheres; threads that race store the same answer.
  std::unique_ptr<std::atomic<std::uint8_t>[]> keptPartTest_;
};

// The crossings of one ray, nearest first, no two within kLayerMergeDistance (the nearer of
// two such is kept), at most `capacity` of them (the nearest).
class LayerList {
 public:
  LayerList() = default;
  LayerList(std::span<SceneHit> storage, double mergeT) : hits_(storage), mergeT_(mergeT) {}
  // Adds a crossing, merging it with one within mergeT (in units of t) of it.
  void insert(const SceneHit& hit);
  bool full() const { return count_ == hits_.size(); }
  std::size_t size() const { return count_; }
  const SceneHit& operator[](std::size_t i) const { return hits_[i]; }
  const SceneHit& back() const { return hits_[count_ - 1]; }

 private:
  std::span<SceneHit> hits_;
  std::size_t count_ = 0;
  double mergeT_ = 0.0;
};

// The most roots one patch can have along a ray (a torus: 4), with room for a root found again.
inline constexpr int kMaxRootsPerPatch = 8;

// Every hit on one patch in (tMin, tMax], ascending: f(const PatchHit&) for each. The ray comes
// with its unit direction (made once per ray), which every intersect() call here would make again.
template <class Patch, class F> void forEachRoot(const Patch& patch, const UnitRay& ray, double tMin, double tMax, F&& f) {
  for (int k = 0; k < kMaxRootsPerPatch; ++k) {
    const std::optional<PatchHit> h = intersect(patch, ray, tMin, tMax);
    if (!h || !(h->t > tMin)) return;
    f(*h);
    tMin = h->t;
  }
}
// A sphere's or a concave patch's roots do not depend on (tMin, tMax]: both come from one
// solve (allHits), the same hits the loop above finds with up to three.
template <class Patch, class F>
  requires std::is_same_v<Patch, SpherePatch> || std::is_same_v<Patch, ConcavePatch>
void forEachRoot(const Patch& patch, const UnitRay& ray, double tMin, double tMax, F&& f) {
  PatchHit hits[2];
  const int count = allHits(patch, ray, tMin, tMax, hits);
  for (int k = 0; k < count; ++k) f(hits[k]);
}

// The crossings of `ray` with a plain loop over every patch (no BVH): the test oracle of
// PatchScene::intersectLayers16, as ScenePatches::intersectAll is of the nearest hit.
std::vector<SceneHit> crossingsAll(const ScenePatches& patches, const SphereClip& clip, const Ray& ray,
                                   std::size_t maxLayers);

}  // namespace surftrace::trace

// Every crossing of a ray with the surface (layers.hpp).
#include "trace/layers.hpp"

#include <algorithm>
#include <cmath>
#include <limits>
#include <tuple>
#include <type_traits>
#include <unordered_map>

#include <glm/geometric.hpp>

namespace surftrace::trace {
namespace {

// Orders two hits at (nearly) one point independently of the order they were found in.
bool before(const SceneHit& a, const SceneHit& b) {
  return std::tie(a.hit.t, a.kind, a.patch) < std::tie(b.hit.t, b.kind, b.patch);
}

}  // namespace

SphereClip::SphereClip(const ScenePatches& patches) {
  const auto& row = patches.of<SphereKind>();
  std::vector<glm::dvec3> centers;
  std::vector<double> radii;
  for (const SpherePatch& s : row.patches) {
    spheres_.push_back(glm::dvec4(s.center, s.radius));
    centers.push_back(s.center);
    radii.push_back(s.radius);
  }
  blockers_ = build::sphereBlockers(patches.params, centers, radii, row.atoms, patches.atoms);
  // The saddles bound the kept parts of each sphere (--drop-cavities drops some: sphere_blockers.hpp).
  if (patches.params.surface != build::SurfaceKind::Ses || patches.atoms.empty()) return;
  const auto& tori = patches.of<TorusKind>();
  std::vector<build::SaddleArc> arcs;
  for (const TorusPatch& t : tori.patches) arcs.push_back({t.center, t.e1, t.e2, t.bigRadius, t.phiExtent});
  // build::addSaddleArcs would check every sphere now; most are never hit (onPatch checks).
  build::attachSaddleArcs(blockers_, row.atoms, arcs, tori.atoms);
  keptPartTest_ = std::make_unique<std::atomic<std::uint8_t>[]>(spheres_.size());
}

bool SphereClip::onPatch(std::uint32_t sphere, const glm::dvec3& x) const {
  const glm::dvec4 s = spheres_[sphere];
  // Most roots on a sphere are on its hidden part (inside a blocker): those need no saddle-arc
  // check, so the blockers go first and the check is made only for a sphere hit on its free part.
  if (!build::onConvexPatch(blockers_, sphere, glm::dvec3(s), s.w, x, kBoundaryTolerance, false)) return false;
  if (!keptPartTest_ || blockers_.arcBegin[sphere] == blockers_.arcBegin[sphere + 1]) return true;
  std::uint8_t state = keptPartTest_[sphere].load(std::memory_order_relaxed);
  if (state == 0) {
    state = build::freeEdgeCovered(blockers_, sphere, glm::dvec3(s), s.w + blockers_.grow) ? 1 : 2;
    keptPartTest_[sphere].store(state, std::memory_order_relaxed);
  }
  // A sphere whose free edges its saddles leave partly open (rare: --drop-cavities) tests
  // again with the kept parts, which repeats the blocker pass (the answer is the same).
  return state == 1 || build::onConvexPatch(blockers_, sphere, glm::dvec3(s), s.w, x, kBoundaryTolerance, true);
}

double SphereClip::edgeDistance(std::uint32_t sphere, const glm::dvec3& x) const {
  const glm::dvec4 s = spheres_[sphere];
  return build::convexPatchEdgeDistance(blockers_, sphere, glm::dvec3(s), s.w, x);
}

void LayerList::insert(const SceneHit& hit) {
  const double t = hit.hit.t;
  std::size_t pos = 0;
  while (pos < count_ && hits_[pos].hit.t <= t) ++pos;
  // The list keeps its entries more than mergeT apart, so only the neighbours can merge.
  if (pos > 0 && t - hits_[pos - 1].hit.t <= mergeT_) {
    if (before(hit, hits_[pos - 1])) hits_[pos - 1] = hit;
    return;
  }
  if (pos < count_ && hits_[pos].hit.t - t <= mergeT_) {
    hits_[pos] = hit;  // nearer than the one it merges with
    return;
  }
  if (pos == hits_.size()) return;  // beyond the nearest `capacity`
  if (count_ < hits_.size()) ++count_;
  for (std::size_t i = count_ - 1; i > pos; --i) hits_[i] = hits_[i - 1];
  hits_[pos] = hit;
}

std::vector<SceneHit> crossingsAll(const ScenePatches& patches, const SphereClip& clip, const Ray& ray,
                                   std::size_t maxLayers) {
  std::vector<SceneHit> storage(maxLayers);
  LayerList layers(storage, kLayerMergeDistance / glm::length(ray.dir));
  const UnitRay unitRay(ray);
  patches.forEachKind([&](const auto& k) {
    using Row = typename std::remove_reference_t<decltype(k)>::Row;
    constexpr PatchKind kind = Row::kind;
    for (std::uint32_t i = 0; i < k.patches.size(); ++i)
      if constexpr (isModelRow<Row>()) {  // opaque: where the ray enters it
        if (const auto h = intersect(k.patches[i], unitRay, 0.0, std::numeric_limits<double>::infinity()))
          layers.insert(SceneHit{kind, i, *h});
      } else forEachRoot(k.patches[i], unitRay, 0.0, std::numeric_limits<double>::infinity(), [&](const PatchHit& h) {
        if constexpr (kind == PatchKind::Convex)
          if (!clip.onPatch(i, ray.org + h.t * ray.dir)) return;
        layers.insert(SceneHit{kind, i, h});
      });
  });
  storage.resize(layers.size());
  return storage;
}

}  // namespace surftrace::trace

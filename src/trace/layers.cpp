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
  const build::SurfaceKind surface = patches.params.surface;
  const double rp = patches.params.probeRadius;
  grow_ = surface == build::SurfaceKind::Ses ? rp : 0.0;
  const auto& row = patches.of<SphereKind>();
  const std::size_t n = row.patches.size();
  std::vector<std::uint32_t> blockerAtom;  // to skip a sphere's own atom
  if (!patches.atoms.empty()) {
    const double h = surface == build::SurfaceKind::Vdw ? 0.0 : rp;
    for (std::uint32_t k = 0; k < patches.atoms.size(); ++k) {
      blockers_.push_back(glm::dvec4(glm::dvec3(patches.atoms[k]), patches.atoms[k].w + h));
      blockerAtom.push_back(k);
    }
  } else {
    for (std::uint32_t k = 0; k < n; ++k) {
      blockers_.push_back(glm::dvec4(row.patches[k].center, row.patches[k].radius + grow_));
      blockerAtom.push_back(row.atoms[k]);
    }
  }
  double largest = 0.0;
  for (const SpherePatch& s : row.patches) {
    spheres_.push_back(glm::dvec4(s.center, s.radius));
    largest = std::max(largest, s.radius + grow_);
  }
  for (const glm::dvec4& b : blockers_) largest = std::max(largest, b.w);
  begin_.assign(n + 1, 0);
  if (n == 0) return;
  // A hash grid of cell 2·(largest grown radius): grown spheres that meet lie in adjacent cells.
  const double cell = std::max(2.0 * largest, 1e-6);
  auto key = [&](const glm::ivec3& k) {
    return (static_cast<std::uint64_t>(static_cast<std::uint32_t>(k.x)) * 73856093u) ^
           (static_cast<std::uint64_t>(static_cast<std::uint32_t>(k.y)) * 19349663u) ^
           (static_cast<std::uint64_t>(static_cast<std::uint32_t>(k.z)) * 83492791u);
  };
  auto cellOf = [&](const glm::dvec3& c) { return glm::ivec3(glm::floor(c / cell)); };
  std::unordered_multimap<std::uint64_t, std::uint32_t> grid;
  grid.reserve(blockers_.size());
  for (std::uint32_t k = 0; k < blockers_.size(); ++k) grid.emplace(key(cellOf(glm::dvec3(blockers_[k]))), k);
  for (std::uint32_t i = 0; i < n; ++i) {
    const glm::dvec3 c = row.patches[i].center;
    const glm::ivec3 k = cellOf(c);
    const std::size_t first = others_.size();
    for (int dz = -1; dz <= 1; ++dz)
      for (int dy = -1; dy <= 1; ++dy)
        for (int dx = -1; dx <= 1; ++dx) {
          const glm::ivec3 kk = k + glm::ivec3(dx, dy, dz);
          const auto [lo, hi] = grid.equal_range(key(kk));
          for (auto it = lo; it != hi; ++it) {
            const std::uint32_t j = it->second;
            const glm::dvec3 cj(blockers_[j]);
            if (blockerAtom[j] == row.atoms[i] || cellOf(cj) != kk) continue;  // its own atom, a hash collision
            if (glm::length(cj - c) < row.patches[i].radius + grow_ + blockers_[j].w) others_.push_back(j);
          }
        }
    // Nearest first: the blocker that hides a point is most often a close one, and onPatch
    // stops at the first. Ties by index keep the order deterministic.
    const auto gap = [&](std::uint32_t j) { return glm::length(glm::dvec3(blockers_[j]) - c) - blockers_[j].w; };
    std::sort(others_.begin() + static_cast<std::ptrdiff_t>(first), others_.end(),
              [&](std::uint32_t a, std::uint32_t b) { return std::pair(gap(a), a) < std::pair(gap(b), b); });
    begin_[i + 1] = static_cast<std::uint32_t>(others_.size());
  }
}

bool SphereClip::onPatch(std::uint32_t sphere, const glm::dvec3& x) const {
  const glm::dvec4 s = spheres_[sphere];
  const glm::dvec3 c(s);
  if (!(s.w > 0.0)) return true;
  const glm::dvec3 y = c + ((s.w + grow_) / s.w) * (x - c);
  for (std::uint32_t k = begin_[sphere]; k < begin_[sphere + 1]; ++k) {
    const glm::dvec4 o = blockers_[others_[k]];
    if (glm::length(y - glm::dvec3(o)) < o.w * (1.0 - kBoundaryTolerance)) return false;
  }
  return true;
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
  patches.forEachKind([&](const auto& k) {
    using Row = typename std::remove_reference_t<decltype(k)>::Row;
    constexpr PatchKind kind = Row::kind;
    for (std::uint32_t i = 0; i < k.patches.size(); ++i)
      if constexpr (isModelRow<Row>()) {  // opaque: where the ray enters it
        if (const auto h = intersect(k.patches[i], ray, 0.0, std::numeric_limits<double>::infinity()))
          layers.insert(SceneHit{kind, i, *h});
      } else forEachRoot(k.patches[i], ray, 0.0, std::numeric_limits<double>::infinity(), [&](const PatchHit& h) {
        if constexpr (kind == PatchKind::Convex)
          if (!clip.onPatch(i, ray.org + h.t * ray.dir)) return;
        layers.insert(SceneHit{kind, i, h});
      });
  });
  storage.resize(layers.size());
  return storage;
}

}  // namespace surftrace::trace

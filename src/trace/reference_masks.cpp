// What the exact tracer records for `compare`'s masks (reference_masks.hpp).
#include "trace/reference_masks.hpp"

#include <algorithm>
#include <cmath>
#include <limits>
#include <type_traits>
#include <vector>

#include <glm/geometric.hpp>
#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>

namespace surftrace::trace {

SeamDistance::SeamDistance(const ScenePatches& patches) : patches_(&patches) {
  const KindPatches<SphereKind>& spheres = patches.of<SphereKind>();
  if (patches.params.surface != build::SurfaceKind::Ses) {
    blockers_.emplace(patches);
    return;
  }
  // An SES sphere's patch ends exactly on its tori's contact circles (far fewer than the
  // circles of every atom that comes near it, and no neighbour search).
  const KindPatches<TorusKind>& tori = patches.of<TorusKind>();
  std::vector<std::uint32_t> sphereOf(patches.params.atomCount, ~0u);
  for (std::uint32_t s = 0; s < spheres.atoms.size(); ++s)
    if (spheres.atoms[s] < sphereOf.size()) sphereOf[spheres.atoms[s]] = s;
  auto sphere = [&](std::uint32_t atom) { return atom < sphereOf.size() ? sphereOf[atom] : ~0u; };
  toriBegin_.assign(spheres.patches.size() + 1, 0);
  for (const glm::uvec2& a : tori.atoms)
    for (const std::uint32_t atom : {a.x, a.y})
      if (sphere(atom) != ~0u) ++toriBegin_[sphere(atom) + 1];
  for (std::size_t s = 0; s < spheres.patches.size(); ++s) toriBegin_[s + 1] += toriBegin_[s];
  tori_.resize(toriBegin_.back());
  std::vector<std::uint32_t> next(toriBegin_.begin(), toriBegin_.end() - 1);
  for (std::uint32_t t = 0; t < tori.atoms.size(); ++t)
    for (const std::uint32_t side : {0u, 1u})
      if (const std::uint32_t s = sphere(tori.atoms[t][side]); s != ~0u) tori_[next[s]++] = 2 * t + side;
}

double SeamDistance::sphereDistance(std::uint32_t sphere, const glm::dvec3& x) const {
  if (blockers_) return blockers_->edgeDistance(sphere, x);
  const KindPatches<TorusKind>& tori = patches_->of<TorusKind>();
  double d = std::numeric_limits<double>::infinity();
  for (std::uint32_t k = toriBegin_[sphere]; k < toriBegin_[sphere + 1]; ++k)
    d = std::min(d, contactCircleDistance(tori.patches[tori_[k] / 2], (tori_[k] & 1u) != 0, x));
  return d;
}

double SeamDistance::operator()(const SceneHit& hit, const glm::dvec3& x) const {
  double d = std::numeric_limits<double>::quiet_NaN();
  patches_->forEachKind([&](const auto& k) {
    using Row = typename std::remove_reference_t<decltype(k)>::Row;
    if (Row::kind != hit.kind) return;
    if constexpr (isModelRow<Row>())
      return;
    else if constexpr (std::is_same_v<Row, SphereKind>)
      d = sphereDistance(hit.patch, x);
    else
      d = boundaryDistance(k.patches[hit.patch], x);
  });
  return d;
}

namespace {

struct Corner {
  bool hit = false;
  glm::dvec3 x{0.0}, normal{0.0};
};

// The nearest hit of the ray through every pixel corner (sx, sy integers), row by row.
std::vector<Corner> traceCorners(const PatchScene& scene, const view::Camera& camera) {
  const int columns = camera.width + 1, rows = camera.height + 1;
  std::vector<Corner> corners(static_cast<std::size_t>(columns) * static_cast<std::size_t>(rows));
  const view::Camera::Frame frame = camera.frame();
  tbb::parallel_for(tbb::blocked_range<int>(0, rows), [&](const tbb::blocked_range<int>& r) {
    for (int y = r.begin(); y < r.end(); ++y)
      for (int x0 = 0; x0 < columns; x0 += 16) {
        Ray rays[16];
        bool valid[16];
        for (int j = 0; j < 16; ++j) {
          valid[j] = x0 + j < columns;
          rays[j] = frame.ray(x0 + j, y);
        }
        SceneHit hits[16];
        scene.intersect16(rays, valid, 0.0, hits);
        for (int j = 0; j < 16 && valid[j]; ++j) {
          Corner& c = corners[static_cast<std::size_t>(y) * static_cast<std::size_t>(columns) + static_cast<std::size_t>(x0 + j)];
          c.hit = hits[j].valid();
          if (!c.hit) continue;
          c.x = rays[j].org + hits[j].hit.t * rays[j].dir;
          c.normal = hits[j].hit.normal;
        }
      }
  });
  return corners;
}

// Whether the surface between two hits, each with its unit normal, is not one smooth piece.
bool jumps(const glm::dvec3& a, const glm::dvec3& na, const glm::dvec3& b, const glm::dvec3& nb) {
  const glm::dvec3 chord = b - a;
  const double length = glm::length(chord);
  return length > 0.0 &&
         (std::abs(glm::dot(na, chord)) > kSmoothChordSine * length || std::abs(glm::dot(nb, chord)) > kSmoothChordSine * length);
}

}  // namespace

void markPixelEdges(const PatchScene& scene, const view::Camera& camera, view::FrameBuffers& f) {
  const std::vector<Corner> corners = traceCorners(scene, camera);
  const view::Camera::Frame frame = camera.frame();
  const std::size_t columns = static_cast<std::size_t>(camera.width) + 1;
  tbb::parallel_for(tbb::blocked_range<int>(0, camera.height), [&](const tbb::blocked_range<int>& r) {
    for (int y = r.begin(); y < r.end(); ++y)
      for (int x = 0; x < camera.width; ++x) {
        const std::size_t p = static_cast<std::size_t>(y) * static_cast<std::size_t>(camera.width) + static_cast<std::size_t>(x);
        const bool hit = f.kind[p] != 0;
        const Ray ray = frame.ray(x + 0.5, y + 0.5);
        const glm::dvec3 at = ray.org + static_cast<double>(f.depth[p]) * ray.dir;
        const glm::dvec3 normal(f.normal[3 * p], f.normal[3 * p + 1], f.normal[3 * p + 2]);
        for (const std::size_t c : {static_cast<std::size_t>(y) * columns + static_cast<std::size_t>(x),
                                    static_cast<std::size_t>(y) * columns + static_cast<std::size_t>(x) + 1,
                                    static_cast<std::size_t>(y + 1) * columns + static_cast<std::size_t>(x),
                                    static_cast<std::size_t>(y + 1) * columns + static_cast<std::size_t>(x) + 1}) {
          const Corner& corner = corners[c];
          if (corner.hit != hit) f.flags[p] |= view::kPixelSilhouette;
          else if (hit && jumps(at, normal, corner.x, corner.normal)) f.flags[p] |= view::kPixelOcclusion;
        }
      }
  });
}

}  // namespace surftrace::trace

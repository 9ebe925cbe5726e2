// The mesh's Embree scene and its drawing through a camera (mesh_scene.hpp).
#include "trace/mesh_scene.hpp"

#include <algorithm>
#include <cmath>
#include <limits>
#include <mutex>
#include <stdexcept>
#include <string>

#include <embree3/rtcore.h>
#include <glm/geometric.hpp>
#include <tbb/parallel_for.h>

namespace surftrace::trace {

struct MeshScene::Embree {
  RTCDevice device = nullptr;
  RTCScene scene = nullptr;
  std::mutex errorMutex;
  std::string error;

  ~Embree() {
    if (scene) rtcReleaseScene(scene);
    if (device) rtcReleaseDevice(device);
  }
  static void onError(void* self, RTCError code, const char* message) {
    auto* e = static_cast<Embree*>(self);
    std::lock_guard lock(e->errorMutex);
    if (e->error.empty()) e->error = "Embree error " + std::to_string(static_cast<int>(code)) + ": " + (message ? message : "");
  }
  void check(const char* what) {
    std::lock_guard lock(errorMutex);
    if (!error.empty()) throw std::runtime_error(std::string(what) + ": " + error);
  }
};

MeshScene::MeshScene(build::mesh::TriangleMesh mesh) : mesh_(std::move(mesh)), embree_(std::make_unique<Embree>()) {
  if (mesh_.triangles.empty()) throw std::invalid_argument("the mesh has no triangles to draw");
  if (mesh_.positions.size() >= std::numeric_limits<std::uint32_t>::max())
    throw std::invalid_argument("the mesh has more vertices than 32-bit indices hold");
  embree_->device = rtcNewDevice(nullptr);
  if (!embree_->device)
    throw std::runtime_error("Embree: cannot create a device (error " + std::to_string(rtcGetDeviceError(nullptr)) + ")");
  rtcSetDeviceErrorFunction(embree_->device, &Embree::onError, embree_.get());
  embree_->scene = rtcNewScene(embree_->device);
  // Robust traversal is watertight: a ray through a shared edge or vertex hits one of the
  // triangles around it, so a closed mesh shows no pinholes that the exact surface has not.
  rtcSetSceneFlags(embree_->scene, RTC_SCENE_FLAG_ROBUST);
  RTCGeometry g = rtcNewGeometry(embree_->device, RTC_GEOMETRY_TYPE_TRIANGLE);
  auto* vertices = static_cast<float*>(
      rtcSetNewGeometryBuffer(g, RTC_BUFFER_TYPE_VERTEX, 0, RTC_FORMAT_FLOAT3, 3 * sizeof(float), mesh_.positions.size()));
  auto* indices = static_cast<unsigned*>(
      rtcSetNewGeometryBuffer(g, RTC_BUFFER_TYPE_INDEX, 0, RTC_FORMAT_UINT3, 3 * sizeof(unsigned), mesh_.triangles.size()));
  embree_->check("creating the mesh's Embree geometry");
  for (std::size_t v = 0; v < mesh_.positions.size(); ++v)
    for (int k = 0; k < 3; ++k) vertices[3 * v + static_cast<std::size_t>(k)] = static_cast<float>(mesh_.positions[v][k]);
  for (std::size_t t = 0; t < mesh_.triangles.size(); ++t)
    for (int k = 0; k < 3; ++k) indices[3 * t + static_cast<std::size_t>(k)] = mesh_.triangles[t][k];
  rtcCommitGeometry(g);
  rtcAttachGeometry(embree_->scene, g);
  rtcReleaseGeometry(g);
  rtcCommitScene(embree_->scene);
  embree_->check("building the mesh's Embree scene");
}

MeshScene::~MeshScene() = default;

MeshHit MeshScene::intersect(const Ray& ray) const {
  RTCIntersectContext context;
  rtcInitIntersectContext(&context);
  RTCRayHit rh{};
  rh.ray.org_x = static_cast<float>(ray.org.x), rh.ray.org_y = static_cast<float>(ray.org.y);
  rh.ray.org_z = static_cast<float>(ray.org.z);
  rh.ray.dir_x = static_cast<float>(ray.dir.x), rh.ray.dir_y = static_cast<float>(ray.dir.y);
  rh.ray.dir_z = static_cast<float>(ray.dir.z);
  rh.ray.tnear = 0.0f;
  rh.ray.tfar = std::numeric_limits<float>::infinity();
  rh.ray.mask = ~0u;
  rh.hit.geomID = RTC_INVALID_GEOMETRY_ID;
  rtcIntersect1(embree_->scene, &context, &rh);
  MeshHit hit;
  if (rh.hit.geomID == RTC_INVALID_GEOMETRY_ID) return hit;
  hit.triangle = rh.hit.primID;
  const glm::uvec3 tri = mesh_.triangles[hit.triangle];
  const glm::dvec3 &v0 = mesh_.positions[tri.x], &v1 = mesh_.positions[tri.y], &v2 = mesh_.positions[tri.z];
  // Möller and Trumbore, "Fast, minimum storage ray/triangle intersection", in double.
  const glm::dvec3 e1 = v1 - v0, e2 = v2 - v0;
  const glm::dvec3 p = glm::cross(ray.dir, e2);
  const double det = glm::dot(e1, p);
  double t = rh.ray.tfar, u = rh.hit.u, v = rh.hit.v;
  // Edge-on (the ray in the triangle's plane) the double solve is no better than Embree's.
  if (std::abs(det) > 1e-12 * glm::length(e1) * glm::length(e2) * glm::length(ray.dir)) {
    const glm::dvec3 s = ray.org - v0, q = glm::cross(s, e1);
    t = glm::dot(e2, q) / det;
    u = glm::dot(s, p) / det;
    v = glm::dot(ray.dir, q) / det;
  }
  hit.t = t;
  const glm::dvec3 face = glm::cross(e1, e2);
  const double faceLength = glm::length(face);
  hit.faceNormal = faceLength > 0.0 ? face / faceLength : glm::dvec3(0.0);
  hit.normal = hit.faceNormal;
  if (!mesh_.normals.empty()) {
    const glm::dvec3 n = (1.0 - u - v) * mesh_.normals[tri.x] + u * mesh_.normals[tri.y] + v * mesh_.normals[tri.z];
    const double len = glm::length(n);
    if (len > 0.0) hit.normal = n / len;
  }
  return hit;
}

// The point of triangle abc nearest to p: Ericson, "Real-Time Collision Detection", 5.1.5
// (the Voronoi regions of the corners, then the edges, then the face).
glm::dvec3 closestOnTriangle(const glm::dvec3& p, const glm::dvec3& a, const glm::dvec3& b, const glm::dvec3& c) {
  const glm::dvec3 ab = b - a, ac = c - a, ap = p - a;
  const double d1 = glm::dot(ab, ap), d2 = glm::dot(ac, ap);
  if (d1 <= 0.0 && d2 <= 0.0) return a;
  const glm::dvec3 bp = p - b;
  const double d3 = glm::dot(ab, bp), d4 = glm::dot(ac, bp);
  if (d3 >= 0.0 && d4 <= d3) return b;
  const double vc = d1 * d4 - d3 * d2;
  if (vc <= 0.0 && d1 >= 0.0 && d3 <= 0.0) return a + (d1 / (d1 - d3)) * ab;
  const glm::dvec3 cp = p - c;
  const double d5 = glm::dot(ab, cp), d6 = glm::dot(ac, cp);
  if (d6 >= 0.0 && d5 <= d6) return c;
  const double vb = d5 * d2 - d1 * d6;
  if (vb <= 0.0 && d2 >= 0.0 && d6 <= 0.0) return a + (d2 / (d2 - d6)) * ac;
  const double va = d3 * d6 - d5 * d4;
  if (va <= 0.0 && d4 - d3 >= 0.0 && d5 - d6 >= 0.0) return b + ((d4 - d3) / ((d4 - d3) + (d5 - d6))) * (c - b);
  const double denom = 1.0 / (va + vb + vc);
  if (!std::isfinite(denom)) return a;  // degenerate: its corners bound it
  return a + ab * (vb * denom) + ac * (vc * denom);
}

namespace {
// What a closest-point query carries: the mesh, the query point in double, the best so far.
struct NearestQuery {
  const build::mesh::TriangleMesh* mesh;
  glm::dvec3 x;
  double best;
};
// Embree's boxes come from float vertices: a margin over their rounding keeps a triangle whose
// float box lies just beyond the double distance from being culled.
double floatMargin(const glm::dvec3& x, double radius) {
  const double scale = std::max({std::abs(x.x), std::abs(x.y), std::abs(x.z)}) + radius;
  return 1e-6 * scale + 1e-9;
}
bool nearestTriangle(RTCPointQueryFunctionArguments* args) {
  auto* q = static_cast<NearestQuery*>(args->userPtr);
  const glm::uvec3 t = q->mesh->triangles[args->primID];
  const glm::dvec3 at = closestOnTriangle(q->x, q->mesh->positions[t.x], q->mesh->positions[t.y], q->mesh->positions[t.z]);
  const double d = glm::length(at - q->x);
  if (!(d < q->best)) return false;
  q->best = d;
  args->query->radius = static_cast<float>(d + floatMargin(q->x, d));
  return true;
}
}  // namespace

double MeshScene::distance(const glm::dvec3& x, double radius) const {
  NearestQuery q{&mesh_, x, std::numeric_limits<double>::infinity()};
  RTCPointQuery query;
  query.x = static_cast<float>(x.x), query.y = static_cast<float>(x.y), query.z = static_cast<float>(x.z);
  query.time = 0.0f;
  query.radius = static_cast<float>(radius + floatMargin(x, radius));
  RTCPointQueryContext context;
  rtcInitPointQueryContext(&context);
  rtcPointQuery(embree_->scene, &query, &context, &nearestTriangle, &q);
  return q.best;
}

view::FrameBuffers drawMesh(const MeshScene& scene, const view::Camera& camera) {
  view::FrameBuffers frame;
  frame.reset(camera.width, camera.height);
  const view::Camera::Frame f = camera.frame();
  const int w = camera.width;
  tbb::parallel_for(0, camera.height, [&](int y) {
    for (int x = 0; x < w; ++x) {
      const Ray ray = f.ray(x + 0.5, y + 0.5);
      const MeshHit hit = scene.intersect(ray);
      if (!hit.valid()) continue;
      const std::size_t p = static_cast<std::size_t>(y) * static_cast<std::size_t>(w) + static_cast<std::size_t>(x);
      frame.depth[p] = static_cast<float>(hit.t);
      frame.viewZ[p] = static_cast<float>(glm::dot(ray.org - f.eye, f.forward) + hit.t * glm::dot(ray.dir, f.forward));
      for (int k = 0; k < 3; ++k) frame.normal[3 * p + static_cast<std::size_t>(k)] = static_cast<float>(hit.normal[k]);
      frame.patchId[p] = hit.triangle;
    }
  });
  frame.rays = frame.pixels();
  return frame;
}

}  // namespace surftrace::trace

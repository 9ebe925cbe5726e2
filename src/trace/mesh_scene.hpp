// A triangle mesh as an Embree scene of triangles, drawn exactly through a camera's
// pixel-centre rays: the buffers another renderer's mesh would give along a reference's rays.
#pragma once

#include <cstdint>
#include <limits>
#include <memory>

#include <glm/vec3.hpp>

#include "build/mesh/triangle_mesh.hpp"
#include "trace/ray.hpp"
#include "view/camera.hpp"
#include "view/frame_buffers.hpp"

namespace surftrace::trace {

struct MeshHit {
  double t = std::numeric_limits<double>::infinity();  // along the ray, in its parametrisation
  glm::dvec3 normal{0.0};      // unit: the vertex normals interpolated, or the face normal
  glm::dvec3 faceNormal{0.0};  // unit, by the triangle's winding (counter-clockwise: outward)
  std::uint32_t triangle = ~0u;
  bool valid() const { return triangle != ~0u; }
};

class MeshScene {
 public:
  // std::invalid_argument for an empty mesh or one with more vertices than 32-bit indices hold;
  // std::runtime_error on an Embree error.
  explicit MeshScene(build::mesh::TriangleMesh mesh);
  ~MeshScene();
  MeshScene(const MeshScene&) = delete;
  MeshScene& operator=(const MeshScene&) = delete;

  const build::mesh::TriangleMesh& mesh() const { return mesh_; }
  // The nearest hit in (0, ∞). Embree finds the triangle with float rays and vertices (robust,
  // watertight traversal); its distance, barycentrics and normal are then computed again in
  // double from the mesh's own positions, so that t does not carry float's rounding of the
  // ray's origin (far from the mesh for an orthographic camera) or of the vertices.
  MeshHit intersect(const Ray& ray) const;
  // The distance from x to the nearest point of the mesh (over every triangle, in double):
  // Embree's closest-point query, searching within `radius` Å of x (an upper bound known
  // beforehand keeps the search local); +inf when no triangle lies that near.
  double distance(const glm::dvec3& x, double radius) const;

 private:
  struct Embree;
  build::mesh::TriangleMesh mesh_;
  std::unique_ptr<Embree> embree_;
};

// What the mesh shows through `camera`'s pixel-centre rays (the very rays Camera::Frame::ray
// gives, row 0 at the top): depth (ray distance, Å), viewZ and world normals where a ray hits,
// and in patchId the triangle hit (~0u for a miss); kind, atom ids and colour stay as a miss
// leaves them. Rows run in parallel (TBB).
// The point of triangle abc nearest to p.
glm::dvec3 closestOnTriangle(const glm::dvec3& p, const glm::dvec3& a, const glm::dvec3& b, const glm::dvec3& c);

view::FrameBuffers drawMesh(const MeshScene& scene, const view::Camera& camera);

}  // namespace surftrace::trace

// What a GL program draws of a set of spheres, from its two matrices alone: one ray per pixel
// centre through inverse(P·V), the nearest sphere, and that hit as window depth, view z, ray
// distance and normals. glm and the standard library only (never SurfTrace's camera): the
// independent side of the tests of `compare`'s foreign buffers (issue 20).
#pragma once

#include <bit>
#include <cmath>
#include <cstdio>
#include <fstream>
#include <limits>
#include <string>
#include <vector>

#include <glm/geometric.hpp>
#include <glm/mat4x4.hpp>
#include <glm/matrix.hpp>
#include <glm/vec3.hpp>
#include <glm/vec4.hpp>

namespace surftrace::test {

struct GlSphereBuffers {
  int width = 0, height = 0;
  // Row 0 at the top (image order); pixel p = y·width + x.
  std::vector<double> window;      // GL window depth, glDepthRange(0, 1); background 1.0
  std::vector<double> viewZ;       // −z of the hit in the view frame (Å); background +inf
  std::vector<double> ray;         // from the eye (orthographic: its plane) along the ray (Å); background +inf
  std::vector<double> edge;        // |distance of the ray from the hit sphere's centre − r| (Å); +inf on a miss
  std::vector<glm::dvec3> worldNormal, viewNormal;  // zero on background
  std::size_t pixels() const { return static_cast<std::size_t>(width) * static_cast<std::size_t>(height); }
  bool hit(std::size_t p) const { return std::isfinite(ray[p]); }
};

// `spheres`: centre xyz and radius w.
inline GlSphereBuffers drawSpheresGl(int width, int height, const glm::dmat4& view, const glm::dmat4& projection,
                                     const std::vector<glm::dvec4>& spheres) {
  constexpr double kInf = std::numeric_limits<double>::infinity();
  GlSphereBuffers b;
  b.width = width, b.height = height;
  const std::size_t n = b.pixels();
  b.window.assign(n, 1.0), b.viewZ.assign(n, kInf), b.ray.assign(n, kInf), b.edge.assign(n, kInf);
  b.worldNormal.assign(n, glm::dvec3(0.0)), b.viewNormal.assign(n, glm::dvec3(0.0));
  const glm::dmat4 clipFromWorld = projection * view, worldFromClip = glm::inverse(clipFromWorld);
  const bool perspective = projection[2][3] != 0.0;  // glFrustum's bottom row (0, 0, −1, 0)
  const glm::dvec3 eye(glm::inverse(view)[3]);
  auto unproject = [&](double x, double y, double z) {
    const glm::dvec4 q = worldFromClip * glm::dvec4(x, y, z, 1.0);
    return glm::dvec3(q) / q.w;
  };
  for (int y = 0; y < height; ++y)
    for (int x = 0; x < width; ++x) {
      // Window y grows upwards: image row 0 is the top, ndc y = +1.
      const double ndcX = 2.0 * (x + 0.5) / width - 1.0, ndcY = 1.0 - 2.0 * (y + 0.5) / height;
      const glm::dvec3 start = unproject(ndcX, ndcY, -1.0);
      const glm::dvec3 dir = glm::normalize(unproject(ndcX, ndcY, 1.0) - start);
      double best = kInf, edge = kInf;
      glm::dvec4 hitSphere(0.0);
      for (const glm::dvec4& s : spheres) {
        const glm::dvec3 oc = glm::dvec3(s) - start;
        const double along = glm::dot(oc, dir), perp2 = glm::dot(oc, oc) - along * along;
        if (perp2 > s.w * s.w) continue;
        const double t = along - std::sqrt(s.w * s.w - perp2);
        if (t >= 0.0 && t < best) best = t, hitSphere = s, edge = s.w - std::sqrt(perp2);
      }
      if (!std::isfinite(best)) continue;
      const std::size_t p = static_cast<std::size_t>(y) * static_cast<std::size_t>(width) + static_cast<std::size_t>(x);
      const glm::dvec3 hit = start + best * dir;
      const glm::dvec4 clip = clipFromWorld * glm::dvec4(hit, 1.0);
      b.window[p] = 0.5 * clip.z / clip.w + 0.5;
      b.viewZ[p] = -(view * glm::dvec4(hit, 1.0)).z;
      b.ray[p] = perspective ? glm::length(hit - eye) : b.viewZ[p];
      b.edge[p] = edge;
      b.worldNormal[p] = (hit - glm::dvec3(hitSphere)) / hitSphere.w;
      b.viewNormal[p] = glm::dmat3(view) * b.worldNormal[p];
    }
  return b;
}

// A little-endian float PFM ("Pf" one channel, "PF" three) of `values` (channels per pixel,
// rows in the order given): the file's first row is `values`' first, which PFM defines as the
// bottom row. Written byte by byte, without OpenImageIO.
inline void writePfm(const std::string& path, int width, int height, int channels, const std::vector<float>& values) {
  static_assert(std::endian::native == std::endian::little, "the scale -1.0 below says little-endian");
  std::ofstream out(path, std::ios::binary);
  out << (channels == 3 ? "PF" : "Pf") << "\n" << width << " " << height << "\n-1.0\n";
  out.write(reinterpret_cast<const char*>(values.data()), static_cast<std::streamsize>(values.size() * sizeof(float)));
}

}  // namespace surftrace::test

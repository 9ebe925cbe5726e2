// The SES for a growing probe tends to the boundary of the convex hull of the atoms' spheres.
// Oracle: for atoms of one radius r the hull of the balls is the parallel body P ⊕ rB of the
// polytope P = conv(centres), whose area is Steiner's formula
//   S(P ⊕ rB) = S(P) + r Σ_edges ℓ_e θ_e + 4π r²     (θ_e: the angle between the normals of
// the edge's two faces), with P from CGAL's convex_hull_3 (exact predicates). CGAL is GPL and
// is linked into this test only.
#include <gmock/gmock.h>
#include <gtest/gtest.h>

#include <cmath>
#include <map>
#include <numbers>
#include <stdexcept>
#include <utility>
#include <vector>

#include <CGAL/Exact_predicates_inexact_constructions_kernel.h>
#include <CGAL/Surface_mesh.h>
#include <CGAL/convex_hull_3.h>

#include "build/io/molecule.hpp"
#include "build/ses/contour_buildup.hpp"
#include "build/ses/surface_area.hpp"

namespace surftrace::build {
namespace {

using Kernel = CGAL::Exact_predicates_inexact_constructions_kernel;
using Point = Kernel::Point_3;
using Mesh = CGAL::Surface_mesh<Point>;

// Area of the convex hull of balls of radius r about `centers`, by Steiner's formula.
double hullOfBallsArea(const std::vector<glm::dvec3>& centers, double r) {
  std::vector<Point> points;
  for (const glm::dvec3& c : centers) points.emplace_back(c.x, c.y, c.z);
  Mesh hull;
  CGAL::convex_hull_3(points.begin(), points.end(), hull);
  auto vec = [&](Mesh::Vertex_index v) {
    const Point& p = hull.point(v);
    return glm::dvec3(p.x(), p.y(), p.z());
  };
  // Triangle normals (area-weighted) per face.
  std::map<Mesh::Face_index, glm::dvec3> normal;
  double faces = 0.0;
  for (Mesh::Face_index f : hull.faces()) {
    std::vector<glm::dvec3> v;
    for (Mesh::Vertex_index x : hull.vertices_around_face(hull.halfedge(f))) v.push_back(vec(x));
    glm::dvec3 n(0.0);
    for (std::size_t k = 1; k + 1 < v.size(); ++k) {
      const glm::dvec3 a = v[k] - v[0], b = v[k + 1] - v[0];
      n += glm::dvec3(a.y * b.z - a.z * b.y, a.z * b.x - a.x * b.z, a.x * b.y - a.y * b.x);
    }
    faces += 0.5 * std::sqrt(n.x * n.x + n.y * n.y + n.z * n.z);
    normal[f] = n;
  }
  double edges = 0.0;
  for (Mesh::Edge_index e : hull.edges()) {
    const Mesh::Halfedge_index h = hull.halfedge(e);
    const glm::dvec3 a = normal.at(hull.face(h)), b = normal.at(hull.face(hull.opposite(h)));
    const glm::dvec3 cross(a.y * b.z - a.z * b.y, a.z * b.x - a.x * b.z, a.x * b.y - a.y * b.x);
    const double theta =
        std::atan2(std::sqrt(cross.x * cross.x + cross.y * cross.y + cross.z * cross.z),
                   a.x * b.x + a.y * b.y + a.z * b.z);
    const glm::dvec3 d = vec(hull.source(h)) - vec(hull.target(h));
    edges += std::sqrt(d.x * d.x + d.y * d.y + d.z * d.z) * theta;
  }
  return faces + r * edges + 4.0 * std::numbers::pi * r * r;
}

// 1CRN's 327 atom centres, every radius 1.7 Å (Steiner's formula needs one radius).
TEST(SesHull, AreaTendsToTheHullOfTheBallsAsTheProbeGrows) {
  const Molecule m = readMolecule(SURFTRACE_TEST_DATA "/structures/1crn.pdb");
  const double r = 1.7;
  const std::vector<double> radii(m.size(), r);
  const double hull = hullOfBallsArea(m.centers, r);
  ASSERT_GT(hull, 1000.0);
  // The gap shrinks as 1/rp (the probe's sagitta over a concave region of width w is
  // w²/(8 rp)): measured 38.7 Å² at 100 Å, 0.0454 at 1e5 Å. The error bar at each probe is
  // twice that rate from the gap at 100 Å, plus 1e-5 of the area for rounding, the bound
  // maxProbeRadius promises (its rounding, ~0.1 ε (rp/r)², is 5e-6 at the limit).
  const double limit = maxProbeRadius(radii);
  EXPECT_EQ(limit, 0x1p19 * r);
  double gap100 = 0.0;
  for (const double rp : {1e2, 1e3, 1e4, 1e5, limit}) {
    const PatchList patches = buildSes(m.centers, radii, SesParams{rp});
    const double ses = computeAreas(patches).sesTotal();
    const double gap = std::abs(ses - hull);
    if (rp == 1e2) {
      gap100 = gap;
      EXPECT_LT(gap, 0.05 * hull);
    } else {
      EXPECT_LT(gap, 2.0 * gap100 * 1e2 / rp + 1e-5 * hull)
          << "rp " << rp << ": SES " << ses << " Å², hull of the balls " << hull << " Å²";
    }
  }
  // Past the limit: an error that names it and says why, not an area.
  try {
    buildSes(m.centers, radii, SesParams{1e9});
    ADD_FAILURE() << "a probe of 1e9 Å was accepted";
  } catch (const std::invalid_argument& e) {
    EXPECT_THAT(e.what(), ::testing::HasSubstr("probe radius 1e+09 Å is above the limit of 891290 Å"));
    EXPECT_THAT(e.what(), ::testing::HasSubstr("double-precision rounding"));
  }
}

}  // namespace
}  // namespace surftrace::build

// Exact area of a sphere minus a union of caps, by Gauss–Bonnet (ORACLES D.2, A.5).
//
// One routine serves the SAS/convex area of an atom (caps: its neighbours' extended
// spheres), and the clipped concave triangle (caps: three hemispheres beyond the edges
// and the self-intersection caps).
#pragma once

#include <vector>

#include <glm/vec3.hpp>

namespace surftrace::build {

// The open cap {u on the unit sphere : u·axis > cosRadius}; axis is unit.
struct Cap {
  glm::dvec3 axis;
  double cosRadius;
};

// Scratch buffers, reused between calls so the per-atom hot path does not allocate.
struct SphericalRegionScratch {
  struct Interval { double begin, end; int cap; };
  struct Arc { glm::dvec3 begin, end; int cap; };
  std::vector<Cap> caps;
  std::vector<Interval> intervals;
  std::vector<Arc> arcs;         // after a call: the region's boundary arcs (cap: index into caps)
  std::vector<int> fullCircles;  // after a call: caps whose whole circle bounds the region
  std::vector<int> parent;
};

struct SphericalRegion {
  double area;             // of the unit sphere minus the caps, in [0, 4π]
  glm::dvec3 vectorArea;   // W = ∫ u dΩ over the region (for volumes, ORACLES D.2)
  int boundaryCycles;
};

// Area (unit sphere) of the sphere minus the union of `caps`. Caps that are empty
// (cosRadius >= 1) are ignored; a cap with cosRadius <= −1 covers everything.
SphericalRegion sphereMinusCaps(const std::vector<Cap>& caps, SphericalRegionScratch& scratch);

}  // namespace surftrace::build

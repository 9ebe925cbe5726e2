// The topology of the exact SES: Euler characteristic and genus of each component, from its patches.
#pragma once

#include <cstdint>
#include <vector>

#include "build/patch_list.hpp"

namespace surftrace::build {

struct ComponentTopology {
  long long euler = 0;      // χ = V − E + F of the closed surface: 2 for a sphere, 0 for a torus
  long long genus = 0;      // (2 − χ) / 2: the handles (tunnels through the body)
  double residual = 0.0;    // |Gauss–Bonnet sum / 2π − χ|: rounding, ~1e-12 when the patches are sound
  // False where χ is not known: the sum is off an integer, or odd, or a crease runs into a
  // torus edge away from a cusp (a concave patch overlapping a torus; tori are not clipped
  // against other probes). Two tori whose probes overlap leave no such trace: where they do,
  // the patches' χ can exceed the true surface's (whose neck there is a handle).
  bool resolved = true;
};

// Per SES component (index = label, as computeAreas), by Gauss–Bonnet over the closed
// piecewise-smooth surface: 2πχ = ∫K dA + ∮ κg ds over its creases + Σ the angle defects of
// its corners. ∫K is exact from the patches (convex A/r², concave A/rp², a torus patch
// −Φ(sin θb − sin θa) over its SES intervals); tangent-continuous seams (contact circles,
// torus meridians) add nothing. Creases are where concave patches are clipped against each
// other (each side's κg = −cos β per radian of the crease circle); their ends, and the cusps
// of spindle tori (cone points of angle Φ·sin θc), are singular corners, whose defect is 2π
// less the interior angles of every face that meets there (found by position). A label is
// what the builder joined: a full-ring spindle torus's two cones are two surfaces under one
// label (χ 4 for two atoms). Empty for any surface but the SES.
std::vector<ComponentTopology> surfaceTopology(const PatchList& patches);

}  // namespace surftrace::build

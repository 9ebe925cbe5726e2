// The SES's outer surfaces alone (`--drop-cavities`): a patch list without its buried cavities.
#pragma once

#include "build/patch_list.hpp"

namespace surftrace::build {

// The outer surfaces alone (components with a positive volume, computeAreas, 0 always
// among them): buried cavities' inner SES components dropped, the outer ones renumbered in
// order, clipping planes remapped. A convex patch exposed to an outer surface and to a
// cavity is kept whole with the outer label (its area then includes the cavity side).
PatchList outerComponent(const PatchList& patches);

}  // namespace surftrace::build

// The SES's outer surfaces alone (`--drop-cavities`), or its buried cavities alone (`--cavities`).
#pragma once

#include "build/patch_list.hpp"

namespace surftrace::build {

// The outer surfaces alone (components with a positive volume, computeAreas, 0 always
// among them): buried cavities' inner SES components dropped, the outer ones renumbered in
// order, clipping planes remapped. A convex patch exposed to an outer surface and to a
// cavity is kept whole with the outer label (its area then includes the cavity side).
PatchList outerComponent(const PatchList& patches);

// The cavities alone (`render --cavities`, the inverse): the patches labelled by a component
// with a negative volume, renumbered in order. A convex patch labelled by an outer surface
// (the atom of a one-atom wall between the outside and a cavity) is left out, since it is
// drawn as its whole sphere: the cavity then shows a hole where such a wall stands. An empty
// list when there is no cavity.
PatchList cavityComponents(const PatchList& patches);

// The cavities alone (`render --cavities`, the inverse): the patches labelled by a component
// with a negative volume, renumbered in order. A convex patch labelled by an outer surface
// (the atom of a one-atom wall between the outside and a cavity) is left out, since it is
// drawn as its whole sphere: the cavity then shows a hole where such a wall stands. An empty
// list when there is no cavity.
PatchList cavityComponents(const PatchList& patches);

}  // namespace surftrace::build

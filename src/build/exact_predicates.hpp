// Exact signs for the SES vertex decisions where double precision cannot be sure
// (Lindow et al. 2010, Sect. 4.1; ORACLES A.2): the filter is the double computation with
// an error bound, the fallback evaluates the same quantity in rational arithmetic (GMP)
// from the double inputs, so the decision is that of the real numbers the inputs denote.
#pragma once

#include <glm/vec3.hpp>

namespace surftrace::build {

// The extended spheres of a sorted atom triple a < b < c (centres, radii r + rp).
struct ProbeTriple {
  glm::dvec3 ca, cb, cc;
  double Ra, Rb, Rc;
};

// Sign of h²·det² where h is the exact height of the probe positions above the plane of the
// centres (ORACLES A.2): > 0 two probe positions, 0 one tangential position, < 0 none.
// Collinear centres (det = 0) give 0.
int exactProbeHeightSign(const ProbeTriple& t);

// Sign of |p − c|² − threshold for the exact probe position p (plus: + h m, m along
// (cb − ca) × (cc − ca)). The triple must have two probe positions (exactProbeHeightSign > 0).
int exactProbeSide(const ProbeTriple& t, bool plus, const glm::dvec3& c, double threshold);

}  // namespace surftrace::build

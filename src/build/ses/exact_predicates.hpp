// Exact signs for the SES vertex decisions where double precision cannot be sure
// (Lindow et al. 2010, Sect. 4.1; ORACLES A.2): the filter is the double computation with
// an error bound, the fallback evaluates the same quantity in rational arithmetic (GMP)
// from the double inputs, so the decision is that of the real numbers the inputs denote.
#pragma once

#include <optional>

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

// The probe positions of a triple computed with 256-bit floating point from the exact
// rational q, H and n, then rounded to double (each coordinate within one ulp of the exact
// value); nothing for collinear centres or when the spheres share no point or only one
// (exactProbeHeightSign <= 0). For triples whose double computation is ill-conditioned:
// nearly collinear centres, or a probe that just fits (h near 0).
struct PreciseProbes {
  glm::dvec3 plus, minus;
  double h;
};
std::optional<PreciseProbes> preciseProbePositions(const ProbeTriple& t);

// Sign of |cb − ca|² − (Ra + sign·Rb)² (sign = +1 or −1): whether two spheres are farther
// apart than the sum (or the difference) of their radii.
int exactDistanceSign(const glm::dvec3& ca, const glm::dvec3& cb, double Ra, double Rb, int sign);

// For the circle where the spheres (cx, Rx) and (cy, Ry) cut, the sign of the mean over the
// circle's points x of |x − ck|² − Rk²: d²(|cx − ck|² + Rx² − Rk²) + (d² + Rx² − Ry²)(cy − cx)·(cx − ck),
// d = |cy − cx| (ORACLES A.1: centre cx + t·axis, radius² Rx² − t²). When no point of the
// circle crosses sphere k, this sign says on which side of it the whole circle lies.
int exactCircleSphereSign(const glm::dvec3& cx, double Rx, const glm::dvec3& cy, double Ry, const glm::dvec3& ck,
                          double Rk);

// Sign of (p − o)·(q − o), exactly: whether o lies strictly between p and q (< 0) on a line
// through them.
int exactDotSign(const glm::dvec3& o, const glm::dvec3& p, const glm::dvec3& q);

}  // namespace surftrace::build

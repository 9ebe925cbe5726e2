// SES cap pre-tests: the single-precision SIMD (SSE2/AVX2) kernels and the double-precision inside test.
#pragma once

#include <cstddef>

#include <glm/vec3.hpp>

#include "build/ses/exact_predicates.hpp"
#include "build/ses/ses_types.hpp"

namespace surftrace::build::detail {

// Which neighbour caps may meet circle a (bits in cand), which clearly cross it (bits in
// clear); false if one clearly buries it. AVX2 when the CPU has it, else SSE2: same bits.
bool classifyCircle(const Neighbourhood& nb, std::size_t a, Word* cand, Word* clear, std::size_t words);

// Whether both vertices of circles a and b clearly lie inside some neighbour cap.
bool clearlyInsideBoth(const Neighbourhood& nb, std::size_t a, std::size_t b);

// Cospherical atoms (ORACLES E.6): a probe position p lies on sphere m, a tie, when
// |p − c_m|² = R_m² to a relative kTie, i.e. |p − c_m| = R_m to 1e-10 relative: the tolerance
// of ORACLES A.2 and of the test oracle. A probe position is exact to ~1e-15 relative
// (1e-12 Å even 1e4 Å from the origin, ORACLES E.14), far inside it; and atoms placed with
// the 1e-3 Å resolution of PDB files meet a fourth sphere within 3e-10 Å only by symmetry.
constexpr double kTie = 2e-10;

// Which of the probe positions p (plus) and q (minus) of `triple` lie inside (bits 0, 1) or
// within the tie tolerance of (bits 2, 3) a sphere of (m1 & m2) other than skip1, skip2.
// Decided for the exact positions: where the double |p − c|² lies within `slack` of a
// threshold, by exactProbeSide. Bits 4, 5: which lie closer than R²(1 + nearBand) to the
// centre of such a sphere (a double hint, no exact fallback).
int insideMask(const Neighbourhood& nb, const Word* m1, const Word* m2, std::size_t words, std::size_t skip1,
               std::size_t skip2, const ProbeTriple& triple, const glm::dvec3& p, const glm::dvec3& q, double slack,
               double nearBand);

}  // namespace surftrace::build::detail

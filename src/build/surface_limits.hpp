// The limits of a surface's parameters, in one place: the request (SurfaceRequest, the --shrink
// and --probe options), the builders and the patch list's checks (PatchList::validate, the .stp
// reader) all take them from here, so that a value one of them takes the others take too.
#pragma once

namespace surftrace::build {

// The largest probe radius double precision serves: 2^19 times the smallest atom radius.
// Patch areas are differences of terms of order rp² that cancel to areas of order r²; their
// rounding error grows as about 0.1 ε (rp/r)² of the total (measured on 1CRN against the
// convex hull of its balls, tests/build/ses_hull_test.cpp: 7e-6 at rp = 5.9e5 r, 9e-4 at
// 5.9e6 r, where answers of 3e17 Å² begin further on), so the limit keeps it under 1e-5.
// Past it the SES differs from the convex hull of the atoms by less than that anyway.
inline constexpr double kMaxProbeToRadius = 0x1p19;

// The smallest shrink factor served. The weights r²/s grow as 1/s, and the skin's areas and
// volume (double precision) lose their digits as they do: measured on 1VIS (2488 atoms), the
// volume is continuous in s down to 1e-4 (74,552 Å³ at 1e-3, 74,906 at 1e-4, converging
// linearly in s) and wrong from 1e-5 (+1.5 %; negative at 1e-7); 1CRN holds down to 1e-7. A
// factor of 10 below what held on 1VIS, for larger molecules; at 1e-3 the skin's volume is
// within 0.1 % of its s -> 0 limit.
// buildMss and MssBuilder throw std::invalid_argument below it.
inline constexpr double kMinShrinkFactor = 1e-3;
inline constexpr double kMaxShrinkFactor = 1.0;

// The shrink factors served: s in [kMinShrinkFactor, 1] (NaN is not). What --shrink takes,
// what buildSurface builds, and what a patch list of any kind may store.
constexpr bool validShrinkFactor(double s) { return s >= kMinShrinkFactor && s <= kMaxShrinkFactor; }
// At s = 1 the skin is exactly the union of the van der Waals balls (μ_X = ν_X: only the atoms'
// own power cells keep a volume, each holding its atom's ball), built (buildSurface) and stored (a Vdw list with
// shrinkFactor 1) as the vdW spheres.
constexpr bool shrinkIsUnionOfBalls(double s) { return s >= kMaxShrinkFactor; }
// The factors of a skin made of mixed cells: what buildMss and MssBuilder take and what an Mss
// patch list stores, [kMinShrinkFactor, 1).
constexpr bool skinBuiltWithCells(double s) { return validShrinkFactor(s) && !shrinkIsUnionOfBalls(s); }

}  // namespace surftrace::build

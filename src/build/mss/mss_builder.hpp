// Molecular skin surface patches from feasible power cells and the mixed complex
// (Edelsbrunner 1999; Lindow et al. 2010, Sect. 4.2-4.3; ORACLES C).
#pragma once

#include <cstdint>
#include <memory>
#include <span>

#include <glm/vec3.hpp>

#include "build/patch_list.hpp"
#include "build/surface_limits.hpp"

namespace surftrace::build {

struct MssParams {
  double shrink = 0.5;  // s in [kMinShrinkFactor, 1): skinBuiltWithCells (surface_limits.hpp)
  // Scales the feasibility radius ρ_i (>= 1). Only tests change it: at large values every
  // cell is the whole power cell, and the list must not change (feasible cells are exact).
  double feasibleScale = 1.0;
};

// Builds the MSS patch list of atoms (centres, radii >= 0, validated by the caller) for the
// shrink factor s: weighted points (c_i, r_i²/s); per atom its feasible power cell (the power
// cell restricted to where the skin can be: neighbours whose power plane comes within
// ρ_i = √(w_i + (1 − s) w_max / s) of the atom, a provable superset since every skin point of
// a mixed cell μ_X has its Voronoi part v with π_i(v) <= (1 − s) w_max / s for i ∈ X); then
// every Voronoi face, edge and vertex of the cell whose atoms all exceed i (so each Delaunay
// simplex is emitted once, by its lowest atom) becomes a patch when its mixed cell holds skin
// (decided exactly per cell from the Minkowski structure: the skin function over
// μ_X = (1 − s) δ_X + s ν_X ranges over [s·d²(z_X, ν_X) − (1 − s) max|δ_X − z_X|² + w_X,
// s·max|ν_X − z_X|² − (1 − s) d²(z_X, δ_X) + w_X]).
//
// Order: patches by kind (convex, edge, face, concave: the simplex's size), then by their
// lowest atom, then by the other atoms, so each kind is one range (mssKindRange). The list
// is identical (order and bits) for any number of threads. Throws std::invalid_argument for
// s outside [kMinShrinkFactor, 1) (skinBuiltWithCells). Fills params.surface, shrinkFactor and atomCount.
PatchList buildMss(std::span<const glm::dvec3> centers, std::span<const double> radii, const MssParams& params);

struct MssUpdateStats {
  std::size_t moved = 0;       // atoms whose centre changed
  std::size_t recomputed = 0;  // atoms whose cells were rebuilt
  std::size_t exactSides = 0;  // plane-side decisions that needed rational arithmetic
  bool full = false;
};

// The MSS builder that keeps its per-atom results, so that frames in which few atoms move
// recompute only the cells within reach of them. A cell is a pure function of the atoms
// within ρ_i + √(ρ_i² + w_max − w_i) of its atom, so after update() the patch list equals
// buildMss() for the new centres, array for array and bit for bit. Cells are kept in fixed
// blocks of atoms; a block with any atom in reach of a moved atom (old or new place) is rebuilt.
class MssBuilder {
 public:
  MssBuilder();
  ~MssBuilder();
  MssBuilder(MssBuilder&&) noexcept;
  MssBuilder& operator=(MssBuilder&&) noexcept;

  const PatchList& build(std::span<const glm::dvec3> centers, std::span<const double> radii, const MssParams& params);
  // Moves atoms moved[k] to newCenters[k]; radii and s unchanged. Throws std::logic_error
  // before build(), std::invalid_argument for a bad index, a length mismatch or a NaN.
  const PatchList& update(std::span<const std::uint32_t> moved, std::span<const glm::dvec3> newCenters);
  // A whole frame: the atoms whose centre differs in any bit are the moved ones.
  const PatchList& update(std::span<const glm::dvec3> centers);

  const PatchList& patches() const;
  // Moves the patch list out; the builder needs build() again before update().
  PatchList takePatches();
  const MssUpdateStats& lastUpdate() const;

 private:
  struct State;
  std::unique_ptr<State> s_;
};

}  // namespace surftrace::build

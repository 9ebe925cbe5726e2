// Atoms a union-of-balls surface can leave out before it is built: balls inside another ball
// (they add nothing, exactly) and near-coincident balls (merged within a stated distance).
#pragma once

#include <cstddef>
#include <cstdint>
#include <optional>
#include <span>
#include <vector>

#include <glm/vec3.hpp>

namespace surftrace::build {

// Balls closer than this to a kept ball are always merged into it: |c_i − c_j| + |r_i − r_j|,
// the Hausdorff distance of the two balls, in Å. Contour-buildup cannot resolve atoms that
// close: three atoms within 1e-8 Å gave a wrong SES (concave area 5.3 Å² instead of 0, SAS 0
// with four), and clusters of 20 atoms within 1e-6 Å a wrong SAS in 2 of 30 random trials.
// No input format resolves it either: PDB, PQR and mmCIF print 1e-3 Å, GRO and XTC 1e-2 Å,
// and float32 (DCD) positions near 100 Å are 7.6e-6 Å apart.
inline constexpr double kMinMergeDistance = 1e-5;

// A near-coincident cluster: more than kMaxClusterAtoms kept atoms whose centres lie within
// kClusterRadius of one of them. Real structures have one atom there (covalent bonds are
// 0.74 Å and longer); a pair is let through, for the clash of a badly modelled file or a
// Drude particle beside its atom. Closer atoms cost the builders work that grows with the
// cluster's size k as about k^2.5 (every triple among them and their neighbours is nearly
// degenerate and decided exactly): 1,000 clusters of 8 atoms within 1e-4 Å took 11 s for the
// SES, 16 within 0.1 Å 12 s, against 0.03 s for 1,000 lone atoms, and the cost only fades
// for spacings beyond about 0.3 Å. Such a cluster is refused (buildSurface) with the merge
// distance that resolves it, so that the work stays linear in the atom count however the
// atoms cluster: a pair costs at most ~7 lone atoms (bench/cluster_bench.cpp).
inline constexpr double kClusterRadius = 0.5;
inline constexpr std::size_t kMaxClusterAtoms = 2;

struct CullParams {
  // Added to every radius for the containment test: the probe radius for the SES and SAS
  // (their extended balls), 0 for the van der Waals surface.
  double inflate = 0.0;
  // Whether balls inside another are left out: exact for the SES, SAS and vdW surface (ORACLES
  // E.2, E.3), not for the skin, whose shape a contained ball can change (E.3).
  bool dropContained = true;
  // Balls within this distance (Å, as kMinMergeDistance; at least that) of a kept ball merge.
  double mergeWithin = kMinMergeDistance;
};

// The first near-coincident cluster found, for the error that names it.
struct NearCluster {
  std::uint32_t atom = 0;     // the kept atom it was found at (input index)
  std::size_t atoms = 0;      // input atoms whose centres lie within kClusterRadius of it
  std::size_t kept = 0;       // of which kept (neither contained nor merged)
  glm::dvec3 center{0.0};     // mean of their centres
  // The largest |c − c_atom| + |r − r_atom| among the kept ones, Å: merging within twice
  // this would leave one of them.
  double spread = 0.0;
  // The kept atoms in any such cluster (this one the first found), and the largest spread of
  // the kept atoms about each of them: merging within twice that leaves one atom of each
  // cluster (of up to 64 atoms in a cluster beyond this one: for larger ones, a lower bound).
  std::size_t crowdedAtoms = 0;
  double largestSpread = 0.0;
};

enum class AtomFate : std::uint8_t { Kept, Contained, Merged };

struct CullResult {
  std::size_t inputCount = 0;
  std::vector<std::uint32_t> kept;  // input indices, ascending
  std::vector<AtomFate> fate;       // per input atom
  std::size_t contained = 0;        // left out: inside another atom's (inflated) ball
  std::uint32_t containedExample = 0, containerExample = 0;
  std::size_t merged = 0;           // left out: within mergeWithin of a kept atom's ball
  double mergedDistance = 0.0;      // the largest distance of a merged ball from its keeper's
  std::uint32_t mergedExample = 0, keeperExample = 0;  // that atom and its keeper
  std::optional<NearCluster> cluster;  // set when a cluster remains among the kept atoms
  // Work done (candidate atoms looked at, both passes): at most 64 per atom, however the
  // atoms are placed. For tests.
  std::size_t candidates = 0;

  bool keepsAll() const { return kept.size() == inputCount; }
};

// Decides, atom by atom in order of decreasing radius (then increasing index), whether an
// atom's ball lies inside a kept one (touching allowed, decided exactly on the inflated radii
// as contour-buildup decides burial, so equal balls keep the lowest index) or within
// mergeWithin of one; the atom is left out then, kept otherwise. Each atom looks at no more
// than 64 earlier atoms near it, largest first, so the cost is linear in the atom count
// whatever their placement; an atom whose container lies beyond them is kept (the builders
// bury it themselves: still exact, only slower). Then looks for a near-coincident cluster
// among the kept atoms (CullResult::cluster), also in linear time.
// Radii >= 0 and centres finite (validated by the caller); mergeWithin >= kMinMergeDistance.
CullResult cullAtoms(std::span<const glm::dvec3> centers, std::span<const double> radii, const CullParams& params);

}  // namespace surftrace::build

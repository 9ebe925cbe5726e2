// Covalent bonds of a molecule (the ball-and-stick model's sticks): the file's own bond records
// where it has them, distances and covalent radii elsewhere. Computed once per topology.
#pragma once

#include <cstdint>
#include <span>
#include <string>
#include <vector>

#include <glm/vec2.hpp>
#include <glm/vec3.hpp>

#include "build/io/molecule.hpp"

namespace surftrace::build {

// The default slack of the distance rule, Å: atoms i and j bond when
//   |c_i − c_j| < r_cov,i + r_cov,j + tolerance
// (r_cov: gemmi's covalent radii, Cordero et al. 2008), as VMD and MDAnalysis guess bonds.
inline constexpr double kBondTolerance = 0.4;
// Atoms closer than this (Å) are not bonded (duplicates, MDAnalysis's lower bound).
inline constexpr double kMinBondLength = 0.1;

// The covalent radius of an element symbol ("C", "Fe"), Å; carbon's for an unknown or empty one
// (XYZR files name no elements).
double covalentRadius(const std::string& element);

// Bonds by distance alone: pairs i < j with kMinBondLength <= d < r_i + r_j + tolerance and not
// at two different alternate locations (altLocs[i], altLocs[j] both set and unequal; ' ' or an
// empty span: none). Linear time through the neighbour grid. Ascending (i, then j).
std::vector<glm::uvec2> distanceBonds(std::span<const glm::dvec3> centers, std::span<const double> covalentRadii,
                                      std::span<const char> altLocs, double tolerance = kBondTolerance);

// The molecule's bonds, pairs of atom indices i < j, ascending. Where the file has bond records
// (PDB CONECT: wwPDB writes them for hetero groups, their links and disulfides, never for the
// bonds inside standard residues), a pair of two HETATM atoms that the records name bonds iff a
// record says so; every other pair bonds by distance (distanceBonds) or by a record. mmCIF's
// _struct_conn links (between residues only) are added to the distance bonds. Records
// naming atoms the selection left out are dropped. Throws std::invalid_argument for a tolerance
// outside [0, 2] Å.
std::vector<glm::uvec2> moleculeBonds(const Molecule& molecule, double tolerance = kBondTolerance);

// The ball-and-stick model the renderers draw beside a patch list (opaque; kinds Ball and Stick
// of view/patch_kind.hpp): ball i is atom i's (centre, ballScale × its radius), stick k the
// capped cylinder of radius stickRadius from bonds[k].x's centre to bonds[k].y's. Plain data.
struct BallStickModel {
  std::vector<glm::dvec3> centers;
  std::vector<double> ballRadii;
  std::vector<glm::uvec2> bonds;
  double stickRadius = 0.15;

  bool empty() const { return centers.empty(); }
};
// Throws std::invalid_argument unless ballScale > 0 and stickRadius > 0 (finite), and every bond
// names two different atoms of `centers`.
BallStickModel ballStickModel(std::span<const glm::dvec3> centers, std::span<const double> radii,
                              std::span<const glm::uvec2> bonds, double ballScale, double stickRadius);

}  // namespace surftrace::build

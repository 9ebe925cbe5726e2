// Covalent bonds of a molecule: bond records, then distances and covalent radii (bonds.hpp).
#include "build/bonds.hpp"

#include <algorithm>
#include <cmath>
#include <stdexcept>
#include <unordered_map>

#include <gemmi/elem.hpp>

#include "build/neighbour_grid.hpp"

namespace surftrace::build {

double covalentRadius(const std::string& element) {
  const gemmi::Element e(element.empty() ? std::string("C") : element);
  return e.elem == gemmi::El::X ? gemmi::Element("C").covalent_r() : e.covalent_r();
}

std::vector<glm::uvec2> distanceBonds(std::span<const glm::dvec3> centers, std::span<const double> covalentRadii,
                                      std::span<const char> altLocs, double tolerance) {
  // The grid's neighbour rule is d < r_i + r_j + 2 rp: with rp = tolerance / 2 it returns a
  // superset of the bonded pairs (the sum is re-evaluated below, as written in bonds.hpp).
  NeighbourGrid grid(centers.size());
  grid.build(centers, covalentRadii, tolerance / 2);
  std::vector<glm::uvec2> bonds;
  std::vector<std::uint32_t> near;
  for (std::uint32_t i = 0; i < centers.size(); ++i) {
    near.clear();
    grid.neighbours(i, near);
    for (std::uint32_t j : near) {
      if (j <= i) continue;
      if (!altLocs.empty() && altLocs[i] != ' ' && altLocs[j] != ' ' && altLocs[i] != altLocs[j]) continue;
      const glm::dvec3 d = centers[i] - centers[j];
      const double d2 = d.x * d.x + d.y * d.y + d.z * d.z;
      const double s = covalentRadii[i] + covalentRadii[j] + tolerance;
      if (d2 < s * s && d2 >= kMinBondLength * kMinBondLength) bonds.push_back({i, j});
    }
  }
  return bonds;
}

std::vector<glm::uvec2> moleculeBonds(const Molecule& molecule, double tolerance) {
  if (!(tolerance >= 0.0 && tolerance <= 2.0))
    throw std::invalid_argument("bond tolerance " + std::to_string(tolerance) + " Å must be in [0, 2]");
  const std::size_t n = molecule.size();
  std::vector<double> radii(n);
  std::vector<char> altLocs(n, ' ');
  std::unordered_map<int, std::uint32_t> bySerial;
  for (std::size_t i = 0; i < n; ++i) {
    const AtomRecord* atom = i < molecule.atoms.size() ? &molecule.atoms[i] : nullptr;
    radii[i] = covalentRadius(atom ? atom->element.str() : std::string());
    if (atom) {
      altLocs[i] = atom->altLoc;
      bySerial.emplace(atom->serial, static_cast<std::uint32_t>(i));
    }
  }
  // The records, as index pairs of atoms that were kept; which HETATM atoms they name.
  std::vector<glm::uvec2> records;
  std::vector<char> recorded(n, 0);
  for (const auto& [a, b] : molecule.bondRecords) {
    const auto i = bySerial.find(a), j = bySerial.find(b);
    if (i == bySerial.end() || j == bySerial.end()) continue;
    records.push_back({std::min(i->second, j->second), std::max(i->second, j->second)});
    // PDB CONECT lists every bond of a hetero group; mmCIF's _struct_conn only the links between
    // residues, whose own bonds come from the chemical component dictionary: distance then.
    if (molecule.format == MoleculeFormat::Pdb)
      for (std::uint32_t k : {i->second, j->second})
        if (molecule.atoms[k].hetatm) recorded[k] = 1;
  }
  std::vector<glm::uvec2> bonds = distanceBonds(molecule.centers, radii, altLocs, tolerance);
  std::erase_if(bonds, [&](const glm::uvec2& b) { return recorded[b.x] && recorded[b.y]; });
  bonds.insert(bonds.end(), records.begin(), records.end());
  const auto less = [](const glm::uvec2& a, const glm::uvec2& b) { return a.x != b.x ? a.x < b.x : a.y < b.y; };
  std::sort(bonds.begin(), bonds.end(), less);
  bonds.erase(std::unique(bonds.begin(), bonds.end()), bonds.end());
  return bonds;
}

BallStickModel ballStickModel(std::span<const glm::dvec3> centers, std::span<const double> radii,
                              std::span<const glm::uvec2> bonds, double ballScale, double stickRadius) {
  if (!(ballScale > 0.0 && std::isfinite(ballScale)))
    throw std::invalid_argument("ball scale " + std::to_string(ballScale) + " must be a finite number > 0");
  if (!(stickRadius > 0.0 && std::isfinite(stickRadius)))
    throw std::invalid_argument("stick radius " + std::to_string(stickRadius) + " must be a finite number > 0");
  if (radii.size() != centers.size()) throw std::invalid_argument("ball-and-stick model: one radius per centre needed");
  BallStickModel m;
  m.centers.assign(centers.begin(), centers.end());
  m.ballRadii.reserve(radii.size());
  for (double r : radii) m.ballRadii.push_back(ballScale * r);
  for (const glm::uvec2& b : bonds)
    if (b.x == b.y || b.x >= centers.size() || b.y >= centers.size())
      throw std::invalid_argument("ball-and-stick model: bond " + std::to_string(b.x) + "-" + std::to_string(b.y) +
                                  " does not join two of the " + std::to_string(centers.size()) + " atoms");
  m.bonds.assign(bonds.begin(), bonds.end());
  m.stickRadius = stickRadius;
  return m;
}

}  // namespace surftrace::build

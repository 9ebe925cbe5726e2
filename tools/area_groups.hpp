// `area --per atom|residue|chain`: per-atom areas summed over residues or chains, relative SASA
// against a published maximum-ASA table, and their rows as a table, CSV or JSON.
#pragma once

#include <cstddef>
#include <optional>
#include <string>
#include <string_view>
#include <vector>

#include <nlohmann/json.hpp>

#include "surftrace/molecule.hpp"

namespace surftrace::tools {

enum class AreaLevel { Atom, Residue, Chain };
AreaLevel areaLevelNamed(const std::string& name);  // "atom", "residue", "chain" (checked by CLI)

// A named per-atom column of areas in Å² ("sas", "ses" or "mss"), in the molecule's atom order.
struct AreaColumn {
  std::string name;
  const std::vector<double>* perAtom;
};

// A residue (consecutive atoms with the same chain, residue name, number and insertion code, as
// FreeSASA and MDAnalysis split them, so that numbers that wrap in large MD systems still part
// residues) or a chain (all atoms of one chain id, in the order chains first appear).
struct AreaGroup {
  std::string chain, residue;  // residue: empty for a chain
  int residueNumber = 0;
  char insertionCode = ' ';
  std::string altLocs;  // the alternate-location letters of the atoms kept, in order; "" for none
  std::vector<std::size_t> atoms;
  std::size_t residueCount = 0;  // a chain's residues
};
std::vector<AreaGroup> residueGroups(const build::Molecule& molecule);
std::vector<AreaGroup> chainGroups(const build::Molecule& molecule);

// The theoretical maximum accessible surface area (Å²) of one of the 20 standard amino acids in
// a Gly-X-Gly tripeptide, from Tien et al. 2013; nullopt for every other residue name.
std::optional<double> maxAsaTien2013(std::string_view residue);
// What the relative column is divided by, as the output names it.
inline constexpr const char* kMaxAsaTable =
    "Tien et al. 2013, theoretical maximum ASA (PLoS ONE 8(11): e80635, Table 1)";
// The CSV/JSON name of the relative SASA: the table is in the name, so a CSV alone says it.
inline constexpr const char* kRelativeSasColumn = "relative_sas_tien2013";

// The rows of one level: the header (CSV column names or a table's heading), then rows, each
// optionally preceded by a frame number and time (trajectories).
struct AreaRows {
  AreaLevel level = AreaLevel::Residue;
  std::string format;                // "table" or "csv"
  std::vector<AreaColumn> columns;   // sas + ses, or mss
  bool withFrame = false;

  void printHeader() const;
  void printRows(const build::Molecule& molecule, const std::vector<AreaGroup>& groups, std::size_t frame = 0,
                 double time = 0.0) const;
  // The rows as JSON objects.
  nlohmann::json json(const build::Molecule& molecule, const std::vector<AreaGroup>& groups) const;
  bool relative() const;  // whether the rows hold a relative SASA (per residue, with an SAS column)
};

// The groups of a level (per atom: one group per atom).
std::vector<AreaGroup> areaGroups(const build::Molecule& molecule, AreaLevel level);

// The residue names among `groups` with no maximum ASA, each once, in order: what the note on
// the empty relative values names.
std::vector<std::string> residuesWithoutMaxAsa(const std::vector<AreaGroup>& groups);

}  // namespace surftrace::tools

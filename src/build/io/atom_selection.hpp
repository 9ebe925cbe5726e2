// Atom selections for the command line (`--select`, `trajectory --flexible`): which atoms of a molecule a
// user means, in the subset of MDAnalysis's selection language (MDAnalysis.core.selection)
// that users type.
#pragma once

#include <cstdint>
#include <string>
#include <vector>

#include "build/io/molecule.hpp"

namespace surftrace::build {

// Terms, read as MDAnalysis's select_atoms reads them:
//   name CA CB          atom names          } several values select their union; values are
//   resname HIS GLU     residue names       } fnmatch patterns (* ? [abc], case-sensitive)
//   chain A B           chain identifiers (also `chainID`; a PSF, which has segments but no
//                       chains, answers with its segment ids)
//   segid 4AKE          segment identifiers (AtomRecord::segid, as MDAnalysis reads them)
//   element C N         element symbols, as the records hold them ("C", "Fe")
//   resid 10-20 45      residue numbers; ranges 10-20, 10:20, "10 to 20" include both ends;
//                       52A names an insertion code (as in MDAnalysis, plain 52 then means
//                       52 without one)
//   index 0-9           positions in the topology file, numbered from 0
//   atom 1-250          positions in the topology file, numbered from 1 (MDAnalysis: bynum;
//                       `bynum` is accepted too)
//   protein, backbone   residues named as proteins in MDAnalysis (ProteinSelection), and
//                       their atoms N CA C O (BackboneSelection)
//   water               residues named as water in MDAnalysis 2.9 (WaterSelection)
//   all                 every atom
// combined with `not` (binding tightest), then `and` and `or` read left to right with equal
// precedence, as MDAnalysis does ("a or b and c" is "(a or b) and c"), and parentheses.
// Commas separate whole expressions and select their union, loosest of all (the older
// "chain A, resid 120-160").
//
// Throws std::invalid_argument quoting the selection with a caret under the word it could not
// read: an unknown keyword (an MDAnalysis keyword this subset lacks is named as such), a
// keyword without values, a value that is not a number or a range, a missing or dangling
// `and`/`or`, unbalanced parentheses; an index or atom range beyond the molecule's file
// (naming its atom count); and a selection that selects no atom (with what each term
// matched and what the molecule holds instead).
// Returns the selected atoms' indices in `molecule`, ascending.
std::vector<std::uint32_t> selectAtoms(const Molecule& molecule, const std::string& selection);

}  // namespace surftrace::build

// Atom selections for the command line (`trajectory --flexible`): which atoms of a molecule a
// user means by residues, chains, names or positions in the file.
#pragma once

#include <cstdint>
#include <string>
#include <vector>

#include "build/io/molecule.hpp"

namespace surftrace::build {

// Terms separated by commas select the union of what each selects; a term is a keyword and
// one or more values separated by spaces:
//   resid 10-20 45      residue numbers (ranges inclusive; negative numbers as in MD files)
//   chain A B           chain identifiers (a PSF's segment ids)
//   resname HIS GLU     residue names
//   name CA CB          atom names
//   atom 1-250          positions in the topology file, numbered from 1 (also called `index`)
// e.g. "chain A, resid 120-160". Throws std::invalid_argument naming the term and what is
// wrong: an unknown keyword, a value that is not a number or range, or a term that selects no
// atom of `molecule` (with what the molecule holds instead).
// Returns the selected atoms' indices in `molecule`, ascending.
std::vector<std::uint32_t> selectAtoms(const Molecule& molecule, const std::string& selection);

}  // namespace surftrace::build

// A number per atom from the user (--values FILE): RMSF, conservation, an area, for the `value`
// colour scheme.
#pragma once

#include <cstddef>
#include <string>
#include <vector>

#include "build/io/molecule.hpp"

namespace surftrace::view {

// The values a CSV file gives the atoms of `molecule`. The file has a header, then one row per
// atom or per residue, in one of two forms (fields separated by commas, spaces around them
// ignored; blank lines and lines starting with # skipped):
//   atom,NAME                  the atom's 0-based index in the structure file (AtomRecord::
//                              fileIndex: MDAnalysis's atom.index), then its value
//   chain,resid[,icode],NAME   every atom of that residue (an empty chain or icode: none)
// NAME, the last column's header, names the values (the legend's label). A value that is empty,
// `nan` or `NA` means "no value" (the atom keeps the scheme's missing colour).
struct AtomValues {
  std::string path;
  std::string label;            // the value column's header
  std::vector<double> values;   // one per atom of the molecule; NaN: no value
  std::size_t rows = 0;         // data rows read
  std::size_t unmatchedRows = 0;  // rows naming a residue, or an atom, that the molecule does not hold
  std::string firstUnmatched;   // "line 7 (chain A resid 999)"
  std::size_t valued() const;   // atoms with a value
};

// Throws build::InputError naming the file, the line and the value: an unknown header, a row
// with another number of fields, a value that is not a finite number, an atom index that is not
// a whole number or lies beyond the file's atoms, an atom given a value twice (both lines
// named), and a file that gives no atom of the molecule a value.
AtomValues readAtomValues(const std::string& path, const build::Molecule& molecule);

}  // namespace surftrace::view

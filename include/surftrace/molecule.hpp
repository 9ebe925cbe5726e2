// Stage "read": a structure file or one frame of a trajectory -> the atoms (centres, radii,
// records), with the choices of the command line's molecule options (ReadOptions: model,
// chains, water, hydrogens, radii set, default radius, format).
#pragma once

#include <cstddef>
#include <string>

#include "build/io/error.hpp"
#include "build/io/atom_selection.hpp"
#include "build/io/molecule.hpp"
#include "build/io/trajectory.hpp"

namespace surftrace {

using build::InputError;
using build::Molecule;
using build::MoleculeFormat;
using build::ReadOptions;
using build::Trajectory;
using build::selectAtoms;  // (molecule, "protein and not name H*") -> the indices of the atoms selected

// A structure file (PDB, mmCIF, PQR, XYZR, XYZ, GRO; gzipped too). What the reader assumed
// where the file was odd but readable is in Molecule::notes. Throws InputError naming the file,
// the line and the value on bad input.
Molecule readStructure(const std::string& path, const ReadOptions& options = {});

// The atoms of frame `frame` (from 0) of `trajectory`, whose topology is `topology` (for many
// frames, keep a Trajectory open instead).
Molecule readTrajectoryFrame(const std::string& topology, const std::string& trajectory, std::size_t frame,
                             const ReadOptions& options = {});

// Whether `path` is a patch list (`.stp`, told by its magic "SURFTRCE") rather than a structure:
// a file named .stp that is not one counts as one too, so that reading it says what is wrong.
bool isPatchListPath(const std::string& path);

}  // namespace surftrace

// FreeSASA (Lee & Richards) SAS areas through the `freesasa` CLI, for ORACLES.md D.2.
#pragma once

#include <vector>

#include "oracles/ses_oracle.hpp"

namespace surftrace::oracle {

struct FreesasaResult {
  double total;                 // Å², FreeSASA's structure total
  std::vector<double> perAtom;  // Å², in input order
};

// Rounds every centre to 1e-3 Å in place, the precision of the PDB coordinate columns
// (%8.3f). Round once and use the SAME rounded atoms for FreeSASA and for the computation it
// is compared against.
void roundForPdb(std::vector<Sphere>& atoms);

// Lee & Richards SAS with `slices` slices per atom and probe radius `probeRadius`, via
//   freesasa -O -L --resolution=<slices> --hetatm --hydrogen --unknown=guess
//            --probe-radius=<rp> --format=json --depth=atom
// on a temporary PDB file with each radius in the occupancy column (one ALA residue per atom,
// atom name C, element C; serial and residue numbers wrap, so any atom count works). Areas
// come from the JSON output at full double precision.
//
// Precision limits: FreeSASA stores radii as float (1.70 becomes 1.7000000477), a relative
// error of ~3e-8; L&R with 1000 slices is within ~2e-5 of the exact total (D.2 table).
//
// Throws std::invalid_argument when a radius is not a multiple of 0.01 (to 1e-9), is
// negative or > 999.99, or a coordinate is not representable in %8.3f; std::runtime_error
// when `freesasa` is not on PATH (run scripts/install-deps.sh --tests), when it fails, or when its
// output does not hold exactly one area per input atom.
FreesasaResult runFreesasa(const std::vector<Sphere>& atoms, double probeRadius,
                           int slices = 1000);

}  // namespace surftrace::oracle

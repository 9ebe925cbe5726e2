// Topologies from MD packages: GROMACS GRO (atoms with coordinates, frame after frame) and
// CHARMM/NAMD/X-PLOR PSF (atoms without coordinates), plus what the text trajectory reader
// (text_trajectory.cpp) shares: the GRO frame layout, and how a frame index names and ends.
#pragma once

#include <cstddef>
#include <string>
#include <vector>

#include "build/io/molecule.hpp"
#include "build/io/trajectory.hpp"

namespace surftrace::build::detail {

// GRO: title, atom count, fixed-column atom lines (residue number, residue name, atom name,
// atom number: 5 columns each; x y z in nm, "%8.3f" or wider with more decimals; velocities
// ignored), box line. Returns the first frame's atoms in file order with records (no chain;
// elements implied by the names), centres in Å, no radii and no selection; modelCount is
// the number of frames in the file. `text` is the decompressed file. Throws InputError
// naming the file, the line and the value for any malformed line of the first frame.
Molecule parseGro(const std::string& text, const std::string& path);

// PSF (CHARMM, NAMD, X-PLOR; standard, EXT, CMAP, CHEQ): the atoms of the !NATOM section in
// file order. chain is the segment id, the element is the one whose standard atomic weight
// is within 0.1 u of the atom's mass (else the one its name implies), the charge is kept.
// A PSF has no coordinates: every centre is NaN, for the caller to fill from a trajectory.
Molecule parsePsf(const std::string& text, const std::string& path);

// Frames are numbered from 0 in messages, as in --frames and the output file names.
std::string frameName(std::size_t index);

// How a frame index (GRO here; XYZ and PDB in text_trajectory.cpp) ends at the first frame
// that cannot be complete, `indexed` complete frames in: with none, an InputError at `line`
// (there is nothing to read); else `note` says where and why, and which frames are read.
void endFrameIndex(const std::string& path, int line, const std::string& why,
                   std::size_t indexed, std::string& note);

// Where one GRO frame lies in the text.
struct GroFrameSpan {
  std::size_t offset = 0;  // first byte of the title line
  int line = 0;            // 1-based line of the title
  std::size_t atoms = 0;   // the frame's atom count line
};

// The GRO frames of `text`, one after another, found from the count lines without parsing
// the atoms. A frame the file ends inside of is left out, and so is everything after a line
// that should be a count (or a box) and is not; `note` then says what and where (it is
// empty when every line belongs to a frame). Throws InputError when not even the first frame
// is complete.
std::vector<GroFrameSpan> indexGroFrames(const std::string& text, const std::string& path,
                                         std::string& note);

// Reads the GRO frame at `span` (the `index`-th, 0-based, named so in errors) into
// `frame`: positions in Å; the box as the cell (a, b, c in Å and the angles between the box
// vectors); time and step from the title's "t=" and "step=", else `index`. With `records`,
// also the atoms' records. InputError naming the file, the line and the value otherwise.
void readGroFrame(const std::string& text, const std::string& path, const GroFrameSpan& span,
                  std::size_t index, Frame& frame, std::vector<AtomRecord>* records);

}  // namespace surftrace::build::detail

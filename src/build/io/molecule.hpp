// A molecule as SurfTrace sees it: atom centres and radii, plus the records they came from.
#pragma once

#include <array>
#include <cstdint>
#include <filesystem>
#include <optional>
#include <string>
#include <vector>

#include <glm/vec3.hpp>

#include "build/io/atom_string.hpp"
#include "build/io/radii.hpp"
#include "build/io/radius_presets.hpp"

namespace surftrace::build {

// Where one atom came from. Kept beside the geometry (never inside it) so that the hot
// loops see only `Molecule::centers` and `Molecule::radii`. 88 bytes: the texts are AtomStrings
// (8 bytes each, longer ones kept whole elsewhere), and the fields are ordered to leave no
// padding, since every pass over a million atoms streams the records whole.
struct AtomRecord {
  AtomString name;           // atom name, e.g. "CA"
  AtomString residue;        // residue name, e.g. "ALA"; empty for XYZ/XYZR
  AtomString chain;          // chain id; empty when the format has none; a PSF's segid (PSF has no chains)
  // Segment id, as MDAnalysis reads it: PDB columns 67-76 (the chain where no atom of the file
  // has one, "SYSTEM" where neither has), mmCIF label_asym_id (PyMOL's segi), PSF's segid, a
  // PQR's chain; "SYSTEM" in formats without segments (GRO, XYZ, XYZR).
  AtomString segid;
  AtomString element;        // canonical symbol, e.g. "C", "Fe"; empty when unknown
  double occupancy = 1.0;    // NaN where the file's field is not a number
  double bFactor = 0.0;      // NaN where the file's field is not a number
  double charge = 0.0;       // PQR charge; 0 elsewhere
  // 0-based position among the atoms of the model read, before any selection: the atom's
  // index in a trajectory whose topology this file is.
  std::size_t fileIndex = 0;
  int residueNumber = 0;
  int serial = 0;            // serial number in the file (1-based order for XYZ/XYZR)
  int line = 0;              // 1-based line in the source file; 0 when unknown
  char insertionCode = ' ';
  char altLoc = ' ';         // alternate location indicator; ' ' when none
  bool hetatm = false;
  ElementSource elementSource = ElementSource::None;  // where `element` came from
};
static_assert(sizeof(AtomRecord) == 88, "AtomRecord gained padding or a field: see its comment");

// Which input format a file holds. `Auto` decides from the extension (after .gz). GRO is
// GROMACS's (its first frame); PSF is a CHARMM/NAMD topology without coordinates, read only
// as the topology of a trajectory (ReadOptions::topologyOnly).
enum class MoleculeFormat { Auto, Pdb, Mmcif, Pqr, Xyzr, Xyz, Gro, Psf };

// How to read a structure file. Defaults: first model, no waters, hydrogens kept,
// all chains, radii by element (Bondi, Mantina, Alvarez: elementRadius).
struct ReadOptions {
  MoleculeFormat format = MoleculeFormat::Auto;
  int model = 1;                              // 1-based model (PDB/mmCIF) or frame (XYZ)
  bool keepWater = false;
  bool keepHydrogens = true;
  std::vector<std::string> chains;            // empty: all chains
  std::optional<std::filesystem::path> radiiFile;  // user radius table
  // FreeSASA's classifier radii by residue and atom name (--radii protor|naccess), FreeSASA's
  // element guess for the atoms the classifier does not name; instead of radiiFile.
  std::optional<RadiusPreset> radiiPreset;
  std::optional<double> defaultRadius;        // radius for unknown elements
  // Coarse-grained systems: every particle one sphere of this radius (RES:ATOM lines of
  // radiiFile still win), no element guessed from a bead's name, and the MARTINI waters
  // (W, WF, PW) are water. Without it a MARTINI system is an error.
  std::optional<double> beadRadius;
  // PQR/XYZR atoms with radius exactly 0 (PDB2PQR gives some hydrogens, e.g. AMBER hydroxyl
  // H, no radius) are an error unless this is set; then they are left out and counted.
  bool dropZeroRadius = false;
  // An atom selection in MDAnalysis's language (atom_selection.hpp): only these atoms are read,
  // after the water, hydrogen and chain choices; AtomRecord::fileIndex keeps their place in
  // the file. A selection that selects no atom is an InputError that quotes it.
  std::optional<std::string> selection;
  // Reading the topology of a trajectory: a file without coordinates (PSF) is accepted and its
  // centres are NaN until a frame sets them; nothing checks the centres.
  bool topologyOnly = false;
};

// Counts of what was read but left out, so `surftrace info` can say what and why.
struct SkipReport {
  std::size_t water = 0;
  std::size_t hydrogens = 0;
  std::size_t altLocs = 0;          // alternate conformers dropped
  std::size_t otherChains = 0;
  std::size_t otherModels = 0;      // atoms in models other than the one used
  std::size_t defaultRadius = 0;    // atoms that got --default-radius (not skipped, noted)
  std::size_t zeroRadius = 0;       // PQR/XYZR atoms of radius 0 left out (dropZeroRadius)
  std::size_t virtualSites = 0;     // massless water sites (TIP4P MW, TIP5P LP) of kept waters
  std::size_t duplicates = 0;       // atoms exactly on an earlier one of the same radius
  std::size_t unselected = 0;       // atoms the selection (ReadOptions::selection) left out
};

struct Molecule {
  std::string source;                   // path as given
  MoleculeFormat format = MoleculeFormat::Auto;
  std::vector<glm::dvec3> centers;      // Å, all finite
  std::vector<double> radii;            // Å, all > 0 and finite
  std::vector<AtomRecord> atoms;        // same order as centers
  int modelCount = 1;                   // models/frames present in the file
  int modelUsed = 1;
  std::size_t fileAtomCount = 0;        // atoms of the model read, before any selection
  std::string radiiSet;                 // "bondi", "file" (PQR/XYZR), "table:<path>", "protor" or "naccess"
  // How many atoms took their radius from each source, indexed by RadiusSource ("bondi"
  // is the chain Bondi, Mantina, Alvarez; see elementRadius).
  std::array<std::size_t, kRadiusSourceCount> radiusSources{};
  // How many of the atoms kept took their element from their name (guessed) or their mass (PSF).
  std::size_t elementsFromNames = 0;
  std::size_t elementsFromMasses = 0;
  // Recognised as a MARTINI coarse-grained system (BB and SC1-SC4 beads in amino-acid residues,
  // lipid head and glycerol beads NC3, NH3, CNO, PO4, GL0-GL2, CHOL's ROH and R1-R5, W, WF or
  // PW waters); read only with ReadOptions::beadRadius.
  bool martini = false;
  std::optional<double> beadRadius;     // the --bead-radius every particle got, when given
  std::uint32_t inputCrc32 = 0;         // CRC-32 of the (decompressed) input text, line ends made LF
  SkipReport skipped;
  std::optional<std::string> selection;  // the ReadOptions::selection read with, when given
  // Bonds the file states (PDB CONECT, mmCIF _struct_conn links), pairs of serials (AtomRecord::serial),
  // lower first; atoms the selection left out may appear. build/bonds.hpp turns them into bonds.
  std::vector<std::array<int, 2>> bondRecords;
  // What the reader assumed where the file was odd but readable (an element column that
  // names no element, ...), each naming the line: the commands print them as notes.
  std::vector<std::string> notes;

  std::size_t size() const { return centers.size(); }
};

// Reads a structure file (PDB, mmCIF, either gzipped; PQR; XYZR; XYZ).
// Throws InputError naming the file, line and value on any bad input.
Molecule readMolecule(const std::filesystem::path& path, const ReadOptions& options = {});

// The same from a file's bytes already in memory (gzipped or not); `name` stands for the
// path in errors and, when options.format is Auto, tells the format by its extension.
Molecule readMoleculeBytes(std::string bytes, const std::string& name, const ReadOptions& options = {});

// The largest coordinate (Å, each of x, y, z) and radius (Å) a molecule may have: a metre's
// ten-thousandth, and a hundred times the largest coarse-grained bead. Beyond them the input
// is in other units or damaged (1e30 rendered blank, issue 18), and float32 renderers lose
// the atoms' size against their position.
inline constexpr double kMaxCoordinate = 1e6;
inline constexpr double kMaxRadius = 1e3;

// Checks that every centre is finite and within kMaxCoordinate, every radius finite, > 0 and
// at most kMaxRadius; throws InputError
// (with the atom's line where known) otherwise. readMolecule calls it; builders that take
// a Molecule from elsewhere (a trajectory frame) call it too.
void validateMolecule(const Molecule& molecule);

const char* formatName(MoleculeFormat format);

}  // namespace surftrace::build

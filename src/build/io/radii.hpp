// Elements and their van der Waals radii: symbols, elements implied by atom names, the Bondi
// table (with Mantina et al. for the main-group elements Bondi lacks, then Alvarez for the
// transition metals, lanthanides and actinides) and user radius tables.
#pragma once

#include <cstddef>
#include <cstdint>
#include <filesystem>
#include <optional>
#include <string>
#include <string_view>
#include <unordered_map>

namespace surftrace::build {

// Canonical symbol ("Fe") of an element symbol written in any letter case ("FE", "fe").
// Deuterium "D" is an element here. Returns "" when `symbol` names no element.
std::string canonicalElement(std::string_view symbol);

// The symbol of the element with this atomic number (1-118), "" for any other number.
std::string elementSymbol(int atomicNumber);

// Hydrogen or deuterium.
bool isHydrogen(std::string_view element);

// Water residue names of the PDB and of the common MD force fields (HOH, WAT, SOL, TIP3...).
bool isWaterResidue(std::string_view residue);

// Residues made only of H, C, N, O, S and P: the standard amino acids with their D forms and
// force-field variants (HID, CYX...), caps, nucleotides and water. In these a name's first
// letter is its element even when the name starts in column 13 (Amber writes "CA  " for C-alpha).
bool isStandardResidue(std::string_view residue);

// Water residues of the MARTINI coarse-grained force field: W (one bead for four waters), WF
// (antifreeze) and PW (polarizable). Only water when the system is read as beads: in an
// atomistic file a residue W is a tungsten ion.
bool isMartiniWaterResidue(std::string_view residue);

// A massless site of a 4- or 5-site water model (TIP4P's MW or OM-less M, TIP5P's LP1/LP2,
// Amber's EPW): not an atom, so it has no element and no surface. Only asked of atoms of water
// residues.
bool isWaterVirtualSite(std::string_view name);

// Where an atom's element came from.
enum class ElementSource : std::uint8_t {
  None,  // unknown
  File,  // the file's element column (PDB columns 77-78, mmCIF type_symbol, the XYZ symbol)
  Mass,  // the atom's mass (PSF)
  Name,  // guessed from the atom name (elementFromAtomName)
};

// Whether an atom of this residue can be of this element: the standard residues hold only H, D,
// C, N, O, S, P and Se (selenomethionine's SE), waters only H, D and O; other residues any.
// Asked of guessed elements, so that a name that reads as a metal or a bead ("BB" as boron)
// is not believed where it cannot be.
bool isPlausibleElement(std::string_view residue, std::string_view element);
// The same for a residue already known to be a water or standard (isWaterResidue,
// isStandardResidue), for loops that look a residue up once per run of its atoms.
bool isPlausibleElement(bool water, bool standard, std::string_view element);

// How an atom name reached us.
enum class AtomNameLayout {
  PdbColumns,  // the raw 4-character field of PDB columns 13-16, spaces kept
  Token,       // a whitespace-delimited token; the column is lost
};

// The element an atom name implies where the file gives none ("" when it implies none): the
// one guess for GRO, PSF atoms without a known mass, PQR, PDB without element columns and
// mmCIF without type_symbol. PDB names follow the convention that columns 13-14 hold the
// element right-justified: " CA " is carbon, "CA  " calcium, "1HB " and "HH31" hydrogen; a
// name the columns leave without an element (" RU1", shifted a column) is read as a token.
// Names in standard residues take their first letter when it is H, C, N, O, S, P or D.
// Tokens, where the column is lost, are read as MDAnalysis's guess_atom_element reads them
// (digits and charges after the letters ignored, CHARMM's SOD, POT, CLA, CAL named), with a
// two-letter element believed only where the name means it: written in the symbol's own case
// ("Ru1", "Cl2"), a first letter that is no element ("RU1", "ZN2"), an ion residue named like
// the atom ("CA" in CA), two letters whose first is not H, C, N, O, S or P ("FE", "BR1"), and
// CL, CU, CS and SI; otherwise the first letter ("CA1", "HG1", "NE2": C, H and N).
std::string elementFromAtomName(std::string_view name, std::string_view residue,
                                AtomNameLayout layout);

// Van der Waals radius in Å by element: Bondi (1964) where Bondi gives one, Mantina et al.
// (2009) for the other main-group elements; deuterium as hydrogen. nullopt for the rest
// (most transition metals, lanthanides, actinides but U).
std::optional<double> bondiRadius(std::string_view element);

// Where an atom's radius came from.
// Bead: --bead-radius, one radius for every particle of a coarse-grained system.
// Preset: a FreeSASA classifier (--radii protor|naccess) by residue and atom name;
// PresetGuess: FreeSASA's element guess for an atom that classifier does not name.
enum class RadiusSource { Bondi, Mantina, Alvarez, UserTable, File, Default, Bead, Preset, PresetGuess };
inline constexpr std::size_t kRadiusSourceCount = 9;
const char* radiusSourceName(RadiusSource source);  // "Bondi 1964", "Alvarez 2013", ...

struct TabulatedRadius {
  double radius;  // Å
  RadiusSource source;
};

// The default radius of an element: Bondi (1964), else Mantina et al. (2009), else Alvarez
// (2013) for the transition metals, lanthanides and actinides. nullopt for Pm, the elements
// from Fm (Z = 100) on, and anything that is not an element symbol.
std::optional<TabulatedRadius> elementRadius(std::string_view element);

// A user radius table: one entry a line, "ELEMENT radius" (Fe 1.95) or "RES:ATOM radius"
// (HEM:FE 1.95), '#' starts a comment. Residue and atom names match without regard to case.
class RadiusTable {
 public:
  // Throws InputError naming the table's path and line for a malformed line, an unknown
  // element, a radius that is not a finite positive number or a repeated key.
  static RadiusTable load(const std::filesystem::path& path);

  // The RES:ATOM entry if there is one, else the element's entry.
  std::optional<double> find(std::string_view residue, std::string_view atom,
                             std::string_view element) const;
  // The RES:ATOM entry alone.
  std::optional<double> findAtom(std::string_view residue, std::string_view atom) const;

  const std::string& path() const { return path_; }
  std::size_t size() const { return byAtom_.size() + byElement_.size(); }

 private:
  std::string path_;
  std::unordered_map<std::string, double> byAtom_;     // "RES:ATOM", upper case
  std::unordered_map<std::string, double> byElement_;  // canonical symbol
};

}  // namespace surftrace::build

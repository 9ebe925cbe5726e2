// Radius presets that reproduce FreeSASA's atom classifiers (`--radii protor`, `--radii naccess`):
// a radius by residue and atom name, and FreeSASA's element guess for the atoms they do not name.
#pragma once

#include <optional>
#include <string_view>

namespace surftrace::build {

// The classifiers FreeSASA 2.1.2 builds in (its --radii=protor|naccess, the same tables as its
// share/protor.config and naccess.config).
//   ProtOr: J. Tsai, R. Taylor, C. Chothia, M. Gerstein, "The packing density in proteins:
//           standard radii and volumes", J. Mol. Biol. 290 (1999) 253-266, by the atom's
//           bonded neighbours (C3H0 1.61 ... O2H1 1.46), as FreeSASA assigns them per atom name.
//   NACCESS: the radii of Hubbard and Thornton's NACCESS (vdw.radii), as FreeSASA's
//           naccess.config gives them (C aliphatic 1.87, C aromatic/carbonyl 1.76, O 1.40, ...).
enum class RadiusPreset { ProtOr, Naccess };

// "protor" or "naccess" (any letter case) -> the preset; nullopt for any other name.
std::optional<RadiusPreset> radiusPresetNamed(std::string_view name);
const char* radiusPresetName(RadiusPreset preset);  // "protor", "naccess"

// The radius (Å) the classifier gives atom `atom` of residue `residue`: the residue's own entry,
// else the entry of the classifier's residue ANY (NACCESS names backbone and sugar atoms so),
// as freesasa_classifier_radius does; names match exactly (upper case, no blanks). nullopt where
// the classifier names neither.
std::optional<double> presetRadius(RadiusPreset preset, std::string_view residue, std::string_view atom);

// The radius FreeSASA gives an atom its classifier does not name (freesasa_guess_radius, its
// default --unknown=guess): by element, mostly Mantina et al. 2009 (H 1.10, C 1.70 ...), but
// for the transition metals the smaller values FreeSASA tabulates (Fe 1.26, Zn 1.39). `element`
// is a canonical symbol ("Fe"); nullopt where FreeSASA has none (deuterium among them).
std::optional<double> freesasaGuessRadius(std::string_view element);

}  // namespace surftrace::build

// One colour per atom for every colour scheme but `patch`: element, chain, residue type,
// hydrophobicity, rainbow, B-factor, user values and uniform, then the selections' colours.
#pragma once

#include <array>
#include <cstddef>
#include <optional>
#include <string>
#include <vector>

#include <glm/vec3.hpp>

#include "build/io/molecule.hpp"
#include "view/atom_values.hpp"
#include "view/color_legend.hpp"
#include "view/shading.hpp"

namespace surftrace::view {

// The colour of an atom that a scheme has no number for (a ligand under hydrophobicity, an
// atom the values file leaves out, a water under rainbow); sRGB, as every colour given here.
inline constexpr glm::vec3 kMissingColor{0.5f, 0.5f, 0.5f};

// `selection` (the selection language of build/io/atom_selection.hpp) painted `color`.
struct ColorOverride {
  std::string selection;
  glm::vec3 color{0.0f};
};

struct ColorScheme {
  ColorMode mode = ColorMode::Uniform;
  glm::vec3 uniform{0.8f};                     // sRGB, as the overrides' colours
  std::string map;                             // empty: defaultColorMap(mode)
  std::optional<std::array<double, 2>> range;  // lo, hi; default: the data's min..max
  const AtomValues* values = nullptr;          // the `value` scheme's numbers
  std::vector<ColorOverride> overrides;        // painted in order over the scheme
};

struct AtomColoring {
  std::vector<glm::vec3> colors;         // one per atom, linear
  std::optional<ColorLegend> legend;     // for bfactor, value, hydrophobicity and rainbow
  std::vector<std::size_t> overridden;   // atoms each override painted
};

// The colour map a scheme takes unless told: coolwarm for bfactor and hydrophobicity (blue low,
// red high), viridis for value, rainbow for rainbow; "" for the schemes that use none.
const char* defaultColorMap(ColorMode mode);
bool usesColorMap(ColorMode mode);

// The schemes (README, `render`):
// - element: Jmol's CPK colours; chain: chainColor in order of appearance; uniform;
// - residue: RasMol's `amino` colours by residue name (acidic red, basic blue, ...);
// - hydrophobicity: the Kyte–Doolittle hydropathy index of the atom's amino acid (Kyte and
//   Doolittle, J. Mol. Biol. 157:105–132, 1982) through the map; other residues are missing;
// - rainbow: the residue's position along its chain, N to C terminus, through the map, as
//   PyMOL's `spectrum` and ChimeraX's `rainbow` do; hetero groups and water are missing;
// - bfactor, value: the atom's B-factor or its --values number through the map.
// A number v takes the map at (v − lo)/(hi − lo), clipped to [0, 1].
// The tables, the maps and the scheme's own colours (uniform, overrides) are sRGB, as published
// and as given; the colours returned are their linear values (view/srgb.hpp), what the renderers
// shade and an EXR holds, so that an 8-bit image shows the sRGB colour again where unshaded.
// Throws std::invalid_argument when the molecule has no data for the scheme (no B-factors, no
// residue names, no amino acids, no values), when the range is empty, and for a selection that
// selects nothing.
AtomColoring colorAtoms(const build::Molecule& molecule, const ColorScheme& scheme);

// colorAtoms with the scheme's defaults: `mode`, `uniform` (sRGB), no map, range or overrides; linear colours.
std::vector<glm::vec3> atomColors(const build::Molecule& molecule, ColorMode mode, const glm::vec3& uniform);

// The sRGB colour of the chain that appears `order`-th (from 0) in the file: the first 24 chains get
// 24 distinct colours (tab10, then Glasbey's), the next 24 the same darkened to kChainDarker, the
// next 24 lightened kChainLighter of the way to white, and so on in turn (README, `render`).
inline constexpr std::size_t kChainPaletteSize = 24;
inline constexpr float kChainDarker = 0.6f, kChainLighter = 0.45f;
glm::vec3 chainColor(std::size_t order);

// The Kyte–Doolittle index of a residue name (HIS's protonation states, MSE and the like
// included), or nothing for a residue that is not an amino acid.
std::optional<double> kyteDoolittle(const std::string& residue);

}  // namespace surftrace::view

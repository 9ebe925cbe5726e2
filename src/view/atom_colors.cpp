// One colour per atom for every colour scheme but `patch` (atom_colors.hpp).
#include "view/atom_colors.hpp"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <limits>
#include <map>
#include <stdexcept>
#include <unordered_map>

#include "build/io/atom_selection.hpp"
#include "build/io/radii.hpp"
#include "view/color_map.hpp"
#include "view/srgb.hpp"

namespace surftrace::view {

namespace {

glm::vec3 elementColor(const std::string& element) {
  // Jmol's CPK colours for the elements of biomolecules; anything else is pink.
  static const std::unordered_map<std::string, glm::vec3> table = {
      {"H", {1.00f, 1.00f, 1.00f}}, {"C", {0.56f, 0.56f, 0.56f}}, {"N", {0.19f, 0.31f, 0.97f}},
      {"O", {1.00f, 0.05f, 0.05f}}, {"S", {1.00f, 1.00f, 0.19f}}, {"P", {1.00f, 0.50f, 0.00f}},
      {"F", {0.56f, 0.88f, 0.31f}}, {"Cl", {0.12f, 0.94f, 0.12f}}, {"Br", {0.65f, 0.16f, 0.16f}},
      {"I", {0.58f, 0.00f, 0.58f}}, {"Fe", {0.88f, 0.40f, 0.20f}}, {"Zn", {0.49f, 0.50f, 0.69f}},
      {"Mg", {0.54f, 1.00f, 0.00f}}, {"Ca", {0.24f, 1.00f, 0.00f}}, {"Na", {0.67f, 0.36f, 0.95f}},
      {"K", {0.56f, 0.25f, 0.83f}}, {"Mn", {0.61f, 0.48f, 0.78f}}, {"Cu", {0.78f, 0.50f, 0.20f}},
      {"Se", {1.00f, 0.63f, 0.00f}}};
  const auto it = table.find(element);
  return it == table.end() ? glm::vec3(1.0f, 0.08f, 0.58f) : it->second;
}

// 24 colours for chains, in order of appearance: matplotlib's tab10 (Tableau 10), then the
// colours that Glasbey's construction adds after it (Glasbey, Heijden, Toh and Gray, "Colour
// displays for categorical images", Color Res. Appl. 32:304-309, 2007), as colorcet publishes
// them (holoviz/colorcet, assets/Glasbey/glasbey_category10_n256.csv, entries 13-32), leaving
// out those darker than CIELAB L* 35 (entries 10-12, 14, 16, 22, 27, 29, 31), which shading
// would turn black. Pairwise CIELAB distance at least 23 (tests/view/chain_colors_test.cpp).
constexpr glm::vec3 kChainPalette[kChainPaletteSize] = {
    // tab10 to two decimals, as the palette has always had it (reference images keep their colours)
    {0.12f, 0.47f, 0.71f}, {1.00f, 0.50f, 0.05f}, {0.17f, 0.63f, 0.17f}, {0.84f, 0.15f, 0.16f},
    {0.58f, 0.40f, 0.74f}, {0.55f, 0.34f, 0.29f}, {0.89f, 0.47f, 0.76f}, {0.50f, 0.50f, 0.50f},
    {0.74f, 0.74f, 0.13f}, {0.09f, 0.75f, 0.81f},
    // Glasbey's
    {0.058824f, 1.000000f, 0.662745f}, {0.737255f, 0.737255f, 1.000000f},
    {0.847059f, 0.686275f, 0.635294f}, {0.419608f, 0.396078f, 0.000000f}, {0.000000f, 0.454902f, 0.345098f},
    {0.380392f, 0.149020f, 1.000000f}, {1.000000f, 1.000000f, 0.603922f}, {0.549020f, 0.721569f, 0.580392f},
    {0.803922f, 0.000000f, 0.505882f}, {0.580392f, 0.988235f, 1.000000f}, {0.568627f, 1.000000f, 0.000000f},
    {0.337255f, 0.325490f, 0.443137f}, {0.678431f, 0.537255f, 0.266667f}, {1.000000f, 0.752941f, 0.952941f}};

// The standard amino acid a residue name stands for: force fields' protonation states and the
// common modified residues (selenomethionine) under their parent's name.
std::string aminoAcid(const std::string& residue) {
  static const std::unordered_map<std::string, std::string> aliases = {
      {"HSD", "HIS"}, {"HSE", "HIS"}, {"HSP", "HIS"}, {"HID", "HIS"}, {"HIE", "HIS"}, {"HIP", "HIS"},
      {"HISA", "HIS"}, {"HISB", "HIS"}, {"HISH", "HIS"}, {"HISD", "HIS"}, {"HISE", "HIS"}, {"CYX", "CYS"},
      {"CYM", "CYS"}, {"CYS2", "CYS"}, {"ASH", "ASP"}, {"GLH", "GLU"}, {"LYN", "LYS"}, {"LSN", "LYS"},
      {"MSE", "MET"}};
  const auto it = aliases.find(residue);
  return it == aliases.end() ? residue : it->second;
}

// RasMol's `amino` colour scheme (RasMol 2.7 manual, "Colour Schemes"), by residue name.
glm::vec3 residueColor(const std::string& residue) {
  static const std::unordered_map<std::string, std::array<int, 3>> table = {
      {"ASP", {230, 10, 10}},   {"GLU", {230, 10, 10}},   {"CYS", {230, 230, 0}},  {"MET", {230, 230, 0}},
      {"LYS", {20, 90, 255}},   {"ARG", {20, 90, 255}},   {"SER", {250, 150, 0}},  {"THR", {250, 150, 0}},
      {"PHE", {50, 50, 170}},   {"TYR", {50, 50, 170}},   {"ASN", {0, 220, 220}},  {"GLN", {0, 220, 220}},
      {"GLY", {235, 235, 235}}, {"LEU", {15, 130, 15}},   {"VAL", {15, 130, 15}},  {"ILE", {15, 130, 15}},
      {"ALA", {200, 200, 200}}, {"TRP", {180, 90, 180}},  {"HIS", {130, 130, 210}}, {"PRO", {220, 150, 130}}};
  const auto it = table.find(aminoAcid(residue));
  const std::array<int, 3> c = it == table.end() ? std::array<int, 3>{190, 160, 110} : it->second;  // "others": tan
  return glm::vec3(c[0], c[1], c[2]) / 255.0f;
}

std::string number(double v) {
  char text[32];
  std::snprintf(text, sizeof text, "%.4g", v);
  return text;
}

// The positions along their chains, 0 (N terminus) to 1 (C terminus), of the polymer atoms'
// residues; NaN for hetero groups and water. Residues follow one another in file order; a new
// residue starts where the number, insertion code or name changes.
std::vector<double> chainPositions(const build::Molecule& m) {
  std::vector<double> t(m.size(), std::numeric_limits<double>::quiet_NaN());
  std::map<std::string, std::vector<std::vector<std::size_t>>> chains;  // chain -> residues -> atoms
  std::map<std::string, std::size_t> lastAtom;
  for (std::size_t i = 0; i < m.size(); ++i) {
    const auto& a = m.atoms[i];
    if (a.hetatm || build::isWaterResidue(a.residue)) continue;
    auto& residues = chains[a.chain];
    const auto last = lastAtom.find(a.chain);
    const bool same = last != lastAtom.end() && m.atoms[last->second].residueNumber == a.residueNumber &&
                      m.atoms[last->second].insertionCode == a.insertionCode && m.atoms[last->second].residue == a.residue;
    if (!same) residues.emplace_back();
    residues.back().push_back(i);
    lastAtom[a.chain] = i;
  }
  for (const auto& [chain, residues] : chains)
    for (std::size_t k = 0; k < residues.size(); ++k)
      for (std::size_t i : residues[k])
        t[i] = residues.size() == 1 ? 0.0 : static_cast<double>(k) / static_cast<double>(residues.size() - 1);
  return t;
}

// Each atom's number under a mapped scheme (NaN: none), and the legend's label.
std::vector<double> schemeNumbers(const build::Molecule& m, const ColorScheme& s, std::string& label) {
  std::vector<double> v(m.size(), std::numeric_limits<double>::quiet_NaN());
  const std::string& source = m.source;
  switch (s.mode) {
    case ColorMode::BFactor: {
      label = "B-factor";
      bool any = false;
      for (std::size_t i = 0; i < m.size(); ++i) {
        v[i] = m.atoms[i].bFactor;
        any = any || (std::isfinite(v[i]) && v[i] != 0.0);
      }
      if (!any)
        throw std::invalid_argument("--color bfactor: " + source + " has no B-factors (every atom's is 0 or missing; " +
                                    "XYZR, XYZ, PQR, GRO and PSF files hold none): colour by your own numbers with "
                                    "--color value --values FILE, or choose another scheme");
      break;
    }
    case ColorMode::Hydrophobicity: {
      label = "hydropathy (Kyte-Doolittle)";
      bool any = false;
      for (std::size_t i = 0; i < m.size(); ++i)
        if (const auto h = kyteDoolittle(m.atoms[i].residue)) v[i] = *h, any = true;
      if (!any)
        throw std::invalid_argument("--color hydrophobicity: " + source + " has no amino-acid residues" +
                                    (std::all_of(m.atoms.begin(), m.atoms.end(), [](const auto& a) { return a.residue.empty(); })
                                         ? std::string(" (its atoms have no residue names: XYZR and XYZ files hold none)")
                                         : std::string()) +
                                    "; choose another scheme");
      break;
    }
    case ColorMode::Rainbow: {
      label = "residue, N to C terminus";
      if (std::all_of(m.atoms.begin(), m.atoms.end(), [](const auto& a) { return a.residue.empty(); }))
        throw std::invalid_argument("--color rainbow: " + source + " has no residues (its atoms have no residue names: "
                                    "XYZR and XYZ files hold none); choose another scheme");
      v = chainPositions(m);
      if (std::all_of(v.begin(), v.end(), [](double x) { return std::isnan(x); }))
        throw std::invalid_argument("--color rainbow: " + source + " has no polymer residues (every atom is a hetero "
                                    "group or water); choose another scheme");
      break;
    }
    case ColorMode::Value: {
      if (!s.values) throw std::invalid_argument("--color value needs --values FILE (a CSV of the atoms' numbers)");
      if (s.values->values.size() != m.size())
        throw std::invalid_argument("--values " + s.values->path + " was read for another molecule");
      label = s.values->label;
      v = s.values->values;
      break;
    }
    default: break;
  }
  return v;
}

}  // namespace

const char* defaultColorMap(ColorMode mode) {
  switch (mode) {
    case ColorMode::BFactor:
    case ColorMode::Hydrophobicity: return "coolwarm";
    case ColorMode::Value: return "viridis";
    case ColorMode::Rainbow: return "rainbow";
    default: return "";
  }
}

bool usesColorMap(ColorMode mode) { return *defaultColorMap(mode) != '\0'; }

std::optional<double> kyteDoolittle(const std::string& residue) {
  static const std::unordered_map<std::string, double> table = {
      {"ILE", 4.5},  {"VAL", 4.2},  {"LEU", 3.8},  {"PHE", 2.8},  {"CYS", 2.5},  {"MET", 1.9},  {"ALA", 1.8},
      {"GLY", -0.4}, {"THR", -0.7}, {"SER", -0.8}, {"TRP", -0.9}, {"TYR", -1.3}, {"PRO", -1.6}, {"HIS", -3.2},
      {"GLU", -3.5}, {"GLN", -3.5}, {"ASP", -3.5}, {"ASN", -3.5}, {"LYS", -3.9}, {"ARG", -4.5}};
  const auto it = table.find(aminoAcid(residue));
  if (it == table.end()) return std::nullopt;
  return it->second;
}

AtomColoring colorAtoms(const build::Molecule& m, const ColorScheme& s) {
  AtomColoring out;
  std::vector<glm::vec3>& colors = out.colors;
  colors.assign(m.size(), s.uniform);
  if (!usesColorMap(s.mode) && (!s.map.empty() || s.range))
    throw std::invalid_argument(std::string(!s.map.empty() ? "--color-map" : "--color-range") + " applies to the schemes "
                                "that map numbers to colours (bfactor, value, hydrophobicity, rainbow), not to --color " +
                                colorModeName(s.mode));
  if (s.mode != ColorMode::Value && s.values)
    throw std::invalid_argument("--values " + s.values->path + " is read by --color value only (the scheme is " +
                                colorModeName(s.mode) + ")");
  switch (s.mode) {
    case ColorMode::Patch:
    case ColorMode::Uniform: break;
    case ColorMode::Element:
      for (std::size_t i = 0; i < m.size(); ++i) colors[i] = elementColor(m.atoms[i].element);
      break;
    case ColorMode::Chain: {
      std::map<std::string, std::size_t> order;
      for (std::size_t i = 0; i < m.size(); ++i) {
        const auto it = order.emplace(m.atoms[i].chain, order.size()).first;
        colors[i] = chainColor(it->second);
      }
      break;
    }
    case ColorMode::Residue:
      if (std::all_of(m.atoms.begin(), m.atoms.end(), [](const auto& a) { return a.residue.empty(); }))
        throw std::invalid_argument("--color residue: " + m.source + " has no residue names (XYZR and XYZ files hold "
                                    "none); choose another scheme");
      for (std::size_t i = 0; i < m.size(); ++i) colors[i] = residueColor(m.atoms[i].residue);
      break;
    case ColorMode::BFactor:
    case ColorMode::Hydrophobicity:
    case ColorMode::Rainbow:
    case ColorMode::Value: {
      ColorLegend legend;
      legend.map = s.map.empty() ? defaultColorMap(s.mode) : s.map;
      const ColorMap& map = ColorMap::named(legend.map);
      const std::vector<double> v = schemeNumbers(m, s, legend.label);
      double lo = std::numeric_limits<double>::infinity(), hi = -lo;
      for (double x : v)
        if (!std::isnan(x)) lo = std::min(lo, x), hi = std::max(hi, x);
      if (s.mode == ColorMode::Rainbow) {
        if (s.range)
          throw std::invalid_argument("--color-range applies to numbers; rainbow always runs from the N terminus (0) to "
                                      "the C terminus (1) of each chain");
        lo = 0.0, hi = 1.0;
        legend.loText = "N", legend.hiText = "C";
      } else if (s.range) {
        lo = (*s.range)[0], hi = (*s.range)[1];
        legend.rangeFromData = false;
      } else if (!(hi > lo)) {
        throw std::invalid_argument("--color " + std::string(colorModeName(s.mode)) + ": every atom's " + legend.label +
                                    " is " + number(lo) + ", so the colour map has no range: give --color-range LO:HI");
      }
      if (legend.loText.empty()) legend.loText = number(lo), legend.hiText = number(hi);
      legend.lo = lo, legend.hi = hi;
      for (std::size_t i = 0; i < m.size(); ++i) {
        if (std::isnan(v[i])) {
          colors[i] = kMissingColor;
          ++legend.missing;
        } else {
          colors[i] = map.at((v[i] - lo) / (hi - lo));
        }
      }
      out.legend = legend;
      break;
    }
  }
  for (const ColorOverride& o : s.overrides) {
    std::vector<std::uint32_t> picked;
    try {
      picked = build::selectAtoms(m, o.selection);
    } catch (const std::invalid_argument& e) {
      throw std::invalid_argument(std::string("--color-select: ") + e.what());
    }
    for (std::uint32_t i : picked) colors[i] = o.color;
    out.overridden.push_back(picked.size());
  }
  // Every colour above is sRGB (the tables, the maps, the user's); the renderers shade linear ones.
  for (glm::vec3& c : colors) c = srgbToLinear(c);
  return out;
}

glm::vec3 chainColor(std::size_t order) {
  const glm::vec3 c = kChainPalette[order % kChainPaletteSize];
  switch (order / kChainPaletteSize % 3) {
    case 1: return kChainDarker * c;
    case 2: return c + kChainLighter * (glm::vec3(1.0f) - c);
    default: return c;
  }
}

std::vector<glm::vec3> atomColors(const build::Molecule& m, ColorMode mode, const glm::vec3& uniform) {
  ColorScheme scheme;
  scheme.mode = mode;
  scheme.uniform = uniform;
  return colorAtoms(m, scheme).colors;
}

}  // namespace surftrace::view

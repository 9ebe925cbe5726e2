// Elements and their van der Waals radii: symbols, elements implied by atom names, the Bondi
// table (with Mantina et al. for the main-group elements Bondi lacks, then Alvarez for the
// transition metals, lanthanides and actinides) and user radius tables.
#include "build/io/radii.hpp"

#include <algorithm>
#include <array>
#include <charconv>
#include <cmath>
#include <cstdint>
#include <utility>
#include <vector>

#include "build/io/error.hpp"
#include "build/io/line_cursor.hpp"
#include "build/io/text_fields.hpp"

namespace surftrace::build {
namespace {

// Symbols by atomic number (index 0 unused), then deuterium.
constexpr std::array<std::string_view, 120> kSymbols = {
    "",   "H",  "He", "Li", "Be", "B",  "C",  "N",  "O",  "F",  "Ne", "Na", "Mg", "Al", "Si",
    "P",  "S",  "Cl", "Ar", "K",  "Ca", "Sc", "Ti", "V",  "Cr", "Mn", "Fe", "Co", "Ni", "Cu",
    "Zn", "Ga", "Ge", "As", "Se", "Br", "Kr", "Rb", "Sr", "Y",  "Zr", "Nb", "Mo", "Tc", "Ru",
    "Rh", "Pd", "Ag", "Cd", "In", "Sn", "Sb", "Te", "I",  "Xe", "Cs", "Ba", "La", "Ce", "Pr",
    "Nd", "Pm", "Sm", "Eu", "Gd", "Tb", "Dy", "Ho", "Er", "Tm", "Yb", "Lu", "Hf", "Ta", "W",
    "Re", "Os", "Ir", "Pt", "Au", "Hg", "Tl", "Pb", "Bi", "Po", "At", "Rn", "Fr", "Ra", "Ac",
    "Th", "Pa", "U",  "Np", "Pu", "Am", "Cm", "Bk", "Cf", "Es", "Fm", "Md", "No", "Lr", "Rf",
    "Db", "Sg", "Bh", "Hs", "Mt", "Ds", "Rg", "Cn", "Nh", "Fl", "Mc", "Lv", "Ts", "Og", "D"};

struct ElementRadius {
  std::string_view element;
  double radius;
};

// A. Bondi, "van der Waals Volumes and Radii", J. Phys. Chem. 68 (1964) 441-451, Table I.
// Transcriptions differ for a few metals (some give Pt 1.75, Hg 1.70 and Cd 1.62, the last
// two from Bondi's 1966 correction); these are the 1964 values.
// clang-format off
constexpr ElementRadius kBondi[] = {
    {"H", 1.20}, {"He", 1.40}, {"Li", 1.82}, {"C", 1.70}, {"N", 1.55}, {"O", 1.52},
    {"F", 1.47}, {"Ne", 1.54}, {"Na", 2.27}, {"Mg", 1.73}, {"Si", 2.10}, {"P", 1.80},
    {"S", 1.80}, {"Cl", 1.75}, {"Ar", 1.88}, {"K", 2.75}, {"Ni", 1.63}, {"Cu", 1.40},
    {"Zn", 1.39}, {"Ga", 1.87}, {"As", 1.85}, {"Se", 1.90}, {"Br", 1.85}, {"Kr", 2.02},
    {"Pd", 1.63}, {"Ag", 1.72}, {"Cd", 1.58}, {"In", 1.93}, {"Sn", 2.17}, {"Te", 2.06},
    {"I", 1.98}, {"Xe", 2.16}, {"Pt", 1.72}, {"Au", 1.66}, {"Hg", 1.55}, {"Tl", 1.96},
    {"Pb", 2.02}, {"U", 1.86},
    // Deuterium is hydrogen to a surface.
    {"D", 1.20}};
// clang-format on

// M. Mantina, A. C. Chamberlin, R. Valero, C. J. Cramer, D. G. Truhlar, "Consistent van der
// Waals Radii for the Whole Main Group", J. Phys. Chem. A 113 (2009) 5806-5812, Table 12:
// the 16 main-group elements Bondi lacks, fitted to be compatible with Bondi's scale.
// clang-format off
constexpr ElementRadius kMantina[] = {
    {"Be", 1.53}, {"B", 1.92}, {"Al", 1.84}, {"Ca", 2.31}, {"Ge", 2.11}, {"Rb", 3.03},
    {"Sr", 2.49}, {"Sb", 2.06}, {"Cs", 3.43}, {"Ba", 2.68}, {"Bi", 2.07}, {"Po", 1.97},
    {"At", 2.02}, {"Rn", 2.20}, {"Fr", 3.48}, {"Ra", 2.83}};
// clang-format on

// S. Alvarez, "A cartography of the van der Waals territories", Dalton Trans. 42 (2013)
// 8617-8636, doi:10.1039/C3DT50599E, Table 1 (the "vdW" column), for the elements neither
// Bondi nor Mantina give. Why this table: it is the one published set that covers the
// transition metals, lanthanides and actinides (Z <= 99 except Pm, Po-Ra) with one method,
// the contact-distance distributions of the Cambridge Structural Database, so the metal
// sites of proteins (Fe in heme, Mn, Co, Mo, W, the lanthanides of phasing) all get a
// radius from the same scale. Its values for Bondi's elements differ from Bondi's (C 1.77,
// Zn 2.39); those keep Bondi's, so existing surfaces do not change. A metal in a protein is
// mostly buried by its ligands, so its radius moves the SES little; --radii overrides it.
// Left out: Pm and Z >= 100, for which the paper gives no value.
// clang-format off
constexpr ElementRadius kAlvarez[] = {
    {"Sc", 2.58}, {"Ti", 2.46}, {"V", 2.42}, {"Cr", 2.45}, {"Mn", 2.45}, {"Fe", 2.44},
    {"Co", 2.40}, {"Y", 2.75}, {"Zr", 2.52}, {"Nb", 2.56}, {"Mo", 2.45}, {"Tc", 2.44},
    {"Ru", 2.46}, {"Rh", 2.44}, {"La", 2.98}, {"Ce", 2.88}, {"Pr", 2.92}, {"Nd", 2.95},
    {"Sm", 2.90}, {"Eu", 2.87}, {"Gd", 2.83}, {"Tb", 2.79}, {"Dy", 2.87}, {"Ho", 2.81},
    {"Er", 2.83}, {"Tm", 2.79}, {"Yb", 2.80}, {"Lu", 2.74}, {"Hf", 2.63}, {"Ta", 2.53},
    {"W", 2.57}, {"Re", 2.49}, {"Os", 2.48}, {"Ir", 2.41}, {"Ac", 2.80}, {"Th", 2.93},
    {"Pa", 2.88}, {"Np", 2.82}, {"Pu", 2.81}, {"Am", 2.83}, {"Cm", 3.05}, {"Bk", 3.40},
    {"Cf", 3.05}, {"Es", 2.70}};
// clang-format on

using text::upper;
char lower(char c) { return (c >= 'A' && c <= 'Z') ? static_cast<char>(c - 'A' + 'a') : c; }
using text::isAlpha;
using text::isDigit;
using text::isSpace;
using text::trim;

std::string toUpper(std::string_view s) {
  std::string out(s);
  for (char& c : out) c = upper(c);
  return out;
}

bool equalsIgnoreCase(std::string_view a, std::string_view b) {
  if (a.size() != b.size()) return false;
  for (std::size_t i = 0; i < a.size(); ++i)
    if (upper(a[i]) != upper(b[i])) return false;
  return true;
}

// A name of up to 7 characters, trimmed and upper-cased, as one number: its length in the top
// byte, its bytes below. 0 for an empty name and for a longer one, which no list holds.
std::uint64_t packedUpper(std::string_view name) {
  name = trim(name);
  if (name.empty() || name.size() > 7) return 0;
  std::uint64_t key = static_cast<std::uint64_t>(name.size()) << 56;
  for (std::size_t i = 0; i < name.size(); ++i)
    key |= static_cast<std::uint64_t>(static_cast<unsigned char>(upper(name[i]))) << (8 * i);
  return key;
}

// A set of short names (residues), matched trimmed and without regard to case. The residue
// lists are asked several times per atom, millions of times for a large file: a sorted array
// of numbers in place of an upper-cased copy compared with every entry in turn (which took a
// fifth of reading a GRO file).
class NameList {
 public:
  NameList(std::initializer_list<std::string_view> names) {
    for (std::string_view name : names) keys_.push_back(packedUpper(name));
    std::sort(keys_.begin(), keys_.end());
  }
  bool contains(std::string_view name) const {
    const std::uint64_t key = packedUpper(name);
    return key != 0 && std::binary_search(keys_.begin(), keys_.end(), key);
  }

 private:
  std::vector<std::uint64_t> keys_;
};

// The one-letter elements that occur in atom names (as gemmi's find_single_letter_element).
std::string singleLetterElement(char c) {
  switch (upper(c)) {
    case 'H':
      return "H";
    case 'B':
      return "B";
    case 'C':
      return "C";
    case 'N':
      return "N";
    case 'O':
      return "O";
    case 'F':
      return "F";
    case 'P':
      return "P";
    case 'S':
      return "S";
    case 'K':
      return "K";
    case 'V':
      return "V";
    case 'Y':
      return "Y";
    case 'I':
      return "I";
    case 'W':
      return "W";
    case 'U':
      return "U";
    case 'D':
      return "D";
    default:
      return "";
  }
}

std::optional<double> parsePositive(std::string_view text) {
  double value = 0.0;
  const char* first = text.data();
  const char* last = text.data() + text.size();
  if (first != last && *first == '+') ++first;
  const auto [ptr, ec] = std::from_chars(first, last, value);
  if (ec != std::errc() || ptr != last || !std::isfinite(value) || value <= 0.0)
    return std::nullopt;
  return value;
}

}  // namespace

std::string canonicalElement(std::string_view symbol) {
  symbol = trim(symbol);
  if (symbol.empty() || symbol.size() > 2) return {};
  std::string wanted(symbol);
  wanted[0] = upper(wanted[0]);
  if (wanted.size() == 2) wanted[1] = lower(wanted[1]);
  // Asked for nearly every atom name, millions of times for a large file: a table by the
  // letters in place of comparing with each of the 119 symbols (most names, "CB", "OG1",
  // are none, and went through them all).
  const auto slot = [](std::string_view letters) -> std::optional<std::size_t> {
    if (letters[0] < 'A' || letters[0] > 'Z') return std::nullopt;
    const auto row = static_cast<std::size_t>(letters[0] - 'A') * 27;
    if (letters.size() == 1) return row;
    if (letters[1] < 'a' || letters[1] > 'z') return std::nullopt;
    return row + static_cast<std::size_t>(letters[1] - 'a' + 1);
  };
  static const std::array<bool, 26 * 27> kIsSymbol = [&] {
    std::array<bool, 26 * 27> table{};
    for (std::string_view s : kSymbols)
      if (!s.empty()) table[*slot(s)] = true;
    return table;
  }();
  const std::optional<std::size_t> at = slot(wanted);
  return at && kIsSymbol[*at] ? wanted : std::string();
}

std::string elementSymbol(int atomicNumber) {
  if (atomicNumber < 1 || atomicNumber > 118) return {};
  return std::string(kSymbols[static_cast<std::size_t>(atomicNumber)]);
}

bool isHydrogen(std::string_view element) { return element == "H" || element == "D"; }

bool isWaterResidue(std::string_view residue) {
  static const NameList kWater{"HOH", "WAT", "H2O", "DOD", "D2O", "SOL", "TIP", "TIP3", "TIP4",
                               "TIP5", "TP3", "T3P", "T4P", "T5P", "SPC", "SPCE"};
  return kWater.contains(residue);
}

bool isStandardResidue(std::string_view residue) {
  if (isWaterResidue(residue)) return true;
  static const NameList kStandard{
      // amino acids
      "ALA", "ARG", "ASN", "ASP", "CYS", "GLN", "GLU", "GLY", "HIS", "ILE", "LEU", "LYS",
      "MET", "PHE", "PRO", "SER", "THR", "TRP", "TYR", "VAL",
      // their D forms (PDB chemical component names)
      "DAL", "DAR", "DSG", "DAS", "DCY", "DGN", "DGL", "DHI", "DIL", "DLE", "DLY", "MED",
      "DPN", "DPR", "DSN", "DTH", "DTR", "DTY", "DVA",
      // protonation and disulfide variants of Amber, CHARMM and GROMACS
      "HID", "HIE", "HIP", "HSD", "HSE", "HSP", "HISD", "HISE", "HISH", "HISA", "HISB",
      "CYX", "CYM", "CYS2", "ASH", "GLH", "LYN", "LSN", "ARN", "TYM",
      // caps
      "ACE", "NME", "NMA", "NH2", "FOR",
      // nucleotides
      "A", "C", "G", "U", "T", "I", "DA", "DC", "DG", "DT", "DU", "DI", "RA", "RC", "RG",
      "RU", "DA5", "DA3", "DC5", "DC3", "DG5", "DG3", "DT5", "DT3", "RA5", "RA3", "RC5",
      "RC3", "RG5", "RG3", "RU5", "RU3", "ADE", "CYT", "GUA", "THY", "URA"};
  return kStandard.contains(residue);
}

namespace {

// Names whose letters mislead, from MDAnalysis's TABLE_ATOMELEMENTS (CHARMM, AMBER, GROMOS):
// CHARMM's ions (SOD is sodium, not sulfur), GROMOS's calcium C0 and Amber's carbons AC, BC.
struct NamedElement {
  std::string_view name;
  std::string_view element;
};
constexpr NamedElement kNamedElements[] = {
    {"SOD", "Na"}, {"POT", "K"},  {"CLA", "Cl"}, {"CLAL", "Cl"}, {"CAL", "Ca"}, {"C0", "Ca"},
    {"CES", "Cs"}, {"LIT", "Li"}, {"IOD", "I"},  {"AC", "C"},    {"BC", "C"}};

std::string namedElement(std::string_view upperName) {
  for (const NamedElement& e : kNamedElements)
    if (e.name == upperName) return std::string(e.element);
  return {};
}

// A name without a column: letters, then digits and charges ("Ru1", "CL-", "1HB", "NA+").
std::string elementFromToken(std::string_view name, std::string_view residue) {
  const std::string_view trimmed = trim(name);
  const std::string upperName = toUpper(trimmed);
  std::string bare;  // without digits and charges, as MDAnalysis strips them
  for (char c : upperName)
    if (!isDigit(c) && c != '+' && c != '-' && c != '*') bare += c;
  if (std::string e = namedElement(upperName); !e.empty()) return e;
  if (std::string e = namedElement(bare); !e.empty()) return e;

  std::size_t skip = 0;
  while (skip < trimmed.size() && isDigit(trimmed[skip])) ++skip;
  const std::string_view stem = trimmed.substr(skip);
  std::size_t letterCount = 0;
  while (letterCount < stem.size() && isAlpha(stem[letterCount])) ++letterCount;
  const std::string_view letters = stem.substr(0, letterCount);
  if (letters.empty()) return {};
  const char first = upper(letters[0]);
  if (isStandardResidue(residue) &&
      std::string_view("HCNOSPD").find(first) != std::string_view::npos)
    return std::string(1, first);

  if (letters.size() >= 2) {
    std::string element = canonicalElement(letters.substr(0, 2));
    if (!element.empty()) {
      // Written in the symbol's own case ("Ru1", "Cl2"): the writer meant the element.
      const bool ownCase = letters[0] == first && letters[1] == lower(letters[1]);
      // "RU1", "ZN2", "MG": no one-letter element to confuse it with.
      const bool noOneLetter = singleLetterElement(first).empty();
      // An ion residue named like its atom ("ZN" in ZN, "NA+" in NA).
      const bool ion = equalsIgnoreCase(letters, trim(residue));
      // Two letters alone ("FE", "FE2", "BR1") that no organic name starts with: C-alpha,
      // N-epsilon, H-gamma and O, S, P names ("CA", "NE2", "HG1", "OS1") stay one-letter.
      const bool bareSymbol = letters.size() == 2 &&
                              std::string_view("HCNOSP").find(first) == std::string_view::npos;
      // The pairs MDAnalysis's tables read as elements although their first letter is one too:
      // CL (CGenFF and GAFF name chlorines CL1, CL2), CU, CS and SI; no organic name uses them.
      // Not NA (heme's pyrrole nitrogens are NA-ND) nor CA (C-alpha).
      const bool mdaPair = letters.size() == 2 && (element == "Cl" || element == "Cu" ||
                                                   element == "Cs" || element == "Si");
      if (ownCase || noOneLetter || ion || bareSymbol || mdaPair) return element;
    }
  }
  return singleLetterElement(first);
}

// What an ion's residue or atom name says, without the charge and count after it ("NA+",
// "MG2+", "CL-"): the element it is named by (NA, CL, K, ZN) or MDAnalysis's table names it
// (SOD, POT, CLA, CAL); "" for anything else.
std::string ionName(std::string_view text) {
  std::string key = toUpper(trim(text));
  while (!key.empty() && (isDigit(key.back()) || key.back() == '+' || key.back() == '-')) key.pop_back();
  if (key.empty() || !isAlpha(key[0])) return {};
  if (std::string e = namedElement(key); !e.empty()) return e;
  return canonicalElement(key);
}

// A monatomic ion: its residue names the same element as its atom (NA in NA, NA+ or SOD; CL in
// CL, CL- or CLA; CA in CA, ZN in ZN), or the residue is the generic ION of GROMACS and
// CHARMM-GUI. MDAnalysis reads NA and CL as sodium and chlorine whatever the residue, which
// makes heme's pyrrole nitrogen NA sodium; the residue tells them apart here.
std::string ionElement(std::string_view name, std::string_view residue) {
  const std::string atom = ionName(name);
  if (atom.empty()) return {};
  if (equalsIgnoreCase(trim(residue), "ION") || ionName(residue) == atom) return atom;
  return {};
}

}  // namespace

bool isMartiniWaterResidue(std::string_view residue) {
  static const NameList kMartiniWater{"W", "WF", "PW"};
  return kMartiniWater.contains(residue);
}

bool isWaterVirtualSite(std::string_view name) {
  std::string key = toUpper(trim(name));
  std::size_t skip = 0;
  while (skip < key.size() && isDigit(key[skip])) ++skip;
  key.erase(0, skip);
  // GROMACS TIP4P: MW; Amber OPC/TIP4P-Ew: EPW; TIP5P: LP1, LP2 (or EP1, EP2); CHARMM TIP4P: OM.
  return key.rfind('M', 0) == 0 || key.rfind("LP", 0) == 0 || key.rfind("EP", 0) == 0 ||
         key == "OM";
}

bool isPlausibleElement(std::string_view residue, std::string_view element) {
  return isPlausibleElement(isWaterResidue(residue), isStandardResidue(residue), element);
}

bool isPlausibleElement(bool water, bool standard, std::string_view element) {
  if (water) return element == "H" || element == "D" || element == "O";
  if (standard)
    return element == "H" || element == "D" || element == "C" || element == "N" ||
           element == "O" || element == "S" || element == "P" || element == "Se";
  return true;
}

std::string elementFromAtomName(std::string_view name, std::string_view residue,
                                AtomNameLayout layout) {
  if (std::string ion = ionElement(name, residue); !ion.empty()) return ion;
  if (layout == AtomNameLayout::Token) return elementFromToken(name, residue);

  const std::string_view trimmed = trim(name);
  // Leading digits number hydrogens in old PDB files ("1HB") and some MD names ("1C4A").
  std::size_t skip = 0;
  while (skip < trimmed.size() && isDigit(trimmed[skip])) ++skip;
  const std::string_view stem = trimmed.substr(skip);
  if (stem.empty() || !isAlpha(stem[0])) return {};
  const char first = upper(stem[0]);

  if (isStandardResidue(residue) &&
      std::string_view("HCNOSPD").find(first) != std::string_view::npos)
    return std::string(1, first);

  const bool twoLetters = stem.size() >= 2 && isAlpha(stem[1]);
  std::string element;
  // A name that starts in column 14 (or after a digit in column 13) has a one-letter element.
  if (name.empty() || name[0] == ' ' || isDigit(name[0])) {
    element = singleLetterElement(first);
  } else if (name.size() >= 4 && name[3] != ' ' && first == 'H') {
    // Four-character names starting with H are hydrogens (HH31, HG21); Hg, He, Hf, Ho and Hs
    // never have four-character names.
    element = "H";
  } else {
    if (twoLetters) element = canonicalElement(stem.substr(0, 2));
    if (element.empty()) element = singleLetterElement(first);
  }
  // Writers that ignore the columns (" RU1" for ruthenium): the columns said nothing.
  if (element.empty()) element = elementFromToken(name, residue);
  return element;
}

std::optional<double> bondiRadius(std::string_view element) {
  const std::optional<TabulatedRadius> r = elementRadius(element);
  if (!r || r->source == RadiusSource::Alvarez) return std::nullopt;
  return r->radius;
}

std::optional<TabulatedRadius> elementRadius(std::string_view element) {
  for (const ElementRadius& e : kBondi)
    if (e.element == element) return TabulatedRadius{e.radius, RadiusSource::Bondi};
  for (const ElementRadius& e : kMantina)
    if (e.element == element) return TabulatedRadius{e.radius, RadiusSource::Mantina};
  for (const ElementRadius& e : kAlvarez)
    if (e.element == element) return TabulatedRadius{e.radius, RadiusSource::Alvarez};
  return std::nullopt;
}

const char* radiusSourceName(RadiusSource source) {
  switch (source) {
    case RadiusSource::Bondi:
      return "Bondi 1964";
    case RadiusSource::Mantina:
      return "Mantina 2009";
    case RadiusSource::Alvarez:
      return "Alvarez 2013";
    case RadiusSource::UserTable:
      return "--radii table";
    case RadiusSource::File:
      return "file";
    case RadiusSource::Default:
      return "--default-radius";
    case RadiusSource::Bead:
      return "--bead-radius";
    case RadiusSource::Preset:
      return "--radii preset (FreeSASA classifier)";
    case RadiusSource::PresetGuess:
      return "--radii preset (FreeSASA element guess)";
  }
  return "unknown";
}

RadiusTable RadiusTable::load(const std::filesystem::path& path) {
  RadiusTable table;
  table.path_ = path.string();
  // Read as the structure files are: gzipped or not, any line end, lines of bounded length.
  const std::string file = text::readTextFile(path, table.path_);

  std::unordered_map<std::string, int> firstLine;
  text::LineCursor lines(file);
  std::string_view line;
  while (lines.next(line)) {
    const int lineNumber = lines.number();
    std::string_view text(line);
    if (const std::size_t hash = text.find('#'); hash != std::string_view::npos)
      text = text.substr(0, hash);
    text = trim(text);
    if (text.empty()) continue;

    std::vector<std::string_view> fields;
    while (!text.empty()) {
      std::size_t end = 0;
      while (end < text.size() && !isSpace(text[end])) ++end;
      fields.push_back(text.substr(0, end));
      text = trim(text.substr(end));
    }
    if (fields.size() != 2)
      throw InputError(table.path_, lineNumber,
                       "expected 'ELEMENT radius' or 'RES:ATOM radius', got " +
                           std::to_string(fields.size()) + " fields: " + text::inQuotes(trim(line)));
    const std::optional<double> radius = parsePositive(fields[1]);
    if (!radius)
      throw InputError(table.path_, lineNumber,
                       "expected a radius > 0 in Å, got '" + std::string(fields[1]) + "'");

    std::string key;
    std::unordered_map<std::string, double>* target = nullptr;
    if (const std::size_t colon = fields[0].find(':'); colon != std::string_view::npos) {
      const std::string_view res = fields[0].substr(0, colon);
      const std::string_view atom = fields[0].substr(colon + 1);
      if (res.empty() || atom.empty() || atom.find(':') != std::string_view::npos)
        throw InputError(table.path_, lineNumber,
                         "expected RES:ATOM (e.g. HEM:FE), got '" + std::string(fields[0]) + "'");
      key = toUpper(res) + ":" + toUpper(atom);
      target = &table.byAtom_;
    } else {
      key = canonicalElement(fields[0]);
      if (key.empty())
        throw InputError(
            table.path_, lineNumber,
            "expected an element symbol or RES:ATOM, got '" + std::string(fields[0]) + "'");
      target = &table.byElement_;
    }
    if (const auto [it, inserted] = firstLine.emplace(key, lineNumber); !inserted)
      throw InputError(table.path_, lineNumber,
                       "'" + key + "' is already given on line " + std::to_string(it->second));
    target->emplace(std::move(key), *radius);
  }
  if (table.size() == 0) throw InputError(table.path_, 0, "the radius table has no entries");
  return table;
}

std::optional<double> RadiusTable::find(std::string_view residue, std::string_view atom,
                                        std::string_view element) const {
  if (!byAtom_.empty()) {
    const auto it = byAtom_.find(toUpper(trim(residue)) + ":" + toUpper(trim(atom)));
    if (it != byAtom_.end()) return it->second;
  }
  if (const auto it = byElement_.find(std::string(element)); it != byElement_.end())
    return it->second;
  return std::nullopt;
}

std::optional<double> RadiusTable::findAtom(std::string_view residue, std::string_view atom) const {
  if (byAtom_.empty()) return std::nullopt;
  const auto it = byAtom_.find(toUpper(trim(residue)) + ":" + toUpper(trim(atom)));
  if (it == byAtom_.end()) return std::nullopt;
  return it->second;
}

}  // namespace surftrace::build

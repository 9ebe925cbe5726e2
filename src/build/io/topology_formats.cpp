// GRO and PSF topologies: the atoms of a GROMACS GRO file (and the layout of its frames) and
// of the !NATOM section of a CHARMM/NAMD/X-PLOR PSF.
#include "build/io/topology_formats.hpp"

#include <algorithm>
#include <array>
#include <charconv>
#include <cmath>
#include <cstdint>
#include <cstring>
#include <numbers>
#include <optional>
#include <string_view>
#include <type_traits>
#include <unordered_map>
#include <utility>

#include "build/io/error.hpp"
#include "build/io/line_cursor.hpp"
#include "build/io/radii.hpp"
#include "build/io/text_fields.hpp"

namespace surftrace::build::detail {

namespace {

using namespace text;

// ---------------------------------------------------------------------------------------------
// GRO

// The box line: v1(x) v2(y) v3(z), then for a triclinic box v1(y) v1(z) v2(x) v2(z) v3(x)
// v3(y) (GROMACS manual, "gro file"), all in nm.
std::optional<std::vector<double>> groBox(std::string_view line) {
  const std::vector<std::string_view> fields = splitFields(line);
  if (fields.size() != 3 && fields.size() != 9) return std::nullopt;
  std::vector<double> values;
  for (std::string_view f : fields) {
    const std::optional<double> v = parseWhole<double>(f);
    if (!v || !std::isfinite(*v)) return std::nullopt;
    values.push_back(*v);
  }
  return values;
}

// a, b, c in Å and alpha (b, c), beta (a, c), gamma (a, b) in degrees; none for a zero box,
// which GROMACS writes when there is no box.
std::optional<std::array<double, 6>> groCell(const std::vector<double>& box) {
  glm::dvec3 a(box[0], 0.0, 0.0), b(0.0, box[1], 0.0), c(0.0, 0.0, box[2]);
  if (box.size() == 9) {
    a = {box[0], box[3], box[4]};
    b = {box[5], box[1], box[6]};
    c = {box[7], box[8], box[2]};
  }
  const auto length = [](const glm::dvec3& v) {
    return std::sqrt(v.x * v.x + v.y * v.y + v.z * v.z);
  };
  const double la = length(a), lb = length(b), lc = length(c);
  if (la == 0.0 && lb == 0.0 && lc == 0.0) return std::nullopt;
  const auto angle = [&](const glm::dvec3& u, const glm::dvec3& v, double lu, double lv) {
    if (lu == 0.0 || lv == 0.0) return 90.0;
    const double cosine = (u.x * v.x + u.y * v.y + u.z * v.z) / (lu * lv);
    return std::acos(std::clamp(cosine, -1.0, 1.0)) * (180.0 / std::numbers::pi);
  };
  // Rectangular boxes give exactly 90, not acos(0) rounded.
  const auto orthogonal = [](const glm::dvec3& u, const glm::dvec3& v) {
    return u.x * v.x + u.y * v.y + u.z * v.z == 0.0;
  };
  return std::array<double, 6>{10.0 * la,
                               10.0 * lb,
                               10.0 * lc,
                               orthogonal(b, c) ? 90.0 : angle(b, c, lb, lc),
                               orthogonal(a, c) ? 90.0 : angle(a, c, la, lc),
                               orthogonal(a, b) ? 90.0 : angle(a, b, la, lb)};
}

// The number after `key` ("t=", "step=") in a title, where the key starts a word.
template <typename T>
std::optional<T> titleValue(std::string_view title, std::string_view key) {
  std::size_t pos = 0;
  while ((pos = title.find(key, pos)) != std::string_view::npos) {
    const bool wordStart = pos == 0 || isSpace(title[pos - 1]);
    pos += key.size();
    if (!wordStart) continue;
    std::size_t start = pos;
    while (start < title.size() && isSpace(title[start])) ++start;
    std::size_t end = start;
    while (end < title.size() && !isSpace(title[end])) ++end;
    const std::optional<T> v = parseWhole<T>(title.substr(start, end - start));
    if (!v) continue;
    if constexpr (std::is_floating_point_v<T>) {
      if (std::isfinite(*v)) return v;
    } else {
      return v;
    }
  }
  return std::nullopt;
}

std::string groColumns(std::size_t first, std::size_t width) {
  return "columns " + std::to_string(first + 1) + "-" + std::to_string(first + width);
}

// ---------------------------------------------------------------------------------------------
// PSF elements by mass

struct ElementMass {
  const char* element;
  double mass;  // u
};

// Standard atomic weights (IUPAC 2013 conventional values; the mass number of the longest-
// lived isotope for elements without a stable one), and deuterium, which CHARMM and NAMD
// files use for deuterated hydrogens.
constexpr ElementMass kMasses[] = {
    {"H", 1.008},   {"D", 2.014},   {"He", 4.0026}, {"Li", 6.94},   {"Be", 9.0122}, {"B", 10.81},
    {"C", 12.011},  {"N", 14.007},  {"O", 15.999},  {"F", 18.998},  {"Ne", 20.180}, {"Na", 22.990},
    {"Mg", 24.305}, {"Al", 26.982}, {"Si", 28.085}, {"P", 30.974},  {"S", 32.06},   {"Cl", 35.45},
    {"Ar", 39.948}, {"K", 39.098},  {"Ca", 40.078}, {"Sc", 44.956}, {"Ti", 47.867}, {"V", 50.942},
    {"Cr", 51.996}, {"Mn", 54.938}, {"Fe", 55.845}, {"Co", 58.933}, {"Ni", 58.693}, {"Cu", 63.546},
    {"Zn", 65.38},  {"Ga", 69.723}, {"Ge", 72.630}, {"As", 74.922}, {"Se", 78.971}, {"Br", 79.904},
    {"Kr", 83.798}, {"Rb", 85.468}, {"Sr", 87.62},  {"Y", 88.906},  {"Zr", 91.224}, {"Nb", 92.906},
    {"Mo", 95.95},  {"Tc", 98.0},   {"Ru", 101.07}, {"Rh", 102.91}, {"Pd", 106.42}, {"Ag", 107.87},
    {"Cd", 112.41}, {"In", 114.82}, {"Sn", 118.71}, {"Sb", 121.76}, {"Te", 127.60}, {"I", 126.90},
    {"Xe", 131.29}, {"Cs", 132.91}, {"Ba", 137.33}, {"La", 138.91}, {"Ce", 140.12}, {"Pr", 140.91},
    {"Nd", 144.24}, {"Pm", 145.0},  {"Sm", 150.36}, {"Eu", 151.96}, {"Gd", 157.25}, {"Tb", 158.93},
    {"Dy", 162.50}, {"Ho", 164.93}, {"Er", 167.26}, {"Tm", 168.93}, {"Yb", 173.05}, {"Lu", 174.97},
    {"Hf", 178.49}, {"Ta", 180.95}, {"W", 183.84},  {"Re", 186.21}, {"Os", 190.23}, {"Ir", 192.22},
    {"Pt", 195.08}, {"Au", 196.97}, {"Hg", 200.59}, {"Tl", 204.38}, {"Pb", 207.2},  {"Bi", 208.98},
    {"Po", 209.0},  {"At", 210.0},  {"Rn", 222.0},  {"Fr", 223.0},  {"Ra", 226.0},  {"Ac", 227.0},
    {"Th", 232.04}, {"Pa", 231.04}, {"U", 238.03},  {"Np", 237.0},  {"Pu", 244.0},  {"Am", 243.0},
    {"Cm", 247.0},  {"Bk", 247.0},  {"Cf", 251.0},  {"Es", 252.0},  {"Fm", 257.0},  {"Md", 258.0},
    {"No", 259.0},  {"Lr", 262.0},
};

// Within this of a standard weight a mass names the element. Force fields round weights
// differently (CHARMM: O 15.9994 or 15.999, S 32.06 or 32.065), but the closest two standard
// weights that matter, Ar and Ca, are 0.13 u apart. United atoms (CH3 15.035) match nothing
// and fall back to the name, except CH2 (14.027), which lies 0.02 u from nitrogen.
constexpr double kMassTolerance = 0.1;

std::string elementOfMass(double mass) {
  const ElementMass* best = nullptr;
  for (const ElementMass& e : kMasses)
    if (!best || std::abs(e.mass - mass) < std::abs(best->mass - mass)) best = &e;
  if (best && std::abs(best->mass - mass) <= kMassTolerance) return best->element;
  return {};
}

// One !NATOM line's fields: id segid resid resname name type charge mass [...]. Returns why
// they do not read, or "" with `atom` filled (element by mass, else by name).
std::string psfAtom(const std::vector<std::string_view>& f, AtomRecord& atom) {
  if (f.size() < 8)
    return "expected 8 fields (id segid resid resname name type charge mass), got " +
           std::to_string(f.size());
  const std::optional<int> id = parseWhole<int>(f[0]);
  if (!id) return "expected an atom number (field 1), got " + inQuotes(f[0]);
  if (!parseResidueNumber(f[2], atom.residueNumber, atom.insertionCode))
    return "expected a residue number (field 3), got " + inQuotes(f[2]);
  const char* what[] = {"the charge (field 7)", "the mass (field 8)"};
  double values[2];
  for (std::size_t k = 0; k < 2; ++k) {
    const std::optional<double> v = parseWhole<double>(f[6 + k]);
    if (!v) return std::string("expected a number for ") + what[k] + ", got " + inQuotes(f[6 + k]);
    if (!std::isfinite(*v)) return std::string(what[k]) + " is not finite: " + inQuotes(f[6 + k]);
    values[k] = *v;
  }
  atom.serial = *id;
  // A PSF has segments but no chains: the segment id serves as both.
  atom.segid = std::string(f[1]);
  atom.chain = atom.segid;
  atom.residue = std::string(f[3]);
  atom.name = std::string(f[4]);
  atom.charge = values[0];
  // Atom types are force-field names or numbers (adk.psf), so the mass tells the element.
  // A massless site of a water (TIP4P's OM) has no element, whatever its name says; elsewhere
  // a mass of 0 is a writer that gave none, and the name tells.
  atom.element = elementOfMass(values[1]);
  atom.elementSource = ElementSource::Mass;
  if (atom.element.empty() && (values[1] != 0.0 || !isWaterResidue(atom.residue))) {
    atom.element = elementFromAtomName(atom.name, atom.residue, AtomNameLayout::Token);
    atom.elementSource = ElementSource::Name;
  }
  if (atom.element.empty()) atom.elementSource = ElementSource::None;
  return {};
}

}  // namespace

// ---------------------------------------------------------------------------------------------
// Frame indexes

std::string frameName(std::size_t index) { return "frame " + std::to_string(index); }

void endFrameIndex(const std::string& path, int line, const std::string& why,
                   std::size_t indexed, std::string& note) {
  if (indexed == 0) throw InputError(path, line, why);
  note = path + ":" + std::to_string(line) + ": " + why + "; " +
         (indexed == 1 ? std::string("only frame 0 is read")
                       : "only frames 0-" + std::to_string(indexed - 1) + " are read");
}

// ---------------------------------------------------------------------------------------------
// GRO

std::vector<GroFrameSpan> indexGroFrames(const std::string& text, const std::string& path,
                                         std::string& note) {
  note.clear();
  std::vector<GroFrameSpan> spans;
  LineCursor cursor(text, 0, 1);
  std::string_view line;
  const auto stop = [&](int lineNumber, const std::string& why) {
    endFrameIndex(path, lineNumber, why, spans.size(), note);
  };
  while (!cursor.onlySpaceLeft()) {
    GroFrameSpan span;
    span.offset = cursor.offset();
    span.line = cursor.number() + 1;
    const std::string frame = frameName(spans.size());
    cursor.next(line);  // the title
    if (!cursor.next(line)) {
      stop(span.line, "the file ends after the title line of " + frame);
      break;
    }
    const int countLine = cursor.number();
    const std::optional<long long> count = parseWhole<long long>(line);
    if (!count || *count < 0) {
      stop(countLine, "expected the atom count of " + frame + ", got " + inQuotes(trim(line)));
      break;
    }
    span.atoms = static_cast<std::size_t>(*count);
    const std::size_t present = cursor.skip(span.atoms);
    std::string_view boxLine;
    if (present < span.atoms || !cursor.next(boxLine)) {
      stop(countLine, "the atom count of " + frame + " is " + std::to_string(span.atoms) +
                          ", but the file ends " + std::to_string(present) +
                          " lines later, before the atoms and the box line are complete");
      break;
    }
    spans.push_back(span);
    // The box line shows whether the count held: a count larger than the frame reads the
    // next frame's lines here. The frame stays in the index, so that reading it reports the
    // line that is wrong.
    if (!groBox(boxLine)) {
      note = path + ":" + std::to_string(cursor.number()) + ": " + frame +
             " has no box line where its atom count (" + std::to_string(span.atoms) +
             ") puts it; the frames after it are not read";
      break;
    }
  }
  if (spans.empty()) throw InputError(path, 0, "no GRO frame (the file is blank)");
  return spans;
}

namespace {

// elementFromAtomName(name, residue, Token) once per distinct pair of names: a system of a
// million atoms has a few hundred, and the guess (ion, residue and element tables) was a seventh
// of reading a large GRO file. Keyed on the AtomStrings' bytes, which equal texts share (the
// same bytes in place, the same index of a long text).
class ElementGuesses {
 public:
  const AtomString& operator()(const AtomString& name, const AtomString& residue) {
    const Key key{bytesOf(name), bytesOf(residue)};
    auto it = known_.find(key);
    if (it == known_.end())
      it = known_.emplace(key, AtomString(elementFromAtomName(name, residue, AtomNameLayout::Token))).first;
    return it->second;
  }

 private:
  static_assert(std::is_trivially_copyable_v<AtomString> && sizeof(AtomString) == sizeof(std::uint64_t));
  using Key = std::pair<std::uint64_t, std::uint64_t>;
  struct KeyHash {
    std::size_t operator()(const Key& k) const noexcept {
      return std::hash<std::uint64_t>()(k.first * 0x9E3779B97F4A7C15ull ^ k.second);
    }
  };
  static std::uint64_t bytesOf(const AtomString& s) {
    std::uint64_t bytes;
    std::memcpy(&bytes, &s, sizeof bytes);
    return bytes;
  }
  std::unordered_map<Key, AtomString, KeyHash> known_;
};

}  // namespace

void readGroFrame(const std::string& text, const std::string& path, const GroFrameSpan& span,
                  std::size_t index, Frame& frame, std::vector<AtomRecord>* records) {
  ElementGuesses guessElement;
  const std::string name = frameName(index);
  LineCursor cursor(text, span.offset, span.line);
  std::string_view title;
  std::string_view line;
  cursor.next(title);
  cursor.next(line);  // the count, already in span.atoms
  frame.positions.resize(span.atoms);
  if (records) {
    records->clear();
    records->reserve(span.atoms);
  }

  const AtomString system("SYSTEM");
  std::size_t width = 8;  // "%8.3f": GROMACS writes decimals + 5 columns per coordinate
  int residueOffset = 0;  // GROMACS writes residue numbers modulo 100000
  int lastResidue = 0;
  for (std::size_t i = 0; i < span.atoms; ++i) {
    if (!cursor.next(line))
      throw InputError(path, cursor.number(),
                       "the file ends after " + std::to_string(i) + " of the " +
                           std::to_string(span.atoms) + " atoms of " + name);
    const int lineNumber = cursor.number();
    if (i == 0) {
      // The precision is the first coordinate's: the digits after its decimal point.
      const std::size_t dot = line.size() > 20 ? line.find('.', 20) : std::string_view::npos;
      std::size_t decimals = 0;
      while (dot != std::string_view::npos && dot + 1 + decimals < line.size() &&
             isDigit(line[dot + 1 + decimals]))
        ++decimals;
      if (decimals == 0)
        throw InputError(path, lineNumber,
                         "expected x, y, z in nm from column 21 (" + name + "), got " +
                             inQuotes(line.size() > 20 ? trim(line.substr(20)) : ""));
      width = decimals + 5;
    }
    if (line.size() < 20 + 3 * width)
      throw InputError(path, lineNumber,
                       "the atom line of " + name + " ends at column " +
                           std::to_string(line.size()) + "; expected x, y, z in " +
                           groColumns(20, 3 * width) + ": " + inQuotes(line));
    const char* axes[] = {"x", "y", "z"};
    for (std::size_t k = 0; k < 3; ++k) {
      const std::string_view field = line.substr(20 + k * width, width);
      const std::optional<double> v = parseWhole<double>(field);
      if (!v)
        throw InputError(path, lineNumber,
                         std::string("expected a number for ") + axes[k] + " in " +
                             groColumns(20 + k * width, width) + ", got " + inQuotes(field));
      if (!std::isfinite(*v))
        throw InputError(path, lineNumber,
                         std::string(axes[k]) + " in " + groColumns(20 + k * width, width) +
                             " is not finite: " + inQuotes(trim(field)));
      frame.positions[i][static_cast<int>(k)] = 10.0 * *v;  // nm to Å
    }
    if (!records) continue;
    AtomRecord& atom = records->emplace_back();  // in place, its texts from views (no std::string each)
    const std::optional<int> residue = parseWhole<int>(line.substr(0, 5));
    if (!residue)
      throw InputError(
          path, lineNumber,
          "expected a residue number in columns 1-5, got " + inQuotes(line.substr(0, 5)));
    if (*residue == 0 && i > 0 && lastResidue != 0) residueOffset += 100000;
    lastResidue = *residue;
    atom.residueNumber = *residue + residueOffset;
    atom.residue = trim(line.substr(5, 5));
    atom.name = trim(line.substr(10, 5));
    atom.segid = system;  // GRO has no segments; MDAnalysis names its one segment so
    atom.serial = parseWhole<int>(line.substr(15, 5)).value_or(0);
    // GROMACS right-justifies names in their 5 columns, so the column tells nothing.
    atom.element = guessElement(atom.name, atom.residue);
    if (!atom.element.empty()) atom.elementSource = ElementSource::Name;
    atom.line = lineNumber;
  }
  if (!cursor.next(line))
    throw InputError(path, cursor.number(), "the file ends before the box line of " + name);
  const std::optional<std::vector<double>> box = groBox(line);
  if (!box)
    throw InputError(path, cursor.number(),
                     "expected the box of " + name + " (3 or 9 numbers in nm), got " +
                         inQuotes(trim(line)) + " (is the atom count " +
                         std::to_string(span.atoms) + " right?)");
  frame.cell = groCell(*box);
  frame.time = titleValue<double>(title, "t=").value_or(static_cast<double>(index));
  frame.step = titleValue<long long>(title, "step=").value_or(static_cast<long long>(index));
}

Molecule parseGro(const std::string& text, const std::string& path) {
  std::string note;
  const std::vector<GroFrameSpan> spans = indexGroFrames(text, path, note);
  Molecule molecule;
  molecule.source = path;
  Frame frame;
  readGroFrame(text, path, spans.front(), 0, frame, &molecule.atoms);
  molecule.centers = std::move(frame.positions);
  molecule.modelCount = static_cast<int>(spans.size());
  molecule.modelUsed = 1;
  return molecule;
}

// ---------------------------------------------------------------------------------------------
// PSF

Molecule parsePsf(const std::string& text, const std::string& path) {
  LineCursor cursor(text, 0, 1);
  std::string_view line;
  if (!cursor.next(line) || trim(line).substr(0, 3) != "PSF")
    throw InputError(path, 1,
                     "expected the PSF header (PSF, then flags such as EXT or CMAP), got " +
                         inQuotes(trim(line)));
  bool extended = false;
  for (std::string_view flag : splitFields(trim(line).substr(3))) extended |= flag == "EXT";
  // The line "N !KEY" that opens a section, after blank lines.
  const auto section = [&](const char* key) -> std::size_t {
    bool more = false;
    while ((more = cursor.next(line)) && trim(line).empty()) {
    }
    if (!more)
      throw InputError(path, cursor.number(),
                       std::string("the file ends before the ") + key + " section");
    const std::vector<std::string_view> f = splitFields(line);
    long long n = -1;
    if (f.size() >= 2 && f[1].substr(0, std::strlen(key)) == key)
      n = parseWhole<long long>(f[0]).value_or(-1);
    if (n < 0)
      throw InputError(path, cursor.number(),
                       std::string("expected '<count> ") + key + "', got " + inQuotes(trim(line)));
    return static_cast<std::size_t>(n);
  };

  const std::size_t titles = section("!NTITLE");
  if (cursor.skip(titles) < titles)
    throw InputError(path, cursor.number(),
                     "the file ends inside the " + std::to_string(titles) + " !NTITLE lines");
  const std::size_t atoms = section("!NATOM");
  const int countLine = cursor.number();

  Molecule molecule;
  molecule.source = path;
  molecule.modelCount = 1;
  molecule.modelUsed = 1;
  molecule.atoms.reserve(atoms);
  const double nan = std::nan("");
  molecule.centers.assign(atoms, glm::dvec3(nan, nan, nan));
  const auto fewer = [&](std::size_t found, const std::string& where) {
    return InputError(path, countLine,
                      "the !NATOM count is " + std::to_string(atoms) + ", but only " +
                          std::to_string(found) + " atom lines follow (" + where + ")");
  };
  for (std::size_t i = 0; i < atoms; ++i) {
    if (!cursor.next(line)) throw fewer(i, "then the file ends");
    const int lineNumber = cursor.number();
    const std::vector<std::string_view> f = splitFields(line);
    if (f.empty() || (f.size() >= 2 && f[1].front() == '!'))
      throw fewer(i, "line " + std::to_string(lineNumber) + " is " + inQuotes(trim(line)));
    AtomRecord atom;
    const std::string why = psfAtom(f, atom);
    // CHARMM's fixed columns (the layouts MDAnalysis reads) where the fields do not split:
    // a blank segment id. The five name fields from the columns, the rest split.
    if (!why.empty()) {
      const std::size_t columns[2][6] = {{0, 8, 13, 18, 23, 28}, {0, 10, 19, 28, 37, 46}};
      const std::size_t* c = columns[extended ? 1 : 0];
      std::vector<std::string_view> fixed;
      for (std::size_t k = 0; k < 5 && line.size() > c[k + 1]; ++k)
        fixed.push_back(
            trim(line.substr(c[k] + (k > 0 ? 1 : 0), c[k + 1] - c[k] - (k > 0 ? 1 : 0))));
      if (fixed.size() == 5)
        for (std::string_view rest : splitFields(line.substr(c[5]))) fixed.push_back(rest);
      AtomRecord columnAtom;
      if (fixed.size() < 8 || !psfAtom(fixed, columnAtom).empty())
        throw InputError(path, lineNumber, why + ": " + inQuotes(trim(line)));
      atom = std::move(columnAtom);
    }
    atom.line = lineNumber;
    molecule.atoms.push_back(std::move(atom));
  }
  if (atoms == 0) throw InputError(path, countLine, "the !NATOM section holds no atoms");
  return molecule;
}

}  // namespace surftrace::build::detail

// PDB and mmCIF through gemmi: the one translation unit that compiles gemmi, so that its
// slow-to-compile headers stay out of every other file.
// clang-format off
#define GEMMI_READ_COOR_IMPLEMENTATION
#include <gemmi/read_coor.hpp>
// clang-format on

#include <gemmi/cif.hpp>
#include <gemmi/pdb.hpp>

#include <algorithm>
#include <array>
#include <charconv>
#include <cmath>
#include <cstring>
#include <optional>
#include <string>
#include <string_view>
#include <unordered_map>
#include <utility>
#include <vector>

#include "build/core/assert.hpp"
#include "build/io/error.hpp"
#include "build/io/molecule.hpp"
#include "build/io/pdb_records.hpp"
#include "build/io/radii.hpp"
#include "build/io/text_fields.hpp"

namespace surftrace::build::detail {

// Called by readMolecule (molecule.cpp). Each returns the atoms of the 1-based `model` in file
// order, with line numbers, elements (given or inferred) and alternate locations, but no
// radii and no selection. `text` is the decompressed file.
Molecule readPdbWithGemmi(std::string text, const std::string& path, int model);
Molecule readMmcifWithGemmi(const std::string& text, const std::string& path, int model);
// Called by the mmCIF trajectory reader (text_trajectory.cpp): the positions of every model,
// models in order of first appearance, atoms in file order, and the unit cell from _cell.*
// when the file gives all six numbers.
std::vector<std::vector<glm::dvec3>> readMmcifModelsWithGemmi(
    const std::string& text, const std::string& path, std::optional<std::array<double, 6>>& cell);

namespace {

using text::inQuotes;
using text::isAlpha;
using text::isSpace;
using text::trim;
using text::upper;

// A whole-field decimal number. gemmi's own readers parse what they can and ignore the rest
// ("abc" reads as 0, "1.2.3" as 1.2, "nan" as NaN), so every number SurfTrace uses is
// checked here first.
bool parseWhole(std::string_view text, double& value) {
  const char* first = text.data();
  const char* last = text.data() + text.size();
  if (first != last && *first == '+') ++first;
  const auto [ptr, ec] = std::from_chars(first, last, value);
  return ec == std::errc() && ptr == last;
}

std::string modelCountText(std::size_t n) {
  return std::to_string(n) + (n == 1 ? " model" : " models");
}

[[noreturn]] void throwNoSuchModel(const std::string& path, int model, std::size_t count) {
  throw InputError(path, 0,
                   "model " + std::to_string(model) + " was asked for, but the file has " +
                       modelCountText(count));
}

// ---------------------------------------------------------------------------------------------
// PDB

struct PdbAtomLine {
  std::size_t start = 0;   // offset of the line in the text
  std::size_t length = 0;  // without the line end
  int line = 0;
  int serial = 0;
  double occupancy = 1.0;
  double bFactor = 0.0;
};

// A fixed-column number (1-based inclusive columns). Blank gives `blank`, or an error when
// the field is required.
double pdbNumber(std::string_view line, std::size_t firstColumn, std::size_t lastColumn,
                 const char* what, std::optional<double> blank, const std::string& path,
                 int lineNumber) {
  std::string_view field;
  if (line.size() >= firstColumn)
    field = line.substr(firstColumn - 1, std::min(lastColumn, line.size()) - (firstColumn - 1));
  // (Spelt out only for a message: three per atom were a tenth of reading a large file.)
  const auto columns = [&] { return std::to_string(firstColumn) + "-" + std::to_string(lastColumn); };
  const std::string_view text = trim(field);
  if (text.empty()) {
    if (blank) return *blank;
    throw InputError(path, lineNumber,
                     std::string("expected a number for ") + what + " in columns " + columns() +
                         ", got a blank field");
  }
  double value = 0.0;
  if (!parseWhole(text, value))
    throw InputError(path, lineNumber,
                     std::string("expected a number for ") + what + " in columns " + columns() +
                         ", got " + inQuotes(field));
  if (!std::isfinite(value))
    throw InputError(
        path, lineNumber,
        std::string(what) + " in columns " + columns() + " is not finite: " + inQuotes(text));
  return value;
}

// A fixed-column number that may be absent or unreadable: `blank` for a blank field, NaN
// for text that is not a finite number.
double pdbLenientNumber(std::string_view line, std::size_t firstColumn, std::size_t lastColumn,
                        double blank) {
  if (line.size() < firstColumn) return blank;
  const std::string_view text =
      trim(line.substr(firstColumn - 1, std::min(lastColumn, line.size()) - (firstColumn - 1)));
  if (text.empty()) return blank;
  double value = 0.0;
  if (!parseWhole(text, value) || !std::isfinite(value)) return std::nan("");
  return value;
}

// Serial numbers as gemmi reads them: decimal, or hybrid-36 past 99999; overflow markers
// such as "*****" read as 0.
int pdbSerial(std::string_view line) {
  const std::string_view field = trim(line.substr(6, 5));
  if (field.empty()) return 0;
  if (field[0] >= 'A' && field[0] <= 'Z' && field.size() == 5) {
    long value = 0;
    for (char c : field) {
      int digit = 0;
      if (c >= '0' && c <= '9')
        digit = c - '0';
      else if (c >= 'A' && c <= 'Z')
        digit = c - 'A' + 10;
      else
        return 0;
      value = value * 36 + digit;
    }
    return static_cast<int>(value - 16796160 + 100000);
  }
  int value = 0;
  const auto [ptr, ec] = std::from_chars(field.data(), field.data() + field.size(), value);
  return (ec == std::errc() && ptr == field.data() + field.size()) ? value : 0;
}

// Writes `value` into the 5-character serial field, in hybrid-36 past 99999 so that gemmi's
// read_serial gives it back.
void writeSerialTag(char* field, int value) {
  if (value < 100000) {
    for (int i = 4; i >= 0; --i) {
      field[i] = static_cast<char>('0' + value % 10);
      value /= 10;
    }
    return;
  }
  long code = static_cast<long>(value) - 100000 + 16796160;
  for (int i = 4; i >= 0; --i) {
    const int digit = static_cast<int>(code % 36);
    field[i] = static_cast<char>(digit < 10 ? '0' + digit : 'A' + digit - 10);
    code /= 36;
  }
}

// gemmi reports "Problem in line N: ..." for its own complaints.
InputError fromGemmi(const std::string& path, const std::exception& e) {
  std::string message = e.what();
  int line = 0;
  const std::string prefix = "Problem in line ";
  if (message.rfind(prefix, 0) == 0) {
    std::size_t pos = prefix.size();
    while (pos < message.size() && message[pos] >= '0' && message[pos] <= '9')
      line = line * 10 + (message[pos++] - '0');
    if (message.compare(pos, 2, ": ") == 0) message.erase(0, pos + 2);
  }
  std::replace(message.begin(), message.end(), '\n', ' ');
  return InputError(path, line, "gemmi: " + message);
}

// `unknown` receives the element column's letters when they name no element ("Xx"), so
// that the reader can say what it assumed instead.
std::string pdbElement(std::string_view line, const std::string& residue, ElementSource& source,
                       std::string& unknown) {
  // Columns 77-78 hold the element in remediated files; older files have the entry ID and a
  // line serial in columns 73-80, so digits there are not an element.
  unknown.clear();
  if (line.size() >= 77) {
    const std::string_view field =
        trim(line.substr(76, std::min<std::size_t>(2, line.size() - 76)));
    if (!field.empty() && std::all_of(field.begin(), field.end(), isAlpha)) {
      std::string element = canonicalElement(field);
      source = ElementSource::File;
      if (!element.empty()) return element;
      unknown = std::string(field);
    }
  }
  std::string element = elementFromAtomName(line.substr(12, 4), residue, AtomNameLayout::PdbColumns);
  source = element.empty() ? ElementSource::None : ElementSource::Name;
  return element;
}

// A note on an element column that names no element: what was taken instead. At most
// kMaxElementNotes such notes, then one that counts the rest.
constexpr std::size_t kMaxElementNotes = 10;
void noteUnknownElement(Molecule& molecule, std::size_t& count, int line, const std::string& where,
                        const std::string& symbol, const AtomRecord& atom) {
  if (++count > kMaxElementNotes) return;
  std::string note = "line " + std::to_string(line) + ": " + where + " " + inQuotes(symbol) + " is no element";
  note += atom.element.empty() ? std::string("; the atom name ") + inQuotes(atom.name) + " gives none either"
                               : "; took " + atom.element + " from the atom name " + inQuotes(atom.name);
  molecule.notes.push_back(note);
}
void countMoreElementNotes(Molecule& molecule, std::size_t count) {
  if (count > kMaxElementNotes)
    molecule.notes.push_back(std::to_string(count - kMaxElementNotes) + " more atoms whose element column names no element");
}

// Records after which gemmi may put an atom in another model than the first or refuse the
// file (MODEL, ENDMDL, ANISOU, the SSBOND/LINK/CISPEP records of its process_conn, an mmCIF or
// mmJSON start), told as gemmi's read_pdb tells records (is_record_type: the first four bytes,
// bit 0x20 ignored). A file with none of them is one model whose atoms gemmi reads from their
// own lines alone (every other record only sets the Structure's metadata), so readPdbWithGemmi
// can take the atoms with gemmi's own field readers without building the Structure.
bool needsGemmiStructure(std::string_view line) {
  if (line.size() < 4) return false;  // no 4-byte record name matches a shorter line
  for (const char* record : {"MODEL", "ENDMDL", "ANISOU", "SSBOND", "LINK", "CISPEP", "data", "{\"da"})
    if (gemmi::pdb_impl::is_record_type(line.data(), record)) return true;
  return false;
}

// The notes and segments of a PDB file's atoms, once all are read.
void finishPdbMolecule(Molecule& molecule, std::size_t unknownElements) {
  countMoreElementNotes(molecule, unknownElements);
  // As MDAnalysis's PDBParser: a file without segment ids takes its chains as segments, and
  // one without either is the one segment SYSTEM.
  const auto noSegid = [](const AtomRecord& a) { return a.segid.empty(); };
  if (std::all_of(molecule.atoms.begin(), molecule.atoms.end(), noSegid)) {
    for (AtomRecord& a : molecule.atoms) a.segid = a.chain;
    if (std::all_of(molecule.atoms.begin(), molecule.atoms.end(), noSegid))
      for (AtomRecord& a : molecule.atoms) a.segid = "SYSTEM";
  }
}

}  // namespace

// MODEL records written with the serial right after the keyword ("MODEL 7", as MDAnalysis
// writes them) make gemmi read the serial from columns 11-14 of the *next* line, and then
// fail on a "duplicate MODEL number". Rewrite such records in the standard columns; the
// line count is unchanged, so line numbers stay right. Such files also repeat serials
// ("MODEL 1" twice in incomplete.pdb), and models are chosen by position anyway, so the
// rewritten records are numbered in order of appearance.
static void normalizeModelRecords(std::string& text) {
  // Most files have no such record: they are not copied line by line.
  if (text.compare(0, 5, "MODEL") != 0 && text.find("\nMODEL") == std::string::npos) return;
  std::string out;
  bool changed = false;
  int models = 0;
  std::size_t pos = 0;
  while (pos < text.size()) {
    std::size_t end = text.find('\n', pos);
    if (end == std::string::npos) end = text.size();
    std::string_view line(text.data() + pos, end - pos);
    if (!line.empty() && line.back() == '\r') line.remove_suffix(1);
    std::string_view rest = line.size() > 5 ? trim(line.substr(5)) : std::string_view();
    const bool shortModel = line.size() < 14 && line.substr(0, std::min<std::size_t>(5, line.size())) == "MODEL" &&
                            !rest.empty() && rest.size() <= 4 &&
                            std::all_of(rest.begin(), rest.end(), [](char c) { return c >= '0' && c <= '9'; });
    if (line.substr(0, std::min<std::size_t>(5, line.size())) == "MODEL") ++models;
    if (shortModel && models <= 9999) {
      changed = true;
      const std::string serial = std::to_string(models);
      out.append("MODEL     ").append(4 - serial.size(), ' ').append(serial);
    } else {
      out.append(line);
    }
    if (end < text.size()) out.push_back('\n');
    pos = end + 1;
  }
  if (changed) text = std::move(out);
}

Molecule readPdbWithGemmi(std::string text, const std::string& path, int model) {
  normalizeModelRecords(text);
  // gemmi keeps no line numbers and reorders atoms into chains and residues. One pass over
  // the ATOM/HETATM lines checks the numbers we use and overwrites each serial field with the
  // record's index, so every atom gemmi returns leads back to its line. The charge columns
  // 79-80 are blanked too: gemmi throws on the line serials old entries keep there.
  std::vector<PdbAtomLine> records;
  records.reserve(text.size() / 81 + 1);  // about one an 80-column line
  std::vector<std::array<int, 2>> bondRecords;
  bool structureNeeded = false;  // see needsGemmiStructure
  int lineNumber = 0;
  std::size_t pos = 0;
  while (pos < text.size()) {
    std::size_t end = text.find('\n', pos);
    if (end == std::string::npos) end = text.size();
    ++lineNumber;
    // gemmi reads 120 columns and skips the rest of the line, but its in-memory getc returns
    // a signed char, so it stops skipping at a byte >= 0x80 and reads what follows as a line
    // of its own, an ATOM record this pass never saw (found by fuzz_pdb). Blanking the
    // columns past 120 keeps gemmi's lines ours; it reads none of them anyway.
    if (end - pos > 120) std::fill(text.begin() + static_cast<std::ptrdiff_t>(pos + 120),
                                   text.begin() + static_cast<std::ptrdiff_t>(end), ' ');
    std::string_view line(text.data() + pos, end - pos);
    if (!line.empty() && line.back() == '\r') line.remove_suffix(1);
    if (line.size() > 120) line = line.substr(0, 120);  // gemmi reads no further

    if (pdb::isAtomRecord(line)) {
      if (line.size() < 54)
        throw InputError(path, lineNumber,
                         "ATOM/HETATM record ends at column " + std::to_string(line.size()) +
                             "; expected x, y, z in columns 31-54");
      PdbAtomLine record;
      record.start = pos;
      record.length = line.size();
      record.line = lineNumber;
      pdbNumber(line, 31, 38, "x", std::nullopt, path, lineNumber);
      pdbNumber(line, 39, 46, "y", std::nullopt, path, lineNumber);
      pdbNumber(line, 47, 54, "z", std::nullopt, path, lineNumber);
      // Occupancy matters only to choose among alternate locations, and the B-factor not at
      // all, so a value that is not a finite number (fullerene.pdb has "inf") is an error only
      // for an atom with an alternate location; elsewhere it is kept as NaN, meaning unknown.
      record.occupancy = pdbLenientNumber(line, 55, 60, 1.0);
      if (std::isnan(record.occupancy) && line[16] != ' ')
        pdbNumber(line, 55, 60, "the occupancy of an atom with an alternate location", 1.0, path,
                  lineNumber);
      record.bFactor = pdbLenientNumber(line, 61, 66, 0.0);
      record.serial = pdbSerial(line);
      if (records.size() >= 43000000)
        throw InputError(path, lineNumber, "more than 43 million atom records");
      writeSerialTag(&text[pos + 6], static_cast<int>(records.size()));
      for (std::size_t column = 78; column < std::min<std::size_t>(line.size(), 80); ++column)
        text[pos + column] = ' ';
      records.push_back(record);
    } else if (pdb::recordIs(line, "CONECT")) {
      // gemmi 0.5.7 reads no CONECT records (pdb.hpp: "ignore for now"), so they are read here:
      // the atom's serial in columns 7-11, up to four bonded atoms' in 12-31, as gemmi reads serials.
      const int from = pdbSerial(line);
      for (std::size_t k = 1; k <= 4 && line.size() > 6 + 5 * k; ++k) {
        const int to = pdbSerial(line.substr(5 * k));
        if (from > 0 && to > 0 && from != to) bondRecords.push_back({std::min(from, to), std::max(from, to)});
      }
    } else if (pdb::isEndRecord(line)) {
      break;
    } else if (!structureNeeded) {
      structureNeeded = needsGemmiStructure(line);
    }
    pos = end + 1;
  }
  if (records.empty()) throw InputError(path, 0, "no ATOM or HETATM records");
  if (text.back() != '\n') text.push_back('\n');  // gemmi rejects a short last line without one

  Molecule molecule;
  molecule.source = path;
  molecule.format = MoleculeFormat::Pdb;
  molecule.modelUsed = model;
  molecule.bondRecords = std::move(bondRecords);
  molecule.centers.reserve(records.size());
  molecule.atoms.reserve(records.size());
  std::string unknownSymbol;
  std::size_t unknownElements = 0;
  // One atom from its record and the fields gemmi gives it.
  const auto addAtom = [&](const PdbAtomLine& record, std::string_view atomName, std::string_view residueName,
                           std::string_view chainName, const gemmi::SeqId& seqid, char altloc,
                           const gemmi::Position& xyz) {
    const std::string_view line(text.data() + record.start, record.length);
    AtomRecord atom;
    atom.name = atomName;
    atom.residue = residueName;
    atom.chain = chainName;
    // MDAnalysis's segid: columns 67-76, wider than the segID field (73-76) that gemmi reads.
    if (line.size() > 66) atom.segid = trim(line.substr(66, 10));
    atom.residueNumber = seqid.num.has_value() ? seqid.num.value : 0;
    atom.insertionCode = seqid.icode;
    atom.serial = record.serial;
    atom.element = pdbElement(line, atom.residue, atom.elementSource, unknownSymbol);
    if (!unknownSymbol.empty())
      noteUnknownElement(molecule, unknownElements, record.line, "columns 77-78 hold", unknownSymbol, atom);
    atom.occupancy = record.occupancy;
    atom.bFactor = record.bFactor;
    atom.hetatm = upper(line[0]) == 'H';
    atom.line = record.line;
    atom.altLoc = altloc == '\0' ? ' ' : altloc;
    molecule.centers.emplace_back(xyz.x, xyz.y, xyz.z);
    molecule.atoms.push_back(atom);
  };

  if (!structureNeeded) {
    // One model, each atom read by gemmi's read_pdb field readers from its own line (what
    // read_pdb gives it, without building chains, residues and atoms of strings that would be
    // copied and dropped: a third of reading a large file).
    molecule.modelCount = 1;
    if (model > 1) throwNoSuchModel(path, model, 1);
    using namespace gemmi::pdb_impl;
    for (const PdbAtomLine& record : records) {
      const char* line = text.data() + record.start;
      addAtom(record, read_string(line + 12, 4), read_string(line + 17, 3), read_string(line + 20, 2),
              read_seq_id(line + 22), read_altloc(line[16]),
              gemmi::Position(read_double(line + 30, 8), read_double(line + 38, 8), read_double(line + 46, 8)));
    }
    finishPdbMolecule(molecule, unknownElements);
    return molecule;
  }

  gemmi::Structure structure;
  try {
    structure = gemmi::read_pdb_from_memory(text.data(), text.size(), path);
  } catch (const std::exception& e) {
    throw fromGemmi(path, e);
  }
  molecule.modelCount = static_cast<int>(structure.models.size());
  if (model > molecule.modelCount) throwNoSuchModel(path, model, structure.models.size());

  struct Found {
    std::size_t index;
    const gemmi::Chain* chain;
    const gemmi::Residue* residue;
    const gemmi::Atom* atom;
  };
  std::vector<Found> found;
  found.reserve(records.size());
  std::vector<char> seen(records.size(), 0);
  for (std::size_t m = 0; m < structure.models.size(); ++m) {
    for (const gemmi::Chain& chain : structure.models[m].chains)
      for (const gemmi::Residue& residue : chain.residues)
        for (const gemmi::Atom& atom : residue.atoms) {
          const auto index = static_cast<std::size_t>(atom.serial);
          SURFTRACE_ASSERT(atom.serial >= 0 && index < records.size() && !seen[index]);
          seen[index] = 1;
          if (static_cast<int>(m) + 1 == model)
            found.push_back({index, &chain, &residue, &atom});
          else
            ++molecule.skipped.otherModels;
        }
  }
  if (found.empty()) throw InputError(path, 0, "model " + std::to_string(model) + " has no atoms");
  const auto byIndex = [](const Found& a, const Found& b) { return a.index < b.index; };
  if (!std::is_sorted(found.begin(), found.end(), byIndex)) std::sort(found.begin(), found.end(), byIndex);

  for (const Found& f : found)
    addAtom(records[f.index], f.atom->name, f.residue->name, f.chain->name, f.residue->seqid, f.atom->altloc,
            f.atom->pos);
  finishPdbMolecule(molecule, unknownElements);
  return molecule;
}

// ---------------------------------------------------------------------------------------------
// mmCIF

namespace {

// The line on which each row of a loop starts. gemmi keeps only the line of "loop_", so the
// loop is re-tokenized from there (CIF 1.1 tokens: bare words, quoted strings, ;-text fields,
// # comments). Rows not found (which would mean a tokenizer disagreement) keep line 0.
std::vector<int> loopRowLines(const std::string& text, int loopLine, std::size_t tagCount,
                              std::size_t valueCount) {
  const std::size_t rows = tagCount == 0 ? 0 : valueCount / tagCount;
  std::vector<int> rowLines(rows, 0);
  std::size_t pos = 0;
  int line = 1;
  while (line < loopLine && pos < text.size()) {
    const std::size_t nl = text.find('\n', pos);
    if (nl == std::string::npos) return rowLines;
    pos = nl + 1;
    ++line;
  }
  std::size_t tokens = 0;  // "loop_", the tags, then the values
  const std::size_t wanted = 1 + tagCount + valueCount;
  bool lineStart = true;
  while (pos < text.size() && tokens < wanted) {
    const char c = text[pos];
    if (c == '\n') {
      ++line;
      ++pos;
      lineStart = true;
      continue;
    }
    if (isSpace(c)) {
      ++pos;
      lineStart = false;
      continue;
    }
    const int tokenLine = line;
    if (c == '#') {
      while (pos < text.size() && text[pos] != '\n') ++pos;
      continue;
    }
    if (c == ';' && lineStart) {
      // A text field runs to the next line that starts with ';'.
      ++pos;
      for (;;) {
        const std::size_t nl = text.find('\n', pos);
        if (nl == std::string::npos) return rowLines;
        ++line;
        pos = nl + 1;
        if (pos < text.size() && text[pos] == ';') {
          ++pos;
          break;
        }
      }
    } else if (c == '\'' || c == '"') {
      // A quoted string ends at its quote followed by whitespace.
      ++pos;
      while (pos < text.size() &&
             !(text[pos] == c && (pos + 1 == text.size() || isSpace(text[pos + 1])))) {
        if (text[pos] == '\n') return rowLines;
        ++pos;
      }
      ++pos;
    } else {
      while (pos < text.size() && !isSpace(text[pos])) ++pos;
    }
    lineStart = false;
    if (tokens > tagCount) {
      const std::size_t value = tokens - 1 - tagCount;
      if (value % tagCount == 0) rowLines[value / tagCount] = tokenLine;
    }
    ++tokens;
  }
  return rowLines;
}

std::string cifTag(const char* column) { return std::string("_atom_site.") + column; }

}  // namespace

namespace {

// The 1-based line on which `token` first stands as a whole word, 0 if nowhere.
int lineOfToken(const std::string& text, const std::string& token) {
  std::size_t pos = 0;
  while (!token.empty() && (pos = text.find(token, pos)) != std::string::npos) {
    const std::size_t end = pos + token.size();
    if ((pos == 0 || isSpace(text[pos - 1])) && (end == text.size() || isSpace(text[end])))
      return 1 + static_cast<int>(std::count(text.begin(), text.begin() + static_cast<std::ptrdiff_t>(pos), '\n'));
    pos = end;
  }
  return 0;
}

Molecule readMmcifTable(const std::string& text, const std::string& path, int model);

}  // namespace

Molecule readMmcifWithGemmi(const std::string& text, const std::string& path, int model) {
  // gemmi's lookups throw std::runtime_error on tables it cannot index (a loop mixing two
  // categories: "Tag _x.y in loop with _atom_site."); they become InputErrors at the tag.
  try {
    return readMmcifTable(text, path, model);
  } catch (const InputError&) {
    throw;
  } catch (const std::runtime_error& e) {
    const std::string message = e.what();
    int line = 0;
    if (message.rfind("Tag ", 0) == 0) line = lineOfToken(text, message.substr(4, message.find(' ', 4) - 4));
    throw InputError(path, line, "mmCIF: " + message);
  }
}

namespace {

// The covalent links of _struct_conn (conn_type_id covale*, disulf; both partners in the
// asymmetric unit, symmetry 1_555) as serial pairs into molecule.bondRecords. Partners are found
// by the names the atoms were read with: author chain and residue number where _atom_site has
// them (as the reader takes them), else the label ones; atom name, insertion code, alternate
// location. Links to atoms not read (another model, a selection) are left out.
void readStructConn(gemmi::cif::Block& block, Molecule& molecule, bool authAsym, bool authSeq) {
  gemmi::cif::Table conn = block.find(
      "_struct_conn.", {"conn_type_id", "?ptnr1_auth_asym_id", "?ptnr1_label_asym_id", "?ptnr1_auth_seq_id",
                        "?ptnr1_label_seq_id", "?ptnr1_label_atom_id", "?pdbx_ptnr1_PDB_ins_code",
                        "?pdbx_ptnr1_label_alt_id", "?ptnr1_symmetry", "?ptnr2_auth_asym_id", "?ptnr2_label_asym_id",
                        "?ptnr2_auth_seq_id", "?ptnr2_label_seq_id", "?ptnr2_label_atom_id",
                        "?pdbx_ptnr2_PDB_ins_code", "?pdbx_ptnr2_label_alt_id", "?ptnr2_symmetry"});
  if (!conn.ok()) return;
  auto key = [](const std::string& chain, const std::string& seq, char ins, const std::string& name, char alt) {
    return chain + '|' + seq + '|' + ins + '|' + name + '|' + alt;
  };
  std::unordered_map<std::string, int> serials;
  for (const AtomRecord& a : molecule.atoms)
    serials.emplace(key(a.chain, std::to_string(a.residueNumber), a.insertionCode, a.name, a.altLoc), a.serial);
  for (std::size_t r = 0; r < conn.length(); ++r) {
    gemmi::cif::Table::Row row = conn[static_cast<int>(r)];
    auto str = [&](int column) {
      return row.has2(static_cast<std::size_t>(column)) ? gemmi::cif::as_string(row[static_cast<std::size_t>(column)])
                                                        : std::string();
    };
    auto letter = [&](int column) {
      const std::string v = str(column);
      return v.empty() ? ' ' : v[0];
    };
    const std::string type = str(0);
    if (type.rfind("covale", 0) != 0 && type != "disulf") continue;
    int partner[2] = {0, 0};
    for (int p = 0; p < 2; ++p) {
      const int base = 1 + 8 * p;  // the columns of ptnr1, then of ptnr2
      const std::string symmetry = str(base + 7);
      if (!symmetry.empty() && symmetry != "1_555") break;
      const auto it = serials.find(key(str(authAsym ? base : base + 1), str(authSeq ? base + 2 : base + 3),
                                       letter(base + 5), str(base + 4), letter(base + 6)));
      if (it == serials.end()) break;
      partner[p] = it->second;
    }
    if (partner[0] > 0 && partner[1] > 0 && partner[0] != partner[1])
      molecule.bondRecords.push_back({std::min(partner[0], partner[1]), std::max(partner[0], partner[1])});
  }
}

Molecule readMmcifTable(const std::string& text, const std::string& path, int model) {
  gemmi::cif::Document document;
  try {
    document = gemmi::cif::read_memory(text.data(), text.size(), path.c_str());
  } catch (const tao::pegtl::parse_error& e) {
    const int line = e.positions().empty() ? 0 : static_cast<int>(e.positions().front().line);
    std::string message(e.message());
    if (message == "Wrong number of values in the loop")
      message = "the loop_ starting here ends with an incomplete row (truncated file?)";
    throw InputError(path, line, "mmCIF syntax: " + message);
  } catch (const std::exception& e) {
    throw fromGemmi(path, e);
  }
  if (document.blocks.empty()) throw InputError(path, 0, "no data_ block");
  gemmi::cif::Block& block = document.blocks.front();

  // gemmi's make_structure silently returns no atoms when a column it requires is missing,
  // so the table is read here, column by column.
  enum Column {
    kX,
    kY,
    kZ,
    kGroup,
    kId,
    kSymbol,
    kAuthAtom,
    kLabelAtom,
    kAltId,
    kAuthComp,
    kLabelComp,
    kAuthAsym,
    kLabelAsym,
    kAuthSeq,
    kLabelSeq,
    kInsCode,
    kOccupancy,
    kBIso,
    kModel
  };
  gemmi::cif::Table table = block.find(
      "_atom_site.",
      {"Cartn_x", "?Cartn_y", "?Cartn_z", "?group_PDB", "?id", "?type_symbol", "?auth_atom_id",
       "?label_atom_id", "?label_alt_id", "?auth_comp_id", "?label_comp_id", "?auth_asym_id",
       "?label_asym_id", "?auth_seq_id", "?label_seq_id", "?pdbx_PDB_ins_code", "?occupancy",
       "?B_iso_or_equiv", "?pdbx_PDB_model_num"});
  if (!table.ok()) {
    if (block.find_mmcif_category("_atom_site.").ok())
      throw InputError(path, 0, "_atom_site has no Cartn_x column");
    throw InputError(path, 0, "no _atom_site records (no atoms) in data_" + block.name);
  }
  for (const auto& [column, name] : {std::pair{kY, "Cartn_y"}, std::pair{kZ, "Cartn_z"}})
    if (!table.has_column(column))
      throw InputError(path, 0, "_atom_site has no " + std::string(name) + " column");
  const int atomColumn = table.first_of(kAuthAtom, kLabelAtom);
  const int compColumn = table.first_of(kAuthComp, kLabelComp);
  const int asymColumn = table.first_of(kAuthAsym, kLabelAsym);
  const int seqColumn = table.first_of(kAuthSeq, kLabelSeq);
  if (!table.has_column(atomColumn))
    throw InputError(path, 0, "_atom_site has neither auth_atom_id nor label_atom_id");

  const std::size_t rows = table.length();
  std::vector<int> rowLines;
  if (table.loop_item != nullptr)
    rowLines = loopRowLines(text, table.loop_item->line_number, table.loop_item->loop.tags.size(),
                            table.loop_item->loop.values.size());
  else if (const gemmi::cif::Item* item = block.find_pair_item(cifTag("Cartn_x")))
    rowLines.assign(rows, item->line_number);
  rowLines.resize(rows, 0);

  Molecule molecule;
  molecule.source = path;
  molecule.format = MoleculeFormat::Mmcif;
  molecule.modelUsed = model;

  std::vector<std::string> models;  // in order of first appearance
  std::string currentModel;
  int currentIndex = -1;
  std::size_t unknownElements = 0;
  for (std::size_t r = 0; r < rows; ++r) {
    gemmi::cif::Table::Row row = table[static_cast<int>(r)];
    const int line = rowLines[r];
    std::string modelName = row.has2(kModel) ? gemmi::cif::as_string(row[kModel]) : "1";
    if (currentIndex < 0 || modelName != currentModel) {
      auto it = std::find(models.begin(), models.end(), modelName);
      if (it == models.end()) it = models.insert(models.end(), modelName);
      currentIndex = static_cast<int>(it - models.begin());
      currentModel = std::move(modelName);
    }
    if (currentIndex + 1 != model) {
      ++molecule.skipped.otherModels;
      continue;
    }

    auto number = [&](int column, const char* name, std::optional<double> null) {
      const std::string& raw = row[static_cast<std::size_t>(column)];
      if (gemmi::cif::is_null(raw)) {
        if (null) return *null;
        throw InputError(path, line,
                         "expected a number for " + cifTag(name) + ", got " + inQuotes(raw));
      }
      std::string_view value = trim(raw);
      if (const std::size_t su = value.find('(');
          su != std::string_view::npos && value.back() == ')')
        value = value.substr(0, su);  // standard uncertainty, e.g. 1.234(5)
      double result = 0.0;
      if (!parseWhole(value, result))
        throw InputError(path, line,
                         "expected a number for " + cifTag(name) + ", got " + inQuotes(raw));
      if (!std::isfinite(result))
        throw InputError(path, line, cifTag(name) + " is not finite: " + inQuotes(raw));
      return result;
    };
    auto str = [&](int column) {
      return table.has_column(column) ? gemmi::cif::as_string(row[static_cast<std::size_t>(column)])
                                      : std::string();
    };
    auto firstChar = [&](int column) {
      if (!row.has2(static_cast<std::size_t>(column))) return ' ';
      const std::string value = gemmi::cif::as_string(row[static_cast<std::size_t>(column)]);
      return value.empty() ? ' ' : value[0];
    };

    const double x = number(kX, "Cartn_x", std::nullopt);
    const double y = number(kY, "Cartn_y", std::nullopt);
    const double z = number(kZ, "Cartn_z", std::nullopt);

    AtomRecord atom;
    atom.name = str(atomColumn);
    atom.residue = str(compColumn);
    atom.chain = str(asymColumn);
    // label_asym_id, the entity instance, is PyMOL's segi; without it the chain.
    atom.segid = table.has_column(kLabelAsym) ? AtomString(str(kLabelAsym)) : atom.chain;
    if (row.has2(static_cast<std::size_t>(seqColumn))) {
      const std::string value = gemmi::cif::as_string(row[static_cast<std::size_t>(seqColumn)]);
      const auto [ptr, ec] =
          std::from_chars(value.data(), value.data() + value.size(), atom.residueNumber);
      if (ec != std::errc() || ptr != value.data() + value.size())
        throw InputError(path, line,
                         "expected an integer for " +
                             cifTag(seqColumn == kAuthSeq ? "auth_seq_id" : "label_seq_id") +
                             ", got " + inQuotes(value));
    }
    atom.insertionCode = firstChar(kInsCode);
    atom.altLoc = firstChar(kAltId);
    if (row.has2(kId)) {
      const std::string value = gemmi::cif::as_string(row[kId]);
      int serial = 0;
      const auto [ptr, ec] = std::from_chars(value.data(), value.data() + value.size(), serial);
      if (ec == std::errc() && ptr == value.data() + value.size()) atom.serial = serial;
    }
    if (row.has2(kSymbol)) {
      // type_symbol may carry a charge in small-molecule style ("Fe2+").
      std::string symbol = gemmi::cif::as_string(row[kSymbol]);
      std::size_t letters = 0;
      while (letters < symbol.size() && isAlpha(symbol[letters])) ++letters;
      atom.element = canonicalElement(std::string_view(symbol).substr(0, letters));
      if (!atom.element.empty()) atom.elementSource = ElementSource::File;
    }
    if (atom.element.empty()) {
      atom.element = elementFromAtomName(atom.name, atom.residue, AtomNameLayout::Token);
      if (!atom.element.empty()) atom.elementSource = ElementSource::Name;
      if (row.has2(kSymbol)) {
        const std::string symbol = gemmi::cif::as_string(row[kSymbol]);
        if (!symbol.empty() && isAlpha(symbol[0]))
          noteUnknownElement(molecule, unknownElements, line, cifTag("type_symbol"), symbol, atom);
      }
    }
    // As for PDB: an unreadable occupancy is an error only where it chooses a conformer.
    atom.occupancy = 1.0;
    if (table.has_column(kOccupancy)) {
      if (atom.altLoc != ' ')
        atom.occupancy = number(kOccupancy, "occupancy", 1.0);
      else if (!row.has2(kOccupancy) || !parseWhole(trim(row[kOccupancy]), atom.occupancy) ||
               !std::isfinite(atom.occupancy))
        atom.occupancy = row.has2(kOccupancy) ? std::nan("") : 1.0;
    }
    atom.bFactor = 0.0;
    if (row.has2(kBIso) &&
        (!parseWhole(trim(row[kBIso]), atom.bFactor) || !std::isfinite(atom.bFactor)))
      atom.bFactor = std::nan("");
    atom.hetatm = str(kGroup) == "HETATM";
    atom.line = line;
    molecule.centers.emplace_back(x, y, z);
    molecule.atoms.push_back(std::move(atom));
  }
  molecule.modelCount = static_cast<int>(models.size());
  if (models.empty()) throw InputError(path, 0, "no atoms in the _atom_site table");
  if (model > molecule.modelCount) throwNoSuchModel(path, model, models.size());
  countMoreElementNotes(molecule, unknownElements);
  readStructConn(block, molecule, table.has_column(kAuthAsym), table.has_column(kAuthSeq));
  return molecule;
}

}  // namespace

// Only the coordinates and the model number of each _atom_site row are read: the atoms'
// records come from the topology, and the trajectory needs the positions of every model.
std::vector<std::vector<glm::dvec3>> readMmcifModelsWithGemmi(
    const std::string& text, const std::string& path, std::optional<std::array<double, 6>>& cell) {
  gemmi::cif::Document document;
  try {
    document = gemmi::cif::read_memory(text.data(), text.size(), path.c_str());
  } catch (const tao::pegtl::parse_error& e) {
    const int line = e.positions().empty() ? 0 : static_cast<int>(e.positions().front().line);
    throw InputError(path, line, "mmCIF syntax: " + std::string(e.message()));
  } catch (const std::exception& e) {
    throw fromGemmi(path, e);
  }
  if (document.blocks.empty()) throw InputError(path, 0, "no data_ block");
  gemmi::cif::Block& block = document.blocks.front();

  // A value as a number: standard uncertainties ("1.234(5)") dropped, '?' and '.' absent.
  auto numberOf = [](const std::string& raw) -> std::optional<double> {
    if (gemmi::cif::is_null(raw)) return std::nullopt;
    std::string_view value = trim(raw);
    if (const std::size_t su = value.find('(');
        su != std::string_view::npos && !value.empty() && value.back() == ')')
      value = value.substr(0, su);
    double result = 0.0;
    if (!parseWhole(value, result)) return std::nullopt;
    return result;
  };

  try {
    cell.reset();
    std::array<double, 6> values{};
    const char* cellTags[] = {"_cell.length_a",    "_cell.length_b",   "_cell.length_c",
                              "_cell.angle_alpha", "_cell.angle_beta", "_cell.angle_gamma"};
    bool complete = true;
    for (std::size_t i = 0; i < 6 && complete; ++i) {
      const std::string* raw = block.find_value(cellTags[i]);
      const std::optional<double> v = raw ? numberOf(*raw) : std::nullopt;
      complete = v && std::isfinite(*v);
      if (complete) values[i] = *v;
    }
    // A cell of 1 Å edges is the PDB's placeholder for "no cell" (NMR entries).
    if (complete && !(values[0] == 1.0 && values[1] == 1.0 && values[2] == 1.0)) cell = values;

    enum Column { kX, kY, kZ, kModel };
    gemmi::cif::Table table =
        block.find("_atom_site.", {"Cartn_x", "Cartn_y", "Cartn_z", "?pdbx_PDB_model_num"});
    if (!table.ok()) {
      if (block.find_mmcif_category("_atom_site.").ok())
        throw InputError(path, 0, "_atom_site lacks one of the Cartn_x, Cartn_y, Cartn_z columns");
      throw InputError(path, 0, "no _atom_site records (no atoms) in data_" + block.name);
    }
    const std::size_t rows = table.length();
    std::vector<int> rowLines;
    if (table.loop_item != nullptr)
      rowLines = loopRowLines(text, table.loop_item->line_number,
                              table.loop_item->loop.tags.size(), table.loop_item->loop.values.size());
    rowLines.resize(rows, 0);

    std::vector<std::string> names;  // model numbers in order of first appearance
    std::vector<std::vector<glm::dvec3>> models;
    std::size_t current = 0;
    for (std::size_t r = 0; r < rows; ++r) {
      gemmi::cif::Table::Row row = table[static_cast<int>(r)];
      const std::string name = row.has2(kModel) ? gemmi::cif::as_string(row[kModel]) : "1";
      if (models.empty() || names[current] != name) {
        auto it = std::find(names.begin(), names.end(), name);
        current = static_cast<std::size_t>(it - names.begin());
        if (it == names.end()) {
          names.push_back(name);
          models.emplace_back();
        }
      }
      glm::dvec3 position;
      const char* columns[] = {"Cartn_x", "Cartn_y", "Cartn_z"};
      for (int axis = 0; axis < 3; ++axis) {
        const std::string& raw = row[static_cast<std::size_t>(axis)];
        const std::optional<double> v = numberOf(raw);
        if (!v)
          throw InputError(path, rowLines[r],
                           "expected a number for " + cifTag(columns[axis]) + ", got " +
                               inQuotes(raw));
        if (!std::isfinite(*v))
          throw InputError(path, rowLines[r],
                           cifTag(columns[axis]) + " is not finite: " + inQuotes(raw));
        position[axis] = *v;
      }
      models[current].push_back(position);
    }
    if (models.empty()) throw InputError(path, 0, "no atoms in the _atom_site table");
    return models;
  } catch (const InputError&) {
    throw;
  } catch (const std::runtime_error& e) {
    throw InputError(path, 0, "mmCIF: " + std::string(e.what()));
  }
}

}  // namespace surftrace::build::detail

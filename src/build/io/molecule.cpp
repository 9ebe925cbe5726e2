// Reading a molecule: the file's bytes (gunzipped when they start with the gzip magic), one
// parser per format, the selection of model, conformer, chains, water and hydrogens, and radii.
#include "build/io/molecule.hpp"

#define ZLIB_CONST
#include <zlib.h>

#include <algorithm>
#include <array>
#include <bit>
#include <cerrno>
#include <charconv>
#include <climits>
#include <cmath>
#include <cstdio>
#include <cstring>
#include <fstream>
#include <map>
#include <new>
#include <set>
#include <stdexcept>
#include <string_view>
#include <tuple>
#include <unordered_map>
#include <utility>

#include "build/core/assert.hpp"
#include "build/io/atom_selection.hpp"
#include "build/io/error.hpp"
#include "build/io/file_formats.hpp"
#include "build/io/line_cursor.hpp"
#include "build/io/radii.hpp"
#include "build/io/text_fields.hpp"
#include "build/io/topology_formats.hpp"

namespace surftrace::build {

namespace detail {
// Defined in gemmi_impl.cpp, the one translation unit that compiles gemmi. Each returns the
// atoms of the 1-based `model` in file order, with lines, elements and alternate locations,
// but no radii and no selection; `text` is the decompressed file.
Molecule readPdbWithGemmi(std::string text, const std::string& path, int model);
Molecule readMmcifWithGemmi(const std::string& text, const std::string& path, int model);
}  // namespace detail

namespace {

using namespace text;

namespace fs = std::filesystem;

std::optional<double> parseNumber(std::string_view text) { return parseWhole<double>(text); }
std::optional<int> parseInt(std::string_view text) { return parseWhole<int>(text); }

// ---------------------------------------------------------------------------------------------
// Bytes

bool hasGzipMagic(std::string_view bytes) {
  return bytes.size() >= 2 && static_cast<unsigned char>(bytes[0]) == 0x1f &&
         static_cast<unsigned char>(bytes[1]) == 0x8b;
}

// Refuses a line longer than kMaxLineBytes as the text arrives (read from disk or inflated),
// before a file of one endless line is held whole: a 1 MB gzip inflates to a 1 GB line in
// seconds. A line ends at "\n", "\r\n" or a lone "\r" (classic Mac OS), as textOfBytes reads.
class LineLengthGuard {
 public:
  explicit LineLengthGuard(const std::string& name) : name_(name) {}

  // Byte by byte this was a tenth of reading a large file. Text without a CR is taken in
  // windows of at most kMaxLineBytes bytes: no line can end inside a window and run past the
  // limit, so only the window's first and last line ends matter, and its lines are counted
  // by std::count. A window with a CR, or one in which the limit may be passed, goes byte by
  // byte (which throws with the line).
  void feed(const char* data, std::size_t size) {
    while (size > 0) {
      const std::size_t window = std::min(size, kMaxLineBytes);
      if (!feedWithoutCr(data, window)) feedBytes(data, window);
      data += window;
      size -= window;
    }
  }

 private:
  bool feedWithoutCr(const char* data, std::size_t size) {
    if (afterCr_ || std::memchr(data, '\r', size)) return false;
    const void* first = std::memchr(data, '\n', size);
    if (!first) {
      if (length_ + size > kMaxLineBytes) return false;
      length_ += size;
      return true;
    }
    if (length_ + static_cast<std::size_t>(static_cast<const char*>(first) - data) > kMaxLineBytes) return false;
    const char* last = static_cast<const char*>(memrchr(data, '\n', size));
    line_ += static_cast<int>(std::count(data, data + size, '\n'));
    length_ = static_cast<std::size_t>(data + size - (last + 1));
    return true;
  }

  void feedBytes(const char* data, std::size_t size) {
    for (std::size_t i = 0; i < size; ++i) {
      const char c = data[i];
      if (c == '\n' || c == '\r') {
        if (!(c == '\n' && afterCr_)) ++line_;  // "\r\n" ends one line
        afterCr_ = c == '\r';
        length_ = 0;
        continue;
      }
      afterCr_ = false;
      if (++length_ > kMaxLineBytes)
        throw InputError(name_, line_,
                         "the line runs past " + std::to_string(kMaxLineBytes) +
                             " bytes (1 MiB) without ending, longer than any line of a structure file: "
                             "SurfTrace reads text lines up to that length (is this the right file, or is "
                             "it damaged?)");
    }
  }

  const std::string& name_;
  int line_ = 1;
  std::size_t length_ = 0;
  bool afterCr_ = false;
};

std::string readFileBytes(const fs::path& path, const std::string& name) {
  std::error_code ec;
  if (fs::is_directory(path, ec)) throw InputError(name, 0, "is a directory, not a file");
  std::ifstream in(path, std::ios::binary);
  if (!in) throw InputError(name, 0, std::string("cannot open: ") + std::strerror(errno));
  std::string bytes;
  // Room for the whole file at once: growing by doubling copied a 100 MB file twice over.
  if (const std::uintmax_t size = fs::file_size(path, ec); !ec) bytes.reserve(static_cast<std::size_t>(size));
  char buffer[1 << 16];
  // Plain text is held to its line length as it is read; gzip data as gunzip inflates it.
  LineLengthGuard guard(name);
  std::optional<bool> plain;
  while (in.read(buffer, sizeof buffer) || in.gcount() > 0) {
    const auto got = static_cast<std::size_t>(in.gcount());
    if (!plain) plain = !hasGzipMagic(std::string_view(buffer, got));
    if (*plain) guard.feed(buffer, got);
    bytes.append(buffer, got);
  }
  if (in.bad()) throw InputError(name, 0, "read error");
  return bytes;
}

int lineOfOffset(const std::string& text, std::size_t offset) {
  return 1 + static_cast<int>(std::count(text.begin(),
                                         text.begin() + static_cast<std::ptrdiff_t>(offset), '\n'));
}

// Inflates all gzip members; bytes after the last member that are not another member are
// ignored, as gzip(1) does.
std::string gunzip(const std::string& bytes, const std::string& name) {
  z_stream zs{};
  if (inflateInit2(&zs, 16 + MAX_WBITS) != Z_OK) throw std::bad_alloc();
  struct Closer {
    z_stream* zs;
    ~Closer() { inflateEnd(zs); }
  } closer{&zs};

  LineLengthGuard guard(name);
  std::string out;
  out.resize(std::max<std::size_t>(bytes.size() * 4, 1 << 16));
  std::size_t consumed = 0;
  std::size_t produced = 0;
  for (;;) {
    if (zs.avail_in == 0 && consumed < bytes.size()) {
      const std::size_t chunk = std::min<std::size_t>(bytes.size() - consumed, UINT_MAX);
      zs.next_in = reinterpret_cast<const Bytef*>(bytes.data() + consumed);
      zs.avail_in = static_cast<uInt>(chunk);
      consumed += chunk;
    }
    if (produced == out.size()) out.resize(out.size() * 2);
    const std::size_t room = std::min<std::size_t>(out.size() - produced, UINT_MAX);
    zs.next_out = reinterpret_cast<Bytef*>(out.data() + produced);
    zs.avail_out = static_cast<uInt>(room);
    const int ret = inflate(&zs, Z_NO_FLUSH);
    guard.feed(out.data() + produced, room - zs.avail_out);
    produced += room - zs.avail_out;
    if (ret == Z_STREAM_END) {
      const std::size_t left = zs.avail_in + (bytes.size() - consumed);
      const std::size_t at = bytes.size() - left;
      if (left >= 2 && static_cast<unsigned char>(bytes[at]) == 0x1f &&
          static_cast<unsigned char>(bytes[at + 1]) == 0x8b) {
        inflateReset(&zs);
        continue;
      }
      break;
    }
    if (ret == Z_MEM_ERROR) throw std::bad_alloc();
    if (ret == Z_DATA_ERROR || ret == Z_STREAM_ERROR || ret == Z_NEED_DICT) {
      out.resize(produced);
      throw InputError(name, 0,
                       std::string("corrupt gzip data (") + (zs.msg ? zs.msg : "zlib error") +
                           ") after " + std::to_string(produced) + " decompressed bytes");
    }
    // Z_OK or Z_BUF_ERROR: more output room, or more input if there is any.
    if (zs.avail_in == 0 && consumed == bytes.size() && zs.avail_out != 0) {
      out.resize(produced);
      throw InputError(name, lineOfOffset(out, produced),
                       "the gzip stream is truncated: it ends after " + std::to_string(produced) +
                           " decompressed bytes, in this line");
    }
  }
  out.resize(produced);
  return out;
}

// Rejects what cannot be a text file of atoms: nothing at all, or control bytes (a NUL in
// DCD, XTC and other binary formats comes within the first few bytes).
void checkText(const std::string& text, const std::string& name, bool wasGzipped) {
  if (text.empty())
    throw InputError(name, 0,
                     wasGzipped ? "the file decompresses to nothing" : "the file is empty");
  // Blocks of 64 bytes are first tested without a branch for any byte below 0x20 but '\n'
  // (the compiler vectorises it); only a block with one, a tab or a CR mostly, is looked at
  // byte by byte. Byte by byte throughout, this was a twentieth of reading a large file.
  const auto control = [](unsigned char c) {
    return c < 0x20 && c != '\t' && c != '\n' && c != '\r' && c != '\f' && c != '\v' && c != 0x1a;
  };
  const auto check = [&](std::size_t from, std::size_t to) {
    for (std::size_t i = from; i < to; ++i) {
      const auto c = static_cast<unsigned char>(text[i]);
      if (!control(c)) continue;
      char hex[8];
      std::snprintf(hex, sizeof hex, "0x%02x", c);
      throw InputError(name, lineOfOffset(text, i),
                       std::string("binary data (byte ") + hex + " at offset " + std::to_string(i) +
                           "); expected a text file");
    }
  };
  constexpr std::size_t kBlock = 64;
  std::size_t at = 0;
  for (; at + kBlock <= text.size(); at += kBlock) {
    unsigned char suspicious = 0;
    for (std::size_t k = 0; k < kBlock; ++k) {
      const auto c = static_cast<unsigned char>(text[at + k]);
      suspicious |= static_cast<unsigned char>((c < 0x20) & (c != '\n'));
    }
    if (suspicious != 0) check(at, at + kBlock);
  }
  check(at, text.size());
}

MoleculeFormat formatFromPath(const fs::path& path, const std::string& name) {
  const std::string ext = formatExtension(path);
  const ExtensionFormats formats = formatsOfExtension(ext);
  if (formats.molecule) return *formats.molecule;
  if (formats.trajectory)
    throw InputError(name, 0,
                     "is a trajectory (." + ext +
                         "), which holds coordinates but no atoms: give it after its topology, "
                         "e.g. `surftrace trajectory TOPOLOGY.psf " +
                         path.filename().string() + " -o frames/%05d.png`");
  throw InputError(name, 0,
                   "cannot tell the format from the name (extension " +
                       inQuotes(ext.empty() ? "" : "." + ext) +
                       "); expected .pdb, .ent, .cif, .mmcif, .pqr, .xyzr, .xyz, .gro or .psf, "
                       "optionally followed by .gz, or give the format explicitly");
}

// ---------------------------------------------------------------------------------------------
// Radii from the file: PQR and XYZR

// Checks a radius from the file. Returns false for a zero radius the options allow to drop.
bool checkFileRadius(double radius, std::string_view text, const ReadOptions& options,
                     const std::string& name, int line) {
  if (!std::isfinite(radius))
    throw InputError(name, line, "the radius is not finite: " + inQuotes(text));
  if (radius < 0.0) throw InputError(name, line, "the radius must be > 0, got " + inQuotes(text));
  if (radius == 0.0) {
    if (options.dropZeroRadius) return false;
    throw InputError(name, line,
                     "the radius must be > 0, got " + inQuotes(text) +
                         " (PDB2PQR gives some hydrogens radius 0; --drop-zero-radius leaves "
                         "them out)");
  }
  return true;
}

void checkCoordinate(double value, std::string_view text, const char* what, const std::string& name,
                     int line) {
  if (!std::isfinite(value))
    throw InputError(name, line, std::string(what) + " is not finite: " + inQuotes(text));
}

// ---------------------------------------------------------------------------------------------
// PQR: "ATOM serial name resName [chain] resSeq x y z charge radius", whitespace-delimited,
// or in PDB columns where fields run together (PDB2PQR without --whitespace writes
// "1999.3232998.770-900.490" and "A1001").

struct PqrFields {
  int serial = 0;
  std::string name;
  char altLoc = ' ';
  std::string residue;
  std::string chain;
  int residueNumber = 0;
  char insertionCode = ' ';
  double xyz[3] = {0.0, 0.0, 0.0};
  std::string_view xyzText[3];
  double charge = 0.0;
  double radius = 0.0;
  std::string_view radiusText;
  bool pdbColumns = false;
};

// The whitespace reading; returns "" on success or why it failed.
std::string pqrWhitespace(const std::vector<std::string_view>& f, PqrFields& out) {
  const std::size_t n = f.size();
  if (n != 9 && n != 10)
    return "expected 10 or 11 fields (ATOM serial name resName [chain] resSeq x y z charge "
           "radius), got " +
           std::to_string(n + 1);
  const std::size_t at = n == 10 ? 1 : 0;  // offset after the optional chain
  const char* names[] = {"x", "y", "z", "the charge", "the radius"};
  double values[5];
  for (std::size_t i = 0; i < 5; ++i) {
    const std::optional<double> v = parseNumber(f[4 + at + i]);
    if (!v)
      return std::string("expected a number for ") + names[i] + " (field " +
             std::to_string(6 + at + i) + "), got " + inQuotes(f[4 + at + i]);
    values[i] = *v;
  }
  const std::optional<int> serial = parseInt(f[0]);
  if (!serial) return "expected an atom serial number (field 2), got " + inQuotes(f[0]);
  int number = 0;
  char icode = ' ';
  std::string_view chain = n == 10 ? f[3] : std::string_view();
  if (!parseResidueNumber(f[3 + at], number, icode)) {
    // PDB2PQR --whitespace still writes the chain and a four-digit residue number together
    // ("A1001").
    const std::string_view glued = f[3 + at];
    if (n == 9 && glued.size() > 1 && isAlpha(glued[0]) &&
        parseResidueNumber(glued.substr(1), number, icode)) {
      chain = glued.substr(0, 1);
    } else {
      return "expected a residue number (field " + std::to_string(5 + at) + "), got " +
             inQuotes(f[3 + at]);
    }
  }
  out.serial = *serial;
  out.name = std::string(f[1]);
  out.residue = std::string(f[2]);
  out.chain = std::string(chain);
  out.residueNumber = number;
  out.insertionCode = icode;
  for (int i = 0; i < 3; ++i) {
    out.xyz[i] = values[i];
    out.xyzText[i] = trim(f[4 + at + static_cast<std::size_t>(i)]);
  }
  out.charge = values[3];
  out.radius = values[4];
  out.radiusText = f[8 + at];
  out.pdbColumns = false;
  return {};
}

// The fixed-column reading: PDB columns up to 54, then charge and radius.
bool pqrColumns(std::string_view line, PqrFields& out) {
  if (line.size() < 54) return false;
  const std::string_view record = line.substr(0, 6);
  if (record != "ATOM  " && record != "HETATM") return false;
  for (int i = 0; i < 3; ++i) {
    const std::string_view field = line.substr(30 + 8 * static_cast<std::size_t>(i), 8);
    const std::optional<double> v = parseNumber(field);
    if (!v) return false;
    out.xyz[i] = *v;
    out.xyzText[i] = trim(field);
  }
  const std::vector<std::string_view> rest = splitFields(line.substr(54));
  if (rest.size() != 2) return false;
  const std::optional<double> charge = parseNumber(rest[0]);
  const std::optional<double> radius = parseNumber(rest[1]);
  if (!charge || !radius) return false;
  const std::optional<int> number = parseInt(line.substr(22, 4));
  if (!number) return false;
  out.serial = parseInt(line.substr(6, 5)).value_or(0);
  out.name = std::string(line.substr(12, 4));
  out.altLoc = line[16];
  out.residue = std::string(trim(line.substr(17, 4)));
  out.chain = std::string(trim(line.substr(21, 1)));
  out.residueNumber = *number;
  out.insertionCode = line[26];
  out.charge = *charge;
  out.radius = *radius;
  out.radiusText = rest[1];
  out.pdbColumns = true;
  return true;
}

Molecule parsePqr(const std::string& text, const std::string& name, const ReadOptions& options) {
  Molecule molecule;
  molecule.source = name;
  molecule.format = MoleculeFormat::Pqr;
  molecule.modelUsed = options.model;
  molecule.radiiSet = "file";
  int models = 0;  // MODEL records so far; atoms before the first belong to model 1
  std::size_t atomsSeen = 0;
  std::size_t zeroRadius = 0;
  LineCursor reader(text);
  std::string_view line;
  while (reader.next(line)) {
    const int lineNumber = reader.number();
    std::string_view body = trim(line);
    std::string record;
    for (char c : body.substr(0, std::min<std::size_t>(body.size(), 6))) record += upper(c);
    if (record.rfind("MODEL", 0) == 0 && (body.size() == 5 || isSpace(body[5]))) {
      ++models;
      continue;
    }
    if (record.rfind("END", 0) == 0 && (body.size() == 3 || isSpace(body[3]))) break;
    std::size_t recordLength = 0;
    if (record.rfind("HETATM", 0) == 0)
      recordLength = 6;
    else if (record.rfind("ATOM", 0) == 0)
      recordLength = 4;
    else
      continue;
    // The serial may follow the record name without a space ("HETATM12345"), but ATOMTYPE
    // and the like are other records.
    if (body.size() > recordLength && !isSpace(body[recordLength]) &&
        !(body[recordLength] >= '0' && body[recordLength] <= '9'))
      continue;
    const std::vector<std::string_view> fields = splitFields(body.substr(recordLength));

    ++atomsSeen;
    if (std::max(models, 1) != options.model) {
      ++molecule.skipped.otherModels;
      continue;
    }
    PqrFields f;
    const std::string why = pqrWhitespace(fields, f);
    if (!why.empty() && !pqrColumns(line, f)) throw InputError(name, lineNumber, why);
    const char* axes[] = {"x", "y", "z"};
    for (int i = 0; i < 3; ++i) checkCoordinate(f.xyz[i], f.xyzText[i], axes[i], name, lineNumber);
    if (!std::isfinite(f.charge)) throw InputError(name, lineNumber, "the charge is not finite");
    if (!checkFileRadius(f.radius, f.radiusText, options, name, lineNumber)) {
      ++zeroRadius;
      continue;
    }
    AtomRecord atom;
    atom.name = std::string(trim(f.name));
    atom.residue = f.residue;
    atom.chain = f.chain;
    atom.segid = f.chain.empty() ? "SYSTEM" : f.chain;  // as MDAnalysis's PQRParser
    atom.residueNumber = f.residueNumber;
    atom.insertionCode = f.insertionCode;
    atom.serial = f.serial;
    atom.element = elementFromAtomName(
        f.name, f.residue, f.pdbColumns ? AtomNameLayout::PdbColumns : AtomNameLayout::Token);
    if (!atom.element.empty()) atom.elementSource = ElementSource::Name;
    atom.charge = f.charge;
    atom.hetatm = record.rfind("HETATM", 0) == 0;
    atom.line = lineNumber;
    atom.altLoc = f.altLoc;
    molecule.centers.emplace_back(f.xyz[0], f.xyz[1], f.xyz[2]);
    molecule.radii.push_back(f.radius);
    molecule.atoms.push_back(std::move(atom));
  }
  molecule.modelCount = std::max(models, 1);
  molecule.skipped.zeroRadius = zeroRadius;
  if (atomsSeen == 0) throw InputError(name, 0, "no ATOM or HETATM records");
  if (options.model > molecule.modelCount)
    throw InputError(name, 0,
                     "model " + std::to_string(options.model) +
                         " was asked for, but the file has " + std::to_string(molecule.modelCount) +
                         (molecule.modelCount == 1 ? " model" : " models"));
  if (molecule.atoms.empty() && zeroRadius > 0)
    throw InputError(name, 0,
                     "all " + std::to_string(zeroRadius) +
                         " atoms have radius 0 and were left out (--drop-zero-radius)");
  return molecule;
}

// ---------------------------------------------------------------------------------------------
// XYZR: "x y z r" a line (MSMS, NanoShaper); MSMS's xyzrn adds a sphere number and a name.

// The common line, "x y z r" with spaces or tabs around the numbers and nothing else, read in
// one pass (the field-by-field reading below was half of reading a large file): returns where
// the next line starts, or nullptr for any other line (blank, a comment, xyzrn's six fields, a
// '+' sign, a number that is not finite, a radius <= 0), which the field-by-field reading then
// reads or refuses with its message. Each number is std::from_chars over the same characters
// the field-by-field reading gives it (a number ends at a space, tab or line end, none of which
// a number can hold), so both read the same values.
const char* readPlainXyzrLine(const char* p, const char* end, double (&v)[4]) {
  const auto blank = [](char c) { return c == ' ' || c == '\t'; };
  for (double& value : v) {
    while (p != end && blank(*p)) ++p;
    const auto [next, ec] = std::from_chars(p, end, value);
    if (ec != std::errc() || next == p) return nullptr;
    p = next;
    if (p != end && !blank(*p) && *p != '\n' && *p != '\r') return nullptr;
  }
  while (p != end && blank(*p)) ++p;
  if (p != end && *p == '\r') ++p;
  if (p != end && *p != '\n') return nullptr;
  if (!std::isfinite(v[0]) || !std::isfinite(v[1]) || !std::isfinite(v[2]) || !std::isfinite(v[3]) ||
      !(v[3] > 0.0))
    return nullptr;
  return p == end ? end : p + 1;
}

Molecule parseXyzr(const std::string& text, const std::string& name, const ReadOptions& options) {
  Molecule molecule;
  molecule.source = name;
  molecule.format = MoleculeFormat::Xyzr;
  molecule.modelUsed = options.model;
  molecule.radiiSet = "file";
  if (options.model != 1)
    throw InputError(
        name, 0,
        "model " + std::to_string(options.model) + " was asked for, but an XYZR file has 1 model");
  // One atom a line, mostly: room for them all at once, not grown (and moved) by doubling.
  const auto lines = static_cast<std::size_t>(std::count(text.begin(), text.end(), '\n')) + 1;
  molecule.centers.reserve(lines);
  molecule.radii.reserve(lines);
  molecule.atoms.reserve(lines);
  const AtomString system("SYSTEM");
  const char* const end = text.data() + text.size();
  const char* p = text.data();
  int lineNumber = 0;
  int serial = 0;
  while (p != end) {
    ++lineNumber;
    double v[4];
    if (const char* next = readPlainXyzrLine(p, end, v)) {
      p = next;
      ++serial;
      AtomRecord& atom = molecule.atoms.emplace_back();  // in place, not built aside and moved in
      atom.serial = serial;
      atom.segid = system;
      atom.line = lineNumber;
      molecule.centers.emplace_back(v[0], v[1], v[2]);
      molecule.radii.push_back(v[3]);
      continue;
    }
    // Any other line (a comment, xyzrn's six fields, an error): field by field.
    const char* const newline = static_cast<const char*>(std::memchr(p, '\n', static_cast<std::size_t>(end - p)));
    std::string_view line(p, static_cast<std::size_t>((newline ? newline : end) - p));
    p = newline ? newline + 1 : end;
    if (!line.empty() && line.back() == '\r') line.remove_suffix(1);
    const std::string_view body = trim(line);
    if (body.empty() || body[0] == '#') continue;
    std::array<std::string_view, 6> f;
    const std::size_t fields = splitFields(body, f);
    const bool xyzrn = fields == 6 && parseInt(f[4]).has_value();
    if (fields != 4 && !xyzrn)
      throw InputError(
          name, lineNumber,
          "expected 4 fields (x y z r), got " + std::to_string(fields) + ": " + inQuotes(body));
    const char* names[] = {"x", "y", "z", "the radius"};
    for (std::size_t i = 0; i < 4; ++i) {
      const std::optional<double> value = parseNumber(f[i]);
      if (!value)
        throw InputError(name, lineNumber,
                         std::string("expected a number for ") + names[i] + " (field " +
                             std::to_string(i + 1) + "), got " + inQuotes(f[i]));
      v[i] = *value;
    }
    for (std::size_t i = 0; i < 3; ++i) checkCoordinate(v[i], f[i], names[i], name, lineNumber);
    ++serial;
    if (!checkFileRadius(v[3], f[3], options, name, lineNumber)) {
      ++molecule.skipped.zeroRadius;
      continue;
    }
    AtomRecord& atom = molecule.atoms.emplace_back();
    atom.serial = serial;
    atom.segid = system;
    atom.line = lineNumber;
    if (xyzrn) atom.name = f[5];
    molecule.centers.emplace_back(v[0], v[1], v[2]);
    molecule.radii.push_back(v[3]);
  }
  if (serial == 0) throw InputError(name, 0, "no atoms (no 'x y z r' lines)");
  if (molecule.atoms.empty())
    throw InputError(name, 0,
                     "all " + std::to_string(molecule.skipped.zeroRadius) +
                         " atoms have radius 0 and were left out (--drop-zero-radius)");
  return molecule;
}

// ---------------------------------------------------------------------------------------------
// XYZ: frames of "count", "comment", then count lines "Element x y z [...]".

Molecule parseXyz(const std::string& text, const std::string& name, int model) {
  Molecule molecule;
  molecule.source = name;
  molecule.format = MoleculeFormat::Xyz;
  molecule.modelUsed = model;
  LineCursor reader(text);
  std::string_view line;
  int frames = 0;
  while (reader.next(line)) {
    if (trim(line).empty()) continue;  // blank lines between frames or at the end
    const int countLine = reader.number();
    const std::optional<int> count = parseInt(line);
    if (!count || *count < 0)
      throw InputError(name, countLine,
                       "expected the atom count of frame " + std::to_string(frames + 1) + ", got " +
                           inQuotes(trim(line)));
    ++frames;
    const bool wanted = frames == model;
    if (!reader.next(line))
      throw InputError(name, countLine + 1,
                       "the file ends before the comment line of frame " + std::to_string(frames));
    for (int i = 0; i < *count; ++i) {
      if (!reader.next(line))
        throw InputError(name, reader.number() + 1,
                         "the file ends after " + std::to_string(i) + " of the " +
                             std::to_string(*count) + " atoms of frame " + std::to_string(frames) +
                             " (truncated?)");
      if (!wanted) {
        ++molecule.skipped.otherModels;
        continue;
      }
      const int lineNumber = reader.number();
      const std::vector<std::string_view> f = splitFields(line);
      if (f.size() < 4)
        throw InputError(name, lineNumber,
                         "expected 'element x y z', got " + std::to_string(f.size()) +
                             " fields: " + inQuotes(trim(line)));
      const char* axes[] = {"x", "y", "z"};
      double v[3];
      for (std::size_t k = 0; k < 3; ++k) {
        const std::optional<double> value = parseNumber(f[k + 1]);
        if (!value)
          throw InputError(name, lineNumber,
                           std::string("expected a number for ") + axes[k] + " (field " +
                               std::to_string(k + 2) + "), got " + inQuotes(f[k + 1]));
        checkCoordinate(*value, f[k + 1], axes[k], name, lineNumber);
        v[k] = *value;
      }
      AtomRecord atom;
      atom.name = std::string(f[0]);
      atom.element = canonicalElement(f[0]);
      // Some writers give the atomic number instead of the symbol.
      if (const std::optional<int> z = parseInt(f[0]); atom.element.empty() && z)
        atom.element = elementSymbol(*z);
      if (!atom.element.empty()) atom.elementSource = ElementSource::File;
      atom.serial = i + 1;
      atom.segid = "SYSTEM";  // as MDAnalysis's XYZParser
      atom.line = lineNumber;
      molecule.centers.emplace_back(v[0], v[1], v[2]);
      molecule.atoms.push_back(std::move(atom));
    }
  }
  molecule.modelCount = frames;
  if (frames == 0)
    throw InputError(name, 0, "no frames (expected an atom count on the first line)");
  if (model > frames)
    throw InputError(name, 0,
                     "frame " + std::to_string(model) + " was asked for, but the file has " +
                         std::to_string(frames) + (frames == 1 ? " frame" : " frames"));
  if (molecule.atoms.empty())
    throw InputError(name, 0, "frame " + std::to_string(model) + " has no atoms");
  return molecule;
}

// ---------------------------------------------------------------------------------------------
// Selection and radii

// What the per-atom loops ask of a residue name, looked up again only when the name differs
// from the previous atom's: atoms come residue by residue, and the table searches (ten per
// atom) were a tenth of reading a million-atom GRO file.
struct ResidueKind {
  bool water = false;         // isWaterResidue
  bool standard = false;      // isStandardResidue (waters included)
  bool martiniWater = false;  // isMartiniWaterResidue
};
class ResidueKinds {
 public:
  const ResidueKind& operator()(const AtomString& residue) {
    if (!known_ || residue != name_) {
      name_ = residue;
      known_ = true;
      kind_ = {isWaterResidue(residue), isStandardResidue(residue), isMartiniWaterResidue(residue)};
    }
    return kind_;
  }

 private:
  AtomString name_;
  bool known_ = false;
  ResidueKind kind_;
};

std::string describe(const AtomRecord& atom) {
  std::string text =
      "atom " + inQuotes(atom.name.empty() ? std::to_string(atom.serial) : atom.name.str());
  if (!atom.residue.empty()) {
    text += " of " + atom.residue;
    if (!atom.chain.empty()) text += " " + atom.chain;
    text += " " + std::to_string(atom.residueNumber);
    if (atom.insertionCode != ' ') text += atom.insertionCode;
  } else if (!atom.name.empty()) {
    text += " (number " + std::to_string(atom.serial) + ")";
  }
  return text;
}

template <typename Keep>
void compact(Molecule& molecule, const Keep& keep) {
  std::size_t out = 0;
  for (std::size_t i = 0; i < molecule.size(); ++i) {
    if (!keep[i]) continue;
    if (out != i) {
      molecule.centers[out] = molecule.centers[i];
      molecule.atoms[out] = std::move(molecule.atoms[i]);
      if (!molecule.radii.empty()) molecule.radii[out] = molecule.radii[i];
    }
    ++out;
  }
  molecule.centers.resize(out);
  molecule.atoms.resize(out);
  if (!molecule.radii.empty()) molecule.radii.resize(out);
}

// Keeps, in each residue with alternate locations, the conformer of highest mean occupancy
// (the first one on a tie) with the atoms that have no alternate location. An atom that has no
// record in that conformer keeps its own best one (highest occupancy, the first on a tie): 3AL1's
// LYS A105 HA has only an `A` record while B wins the residue, and is no less there. Atoms of
// another residue name (microheterogeneity, 1CBN's PRO/SER 22) go with their conformer.
std::size_t dropAlternateLocations(Molecule& molecule) {
  struct Conformer {
    char altLoc;
    double occupancy;
    std::size_t count;
    std::string residue;
  };
  using ResidueKey = std::tuple<std::string, int, char>;
  const auto residueOf = [](const AtomRecord& a) { return ResidueKey{a.chain, a.residueNumber, a.insertionCode}; };
  std::map<ResidueKey, std::vector<Conformer>> residues;
  bool any = false;
  for (const AtomRecord& atom : molecule.atoms) {
    if (atom.altLoc == ' ') continue;
    any = true;
    auto& conformers = residues[residueOf(atom)];
    auto it = std::find_if(conformers.begin(), conformers.end(),
                           [&](const Conformer& c) { return c.altLoc == atom.altLoc; });
    if (it == conformers.end()) it = conformers.insert(conformers.end(), {atom.altLoc, 0.0, 0, atom.residue});
    it->occupancy += atom.occupancy;
    ++it->count;
  }
  if (!any) return 0;
  std::map<ResidueKey, const Conformer*> chosen;
  for (const auto& [key, conformers] : residues) {
    const Conformer* best = &conformers.front();
    for (const Conformer& c : conformers)
      if (c.occupancy / static_cast<double>(c.count) >
          best->occupancy / static_cast<double>(best->count))
        best = &c;
    chosen[key] = best;
  }
  // Per atom name of a residue: the record kept among its alternate locations.
  std::map<std::pair<ResidueKey, std::string>, std::size_t> kept;
  for (std::size_t i = 0; i < molecule.size(); ++i) {
    const AtomRecord& atom = molecule.atoms[i];
    if (atom.altLoc == ' ') continue;
    const Conformer& c = *chosen.at(residueOf(atom));
    if (atom.residue != c.residue) continue;
    const auto [it, fresh] = kept.try_emplace({residueOf(atom), atom.name}, i);
    if (fresh) continue;
    const AtomRecord& held = molecule.atoms[it->second];
    const bool heldChosen = held.altLoc == c.altLoc;
    if (atom.altLoc == c.altLoc ? !heldChosen : (!heldChosen && atom.occupancy > held.occupancy)) it->second = i;
  }
  // A name that also has a record without an alternate location keeps that one alone.
  for (const AtomRecord& atom : molecule.atoms)
    if (atom.altLoc == ' ') kept.erase({residueOf(atom), atom.name});
  std::vector<char> keep(molecule.size(), 1);
  std::size_t dropped = 0;
  for (std::size_t i = 0; i < molecule.size(); ++i) {
    const AtomRecord& atom = molecule.atoms[i];
    if (atom.altLoc == ' ') continue;
    const auto it = kept.find({residueOf(atom), atom.name});
    if (it == kept.end() || it->second != i) {
      keep[i] = 0;
      ++dropped;
    }
  }
  compact(molecule, keep);
  return dropped;
}

std::string plural(std::size_t n, const char* one, const char* many) {
  return std::to_string(n) + " " + (n == 1 ? one : many);
}

void selectAtoms(Molecule& molecule, const ReadOptions& options, const std::string& name) {
  const bool hasResidues =
      molecule.format != MoleculeFormat::Xyz && molecule.format != MoleculeFormat::Xyzr;
  SkipReport& skipped = molecule.skipped;
  skipped.altLocs = dropAlternateLocations(molecule);

  if (!options.chains.empty()) {
    if (!hasResidues)
      throw InputError(name, 0,
                       std::string(formatName(molecule.format)) +
                           " files have no chains; a chain selection cannot apply");
    std::set<std::string> present;
    for (const AtomRecord& atom : molecule.atoms) present.insert(atom.chain);
    for (const std::string& chain : options.chains) {
      if (present.count(chain) != 0) continue;
      std::string list;
      for (const std::string& c : present) list += (list.empty() ? "" : ", ") + inQuotes(c);
      throw InputError(name, 0,
                       "chain " + inQuotes(chain) + " is not in model " +
                           std::to_string(molecule.modelUsed) + " (chains: " + list + ")");
    }
    std::vector<char> keep(molecule.size(), 1);
    for (std::size_t i = 0; i < molecule.size(); ++i)
      if (std::find(options.chains.begin(), options.chains.end(), molecule.atoms[i].chain) ==
          options.chains.end()) {
        keep[i] = 0;
        ++skipped.otherChains;
      }
    compact(molecule, keep);
  }
  const std::size_t considered = molecule.size();

  // MARTINI's W, WF and PW are water only where the system is read as beads: in an atomistic
  // file a residue W is a tungsten ion.
  ResidueKinds kinds;
  const auto isWater = [&](const AtomRecord& atom) {
    const ResidueKind& kind = kinds(atom.residue);
    return kind.water || (options.beadRadius && kind.martiniWater);
  };
  if (!options.keepWater && hasResidues) {
    std::vector<char> keep(molecule.size(), 1);
    for (std::size_t i = 0; i < molecule.size(); ++i)
      if (isWater(molecule.atoms[i])) {
        keep[i] = 0;
        ++skipped.water;
      }
    compact(molecule, keep);
  } else if (hasResidues && !options.beadRadius) {
    // The massless sites of 4- and 5-site waters (MW, LP1, a PSF atom of mass 0) carry charge
    // but no electrons: no element, no volume. Reading "MW" as tungsten would put a metal in
    // every water, so they are left out and counted.
    std::vector<char> keep(molecule.size(), 1);
    for (std::size_t i = 0; i < molecule.size(); ++i) {
      const AtomRecord& atom = molecule.atoms[i];
      if (kinds(atom.residue).water &&
          (isWaterVirtualSite(atom.name) ||
           (molecule.format == MoleculeFormat::Psf && atom.element.empty()))) {
        keep[i] = 0;
        ++skipped.virtualSites;
      }
    }
    compact(molecule, keep);
  }
  if (!options.keepHydrogens) {
    if (molecule.format == MoleculeFormat::Xyzr)
      throw InputError(name, 0, "XYZR files have no elements, so hydrogens cannot be left out");
    std::vector<char> keep(molecule.size(), 1);
    for (std::size_t i = 0; i < molecule.size(); ++i)
      if (isHydrogen(molecule.atoms[i].element)) {
        keep[i] = 0;
        ++skipped.hydrogens;
      }
    compact(molecule, keep);
  }

  if (molecule.size() != 0) return;
  const std::string of = options.chains.empty() ? "" : " of the selected chains";
  if (skipped.water == considered)
    throw InputError(name, 0,
                     "all " + plural(considered, "atom", "atoms") + of +
                         (considered == 1 ? " is" : " are") + " water; use --keep-water");
  if (skipped.hydrogens == considered)
    throw InputError(name, 0,
                     "all " + plural(considered, "atom", "atoms") + of +
                         (considered == 1 ? " is" : " are") +
                         " hydrogen, and --no-hydrogens leaves them out");
  throw InputError(name, 0,
                   "no atoms left" + of + ": " + plural(skipped.water, "is water", "are water") +
                       " (use --keep-water) and " +
                       plural(skipped.hydrogens, "is hydrogen", "are hydrogen") +
                       " (--no-hydrogens)");
}

// The user's selection, after the water, hydrogen and chain choices, so that `index` and `atom`
// still count every atom of the file (AtomRecord::fileIndex) and a selection of water that
// --keep-water would keep says so.
void applySelection(Molecule& molecule, const std::string& selection, const std::string& name) {
  std::vector<std::uint32_t> chosen;
  try {
    chosen = build::selectAtoms(static_cast<const Molecule&>(molecule), selection);
  } catch (const std::invalid_argument& e) {
    throw InputError(name, 0, e.what());
  }
  std::vector<char> keep(molecule.size(), 0);
  for (std::uint32_t i : chosen) keep[i] = 1;
  molecule.skipped.unselected = molecule.size() - chosen.size();
  molecule.selection = selection;
  compact(molecule, keep);
}

std::string upperCase(std::string_view s) {
  std::string out(s);
  for (char& c : out) c = upper(c);
  return out;
}

// What a user can do about an atom without a radius; `element` is "" when it is unknown. A
// RES:ATOM line is offered only where the format has residues (not XYZ).
std::string waysOut(const AtomRecord& atom, const std::string& element) {
  const std::string resAtom =
      atom.residue.empty() ? std::string() : inQuotes(atom.residue + ":" + atom.name + " r");
  if (element.empty())
    return (resAtom.empty() ? std::string("use") : "give its radius with a line " + resAtom +
                                                       " in --radii FILE, use") +
           " --default-radius R for every atom without a radius, or --bead-radius R if the "
           "particles are coarse-grained beads";
  return "give one with a line " + inQuotes(element + " r") + " (every " + element + " atom)" +
         (resAtom.empty() ? std::string() : " or " + resAtom + " (this atom)") +
         " in --radii FILE, or use --default-radius R";
}

// A MARTINI bead: BB (BB1-BB3 in nucleotides) and SC1-SC6 in biopolymer residues, the
// single-bead waters W, WF and PW (whose polarizable beads are W, WP, WM), the head-group and
// glycerol beads of lipids (NC3, NH3, CNO, PO4, GL0-GL2: POPC, POPE, POPS, POPG, ...) and the
// sterol beads ROH and R1-R5 of CHOL. No atomistic force field names an atom so (CHARMM36's
// POPE has N, P, C1-C3 and O11-O14; its cholesterol is CHL1), and a tail bead (C1A, D2A) alone
// would not do: heme has atoms C1A-C4A.
bool isMartiniBead(const AtomRecord& atom, const ResidueKind& kind) {
  // Every bead name has at most 3 characters: longer names are told apart without making an
  // upper-cased copy, since this runs over every atom read.
  const std::string_view trimmed = trim(atom.name);
  if (trimmed.size() > 3) return false;
  char folded[3] = {};
  for (std::size_t i = 0; i < trimmed.size(); ++i) folded[i] = upper(trimmed[i]);
  const std::string_view name(folded, trimmed.size());
  if (kind.martiniWater)
    return name == "W" || name == "WF" || name == "PW" || name == "WP" || name == "WM";
  if (!kind.standard) {
    if (name == "NC3" || name == "NH3" || name == "CNO" || name == "PO4" || name == "GL0" || name == "GL1" ||
        name == "GL2")
      return true;
    return upperCase(trim(atom.residue)) == "CHOL" &&
           (name == "ROH" || (name.size() == 2 && name[0] == 'R' && name[1] >= '1' && name[1] <= '5'));
  }
  if (kind.water) return false;
  if (name == "BB") return true;
  const auto numbered = [&](std::string_view prefix, char last) {
    return name.size() == prefix.size() + 1 && name.compare(0, prefix.size(), prefix) == 0 &&
           name.back() >= '1' && name.back() <= last;
  };
  return numbered("BB", '3') || numbered("SC", '6');
}

// Recognises a MARTINI system; without --bead-radius reading its beads as atoms would give
// boron backbones, sulfur side chains and tungsten waters, so that is an error. One residue W
// of one atom W is the PDB's tungsten ion, so W waters count from the second on.
void recogniseCoarseGrained(Molecule& molecule, const ReadOptions& options,
                            const std::string& name) {
  auto bead = molecule.atoms.end();
  std::size_t tungstenLike = 0;
  ResidueKinds kinds;
  for (auto it = molecule.atoms.begin(); it != molecule.atoms.end(); ++it) {
    if (!isMartiniBead(*it, kinds(it->residue))) continue;
    const bool w = upperCase(trim(it->residue)) == "W";
    if (w && ++tungstenLike < 2) continue;
    bead = it;
    break;
  }
  molecule.martini = bead != molecule.atoms.end();
  if (molecule.martini && !options.beadRadius) {
    const std::string element = bead->element.empty() ? "no element" : "element " + bead->element;
    throw InputError(name, bead->line,
                     describe(*bead) +
                         " is a MARTINI bead: this is a MARTINI coarse-grained system (BB and "
                         "SC1-SC4 beads, lipid heads NC3, NH3, PO4 and GL1-GL2, sterol ROH, "
                         "W, WF and PW waters), whose particles are not atoms "
                         "(the name would read as " + element +
                         "); draw it with --bead-radius R, every bead one sphere of R Å "
                         "(e.g. --bead-radius 2.35, half MARTINI's bead size of 0.47 nm)");
  }
  if (!options.beadRadius) return;
  // A bead's name says nothing about an element; the file's element column or mass still does.
  for (AtomRecord& atom : molecule.atoms)
    if (atom.elementSource == ElementSource::Name) {
      atom.element.clear();
      atom.elementSource = ElementSource::None;
    }
}

void assignRadii(Molecule& molecule, const ReadOptions& options, const std::string& name) {
  if (options.defaultRadius &&
      (!std::isfinite(*options.defaultRadius) || *options.defaultRadius <= 0.0))
    throw InputError(name, 0,
                     "the default radius must be a finite number > 0, got " +
                         std::to_string(*options.defaultRadius));
  if (options.beadRadius && (!std::isfinite(*options.beadRadius) || *options.beadRadius <= 0.0))
    throw InputError(name, 0,
                     "the bead radius must be a finite number > 0, got " +
                         std::to_string(*options.beadRadius));
  if (options.radiiPreset && (options.radiiFile || options.beadRadius))
    throw InputError(name, 0,
                     std::string("--radii ") + radiusPresetName(*options.radiiPreset) +
                         " gives every atom FreeSASA's radius by residue and atom name; it cannot be "
                         "combined with " + (options.radiiFile ? "a radius table" : "--bead-radius") +
                         " (choose one)");
  if (molecule.format == MoleculeFormat::Xyzr) {
    if (options.radiiFile || options.beadRadius || options.radiiPreset)
      throw InputError(name, 0,
                       "an XYZR file gives its own radii and no atom names or elements, so " +
                           (options.radiiFile    ? "the radius table " + options.radiiFile->string()
                            : options.radiiPreset ? std::string("--radii ") + radiusPresetName(*options.radiiPreset)
                                                  : std::string("--bead-radius")) +
                           " cannot apply");
    molecule.radiusSources[static_cast<std::size_t>(RadiusSource::File)] = molecule.size();
    return;
  }
  if (molecule.format == MoleculeFormat::Pqr && !options.radiiFile && !options.beadRadius && !options.radiiPreset) {
    molecule.radiusSources[static_cast<std::size_t>(RadiusSource::File)] = molecule.size();
    return;
  }

  std::optional<RadiusTable> table;
  if (options.radiiFile) table = RadiusTable::load(*options.radiiFile);
  if (options.beadRadius) {
    char text[64];
    std::snprintf(text, sizeof text, "bead:%g", *options.beadRadius);
    molecule.radiiSet = text;
    if (table) molecule.radiiSet += ",table:" + table->path();
    molecule.beadRadius = options.beadRadius;
  } else if (options.radiiPreset) {
    molecule.radiiSet = radiusPresetName(*options.radiiPreset);
  } else {
    molecule.radiiSet = table ? "table:" + table->path() : std::string("bondi");
  }
  molecule.radii.assign(molecule.size(), 0.0);
  ResidueKinds kinds;
  for (std::size_t i = 0; i < molecule.size(); ++i) {
    AtomRecord& atom = molecule.atoms[i];
    std::optional<TabulatedRadius> radius;
    if (options.beadRadius) {
      radius = TabulatedRadius{*options.beadRadius, RadiusSource::Bead};
      if (table)
        if (const std::optional<double> r = table->findAtom(atom.residue, atom.name))
          radius = TabulatedRadius{*r, RadiusSource::UserTable};
      molecule.radii[i] = radius->radius;
      ++molecule.radiusSources[static_cast<std::size_t>(radius->source)];
      continue;
    }
    // An ion's residue is named like its atom (iodide I, uranium U), even where the name is
    // also a nucleotide's.
    const std::string_view atomName = trim(atom.name), residueName = trim(atom.residue);
    const bool ion = atomName.size() == residueName.size() &&
                     std::equal(atomName.begin(), atomName.end(), residueName.begin(),
                                [](char a, char b) { return upper(a) == upper(b); });
    // A classifier that names the atom decides its radius whatever its element reads as.
    if (options.radiiPreset)
      if (const std::optional<double> r = presetRadius(*options.radiiPreset, trim(atom.residue), trim(atom.name)))
        radius = TabulatedRadius{*r, RadiusSource::Preset};
    if (!radius && atom.elementSource == ElementSource::Name && !ion &&
        !isPlausibleElement(kinds(atom.residue).water, kinds(atom.residue).standard, atom.element)) {
      // The guess cannot be right; a RES:ATOM line gives the atom a radius all the same.
      const std::optional<double> r = table ? table->findAtom(atom.residue, atom.name) : std::nullopt;
      if (!r) {
        const bool water = isWaterResidue(atom.residue);
        throw InputError(
            name, atom.line,
            describe(atom) + ": its name reads as element " + atom.element + ", which " +
                (water ? "a water cannot hold (waters hold H and O)"
                       : "a standard residue cannot hold (amino acids and nucleotides hold H, C, "
                         "N, O, S, P and Se)") +
                "; if the particles are coarse-grained beads use --bead-radius R, otherwise give "
                "the atom's radius with a line " +
                inQuotes(atom.residue + ":" + atom.name + " r") +
                " in --radii FILE, or read a file with an element column");
      }
      atom.element.clear();
      atom.elementSource = ElementSource::None;
      radius = TabulatedRadius{*r, RadiusSource::UserTable};
    }
    if (!radius && table)
      if (const std::optional<double> r = table->find(atom.residue, atom.name, atom.element))
        radius = TabulatedRadius{*r, RadiusSource::UserTable};
    if (!radius && options.radiiPreset)
      if (const std::optional<double> r = freesasaGuessRadius(atom.element))
        radius = TabulatedRadius{*r, RadiusSource::PresetGuess};
    if (!radius) radius = elementRadius(atom.element);
    if (!radius && options.defaultRadius) {
      radius = TabulatedRadius{*options.defaultRadius, RadiusSource::Default};
      ++molecule.skipped.defaultRadius;
    }
    if (!radius) {
      const std::string what =
          atom.element.empty()
              ? (molecule.format == MoleculeFormat::Xyz
                     ? inQuotes(atom.name) + " is not an element symbol"
                     : std::string("its element is unknown (no element column, and the name "
                                   "implies none)"))
              : "element " + atom.element +
                    " has no radius in the Bondi (1964), Mantina (2009) or Alvarez (2013) "
                    "tables" +
                    (table ? " nor in " + table->path() : std::string());
      throw InputError(name, atom.line, describe(atom) + ": " + what + "; " + waysOut(atom, atom.element));
    }
    molecule.radii[i] = radius->radius;
    ++molecule.radiusSources[static_cast<std::size_t>(radius->source)];
  }
}

// Atoms at exactly the same centre that get exactly the same radius (the same radius in the
// file, or the same element, residue and name) add nothing to any surface but make every
// neighbour search quadratic (200,000 coincident atoms took minutes): the first is kept, the
// others left out, counted and noted. Before the radii are assigned, so the radius sources
// count only the atoms kept.
void dropExactDuplicates(Molecule& molecule) {
  const std::size_t n = molecule.size();
  const bool fileRadii = molecule.radii.size() == n;
  struct Key {
    std::array<std::uint64_t, 4> bits;
    std::string_view element, residue, name;
    bool operator==(const Key&) const = default;
  };
  // +0.0 and -0.0 are one coordinate.
  const auto bitsOf = [](double v) { return std::bit_cast<std::uint64_t>(v == 0.0 ? 0.0 : v); };
  const auto keyOf = [&](std::size_t i) {
    const glm::dvec3& c = molecule.centers[i];
    const AtomRecord& a = molecule.atoms[i];
    return Key{{bitsOf(c.x), bitsOf(c.y), bitsOf(c.z), fileRadii ? bitsOf(molecule.radii[i]) : 0},
               a.element, a.residue, a.name};
  };
  // Every bit of the key is mixed into the hash (MurmurHash3's finaliser after each word): its
  // top bits choose the partition, its low bits the slot.
  const auto mix = [](std::uint64_t h) {
    h ^= h >> 33;
    h *= 0xff51afd7ed558ccdull;
    h ^= h >> 33;
    h *= 0xc4ceb9fe1a85ec53ull;
    return h ^ (h >> 33);
  };
  const auto mixText = [&](std::uint64_t h, std::string_view s) {
    std::uint64_t word = s.size();
    for (std::size_t k = 0; k < s.size(); ++k) {
      word = word << 8 | static_cast<unsigned char>(s[k]);
      if (k % 8 == 7) h = mix(h ^ word), word = 0;
    }
    return mix(h ^ word);
  };
  const auto hashOf = [&](const Key& k) {
    std::uint64_t h = 0;
    for (std::uint64_t b : k.bits) h = mix(h ^ b);
    return mixText(mixText(mixText(h, k.name), k.residue), k.element);
  };
  // Partitioned by the hash's top bits into runs of about 2,048 atoms, each searched with its
  // own small open-addressing table (a power of two at most half full, linear probing) that
  // stays in the cache. One table over all atoms made this a fifth of reading a million-atom
  // XYZR file: a cache and TLB miss per atom in a 64 MB table (a node-based
  // std::unordered_map before it, a third, and 100 bytes per atom). The partitions keep each
  // atom's file order, so the first atom of a key to be seen is the earliest in the file.
  struct Entry {
    std::uint64_t hash;
    std::size_t index;
  };
  int partitionBits = 0;
  while (partitionBits < 16 && (n >> partitionBits) > 2048) ++partitionBits;
  const int shift = 64 - partitionBits;
  const auto partitionOf = [&](std::uint64_t hash) {
    return partitionBits == 0 ? std::size_t{0} : static_cast<std::size_t>(hash >> shift);
  };
  std::vector<std::uint64_t> hashes(n);
  std::vector<std::size_t> starts((std::size_t{1} << partitionBits) + 1, 0);
  for (std::size_t i = 0; i < n; ++i) {
    hashes[i] = hashOf(keyOf(i));
    ++starts[partitionOf(hashes[i]) + 1];
  }
  for (std::size_t p = 1; p < starts.size(); ++p) starts[p] += starts[p - 1];
  std::vector<Entry> entries(n);
  {
    std::vector<std::size_t> next(starts.begin(), starts.end() - 1);
    for (std::size_t i = 0; i < n; ++i) entries[next[partitionOf(hashes[i])]++] = Entry{hashes[i], i};
  }
  hashes = {};

  std::vector<char> keep(n, 1);
  std::size_t dropped = 0;
  std::size_t firstDropped = n, itsOriginal = n;  // the earliest duplicate in the file, and whom it repeats
  std::vector<std::uint32_t> table;                // a position in the partition + 1; 0 is empty
  for (std::size_t p = 0; p + 1 < starts.size(); ++p) {
    const std::size_t begin = starts[p], count = starts[p + 1] - begin;
    if (count < 2) continue;
    std::size_t slots = 16;
    while (slots < 2 * count) slots *= 2;
    table.assign(slots, 0);
    for (std::size_t k = 0; k < count; ++k) {
      const Entry& e = entries[begin + k];
      std::size_t s = static_cast<std::size_t>(e.hash) & (slots - 1);
      std::uint32_t held = 0;
      for (; (held = table[s]) != 0; s = (s + 1) & (slots - 1)) {
        const Entry& other = entries[begin + held - 1];
        if (other.hash == e.hash && keyOf(other.index) == keyOf(e.index)) break;
      }
      if (held == 0) {
        table[s] = static_cast<std::uint32_t>(k + 1);
        continue;
      }
      keep[e.index] = 0;
      ++dropped;
      if (e.index < firstDropped) firstDropped = e.index, itsOriginal = entries[begin + held - 1].index;
    }
  }
  entries = {};
  table = {};
  if (dropped == 0) return;
  const auto where = [&](std::size_t i) {
    const int line = molecule.atoms[i].line;
    return line > 0 ? "line " + std::to_string(line) : "atom " + std::to_string(i + 1);
  };
  const std::string example = " (the first: " + where(firstDropped) + " repeats " + where(itsOriginal) + ")";
  compact(molecule, keep);
  molecule.skipped.duplicates = dropped;
  molecule.notes.push_back(std::to_string(dropped) + (dropped == 1 ? " atom lies" : " atoms lie") +
                           " exactly on an earlier atom of the same radius and " + (dropped == 1 ? "was" : "were") +
                           " left out" + example);
}

void countElementSources(Molecule& molecule) {
  for (const AtomRecord& atom : molecule.atoms) {
    molecule.elementsFromNames += atom.elementSource == ElementSource::Name;
    molecule.elementsFromMasses += atom.elementSource == ElementSource::Mass;
  }
}

}  // namespace

std::string text::textOfBytes(std::string bytes, const std::string& name) {
  const bool gzipped = hasGzipMagic(bytes);
  if (!gzipped && hasGzipExtension(name))
    throw InputError(
        name, 0,
        bytes.empty()
            ? std::string("the file is empty (expected gzip data, as the name ends in .gz)")
            : "the name ends in .gz but the file is not gzip-compressed "
              "(it does not start with the gzip magic bytes 1f 8b)");
  // (Bytes read by readFileBytes were held to the line length as they came; bytes handed in
  // from memory are checked here.)
  if (!gzipped) LineLengthGuard(name).feed(bytes.data(), bytes.size());
  std::string text = gzipped ? gunzip(bytes, name) : std::move(bytes);
  // A lone CR ends a line (classic Mac OS files, some Windows tools): made a LF in place, so
  // that every reader, gemmi's too, sees the lines ("\r\n" stays; the readers drop its CR).
  char* const end = text.data() + text.size();
  for (char* cr = text.data(); (cr = static_cast<char*>(std::memchr(cr, '\r', static_cast<std::size_t>(end - cr))));
       ++cr)
    if (cr + 1 == end || cr[1] != '\n') *cr = '\n';
  checkText(text, name, gzipped);
  return text;
}

std::string text::readTextFile(const fs::path& path, const std::string& name) {
  return textOfBytes(readFileBytes(path, name), name);
}

const char* formatName(MoleculeFormat format) {
  switch (format) {
    case MoleculeFormat::Auto:
      return "auto";
    case MoleculeFormat::Pdb:
      return "PDB";
    case MoleculeFormat::Mmcif:
      return "mmCIF";
    case MoleculeFormat::Pqr:
      return "PQR";
    case MoleculeFormat::Xyzr:
      return "XYZR";
    case MoleculeFormat::Xyz:
      return "XYZ";
    case MoleculeFormat::Gro:
      return "GRO";
    case MoleculeFormat::Psf:
      return "PSF";
  }
  return "unknown";
}

Molecule readMolecule(const std::filesystem::path& path, const ReadOptions& options) {
  const std::string name = path.string();
  if (options.model < 1)
    throw InputError(name, 0,
                     "models are numbered from 1, got model " + std::to_string(options.model));
  if (options.format == MoleculeFormat::Auto) formatFromPath(path, name);  // before reading
  return readMoleculeBytes(readFileBytes(path, name), name, options);
}

Molecule readMoleculeBytes(std::string bytes, const std::string& name, const ReadOptions& options) {
  const fs::path path(name);
  if (options.model < 1)
    throw InputError(name, 0,
                     "models are numbered from 1, got model " + std::to_string(options.model));
  const MoleculeFormat format =
      options.format == MoleculeFormat::Auto ? formatFromPath(path, name) : options.format;

  // Not const: the PDB reader takes it over (std::move of a const string copied 100 MB).
  std::string text = text::textOfBytes(std::move(bytes), name);
  const auto crc = static_cast<std::uint32_t>(
      crc32_z(crc32_z(0L, Z_NULL, 0), reinterpret_cast<const Bytef*>(text.data()), text.size()));

  Molecule molecule;
  switch (format) {
    case MoleculeFormat::Pdb:
      molecule = detail::readPdbWithGemmi(std::move(text), name, options.model);
      break;
    case MoleculeFormat::Mmcif:
      molecule = detail::readMmcifWithGemmi(text, name, options.model);
      break;
    case MoleculeFormat::Pqr:
      molecule = parsePqr(text, name, options);
      break;
    case MoleculeFormat::Xyzr:
      molecule = parseXyzr(text, name, options);
      break;
    case MoleculeFormat::Xyz:
      molecule = parseXyz(text, name, options.model);
      break;
    case MoleculeFormat::Gro:
      if (options.model != 1)
        throw InputError(name, 0,
                         "--model " + std::to_string(options.model) +
                             ": a GRO file's later frames are a trajectory; read them with "
                             "`surftrace trajectory TOPOLOGY " + name + "`");
      molecule = detail::parseGro(text, name);
      break;
    case MoleculeFormat::Psf:
      if (!options.topologyOnly)
        throw InputError(name, 0,
                         "a PSF is a topology without coordinates: give it with a trajectory, e.g. "
                         "`surftrace trajectory " + name + " TRAJECTORY.dcd -o frames/%05d.png`");
      molecule = detail::parsePsf(text, name);
      break;
    case MoleculeFormat::Auto:
      SURFTRACE_ASSERT(false);
      break;
  }
  std::string().swap(text);  // not held through the choices below (the text of a million atoms: 50-130 MB)
  molecule.source = name;
  molecule.format = format;
  molecule.modelUsed = options.model;
  molecule.inputCrc32 = crc;
  molecule.fileAtomCount = molecule.size();
  for (std::size_t i = 0; i < molecule.size(); ++i) molecule.atoms[i].fileIndex = i;

  if (format != MoleculeFormat::Xyz && format != MoleculeFormat::Xyzr)
    recogniseCoarseGrained(molecule, options, name);
  selectAtoms(molecule, options, name);
  if (options.selection) applySelection(molecule, *options.selection, name);
  if (!options.topologyOnly) dropExactDuplicates(molecule);
  assignRadii(molecule, options, name);
  countElementSources(molecule);
  if (!options.topologyOnly) validateMolecule(molecule);
  return molecule;
}

void validateMolecule(const Molecule& molecule) {
  const std::string& name = molecule.source;
  if (molecule.radii.size() != molecule.centers.size() ||
      (!molecule.atoms.empty() && molecule.atoms.size() != molecule.centers.size()))
    throw InputError(name, 0,
                     "inconsistent molecule: " + std::to_string(molecule.centers.size()) +
                         " centres, " + std::to_string(molecule.radii.size()) + " radii, " +
                         std::to_string(molecule.atoms.size()) + " atom records");
  if (molecule.centers.empty()) throw InputError(name, 0, "the molecule has no atoms");
  for (std::size_t i = 0; i < molecule.centers.size(); ++i) {
    const glm::dvec3& c = molecule.centers[i];
    const double r = molecule.radii[i];
    const bool centreOk = std::isfinite(c.x) && std::isfinite(c.y) && std::isfinite(c.z);
    const bool radiusOk = std::isfinite(r) && r > 0.0;
    const bool centreNear = std::max({std::abs(c.x), std::abs(c.y), std::abs(c.z)}) <= kMaxCoordinate;
    const bool radiusSmall = r <= kMaxRadius;
    if (centreOk && radiusOk && centreNear && radiusSmall) continue;
    const int line = molecule.atoms.empty() ? 0 : molecule.atoms[i].line;
    const std::string who =
        molecule.atoms.empty() ? "atom " + std::to_string(i + 1) : describe(molecule.atoms[i]);
    if (!centreOk)
      throw InputError(name, line,
                       who + ": the centre is not finite (" + std::to_string(c.x) + ", " +
                           std::to_string(c.y) + ", " + std::to_string(c.z) + ")");
    if (!radiusOk)
      throw InputError(name, line, who + ": the radius must be finite and > 0, got " + std::to_string(r));
    char text[256];
    if (!centreNear)
      std::snprintf(text, sizeof text,
                    ": the centre (%g, %g, %g) lies beyond %g Å of the origin, farther than any molecule or "
                    "simulation box in Å reaches (are the coordinates in other units, or the file damaged?)",
                    c.x, c.y, c.z, kMaxCoordinate);
    else
      std::snprintf(text, sizeof text, ": the radius %g Å is larger than %g Å, more than any atom or bead has",
                    r, kMaxRadius);
    throw InputError(name, line, who + text);
  }
}

}  // namespace surftrace::build

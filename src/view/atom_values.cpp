// Per-atom values from a CSV file (atom_values.hpp).
#include "view/atom_values.hpp"

#include <algorithm>
#include <cctype>
#include <cmath>
#include <cstdlib>
#include <fstream>
#include <limits>
#include <map>
#include <sstream>
#include <tuple>

#include "build/io/error.hpp"

namespace surftrace::view {
namespace {

std::string trimmed(const std::string& s) {
  const auto first = s.find_first_not_of(" \t\r");
  if (first == std::string::npos) return "";
  return s.substr(first, s.find_last_not_of(" \t\r") - first + 1);
}

std::vector<std::string> fields(const std::string& line) {
  std::vector<std::string> out;
  std::string field;
  std::istringstream in(line);
  while (std::getline(in, field, ',')) out.push_back(trimmed(field));
  if (!line.empty() && line.back() == ',') out.emplace_back();
  return out;
}

std::string lower(std::string s) {
  for (char& c : s) c = static_cast<char>(std::tolower(static_cast<unsigned char>(c)));
  return s;
}

bool wholeNumber(const std::string& text, long long& value) {
  if (text.empty()) return false;
  char* end = nullptr;
  errno = 0;
  value = std::strtoll(text.c_str(), &end, 10);
  return errno == 0 && *end == '\0';
}

}  // namespace

std::size_t AtomValues::valued() const {
  return static_cast<std::size_t>(std::count_if(values.begin(), values.end(), [](double v) { return !std::isnan(v); }));
}

AtomValues readAtomValues(const std::string& path, const build::Molecule& molecule) {
  std::ifstream in(path);
  if (!in) throw build::InputError(path, 0, "cannot open the values file (--values)");
  AtomValues out;
  out.path = path;
  out.values.assign(molecule.size(), std::numeric_limits<double>::quiet_NaN());
  std::vector<int> setOnLine(molecule.size(), 0);
  // The molecule's atoms by their index in the file, and by residue.
  std::size_t fileAtoms = molecule.fileAtomCount;
  for (const auto& a : molecule.atoms) fileAtoms = std::max(fileAtoms, a.fileIndex + 1);
  std::vector<std::size_t> byFileIndex(fileAtoms, SIZE_MAX);
  std::map<std::tuple<std::string, int, char>, std::vector<std::size_t>> byResidue;
  for (std::size_t i = 0; i < molecule.size(); ++i) {
    const auto& a = molecule.atoms[i];
    byFileIndex[a.fileIndex] = i;
    byResidue[{a.chain, a.residueNumber, a.insertionCode}].push_back(i);
  }
  enum class Form { None, Atom, Residue, ResidueIcode } form = Form::None;
  std::size_t columns = 0;
  std::string line;
  int lineNo = 0;
  while (std::getline(in, line)) {
    ++lineNo;
    const std::string text = trimmed(line);
    if (text.empty() || text[0] == '#') continue;
    const std::vector<std::string> f = fields(text);
    if (form == Form::None) {
      std::vector<std::string> names;
      for (const auto& n : f) names.push_back(lower(n));
      if (names.size() == 2 && names[0] == "atom") form = Form::Atom;
      else if (names.size() == 3 && names[0] == "chain" && names[1] == "resid") form = Form::Residue;
      else if (names.size() == 4 && names[0] == "chain" && names[1] == "resid" && names[2] == "icode") form = Form::ResidueIcode;
      if (form == Form::None || f.back().empty())
        throw build::InputError(path, lineNo, "header '" + text + "': expected `atom,NAME` (0-based atom index) or "
                                "`chain,resid,NAME` or `chain,resid,icode,NAME`, NAME naming the values");
      columns = f.size();
      out.label = f.back();
      continue;
    }
    if (f.size() != columns)
      throw build::InputError(path, lineNo, "'" + text + "': " + std::to_string(f.size()) + " fields, but the header has " +
                                            std::to_string(columns));
    const std::string& valueText = f.back();
    double value = std::numeric_limits<double>::quiet_NaN();
    const std::string lv = lower(valueText);
    if (!(valueText.empty() || lv == "nan" || lv == "na")) {
      char* end = nullptr;
      value = std::strtod(valueText.c_str(), &end);
      if (end == valueText.c_str() || *end != '\0' || !std::isfinite(value))
        throw build::InputError(path, lineNo, "value '" + valueText + "' is not a finite number (leave it empty, or "
                                "write nan, for an atom without a value)");
    }
    ++out.rows;
    std::vector<std::size_t> atoms;
    std::string what;
    if (form == Form::Atom) {
      long long index = 0;
      if (!wholeNumber(f[0], index) || index < 0)
        throw build::InputError(path, lineNo, "atom '" + f[0] + "' is not an atom index (a whole number from 0)");
      if (static_cast<unsigned long long>(index) >= fileAtoms)
        throw build::InputError(path, lineNo, "atom " + f[0] + " is beyond the structure's " + std::to_string(fileAtoms) +
                                " atoms (indices count from 0, as MDAnalysis's atom.index)");
      if (byFileIndex[static_cast<std::size_t>(index)] != SIZE_MAX) atoms.push_back(byFileIndex[static_cast<std::size_t>(index)]);
      what = "atom " + f[0];
    } else {
      long long resid = 0;
      if (!wholeNumber(f[1], resid) || resid < std::numeric_limits<int>::min() || resid > std::numeric_limits<int>::max())
        throw build::InputError(path, lineNo, "resid '" + f[1] + "' is not a residue number (a whole number)");
      char icode = ' ';
      if (form == Form::ResidueIcode) {
        if (f[2].size() > 1)
          throw build::InputError(path, lineNo, "icode '" + f[2] + "' is not an insertion code (one character, or empty)");
        if (!f[2].empty()) icode = f[2][0];
      }
      if (const auto it = byResidue.find({f[0], static_cast<int>(resid), icode}); it != byResidue.end()) atoms = it->second;
      what = "chain " + (f[0].empty() ? std::string("(none)") : f[0]) + " resid " + f[1] +
             (icode == ' ' ? std::string() : std::string(1, icode));
    }
    if (atoms.empty()) {
      if (out.unmatchedRows++ == 0) out.firstUnmatched = "line " + std::to_string(lineNo) + " (" + what + ")";
      continue;
    }
    for (std::size_t i : atoms) {
      if (setOnLine[i] != 0)
        throw build::InputError(path, lineNo, what + " gives atom " + std::to_string(molecule.atoms[i].fileIndex) +
                                " a value that line " + std::to_string(setOnLine[i]) + " gave it already");
      setOnLine[i] = lineNo;
      out.values[i] = value;
    }
  }
  if (form == Form::None) throw build::InputError(path, 0, "no header: the file is empty");
  if (out.valued() == 0)
    throw build::InputError(path, 0, "no atom of " + molecule.source + " gets a value from this file (" +
                            std::to_string(out.rows) + " rows" +
                            (out.unmatchedRows ? "; none names an atom it holds, first " + out.firstUnmatched : "") + ")");
  return out;
}

}  // namespace surftrace::view

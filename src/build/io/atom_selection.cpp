// Atom selections (atom_selection.hpp): the subset of MDAnalysis's selection language that
// users type, parsed as MDAnalysis's SelectionParser parses it.
#include "build/io/atom_selection.hpp"

#include <algorithm>
#include <cctype>
#include <charconv>
#include <cstddef>
#include <optional>
#include <set>
#include <stdexcept>
#include <string_view>
#include <unordered_map>
#include <utility>

#include "build/io/text_fields.hpp"

namespace surftrace::build {
namespace {

using text::inQuotes;
using text::isSpace;

// What MDAnalysis's keywords stand for, copied from MDAnalysis/core/selection.py so that a
// selection means here what it means there: ProteinSelection.prot_res and
// BackboneSelection.bb_atoms (2.4.2), WaterSelection.water_res (added in 2.9.0).
constexpr std::string_view kProteinResidues[] = {
    // CHARMM top_all27_prot_lipid.rtf
    "ALA", "ARG", "ASN", "ASP", "CYS", "GLN", "GLU", "GLY", "HSD", "HSE", "HSP", "ILE", "LEU", "LYS", "MET", "PHE",
    "PRO", "SER", "THR", "TRP", "TYR", "VAL", "ALAD",
    // PDB
    "HIS", "MSE",
    // GROMACS 4.5.3 oplsaa.ff
    "ARGN", "ASPH", "CYS2", "CYSH", "QLN", "PGLU", "GLUH", "HIS1", "HISD", "HISE", "HISH", "LYSH",
    // GROMACS 4.5.3 gromos53a6.ff
    "ASN1", "CYS1", "HISA", "HISB", "HIS2",
    // GROMACS 4.5.3 amber03.ff
    "HID", "HIE", "HIP", "ORN", "DAB", "LYN", "HYP", "CYM", "CYX", "ASH", "GLH", "ACE", "NME",
    // GROMACS 2016.3 amber99sb-star-ildn.ff
    "NALA", "NGLY", "NSER", "NTHR", "NLEU", "NILE", "NVAL", "NASN", "NGLN", "NARG", "NHID", "NHIE", "NHIP", "NTRP",
    "NPHE", "NTYR", "NGLU", "NASP", "NLYS", "NPRO", "NCYS", "NCYX", "NMET", "CALA", "CGLY", "CSER", "CTHR", "CLEU",
    "CILE", "CVAL", "CASF", "CASN", "CGLN", "CARG", "CHID", "CHIE", "CHIP", "CTRP", "CPHE", "CTYR", "CGLU", "CASP",
    "CLYS", "CPRO", "CCYS", "CCYX", "CMET", "CME", "ASF"};
constexpr std::string_view kBackboneNames[] = {"N", "CA", "C", "O"};
constexpr std::string_view kWaterResidues[] = {"H2O", "HOH", "OH2", "HHO", "OHH",  "T3P",  "T4P",
                                               "T5P", "SOL", "WAT", "TIP", "TIP2", "TIP3", "TIP4"};

enum class Key { All, Protein, Backbone, Water, Name, Resname, Chain, Segid, Element, Resid, Index, Atom };

struct Keyword {
  std::string_view word;
  Key key;
};
constexpr Keyword kKeywords[] = {{"name", Key::Name},         {"resname", Key::Resname}, {"resid", Key::Resid},
                                 {"chain", Key::Chain},       {"chainID", Key::Chain},   {"chainid", Key::Chain},
                                 {"segid", Key::Segid},       {"element", Key::Element}, {"index", Key::Index},
                                 {"atom", Key::Atom},         {"bynum", Key::Atom},      {"protein", Key::Protein},
                                 {"backbone", Key::Backbone}, {"water", Key::Water},     {"all", Key::All}};
constexpr std::string_view kKeywordList =
    "name, resname, resid, chain (chainID), segid, element, index, atom (bynum), protein, backbone, water, all";

// MDAnalysis 2.4.2's other keywords. As there, they end a keyword's values; here they are an
// error that says so, rather than names nobody has.
constexpr std::string_view kOtherMdaKeywords[] = {
    "altLoc",        "altloc",       "aromatic",  "aromaticity", "around",  "bfactor",  "bonded",
    "byres",         "charge",       "chirality", "cylayer",     "cyzone",  "epsilon",  "epsilon14",
    "formalcharge",  "gbscreen",     "global",    "group",       "icode",   "id",       "isolayer",
    "mass",          "model",        "molnum",    "moltype",     "nbindex", "nucleic",  "nucleicbackbone",
    "nucleicbase",   "nucleicsugar", "occupancy", "point",       "prop",    "radius",   "record_type",
    "resindex",      "resnum",       "rmin",      "rmin14",      "same",    "segindex", "smarts",
    "solventradius", "sphlayer",     "sphzone",   "tempfactor",  "type"};

template <std::size_t N>
bool inList(std::string_view s, const std::string_view (&list)[N]) {
  return std::find(std::begin(list), std::end(list), s) != std::end(list);
}

std::optional<Key> keywordOf(std::string_view word) {
  for (const Keyword& k : kKeywords)
    if (k.word == word) return k.key;
  return std::nullopt;
}

std::string lowerCase(std::string_view s) {
  std::string out(s);
  for (char& c : out) c = static_cast<char>(std::tolower(static_cast<unsigned char>(c)));
  return out;
}

bool isOperator(std::string_view w) { return w == "and" || w == "or"; }
bool isPunctuation(std::string_view w) { return w == "(" || w == ")" || w == ","; }
// What ends a keyword's values (MDAnalysis's is_keyword, plus this grammar's own words).
bool endsValues(std::string_view w) {
  return isOperator(w) || isPunctuation(w) || w == "not" || keywordOf(w) || inList(w, kOtherMdaKeywords);
}

// Python's fnmatch.fnmatchcase, which MDAnalysis's string keywords use: * any run, ? any one
// character, [abc], [a-z] and [!abc] one of (not one of) a set; a '[' without its ']' is itself.
bool matchesPattern(std::string_view pattern, std::string_view s) {
  if (pattern.find_first_of("*?[") == std::string_view::npos) return pattern == s;
  std::size_t p = 0, i = 0, starP = std::string_view::npos, starI = 0;
  while (i < s.size()) {
    if (p < pattern.size()) {
      const char c = pattern[p];
      if (c == '*') {
        starP = p++, starI = i;
        continue;
      }
      bool step = false;
      std::size_t next = p + 1;
      if (c == '?') {
        step = true;
      } else if (c == '[') {
        std::size_t j = p + 1;
        if (j < pattern.size() && pattern[j] == '!') ++j;
        if (j < pattern.size() && pattern[j] == ']') ++j;
        while (j < pattern.size() && pattern[j] != ']') ++j;
        if (j >= pattern.size()) {
          step = s[i] == '[';
        } else {
          std::string_view set = pattern.substr(p + 1, j - p - 1);
          const bool negate = !set.empty() && set[0] == '!';
          if (negate) set.remove_prefix(1);
          bool in = false;
          for (std::size_t k = 0; k < set.size(); ++k) {
            if (k + 2 < set.size() && set[k + 1] == '-') {
              in = in || (s[i] >= set[k] && s[i] <= set[k + 2]);
              k += 2;
            } else {
              in = in || s[i] == set[k];
            }
          }
          step = in != negate;
          next = j + 1;
        }
      } else {
        step = c == s[i];
      }
      if (step) {
        p = next, ++i;
        continue;
      }
    }
    if (starP == std::string_view::npos) return false;
    p = starP + 1, i = ++starI;
  }
  while (p < pattern.size() && pattern[p] == '*') ++p;
  return p == pattern.size();
}

struct Word {
  std::string text;
  std::size_t offset = 0;  // in the selection
};

// Words split at whitespace; parentheses (as MDAnalysis does) and commas are words of their own.
std::vector<Word> splitWords(std::string_view selection) {
  std::vector<Word> words;
  for (std::size_t i = 0; i < selection.size();) {
    if (isSpace(selection[i])) {
      ++i;
    } else if (isPunctuation(selection.substr(i, 1))) {
      words.push_back({std::string(1, selection[i]), i});
      ++i;
    } else {
      const std::size_t start = i;
      while (i < selection.size() && !isSpace(selection[i]) && !isPunctuation(selection.substr(i, 1))) ++i;
      words.push_back({std::string(selection.substr(start, i - start)), start});
    }
  }
  return words;
}

// A value of resid, index or atom: one number or an inclusive range; for resid, each end may
// carry an insertion code ("52A").
struct NumberRange {
  long long lo = 0, hi = 0;
  std::string loCode, hiCode;
  bool isRange = false;
};

std::optional<std::pair<long long, std::string>> leadingNumber(std::string_view& s, bool withCode) {
  std::size_t n = (!s.empty() && s[0] == '-') ? 1 : 0;
  const std::size_t digitsFrom = n;
  while (n < s.size() && s[n] >= '0' && s[n] <= '9') ++n;
  if (n == digitsFrom) return std::nullopt;
  long long v = 0;
  if (std::from_chars(s.data(), s.data() + n, v).ec != std::errc()) return std::nullopt;
  std::string code;
  const auto isWordChar = [](char c) { return (c >= 'A' && c <= 'Z') || (c >= 'a' && c <= 'z') || c == '_'; };
  if (withCode && n < s.size() && isWordChar(s[n])) code = std::string(1, s[n++]);
  s.remove_prefix(n);
  return std::make_pair(v, code);
}

// MDAnalysis's INT_PATTERN and RANGE_PATTERN: "12", "10-20", "10:20", "-5--2", "10 to 20".
std::optional<NumberRange> parseNumberRange(std::string_view s, bool withCode) {
  NumberRange r;
  const auto lo = leadingNumber(s, withCode);
  if (!lo) return std::nullopt;
  r.lo = r.hi = lo->first;
  r.loCode = r.hiCode = lo->second;
  if (s.empty()) return r;
  std::size_t spaces = 0;
  while (spaces < s.size() && s[spaces] == ' ') ++spaces;
  s.remove_prefix(spaces);
  if (!s.empty() && (s[0] == ':' || s[0] == '-')) {
    s.remove_prefix(1);
  } else if (spaces > 0 && s.substr(0, 3) == "to ") {
    s.remove_prefix(2);
  } else {
    return std::nullopt;
  }
  while (!s.empty() && s[0] == ' ') s.remove_prefix(1);
  const auto hi = leadingNumber(s, withCode);
  if (!hi || !s.empty()) return std::nullopt;
  r.hi = hi->first;
  r.hiCode = hi->second;
  r.isRange = true;
  return r;
}

// MDAnalysis's residue number test, insertion codes included: a plain number is that residue
// without a code, and a range runs from its first end's code to its last end's.
bool residInRange(int resid, std::string_view code, const NumberRange& r) {
  if (!r.isRange) return resid == r.lo && code == r.loCode;
  if (r.lo == r.hi) return resid == r.lo && code >= r.loCode && code <= r.hiCode;
  return (resid == r.lo && code >= r.loCode) || (resid > r.lo && resid < r.hi) || (resid == r.hi && code <= r.hiCode);
}

using Mask = std::vector<char>;

struct TermReport {
  std::string text;  // as typed
  Key key;
  std::size_t hits = 0;
};

std::string quotedList(const std::set<std::string>& names) {
  constexpr std::size_t kShown = 12;
  std::string list;
  std::size_t n = 0;
  for (const std::string& name : names) {
    if (n++ == kShown) return list + ", ... (" + std::to_string(names.size()) + " in all)";
    list.append(list.empty() ? "" : ", ").append(inQuotes(name));
  }
  return list;
}

// What the molecule holds for a keyword, to say so when a term selects nothing.
std::string present(const Molecule& m, Key key) {
  if (m.atoms.empty()) return "no atoms";
  if (key == Key::Resid || key == Key::Index || key == Key::Atom) {
    long long lo = 0, hi = 0;
    for (std::size_t i = 0; i < m.atoms.size(); ++i) {
      const AtomRecord& a = m.atoms[i];
      const long long v = key == Key::Resid  ? a.residueNumber
                          : key == Key::Atom ? static_cast<long long>(a.fileIndex) + 1
                                             : static_cast<long long>(a.fileIndex);
      lo = i == 0 ? v : std::min(lo, v), hi = i == 0 ? v : std::max(hi, v);
    }
    return (key == Key::Resid  ? "residues "
            : key == Key::Atom ? "atoms "
                               : "atoms at index ") +
           std::to_string(lo) + " to " + std::to_string(hi);
  }
  std::set<std::string> names;
  for (const AtomRecord& a : m.atoms)
    names.insert(key == Key::Name      ? a.name
                 : key == Key::Chain   ? a.chain
                 : key == Key::Segid   ? a.segid
                 : key == Key::Element ? a.element
                                       : a.residue);
  std::string what = (key == Key::Name      ? "atom names "
                      : key == Key::Chain   ? "chains "
                      : key == Key::Segid   ? "segids "
                      : key == Key::Element ? "elements "
                                            : "residue names ") +
                     quotedList(names);
  if (key == Key::Water && m.skipped.water > 0)
    what += "; " + std::to_string(m.skipped.water) +
            " water atoms were left out when it was read (--keep-water keeps them)";
  return what;
}

class Parser {
 public:
  Parser(const Molecule& molecule, const std::string& selection)
      : m_(molecule), selection_(selection), words_(splitWords(selection)) {
    fileAtoms_ = molecule.fileAtomCount;
    for (const AtomRecord& a : molecule.atoms) fileAtoms_ = std::max(fileAtoms_, a.fileIndex + 1);
  }

  std::vector<std::uint32_t> select() {
    if (words_.empty()) throw std::invalid_argument("the atom selection is empty");
    const Mask chosen = parseUnion();
    if (pos_ < words_.size()) fail(pos_, pos_, "closes no '('");  // parseUnion stops only at ')'
    std::vector<std::uint32_t> out;
    for (std::size_t i = 0; i < chosen.size(); ++i)
      if (chosen[i]) out.push_back(static_cast<std::uint32_t>(i));
    if (out.empty()) throw std::invalid_argument(nothingSelected());
    return out;
  }

 private:
  // Expressions separated by commas: their union, loosest of all.
  Mask parseUnion() {
    Mask m = parseExpression();
    while (pos_ < words_.size() && words_[pos_].text == ",") {
      ++pos_;
      const Mask rhs = parseExpression();
      for (std::size_t i = 0; i < m.size(); ++i) m[i] = m[i] || rhs[i];
    }
    return m;
  }

  // MDAnalysis gives `and` and `or` one precedence: left to right.
  Mask parseExpression() {
    Mask m = parseUnary();
    expectOperatorOrEnd();
    while (pos_ < words_.size() && isOperator(words_[pos_].text)) {
      const bool isAnd = words_[pos_++].text == "and";
      const Mask rhs = parseUnary();
      for (std::size_t i = 0; i < m.size(); ++i) m[i] = isAnd ? (m[i] && rhs[i]) : (m[i] || rhs[i]);
      expectOperatorOrEnd();
    }
    return m;
  }

  Mask parseUnary() {
    if (pos_ == words_.size())
      failAtEnd("the selection ends after " + inQuotes(words_.back().text) +
                ": expected a term such as 'name CA' after it");
    const std::string& w = words_[pos_].text;
    if (w == "not") {
      ++pos_;
      Mask m = parseUnary();
      for (char& c : m) c = !c;
      return m;
    }
    if (w == "(") {
      const std::size_t open = pos_++;
      if (pos_ < words_.size() && words_[pos_].text == ")") fail(open, pos_, "the parentheses hold no term");
      Mask m = parseUnion();
      if (pos_ == words_.size()) fail(open, open, "is never closed: expected ')'");
      ++pos_;  // parseUnion stops only at ')' or the end
      return m;
    }
    if (isOperator(w) || isPunctuation(w))
      fail(pos_, pos_,
           pos_ == 0 ? "expected a term such as 'name CA' at the start"
                     : "expected a term such as 'name CA' after " + inQuotes(words_[pos_ - 1].text));
    if (const auto key = keywordOf(w)) return parseTerm(*key);
    if (inList(w, kOtherMdaKeywords))
      fail(pos_, pos_,
           inQuotes(w) + " is an MDAnalysis selection keyword that surftrace does not support; use " +
               std::string(kKeywordList));
    std::string hint;
    const std::string lower = lowerCase(w);
    for (const Keyword& k : kKeywords)
      if (lowerCase(k.word) == lower)
        hint = " (keywords are case-sensitive, as in MDAnalysis: " + inQuotes(k.word) + ")";
    if (lower == "and" || lower == "or" || lower == "not")
      hint = " (operators are lower case: " + inQuotes(lower) + ")";
    fail(pos_, pos_, "unknown keyword " + inQuotes(w) + hint + "; a term starts with " + std::string(kKeywordList));
  }

  // After a term or a parenthesis: `and`, `or`, ',', ')' or the end.
  void expectOperatorOrEnd() {
    if (pos_ == words_.size()) return;
    const std::string& w = words_[pos_].text;
    if (isOperator(w) || w == "," || w == ")") return;
    const std::string& before = words_[pos_ - 1].text;
    if (!endsValues(w))  // a word after a keyword that takes no values, or after ')'
      fail(pos_, pos_,
           "cannot follow " + inQuotes(before) + (keywordOf(before) ? ", which takes no values" : "") +
               ": expected 'and', 'or', ',' or the end");
    std::string why = "needs 'and' or 'or' before it";
    if (lastValues_.second == pos_ && lastValues_.second > lastValues_.first) {
      why += " (" + inQuotes(span(lastValues_.first, lastValues_.second - 1)) + " before it " +
             (lastValues_.second - lastValues_.first == 1 ? "was" : "were") + " read as values of " +
             inQuotes(words_[lastValues_.first - 1].text);
      for (std::size_t k = lastValues_.first; k < lastValues_.second; ++k) {
        const std::string lower = lowerCase(words_[k].text);
        if (lower == "and" || lower == "or" || lower == "not") {
          why += "; operators are lower case: " + inQuotes(lower);
          break;
        }
      }
      why += ")";
    }
    fail(pos_, pos_, why);
  }

  Mask parseTerm(Key key) {
    const std::size_t at = pos_++;
    const std::string& keyword = words_[at].text;
    Mask m(m_.size(), 0);
    const auto each = [&](auto&& keep) {
      for (std::size_t i = 0; i < m_.size(); ++i) m[i] = keep(m_.atoms[i]) ? 1 : 0;
    };
    // Tests each distinct name once, as MDAnalysis does with its name tables: a large system has
    // many atoms but few names. Atoms failing `test` are left out of m.
    const auto byName = [&](AtomString AtomRecord::*field, auto&& test) {
      std::unordered_map<std::string_view, char> seen;
      for (std::size_t i = 0; i < m_.size(); ++i) {
        const auto [it, fresh] = seen.try_emplace(m_.atoms[i].*field, 0);
        if (fresh) it->second = test(it->first) ? 1 : 0;
        m[i] = m[i] && it->second;
      }
    };
    if (key == Key::All || key == Key::Protein || key == Key::Backbone || key == Key::Water) {
      lastValues_ = {0, 0};
      each([](const AtomRecord&) { return true; });
      if (key == Key::Protein || key == Key::Backbone)
        byName(&AtomRecord::residue, [](std::string_view r) { return inList(r, kProteinResidues); });
      if (key == Key::Backbone) byName(&AtomRecord::name, [](std::string_view n) { return inList(n, kBackboneNames); });
      if (key == Key::Water) byName(&AtomRecord::residue, [](std::string_view r) { return inList(r, kWaterResidues); });
      return report(at, key, std::move(m));
    }

    const std::size_t first = pos_;
    while (pos_ < words_.size() && !endsValues(words_[pos_].text)) ++pos_;
    lastValues_ = {first, pos_};
    if (pos_ == first) {
      const char* example = key == Key::Resid     ? " 10-20"
                            : key == Key::Index   ? " 0-9"
                            : key == Key::Atom    ? " 1-250"
                            : key == Key::Name    ? " CA CB"
                            : key == Key::Resname ? " ALA GLY"
                            : key == Key::Element ? " C N"
                                                  : " A";
      fail(at, at, "needs values, e.g. " + inQuotes(keyword + example));
    }

    if (key == Key::Name || key == Key::Resname || key == Key::Chain || key == Key::Segid || key == Key::Element) {
      std::vector<std::string_view> patterns;
      for (std::size_t k = first; k < pos_; ++k) patterns.push_back(words_[k].text);
      AtomString AtomRecord::*field = key == Key::Name      ? &AtomRecord::name
                                       : key == Key::Resname ? &AtomRecord::residue
                                       : key == Key::Chain   ? &AtomRecord::chain
                                       : key == Key::Segid   ? &AtomRecord::segid
                                                             : &AtomRecord::element;
      each([](const AtomRecord&) { return true; });
      byName(field, [&](std::string_view v) {
        return std::any_of(patterns.begin(), patterns.end(), [v](std::string_view p) { return matchesPattern(p, v); });
      });
      return report(at, key, std::move(m));
    }

    std::vector<NumberRange> ranges;
    for (const auto& [from, to, value] : joinRanges(first, pos_)) {
      const auto r = parseNumberRange(value, key == Key::Resid);
      const char* what = key == Key::Resid   ? "a residue number or a range such as 10-20 or 10:20"
                         : key == Key::Index ? "an index (from 0) or a range such as 0-9"
                                             : "an atom number (from 1) or a range such as 1-250";
      if (!r) fail(from, to, inQuotes(value) + " is not " + std::string(what));
      if (r->lo > r->hi)
        fail(from, to,
             "the range " + value + " is empty (" + std::to_string(r->lo) + " > " + std::to_string(r->hi) + ")");
      if (key != Key::Resid) {
        const long long base = key == Key::Atom ? 1 : 0;
        const long long last = static_cast<long long>(fileAtoms_) - 1 + base;
        if (r->lo < base || r->hi > last)
          fail(from, to,
               keyword + " " + value + ": the topology has " + std::to_string(fileAtoms_) + " atoms (" + keyword + " " +
                   std::to_string(base) + " to " + std::to_string(last) + ")");
      }
      ranges.push_back(*r);
    }
    if (key == Key::Resid) {
      each([&](const AtomRecord& a) {
        const std::string code = a.insertionCode == ' ' ? std::string() : std::string(1, a.insertionCode);
        return std::any_of(ranges.begin(), ranges.end(),
                           [&](const NumberRange& r) { return residInRange(a.residueNumber, code, r); });
      });
    } else {
      const long long base = key == Key::Atom ? 1 : 0;
      each([&](const AtomRecord& a) {
        const long long v = static_cast<long long>(a.fileIndex) + base;
        return std::any_of(ranges.begin(), ranges.end(), [v](const NumberRange& r) { return v >= r.lo && v <= r.hi; });
      });
    }
    return report(at, key, std::move(m));
  }

  struct Joined {
    std::size_t from, to;  // words
    std::string value;
  };
  // MDAnalysis's join_separated_values: "10 - 20", "10 to 20", "10 :20" are one value.
  std::vector<Joined> joinRanges(std::size_t first, std::size_t end) const {
    std::vector<Joined> out;
    const auto endsWithDelimiter = [](std::string_view v) {
      return v.ends_with("to") || v.ends_with(":") || v.ends_with("-");
    };
    for (std::size_t k = first; k < end; ++k) {
      const std::string& v = words_[k].text;
      if (v == "to" || v == ":" || v == "-") {
        if (out.empty() || k + 1 == end) fail(k, k, "needs a number on each side");
        out.back().value += " " + v + " " + words_[k + 1].text;
        out.back().to = ++k;
      } else if (!out.empty() &&
                 (v.starts_with("--") || v.starts_with("to") || v[0] == ':' || endsWithDelimiter(out.back().value))) {
        out.back().value += " " + v;
        out.back().to = k;
      } else {
        out.push_back({k, k, v});
      }
    }
    return out;
  }

  Mask report(std::size_t at, Key key, Mask m) {
    TermReport r{span(at, pos_ - 1), key, static_cast<std::size_t>(std::count(m.begin(), m.end(), 1))};
    terms_.push_back(std::move(r));
    return m;
  }

  std::string span(std::size_t from, std::size_t to) const {
    const std::size_t begin = words_[from].offset;
    return selection_.substr(begin, words_[to].offset + words_[to].text.size() - begin);
  }

  std::string quoted() const { return "selection " + inQuotes(selection_); }

  // The selection with a caret under the columns [begin, end).
  std::string pointAt(std::size_t begin, std::size_t end) const {
    std::string shown = selection_;
    for (char& c : shown)
      if (isSpace(c)) c = ' ';
    return "\n  " + shown + "\n  " + std::string(begin, ' ') + std::string(std::max<std::size_t>(end - begin, 1), '^');
  }

  // Throws `what` about words [from, to]: the selection, which words, and a caret under them.
  [[noreturn]] void fail(std::size_t from, std::size_t to, const std::string& what) const {
    const std::string where = from == to ? "word " + std::to_string(from + 1)
                                         : "words " + std::to_string(from + 1) + "-" + std::to_string(to + 1);
    throw std::invalid_argument(quoted() + ": at " + where + " " + inQuotes(span(from, to)) + ": " + what +
                                pointAt(words_[from].offset, words_[to].offset + words_[to].text.size()));
  }

  [[noreturn]] void failAtEnd(const std::string& what) const {
    throw std::invalid_argument(quoted() + ": " + what + pointAt(selection_.size(), selection_.size() + 1));
  }

  std::string nothingSelected() const {
    std::vector<std::string> empty;
    std::set<std::string> seen;
    for (const TermReport& t : terms_)
      if (t.hits == 0 && seen.insert(t.text).second)
        empty.push_back(inQuotes(t.text) + " matches no atom (the molecule has " + present(m_, t.key) + ")");
    if (terms_.size() == 1 && terms_[0].hits == 0)
      return quoted() + " selects no atom (the molecule has " + present(m_, terms_[0].key) + ")";
    std::string out = quoted() + " selects no atom";
    if (!empty.empty()) {
      out += ": ";
      for (std::size_t k = 0; k < empty.size(); ++k) out += (k ? "; " : "") + empty[k];
      return out;
    }
    out += ", though each of its terms matches atoms (";
    for (std::size_t k = 0; k < terms_.size(); ++k)
      out += (k ? ", " : "") + inQuotes(terms_[k].text) + " " + std::to_string(terms_[k].hits);
    return out +
           "); check the 'not', 'and' and 'or' ('and' and 'or' are read left to right, as in MDAnalysis: "
           "group with parentheses)";
  }

  const Molecule& m_;
  const std::string& selection_;
  std::vector<Word> words_;
  std::size_t pos_ = 0;
  std::size_t fileAtoms_ = 0;
  std::pair<std::size_t, std::size_t> lastValues_{0, 0};  // words [first, end) of the last term's values
  std::vector<TermReport> terms_;
};

}  // namespace

std::vector<std::uint32_t> selectAtoms(const Molecule& molecule, const std::string& selection) {
  return Parser(molecule, selection).select();
}

}  // namespace surftrace::build

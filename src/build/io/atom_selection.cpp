// Atom selections (atom_selection.hpp).
#include "build/io/atom_selection.hpp"

#include "build/io/text_fields.hpp"

#include <algorithm>
#include <charconv>
#include <limits>
#include <set>
#include <sstream>
#include <stdexcept>
#include <string_view>

namespace surftrace::build {
namespace {

using text::trim;

std::vector<std::string> words(std::string_view term) {
  std::vector<std::string> out;
  std::istringstream in{std::string(term)};
  for (std::string w; in >> w;) out.push_back(w);
  return out;
}

std::optional<long long> wholeNumber(std::string_view text) {
  long long v = 0;
  const auto [end, ec] = std::from_chars(text.data(), text.data() + text.size(), v);
  if (ec != std::errc() || end != text.data() + text.size() || text.empty()) return std::nullopt;
  return v;
}

struct Range {
  long long lo, hi;
};

// "12", "10-20", "-5--2", "10:20".
Range parseRange(const std::string& value, const std::string& term) {
  if (auto v = wholeNumber(value)) return {*v, *v};
  for (std::size_t cut = 1; cut < value.size(); ++cut) {
    if (value[cut] != '-' && value[cut] != ':') continue;
    const auto lo = wholeNumber(std::string_view(value).substr(0, cut));
    const auto hi = wholeNumber(std::string_view(value).substr(cut + 1));
    if (lo && hi) {
      if (*lo > *hi) throw std::invalid_argument("selection '" + term + "': the range " + value + " is empty (" +
                                                 std::to_string(*lo) + " > " + std::to_string(*hi) + ")");
      return {*lo, *hi};
    }
  }
  throw std::invalid_argument("selection '" + term + "': '" + value +
                              "' is not a whole number or a range such as 10-20");
}

bool inRanges(long long v, const std::vector<Range>& ranges) {
  return std::any_of(ranges.begin(), ranges.end(), [v](const Range& r) { return v >= r.lo && v <= r.hi; });
}

// What the molecule holds for a keyword, to say so when a term selects nothing.
std::string present(const Molecule& m, const std::string& keyword) {
  if (keyword == "resid" || keyword == "atom" || keyword == "index") {
    long long lo = std::numeric_limits<long long>::max(), hi = std::numeric_limits<long long>::min();
    for (const AtomRecord& a : m.atoms) {
      const long long v = keyword == "resid" ? a.residueNumber : static_cast<long long>(a.fileIndex) + 1;
      lo = std::min(lo, v), hi = std::max(hi, v);
    }
    return (keyword == "resid" ? "residues " : "atoms ") + std::to_string(lo) + " to " + std::to_string(hi);
  }
  std::set<std::string> names;
  for (const AtomRecord& a : m.atoms) {
    names.insert(keyword == "chain" ? a.chain : keyword == "resname" ? a.residue : a.name);
    if (names.size() > 12) break;
  }
  std::string list;
  for (const std::string& n : names) list += (list.empty() ? "'" : ", '") + n + "'";
  return (keyword == "chain" ? "chains " : keyword == "resname" ? "residue names " : "atom names ") + list +
         (names.size() > 12 ? ", ..." : "");
}

}  // namespace

std::vector<std::uint32_t> selectAtoms(const Molecule& molecule, const std::string& selection) {
  if (trim(selection).empty()) throw std::invalid_argument("the atom selection is empty");
  std::vector<char> chosen(molecule.size(), 0);
  std::string_view rest = selection;
  while (true) {
    const std::size_t comma = rest.find(',');
    const std::string term(trim(rest.substr(0, comma)));
    const std::vector<std::string> w = words(term);
    if (w.size() < 2)
      throw std::invalid_argument("selection '" + term +
                                  "': expected a keyword (resid, chain, resname, name, atom) and values, e.g. "
                                  "'resid 10-20'");
    const std::string& keyword = w[0];
    const std::vector<std::string> values(w.begin() + 1, w.end());
    std::size_t hits = 0;
    if (keyword == "resid" || keyword == "atom" || keyword == "index") {
      std::vector<Range> ranges;
      for (const std::string& v : values) ranges.push_back(parseRange(v, term));
      for (std::size_t i = 0; i < molecule.size(); ++i) {
        const AtomRecord& a = molecule.atoms[i];
        const long long v = keyword == "resid" ? a.residueNumber : static_cast<long long>(a.fileIndex) + 1;
        if (inRanges(v, ranges)) chosen[i] = 1, ++hits;
      }
    } else if (keyword == "chain" || keyword == "segid" || keyword == "resname" || keyword == "name") {
      for (std::size_t i = 0; i < molecule.size(); ++i) {
        const AtomRecord& a = molecule.atoms[i];
        const std::string& field = (keyword == "chain" || keyword == "segid") ? a.chain
                                   : keyword == "resname"                   ? a.residue
                                                                            : a.name;
        if (std::find(values.begin(), values.end(), field) != values.end()) chosen[i] = 1, ++hits;
      }
    } else {
      throw std::invalid_argument("selection '" + term + "': unknown keyword '" + keyword +
                                  "'; use resid, chain, resname, name or atom");
    }
    if (hits == 0)
      throw std::invalid_argument("selection '" + term + "' selects no atom (the molecule has " +
                                  present(molecule, keyword == "segid" ? "chain" : keyword) + ")");
    if (comma == std::string_view::npos) break;
    rest.remove_prefix(comma + 1);
  }
  std::vector<std::uint32_t> out;
  for (std::size_t i = 0; i < chosen.size(); ++i)
    if (chosen[i]) out.push_back(static_cast<std::uint32_t>(i));
  return out;
}

}  // namespace surftrace::build

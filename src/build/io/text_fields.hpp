// Small pieces of text parsing that every text reader (molecule.cpp, topology_formats.cpp,
// text_trajectory.cpp, gemmi_impl.cpp, radii.cpp) shares: character classes, fields, whole
// numbers, residue numbers, quoting for messages.
#pragma once

#include <array>
#include <charconv>
#include <cstddef>
#include <filesystem>
#include <optional>
#include <string>
#include <string_view>
#include <vector>

namespace surftrace::build::text {

inline bool isSpace(char c) { return c == ' ' || c == '\t' || c == '\r' || c == '\n' || c == '\f' || c == '\v'; }
inline bool isAlpha(char c) { return (c >= 'a' && c <= 'z') || (c >= 'A' && c <= 'Z'); }
inline bool isDigit(char c) { return c >= '0' && c <= '9'; }
inline char upper(char c) { return (c >= 'a' && c <= 'z') ? static_cast<char>(c - 'a' + 'A') : c; }

inline std::string_view trim(std::string_view s) {
  while (!s.empty() && isSpace(s.front())) s.remove_prefix(1);
  while (!s.empty() && isSpace(s.back())) s.remove_suffix(1);
  return s;
}

// 'value', for error messages; a value longer than 80 characters (a 20 MB line) is cut to
// its first 72 with its length said. (Built by appending: GCC 12 gives a false -Wrestrict for
// "'" + std::string(s) + "'".)
inline std::string inQuotes(std::string_view s) {
  constexpr std::size_t kLongest = 80, kKept = 72;
  std::string out;
  if (s.size() <= kLongest) {
    out.reserve(s.size() + 2);
    out.append(1, '\'').append(s).append(1, '\'');
    return out;
  }
  out.append(1, '\'').append(s.substr(0, kKept)).append("...' (").append(std::to_string(s.size()));
  out.append(" characters)");
  return out;
}

// The whitespace-separated fields of a line.
inline std::vector<std::string_view> splitFields(std::string_view line) {
  std::vector<std::string_view> fields;
  std::size_t pos = 0;
  while (pos < line.size()) {
    while (pos < line.size() && isSpace(line[pos])) ++pos;
    const std::size_t start = pos;
    while (pos < line.size() && !isSpace(line[pos])) ++pos;
    if (pos > start) fields.push_back(line.substr(start, pos - start));
  }
  return fields;
}

// The first N whitespace-separated fields of a line into `fields`, without allocating (the
// XYZR reader calls it for every atom); returns how many fields the line has, N or more.
template <std::size_t N>
std::size_t splitFields(std::string_view line, std::array<std::string_view, N>& fields) {
  std::size_t count = 0;
  std::size_t pos = 0;
  while (pos < line.size()) {
    while (pos < line.size() && isSpace(line[pos])) ++pos;
    const std::size_t start = pos;
    while (pos < line.size() && !isSpace(line[pos])) ++pos;
    if (pos == start) break;
    if (count < N) fields[count] = line.substr(start, pos - start);
    ++count;
  }
  return count;
}

// A whole field as a number: "+1.5", ".721" and "0.9E-01" are numbers, "1.2.3", "+-1" and ""
// are not. (std::from_chars reads no '+', so one is skipped here, but not before a '-'.)
template <typename T>
std::optional<T> parseWhole(std::string_view text) {
  text = trim(text);
  T value{};
  const char* first = text.data();
  const char* last = text.data() + text.size();
  if (first != last && *first == '+' && ++first != last && *first == '-') return std::nullopt;
  const auto [ptr, ec] = std::from_chars(first, last, value);
  if (first == last || ec != std::errc() || ptr != last) return std::nullopt;
  return value;
}

// A residue number with an optional insertion code ("52A"), as PQR and PSF files write it.
inline bool parseResidueNumber(std::string_view text, int& number, char& icode) {
  icode = ' ';
  if (text.size() > 1 && isAlpha(text.back())) {
    icode = text.back();
    text.remove_suffix(1);
  }
  const std::optional<int> value = parseWhole<int>(text);
  if (!value) return false;
  number = *value;
  return true;
}

// The longest line a text input may hold, in bytes without its line end. No structure,
// topology or table format comes near it (a PDB line is 80 bytes, an mmCIF line rarely 200);
// a longer line is refused as it arrives, before the file is held whole.
inline constexpr std::size_t kMaxLineBytes = std::size_t{1} << 20;

// A text input's bytes as text (molecule.cpp): gunzipped when they start with the gzip magic
// (every member), refused when the name ends in .gz and they do not, refused when empty or
// binary (a control byte: InputError naming the line and offset), and refused at the first
// line longer than kMaxLineBytes (naming the line). Lines may end in "\n", "\r\n" or a lone
// "\r": a lone CR is made a "\n" in the text returned. `name` stands for the file.
std::string textOfBytes(std::string bytes, const std::string& name);
// The same for a whole file read from disk.
std::string readTextFile(const std::filesystem::path& path, const std::string& name);

}  // namespace surftrace::build::text

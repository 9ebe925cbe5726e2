// The short texts of an atom record (atom, residue, chain, segment names, element) in 8 bytes.
#pragma once

#include <cstddef>
#include <cstdint>
#include <cstring>
#include <ostream>
#include <string>
#include <string_view>
#include <utility>

namespace surftrace::build {

// A text of any length that stores up to 7 bytes in place and a longer one as the index of its
// copy in a process-wide table of long texts (each distinct text kept once, never freed). An
// atom record holds five of them: 8 bytes each where five std::strings took 160, the most of a
// record's size and, for a million atoms, of the memory and page faults of reading. Names of
// real files fit in place (PDB atom names 4, residue names 3-4, GRO 5, CCD ids 5, chains and
// segids 1-4); the longer ones mmCIF, PSF and GRO allow still read and print whole.
//
// It reads like a const std::string: converts implicitly to std::string_view and std::string,
// compares with either and with C strings, and has the accessors the readers and printers use.
// c_str() is NUL-terminated: the last byte holds 7 minus the length, so a 7-byte text ends in
// that byte's 0 (the layout of folly's fbstring).
class AtomString {
 public:
  static constexpr std::size_t kInline = 7;

  AtomString() { clearBytes(); }
  AtomString(std::string_view text) { assign(text); }
  AtomString(const char* text) { assign(std::string_view(text)); }
  AtomString(const std::string& text) { assign(std::string_view(text)); }

  std::string_view view() const {
    if (isLong()) return longText(longIndex());
    return {bytes_, kInline - static_cast<unsigned char>(bytes_[kInline])};
  }
  operator std::string_view() const { return view(); }
  operator std::string() const { return std::string(view()); }
  std::string str() const { return std::string(view()); }

  bool empty() const { return static_cast<unsigned char>(bytes_[kInline]) == kInline; }
  std::size_t size() const { return view().size(); }
  std::size_t length() const { return size(); }
  const char* data() const { return view().data(); }
  const char* c_str() const { return view().data(); }  // both kinds are NUL-terminated
  char operator[](std::size_t i) const { return view()[i]; }
  char front() const { return view().front(); }
  char back() const { return view().back(); }
  std::string_view::const_iterator begin() const { return view().begin(); }
  std::string_view::const_iterator end() const { return view().end(); }
  std::string substr(std::size_t pos, std::size_t count = std::string::npos) const {
    return std::string(view().substr(pos, count));
  }
  void clear() { clearBytes(); }

  // Comparisons with each text type in both orders, written out rather than by operator<=>:
  // gemmi_impl.cpp, which includes this header, is compiled as C++17 in the fuzzing build.
#define SURFTRACE_ATOM_STRING_COMPARE(OP)                                                                    \
  friend bool operator OP(const AtomString& a, const AtomString& b) { return a.view() OP b.view(); }          \
  friend bool operator OP(const AtomString& a, std::string_view b) { return a.view() OP b; }                  \
  friend bool operator OP(std::string_view a, const AtomString& b) { return a OP b.view(); }                  \
  friend bool operator OP(const AtomString& a, const std::string& b) { return a.view() OP std::string_view(b); } \
  friend bool operator OP(const std::string& a, const AtomString& b) { return std::string_view(a) OP b.view(); } \
  friend bool operator OP(const AtomString& a, const char* b) { return a.view() OP std::string_view(b); }      \
  friend bool operator OP(const char* a, const AtomString& b) { return std::string_view(a) OP b.view(); }
  SURFTRACE_ATOM_STRING_COMPARE(==)
  SURFTRACE_ATOM_STRING_COMPARE(!=)
  SURFTRACE_ATOM_STRING_COMPARE(<)
  SURFTRACE_ATOM_STRING_COMPARE(>)
  SURFTRACE_ATOM_STRING_COMPARE(<=)
  SURFTRACE_ATOM_STRING_COMPARE(>=)
#undef SURFTRACE_ATOM_STRING_COMPARE

  friend std::string operator+(const std::string& a, const AtomString& b) { return a + std::string(b.view()); }
  friend std::string operator+(std::string&& a, const AtomString& b) { return std::move(a.append(b.view())); }
  friend std::string operator+(const char* a, const AtomString& b) { return std::string(a).append(b.view()); }
  friend std::string operator+(const AtomString& a, const std::string& b) { return std::string(a.view()) + b; }
  friend std::string operator+(const AtomString& a, const char* b) { return std::string(a.view()) + b; }
  friend std::string operator+(const AtomString& a, char b) { return std::string(a.view()) + b; }
  friend std::string operator+(const AtomString& a, const AtomString& b) {
    return std::string(a.view()).append(b.view());
  }
  friend std::ostream& operator<<(std::ostream& out, const AtomString& s) { return out << s.view(); }

 private:
  static constexpr unsigned char kLongMark = 0xFF;

  bool isLong() const { return static_cast<unsigned char>(bytes_[kInline]) == kLongMark; }
  std::uint32_t longIndex() const {
    std::uint32_t index;
    std::memcpy(&index, bytes_, sizeof index);
    return index;
  }
  void clearBytes() {
    std::memset(bytes_, 0, kInline);
    bytes_[kInline] = static_cast<char>(kInline);
  }
  void assign(std::string_view text) {
    if (text.size() <= kInline) {
      std::memset(bytes_, 0, kInline);
      if (!text.empty()) std::memcpy(bytes_, text.data(), text.size());
      bytes_[kInline] = static_cast<char>(kInline - text.size());
    } else {
      const std::uint32_t index = internLong(text);
      std::memset(bytes_, 0, kInline);
      std::memcpy(bytes_, &index, sizeof index);
      bytes_[kInline] = static_cast<char>(kLongMark);
    }
  }
  // The table of long texts (atom_string.cpp): interning takes a lock, reading does not (a
  // text's storage never moves once written).
  static std::uint32_t internLong(std::string_view text);
  static std::string_view longText(std::uint32_t index);

  char bytes_[kInline + 1];
};

static_assert(sizeof(AtomString) == 8);

}  // namespace surftrace::build

namespace std {
template <>
struct hash<surftrace::build::AtomString> {
  std::size_t operator()(const surftrace::build::AtomString& s) const noexcept {
    return std::hash<std::string_view>()(s.view());
  }
};
}  // namespace std

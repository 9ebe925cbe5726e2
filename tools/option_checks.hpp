// Checks of numeric options whose messages a user can read: CLI11's own range checks print
// the limits of double in full (300 digits) and "0.000000" for an open bound.
#pragma once

#include <cerrno>
#include <cstdio>
#include <cmath>
#include <cstdlib>
#include <cctype>
#include <string>
#include <utility>
#include <vector>

#include <CLI/CLI.hpp>

namespace surftrace::tools {

namespace detail {
// %g-style text of a bound: "1024", "0.5", "1e+06".
inline std::string shortNumber(double v) {
  char text[32];
  std::snprintf(text, sizeof text, "%g", v);
  return text;
}

// "" when `text` is a whole finite number in [lo, hi] (lo excluded when `openLow`), else a
// message that says what is expected and repeats what was given.
inline std::string checkNumber(const std::string& text, double lo, double hi, bool openLow,
                               bool integer) {
  const char* kind = integer ? "a whole number" : "a number";
  std::string range;
  if (std::isinf(hi))
    range = std::string(openLow ? "> " : ">= ") + shortNumber(lo);
  else
    range = std::string("in ") + (openLow ? "(" : "[") + shortNumber(lo) + ", " + shortNumber(hi) + "]";
  const std::string expected = std::string("expected ") + kind + " " + range + ", got '" + text + "'";
  errno = 0;
  char* end = nullptr;
  const double v = std::strtod(text.c_str(), &end);
  if (text.empty() || end != text.c_str() + text.size()) return expected;
  if (errno == ERANGE)
    return expected + (std::abs(v) < 1.0 ? " (below 2.2e-308, the smallest normal double)" : " (beyond double's range)");
  if (!std::isfinite(v)) return expected + " (not finite)";
  if (integer && v != std::floor(v)) return expected;
  if (v < lo || (openLow && v == lo) || v > hi) return expected;
  return {};
}
}  // namespace detail

// A finite number > 0 (a radius, a distance).
inline CLI::Validator positive() {
  return CLI::Validator(
      [](std::string& text) { return detail::checkNumber(text, 0.0, HUGE_VAL, true, false); }, "NUMBER > 0",
      "positive");
}

// A whole number in [lo, hi] (a count, a model number); hi may be HUGE_VAL.
inline CLI::Validator wholeIn(double lo, double hi) {
  return CLI::Validator([lo, hi](std::string& text) { return detail::checkNumber(text, lo, hi, false, true); },
                        "INTEGER", "whole number");
}

// A finite number in [lo, hi] (a fraction); hi may be HUGE_VAL.
inline CLI::Validator numberIn(double lo, double hi) {
  return CLI::Validator([lo, hi](std::string& text) { return detail::checkNumber(text, lo, hi, false, false); },
                        "NUMBER", "number");
}

// One of a few names, in any letter case, standing for values of an enum: the help shows the
// names alone ("auto|pdb|mmcif"), a wrong name is answered with the names it could have been.
// (CLI11's CheckedTransformer prints its map, "{auto->0,pdb->1} OR {0,1}".)
template <typename Enum>
CLI::Validator namedValue(std::vector<std::pair<std::string, Enum>> names) {
  std::string list;
  for (const auto& [name, value] : names) list += (list.empty() ? "" : "|") + name;
  return CLI::Validator(
      [names, list](std::string& text) -> std::string {
        std::string lower = text;
        for (char& c : lower) c = static_cast<char>(std::tolower(static_cast<unsigned char>(c)));
        for (const auto& [name, value] : names)
          if (name == lower) {
            text = std::to_string(static_cast<long long>(value));
            return {};
          }
        std::string expected = "expected one of ";
        for (std::size_t i = 0; i < names.size(); ++i)
          expected += (i ? ", " : "") + names[i].first;
        return expected + "; got '" + text + "'";
      },
      list, "named value");
}

}  // namespace surftrace::tools

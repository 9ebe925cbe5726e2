// Colour maps as matplotlib reads them (color_map.hpp).
#include "view/color_map.hpp"

#include <algorithm>
#include <cmath>
#include <stdexcept>

#include "view/color_map_tables.hpp"

namespace surftrace::view {
namespace {

constexpr int kEntries = 256;
using Lut = std::array<std::array<double, 3>, kEntries>;

// matplotlib.colors._create_lookup_table for a continuous piecewise-linear map (coolwarm): the
// 256 samples at x = i/255 of the polyline through the control points.
Lut interpolated(const std::array<std::array<double, 4>, 33>& points) {
  Lut lut{};
  const double last = kEntries - 1;
  for (int i = 0; i < kEntries; ++i) {
    const double x = last * (static_cast<double>(i) / last);
    std::size_t k = 1;
    while (k + 1 < points.size() && points[k][0] * last < x) ++k;
    const double x0 = points[k - 1][0] * last, x1 = points[k][0] * last;
    const double w = (x - x0) / (x1 - x0);
    for (int c = 0; c < 3; ++c)
      lut[i][c] = std::clamp(w * (points[k][c + 1] - points[k - 1][c + 1]) + points[k - 1][c + 1], 0.0, 1.0);
  }
  lut.front() = {points.front()[1], points.front()[2], points.front()[3]};
  lut.back() = {points.back()[1], points.back()[2], points.back()[3]};
  return lut;
}

// matplotlib's `rainbow`: gnuplot's formulas 33 (|2x − 0.5|), 13 (sin πx) and 10 (cos πx/2),
// sampled at x = i/255 and clipped to [0, 1].
Lut rainbow() {
  Lut lut{};
  constexpr double kPi = 3.141592653589793;
  for (int i = 0; i < kEntries; ++i) {
    const double x = static_cast<double>(i) / (kEntries - 1);
    lut[i] = {std::clamp(std::abs(2.0 * x - 0.5), 0.0, 1.0), std::clamp(std::sin(x * kPi), 0.0, 1.0),
              std::clamp(std::cos(x * kPi / 2.0), 0.0, 1.0)};
  }
  return lut;
}

}  // namespace

const ColorMap& ColorMap::named(const std::string& name) {
  static const ColorMap maps[] = {{"viridis", kViridisTable},
                                  {"magma", kMagmaTable},
                                  {"cividis", kCividisTable},
                                  {"coolwarm", interpolated(kCoolwarmPoints)},
                                  {"rainbow", rainbow()}};
  for (const ColorMap& m : maps)
    if (m.name_ == name) return m;
  std::string known;
  for (const ColorMap& m : maps) known += (known.empty() ? "" : ", ") + m.name_;
  throw std::invalid_argument("unknown colour map '" + name + "': use one of " + known);
}

std::vector<std::string> ColorMap::names() { return {"viridis", "magma", "cividis", "coolwarm", "rainbow"}; }

glm::vec3 ColorMap::at(double t) const {
  // matplotlib: x·N truncated towards zero, N itself (t = 1) the last entry, out of range
  // clipped to the ends (its default under and over colours); NaN has no colour here.
  const double x = t * kEntries;
  const int i = !(x > 0.0) ? 0 : x >= kEntries ? kEntries - 1 : static_cast<int>(x);
  return glm::vec3(static_cast<float>(lut_[i][0]), static_cast<float>(lut_[i][1]), static_cast<float>(lut_[i][2]));
}

}  // namespace surftrace::view

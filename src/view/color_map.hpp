// Colour maps: a number in [0, 1] to a colour, as matplotlib's colormaps give it.
#pragma once

#include <array>
#include <string>
#include <vector>

#include <glm/vec3.hpp>

namespace surftrace::view {

// A 256-entry lookup table read as matplotlib's Colormap.__call__ reads its own: t in [0, 1]
// takes entry floor(256 t) (t = 1 the last), values outside [0, 1] the end entries. The
// tables are the published ones (viridis, magma, cividis), coolwarm's 33 control points
// interpolated to 256 entries as matplotlib's LinearSegmentedColormap does, and `rainbow`
// sampled from gnuplot's formulas (33, 13, 10) as matplotlib's `rainbow` is; so a colour
// equals matplotlib.colormaps[name](t) to float precision (tests/view/color_map_test.cpp).
// Those are sRGB colours: whoever draws one decodes it first (view/srgb.hpp).
class ColorMap {
 public:
  // viridis, magma, cividis, coolwarm, rainbow; std::invalid_argument naming the others.
  static const ColorMap& named(const std::string& name);
  static std::vector<std::string> names();

  const std::string& name() const { return name_; }
  glm::vec3 at(double t) const;

 private:
  ColorMap(std::string name, const std::array<std::array<double, 3>, 256>& lut) : name_(std::move(name)), lut_(lut) {}
  std::string name_;
  std::array<std::array<double, 3>, 256> lut_;
};

}  // namespace surftrace::view

// The published data behind the colour maps (color_map_tables.cpp, generated): for color_map.cpp only.
#pragma once

#include <array>

namespace surftrace::view {

extern const std::array<std::array<double, 3>, 256> kViridisTable;
extern const std::array<std::array<double, 3>, 256> kMagmaTable;
extern const std::array<std::array<double, 3>, 256> kCividisTable;
extern const std::array<std::array<double, 4>, 33> kCoolwarmPoints;  // x, red, green, blue

}  // namespace surftrace::view

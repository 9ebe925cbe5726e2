// matplotlib's colours (tests/oracles/mpl_colormap.py) as a test oracle for the colour maps.
#pragma once

#include <filesystem>
#include <fstream>
#include <sstream>
#include <string>
#include <vector>

#include <glm/vec3.hpp>
#include <gtest/gtest.h>

#include "oracles/python_oracle.hpp"

namespace surftrace::test {

// matplotlib's colour of each number of `t` under `map` (its file of numbers is written in `dir`).
inline std::vector<glm::dvec3> matplotlibColors(const std::string& map, const std::vector<double>& t,
                                                const std::filesystem::path& dir) {
  const std::string file = (dir / (map + "_t.txt")).string();
  {
    std::ofstream out(file);
    out.precision(17);
    for (double x : t) out << x << "\n";
  }
  const auto run = runOracleScript("mpl_colormap.py", {map, file}, dir);
  EXPECT_TRUE(run.ok()) << run.describe();
  std::vector<glm::dvec3> colors;
  std::istringstream in(run.out);
  glm::dvec3 c;
  while (in >> c.r >> c.g >> c.b) colors.push_back(c);
  EXPECT_EQ(colors.size(), t.size());
  return colors;
}

}  // namespace surftrace::test

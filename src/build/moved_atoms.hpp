// The atoms of a new frame whose centre differs from the last, for builders' partial updates.
#pragma once

#include <cstdint>
#include <cstring>
#include <span>
#include <vector>

#include <glm/vec3.hpp>

namespace surftrace::build {

// Appends to `moved` every i whose centre differs in any bit between `last` and `next` (which
// have the same length), and its new centre to `places`.
inline void movedAtoms(std::span<const glm::dvec3> last, std::span<const glm::dvec3> next,
                       std::vector<std::uint32_t>& moved, std::vector<glm::dvec3>& places) {
  for (std::size_t i = 0; i < next.size(); ++i) {
    if (std::memcmp(&next[i], &last[i], sizeof(glm::dvec3)) != 0) {
      moved.push_back(static_cast<std::uint32_t>(i));
      places.push_back(next[i]);
    }
  }
}

}  // namespace surftrace::build

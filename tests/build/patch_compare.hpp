// Two patch lists compared array by array, bit for bit, through the patch list's own field
// list (build::forEachArray), so a field added to the patch list is compared too.
#pragma once

#include <cstring>
#include <string>
#include <vector>

#include <gtest/gtest.h>

#include "build/patch_list.hpp"

namespace surftrace::build::test {

// Reports the first differing element of an array.
template <class T>
void expectSameArray(const std::vector<T>& got, const std::vector<T>& want, const std::string& name,
                     const std::string& where) {
  ASSERT_EQ(got.size(), want.size()) << name << " (" << where << ")";
  for (std::size_t i = 0; i < got.size(); ++i) {
    if (std::memcmp(&got[i], &want[i], sizeof(T)) != 0) {
      ADD_FAILURE() << name << "[" << i << "] of " << got.size() << " differs (" << where << ")";
      return;
    }
  }
}

inline void expectSamePatchLists(const PatchList& got, const PatchList& want, const std::string& where) {
  EXPECT_EQ(got.params.surface, want.params.surface) << where;
  EXPECT_EQ(got.params.probeRadius, want.params.probeRadius) << where;
  EXPECT_EQ(got.params.shrinkFactor, want.params.shrinkFactor) << where;
  EXPECT_EQ(got.params.atomCount, want.params.atomCount) << where;
  EXPECT_EQ(got.componentCount, want.componentCount) << where;
  forEachArray([&](const char* group, const char* name, const auto& a, const auto& b) {
    expectSameArray(a, b, std::string(group) + "." + name, where);
  }, got, want);
}

}  // namespace surftrace::build::test

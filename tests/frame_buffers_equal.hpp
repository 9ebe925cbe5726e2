// Two renderings compared buffer by buffer, for the tests that hold one way of drawing a frame
// to another (a trajectory frame against a `render` of it, a kept renderer against a fresh one).
#pragma once

#include <cstring>
#include <string>
#include <vector>

#include <gtest/gtest.h>

#include "view/frame_buffers.hpp"

namespace surftrace::test {

// Bytes equal, so that NaNs and signed zeros compare too.
template <class T> bool sameBytes(const std::vector<T>& a, const std::vector<T>& b) {
  return a.size() == b.size() && (a.empty() || std::memcmp(a.data(), b.data(), a.size() * sizeof(T)) == 0);
}

// The buffers every engine fills (colour, ray depth, normal, patch kind, patch id, atom id),
// equal value for value.
inline void expectSameBuffers(const view::FrameBuffers& a, const view::FrameBuffers& b, const std::string& what) {
  ASSERT_EQ(a.width, b.width) << what;
  ASSERT_EQ(a.height, b.height) << what;
  EXPECT_TRUE(a.rgba == b.rgba) << what << ": colour differs";
  EXPECT_TRUE(a.depth == b.depth) << what << ": depth differs";
  EXPECT_TRUE(a.normal == b.normal) << what << ": normal differs";
  EXPECT_TRUE(a.kind == b.kind) << what << ": patch kind differs";
  EXPECT_TRUE(a.patchId == b.patchId) << what << ": patch id differs";
  EXPECT_TRUE(a.atomId == b.atomId) << what << ": atom id differs";
}

}  // namespace surftrace::test

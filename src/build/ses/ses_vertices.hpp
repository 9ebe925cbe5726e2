// SES vertex pass: probe positions, their validity, and cospherical vertices merged into concave polygons.
#pragma once

#include <cstdint>
#include <span>

#include "build/ses/ses_types.hpp"

namespace surftrace::build::detail {

// The vertex pass of owner x (row: x's grid neighbours): x's concave patches and free
// circles into out (with one concaveCount and freeCount entry), its cap state into capState.
void vertexPass(const Atoms& a, std::uint32_t x, std::span<const std::uint32_t> row, Scratch& s, VertexBuf& out,
                CapState& capState);

}  // namespace surftrace::build::detail

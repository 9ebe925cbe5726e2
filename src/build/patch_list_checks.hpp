// The field checks behind PatchList::validate(), for the .stp reader too: it checks a file's
// parameters, simplices and plane ranges before it derives the skin from them, then the whole
// list. Each throws std::runtime_error naming the field, its index and value.
#pragma once

#include <cstddef>
#include <cstdint>
#include <string>
#include <vector>

#include <glm/vec3.hpp>
#include <glm/vec4.hpp>

#include "build/patch_list.hpp"

namespace surftrace::build::list_checks {

// Lengths and coordinates: the largest structures span ~1e4 Å and the SES builder takes probes up
// to 2^19 times the smallest radius (~1e6 Å); 1e9 Å is far beyond both, and keeps squares and
// cubes (areas, volumes, quadric coefficients) finite in double and in the renderers' floats.
inline constexpr double kMaxLength = 1e9;

bool finite(double v);
bool finite(const glm::dvec3& v);
bool finite(const glm::dvec4& v);
// Every coordinate within kMaxLength.
bool inCube(const glm::dvec3& v);
// The shortest of 15 to 17 digits that reads back as the same double: "1.4", not "1.3999999999999999".
std::string text(double v);
std::string text(std::uint32_t v);
std::string text(const glm::dvec3& v);
std::string text(const glm::dvec4& v);
std::string text(const glm::uvec4& v);

// Each run [begin, begin + count) within `limit` planes.
void checkRange(const std::vector<std::uint32_t>& begin, const std::vector<std::uint32_t>& count, std::size_t limit,
                const char* group, const char* beginName, const char* countName, const char* planes);
// The surface kind, probe radius and shrink factor, and the kinds of patch the surface has.
void checkParams(const PatchList& p);
// The skin's kinds (grouped, in order) and simplices.
void checkSimplices(const MssQuadrics& q, std::uint32_t atomCount);
// Every field (PatchList::validate() without its "patch list: " prefix).
void checkList(const PatchList& p);

}  // namespace surftrace::build::list_checks

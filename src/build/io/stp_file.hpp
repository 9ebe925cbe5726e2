// The patch list's file (.stp): what `surftrace build` writes and every command reads.
#pragma once

#include <cstdint>
#include <span>
#include <string>
#include <vector>

#include <glm/vec3.hpp>

#include "build/patch_list.hpp"

namespace surftrace::build {

// Binary patch-list file (.stp). Layout, all little-endian:
//   magic "SURFTRCE" | u32 version | u32 endian tag 0x01020304 | u64 body size |
//   body (parameters, then a table of named arrays) | u32 CRC-32 of the body.
// Readers reject a wrong magic, a newer version, a truncated file or a bad checksum with
// an error that says which, and a list that fails validate() behind a good checksum with one
// that names the field, its index and value ("FILE: corrupt patch list: tori.axis[17] = ...").
// Version 2: every array of forEachArray as it is (cellPlanes.atom excepted; read as ~0u).
// Version 3 (written now): the SES arrays as in version 2; the skin's patches by reference.
// Given the atoms (centres and radii of the list's atoms, the builder's input), the writer
// stores their weighted points once, and per patch its simplex and plane count, per plane the
// atom across it; the reader derives the quadrics and planes from them with the builder's own
// functions (mss::skinPatch, mss::cellPlane), so a built list comes back bit for bit in a
// sixth of version 2's bytes (1AON's skin at s = 0.5: 30 MB, was 191 MB). A patch or plane
// whose derivation does not give back its stored bits (a list not made by the builder, or no
// atoms given) is stored whole. The atoms, when not given, are the list's own skinAtoms, and
// the reader gives them back there (a version 2 file: none). Version 1 lists are refused with
// advice.
inline constexpr std::uint32_t kPatchFileVersion = 3;
// The most atoms a list may speak of for each byte of its body. Nothing in the file but
// params.atomCount says how many atoms there were (those inside another ball, merged or
// buried have no patch), yet `render`, `area` and `info` size per-atom arrays by it: a forged
// count of 10^8 in a 160 KB file allocated gigabytes. Lists of real structures hold hundreds
// of bytes an atom (1AON's SES: 530); a list past the bound is refused by the reader as
// damaged, and by the writer, which names the count (an input of near-copies, nearly all left
// out of the surface, can make one).
inline constexpr std::uint64_t kMaxAtomsPerByte = 16;
// The atoms a list was built from, input indices as in the list (what `surftrace build` read).
struct PatchListAtoms {
  std::span<const glm::dvec3> centers;
  std::span<const double> radii;
};
void writePatchList(const std::string& path, const PatchList& patches, const PatchListAtoms& atoms = {});
// The file's bytes, as writePatchList writes them; `version` 2 writes the older layout (tests).
std::vector<unsigned char> encodePatchList(const PatchList& patches, const PatchListAtoms& atoms = {},
                                           std::uint32_t version = kPatchFileVersion);
PatchList readPatchList(const std::string& path);
// The same from the file's bytes; `path` names them in errors.
PatchList parsePatchList(std::span<const unsigned char> bytes, const std::string& path);
// Whether the file starts with the magic "SURFTRCE" (false when it cannot be read).
bool isPatchListFile(const std::string& path);

}  // namespace surftrace::build

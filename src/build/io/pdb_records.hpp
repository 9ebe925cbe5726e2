// PDB record names as gemmi reads them, for the code that reads PDB lines beside gemmi (the
// checks before it in gemmi_impl.cpp, the frame index of text_trajectory.cpp), so that each
// line is the same record to all of them.
#pragma once

#include <string_view>

#include "build/io/text_fields.hpp"

namespace surftrace::build::pdb {

// The line starts with `name` (upper case), in any case: "MODEL", "ENDMDL", "CRYST1".
inline bool recordIs(std::string_view line, std::string_view name) {
  if (line.size() < name.size()) return false;
  for (std::size_t i = 0; i < name.size(); ++i)
    if (text::upper(line[i]) != name[i]) return false;
  return true;
}

// ATOM and HETATM records as gemmi's is_record_type tells them: the first four characters,
// any case.
inline bool isAtomRecord(std::string_view line) {
  return recordIs(line, "ATOM") || recordIs(line, "HETA");
}

// END, but not ENDMDL: as gemmi's is_record_type3 reads it, "END" then the end of the line or
// a byte whose bits 0xD0 are clear (space, tab, CR, '!' to '/'). gemmi stops reading there.
inline bool isEndRecord(std::string_view line) {
  if (!recordIs(line, "END")) return false;
  return line.size() == 3 || (static_cast<unsigned char>(line[3]) & 0xD0) == 0;
}

}  // namespace surftrace::build::pdb

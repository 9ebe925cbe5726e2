// What a file's name says about its format: the one table of extensions behind readMolecule,
// openTrajectory and the text trajectory reader.
#pragma once

#include <filesystem>
#include <optional>
#include <string>
#include <string_view>

#include "build/io/molecule.hpp"
#include "build/io/trajectory.hpp"

namespace surftrace::build {

// The extension that names a file's format: the name's last extension, lower case and
// without its dot, once a final ".gz" is dropped ("1ABC.pdb.gz" -> "pdb"); "" when the name
// has none.
std::string formatExtension(const std::filesystem::path& path);

// Whether the file's name ends in ".gz", in any case, after something (".gz" alone does not).
bool hasGzipExtension(const std::filesystem::path& path);

// The formats an extension (as formatExtension gives it) stands for: as a structure or
// topology (readMolecule), and as a trajectory (openTrajectory); none where it names none.
struct ExtensionFormats {
  std::optional<MoleculeFormat> molecule;
  std::optional<TrajectoryFormat> trajectory;
};
ExtensionFormats formatsOfExtension(std::string_view extension);

}  // namespace surftrace::build

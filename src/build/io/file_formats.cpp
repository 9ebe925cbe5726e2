// The table of file name extensions and the formats they stand for.
#include "build/io/file_formats.hpp"

#include <algorithm>
#include <cctype>

namespace surftrace::build {

namespace {

std::string lowerCaseName(const std::filesystem::path& path) {
  std::string file = path.filename().string();
  for (char& c : file) c = static_cast<char>(std::tolower(static_cast<unsigned char>(c)));
  return file;
}

bool endsInGz(const std::string& lowerName) {
  return lowerName.size() > 3 && lowerName.compare(lowerName.size() - 3, 3, ".gz") == 0;
}

struct ExtensionRow {
  std::string_view extension;
  ExtensionFormats formats;
};

using M = MoleculeFormat;
using T = TrajectoryFormat;
constexpr std::nullopt_t kNone = std::nullopt;

// Text formats are read gzipped too; DCD and XTC are trajectories only, PQR, XYZR and PSF
// structures (or topologies) only.
constexpr ExtensionRow kExtensions[] = {
    {"pdb", {M::Pdb, T::Pdb}},     {"ent", {M::Pdb, T::Pdb}},   {"brk", {M::Pdb, kNone}},
    {"cif", {M::Mmcif, T::Mmcif}}, {"mmcif", {M::Mmcif, T::Mmcif}}, {"mcif", {M::Mmcif, kNone}},
    {"pqr", {M::Pqr, kNone}},      {"xyzr", {M::Xyzr, kNone}},  {"xyzrn", {M::Xyzr, kNone}},
    {"xyz", {M::Xyz, T::Xyz}},     {"gro", {M::Gro, T::Gro}},   {"psf", {M::Psf, kNone}},
    {"dcd", {kNone, T::Dcd}},      {"xtc", {kNone, T::Xtc}},
};

// Biological assemblies: .pdb1, .pdb2, ...
bool isAssemblyExtension(std::string_view extension) {
  return extension.size() > 3 && extension.substr(0, 3) == "pdb" &&
         std::all_of(extension.begin() + 3, extension.end(), [](char c) { return c >= '0' && c <= '9'; });
}

}  // namespace

std::string formatExtension(const std::filesystem::path& path) {
  std::string file = lowerCaseName(path);
  if (endsInGz(file)) file.resize(file.size() - 3);
  const std::size_t dot = file.rfind('.');
  return dot == std::string::npos ? std::string() : file.substr(dot + 1);
}

bool hasGzipExtension(const std::filesystem::path& path) { return endsInGz(lowerCaseName(path)); }

ExtensionFormats formatsOfExtension(std::string_view extension) {
  for (const ExtensionRow& row : kExtensions)
    if (row.extension == extension) return row.formats;
  if (isAssemblyExtension(extension)) return {M::Pdb, kNone};
  return {};
}

}  // namespace surftrace::build

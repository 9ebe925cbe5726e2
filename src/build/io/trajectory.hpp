// Trajectories: the coordinates of a molecule frame after frame, one reader per file format
// behind one interface (FrameSource), and the binding of a topology's selected atoms to them
// (Trajectory). Every reader gives random access to frame k without decoding the frames
// before it: DCD by its fixed frame size, XTC, GRO, XYZ and multi-model PDB/mmCIF by an index
// of frame offsets built once when the file is opened (kept in memory, written nowhere).
#pragma once

#include <array>
#include <cstddef>
#include <filesystem>
#include <memory>
#include <optional>
#include <string>
#include <vector>

#include <glm/vec3.hpp>

#include "build/io/molecule.hpp"

namespace surftrace::build {

// One frame: every atom of the trajectory file, in file order, in Å.
struct Frame {
  std::vector<glm::dvec3> positions;
  // ps: as stored (XTC, GRO titles with "t="), from the header's step and time step (DCD, as
  // MDAnalysis computes it); else the frame index.
  double time = 0.0;
  long long step = 0;  // MD step where stored (XTC, DCD start + k * interval); else the index
  // Unit cell a, b, c (Å) and alpha, beta, gamma (degrees) where the file stores one.
  std::optional<std::array<double, 6>> cell;
};

enum class TrajectoryFormat { Auto, Dcd, Xtc, Gro, Xyz, Pdb, Mmcif };

// Tells the format from the extension (".dcd", ".xtc", ".gro", ".xyz", ".pdb", ".ent",
// ".cif", ".mmcif"; ".gz" allowed for the text formats). InputError naming the choices otherwise.
TrajectoryFormat trajectoryFormatFromPath(const std::filesystem::path& path);
const char* trajectoryFormatName(TrajectoryFormat format);

// The frames of one trajectory file. Not thread-safe: one reader per thread.
class FrameSource {
 public:
  virtual ~FrameSource() = default;
  virtual std::size_t atomCount() const = 0;
  virtual std::size_t frameCount() const = 0;
  // Reads frame `index` (0-based, < frameCount()) into `frame`, reusing its memory. Throws
  // InputError naming the file, the frame (from 0, as `index`) and what is wrong: a
  // truncated frame, a non-finite coordinate, a corrupt compressed block. Earlier frames stay
  // readable after a later one failed.
  virtual void read(std::size_t index, Frame& frame) = 0;
  // What the reader noticed while opening (a header frame count that disagrees with the file
  // size, a truncated last frame left out); shown by `surftrace trajectory` and `info`.
  const std::vector<std::string>& notes() const { return notes_; }
  const std::string& path() const { return path_; }

 protected:
  explicit FrameSource(std::string path) : path_(std::move(path)) {}
  std::vector<std::string> notes_;

 private:
  std::string path_;
};

// Opens a trajectory file; InputError naming the file and what is wrong if it cannot be read.
std::unique_ptr<FrameSource> openTrajectory(const std::filesystem::path& path,
                                            TrajectoryFormat format = TrajectoryFormat::Auto);

// Readers, one per format (each in its own file; openTrajectory picks one).
std::unique_ptr<FrameSource> openDcd(const std::filesystem::path& path);
std::unique_ptr<FrameSource> openXtc(const std::filesystem::path& path);
// GRO and XYZ frames one after another, and PDB/mmCIF models (gemmi), from text files
// (gzipped or not).
std::unique_ptr<FrameSource> openTextTrajectory(const std::filesystem::path& path, TrajectoryFormat format);

// A molecule that moves: the topology's selected atoms (Molecule, with radii and records) and
// the trajectory file's atom of each (the topology's atom order is the trajectory's).
class Trajectory {
 public:
  // Reads the topology (PDB, mmCIF, GRO, PSF, or anything readMolecule takes) with `options`
  // (water, hydrogens, chains and radii select atoms as for a structure), and opens the
  // trajectory. InputError if the topology's atom count (before selection) differs from the
  // trajectory's, naming both files and both counts. A PSF has no coordinates: the molecule's
  // centres are those of frame 0 until load() is called.
  Trajectory(const std::filesystem::path& topology, const std::filesystem::path& trajectory,
             const ReadOptions& options = {});

  std::size_t frameCount() const { return frames_->frameCount(); }
  // The selected atoms, their radii and records; centres of the frame last loaded.
  const Molecule& molecule() const { return molecule_; }
  // For each selected atom, its index in the trajectory file.
  const std::vector<std::size_t>& fileIndex() const { return fileIndex_; }
  const FrameSource& source() const { return *frames_; }
  // Reads frame `index` and sets the molecule's centres to it (validated: finite).
  void load(std::size_t index);
  // The whole frame last loaded (every atom of the file).
  const Frame& frame() const { return frame_; }

 private:
  Molecule molecule_;
  std::vector<std::size_t> fileIndex_;
  std::unique_ptr<FrameSource> frames_;
  Frame frame_;
};

}  // namespace surftrace::build

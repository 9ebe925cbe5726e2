// Trajectory formats by name, and a topology's selected atoms bound to a trajectory's frames.
#include "build/io/trajectory.hpp"

#include <algorithm>
#include <cmath>

#include "build/core/assert.hpp"
#include "build/io/error.hpp"
#include "build/io/file_formats.hpp"

namespace surftrace::build {

namespace fs = std::filesystem;

TrajectoryFormat trajectoryFormatFromPath(const fs::path& path) {
  const std::string ext = formatExtension(path);
  if (const std::optional<TrajectoryFormat> format = formatsOfExtension(ext).trajectory) return *format;
  throw InputError(path.string(), 0,
                   "cannot tell the trajectory format from the name (extension '" + (ext.empty() ? "" : "." + ext) +
                       "'); expected .dcd, .xtc, .gro, .xyz, .pdb or .cif (the text formats may be gzipped)");
}

const char* trajectoryFormatName(TrajectoryFormat format) {
  switch (format) {
    case TrajectoryFormat::Auto: return "auto";
    case TrajectoryFormat::Dcd: return "DCD";
    case TrajectoryFormat::Xtc: return "XTC";
    case TrajectoryFormat::Gro: return "GRO";
    case TrajectoryFormat::Xyz: return "XYZ";
    case TrajectoryFormat::Pdb: return "PDB";
    case TrajectoryFormat::Mmcif: return "mmCIF";
  }
  return "unknown";
}

std::unique_ptr<FrameSource> openTrajectory(const fs::path& path, TrajectoryFormat format) {
  std::error_code ec;
  if (!fs::exists(path, ec)) throw InputError(path.string(), 0, "no such file");
  if (fs::is_directory(path, ec)) throw InputError(path.string(), 0, "is a directory, not a trajectory file");
  if (format == TrajectoryFormat::Auto) format = trajectoryFormatFromPath(path);
  switch (format) {
    case TrajectoryFormat::Dcd: return openDcd(path);
    case TrajectoryFormat::Xtc: return openXtc(path);
    case TrajectoryFormat::Auto: break;
    default: return openTextTrajectory(path, format);
  }
  SURFTRACE_ASSERT(false);
  return nullptr;
}

Trajectory::Trajectory(const fs::path& topology, const fs::path& trajectory, const ReadOptions& options) {
  ReadOptions topologyOptions = options;
  topologyOptions.topologyOnly = true;
  molecule_ = readMolecule(topology, topologyOptions);
  frames_ = openTrajectory(trajectory);
  if (molecule_.fileAtomCount != frames_->atomCount())
    throw InputError(trajectory.string(), 0,
                     "holds " + std::to_string(frames_->atomCount()) + " atoms per frame, but the topology " +
                         topology.string() + " has " + std::to_string(molecule_.fileAtomCount) +
                         (molecule_.modelCount > 1 ? " in model " + std::to_string(molecule_.modelUsed) : "") +
                         ": a trajectory must list exactly the topology's atoms, in its order");
  if (frames_->frameCount() == 0) throw InputError(trajectory.string(), 0, "holds no complete frame");
  fileIndex_.resize(molecule_.size());
  for (std::size_t i = 0; i < molecule_.size(); ++i) fileIndex_[i] = molecule_.atoms[i].fileIndex;
  // A PSF has no coordinates of its own: the molecule stands where frame 0 puts it.
  const bool hasCentres = std::all_of(molecule_.centers.begin(), molecule_.centers.end(), [](const glm::dvec3& c) {
    return std::isfinite(c.x) && std::isfinite(c.y) && std::isfinite(c.z);
  });
  if (!hasCentres) load(0);
  validateMolecule(molecule_);
}

void Trajectory::load(std::size_t index) {
  if (index >= frames_->frameCount())
    throw InputError(frames_->path(), 0,
                     "frame " + std::to_string(index) + " does not exist: the file holds frames 0 to " +
                         std::to_string(frames_->frameCount() - 1));
  frames_->read(index, frame_);
  SURFTRACE_ASSERT(frame_.positions.size() == frames_->atomCount());
  for (std::size_t i = 0; i < fileIndex_.size(); ++i) molecule_.centers[i] = frame_.positions[fileIndex_[i]];
}

}  // namespace surftrace::build

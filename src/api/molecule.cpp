// Stage "read" (surftrace/molecule.hpp).
#include "surftrace/molecule.hpp"

#include "build/io/stp_file.hpp"

namespace surftrace {

Molecule readStructure(const std::string& path, const ReadOptions& options) { return build::readMolecule(path, options); }

Molecule readTrajectoryFrame(const std::string& topology, const std::string& trajectory, std::size_t frame,
                             const ReadOptions& options) {
  Trajectory frames(topology, trajectory, options);
  frames.load(frame);
  return frames.molecule();
}

bool isPatchListPath(const std::string& path) {
  if (build::isPatchListFile(path)) return true;
  const std::string ext = ".stp";
  return path.size() > ext.size() && path.compare(path.size() - ext.size(), ext.size(), ext) == 0;
}

}  // namespace surftrace

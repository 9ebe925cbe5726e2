# The library sources the fuzz harnesses link, relative to the repository root. One list for
# the two builds that use it: tests/fuzz/CMakeLists.txt (clang, libFuzzer, scripts/fuzz.sh) and
# tests/CMakeLists.txt (the same harnesses linked by the project's own compiler and replayed
# over the bundled files), so a source missing here fails every build's link, not only the
# fuzzing stage at the end of scripts/test.sh.
#
# When a reader, the patch list or a patch consumer starts calling code in a new .cpp file, add
# that file to the list it belongs to.

# The input layer of surftrace_build: the structure, trajectory and .stp readers.
set(SURFTRACE_FUZZ_IO_SOURCES
  src/build/core/assert.cpp
  src/build/io/gemmi_impl.cpp
  src/build/io/file_formats.cpp
  src/build/io/atom_string.cpp
  src/build/io/molecule.cpp
  src/build/io/radii.cpp
  src/build/io/radius_presets.cpp
  src/build/io/atom_selection.cpp
  src/build/io/topology_formats.cpp
  src/build/io/trajectory.cpp
  src/build/io/text_trajectory.cpp
  src/build/io/binary_reader.cpp
  src/build/io/dcd.cpp
  src/build/io/xtc.cpp
  src/build/io/output_file.cpp
  src/build/patch_list.cpp
  src/build/io/stp_file.cpp
  src/build/mss/skin_geometry.cpp
)

# What reads a loaded patch list, for fuzz_stp's contract: the areas of `surftrace area`, the
# trace intersectors' records and boxes (the Embree-free part of surftrace_trace) and the GL
# upload (the GL-free part of surftrace_gl), with the neighbour grid that the skin's owner
# search (mss_patch.cpp) keeps.
set(SURFTRACE_FUZZ_CONSUMER_SOURCES
  src/build/neighbour_grid.cpp
  src/build/ses/surface_area.cpp
  src/build/surface_components.cpp
  src/build/surface_topology.cpp
  src/build/spherical_region.cpp
  src/trace/sphere_patch.cpp
  src/trace/torus_patch.cpp
  src/trace/concave_patch.cpp
  src/trace/mss_patch.cpp
  src/trace/polynomial.cpp
  src/gl/gpu_kinds.cpp
  src/view/patch_kind.cpp
)

# One harness program per format: fuzz_molecule.cpp for the structures, fuzz_trajectory.cpp
# for the trajectories (frames one after another), fuzz_patch_list.cpp for .stp.
set(SURFTRACE_FUZZ_MOLECULE_FORMATS pdb mmcif pqr xyzr xyz)
set(SURFTRACE_FUZZ_TRAJECTORY_FORMATS dcd xtc gro)

// What the parts of the Python module share: the objects Python holds, and each part's
// registration function (module.cpp calls them in the order data flows).
#pragma once

#include <memory>
#include <optional>

#include <pybind11/pybind11.h>

#include "surftrace/surftrace.hpp"

namespace surftrace::python {

namespace py = pybind11;

// surftrace.Molecule: the atoms, shared (a Surface keeps the molecule it was built from).
struct PyMolecule {
  std::shared_ptr<const Molecule> molecule;
};

// surftrace.Surface: a patch list and, when known, the molecule it was built from (none for a
// patch list loaded alone); its areas computed on first use.
struct PySurface {
  std::shared_ptr<const PatchList> patches;
  std::shared_ptr<const Molecule> molecule;
  mutable std::shared_ptr<const SurfaceAreas> areas;
  const SurfaceAreas& areasOf() const;
};

void bindMolecules(py::module_& m);  // read, Molecule, select          (molecule_bindings.cpp)
void bindSurfaces(py::module_& m);   // ses, skin, sas, vdw, Surface, load, Updater  (surface_bindings.cpp)
void bindImages(py::module_& m);     // Camera, render, Image, compare  (image_bindings.cpp)

}  // namespace surftrace::python

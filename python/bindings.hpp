// What the parts of the Python module share: the objects Python holds, and each part's
// registration function (module.cpp calls them in the order data flows).
#pragma once

#include <cstddef>
#include <memory>
#include <optional>
#include <string>
#include <vector>

#include <pybind11/numpy.h>
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
  // What it was built for (the SAS's areas come from the SES of the same request); for a list
  // loaded alone, SurfaceRequest::of its parameters.
  SurfaceRequest request;
  std::vector<std::string> notes;  // what buildSurface left out (atoms inside others, merged)
  // The areas of this surface, computed once with the GIL released (call it holding the GIL).
  // The SAS's are those of the SES of the same probe (its `sas` and `sasPerAtom`, as total and
  // perAtom); std::invalid_argument for a surface without areas (a SAS or a skin loaded alone).
  const SurfaceAreas& areasOf() const;
};

// A read-only numpy array over `data` (C order), which `owner` keeps alive: no copy.
py::array readOnlyView(std::shared_ptr<const void> owner, const double* data, std::vector<py::ssize_t> shape);

void bindMolecules(py::module_& m);  // read, Molecule, select          (molecule_bindings.cpp)
void bindSurfaces(py::module_& m);   // ses, skin, sas, vdw, Surface, load, Updater  (surface_bindings.cpp)
void bindImages(py::module_& m);     // Camera, render, Image, compare  (image_bindings.cpp)

}  // namespace surftrace::python

namespace surftrace::python {

// Arrays from Python, checked where they enter (README, "Python"): any numeric dtype (float64
// as it is, float32 and integers widened exactly), any strides, `rows` rows when given;
// TypeError for a dtype that is not a number, ValueError for a shape or a value that is wrong,
// each naming `what` and, for a value, its place.
std::vector<glm::dvec3> centresFrom(py::handle array, const std::string& what, std::optional<std::size_t> rows);
std::vector<double> valuesFrom(py::handle array, const std::string& what, std::optional<std::size_t> rows);
// A path given as str or os.PathLike.
std::string pathFrom(py::handle path);
// The Python object of a molecule (one surftrace.Molecule per call).
py::object moleculeObject(std::shared_ptr<const Molecule> molecule);

}  // namespace surftrace::python

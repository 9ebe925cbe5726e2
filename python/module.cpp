// The Python module `surftrace`: exact molecular surfaces, their areas and images (README, "Python").
#include "bindings.hpp"

PYBIND11_MODULE(surftrace, m) {
  m.doc() = "SurfTrace: exact molecular surfaces (SES, skin), their areas, and ray-traced images";
  m.attr("__version__") = surftrace::version();
  surftrace::python::bindMolecules(m);
  surftrace::python::bindSurfaces(m);
  surftrace::python::bindImages(m);
}

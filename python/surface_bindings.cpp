// (placeholder until written) bindSurfaces.
#include "bindings.hpp"

namespace surftrace::python {

void bindSurfaces(py::module_&) {}

}  // namespace surftrace::python

namespace surftrace::python {
const SurfaceAreas& PySurface::areasOf() const {
  if (!areas) areas = std::make_shared<const SurfaceAreas>(surfaceAreas(*patches, molecule ? std::span<const glm::dvec3>(molecule->centers) : std::span<const glm::dvec3>()));
  return *areas;
}
}  // namespace surftrace::python

// (placeholder until written) bindMolecules.
#include "bindings.hpp"

namespace surftrace::python {

void bindMolecules(py::module_&) {}

}  // namespace surftrace::python

// (placeholder until written) bindImages.
#include "bindings.hpp"

namespace surftrace::python {

void bindImages(py::module_&) {}

}  // namespace surftrace::python

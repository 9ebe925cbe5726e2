// The library's version (surftrace/version.hpp).
#include "surftrace/version.hpp"

namespace surftrace {

const char* version() { return SURFTRACE_VERSION; }

}  // namespace surftrace

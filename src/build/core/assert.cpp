// Reporting of broken internal invariants.
#include "build/core/assert.hpp"

#include <cstdio>
#include <cstdlib>

namespace surftrace::build {

void assertionFailed(const char* expr, const char* file, int line) {
  std::fprintf(stderr, "surftrace: internal error: %s failed at %s:%d\n", expr, file, line);
  std::abort();
}

}  // namespace surftrace::build

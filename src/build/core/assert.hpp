// SURFTRACE_ASSERT: the check of internal invariants that every layer of surftrace_build uses.
#pragma once

// Internal invariants (never bad input, which is an InputError): abort with the location in
// every build type.
#define SURFTRACE_ASSERT(cond)                                                        \
  do {                                                                                \
    if (!(cond)) ::surftrace::build::assertionFailed(#cond, __FILE__, __LINE__);      \
  } while (false)

namespace surftrace::build {
[[noreturn]] void assertionFailed(const char* expr, const char* file, int line);
}

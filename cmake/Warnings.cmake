# Warnings come from one INTERFACE target that every SurfTrace target links privately.
add_library(surftrace_warnings INTERFACE)
target_compile_options(surftrace_warnings INTERFACE
  $<$<CXX_COMPILER_ID:GNU,Clang>:-Wall -Wextra -Wpedantic -Wshadow -Wnon-virtual-dtor
                                 -Wold-style-cast -Wcast-align -Woverloaded-virtual>
  $<$<AND:$<BOOL:${SURFTRACE_WARNINGS_AS_ERRORS}>,$<CXX_COMPILER_ID:GNU,Clang>>:-Werror>)

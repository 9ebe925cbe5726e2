# Every dependency comes from a Debian package (scripts/install-deps.sh) and is found
# through its own CMake config; the workarounds below are for known Debian packaging bugs.
find_package(Threads REQUIRED)
find_package(TBB REQUIRED)
find_package(glm REQUIRED)
find_package(ZLIB REQUIRED)
find_package(nlohmann_json 3 REQUIRED)
find_package(CLI11 REQUIRED)
find_package(embree 3 REQUIRED)
find_package(OpenImageIO REQUIRED)
find_package(assimp REQUIRED)  # meshes in (compare) and out
find_package(OpenGL REQUIRED COMPONENTS OpenGL EGL)

include(${CMAKE_CURRENT_LIST_DIR}/OpenImageIOFix.cmake)  # its include path to opencv4

# gemmi-dev is header-only and ships no CMake config; it needs PEGTL (for CIF) and zlib.
find_path(GEMMI_INCLUDE_DIR gemmi/mmread.hpp REQUIRED)
find_path(PEGTL_INCLUDE_DIR tao/pegtl.hpp REQUIRED)
add_library(surftrace_gemmi INTERFACE)
target_include_directories(surftrace_gemmi SYSTEM INTERFACE ${GEMMI_INCLUDE_DIR} ${PEGTL_INCLUDE_DIR})
target_link_libraries(surftrace_gemmi INTERFACE ZLIB::ZLIB)

# GMP (libgmp-dev) for the exact fallback of the SES predicates; it ships no CMake config.
# Both targets are this build's only (src/build links them as $<BUILD_INTERFACE:...>): the
# installed package needs no gemmi (its headers are read by .cpp files alone) and finds the GMP
# libraries again itself, as SurfTrace::gmp (cmake/SurfTraceConfig.cmake.in).
find_path(GMPXX_INCLUDE_DIR gmpxx.h REQUIRED)
find_library(GMPXX_LIBRARY gmpxx REQUIRED)
find_library(GMP_LIBRARY gmp REQUIRED)
add_library(surftrace_gmp INTERFACE)
target_include_directories(surftrace_gmp SYSTEM INTERFACE ${GMPXX_INCLUDE_DIR})
target_link_libraries(surftrace_gmp INTERFACE ${GMPXX_LIBRARY} ${GMP_LIBRARY})

if(SURFTRACE_BUILD_TESTS)
  find_package(GTest REQUIRED)
  find_package(CGAL QUIET)   # GPL: test oracles only, never linked into a library or tool
endif()
if(SURFTRACE_BUILD_BENCHMARKS)
  find_package(benchmark REQUIRED)
endif()

# `cmake --install`: the library, its headers and a CMake package, so that a program's
# find_package(SurfTrace) and target_link_libraries(app SurfTrace::surftrace) work
# (examples/cpp/ is one; tests/scripts/installed_package_test.sh builds it against an install).
#
#   lib/                               libsurftrace.a and the four modules' archives it links
#   include/surftrace/                 the public API
#   include/surftrace/internal/        the modules' headers (src/*/), which the public ones
#                                      include as "build/patch_list.hpp" and so on
#   lib/cmake/SurfTrace/               SurfTraceConfig.cmake, its version and the targets
#
# Only SurfTrace::surftrace is for programs; the modules' targets come with it because the
# archives are static. The programs (tools/CMakeLists.txt) install themselves.
include(CMakePackageConfigHelpers)
set(surftrace_config_dir ${CMAKE_INSTALL_LIBDIR}/cmake/SurfTrace)

install(TARGETS surftrace_build surftrace_view surftrace_trace surftrace_gl surftrace_api
  EXPORT SurfTraceTargets
  ARCHIVE DESTINATION ${CMAKE_INSTALL_LIBDIR}
  LIBRARY DESTINATION ${CMAKE_INSTALL_LIBDIR})
install(DIRECTORY ${PROJECT_SOURCE_DIR}/include/surftrace/ DESTINATION ${CMAKE_INSTALL_INCLUDEDIR}/surftrace
  FILES_MATCHING PATTERN "*.hpp")
# Every module header rather than the set the public ones reach today: that set changes with
# each include, and a missing one shows only in a program built against the install.
install(DIRECTORY ${PROJECT_SOURCE_DIR}/src/ DESTINATION ${SURFTRACE_INSTALL_MODULE_INCLUDEDIR}
  FILES_MATCHING PATTERN "*.hpp" PATTERN "*.h" PATTERN "api" EXCLUDE)

install(EXPORT SurfTraceTargets NAMESPACE SurfTrace:: DESTINATION ${surftrace_config_dir})
configure_package_config_file(${CMAKE_CURRENT_LIST_DIR}/SurfTraceConfig.cmake.in
  ${PROJECT_BINARY_DIR}/SurfTraceConfig.cmake INSTALL_DESTINATION ${surftrace_config_dir})
# Before 1.0 a minor version may change the API: only the same major.minor matches.
write_basic_package_version_file(${PROJECT_BINARY_DIR}/SurfTraceConfigVersion.cmake
  COMPATIBILITY SameMinorVersion)
install(FILES ${PROJECT_BINARY_DIR}/SurfTraceConfig.cmake ${PROJECT_BINARY_DIR}/SurfTraceConfigVersion.cmake
  ${CMAKE_CURRENT_LIST_DIR}/OpenImageIOFix.cmake DESTINATION ${surftrace_config_dir})

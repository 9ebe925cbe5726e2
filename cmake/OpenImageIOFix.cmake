# Debian bookworm's OpenImageIO target names /usr/include/opencv4, which does not exist
# unless OpenCV's headers happen to be installed; CMake rejects a missing include path.
# Included after find_package(OpenImageIO) by this build (Dependencies.cmake) and by the
# installed package's SurfTraceConfig.cmake, whose users meet the same target.
foreach(_surftrace_prop INTERFACE_INCLUDE_DIRECTORIES INTERFACE_SYSTEM_INCLUDE_DIRECTORIES)
  get_target_property(_surftrace_dirs OpenImageIO::OpenImageIO ${_surftrace_prop})
  if(_surftrace_dirs)
    list(FILTER _surftrace_dirs EXCLUDE REGEX "opencv4")
    set_target_properties(OpenImageIO::OpenImageIO PROPERTIES ${_surftrace_prop} "${_surftrace_dirs}")
  endif()
endforeach()
unset(_surftrace_prop)
unset(_surftrace_dirs)

# The one Python that runs the test oracles (tests/oracles/*.py: numpy, MDAnalysis).
#
# surftrace_find_oracle_python(<var>) sets <var> to the first of /usr/bin/python3 (where Debian's
# python3-mdanalysis installs) and the python3 on PATH that imports numpy and MDAnalysis, or to
# "" when neither does. A pyenv or venv python3 first on PATH without them is passed over.
#
# Run as a script (cmake -P cmake/OraclePython.cmake) it prints the choice and fails when there
# is none: scripts/test.sh checks the choice that way with a numpy-less python3 first on PATH.
function(surftrace_find_oracle_python var)
  find_program(usr_python python3 PATHS /usr/bin NO_DEFAULT_PATH NO_CACHE)
  find_program(path_python python3 NO_CACHE)
  foreach(candidate IN ITEMS ${usr_python} ${path_python})
    execute_process(COMMAND ${candidate} -c "import numpy, MDAnalysis"
                    RESULT_VARIABLE imported OUTPUT_QUIET ERROR_QUIET)
    if(imported EQUAL 0)
      set(${var} ${candidate} PARENT_SCOPE)
      return()
    endif()
  endforeach()
  set(${var} "" PARENT_SCOPE)
endfunction()

if(CMAKE_SCRIPT_MODE_FILE STREQUAL CMAKE_CURRENT_LIST_FILE)
  surftrace_find_oracle_python(chosen)
  if(NOT chosen)
    message(FATAL_ERROR "no python3 that imports numpy and MDAnalysis")
  endif()
  message(STATUS "oracle Python: ${chosen}")
endif()

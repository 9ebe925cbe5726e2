# cmake -DCTEST=ctest -DBUILD_DIR=<build folder> -P check_labels.cmake
# Fails when a test of that build has neither the label `fast` nor `slow` (so `ctest -L fast`
# would leave it out of the quick check and `-L slow` too), or has a label that tests/labels.cmake
# does not explain (a misspelt label selects nothing), or when a pattern of release_only_tests
# names no test (a renamed test would silently run under ASan again).
cmake_minimum_required(VERSION 3.25)
set(known_labels fast slow gl oracle cli script release_only)

execute_process(COMMAND ${CTEST} -N -LE "^(fast|slow)$" WORKING_DIRECTORY ${BUILD_DIR}
                OUTPUT_VARIABLE unlabelled RESULT_VARIABLE status)
if(NOT status EQUAL 0)
  message(FATAL_ERROR "${CTEST} -N failed (${status}) in ${BUILD_DIR}:\n${unlabelled}")
endif()
if(NOT unlabelled MATCHES "Total Tests: ([0-9]+)")
  message(FATAL_ERROR "no test count in the output of ${CTEST} -N in ${BUILD_DIR}:\n${unlabelled}")
endif()
set(count ${CMAKE_MATCH_1})
if(NOT count EQUAL 0)
  string(REGEX MATCHALL "Test +#[0-9]+: [^\n]*" tests "${unlabelled}")
  list(JOIN tests "\n  " tests)
  message(FATAL_ERROR "${count} tests have neither the label fast nor slow; give them one "
                      "in tests/labels.cmake (GoogleTest's) or tests/CMakeLists.txt (add_test's):\n  ${tests}")
endif()

execute_process(COMMAND ${CTEST} --print-labels WORKING_DIRECTORY ${BUILD_DIR}
                OUTPUT_VARIABLE printed RESULT_VARIABLE status)
if(NOT status EQUAL 0)
  message(FATAL_ERROR "${CTEST} --print-labels failed (${status}) in ${BUILD_DIR}:\n${printed}")
endif()
string(REGEX MATCHALL "\n  [^\n]+" labels "${printed}")
foreach(label IN LISTS labels)
  string(STRIP "${label}" label)
  if(NOT label IN_LIST known_labels)
    message(FATAL_ERROR "a test has the label '${label}', which is none of ${known_labels}: "
                        "correct it, or add it to tests/check_labels.cmake and explain it in tests/labels.cmake")
  endif()
endforeach()

# labels.cmake's lists alone: in script mode it labels no test (no test programs are listed).
include(${CMAKE_CURRENT_LIST_DIR}/labels.cmake)
foreach(pattern IN LISTS release_only_tests)
  execute_process(COMMAND ${CTEST} -N -R "^(${pattern})$" WORKING_DIRECTORY ${BUILD_DIR}
                  OUTPUT_VARIABLE matched RESULT_VARIABLE status)
  if(NOT status EQUAL 0 OR NOT matched MATCHES "Total Tests: ([1-9][0-9]*)")
    message(FATAL_ERROR "the release_only pattern '${pattern}' in tests/labels.cmake names no test: "
                        "correct it to the test's name, or remove it")
  endif()
endforeach()
message(STATUS "every test has fast or slow, and only the labels ${known_labels}; "
               "every release_only pattern names a test")

# plugslam_add_test(NAME SOURCES ... [LIBRARIES ...] [LABELS unit|integration|e2e])
# One GoogleTest executable registered with CTest. Tests find real datasets through PLUGSLAM_DATA
# (may be absent: they skip with a reason) and the build tree through tests/support/test_paths.h.
# The data folder is read when a test runs: $PLUGSLAM_DATA, else the PLUGSLAM_DATA this build was
# configured with, else ../shared/data beside the source tree. The configure-time value reaches the
# tests as PLUGSLAM_TEST_DATA_DEFAULT in their environment, so it never overrides the user's
# PLUGSLAM_DATA and changing it recompiles nothing.
set(PLUGSLAM_TEST_ENVIRONMENT "")
if(DEFINED ENV{PLUGSLAM_DATA} AND NOT "$ENV{PLUGSLAM_DATA}" STREQUAL "")
  set(PLUGSLAM_TEST_ENVIRONMENT "PLUGSLAM_TEST_DATA_DEFAULT=$ENV{PLUGSLAM_DATA}")
endif()

# The one object that knows this checkout's folders: every other test object is the same in any
# checkout, so worktrees and clean clones share the compiler cache.
function(plugslam_test_paths_library)
  if(TARGET plugslam_test_paths)
    return()
  endif()
  add_library(plugslam_test_paths STATIC "${PROJECT_SOURCE_DIR}/tests/support/test_paths.cpp")
  target_include_directories(plugslam_test_paths PUBLIC "${PROJECT_SOURCE_DIR}/tests/support")
  target_compile_definitions(plugslam_test_paths PRIVATE
    PLUGSLAM_TEST_BUILD_DIR="${CMAKE_BINARY_DIR}"
    PLUGSLAM_TEST_SOURCE_DIR="${PROJECT_SOURCE_DIR}")
endfunction()

function(plugslam_add_test name)
  if(NOT PLUGSLAM_BUILD_TESTS)
    return()
  endif()
  cmake_parse_arguments(ARG "" "" "SOURCES;LIBRARIES;LABELS" ${ARGN})
  plugslam_test_paths_library()
  add_executable(${name} ${ARG_SOURCES})
  target_link_libraries(${name} PRIVATE plugslam_sdk GTest::gtest GTest::gtest_main ${ARG_LIBRARIES})
  set_target_properties(${name} PROPERTIES RUNTIME_OUTPUT_DIRECTORY "${CMAKE_BINARY_DIR}/tests")
  if(NOT ARG_LABELS)
    set(ARG_LABELS unit)
  endif()
  # The build and source folders are compiled into tests/support/test_paths.cpp only; the data
  # folder is not compiled in at all (see above).
  target_link_libraries(${name} PRIVATE plugslam_test_paths)
  # gtest_discover_tests splits list-valued properties, so ENVIRONMENT carries one variable.
  gtest_discover_tests(${name}
    PROPERTIES LABELS "${ARG_LABELS}" ENVIRONMENT "${PLUGSLAM_TEST_ENVIRONMENT}"
    DISCOVERY_TIMEOUT 60)
endfunction()

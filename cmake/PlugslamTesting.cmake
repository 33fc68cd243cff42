# plugslam_add_test(NAME SOURCES ... [LIBRARIES ...] [LABELS unit|integration|e2e])
# One GoogleTest executable registered with CTest. Tests find real datasets through PLUGSLAM_DATA
# (may be absent: they skip with a reason) and the build tree through tests/support/test_paths.h.
if(DEFINED ENV{PLUGSLAM_DATA})
  set(PLUGSLAM_DATA_DIR "$ENV{PLUGSLAM_DATA}")
else()
  get_filename_component(PLUGSLAM_DATA_DIR "${PROJECT_SOURCE_DIR}/../shared/data" ABSOLUTE)
endif()

function(plugslam_add_test name)
  if(NOT PLUGSLAM_BUILD_TESTS)
    return()
  endif()
  cmake_parse_arguments(ARG "" "" "SOURCES;LIBRARIES;LABELS" ${ARGN})
  add_executable(${name} ${ARG_SOURCES})
  target_link_libraries(${name} PRIVATE plugslam_sdk GTest::gtest GTest::gtest_main ${ARG_LIBRARIES})
  set_target_properties(${name} PROPERTIES RUNTIME_OUTPUT_DIRECTORY "${CMAKE_BINARY_DIR}/tests")
  if(NOT ARG_LABELS)
    set(ARG_LABELS unit)
  endif()
  # The build and source folders are compiled in (tests/support/test_paths.h); the data folder
  # also comes from the environment, so a user can point PLUGSLAM_DATA elsewhere.
  target_include_directories(${name} PRIVATE "${PROJECT_SOURCE_DIR}/tests/support")
  target_compile_definitions(${name} PRIVATE
    PLUGSLAM_TEST_DATA_DIR="${PLUGSLAM_DATA_DIR}"
    PLUGSLAM_TEST_BUILD_DIR="${CMAKE_BINARY_DIR}"
    PLUGSLAM_TEST_SOURCE_DIR="${PROJECT_SOURCE_DIR}")
  # gtest_discover_tests splits list-valued properties, so ENVIRONMENT carries one variable.
  gtest_discover_tests(${name}
    PROPERTIES LABELS "${ARG_LABELS}" ENVIRONMENT "PLUGSLAM_DATA=${PLUGSLAM_DATA_DIR}"
    DISCOVERY_TIMEOUT 60)
endfunction()

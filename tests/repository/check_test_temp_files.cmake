# Fails when a test writes into the shared temporary folder by name (temp_directory_path(),
# ::testing::TempDir()): two users, or two runs, then share files. Tests use
# plugslam::testing::TempDir (tests/support/temp_dir.h), a fresh folder of their own.
# tests/fuzz is left out: libFuzzer drivers take their folder from TMPDIR.
file(GLOB_RECURSE sources "${SOURCE}/tests/*.cpp" "${SOURCE}/tests/*.h" "${SOURCE}/plugins/*/tests/*.cpp"
     "${SOURCE}/plugins/*/tests/*.h")
include("${CMAKE_CURRENT_LIST_DIR}/offenders.cmake")
foreach(f ${sources})
  if(f MATCHES "/tests/fuzz/" OR f MATCHES "/tests/support/temp_dir.h$")
    continue()
  endif()
  file(STRINGS "${f}" hits REGEX "temp_directory_path\\(|testing::TempDir\\(\\)")
  if(hits)
    add_offender("${f}" ": ${hits}")
  endif()
endforeach()
fail_with_offenders("tests that write into the shared temporary folder by name (use "
                    "plugslam::testing::TempDir from tests/support/temp_dir.h)")

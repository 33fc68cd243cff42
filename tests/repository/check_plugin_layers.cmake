# Fails when a plugin sits above the host: a CMakeLists.txt under plugins/ that links (or names)
# plugslam_runtime, or a plugin's source or test that includes one of the host's headers
# (runtime/src/). Plugins link the SDK only (docs/architecture.md, "Layers"); what needs the host
# too lives in runtime/tools/ or tests/.
include("${CMAKE_CURRENT_LIST_DIR}/offenders.cmake")
file(GLOB_RECURSE cmake_files "${SOURCE}/plugins/*CMakeLists.txt" "${SOURCE}/plugins/*.cmake")
foreach(f ${cmake_files})
  file(STRINGS "${f}" lines)
  set(n 0)
  foreach(line IN LISTS lines)
    math(EXPR n "${n} + 1")
    string(REGEX REPLACE "#.*$" "" code "${line}")  # a comment may name the host
    if(code MATCHES "plugslam_runtime")
      add_offender("${f}" ":${n}: names plugslam_runtime")
    endif()
  endforeach()
endforeach()

# A quoted include names a host header when runtime/src has it and no plugin or SDK folder does
# (a few names, such as report.h, exist in both).
file(GLOB_RECURSE sources "${SOURCE}/plugins/*.h" "${SOURCE}/plugins/*.cpp")
foreach(f ${sources})
  file(STRINGS "${f}" includes REGEX "^[ \t]*#[ \t]*include[ \t]*\"[^\"]+\"")
  foreach(line IN LISTS includes)
    string(REGEX REPLACE "^[^\"]*\"([^\"]+)\".*$" "\\1" header "${line}")
    if(NOT EXISTS "${SOURCE}/runtime/src/${header}")
      continue()
    endif()
    file(GLOB_RECURSE own "${SOURCE}/plugins/*/${header}" "${SOURCE}/sdk/include/${header}")
    if(NOT own)
      add_offender("${f}" ": includes the host's ${header}")
    endif()
  endforeach()
endforeach()
fail_with_offenders("plugins that use the host (plugslam_runtime); move what needs it to "
                    "runtime/tools/ or tests/")

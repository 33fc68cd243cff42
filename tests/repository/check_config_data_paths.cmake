# Fails when a shipped config names the data folder by a relative path (../shared/data/...): such
# a path works from the repository root only. Configs say ${PLUGSLAM_DATA} (configs/README.md).
include("${CMAKE_CURRENT_LIST_DIR}/offenders.cmake")
file(GLOB configs "${SOURCE}/configs/*.yaml")
foreach(f ${configs})
  file(STRINGS "${f}" lines REGEX "shared/data")
  foreach(line ${lines})
    if(NOT line MATCHES "^[ \t]*#")
      add_offender("${f}" ": ${line}")
    endif()
  endforeach()
endforeach()
fail_with_offenders("configs that name the data folder relative to the current folder (write "
                    "\${PLUGSLAM_DATA}/...)")
list(LENGTH configs count)
message(STATUS "${count} configs, none names ../shared/data")

# Regenerates the configuration reference and fails, saying how to fix it, when the committed
# docs/config-reference.md differs.
execute_process(COMMAND "${PLUGSLAM}" -q reference -o "${ACTUAL}" RESULT_VARIABLE rc)
if(NOT rc EQUAL 0)
  message(FATAL_ERROR "plugslam reference failed (${rc})")
endif()
file(READ "${EXPECTED}" expected)
file(READ "${ACTUAL}" actual)
if(NOT expected STREQUAL actual)
  message(FATAL_ERROR "docs/config-reference.md is stale: run `build/bin/plugslam reference -o docs/config-reference.md` and commit it (generated copy: ${ACTUAL})")
endif()

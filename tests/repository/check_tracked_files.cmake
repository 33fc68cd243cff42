# Fails when git tracks a compiled or generated file that the build or a script writes.
execute_process(COMMAND "${GIT}" -C "${SOURCE}" ls-files -- "*.pyc" "*__pycache__*" "*.o" "*.so"
                        "*.a" "compile_commands.json"
                OUTPUT_VARIABLE tracked RESULT_VARIABLE rc)
if(NOT rc EQUAL 0)
  message(FATAL_ERROR "git ls-files failed (${rc})")
endif()
if(NOT tracked STREQUAL "")
  message(FATAL_ERROR "build products are committed (git rm --cached them; .gitignore lists "
                      "their patterns):\n${tracked}")
endif()

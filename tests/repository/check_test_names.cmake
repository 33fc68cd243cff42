# Fails when a test's name is not the same from build to build: GoogleTest names a parameterised
# case it cannot print by the bytes of its parameter ("24-byte object <04-80 ...>"), heap
# addresses included. Give INSTANTIATE_TEST_SUITE_P a name generator.
execute_process(COMMAND "${CTEST}" --test-dir "${BUILD}" -N OUTPUT_VARIABLE listing RESULT_VARIABLE rc)
if(NOT rc EQUAL 0)
  message(FATAL_ERROR "ctest -N failed (${rc})")
endif()
string(REGEX MATCHALL "Test +#[0-9]+: [^\n]*byte object[^\n]*" unstable "${listing}")
if(unstable)
  list(JOIN unstable "\n" text)
  message(FATAL_ERROR "test names made of a parameter's bytes:\n${text}")
endif()
string(REGEX MATCHALL "Test +#[0-9]+:" all "${listing}")
list(LENGTH all count)
message(STATUS "${count} test names, all stable")

# What the repository checks share: the list of offenders, each a file (relative to the source
# tree) and what it does wrong, and the failure that lists them under a heading.
set(offenders "")

# Adds `file` (an absolute path) and `what` to the offenders.
function(add_offender file what)
  string(REPLACE "${SOURCE}/" "" rel "${file}")
  list(APPEND offenders "${rel}${what}")
  set(offenders "${offenders}" PARENT_SCOPE)
endfunction()

# Fails with a heading (the arguments joined, as message() joins them) and the offenders, one a
# line, when there are any.
function(fail_with_offenders)
  if(offenders)
    set(heading "")
    math(EXPR last "${ARGC} - 1")
    foreach(i RANGE ${last})
      string(APPEND heading "${ARGV${i}}")
    endforeach()
    list(JOIN offenders "\n" text)
    message(FATAL_ERROR "${heading}:\n${text}")
  endif()
endfunction()

# SPDX-License-Identifier: BSD-3-Clause
# Runs Doxygen on DOXYFILE, whose WARN_LOGFILE is LOG, and reports the warnings it logged: with
# FAIL_ON_WARNINGS (the ctest docs.api) a non-empty log is an error naming every warning.
#   cmake -DDOXYGEN=doxygen -DDOXYFILE=build/docs/Doxyfile -DLOG=build/docs/doxygen-warnings.log
#         -DFAIL_ON_WARNINGS=ON -P docs/check_doxygen.cmake
foreach(var DOXYGEN DOXYFILE LOG)
  if(NOT ${var})
    message(FATAL_ERROR "check_doxygen.cmake: ${var} is not set")
  endif()
endforeach()

file(REMOVE ${LOG}) # a log left by an earlier run must not stand for this one
execute_process(COMMAND ${DOXYGEN} ${DOXYFILE} RESULT_VARIABLE status)
if(NOT status EQUAL 0)
  message(FATAL_ERROR "doxygen ${DOXYFILE} failed (${status})")
endif()
if(NOT EXISTS ${LOG})
  message(FATAL_ERROR "doxygen wrote no warning log ${LOG}")
endif()

file(READ ${LOG} warnings)
string(STRIP "${warnings}" warnings)
if(warnings)
  string(REGEX MATCHALL "\n" lines "\n${warnings}")
  list(LENGTH lines count)
  # Indented lines are printed as they are (message() reflows the others).
  string(REPLACE "\n" "\n  " warnings "  ${warnings}")
  set(text "Doxygen logged ${count} warning line(s) (${LOG}):\n${warnings}\n")
  if(FAIL_ON_WARNINGS)
    message(FATAL_ERROR "${text}")
  endif()
  message(WARNING "${text}")
else()
  message(STATUS "Doxygen: no warnings")
endif()

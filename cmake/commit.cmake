# SPDX-License-Identifier: BSD-3-Clause
# Writes OUTPUT, a header defining SMPM_COMMIT: the checkout's commit (`git describe --always
# --dirty`), or "unknown" outside a git checkout. Run at every build (apps/CMakeLists.txt); the
# header is rewritten only when the commit changes, so nothing recompiles otherwise.
execute_process(COMMAND git describe --always --dirty --abbrev=12
                WORKING_DIRECTORY "${SOURCE_DIR}"
                OUTPUT_VARIABLE commit OUTPUT_STRIP_TRAILING_WHITESPACE
                RESULT_VARIABLE status ERROR_QUIET)
if(NOT status EQUAL 0 OR commit STREQUAL "")
  set(commit "unknown")
endif()
set(text "#pragma once\n#define SMPM_COMMIT \"${commit}\"\n")
if(EXISTS "${OUTPUT}")
  file(READ "${OUTPUT}" old)
endif()
if(NOT old STREQUAL text)
  file(WRITE "${OUTPUT}" "${text}")
endif()

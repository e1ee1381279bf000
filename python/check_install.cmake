# SPDX-License-Identifier: BSD-3-Clause
# Installs the build into a scratch prefix and imports the installed package with the system
# interpreter from outside the build tree; checks that the site directory under the prefix
# /usr/local is on that interpreter's sys.path (so `cmake --install build` needs no PYTHONPATH).
file(REMOVE_RECURSE ${WORK_DIR})
file(MAKE_DIRECTORY ${WORK_DIR})
execute_process(COMMAND ${CMAKE_COMMAND} --install ${BUILD_DIR} --prefix ${WORK_DIR}/prefix
                RESULT_VARIABLE rc OUTPUT_QUIET)
if(rc)
  message(FATAL_ERROR "cmake --install failed: ${rc}")
endif()
set(site ${WORK_DIR}/prefix/${INSTALL_DIR})
execute_process(
  COMMAND ${CMAKE_COMMAND} -E env PYTHONPATH=${site} ${PYTHON} -c
          "import sparsempm as s, numpy as n; m = s.Model(s.Grid([3]), [0.75, 1.25, 1.75, 2.25], [0.25] * 4, [0.5] * 4, materials=[s.Material()]); o = s.assemble(m); print(s.__file__); print('rho(A) = %.4f' % s.mass_spectrum(o).rho_A)"
  WORKING_DIRECTORY ${WORK_DIR} RESULT_VARIABLE rc OUTPUT_VARIABLE out ERROR_VARIABLE err)
message(STATUS "installed module printed: ${out}")
if(rc)
  message(FATAL_ERROR "importing the installed module failed: ${err}")
endif()
# Imported from the prefix, not the build tree; ρ(A) of the four particles of docs/guide/cpp.md
# (the largest eigenvalue printed by examples/hello: 0.9459).
if(NOT out MATCHES "^${site}/sparsempm/__init__.py\n" OR NOT out MATCHES "rho\\(A\\) = 0\\.9459")
  message(FATAL_ERROR "unexpected output of the installed module")
endif()
execute_process(
  COMMAND ${PYTHON} -c "import sys; sys.exit('/usr/local/${INSTALL_DIR}' not in sys.path)"
  RESULT_VARIABLE rc)
if(rc)
  message(FATAL_ERROR "/usr/local/${INSTALL_DIR} is not on the sys.path of ${PYTHON}")
endif()

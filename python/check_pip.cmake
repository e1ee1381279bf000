# SPDX-License-Identifier: BSD-3-Clause
# `pip install --no-build-isolation .` as docs/guide/python.md says, into a scratch virtual environment that
# sees the system's numpy and scipy: the package builds offline (setup.py drives CMake) and
# imports from the environment. Its CMake build is made beside the test build, BUILD_DIR.pip,
# with the test build's flags: the same relative paths, so that ccache (with CCACHE_BASEDIR at
# the source tree, as scripts/test sets it) serves every object of the test build.
set(PIP_BUILD_DIR ${BUILD_DIR}.pip)
file(REMOVE_RECURSE ${WORK_DIR} ${PIP_BUILD_DIR})
execute_process(COMMAND ${PYTHON} -m venv --system-site-packages ${WORK_DIR}/venv
                RESULT_VARIABLE rc)
if(rc)
  message(FATAL_ERROR "python3 -m venv failed: ${rc} (scripts/install-deps installs python3-venv)")
endif()
execute_process(
  COMMAND ${CMAKE_COMMAND} -E env SPARSEMPM_CMAKE_ARGS=-DSMPM_WERROR=ON
          SPARSEMPM_BUILD_DIR=${PIP_BUILD_DIR}
          ${WORK_DIR}/venv/bin/pip install --no-build-isolation --no-deps --no-index -q ${SOURCE_DIR}
  WORKING_DIRECTORY ${WORK_DIR} RESULT_VARIABLE rc OUTPUT_VARIABLE out ERROR_VARIABLE err)
if(rc)
  message(FATAL_ERROR "pip install failed: ${rc}\n${out}\n${err}")
endif()
execute_process(
  COMMAND ${WORK_DIR}/venv/bin/python -c
          "import sparsempm as s; m = s.Model(s.Grid([3]), [0.75, 1.25, 1.75, 2.25], [0.25] * 4, [0.5] * 4, materials=[s.Material()]); print(s.__file__); print(s.__version__); print('rho(A) = %.4f' % s.mass_spectrum(s.assemble(m)).rho_A)"
  WORKING_DIRECTORY ${WORK_DIR} RESULT_VARIABLE rc OUTPUT_VARIABLE out ERROR_VARIABLE err)
message(STATUS "the pip-installed module printed: ${out}")
if(rc)
  message(FATAL_ERROR "importing the pip-installed module failed: ${err}")
endif()
# From the environment, with the project's version, and ρ(A) of the four particles of docs/guide/cpp.md
# (examples/hello: 0.9459).
if(NOT out MATCHES "^${WORK_DIR}/venv/lib/python3[.0-9]*/site-packages/sparsempm/__init__.py\n"
   OR NOT out MATCHES "\n${VERSION}\n" OR NOT out MATCHES "rho\\(A\\) = 0\\.9459")
  message(FATAL_ERROR "unexpected output of the pip-installed module")
endif()
file(REMOVE_RECURSE ${PIP_BUILD_DIR})

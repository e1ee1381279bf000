# SPDX-License-Identifier: BSD-3-Clause
# Installs the built library into a scratch prefix, then configures, builds and runs a tiny
# outside project that uses find_package(sparsempm) and links sparsempm::sparsempm.
file(REMOVE_RECURSE ${WORK_DIR})
execute_process(COMMAND ${CMAKE_COMMAND} --install ${BUILD_DIR} --prefix ${WORK_DIR}/prefix
                RESULT_VARIABLE rc OUTPUT_QUIET)
if(rc)
  message(FATAL_ERROR "cmake --install failed: ${rc}")
endif()
set(extra "")
if(SANITIZE)
  # The installed static library was built with the sanitizers; under AddressSanitizer Eigen
  # changes its allocator, so the consumer must be compiled the same way.
  set(extra -DCMAKE_CXX_FLAGS=-fsanitize=address,undefined
            -DCMAKE_EXE_LINKER_FLAGS=-fsanitize=address,undefined)
elseif(TSAN)
  set(extra -DCMAKE_CXX_FLAGS=-fsanitize=thread -DCMAKE_EXE_LINKER_FLAGS=-fsanitize=thread)
endif()
execute_process(COMMAND ${CMAKE_COMMAND} -S ${SOURCE_DIR} -B ${WORK_DIR}/build
                        -DCMAKE_PREFIX_PATH=${WORK_DIR}/prefix -DCMAKE_BUILD_TYPE=Release ${extra}
                RESULT_VARIABLE rc)
if(rc)
  message(FATAL_ERROR "configuring the consumer project failed: ${rc}")
endif()
execute_process(COMMAND ${CMAKE_COMMAND} --build ${WORK_DIR}/build RESULT_VARIABLE rc)
if(rc)
  message(FATAL_ERROR "building the consumer project failed: ${rc}")
endif()
execute_process(COMMAND ${WORK_DIR}/build/consumer RESULT_VARIABLE rc OUTPUT_VARIABLE out)
message(STATUS "consumer printed: ${out}")
if(rc)
  message(FATAL_ERROR "the consumer program failed: ${rc}")
endif()
# ρ(A) = 0.75 for the bar's lattice (FMPM 2026 §3.3; tests/analysis/test_stability.cpp), the
# exact solve to round-off, and the 5 nodes of the inline 4-cell grid.
if(NOT out MATCHES "rho\\(A\\) = 0\\.75\n" OR NOT out MATCHES "exact residual = [0-9.]+e-1[5-9]"
   OR NOT out MATCHES "nodes read = 5")
  message(FATAL_ERROR "unexpected consumer output")
endif()
# The distributed component on one rank (a singleton MPI process), when it was built.
if(EXISTS ${WORK_DIR}/build/consumer_petsc)
  execute_process(COMMAND ${WORK_DIR}/build/consumer_petsc RESULT_VARIABLE rc
                  OUTPUT_VARIABLE out)
  message(STATUS "consumer_petsc printed: ${out}")
  if(rc OR NOT out MATCHES "distributed mass error = [0-9.e-]+\n"
     OR NOT out MATCHES "error = (0|[0-9.]+e-1[4-9])\n")
    message(FATAL_ERROR "unexpected output of the distributed consumer")
  endif()
elseif(HAVE_PETSC)
  message(FATAL_ERROR "the installation has sparsempm::petsc but the consumer did not find it")
endif()

# SPDX-License-Identifier: BSD-3-Clause
# Finds UMFPACK (SuiteSparse) and defines the imported target UMFPACK::UMFPACK.
# Debian's libsuitesparse-dev ships neither a CMake package nor a pkg-config file for it.
find_path(UMFPACK_INCLUDE_DIR umfpack.h PATH_SUFFIXES suitesparse)
find_library(UMFPACK_LIBRARY umfpack)
find_library(UMFPACK_AMD_LIBRARY amd)
find_library(UMFPACK_SUITESPARSECONFIG_LIBRARY suitesparseconfig)
include(FindPackageHandleStandardArgs)
find_package_handle_standard_args(UMFPACK
  REQUIRED_VARS UMFPACK_LIBRARY UMFPACK_AMD_LIBRARY UMFPACK_SUITESPARSECONFIG_LIBRARY
                UMFPACK_INCLUDE_DIR)
if(UMFPACK_FOUND AND NOT TARGET UMFPACK::UMFPACK)
  add_library(UMFPACK::UMFPACK UNKNOWN IMPORTED)
  set_target_properties(UMFPACK::UMFPACK PROPERTIES
    IMPORTED_LOCATION "${UMFPACK_LIBRARY}"
    INTERFACE_INCLUDE_DIRECTORIES "${UMFPACK_INCLUDE_DIR}"
    INTERFACE_LINK_LIBRARIES "${UMFPACK_AMD_LIBRARY};${UMFPACK_SUITESPARSECONFIG_LIBRARY}")
endif()
mark_as_advanced(UMFPACK_INCLUDE_DIR UMFPACK_LIBRARY UMFPACK_AMD_LIBRARY
                 UMFPACK_SUITESPARSECONFIG_LIBRARY)

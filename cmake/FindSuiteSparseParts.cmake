# Finds CHOLMOD and UMFPACK from Debian's libsuitesparse-dev (5.x ships no CMake config)
# and defines the imported targets SuiteSparse::CHOLMOD and SuiteSparse::UMFPACK.
find_path(SuiteSparse_INCLUDE_DIR cholmod.h PATH_SUFFIXES suitesparse)
find_library(CHOLMOD_LIBRARY cholmod)
find_library(UMFPACK_LIBRARY umfpack)
find_library(SUITESPARSECONFIG_LIBRARY suitesparseconfig)
include(FindPackageHandleStandardArgs)
find_package_handle_standard_args(SuiteSparseParts
  REQUIRED_VARS SuiteSparse_INCLUDE_DIR CHOLMOD_LIBRARY UMFPACK_LIBRARY SUITESPARSECONFIG_LIBRARY)
if(SuiteSparseParts_FOUND)
  foreach(part CHOLMOD UMFPACK)
    if(NOT TARGET SuiteSparse::${part})
      add_library(SuiteSparse::${part} UNKNOWN IMPORTED)
      set_target_properties(SuiteSparse::${part} PROPERTIES
        IMPORTED_LOCATION "${${part}_LIBRARY}"
        INTERFACE_INCLUDE_DIRECTORIES "${SuiteSparse_INCLUDE_DIR}"
        INTERFACE_LINK_LIBRARIES "${SUITESPARSECONFIG_LIBRARY}")
    endif()
  endforeach()
endif()
mark_as_advanced(SuiteSparse_INCLUDE_DIR CHOLMOD_LIBRARY UMFPACK_LIBRARY SUITESPARSECONFIG_LIBRARY)

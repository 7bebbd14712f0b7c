# Finds Debian's libgmsh-dev: the Gmsh C API header (gmshc.h) and the library, which hapstate
# loads at run time with dlopen (libstate/mesh/tetrahedralize.cc says why). Defines
# GMSH_INCLUDE_DIR and GMSH_RUNTIME_LIBRARY: the library's SONAME (libgmsh.so.4.8 on Debian 12,
# installed by the runtime package and stable across its point releases), or, where objdump
# cannot tell it, the file the -dev symlink points to.
find_path(GMSH_INCLUDE_DIR gmshc.h)
find_library(GMSH_LIBRARY gmsh)
include(FindPackageHandleStandardArgs)
find_package_handle_standard_args(gmsh_lib REQUIRED_VARS GMSH_INCLUDE_DIR GMSH_LIBRARY)
if(gmsh_lib_FOUND)
  file(REAL_PATH "${GMSH_LIBRARY}" GMSH_RUNTIME_LIBRARY)
  find_program(GMSH_OBJDUMP NAMES objdump)
  if(GMSH_OBJDUMP)
    execute_process(COMMAND "${GMSH_OBJDUMP}" -p "${GMSH_RUNTIME_LIBRARY}"
                    OUTPUT_VARIABLE _gmsh_dynamic ERROR_QUIET)
    if(_gmsh_dynamic MATCHES "SONAME +([^\n ]+)")
      set(GMSH_RUNTIME_LIBRARY "${CMAKE_MATCH_1}")
    endif()
  endif()
endif()
mark_as_advanced(GMSH_INCLUDE_DIR GMSH_LIBRARY GMSH_OBJDUMP)

# Finds Debian's libgmsh-dev: the Gmsh C API header (gmshc.h) and the library, which hapstate
# loads at run time with dlopen (libstate/mesh/tetrahedralize.cc says why). Defines
# GMSH_INCLUDE_DIR and GMSH_RUNTIME_LIBRARY (the versioned file the -dev symlink points to, which
# the runtime package installs).
find_path(GMSH_INCLUDE_DIR gmshc.h)
find_library(GMSH_LIBRARY gmsh)
include(FindPackageHandleStandardArgs)
find_package_handle_standard_args(gmsh_lib REQUIRED_VARS GMSH_INCLUDE_DIR GMSH_LIBRARY)
if(gmsh_lib_FOUND)
  file(REAL_PATH "${GMSH_LIBRARY}" GMSH_RUNTIME_LIBRARY)
endif()
mark_as_advanced(GMSH_INCLUDE_DIR GMSH_LIBRARY)

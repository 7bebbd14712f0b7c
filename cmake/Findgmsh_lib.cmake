# Finds Debian's libgmsh-dev (the Gmsh C++ API, gmsh.h) and defines gmsh::gmsh.
find_path(GMSH_INCLUDE_DIR gmsh.h)
find_library(GMSH_LIBRARY gmsh)
include(FindPackageHandleStandardArgs)
find_package_handle_standard_args(gmsh_lib REQUIRED_VARS GMSH_INCLUDE_DIR GMSH_LIBRARY)
if(gmsh_lib_FOUND AND NOT TARGET gmsh::gmsh)
  add_library(gmsh::gmsh UNKNOWN IMPORTED)
  set_target_properties(gmsh::gmsh PROPERTIES
    IMPORTED_LOCATION "${GMSH_LIBRARY}" INTERFACE_INCLUDE_DIRECTORIES "${GMSH_INCLUDE_DIR}")
endif()
mark_as_advanced(GMSH_INCLUDE_DIR GMSH_LIBRARY)

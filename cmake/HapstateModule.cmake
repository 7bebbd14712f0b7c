# hapstate_module(NAME [SOURCES file...] [DEPENDS module...] [LINK target...])
#
# One library target per libstate module (docs/architecture.md): an OBJECT library
# `hapstate_<NAME>` built from SOURCES, whose objects go into hapstate::state (or another
# library that collects them). The layering is enforced by what the module's sources can see:
# their only libstate include directory is a view, ${CMAKE_BINARY_DIR}/layers/<NAME>/, holding
# a symbolic link to the module's own folder and to the folders of the modules it DEPENDS on
# (and of theirs, transitively). An `#include "scene/..."` in a module that does not depend on
# scene, e.g. an upward include from solver/, fails to build with "No such file or directory".
# LINK names the third-party targets the module's sources use (their include directories and
# compile definitions). A module without SOURCES (headers only) only declares its view.
#
# Every module must be declared after the modules it depends on.
function(hapstate_module name)
  cmake_parse_arguments(M "" "" "SOURCES;DEPENDS;LINK" ${ARGN})
  set(visible ${name})
  foreach(dep IN LISTS M_DEPENDS)
    get_property(known GLOBAL PROPERTY HAPSTATE_MODULE_VISIBLE_${dep} SET)
    if(NOT known)
      message(FATAL_ERROR "hapstate_module(${name}): '${dep}' is not a module declared before it")
    endif()
    get_property(dep_visible GLOBAL PROPERTY HAPSTATE_MODULE_VISIBLE_${dep})
    list(APPEND visible ${dep_visible})
  endforeach()
  list(REMOVE_DUPLICATES visible)
  set_property(GLOBAL PROPERTY HAPSTATE_MODULE_VISIBLE_${name} ${visible})

  set(view ${CMAKE_BINARY_DIR}/layers/${name})
  file(REMOVE_RECURSE ${view})
  file(MAKE_DIRECTORY ${view})
  foreach(module IN LISTS visible)
    file(CREATE_LINK ${HAPSTATE_LIBSTATE_DIR}/${module} ${view}/${module} SYMBOLIC)
  endforeach()

  if(M_SOURCES)
    add_library(hapstate_${name} OBJECT ${M_SOURCES})
    target_include_directories(hapstate_${name} PRIVATE ${view} ${PROJECT_SOURCE_DIR}/include)
    target_link_libraries(hapstate_${name} PRIVATE Eigen3::Eigen ${M_LINK})
  endif()
endfunction()

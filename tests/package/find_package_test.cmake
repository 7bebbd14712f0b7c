# cmake -P script: install the hapstate build tree into a scratch prefix, then configure,
# build and run tests/package/consumer against it (CMAKE_PREFIX_PATH = that prefix only).
foreach(var HAPSTATE_BUILD_DIR CONSUMER_SOURCE_DIR WORK_DIR CXX_COMPILER)
  if(NOT DEFINED ${var})
    message(FATAL_ERROR "find_package_test.cmake: -D${var}=... is required")
  endif()
endforeach()

set(prefix ${WORK_DIR}/prefix)
set(build ${WORK_DIR}/build)
file(REMOVE_RECURSE ${WORK_DIR})
file(MAKE_DIRECTORY ${WORK_DIR})

function(step name)
  execute_process(COMMAND ${ARGN} RESULT_VARIABLE rc OUTPUT_VARIABLE out ERROR_VARIABLE err)
  if(NOT rc EQUAL 0)
    message(FATAL_ERROR "${name} failed (${rc}):\n${out}\n${err}")
  endif()
  set(step_output "${out}" PARENT_SCOPE)
endfunction()

step("cmake --install" ${CMAKE_COMMAND} --install ${HAPSTATE_BUILD_DIR} --prefix ${prefix})
# The public headers and the package files must be where the config says.
foreach(f include/hapstate/solver/path_solver.h include/hapstate/mesh/box_mesh.h
          include/hapstate/scene/problem.h)
  if(NOT EXISTS ${prefix}/${f})
    message(FATAL_ERROR "not installed: ${prefix}/${f}")
  endif()
endforeach()
file(GLOB_RECURSE config ${prefix}/*/hapstateConfig.cmake)
if(NOT config)
  message(FATAL_ERROR "hapstateConfig.cmake not installed under ${prefix}")
endif()

step("configure consumer" ${CMAKE_COMMAND} -S ${CONSUMER_SOURCE_DIR} -B ${build}
     -DCMAKE_BUILD_TYPE=Release -DCMAKE_CXX_COMPILER=${CXX_COMPILER}
     -DCMAKE_PREFIX_PATH=${prefix} -DCMAKE_FIND_USE_PACKAGE_REGISTRY=OFF)
step("build consumer" ${CMAKE_COMMAND} --build ${build} -j2)
step("run consumer" ${build}/consumer)
message(STATUS "${step_output}")
if(NOT step_output MATCHES "consumer: [0-9]+ nodes, [0-9]+ iterations, force felt = ")
  message(FATAL_ERROR "consumer printed no force: ${step_output}")
endif()

# cmake -P script: install the hapstate build tree into a scratch prefix, then configure,
# build and run tests/package/consumer against it (CMAKE_PREFIX_PATH = that prefix only).
foreach(var HAPSTATE_BUILD_DIR CONSUMER_SOURCE_DIR WORK_DIR CXX_COMPILER SCENE)
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
# The public headers are installed, and only they: include/hapstate/*.h, nothing below it.
foreach(f include/hapstate/solver.h include/hapstate/error.h include/hapstate/playback.h
          include/hapstate/playback_c.h)
  if(NOT EXISTS ${prefix}/${f})
    message(FATAL_ERROR "not installed: ${prefix}/${f}")
  endif()
endforeach()
file(GLOB_RECURSE installed_headers RELATIVE ${prefix}/include ${prefix}/include/*)
foreach(h IN LISTS installed_headers)
  if(NOT h MATCHES "^hapstate/[a-z_]+\\.h$")
    message(FATAL_ERROR "an internal header is installed: include/${h}")
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
step("run consumer" ${build}/consumer ${SCENE} ${WORK_DIR})
message(STATUS "${step_output}")
if(NOT step_output MATCHES "consumer: [0-9]+ nodes, [0-9]+ iterations, force felt = "
   OR NOT step_output MATCHES "consumer: bad scene refused: ")
  message(FATAL_ERROR "consumer printed no force or no refusal: ${step_output}")
endif()

# ctest consumer_find_package: install this build into a fresh prefix, then configure, build and
# run tests/consumer/project against that prefix only, as an outside project would.
#   cmake -DBUILD=<this build tree> -DWORK=<scratch folder> -DSOURCE=<tests/consumer/project>
#         -DGENERATOR=<generator> -DCXX=<C++ compiler> -DC=<C compiler> [-DLAUNCHER=ccache] -P run_consumer.cmake
cmake_minimum_required(VERSION 3.25)
foreach(var BUILD WORK SOURCE GENERATOR CXX C)
  if(NOT DEFINED ${var})
    message(FATAL_ERROR "run_consumer.cmake: -D${var}=... is required")
  endif()
endforeach()

function(run step)
  execute_process(COMMAND ${ARGN} RESULT_VARIABLE rc OUTPUT_VARIABLE out ERROR_VARIABLE err)
  if(NOT rc EQUAL 0)
    message(FATAL_ERROR "consumer ${step} failed (${rc}):\n${out}\n${err}")
  endif()
  message(STATUS "consumer ${step}: ok")
  set(last_output "${out}${err}" PARENT_SCOPE)
endfunction()

set(prefix ${WORK}/prefix)
file(REMOVE_RECURSE ${WORK})
run(install ${CMAKE_COMMAND} --install ${BUILD} --prefix ${prefix})

set(launcher)
if(LAUNCHER)
  set(launcher -DCMAKE_CXX_COMPILER_LAUNCHER=${LAUNCHER})
endif()
# CMAKE_FIND_USE_PACKAGE_REGISTRY=OFF and only the prefix on CMAKE_PREFIX_PATH: the package must
# come from the installed tree, never from this build tree.
run(configure ${CMAKE_COMMAND} -S ${SOURCE} -B ${WORK}/build -G ${GENERATOR} -DCMAKE_BUILD_TYPE=Release
    -DCMAKE_CXX_COMPILER=${CXX} -DCMAKE_C_COMPILER=${C} ${launcher}
    -DCMAKE_PREFIX_PATH=${prefix} -DCMAKE_FIND_USE_PACKAGE_REGISTRY=OFF
    -Dhermite_sdf_DIR=${prefix}/lib/cmake/hermite_sdf)
run(build ${CMAKE_COMMAND} --build ${WORK}/build)
run(run ${WORK}/build/torus_frame)
message(STATUS "${last_output}")
run(own_feature ${WORK}/build/corner_frame)
message(STATUS "${last_output}")

# ctest gltf_testdata_validator_live: runs the Khronos glTF validator (npm gltf-validator, installed
# by `npm ci` in tools/gltf_testdata) over the valid test files again. Skipped (exit 77) when node or
# the npm packages are absent, so that the suite never needs the network.
#   cmake -DDIR=tests/data/gltf -DTOOLS=tools/gltf_testdata -DWORK=<scratch> -P run_validator.cmake
cmake_minimum_required(VERSION 3.25)
find_program(NODE node)
if(NOT NODE OR NOT EXISTS ${TOOLS}/node_modules/gltf-validator)
  message(STATUS "skipped: node or ${TOOLS}/node_modules/gltf-validator missing (cd ${TOOLS} && npm ci)")
  cmake_language(EXIT 77)
endif()
file(READ ${DIR}/validation.json report)
string(JSON count LENGTH "${report}" files)
math(EXPR last "${count} - 1")
set(paths)
foreach(i RANGE ${last})
  string(JSON name MEMBER "${report}" files ${i})
  list(APPEND paths ${DIR}/${name})
endforeach()
file(MAKE_DIRECTORY ${WORK})
execute_process(COMMAND ${NODE} ${TOOLS}/validate.mjs ${WORK}/validation.json ${paths}
                WORKING_DIRECTORY ${TOOLS} RESULT_VARIABLE rc OUTPUT_VARIABLE out ERROR_VARIABLE err)
message(STATUS "${out}")
if(NOT rc EQUAL 0)
  message(FATAL_ERROR "the glTF validator reported errors (or failed):\n${out}\n${err}")
endif()

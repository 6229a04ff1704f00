# A mesh bakes to the same cells at any scale: the tilted cube, and the same cube scaled by 2^100
# (1.3e30 across) and 2^-17 (1.3e-5 across). Powers of two scale every distance exactly, so the
# classification line (crossing / ambiguous / empty counts) must be identical, and each file must
# pass --inspect. At 2^100 the squared float pruning bounds of the mesh source overflowed and
# hsdf_bake crashed (SIGSEGV).
set(reference "")
foreach(scene tilted_cube tilted_cube_2e100 tilted_cube_2e-17)
  set(file ${WORK}/scale_${scene}.hsdf)
  execute_process(COMMAND ${BAKE} ${DATA}/${scene}.gltf -o ${file} -r 8 -q
                  RESULT_VARIABLE rc OUTPUT_VARIABLE out ERROR_VARIABLE err)
  if(NOT rc EQUAL 0)
    message(FATAL_ERROR "hsdf_bake ${scene}.gltf failed (${rc}):\n${out}\n${err}")
  endif()
  string(REGEX MATCH "cells [0-9]+: crossing [^\n]*" cells "${out}")
  if(cells STREQUAL "" OR cells MATCHES "kept 0,")
    message(FATAL_ERROR "${scene}.gltf: no cells kept:\n${out}")
  endif()
  if(reference STREQUAL "")
    set(reference "${cells}")
  elseif(NOT cells STREQUAL reference)
    message(FATAL_ERROR "${scene}.gltf classifies differently from the unit cube:\n  ${cells}\n  ${reference}")
  endif()
  execute_process(COMMAND ${BAKE} --inspect ${file} RESULT_VARIABLE rc OUTPUT_VARIABLE out ERROR_VARIABLE err)
  if(NOT rc EQUAL 0)
    message(FATAL_ERROR "hsdf_bake --inspect ${file} failed (${rc}):\n${out}\n${err}")
  endif()
endforeach()

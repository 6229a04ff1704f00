# ctest gltf_testdata_validated: every glTF file in tests/data/gltf/ is either deliberately broken
# (listed below) or recorded in validation.json, written by tools/gltf_testdata/validate.mjs (the
# Khronos glTF validator), with 0 errors and the SHA-256 of the committed file. Needs no network:
# the validator ran when the files were made; this proves the committed files are those.
#   cmake -DDIR=tests/data/gltf -P check_validation_report.cmake
cmake_minimum_required(VERSION 3.25)
set(broken empty.gltf missing_buffer.gltf not_json.gltf)

file(READ ${DIR}/validation.json report)
string(JSON validator GET "${report}" validator)
file(GLOB files RELATIVE ${DIR} ${DIR}/*.gltf ${DIR}/*.glb)
set(checked 0)
foreach(name IN LISTS files)
  if(name IN_LIST broken)
    continue()
  endif()
  string(JSON entry ERROR_VARIABLE missing GET "${report}" files ${name})
  if(missing)
    message(FATAL_ERROR "${name} is not in validation.json: run tools/gltf_testdata/make_testdata.sh (or list it as broken here)")
  endif()
  string(JSON recorded GET "${entry}" sha256)
  string(JSON errors GET "${entry}" errors)
  file(SHA256 ${DIR}/${name} actual)
  if(NOT recorded STREQUAL actual)
    message(FATAL_ERROR "${name} changed since ${validator} checked it (sha256 ${actual}, report ${recorded}): re-run tools/gltf_testdata/make_testdata.sh")
  endif()
  if(NOT errors EQUAL 0)
    message(FATAL_ERROR "${name}: ${validator} reported ${errors} errors")
  endif()
  math(EXPR checked "${checked} + 1")
endforeach()
message(STATUS "${checked} glTF files validated by ${validator} with 0 errors, unchanged since")

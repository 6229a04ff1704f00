# perf_capture with no Vulkan driver to load (VK_ICD_FILENAMES / VK_DRIVER_FILES naming nothing):
# refused naming why, with no empty images folder left in --out (one was, before any image).
file(REMOVE_RECURSE "${OUT}")
execute_process(
  COMMAND ${CMAKE_COMMAND} -E env VK_ICD_FILENAMES=/nonexistent/icd.json VK_DRIVER_FILES=/nonexistent/icd.json
          "${CAPTURE}" --out "${OUT}" --quick --methods cells
  RESULT_VARIABLE rc OUTPUT_VARIABLE out ERROR_VARIABLE err)
if(rc EQUAL 0)
  message(FATAL_ERROR "perf_capture without a Vulkan driver exited 0:\n${out}${err}")
endif()
if(NOT "${out}${err}" MATCHES "no Vulkan driver found")
  message(FATAL_ERROR "perf_capture without a Vulkan driver did not say so:\n${out}${err}")
endif()
if(EXISTS "${OUT}/images")
  message(FATAL_ERROR "perf_capture without a Vulkan driver left '${OUT}/images'")
endif()
message(STATUS "refused, nothing left: ${err}")

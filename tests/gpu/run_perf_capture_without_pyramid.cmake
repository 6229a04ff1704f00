# perf_capture's occlusion-culling row when the depth pyramid cannot be made (its shader missing):
# the frames are still right, only not culled, so the row would be a measurement of something else.
#   cmake -DCAPTURE=<perf_capture> -DSHADERS=<build shader dir> -DWORK=<folder> -P run_perf_capture_without_pyramid.cmake
# What would break: the row measured and reported as passing (exit 0) without occlusion culling.
file(REMOVE_RECURSE "${WORK}")
file(MAKE_DIRECTORY "${WORK}/shaders")
file(GLOB spv "${SHADERS}/*.spv")
list(FILTER spv EXCLUDE REGEX "depth_pyramid\\.comp\\.spv$")
file(COPY ${spv} DESTINATION "${WORK}/shaders")
set(ENV{HSDF_SHADER_DIR} "${WORK}/shaders")
execute_process(COMMAND "${CAPTURE}" --out "${WORK}/out" --quick --methods cells --settings "n=3 r=1 occlusion"
                        --resolutions 16 --views 1 --frames 1 --warmup 0
                RESULT_VARIABLE rc ERROR_VARIABLE err OUTPUT_VARIABLE out)
if(rc EQUAL 0)
  message(FATAL_ERROR "the occlusion row passed without a depth pyramid:\n${err}")
endif()
file(READ "${WORK}/out/results.md" md)
if(NOT md MATCHES "occlusion K=16 \\| failed: occlusion culling culls nothing: depth pyramid: [^|]*depth_pyramid.comp")
  message(FATAL_ERROR "results.md does not name why the occlusion row failed:\n${md}")
endif()
message(STATUS "the occlusion row failed, naming the missing depth pyramid")

# scene_runner --lod, one headless frame: the screenshot shows the level the view picks, as a
# run at that level's K draws it. The level bakes ran on worker threads and the one frame drew
# K = 64 while they baked (found by a helper); now the runner waits for them as for a comparison.
# From 120 units, 320x240, the bunny's cells are about 0.9 px at K = 32 and 1.9 px at K = 16: the level
# is K = 32 at the default 2 px per cell.
set(camera --camera 0 5 120 0 5 0 --size 320x240 --method cells --no-ground)
execute_process(COMMAND ${RUNNER} --headless --validation --resolution 64 --lod ${camera}
                --screenshot ${WORK}/lod_first_frame.png RESULT_VARIABLE rc OUTPUT_VARIABLE out ERROR_VARIABLE err)
if(NOT rc EQUAL 0)
  message(FATAL_ERROR "scene_runner --lod failed (${rc}):\n${out}${err}")
endif()
execute_process(COMMAND ${RUNNER} --headless --validation --resolution 32 ${camera}
                --screenshot ${WORK}/lod_k32.png RESULT_VARIABLE rc OUTPUT_VARIABLE out ERROR_VARIABLE err)
if(NOT rc EQUAL 0)
  message(FATAL_ERROR "scene_runner --resolution 32 failed (${rc}):\n${out}${err}")
endif()
file(SHA256 ${WORK}/lod_first_frame.png lodImage)
file(SHA256 ${WORK}/lod_k32.png levelImage)
if(NOT lodImage STREQUAL levelImage)
  message(FATAL_ERROR "the first --lod frame is not the K = 32 level's image (lod_first_frame.png, lod_k32.png)")
endif()

# Runs the scene runner headless and checks that it wrote a non-trivial PNG.
file(REMOVE ${OUT})
execute_process(COMMAND ${RUNNER} --headless --validation --size 160x120 --frames 2 --screenshot ${OUT}
                RESULT_VARIABLE rc OUTPUT_VARIABLE out ERROR_VARIABLE err)
if(NOT rc EQUAL 0)
  message(FATAL_ERROR "scene_runner failed (${rc}):\n${out}\n${err}")
endif()
if(NOT EXISTS ${OUT})
  message(FATAL_ERROR "scene_runner did not write ${OUT}")
endif()
file(SIZE ${OUT} size)
if(size LESS 2000)
  message(FATAL_ERROR "${OUT} is suspiciously small (${size} bytes)")
endif()

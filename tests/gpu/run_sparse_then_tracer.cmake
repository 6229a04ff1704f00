# A scene baked sparsely (cells past K = 256: no dense field) whose method becomes a sphere tracer
# in the next frame: the tracer needs a dense re-bake, and until it lands the frames draw the cells
# (tuning.h, drawableMethod). Before, the next frame failed ("field has 0 samples") and the runner
# exited 1, from a script as from the panel.
file(WRITE ${WORK}/sparse_then_tracer.txt "frame 1: method=trilinear\nframe 2: wait-bake\n")
execute_process(COMMAND ${RUNNER} --headless --validation --scene ${SCENE} --resolution 260 --size 96x64 --frames 4
                --script ${WORK}/sparse_then_tracer.txt --screenshot ${WORK}/sparse_then_tracer.png
                RESULT_VARIABLE rc OUTPUT_VARIABLE out ERROR_VARIABLE err)
if(NOT rc EQUAL 0)
  message(FATAL_ERROR "a tracer picked while its dense re-bake runs failed the run (${rc}):\n${out}${err}")
endif()
if(NOT "${out}${err}" MATCHES "re-baked at resolution 260")
  message(FATAL_ERROR "the dense re-bake did not land:\n${out}${err}")
endif()

# hsdf_bake -> .hsdf -> scene_runner --sdf: a baked file drawn by every method it supports, and a
# cells-only file refused for a sphere-tracing method with a message naming the file, on the
# command line for the method drawn and for the compared side; a tracer asked for later (a script,
# the panel) draws the file's cells, the same image as --method cells, and says why. Before, the
# frame failed and the runner exited 1 ("resolution 0 exceeds the device's 3D texture size").
set(dense ${WORK}/torus_dense.hsdf)
set(cells ${WORK}/torus_cells.hsdf)
execute_process(COMMAND ${BAKE} torus -o ${dense} -r 20 -q RESULT_VARIABLE rc)
if(NOT rc EQUAL 0)
  message(FATAL_ERROR "hsdf_bake (dense) failed: ${rc}")
endif()
execute_process(COMMAND ${BAKE} torus -o ${cells} -r 20 --cells --fp16 -q RESULT_VARIABLE rc)
if(NOT rc EQUAL 0)
  message(FATAL_ERROR "hsdf_bake (cells) failed: ${rc}")
endif()
foreach(run "${dense};cells" "${dense};hermite" "${dense};trilinear" "${cells};cells")
  list(GET run 0 file)
  list(GET run 1 method)
  execute_process(COMMAND ${RUNNER} --headless --validation --sdf ${file} --method ${method} --size 96x64
                  --screenshot ${WORK}/sdf_${method}.png RESULT_VARIABLE rc ERROR_VARIABLE err)
  if(NOT rc EQUAL 0)
    message(FATAL_ERROR "scene_runner --sdf ${file} --method ${method} failed (${rc}):\n${err}")
  endif()
endforeach()
execute_process(COMMAND ${RUNNER} --headless --sdf ${cells} --method hermite RESULT_VARIABLE rc ERROR_VARIABLE err)
if(rc EQUAL 0 OR NOT err MATCHES "torus_cells.hsdf: holds only cells")
  message(FATAL_ERROR "a cells-only file must be refused for --method hermite with a clear message, got (${rc}): ${err}")
endif()
execute_process(COMMAND ${RUNNER} --headless --sdf ${cells} --split vertical RESULT_VARIABLE rc ERROR_VARIABLE err)
if(rc EQUAL 0 OR NOT err MATCHES "torus_cells.hsdf: holds only cells; the compared side")
  message(FATAL_ERROR "a cells-only file must be refused for a traced compared side with a clear message, got (${rc}): ${err}")
endif()
file(WRITE ${WORK}/sdf_trace_later.txt "frame 1: method=trilinear\nframe 2: method=hermite\n")
execute_process(COMMAND ${RUNNER} --headless --validation --sdf ${cells} --size 96x64 --frames 4
                --script ${WORK}/sdf_trace_later.txt --screenshot ${WORK}/sdf_trace_later.png
                RESULT_VARIABLE rc OUTPUT_VARIABLE out ERROR_VARIABLE err)
if(NOT rc EQUAL 0 OR NOT "${out}${err}" MATCHES "holds only cells: the sphere tracers need the dense field")
  message(FATAL_ERROR "a tracer asked for by a script must draw the cells and say so, got (${rc}):\n${out}${err}")
endif()
file(SHA256 ${WORK}/sdf_cells.png cellsImage)
file(SHA256 ${WORK}/sdf_trace_later.png laterImage)
if(NOT cellsImage STREQUAL laterImage)
  message(FATAL_ERROR "the cells drawn for a tracer differ from --method cells (sdf_cells.png, sdf_trace_later.png)")
endif()
# What a .hsdf file cannot do is refused when a script asks for it, as on the command line, naming
# the script's line (before: method=mesh drew only the ground, resolution=16 was ignored); the
# settings the runner saves say the K the file was baked with (before: the default, 64).
foreach(run "method=mesh;this scene has no triangles" "resolution=16;drawn as it was baked \\(K = 20\\)" "shell=0.1;shell 0.1: a .hsdf file is drawn as it was baked"
            "lod=true;a .hsdf file has no source")
  list(GET run 0 line)
  list(GET run 1 expected)
  file(WRITE ${WORK}/sdf_refused.txt "frame 1: ${line}\n")
  execute_process(COMMAND ${RUNNER} --headless --sdf ${dense} --size 32x32 --frames 3 --script ${WORK}/sdf_refused.txt
                  RESULT_VARIABLE rc OUTPUT_VARIABLE out ERROR_VARIABLE err)
  if(rc EQUAL 0 OR NOT "${out}${err}" MATCHES "sdf_refused.txt:1: .*${expected}")
    message(FATAL_ERROR "script '${line}' on a .hsdf file must be refused naming the line, got (${rc}):\n${out}${err}")
  endif()
endforeach()
execute_process(COMMAND ${RUNNER} --headless --sdf ${dense} --size 32x32 --save-settings ${WORK}/sdf_settings.json
                RESULT_VARIABLE rc ERROR_VARIABLE err)
file(READ ${WORK}/sdf_settings.json saved)
if(NOT rc EQUAL 0 OR NOT saved MATCHES "\"resolution\": 20,")
  message(FATAL_ERROR "the saved settings of a .hsdf file must say its K (20), got (${rc}): ${saved}${err}")
endif()
# A file baked with --refine keeps its refined cells when drawn: the loader classified the stored
# field again, at depth 0, and drew the cells refinement had dropped (found by a helper).
execute_process(COMMAND ${BAKE} sphere -o ${WORK}/sphere_refined.hsdf -r 32 --refine 2 RESULT_VARIABLE rc OUTPUT_VARIABLE baked)
string(REGEX MATCH "kept ([0-9]+), refined to empty ([0-9]+)" found "${baked}")
if(NOT rc EQUAL 0 OR NOT found OR CMAKE_MATCH_2 EQUAL 0)
  message(FATAL_ERROR "hsdf_bake --refine 2 must refine some cells for this test (${rc}): ${baked}")
endif()
set(kept ${CMAKE_MATCH_1})
execute_process(COMMAND ${RUNNER} --headless --validation --sdf ${WORK}/sphere_refined.hsdf --size 64x48
                RESULT_VARIABLE rc OUTPUT_VARIABLE out ERROR_VARIABLE err)
if(NOT rc EQUAL 0 OR NOT "${out}${err}" MATCHES "cell objects: 1 drawn \\(${kept} cells\\)")
  message(FATAL_ERROR "a refined file must draw its ${kept} stored cells, got (${rc}):\n${out}${err}")
endif()

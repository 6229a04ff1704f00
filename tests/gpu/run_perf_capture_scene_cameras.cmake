# perf_capture --scene-cameras end to end: a scene measured from its own glTF camera nodes.
#   cmake -DCAPTURE=<perf_capture> -DRUNNER=<scene_runner> -DPROBE=<png_probe> -DSCENE=<camera_cube.gltf>
#         -DOUT=<folder> -P run_perf_capture_scene_cameras.cmake
# The device: as run_perf_capture_quick.cmake (hsdf_test_device_run sets HSDF_DEVICE).
# What would break: the views not being the cameras asked for (the count, the names in results.md);
# the timed frames drawn from other cameras than asked (the first view's image must be the scene
# runner's through the same camera, pixel for pixel: both draw through samples::Viewer); the ground
# truth cast from other cameras than the measured frames: then the coverage mismatch is of the
# order of the covered pixels, where the cells at K = 16 miss about 5 % of them (the cube's corners,
# rounded by the interpolant).
cmake_policy(SET CMP0054 NEW)
file(REMOVE_RECURSE "${OUT}")
execute_process(COMMAND "${CAPTURE}" --out "${OUT}" --scene "${SCENE}" --scene-cameras front,tilted --size 160x120
                        --resolutions 16 --methods cells --settings "n=3 r=1" --frames 1 --warmup 0
                RESULT_VARIABLE rc ERROR_VARIABLE err)
if(NOT rc EQUAL 0)
  message(FATAL_ERROR "perf_capture --scene-cameras failed (${rc}):\n${err}")
endif()
file(READ "${OUT}/results.md" md)
string(FIND "${md}" "2 views (the scene's cameras: front, tilted)" named)
if(named EQUAL -1)
  message(FATAL_ERROR "results.md does not name the two cameras as its views")
endif()
file(READ "${OUT}/results.json" json)
string(JSON rows LENGTH "${json}" rows)
if(NOT rows EQUAL 1)
  message(FATAL_ERROR "expected one row, got ${rows}")
endif()
string(JSON views GET "${json}" views)
string(JSON ok GET "${json}" rows 0 ok)
string(JSON covered GET "${json}" rows 0 covered_pixels)
string(JSON mismatch GET "${json}" rows 0 coverage_mismatch)
if(NOT views EQUAL 2 OR NOT ok)
  message(FATAL_ERROR "views ${views}, ok ${ok}")
endif()
# covered_pixels sums the views; coverage_mismatch is per view.
math(EXPR coveredPerView "${covered} / ${views}")
string(REGEX REPLACE "\\..*" "" mismatchPixels "${mismatch}")
math(EXPR limit "${coveredPerView} / 4")
if(coveredPerView LESS 1000 OR NOT mismatchPixels LESS limit)
  message(FATAL_ERROR "covered ${coveredPerView} pixels per view with ${mismatch} mismatching: the frames and the "
                      "ground truth do not see the scene from the same cameras")
endif()
execute_process(COMMAND "${RUNNER}" --headless --scene "${SCENE}" --scene-camera front --size 160x120 --method cells
                        --resolution 16 --no-ground --screenshot "${OUT}/runner_front.png"
                RESULT_VARIABLE rc ERROR_VARIABLE err)
if(NOT rc EQUAL 0)
  message(FATAL_ERROR "scene_runner --scene-camera front failed (${rc}):\n${err}")
endif()
execute_process(COMMAND "${PROBE}" "${OUT}/images/cells_n_3_r_1_K_16.png" "${OUT}/runner_front.png"
                OUTPUT_VARIABLE probe RESULT_VARIABLE rc)
if(NOT rc EQUAL 0 OR NOT probe MATCHES "differs 0.0000")
  message(FATAL_ERROR "the capture's first view is not the scene runner's frame through camera 'front': ${probe}")
endif()
message(STATUS "scene cameras: ${coveredPerView} covered pixels per view, ${mismatch} mismatching")

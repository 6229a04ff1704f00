# The scene runner frames and draws a scene the same way at any scale it accepts: the tilted cube
# and the same cube scaled by 2^-17 (1.3e-5 across; a power of two, so every float computation
# scales exactly) must give byte-identical screenshots, with the mesh and with the baked cells.
# Before the camera framing was made relative, the small one came out empty (a fixed 1e-3 minimum
# orbit radius and 1e-4 near plane). The unit image must not be empty itself: with --no-ground an
# empty frame is one flat colour; png_probe's coverage is the share of pixels unlike the corner's.
# (The file's size told before: the flat-shaded mesh, three faces of one colour each, compresses to
# 611 bytes.)
foreach(method mesh cells)
  foreach(scene tilted_cube tilted_cube_2e-17)
    set(png ${WORK}/scale_${scene}_${method}.png)
    file(REMOVE ${png})
    execute_process(COMMAND ${RUNNER} --headless --validation --no-ground --size 96x64 --method ${method}
                            --resolution 12 --scene ${DATA}/${scene}.gltf --screenshot ${png}
                    RESULT_VARIABLE rc ERROR_VARIABLE err)
    if(NOT rc EQUAL 0)
      message(FATAL_ERROR "scene_runner --scene ${scene}.gltf --method ${method} failed (${rc}):\n${err}")
    endif()
  endforeach()
  execute_process(COMMAND ${PROBE} ${WORK}/scale_tilted_cube_${method}.png OUTPUT_VARIABLE probe RESULT_VARIABLE rc)
  string(REGEX MATCH "coverage ([0-9.]+)" found "${probe}")
  if(NOT rc EQUAL 0 OR NOT found)
    message(FATAL_ERROR "png_probe failed on the unit cube's image: ${probe}")
  endif()
  if(CMAKE_MATCH_1 LESS 0.05)
    message(FATAL_ERROR "the unit cube drawn with ${method} looks empty: ${probe}")
  endif()
  execute_process(COMMAND ${CMAKE_COMMAND} -E compare_files ${WORK}/scale_tilted_cube_${method}.png
                          ${WORK}/scale_tilted_cube_2e-17_${method}.png RESULT_VARIABLE differ)
  if(NOT differ EQUAL 0)
    message(FATAL_ERROR "--method ${method}: the cube 2^-17 times smaller is drawn differently from the unit cube")
  endif()
endforeach()

# fp16 cannot hold the tiny cube's field (spacing below 2^-13: the values near the surface would be
# fp16 subnormals, 116 colour values off by up to 170 when they were used); halfPrecision must fall
# back to the fp32 data there, so --fp16 draws exactly what fp32 draws, for cells and textures.
foreach(method cells trilinear)
  foreach(precision fp32 fp16)
    set(png ${WORK}/scale_tiny_${method}_${precision}.png)
    file(REMOVE ${png})
    set(flag "")
    if(precision STREQUAL "fp16")
      set(flag --fp16)
    endif()
    execute_process(COMMAND ${RUNNER} --headless --validation --no-ground --size 96x64 --method ${method} ${flag}
                            --resolution 12 --scene ${DATA}/tilted_cube_2e-17.gltf --screenshot ${png}
                    RESULT_VARIABLE rc ERROR_VARIABLE err)
    if(NOT rc EQUAL 0)
      message(FATAL_ERROR "scene_runner --method ${method} ${flag} on the tiny cube failed (${rc}):\n${err}")
    endif()
  endforeach()
  execute_process(COMMAND ${CMAKE_COMMAND} -E compare_files ${WORK}/scale_tiny_${method}_fp32.png
                          ${WORK}/scale_tiny_${method}_fp16.png RESULT_VARIABLE differ)
  if(NOT differ EQUAL 0)
    message(FATAL_ERROR "--method ${method} --fp16: the tiny cube is not drawn from fp32 data")
  endif()
endforeach()

# The scene runner frames and draws a scene the same way at any scale it accepts: the tilted cube
# and the same cube scaled by 2^-17 (1.3e-5 across; a power of two, so every float computation
# scales exactly) must give byte-identical screenshots, with the mesh and with the baked cells.
# Before the camera framing was made relative, the small one came out empty (a fixed 1e-3 minimum
# orbit radius and 1e-4 near plane). The unit image must not be empty itself: with --no-ground an
# empty frame is one flat colour and compresses to a few hundred bytes.
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
  file(SIZE ${WORK}/scale_tilted_cube_${method}.png size)
  if(size LESS 1000)
    message(FATAL_ERROR "the unit cube drawn with ${method} looks empty (${size} bytes)")
  endif()
  execute_process(COMMAND ${CMAKE_COMMAND} -E compare_files ${WORK}/scale_tilted_cube_${method}.png
                          ${WORK}/scale_tilted_cube_2e-17_${method}.png RESULT_VARIABLE differ)
  if(NOT differ EQUAL 0)
    message(FATAL_ERROR "--method ${method}: the cube 2^-17 times smaller is drawn differently from the unit cube")
  endif()
endforeach()

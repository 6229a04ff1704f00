# perf_capture --lod: a row with levels of detail holds every level (K, K/2, ...) and draws the
# ones its views pick. Its storage is all of them, more than the row at K alone; its cells are
# those of the levels drawn, fewer than K's where the views pick a coarser level (from 6 units,
# 320x240: K = 32 for the bunny at K = 64). The rows reported level 0's storage and cells for both
# (found by a helper).
file(REMOVE_RECURSE "${OUT}")
execute_process(COMMAND ${CAPTURE} --device lavapipe --out ${OUT} --methods cells --settings "n=3 r=1" --resolutions 64
                        --lod --distance 6 --views 2 --frames 1 --warmup 0 --size 320x240
                RESULT_VARIABLE rc OUTPUT_VARIABLE out ERROR_VARIABLE err)
if(NOT rc EQUAL 0)
  message(FATAL_ERROR "perf_capture --lod failed (${rc}):\n${out}${err}")
endif()
file(STRINGS "${OUT}/results.csv" lines)
foreach(line IN LISTS lines)
  string(REPLACE "," ";" fields "${line}")
  list(GET fields 17 bytes)
  list(GET fields 18 cells)
  list(GET fields -1 label)
  if(label STREQUAL "cells n=3 r=1 K=64")
    set(kBytes ${bytes})
    set(kCells ${cells})
  elseif(label STREQUAL "cells n=3 r=1 lod K=64")
    set(lodBytes ${bytes})
    set(lodCells ${cells})
  endif()
endforeach()
if(NOT DEFINED kBytes OR NOT DEFINED lodBytes)
  message(FATAL_ERROR "missing the K = 64 rows with and without levels of detail:\n${lines}")
endif()
if(NOT lodBytes GREATER kBytes)
  message(FATAL_ERROR "the levels of detail row stores ${lodBytes} B, not more than K = 64 alone (${kBytes} B)")
endif()
if(NOT lodCells LESS kCells)
  message(FATAL_ERROR "the levels of detail row draws ${lodCells} cells, not fewer than K = 64 (${kCells})")
endif()

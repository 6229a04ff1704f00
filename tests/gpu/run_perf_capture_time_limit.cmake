# perf_capture --time-limit: a capture that runs out of time still writes every output.
#   cmake -DCAPTURE=<perf_capture> -DOUT=<folder> -P run_perf_capture_time_limit.cmake
# A limit of 1 ms is reached before any row starts: the first row is measured anyway (a capture
# always measures one), the three others are listed as not run, and the exit code says rows failed.
# What would break: rows run past the limit (four measured rows); nothing written when rows did
# not run (a missing results.csv / results.json / results.md); a not-run row that looks measured
# (numbers in its CSV fields, "ok": true) or that does not say why; a zero exit code.
cmake_policy(SET CMP0054 NEW)
file(REMOVE_RECURSE "${OUT}")
execute_process(COMMAND "${CAPTURE}" --quick --out "${OUT}" --methods hermite,cells --settings "n=3 r=1"
                        --time-limit 0.001
                RESULT_VARIABLE rc ERROR_VARIABLE err)
if(rc EQUAL 0)
  message(FATAL_ERROR "perf_capture exited 0 although rows were not run:\n${err}")
endif()
foreach(f results.csv results.json results.md)
  if(NOT EXISTS "${OUT}/${f}")
    message(FATAL_ERROR "missing output ${f}:\n${err}")
  endif()
endforeach()
file(STRINGS "${OUT}/results.csv" lines)
list(LENGTH lines count)
if(NOT count EQUAL 5)
  message(FATAL_ERROR "results.csv has ${count} lines, expected a header and 4 rows")
endif()
list(GET lines 1 first)
if(NOT first MATCHES "^hermite,16,0,0,exact,320,180,2,2,[0-9]")
  message(FATAL_ERROR "the first row was not measured: ${first}")
endif()
foreach(i 2 3 4)
  list(GET lines ${i} row)
  if(NOT row MATCHES "^[a-z]+,[0-9]+,[0-9]+,[0-9]+,[a-z]+,320,180,2,2,,,,,,,,,,,,,,,,,\"")
    message(FATAL_ERROR "row ${i} is not listed as not run: ${row}")
  endif()
endforeach()
# How many times `regex` occurs in file `name`, which must be `expected`.
function(expect_matches name regex expected)
  file(READ "${OUT}/${name}" text)
  string(REGEX MATCHALL "${regex}" found "${text}")
  list(LENGTH found count)
  if(NOT count EQUAL expected)
    message(FATAL_ERROR "${name}: '${regex}' found ${count} times, expected ${expected}")
  endif()
endfunction()
expect_matches(results.json "\"ok\": true" 1)  # only the first row measured
expect_matches(results.md "not run: --time-limit 0.001 s reached" 3)

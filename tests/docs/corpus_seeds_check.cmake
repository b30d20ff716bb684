# data/corpus_seeds/summary.json (scripts/corpus-seeds.sh) belongs to the same code as luts/: its
# seed-1 record is `gtbake all`'s own corpus, Monte Carlo seed and fit, so each of its figures
# must equal luts/fit/fit.json's. A summary left over from older code or another corpus fails here.
# Run: cmake -DSUMMARY=... -DFIT=... -P corpus_seeds_check.cmake
file(READ "${SUMMARY}" summary)
file(READ "${FIT}" fit)
string(JSON seeds LENGTH "${summary}" seeds)
set(found -1)
math(EXPR last "${seeds} - 1")
foreach(i RANGE ${last})
  string(JSON seed GET "${summary}" seeds ${i} seed)
  if(seed EQUAL 1)
    set(found ${i})
  endif()
endforeach()
if(found EQUAL -1)
  message(FATAL_ERROR "${SUMMARY} has no record for seed 1")
endif()
# Pairs "record key|path into fit.json", each path's parts separated by spaces.
set(pairs
    "scenes|scene_jackknife n"
    "types|type_jackknife n"
    "detectable_difference|shipped against_band detectable_difference largest value"
    "scene_band_max|scene_jackknife band_max value"
    "type_band_max|type_jackknife band_max value"
    "paper_ratio_to_band|shipped against_band max_ratio_to_band"
    "paper_max_curve_difference|shipped max_curve_difference value")
foreach(coeff a1 a0 b1 b0 c1 c0)
  list(APPEND pairs "linear ${coeff}|linear ${coeff}")
endforeach()
set(failures 0)
foreach(pair IN LISTS pairs)
  string(REPLACE "|" ";" parts "${pair}")
  list(GET parts 0 key)
  list(GET parts 1 path)
  string(REPLACE " " ";" key_path "${key}")
  string(REPLACE " " ";" fit_path "${path}")
  string(JSON want GET "${summary}" seeds ${found} ${key_path})
  string(JSON got GET "${fit}" ${fit_path})
  # EQUAL compares the two as numbers (doubles), so 17-digit and shortest forms agree.
  if(NOT want EQUAL got)
    message(SEND_ERROR "seed 1 '${key}' is ${want} in ${SUMMARY} but ${got} in ${FIT}")
    math(EXPR failures "${failures} + 1")
  endif()
endforeach()
if(failures GREATER 0)
  message(FATAL_ERROR "regenerate it: scripts/corpus-seeds.sh OUT, then copy OUT/summary.json")
endif()
message(STATUS "seed 1 of ${SUMMARY} agrees with ${FIT}")

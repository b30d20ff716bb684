# Runs the same small sweep through gtbake (AVX2 clones where the CPU has them) and through
# portable_sweep (default path only), and requires byte-identical EXR files. Two scenes with very
# different walks (bowls and clutter), an odd resolution (vector tails) and 2 threads.
set(scenes ${SCENES}/cavity.gltf ${SCENES}/clutter.gltf)
set(spp 24)
set(res_w 29)
set(res_h 23)
file(REMOVE_RECURSE ${WORK})
file(MAKE_DIRECTORY ${WORK})
execute_process(COMMAND ${GTBAKE} sweep --quiet --threads 2 --spp ${spp} --res ${res_w}x${res_h}
                        --out ${WORK}/avx2 --scenes ${scenes}
                RESULT_VARIABLE rc ERROR_VARIABLE err)
if(NOT rc EQUAL 0)
  message(FATAL_ERROR "gtbake sweep failed: ${err}")
endif()
execute_process(COMMAND ${PORTABLE} ${WORK}/default ${spp} ${res_w} ${res_h} 2 ${scenes}
                RESULT_VARIABLE rc ERROR_VARIABLE err)
if(NOT rc EQUAL 0)
  message(FATAL_ERROR "portable_sweep failed: ${err}")
endif()
foreach(name cavity clutter)
  execute_process(COMMAND ${CMAKE_COMMAND} -E compare_files ${WORK}/avx2/${name}.exr
                          ${WORK}/default/${name}.exr RESULT_VARIABLE differ)
  if(NOT differ EQUAL 0)
    message(FATAL_ERROR "${name}.exr: the default code path wrote other bytes than the AVX2 path")
  endif()
endforeach()
file(REMOVE_RECURSE ${WORK})
message(STATUS "default and AVX2 paths wrote identical EXR bytes (cavity, clutter)")

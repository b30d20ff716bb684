# `cmake --install` into a scratch prefix puts gtbake in bin/ and the shipped luts in
# share/gtbake/luts (the header, the DDS/KTX2 volumes, the JSON results), and leaves out the
# intermediate scenes/ of `gtbake all`. The per-view EXRs are installed only where `gtbake all`
# wrote them: a clone does not hold them (docs/reproducibility.md "What luts/ keeps").
file(REMOVE_RECURSE ${PREFIX})
execute_process(COMMAND ${CMAKE_COMMAND} --install ${BUILD} --prefix ${PREFIX}
                RESULT_VARIABLE rc OUTPUT_QUIET ERROR_VARIABLE err)
if(NOT rc EQUAL 0)
  message(FATAL_ERROR "cmake --install failed: ${err}")
endif()
# The layout of docs/reproducibility.md "Layout": ship/ and one folder per stage.
foreach(file bin/gtbake share/gtbake/luts/ship/gtbake_tables.h
             share/gtbake/luts/ship/gtbake_tables.hlsl share/gtbake/luts/ship/gtbake_tables.glsl
             share/gtbake/luts/ship/gtso3d.dds share/gtbake/luts/ship/gtso4d.ktx2
             share/gtbake/luts/ship/README.md share/gtbake/luts/fit/fit.json
             share/gtbake/luts/sweep/sweep.json share/gtbake/luts/gtso/gtso.json
             share/gtbake/luts/encode/encode.json share/gtbake/luts/screen_ao/screen_ao.json)
  if(NOT EXISTS ${PREFIX}/${file})
    message(FATAL_ERROR "cmake --install did not install ${file}")
  endif()
endforeach()
foreach(file share/gtbake/luts/.gitignore share/gtbake/luts/scenes)
  if(EXISTS ${PREFIX}/${file})
    message(FATAL_ERROR "cmake --install installed ${file}, which is not shipped")
  endif()
endforeach()
execute_process(COMMAND ${PREFIX}/bin/gtbake --version RESULT_VARIABLE rc OUTPUT_QUIET)
if(NOT rc EQUAL 0)
  message(FATAL_ERROR "the installed gtbake does not run")
endif()
file(REMOVE_RECURSE ${PREFIX})

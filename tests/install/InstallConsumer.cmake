# ctest install_consumer: `cmake --install` into a scratch prefix, then the out-of-tree projects
# examples/mapping_consumer, examples/plugin_mapper (a mapper registered by name and run in the
# closed loop) and examples/mcap_preview (that run's run.mcap drawn) configured with
# find_package(trav) against it, built and run; and the installed trav executable with its models
# and scenarios. Run with -DBUILD_DIR, -DSOURCE_DIR,
# -DWORK (scratch folder, replaced) and -DGENERATOR.
function(run what)
  execute_process(COMMAND ${ARGN} RESULT_VARIABLE code OUTPUT_VARIABLE out ERROR_VARIABLE err)
  if(NOT code EQUAL 0)
    message(FATAL_ERROR "${what} failed (${code}):\n${out}\n${err}")
  endif()
  set(output "${out}" PARENT_SCOPE)
endfunction()

file(REMOVE_RECURSE ${WORK})
set(prefix ${WORK}/prefix)
run("cmake --install" ${CMAKE_COMMAND} --install ${BUILD_DIR} --prefix ${prefix})
foreach(installed lib/cmake/trav/travConfig.cmake lib/cmake/trav/travTargets.cmake
                  include/trav/mapping/fsgp_bgk_mapper.h include/trav/planner/navigation/navigator.h
                  bin/trav share/trav/models/scout_mini.xml share/trav/scenarios/suite/forest.yaml)
  if(NOT EXISTS ${prefix}/${installed})
    message(FATAL_ERROR "cmake --install did not install ${installed}")
  endif()
endforeach()

run("configuring the consumer" ${CMAKE_COMMAND} -S ${SOURCE_DIR}/examples/mapping_consumer
    -B ${WORK}/consumer -G ${GENERATOR} -DCMAKE_BUILD_TYPE=Release -DCMAKE_PREFIX_PATH=${prefix})
run("building the consumer" ${CMAKE_COMMAND} --build ${WORK}/consumer)
run("running the consumer" ${WORK}/consumer/mapping_consumer)
foreach(expected "frame 2: [0-9]+ training points" "wall cost 1.00" "path found")
  if(NOT output MATCHES "${expected}")
    message(FATAL_ERROR "the consumer's output lacks '${expected}':\n${output}")
  endif()
endforeach()
message(STATUS "consumer: ${output}")

# a mapper of the user's own, registered by name and run in the closed loop (examples/plugin_mapper)
run("configuring the plugin mapper" ${CMAKE_COMMAND} -S ${SOURCE_DIR}/examples/plugin_mapper
    -B ${WORK}/plugin -G ${GENERATOR} -DCMAKE_BUILD_TYPE=Release -DCMAKE_PREFIX_PATH=${prefix})
run("building the plugin mapper" ${CMAKE_COMMAND} --build ${WORK}/plugin)
run("running the plugin mapper" ${WORK}/plugin/plugin_mapper ${prefix}/share/trav/models
    ${WORK}/plugin_run)
if(NOT output MATCHES "mapper height-span: success")
  message(FATAL_ERROR "the plugin mapper's run did not succeed:\n${output}")
endif()
if(NOT EXISTS ${WORK}/plugin_run/trajectory.csv)
  message(FATAL_ERROR "the plugin mapper's run wrote no trajectory.csv")
endif()
message(STATUS "plugin mapper: ${output}")

# that run's run.mcap read back and drawn from above (examples/mcap_preview)
run("configuring the MCAP preview" ${CMAKE_COMMAND} -S ${SOURCE_DIR}/examples/mcap_preview
    -B ${WORK}/preview -G ${GENERATOR} -DCMAKE_BUILD_TYPE=Release -DCMAKE_PREFIX_PATH=${prefix})
run("building the MCAP preview" ${CMAKE_COMMAND} --build ${WORK}/preview)
run("running the MCAP preview" ${WORK}/preview/mcap_preview ${WORK}/plugin_run/run.mcap
    ${WORK}/preview.png)
if(NOT output MATCHES "preview.png \\([0-9]+ x [0-9]+ pixels, 1[01] topics\\)" OR NOT EXISTS ${WORK}/preview.png)
  message(FATAL_ERROR "the MCAP preview did not draw the run:\n${output}")
endif()
message(STATUS "MCAP preview: ${output}")

# the installed executable finds its models beside it, with the source tree out of reach
run("the installed trav" ${CMAKE_COMMAND} -E env TRAV_MODELS_DIR= ${prefix}/bin/trav --version)

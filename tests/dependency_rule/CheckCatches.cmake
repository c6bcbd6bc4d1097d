# The dependency rule fails on a forbidden include in any folder: for each folder, a tree with one
# source that includes what the folder must not is checked by cmake/CheckDependencyRule.cmake,
# which must fail naming that file. Run as a ctest: cmake -DCHECKER=<rule script> -DWORK=<dir> -P <this>.
set(cases
  "common|#include \"planner/astar.h\""
  "controller|#include <mujoco/mujoco.h>"
  "mapping|#include \"sim/simulation.h\""
  "planner|#include \"sim/terrain.h\""
  "planner|#include <embree3/rtcore.h>"
  "planner/navigation|#include <ompl/base/State.h>"
  "planner/navigation|#include \"renders/renderer.h\""
  "planner/ompl|#include \"controller/mpc.h\""
  "sim|#include \"renders/renderer.h\""
  "sim/lidar|#include \"sim/simulation.h\""
  "sim/actors|#include \"mapping/features.h\""
  "renders|#include \"scenarios/run/scenario.h\""
  "scenarios/run|#include \"scenarios/experiments/batch.h\""
  "scenarios/experiments|#include \"sim/terrain.h\""
  "scenarios/experiments|#include \"renders/image.h\""
  "scenarios/experiments|#include <mujoco/mujoco.h>"
  "scenarios/cli|#include \"sim/simulation.h\"")
set(index 0)
foreach(case IN LISTS cases)
  string(REPLACE "|" ";" parts "${case}")
  list(GET parts 0 folder)
  list(GET parts 1 line)
  set(root "${WORK}/case_${index}")
  file(REMOVE_RECURSE "${root}")
  file(WRITE "${root}/${folder}/bad.cc" "${line}\n")
  execute_process(COMMAND ${CMAKE_COMMAND} -DROOT=${root} -P ${CHECKER}
                  RESULT_VARIABLE result OUTPUT_VARIABLE out ERROR_VARIABLE err)
  if(result EQUAL 0 OR NOT err MATCHES "${folder}/bad.cc")
    message(FATAL_ERROR "the dependency rule let through ${folder}: ${line}\n${err}")
  endif()
  file(REMOVE_RECURSE "${root}")
  math(EXPR index "${index} + 1")
endforeach()
# and an allowed include passes
file(REMOVE_RECURSE "${WORK}/allowed")
file(WRITE "${WORK}/allowed/planner/navigation/good.cc" "#include \"controller/mpc.h\"\n#include <vector>\n")
execute_process(COMMAND ${CMAKE_COMMAND} -DROOT=${WORK}/allowed -P ${CHECKER} RESULT_VARIABLE result)
if(NOT result EQUAL 0)
  message(FATAL_ERROR "the dependency rule rejected an allowed include")
endif()
message(STATUS "the dependency rule catches every forbidden include tried")

# Dependency rule (docs/architecture.md): what each folder's sources may include. The algorithms
# (mapping, planner, controller) work on plain data and include nothing of MuJoCo, Embree or sim/;
# the navigation stack links no OMPL; the experiments drive runs through scenarios/run only and
# include nothing of sim/ or renders/. Run as a ctest: cmake -DROOT=<source tree> -P <this>.
#
# Each rule: <folder>|<project folders its files may include>|<system headers they may include>.
# A file follows the rule of the longest folder that contains it; "*" allows every project folder.
cmake_policy(SET CMP0007 NEW)
set(rules
  "common|common|"
  "controller|common controller|ceres"
  "mapping|common mapping|pcl lbfgs.h"
  "planner|common planner|lbfgs.h"
  "planner/navigation|common planner controller|"
  "planner/ompl|common planner|ompl"
  "sim|common sim|mujoco"
  "sim/lidar|common sim/lidar|embree3"
  "sim/actors|common sim|"
  "renders|common sim renders|mujoco GL EGL png.h"
  "scenarios/run|common controller mapping planner sim renders scenarios/run|pcl mcap"
  "scenarios/experiments|common controller mapping planner scenarios/run scenarios/experiments|nlopt.hpp"
  "scenarios/cli|common scenarios/run scenarios/experiments scenarios/cli|CLI")
# System headers owned by one folder: nobody else includes them.
set(owned_system_headers mujoco embree3 ompl ceres pcl nlopt.hpp GL EGL png.h CLI lbfgs.h mcap)

set(violations "")
foreach(rule IN LISTS rules)
  string(REPLACE "|" ";" parts "${rule}")
  list(GET parts 0 folder)
  file(GLOB_RECURSE sources "${ROOT}/${folder}/*.h" "${ROOT}/${folder}/*.cc")
  foreach(source IN LISTS sources)
    # the longest rule folder containing the file decides
    file(RELATIVE_PATH relative "${ROOT}" "${source}")
    set(best "")
    set(best_rule "")
    foreach(candidate IN LISTS rules)
      string(REPLACE "|" ";" candidate_parts "${candidate}")
      list(GET candidate_parts 0 candidate_folder)
      string(LENGTH "${candidate_folder}" length)
      string(LENGTH "${best}" best_length)
      if(relative MATCHES "^${candidate_folder}/" AND length GREATER best_length)
        set(best "${candidate_folder}")
        set(best_rule "${candidate}")
      endif()
    endforeach()
    if(NOT best STREQUAL folder)
      continue()
    endif()
    string(REPLACE "|" ";" best_parts "${best_rule}")
    list(GET best_parts 1 allowed)
    list(GET best_parts 2 allowed_system)
    string(REPLACE " " ";" allowed "${allowed}")
    string(REPLACE " " ";" allowed_system "${allowed_system}")
    file(STRINGS "${source}" includes REGEX "^[ \t]*#[ \t]*include[ \t]*[<\"]")
    foreach(line IN LISTS includes)
      string(REGEX REPLACE "^[ \t]*#[ \t]*include[ \t]*[<\"]([^>\"]*)[>\"].*" "\\1" header "${line}")
      if(line MATCHES "#[ \t]*include[ \t]*\"")
        # project headers: "<folder>/<file>.h"; generated and test headers are not checked
        if(NOT header MATCHES "/" OR header MATCHES "^tests/")
          continue()
        endif()
        set(ok FALSE)
        foreach(prefix IN LISTS allowed)
          if(header MATCHES "^${prefix}/")
            set(ok TRUE)
          endif()
        endforeach()
        if(NOT ok)
          list(APPEND violations "${relative}: ${line}")
        endif()
      else()
        string(REGEX REPLACE "/.*" "" top "${header}")
        list(FIND owned_system_headers "${top}" owned)
        list(FIND allowed_system "${top}" permitted)
        if(owned GREATER -1 AND permitted EQUAL -1)
          list(APPEND violations "${relative}: ${line}")
        endif()
      endif()
    endforeach()
  endforeach()
endforeach()
if(violations)
  list(JOIN violations "\n  " message)
  message(FATAL_ERROR "dependency rule broken (docs/architecture.md):\n  ${message}")
endif()
message(STATUS "dependency rule holds")

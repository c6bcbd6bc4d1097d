# Every C++ source of the tree is formatted as .clang-format says (clang-format --dry-run
# --Werror). Run as a ctest: cmake -DROOT=<source tree> -DCLANG_FORMAT=<program> -P <this>.
if(NOT CLANG_FORMAT)
  message(FATAL_ERROR "clang-format not found: scripts/install-deps installs it")
endif()
set(sources "")
foreach(folder common controller mapping planner sim renders scenarios tests examples)
  file(GLOB_RECURSE found "${ROOT}/${folder}/*.cc" "${ROOT}/${folder}/*.h")
  list(APPEND sources ${found})
endforeach()
execute_process(COMMAND ${CLANG_FORMAT} --dry-run --Werror ${sources}
                RESULT_VARIABLE result ERROR_VARIABLE errors)
if(NOT result EQUAL 0)
  message(FATAL_ERROR "not formatted (run clang-format -i on these files):\n${errors}")
endif()
message(STATUS "every source is formatted")

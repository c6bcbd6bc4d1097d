# trav_add_module(<module> SOURCES <files...> [PUBLIC <targets...>] [PRIVATE <targets...>])
# Creates the library trav_<module> with the alias trav::<module>: includes read
# "<module>/<file>.h" from the source root, PUBLIC lists what its headers expose, PRIVATE what only its
# sources use, and every module gets trav's warning flags.
function(trav_add_module module)
  cmake_parse_arguments(ARG "" "" "SOURCES;PUBLIC;PRIVATE" ${ARGN})
  add_library(trav_${module} ${ARG_SOURCES})
  add_library(trav::${module} ALIAS trav_${module})
  target_include_directories(trav_${module} PUBLIC ${PROJECT_SOURCE_DIR})
  target_link_libraries(trav_${module} PUBLIC ${ARG_PUBLIC} PRIVATE ${ARG_PRIVATE} trav_warnings)
endfunction()

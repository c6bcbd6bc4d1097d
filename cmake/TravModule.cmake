# trav_add_module(<module> SOURCES <files...> [PUBLIC <targets...>] [PRIVATE <targets...>])
# Creates the library trav_<module> with the alias trav::<module>: includes read
# "<module>/<file>.h" from the source root, PUBLIC lists what its headers expose, PRIVATE what only its
# sources use, and every module gets trav's warning flags. `cmake --install` installs the library and
# the headers of its folder (under include/trav/, keeping the folder) into the export set travTargets,
# as trav::<module> for find_package(trav) (cmake/travConfig.cmake.in).
include(GNUInstallDirs)

function(trav_add_module module)
  cmake_parse_arguments(ARG "" "" "SOURCES;PUBLIC;PRIVATE" ${ARGN})
  add_library(trav_${module} ${ARG_SOURCES})
  add_library(trav::${module} ALIAS trav_${module})
  target_include_directories(trav_${module} PUBLIC $<BUILD_INTERFACE:${PROJECT_SOURCE_DIR}>
                                                   $<INSTALL_INTERFACE:${CMAKE_INSTALL_INCLUDEDIR}/trav>)
  target_link_libraries(trav_${module} PUBLIC ${ARG_PUBLIC} PRIVATE ${ARG_PRIVATE} trav_warnings)
  set_target_properties(trav_${module} PROPERTIES EXPORT_NAME ${module})
  install(TARGETS trav_${module} EXPORT travTargets
          ARCHIVE DESTINATION ${CMAKE_INSTALL_LIBDIR} LIBRARY DESTINATION ${CMAKE_INSTALL_LIBDIR})
  file(RELATIVE_PATH folder ${PROJECT_SOURCE_DIR} ${CMAKE_CURRENT_SOURCE_DIR})
  file(GLOB headers ${CMAKE_CURRENT_SOURCE_DIR}/*.h)
  install(FILES ${headers} DESTINATION ${CMAKE_INSTALL_INCLUDEDIR}/trav/${folder})
endfunction()

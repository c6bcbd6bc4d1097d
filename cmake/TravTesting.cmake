# trav_add_test(<name> SOURCES <files...> LIBS <targets...> [LABELS <label>] [PROCESSORS <n>])
# Builds one GoogleTest executable per test file and registers its tests with ctest. Tests find the
# robot model through the TRAV_MODELS_DIR definition. Labels (README "Tests"): unit (sub-second),
# physics (simulated dynamics, ray casting over many frames, closed-loop control), process (starts
# processes), render, scenario (whole runs through the trav executable), stress, seeds, cluster.
# Every test gets its label's time limit; PROCESSORS declares the cores a test keeps busy (process
# pools), so that ctest -j does not oversubscribe the machine.
find_package(GTest REQUIRED)
include(GoogleTest)

# The time limit [s] of one test of a label.
function(trav_test_timeout label out)
  set(limits unit 60 physics 300 process 300 render 300 scenario 900 stress 1800 seeds 1800
             cluster 1800)
  list(FIND limits ${label} at)
  if(at EQUAL -1)
    message(FATAL_ERROR "trav_add_test: unknown label ${label}")
  endif()
  math(EXPR at "${at} + 1")
  list(GET limits ${at} limit)
  set(${out} ${limit} PARENT_SCOPE)
endfunction()

function(trav_add_test name)
  cmake_parse_arguments(ARG "" "PROCESSORS" "SOURCES;LIBS;LABELS" ${ARGN})
  if(NOT ARG_LABELS)
    set(ARG_LABELS unit)
  endif()
  if(NOT ARG_PROCESSORS)
    set(ARG_PROCESSORS 1)
  endif()
  trav_test_timeout(${ARG_LABELS} timeout)
  add_executable(${name} ${ARG_SOURCES})
  target_link_libraries(${name} PRIVATE ${ARG_LIBS} GTest::gtest_main GTest::gmock trav_warnings)
  target_include_directories(${name} PRIVATE ${PROJECT_SOURCE_DIR})
  target_compile_definitions(${name} PRIVATE TRAV_MODELS_DIR="${TRAV_MODELS_DIR}")
  gtest_discover_tests(${name} PROPERTIES LABELS "${ARG_LABELS}" TIMEOUT ${timeout}
                       PROCESSORS ${ARG_PROCESSORS} DISCOVERY_TIMEOUT 60)
endfunction()

# trav_add_benchmark(<name> SOURCES <files...> LIBS <targets...>): a Google Benchmark program, not run by ctest.
function(trav_add_benchmark name)
  cmake_parse_arguments(ARG "" "" "SOURCES;LIBS" ${ARGN})
  find_package(benchmark REQUIRED)
  add_executable(${name} ${ARG_SOURCES})
  target_link_libraries(${name} PRIVATE ${ARG_LIBS} benchmark::benchmark trav_warnings)
  target_include_directories(${name} PRIVATE ${PROJECT_SOURCE_DIR})
  target_compile_definitions(${name} PRIVATE TRAV_MODELS_DIR="${TRAV_MODELS_DIR}")
endfunction()

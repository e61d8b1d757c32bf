# Test registration helpers. Every test binary is a GoogleTest binary and is
# registered with CTest case by case, so ctest's summary counts test cases.
include(GoogleTest)

# sinkwatch_gtest(<name> SOURCES <files...> LIBS <targets...>)
function(sinkwatch_gtest name)
  cmake_parse_arguments(ARG "" "" "SOURCES;LIBS" ${ARGN})
  add_executable(${name} ${ARG_SOURCES})
  target_link_libraries(${name} PRIVATE ${ARG_LIBS} GTest::gtest GTest::gtest_main)
  target_compile_definitions(${name} PRIVATE SINKWATCH_DATA_DIR="${SINKWATCH_DATA_DIR}")
  sinkwatch_host_target(${name})
  gtest_discover_tests(${name} DISCOVERY_TIMEOUT 60 PROPERTIES LABELS "unit")
endfunction()

# sinkwatch_rapidcheck(<name> SOURCES <files...> LIBS <targets...>)
# RapidCheck through its GoogleTest integration (RC_GTEST_PROP). CI runs a
# fixed seed so that a run can be reproduced exactly; set RC_PARAMS yourself
# for a random or longer run (docs/testing.md).
set(SINKWATCH_RC_PARAMS "seed=20261121 max_success=2000" CACHE STRING "RapidCheck parameters for ctest")
function(sinkwatch_rapidcheck name)
  cmake_parse_arguments(ARG "" "" "SOURCES;LIBS" ${ARGN})
  add_executable(${name} ${ARG_SOURCES})
  target_link_libraries(${name} PRIVATE ${ARG_LIBS} rapidcheck rapidcheck_gtest GTest::gtest GTest::gtest_main)
  target_compile_definitions(${name} PRIVATE SINKWATCH_DATA_DIR="${SINKWATCH_DATA_DIR}")
  sinkwatch_host_target(${name})
  gtest_discover_tests(${name} DISCOVERY_TIMEOUT 60
    PROPERTIES LABELS "property" ENVIRONMENT "RC_PARAMS=${SINKWATCH_RC_PARAMS}")
endfunction()

# Warning sets. Flight and fixed-point code get the strict set: implicit
# narrowing and sign changes are warnings there (MISRA C++:2023 7.0.x), and
# errors with SINKWATCH_WARNINGS_AS_ERRORS.
#
# -Werror is an option so that a build with another compiler, version or
# build type than the ones the project checks (a firmware project taking
# sinkwatch with add_subdirectory or find_package, a plain
# `cmake -DCMAKE_BUILD_TYPE=...`) still builds if that compiler finds
# something new: it prints the warning instead of failing. The project's own
# presets (CMakePresets.json), and so CI, turn it ON.
option(SINKWATCH_WARNINGS_AS_ERRORS
  "Treat compiler warnings in sinkwatch's own targets as errors (-Werror); ON in the project's presets and CI" OFF)

set(SINKWATCH_STRICT_WARNINGS
  -Wall -Wextra -Wpedantic -Wconversion -Wsign-conversion -Wshadow
  -Wold-style-cast -Wcast-align -Wcast-qual -Wnull-dereference
  -Wdouble-promotion -Wformat=2 -Wundef -Wswitch-enum -Wimplicit-fallthrough)
set(SINKWATCH_HOST_WARNINGS -Wall -Wextra -Wpedantic -Wshadow)
if(SINKWATCH_WARNINGS_AS_ERRORS)
  list(APPEND SINKWATCH_STRICT_WARNINGS -Werror)
  list(APPEND SINKWATCH_HOST_WARNINGS -Werror)
endif()

# Flight targets: strict warnings and the embedded-safe code generation flags.
function(sinkwatch_flight_target target)
  target_compile_options(${target} PRIVATE ${SINKWATCH_STRICT_WARNINGS}
    $<$<COMPILE_LANGUAGE:CXX>:-fno-exceptions -fno-rtti>)
endfunction()

# Host targets (ground tools, tests): the usual warnings (errors with
# SINKWATCH_WARNINGS_AS_ERRORS), but the host code may use exceptions, the
# heap and double precision.
function(sinkwatch_host_target target)
  target_compile_options(${target} PRIVATE ${SINKWATCH_HOST_WARNINGS})
endfunction()

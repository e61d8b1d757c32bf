# Warning sets. Flight and fixed-point code get the strict set and -Werror:
# implicit narrowing and sign changes are errors there (MISRA C++:2023 7.0.x).
set(SINKWATCH_STRICT_WARNINGS
  -Wall -Wextra -Wpedantic -Wconversion -Wsign-conversion -Wshadow
  -Wold-style-cast -Wcast-align -Wcast-qual -Wnull-dereference
  -Wdouble-promotion -Wformat=2 -Wundef -Wswitch-enum -Wimplicit-fallthrough
  -Werror)

# Flight targets: strict warnings and the embedded-safe code generation flags.
function(sinkwatch_flight_target target)
  target_compile_options(${target} PRIVATE ${SINKWATCH_STRICT_WARNINGS}
    $<$<COMPILE_LANGUAGE:CXX>:-fno-exceptions -fno-rtti>)
endfunction()

# Host targets (ground tools, tests): the usual warnings, errors too, but the
# host code may use exceptions, the heap and double precision.
function(sinkwatch_host_target target)
  target_compile_options(${target} PRIVATE -Wall -Wextra -Wpedantic -Wshadow -Werror)
endfunction()

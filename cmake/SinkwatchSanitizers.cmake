# Sanitizer build: address and undefined behaviour, and with clang the float
# checks (float-cast-overflow, float-divide-by-zero) that UBSan leaves out by
# default. Any finding aborts the test that caused it.
set(_san address,undefined)
if(CMAKE_CXX_COMPILER_ID MATCHES "Clang")
  string(APPEND _san ",float-cast-overflow,float-divide-by-zero")
endif()
add_compile_options(-fsanitize=${_san} -fno-sanitize-recover=all -fno-omit-frame-pointer)
add_link_options(-fsanitize=${_san})

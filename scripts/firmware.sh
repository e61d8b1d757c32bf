#!/usr/bin/env bash
# Firmware checks (docs/firmware.md), run by scripts/test.sh:
#  1. build fixedpoint and flight for Cortex-M4F and Cortex-M0 (arm-none-eabi);
#  2. link the heap-trap image (an allocation anywhere is a link error);
#  3. no exception, RTTI or soft-float machinery among the libraries' undefined
#     symbols;
#  4. print the worst-case stack of the per-cycle step and the image's size;
#  5. build the flight tests for 32-bit ARM Linux and run them under qemu-arm,
#     golden vectors included: every output bit must equal the host's.
set -euo pipefail
cd "$(dirname "$0")/.."

# Symbols whose presence as undefined references means exceptions, RTTI,
# run-time floating point or allocation reached the flight code.
forbidden='^(__cxa_.*|__gxx_personality.*|_Unwind_.*|_ZTI.*|_ZTS.*|__aeabi_(c?[df][a-z0-9]+|[a-z]*2[df])|__([a-z]+(df|sf)[0-9]?|float[a-z]+|fix[a-z]+|extendsfdf2|truncdfsf2)|malloc|calloc|realloc|free|_malloc_r|_free_r|_Znw.*|_Zna.*|_Zdl.*|_Zda.*)$'

for preset in firmware-m4f firmware-m0; do
  echo "---- $preset"
  cmake --preset "$preset" >/dev/null
  cmake --build --preset "$preset"
  dir="build/$preset"
  bad=0
  libs=$(find "$dir" -name 'libsinkwatch_*.a' | sort)
  # What the libraries need from outside themselves: undefined in one object
  # and defined in none.
  # shellcheck disable=SC2086
  defined=$(arm-none-eabi-nm --defined-only $libs 2>/dev/null | awk 'NF==3 {print $3}' | sort -u)
  # shellcheck disable=SC2086
  external=$(arm-none-eabi-nm -u $libs 2>/dev/null | awk 'NF==2 {print $2}' | sort -u | comm -23 - <(echo "$defined"))
  hits=$(grep -E "$forbidden" <<<"$external" || true)
  if [ -n "$hits" ]; then
    echo "FORBIDDEN external symbols in the flight libraries:"; echo "$hits"; bad=1
  else
    echo "external symbols of the flight libraries (integer runtime only): $(tr '\n' ' ' <<<"$external")"
  fi
  [ "$bad" -eq 0 ]
  image="$dir/flight/firmware/sinkwatch_heap_trap"
  echo "heap trap linked: $image (malloc/free/new/delete wrapped, no wrapper defined)"
  arm-none-eabi-size "$image" | awk -v t="$preset" 'NR==2 {printf "image_size target=%s text=%d data=%d bss=%d\n", t, $1, $2, $3}'
  entries=$(cat flight/firmware/stack_entries.txt 2>/dev/null | grep -v '^#' || echo main)
  # shellcheck disable=SC2086
  python3 scripts/stack_report.py "$dir" "$preset" $entries
done

echo "---- a C firmware project consuming sinkwatch (Cortex-M0): find_package and add_subdirectory"
prefix="build/firmware-m0/install"
rm -rf "$prefix" build/consumer-package build/consumer-subdir
cmake --install build/firmware-m0 --prefix "$prefix" >/dev/null
for mode in package subdir; do
  extra="-DCMAKE_PREFIX_PATH=$(pwd)/$prefix"
  [ "$mode" = subdir ] && extra="-DSINKWATCH_VIA_SUBDIRECTORY=ON"
  cmake -S flight/firmware/consumer -B "build/consumer-$mode" -G Ninja -DCMAKE_BUILD_TYPE=MinSizeRel \
    --toolchain "$(pwd)/toolchains/arm-none-eabi-cortex-m0.cmake" $extra >/dev/null
  cmake --build "build/consumer-$mode" --target consumer >/dev/null
  echo "consumer ($mode) linked: $(arm-none-eabi-size "build/consumer-$mode/consumer" | awk 'NR==2 {print "text=" $1 " data=" $2 " bss=" $3}')"
done

echo "---- arm-linux (qemu-arm): flight and fixed-point tests, golden vectors"
cmake --preset arm-linux >/dev/null
cmake --build --preset arm-linux
ctest --preset arm-linux 2>&1 | tee "${SINKWATCH_CTEST_LOG:-/dev/null}"
exit "${PIPESTATUS[0]}"

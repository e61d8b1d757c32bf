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
forbidden='__cxa_|__gxx_personality|_Unwind_|_ZTI|_ZTS|__aeabi_[dfi]2|__aeabi_[ui]?[dfl]2[dfl]|__aeabi_[df](add|sub|mul|div|cmp|neg)|__aeabi_[df]cmp|malloc|calloc|realloc|free$|_Znw|_Zna|_Zdl|_Zda'

for preset in firmware-m4f firmware-m0; do
  echo "---- $preset"
  cmake --preset "$preset" >/dev/null
  cmake --build --preset "$preset"
  dir="build/$preset"
  bad=0
  while IFS= read -r lib; do
    hits=$(arm-none-eabi-nm -u "$lib" | awk '{print $2}' | grep -E "$forbidden" | sort -u || true)
    if [ -n "$hits" ]; then
      echo "FORBIDDEN undefined symbols in $lib:"; echo "$hits"; bad=1
    else
      echo "symbols ok: $(basename "$lib") needs only: $(arm-none-eabi-nm -u "$lib" | awk '{print $2}' | sort -u | tr '\n' ' ')"
    fi
  done < <(find "$dir" -name 'libsinkwatch_*.a')
  [ "$bad" -eq 0 ]
  image="$dir/flight/firmware/sinkwatch_heap_trap"
  echo "heap trap linked: $image (malloc/free/new/delete wrapped, no wrapper defined)"
  arm-none-eabi-size "$image" | awk -v t="$preset" 'NR==2 {printf "image_size target=%s text=%d data=%d bss=%d\n", t, $1, $2, $3}'
  entries=$(cat flight/firmware/stack_entries.txt 2>/dev/null | grep -v '^#' || echo main)
  # shellcheck disable=SC2086
  python3 scripts/stack_report.py "$dir" "$preset" $entries
done

echo "---- arm-linux (qemu-arm): flight and fixed-point tests, golden vectors"
cmake --preset arm-linux >/dev/null
cmake --build --preset arm-linux
ctest --preset arm-linux 2>&1 | tee "${SINKWATCH_CTEST_LOG:-/dev/null}"
exit "${PIPESTATUS[0]}"

#!/usr/bin/env bash
# The performance report (docs/performance.md): a benchmark that prints
# figures and never fails on a number. For the six-wheel per-cycle step:
#
#   instructions_per_step target=<name> impl=<fixed|double> value=<n>
#     host:       x86-64 g++ -O2 (RelWithDebInfo), valgrind --tool=callgrind,
#                 (Ir of N steps - Ir of 0 steps) / N;
#     cortex-m0:  arm-none-eabi-g++ -mcpu=cortex-m0 -mthumb -mfloat-abi=soft
#                 -Os (the firmware-m0 flags), run under qemu-arm with one
#                 instruction per translation block and no chaining, every
#                 executed instruction logged: (count(N) - count(0)) / N;
#     cortex-m4:  the same with -mcpu=cortex-m4 -mthumb -mfloat-abi=hard
#                 -mfpu=fpv4-sp-d16 (the firmware-m4f flags, preset perf-m4).
#   code_size, stack: arm-none-eabi-size and scripts/stack_report.py on the
#                 Cortex-M0 and M4 builds (build/perf-m0, build/perf-m4).
#   wide_instructions_per_step target=cortex-m0 impl=fixed value=<n>
#                 the instructions of fixedpoint/wide.hpp's 128-bit type per
#                 step (issue 15 asks for none), from one step of the M0
#                 driver against the flight library at -O0 -g (preset
#                 perf-m0-wide: there every instruction keeps its source
#                 line; the paths taken are those of -Os), mapped by
#                 scripts/wide_per_step.py; the functions are listed when
#                 there are any.
#
#   scripts/assurance/perf_report.sh [--host-bin DIR]
# DIR holds perf_step_fixed and perf_step_double (the perf-report target
# passes its own build directory); without it the default preset is built.
# A missing tool skips its lines with a note; exit status is 0 unless a
# driver fails to build or run.
set -euo pipefail
cd "$(dirname "$0")/../.."

host_bin=""
if [ "${1:-}" = "--host-bin" ]; then host_bin=$2; fi
host_steps=${SINKWATCH_PERF_HOST_STEPS:-2000}
arm_steps=${SINKWATCH_PERF_ARM_STEPS:-8}   # at most 9 (one digit in the check)

check_full() {  # driver output, expected cycles, label
  local full
  full=$(sed -nE 's/.*full_chain_steps=([0-9]+).*/\1/p' <<<"$1")
  if [ "$full" != "$2" ]; then
    echo "note: $3: only $full of $2 cycles ran the whole chain"
  fi
}

# ---- host: callgrind
if [ -z "$host_bin" ]; then
  cmake --preset default >/dev/null
  cmake --build --preset default --target perf_step_fixed perf_step_double >/dev/null
  host_bin=build/default/perf
fi
if command -v valgrind >/dev/null; then
  for impl in fixed double; do
    bin="$host_bin/perf_step_$impl"
    ir() { valgrind --tool=callgrind --callgrind-out-file=/dev/null "$bin" "$1" 2>&1 | sed -nE 's/.*Collected : ([0-9]+).*/\1/p'; }
    out=$("$bin" "$host_steps")
    check_full "$out" "$host_steps" "host $impl"
    with=$(ir "$host_steps")
    without=$(ir 0)
    echo "instructions_per_step target=host-x86_64 impl=$impl value=$(( (with - without) / host_steps ))"
  done
else
  echo "note: valgrind missing: host figures skipped"
fi

# ---- Cortex-M0 and Cortex-M4 under qemu-arm
if ! command -v arm-none-eabi-g++ >/dev/null || ! command -v qemu-arm >/dev/null; then
  echo "note: arm-none-eabi-g++ or qemu-arm missing: Cortex-M figures skipped"
  exit 0
fi
# qemu-arm's log of an ELF run with one instruction per translation block and
# no chaining: one Trace line per executed instruction.
# shellcheck disable=SC2069  # the log (stderr) to the pipe, the driver's output away
trace() { qemu-arm -cpu any -singlestep -d exec,nochain "$1" 2>&1 >/dev/null; }
count_insns() {  # elf -> executed instructions
  trace "$1" | grep -c '^Trace'
}
# The perf driver for <cycles> cycles, linked bare-metal:
# link_driver <cpu flags> <elf> <cycles> <flight library> <start object> [flags and objects...]
# (the objects follow the driver's source, as the double twin's always did)
link_driver() {
  local cpu=$1 elf=$2 n=$3 lib=$4 start=$5
  shift 5
  # shellcheck disable=SC2086
  arm-none-eabi-g++ -std=c++17 $cpu -Iflight/include -Ifixedpoint/include -Iground/reference/include \
    -DPERF_BARE_METAL -DPERF_STEPS="$n" perf/perf_step.cpp "$@" "$start" "$lib" \
    -nostartfiles --specs=nosys.specs -Wl,--gc-sections -o "$elf" 2>&1 \
    | grep -vE 'is not implemented and will always fail|^collect2|in function|warning: .*has a LOAD segment' || true
}

# One core: its preset (the flight library as its firmware preset builds it),
# the driver's CPU flags, the target name printed.
arm_target() {
  local preset=$1 target=$2 cpu=$3
  local dir=build/$preset
  cmake --preset "$preset" >/dev/null
  cmake --build --preset "$preset" >/dev/null
  local out_dir=$dir/perf
  mkdir -p "$out_dir"
  local inc="-Iflight/include -Ifixedpoint/include -Iground/reference/include"
  local flight_lib="$dir/flight/libsinkwatch_flight.a"
  # shellcheck disable=SC2086
  arm-none-eabi-gcc $cpu -c perf/arm_start.c -o "$out_dir/arm_start.o"
  # The double reference is host code (exceptions, std::vector): built as it is.
  local ref_objs=() src obj
  for src in ground/reference/src/*.cpp; do
    obj="$out_dir/$(basename "$src" .cpp).o"
    # shellcheck disable=SC2086
    arm-none-eabi-g++ -std=c++17 $cpu $inc -c "$src" -o "$obj"
    ref_objs+=("$obj")
  done
  local impl n elf out with without extra objs
  for impl in fixed double; do
    extra=(-fno-exceptions -fno-rtti)
    objs=()
    if [ "$impl" = double ]; then extra=(-DPERF_IMPL_DOUBLE); objs=("${ref_objs[@]}"); fi
    for n in 0 "$arm_steps"; do
      elf="$out_dir/perf_step_${impl}_$n.elf"
      link_driver "$cpu" "$elf" "$n" "$flight_lib" "$out_dir/arm_start.o" "${extra[@]}" "${objs[@]}"
    done
    out=$(qemu-arm -cpu any "$out_dir/perf_step_${impl}_${arm_steps}.elf")
    check_full "$out" "$arm_steps" "$target $impl"
    with=$(count_insns "$out_dir/perf_step_${impl}_${arm_steps}.elf")
    without=$(count_insns "$out_dir/perf_step_${impl}_0.elf")
    echo "instructions_per_step target=$target impl=$impl value=$(( (with - without) / arm_steps ))"
    arm-none-eabi-size "$out_dir/perf_step_${impl}_${arm_steps}.elf" |
      awk -v i="$impl" -v t="$target" 'NR==2 {printf "code_size target=%s impl=%s driver_text=%d data=%d bss=%d (whole program: driver, libraries, newlib)\n", t, i, $1, $2, $3}'
  done
}

opt="-Os -ffunction-sections -fdata-sections -Wno-psabi"
arm_target perf-m0 cortex-m0 "-mcpu=cortex-m0 -mthumb -mfloat-abi=soft $opt"
# The M4F's FPU is single precision: the double twin is soft-float there too.
arm_target perf-m4 cortex-m4 "-mcpu=cortex-m4 -mthumb -mfloat-abi=hard -mfpu=fpv4-sp-d16 $opt"
wide_report() {  # 128-bit instructions per step (issue 15 asks for none), on the M0
  local dir=build/perf-m0-wide out_dir=build/perf-m0-wide/perf n elf
  local cpu="-mcpu=cortex-m0 -mthumb -mfloat-abi=soft $opt"
  cmake --preset perf-m0-wide >/dev/null
  cmake --build "$dir" --target sinkwatch_flight >/dev/null
  mkdir -p "$out_dir"
  # shellcheck disable=SC2086
  arm-none-eabi-gcc $cpu -c perf/arm_start.c -o "$out_dir/arm_start.o"
  for n in 0 1; do
    elf="$out_dir/perf_step_fixed_$n.elf"
    link_driver "$cpu" "$elf" "$n" "$dir/flight/libsinkwatch_flight.a" "$out_dir/arm_start.o" -fno-exceptions -fno-rtti
    trace "$elf" | sed -nE 's/^Trace [^[]*\[[0-9a-f]*\/([0-9a-f]+)\/.*/\1/p' | sort | uniq -c >"$out_dir/pcs_$n.txt"
  done
  python3 scripts/wide_per_step.py "$out_dir/perf_step_fixed_1.elf" "$out_dir/pcs_1.txt" "$out_dir/pcs_0.txt" 1 cortex-m0
}
wide_report

m0=build/perf-m0

# Flight library text (what a firmware links at most) and the stack of a cycle.
arm-none-eabi-size -t "$m0/flight/libsinkwatch_flight.a" | awk '/\(TOTALS\)/ {printf "code_size target=cortex-m0 impl=fixed library=libsinkwatch_flight.a text=%d data=%d bss=%d\n", $1, $2, $3}'
arm-none-eabi-size "$m0/flight/firmware/sinkwatch_heap_trap" | awk 'NR==2 {printf "image_size target=cortex-m0 heap_trap_text=%d data=%d bss=%d\n", $1, $2, $3}'
python3 scripts/stack_report.py "$m0" cortex-m0 sw_step main
m4=build/perf-m4
arm-none-eabi-size -t "$m4/flight/libsinkwatch_flight.a" | awk '/\(TOTALS\)/ {printf "code_size target=cortex-m4 impl=fixed library=libsinkwatch_flight.a text=%d data=%d bss=%d\n", $1, $2, $3}'
python3 scripts/stack_report.py "$m4" cortex-m4 sw_step

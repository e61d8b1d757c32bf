#!/usr/bin/env bash
# Consumer builds (docs/firmware.md, "Consuming the module"), run by
# scripts/test.sh: the host counterpart of the Cortex-M0 consumer check in
# scripts/firmware.sh. A project that takes sinkwatch with its own build type
# and its own warning flags must build it without a warning.
#
# For g++ and clang++, Release and MinSizeRel, flight/firmware/consumer (a C
# program calling sinkwatch::flight_c) is built both ways:
#   subdir   add_subdirectory(sinkwatch) from the source tree;
#   package  find_package(sinkwatch) after `cmake --install` of sinkwatch,
#            built with the same compiler, build type and flags, into a
#            temporary prefix.
# The consumer's flags are -Wall -Wextra; SINKWATCH_WARNINGS_AS_ERRORS is not
# set (its default, OFF, is what a consumer gets), and SINKWATCH_HOST=OFF
# keeps it to the flight libraries. A failed configure or build, a compiler
# or linker "warning:" or a "CMake Warning" in any log fails the script, as
# does a consumer that does not run to exit status 0.
#
# Work directory: a temporary one, removed at the end, or
# SINKWATCH_CONSUMER_DIR (kept, with every log).
set -euo pipefail
cd "$(dirname "$0")/.."
src=$(pwd)

if [ -n "${SINKWATCH_CONSUMER_DIR:-}" ]; then
  work=$SINKWATCH_CONSUMER_DIR
  rm -rf "$work"
  mkdir -p "$work"
  work=$(cd "$work" && pwd)
else
  work=$(mktemp -d)
  trap 'rm -rf "$work"' EXIT
fi

generator=()
if command -v ninja >/dev/null 2>&1; then
  generator=(-G Ninja)
fi
flags="-Wall -Wextra"
failures=0

# Runs one command with its output in a log; returns 1 when the command
# failed or the log holds a warning, and prints the log then.
run_logged() {
  local log=$1; shift
  local rc=0
  "$@" >"$log" 2>&1 || rc=$?
  if [ "$rc" -ne 0 ]; then
    echo "FAILED (exit $rc): $*"; cat "$log"; return 1
  fi
  if grep -qE 'warning:|CMake Warning' "$log"; then
    echo "WARNINGS in: $*"; grep -E -A4 'warning:|CMake Warning' "$log"; return 1
  fi
  return 0
}

# One consumer build: compiler pair, build type, route.
consumer() {
  local cc=$1 cxx=$2 type=$3 mode=$4 prefix=$5
  local dir="$work/$cc-$type-$mode"
  local route=(-DCMAKE_PREFIX_PATH="$prefix")
  [ "$mode" = subdir ] && route=(-DSINKWATCH_VIA_SUBDIRECTORY=ON -DSINKWATCH_HOST=OFF)
  run_logged "$dir.configure.log" cmake -S "$src/flight/firmware/consumer" -B "$dir" "${generator[@]}" \
    -DCMAKE_BUILD_TYPE="$type" -DCMAKE_C_COMPILER="$cc" -DCMAKE_CXX_COMPILER="$cxx" \
    -DCMAKE_C_FLAGS="$flags" -DCMAKE_CXX_FLAGS="$flags" "${route[@]}" || return 1
  run_logged "$dir.build.log" cmake --build "$dir" -j2 || return 1
  "$dir/consumer" || { echo "FAILED: $dir/consumer exited with $?"; return 1; }
}

for pair in gcc:g++ clang:clang++; do
  cc=${pair%%:*}; cxx=${pair##*:}
  for type in Release MinSizeRel; do
    start=$SECONDS
    # sinkwatch itself, as a firmware team would build and install it.
    lib="$work/$cc-$type-sinkwatch"
    prefix="$work/$cc-$type-prefix"
    ok=1
    run_logged "$lib.configure.log" cmake -S "$src" -B "$lib" "${generator[@]}" \
      -DCMAKE_BUILD_TYPE="$type" -DCMAKE_C_COMPILER="$cc" -DCMAKE_CXX_COMPILER="$cxx" \
      -DCMAKE_C_FLAGS="$flags" -DCMAKE_CXX_FLAGS="$flags" -DSINKWATCH_HOST=OFF &&
      run_logged "$lib.build.log" cmake --build "$lib" -j2 &&
      run_logged "$lib.install.log" cmake --install "$lib" --prefix "$prefix" || ok=0
    for mode in subdir package; do
      if [ "$mode" = package ] && [ "$ok" -eq 0 ]; then
        echo "consumer $cc $type package: not built (the sinkwatch build or install above failed)"
        failures=$((failures + 1)); continue
      fi
      if consumer "$cc" "$cxx" "$type" "$mode" "$prefix"; then
        echo "consumer $cc $type $mode: built without warnings, ran"
      else
        echo "consumer $cc $type $mode: FAILED"
        failures=$((failures + 1))
      fi
    done
    echo "  ($cc $type: $((SECONDS - start)) s)"
  done
done

if [ "$failures" -ne 0 ]; then
  echo "consumer builds: $failures of 8 failed"
  exit 1
fi
echo "consumer builds: all 8 built without warnings (g++, clang++; Release, MinSizeRel; add_subdirectory, find_package)"

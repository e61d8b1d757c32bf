#!/usr/bin/env bash
# Sets up the machine, builds every configuration and runs every test.
# This is the README's second command and what CI runs (.ci/run).
set -euo pipefail
cd "$(dirname "$0")/.."

bash scripts/setup.sh

logdir=$(mktemp -d)
step() { printf '\n==== %s ====\n' "$*"; }
# Runs ctest with the given arguments, keeps its summary line for the total.
run_ctest() {
  local name=$1; shift
  ctest "$@" 2>&1 | tee "$logdir/$name.log"
  return "${PIPESTATUS[0]}"
}

step "host build (g++): flight, ground tools, unit and property tests"
cmake --preset default >/dev/null
cmake --build --preset default
run_ctest host --preset default

step "sanitizer build (clang++: address, undefined, float-cast-overflow, float-divide-by-zero)"
cmake --preset sanitize >/dev/null
cmake --build --preset sanitize
run_ctest sanitize --preset sanitize

if [ -f scripts/firmware.sh ]; then
  step "firmware: Cortex-M4F and Cortex-M0 builds, heap trap, stack and size; ARM32 bit-exact under qemu"
  SINKWATCH_CTEST_LOG="$logdir/arm.log" bash scripts/firmware.sh
fi

# Assurance (docs/assurance.md, docs/performance.md). Fuzzing is a gate: each
# harness runs for a bounded time from a fixed seed, and a crash, sanitizer
# finding or failed range assertion fails CI. The performance report prints
# figures and never fails on them. The static-analysis and coverage gates are
# run by hand until they meet their targets (docs/assurance.md).
step "assurance: fuzzing (${SINKWATCH_FUZZ_SECONDS:-15} s per harness), performance report"
bash scripts/assurance/fuzz.sh "${SINKWATCH_FUZZ_SECONDS:-15}"
bash scripts/assurance/perf_report.sh ||
  echo "assurance: the performance report did not complete (above); figures only, not a gate"

# One closing line over every ctest run above.
step "all test runs"
passed=0; failed=0
for log in "$logdir"/*.log; do
  line=$(grep -E 'tests passed, [0-9]+ tests failed out of [0-9]+' "$log" | tail -n 1) || continue
  total=$(sed -E 's/.*out of ([0-9]+).*/\1/' <<<"$line")
  fail=$(sed -E 's/.* ([0-9]+) tests failed.*/\1/' <<<"$line")
  printf '%-10s %s\n' "$(basename "$log" .log)" "$line"
  passed=$((passed + total - fail)); failed=$((failed + fail))
done
echo "total: ${passed} passed, ${failed} failed"
[ "$failed" -eq 0 ]

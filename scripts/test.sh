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

step "static analysis (gate): clang-tidy (MISRA C++:2023 approximation) and cppcheck over flight/ and fixedpoint/; function size over ground/"
bash scripts/assurance/tidy.sh build/default

step "sanitizer build (clang++: address, undefined, float-cast-overflow, float-divide-by-zero)"
cmake --preset sanitize >/dev/null
cmake --build --preset sanitize
run_ctest sanitize --preset sanitize

if [ -f scripts/firmware.sh ]; then
  step "firmware: Cortex-M4F and Cortex-M0 builds, heap trap, stack and size; ARM32 bit-exact under qemu"
  SINKWATCH_CTEST_LOG="$logdir/arm.log" bash scripts/firmware.sh
fi

step "consumer builds: add_subdirectory and find_package, g++ and clang++, Release and MinSizeRel, -Wall -Wextra, no warning"
bash scripts/consumer_build.sh

# Assurance (docs/assurance.md, docs/performance.md). Fuzzing is a gate: each
# harness runs for a bounded time from a fixed seed, and a crash, sanitizer
# finding or failed range assertion fails CI. The performance report prints
# figures and never fails on them. Coverage is a gate: 100 % of the lines and
# at least 95 % of the branches of flight/ and fixedpoint/ (docs/coverage.md).
step "assurance: coverage (gate: lines 100 %, branches >= 95 %)"
SINKWATCH_COVERAGE_MIN_LINES=100 SINKWATCH_COVERAGE_MIN_BRANCHES=95 bash scripts/assurance/coverage.sh
step "assurance: fuzzing (${SINKWATCH_FUZZ_SECONDS:-15} s per harness), performance report"
bash scripts/assurance/fuzz.sh "${SINKWATCH_FUZZ_SECONDS:-15}"
bash scripts/assurance/perf_report.sh ||
  echo "assurance: the performance report did not complete (above); figures only, not a gate"

# One closing line over every ctest run above.
step "all test runs"
# ctest counts a skipped test (an opt-in exhaustive sweep) as not failed;
# the total names them apart.
passed=0; failed=0; skipped=0
for log in "$logdir"/*.log; do
  line=$(grep -E 'tests passed, [0-9]+ tests failed out of [0-9]+' "$log" | tail -n 1) || continue
  total=$(sed -E 's/.*out of ([0-9]+).*/\1/' <<<"$line")
  fail=$(sed -E 's/.* ([0-9]+) tests failed.*/\1/' <<<"$line")
  skip=$(grep -cE '\(Skipped\)$' "$log" || true)
  printf '%-10s %s (%s skipped)\n' "$(basename "$log" .log)" "$line" "$skip"
  passed=$((passed + total - fail - skip)); failed=$((failed + fail)); skipped=$((skipped + skip))
done
echo "total: ${passed} passed, ${failed} failed, ${skipped} skipped"
[ "$failed" -eq 0 ]

#!/usr/bin/env bash
# Line and branch coverage of the flight code (flight/, fixedpoint/) from the
# host unit tests and property tests that exercise it (docs/assurance.md).
#   g++ --coverage, Debug (the `coverage` preset, build/coverage);
#   builds and runs the tests of host_tests/{fixedpoint,flight,rover,firmware}
#   and props/{fixedpoint,flight,rover} (ctest per directory);
#   gcovr over flight/ and fixedpoint/: text summary and per-file table on
#   stdout, HTML with every line in build/coverage/coverage/index.html.
# Prints the figures; exits non-zero only when a build or a test fails.
# SINKWATCH_COVERAGE_MIN_LINES / _MIN_BRANCHES (percent) turn it into a gate.
set -euo pipefail
cd "$(dirname "$0")/../.."

areas_tests=(fixedpoint flight rover firmware)
areas_props=(fixedpoint flight rover)
dir=build/coverage

cmake --preset coverage >/dev/null
targets=()
for a in "${areas_tests[@]}"; do [ -d "host_tests/$a" ] && targets+=("host_tests/$a/all"); done
for a in "${areas_props[@]}"; do [ -d "props/$a" ] && targets+=("props/$a/all"); done
cmake --build --preset coverage --target "${targets[@]}"

# Counters from an earlier run would inflate the figures.
find "$dir" -name '*.gcda' -delete
status=0
for t in "${targets[@]}"; do
  sub="$dir/${t%/all}"
  ctest --test-dir "$sub" -j2 --output-on-failure > "$dir/ctest_$(echo "${t%/all}" | tr / _).log" 2>&1 || status=1
  echo "${t%/all}: $(grep -E 'tests passed' "$dir/ctest_$(echo "${t%/all}" | tr / _).log" || echo 'no summary')"
done

# Scope: the code that flies. Excluded: the firmware image (not built on the
# host) and fixedpoint/src/fixedpoint_check.cpp (a compile-only check of the
# strict flags: it instantiates every operation and is never run).
filters=(--filter '^flight/(include|src|c_api)/' --filter '^fixedpoint/include/')
mkdir -p "$dir/coverage"
gcovr -r . "${filters[@]}" --exclude '^flight/firmware/' --exclude '^fixedpoint/src/' \
  --object-directory "$dir" --print-summary \
  --html-details "$dir/coverage/index.html" --json "$dir/coverage/coverage.json" \
  --txt "$dir/coverage/lines.txt" "$dir" | tee "$dir/coverage/summary.txt" | tail -n 3
gcovr -r . --add-tracefile "$dir/coverage/coverage.json" --branches --txt "$dir/coverage/branches.txt" >/dev/null
echo "---- per file (lines)"
sed -n '1,200p' "$dir/coverage/lines.txt"
echo "---- per file (branches)"
sed -n '1,200p' "$dir/coverage/branches.txt"

lines=$(sed -nE 's/^lines: ([0-9.]+)%.*/\1/p' "$dir/coverage/summary.txt")
branches=$(sed -nE 's/^branches: ([0-9.]+)%.*/\1/p' "$dir/coverage/summary.txt")
echo "coverage scope=flight,fixedpoint lines=${lines}% branches=${branches}%"
if [ -n "${SINKWATCH_COVERAGE_MIN_LINES:-}" ] && awk -v a="$lines" -v b="$SINKWATCH_COVERAGE_MIN_LINES" 'BEGIN{exit !(a<b)}'; then
  echo "coverage gate: lines ${lines}% < ${SINKWATCH_COVERAGE_MIN_LINES}%"; status=1
fi
if [ -n "${SINKWATCH_COVERAGE_MIN_BRANCHES:-}" ] && awk -v a="$branches" -v b="$SINKWATCH_COVERAGE_MIN_BRANCHES" 'BEGIN{exit !(a<b)}'; then
  echo "coverage gate: branches ${branches}% < ${SINKWATCH_COVERAGE_MIN_BRANCHES}%"; status=1
fi
exit "$status"

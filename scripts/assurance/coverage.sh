#!/usr/bin/env bash
# Line and branch coverage of the flight code (flight/, fixedpoint/) from the
# host unit tests and property tests that exercise it (docs/assurance.md).
#   g++ --coverage, Debug (the `coverage` preset, build/coverage);
#   builds and runs the tests of host_tests/{fixedpoint,flight,rover,firmware}
#   and props/{fixedpoint,flight,rover} (ctest per directory);
#   gcovr over flight/ and fixedpoint/: text summary and per-file table on
#   stdout, HTML with every line in build/coverage/coverage/index.html.
#   build/coverage/coverage/per_file.txt: lines, branches and functions per
#   file; uncovered.txt: every unexecuted line and every line with an untaken
#   branch, with its source text (docs/coverage.md explains each one).
# gcovr runs with its defaults: every branch gcov reports counts, none is
# excluded (--exclude-unreachable-branches and --exclude-throw-branches change
# nothing here: the flight code is noexcept and built without exceptions).
# Prints the figures; exits non-zero only when a build or a test fails.
# SINKWATCH_COVERAGE_MIN_LINES / _MIN_BRANCHES (percent) turn it into a gate;
# docs/coverage.md gives the recommended values.
set -euo pipefail
cd "$(dirname "$0")/../.."

areas_tests=(fixedpoint flight rover firmware)
areas_props=(fixedpoint flight rover)
dir=build/coverage

cmake --preset coverage >/dev/null
# A source edited while this runs (a shared checkout) leaves objects built
# from two versions of a header; gcovr then stops on an assertion. Noticed
# below and reported.
stamp=$(mktemp)
trap 'rm -f "$stamp"' EXIT
sources_changed() {
  local changed
  changed=$(find flight fixedpoint -newer "$stamp" -type f | head -n 5)
  [ -z "$changed" ] && return 1
  echo "coverage: WARNING sources changed during the run, the figures mix versions; run again:"
  echo "$changed"
}
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
if ! gcovr -r . "${filters[@]}" --exclude '^flight/firmware/' --exclude '^fixedpoint/src/' \
  --object-directory "$dir" --print-summary \
  --html-details "$dir/coverage/index.html" --json "$dir/coverage/coverage.json" \
  --txt "$dir/coverage/lines.txt" "$dir" | tee "$dir/coverage/summary.txt" | tail -n 3; then
  echo "coverage: gcovr failed"
  sources_changed || true
  exit 1
fi
gcovr -r . --add-tracefile "$dir/coverage/coverage.json" --branches --txt "$dir/coverage/branches.txt" >/dev/null
echo "---- per file (lines)"
sed -n '1,200p' "$dir/coverage/lines.txt"
echo "---- per file (branches)"
sed -n '1,200p' "$dir/coverage/branches.txt"

# Lines, branches and functions per file, and the uncovered lines and
# branches with their source text, from gcovr's JSON.
python3 - "$dir/coverage/coverage.json" "$dir/coverage/per_file.txt" "$dir/coverage/uncovered.txt" <<'PY'
import json
import sys

data = json.load(open(sys.argv[1]))

def pct(hit, total):
    return "--" if total == 0 else "%.1f" % (100.0 * hit / total)

rows, gaps = [], []
for f in sorted(data["files"], key=lambda f: f["file"]):
    lines = [l for l in f["lines"] if not l.get("gcovr/noncode") and not l.get("gcovr/excluded")]
    lh = sum(1 for l in lines if l["count"] > 0)
    branches = [b for l in lines for b in l["branches"]]
    bh = sum(1 for b in branches if b["count"] > 0)
    fh = sum(1 for fn in f["functions"] if fn["execution_count"] > 0)
    rows.append("%-58s %6s%% %4d/%-4d %6s%% %4d/%-4d %6s%% %3d/%-3d" % (
        f["file"], pct(lh, len(lines)), lh, len(lines), pct(bh, len(branches)), bh, len(branches),
        pct(fh, len(f["functions"])), fh, len(f["functions"])))
    try:
        text = open(f["file"]).read().split("\n")
    except OSError:
        text = []
    for l in lines:
        untaken = [i for i, b in enumerate(l["branches"]) if b["count"] == 0]
        if l["count"] == 0 or untaken:
            src = text[l["line_number"] - 1].strip() if l["line_number"] <= len(text) else ""
            what = "not run" if l["count"] == 0 else "branches %s of %d untaken" % (
                ",".join(str(i) for i in untaken), len(l["branches"]))
            gaps.append("%s:%d: %s | %s" % (f["file"], l["line_number"], what, src))

with open(sys.argv[2], "w") as out:
    out.write("%-58s %18s %18s %16s\n" % ("file", "lines", "branches", "functions"))
    out.write("\n".join(rows) + "\n")
with open(sys.argv[3], "w") as out:
    out.write("\n".join(gaps) + ("\n" if gaps else ""))
PY
echo "---- per file (lines, branches, functions): $dir/coverage/per_file.txt"
cat "$dir/coverage/per_file.txt"
echo "---- uncovered lines and branches: $dir/coverage/uncovered.txt ($(wc -l < "$dir/coverage/uncovered.txt") lines)"

sources_changed || true

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

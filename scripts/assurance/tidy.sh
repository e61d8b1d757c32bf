#!/usr/bin/env bash
# Static analysis of the flight code (flight/, fixedpoint/), docs/assurance.md:
#   clang-tidy with the repository's .clang-tidy (the MISRA C++:2023
#     approximation; docs/misra.md maps checks to rules) over every flight and
#     fixed-point source, headers included through its HeaderFilterRegex, with
#     the compile database of a host build (default: build/default, configured
#     if missing; nothing is compiled);
#   cppcheck --enable=warning,style,performance,portability over the same
#     sources, suppressions with reasons in scripts/assurance/cppcheck-suppressions.txt.
# and a second clang-tidy pass, "ground function size", with ground/.clang-tidy
# (readability-function-size only: 60 lines, 60 statements, 7 parameters,
# nesting 4; docs/conventions.md, "Function size") over the ground tools'
# sources (ground/*/src, ground/cli, ground/*/tools), the ground headers
# through its HeaderFilterRegex.
# Prints every finding once, the count per check, and one line per tool:
#   static_analysis tool=<clang-tidy|cppcheck|clang-tidy-ground> findings=<n>
# A tool that fails without reporting a finding (a crash, a source missing
# from the compile database, a bad option) counts as a finding too.
# Exit status: 0 with zero findings, 1 otherwise (the gate); 2 when the build
# directory or the tools are missing.
#
#   scripts/assurance/tidy.sh [build dir with compile_commands.json]
set -euo pipefail
cd "$(dirname "$0")/../.."

build=${1:-build/default}
if [ ! -f "$build/compile_commands.json" ]; then
  if [ "$build" = build/default ]; then
    cmake --preset default >/dev/null
  else
    echo "tidy: $build/compile_commands.json missing"; exit 2
  fi
fi
out=$(mktemp -d)
trap 'rm -rf "$out"' EXIT

sources=$(ls flight/src/*.cpp flight/c_api/src/*.cpp fixedpoint/src/*.cpp)
tidy=$(command -v clang-tidy-14 || command -v clang-tidy || true)
if [ -z "$tidy" ] || ! command -v cppcheck > /dev/null; then
  echo "tidy: clang-tidy and cppcheck are needed (scripts/setup.sh installs them)"; exit 2
fi
finding='^/.*:[0-9]+:[0-9]+: (warning|error): .*\[[A-Za-z0-9._,-]+\]$'
# clang-tidy over the files given, one process per file, two at a time, each
# writing its own log and exit code into directory $1; $2: extra option (a
# --config-file) or ''.
tidy_each() {
  local dir=$1 option=$2; shift 2
  mkdir -p "$dir"
  # shellcheck disable=SC2016
  printf '%s\n' "$@" | xargs -P 2 -I{} sh -c \
    'log="$2/$(echo "{}" | tr / _)"; "$0" -p "$1" ${3:+"$3"} --quiet "{}" > "$log.log" 2> "$log.err"; echo $? > "$log.rc"' \
    "$tidy" "$build" "$dir" "$option"
}
# clang-tidy failing without a finding (a crash, a file missing from the
# compile database) must not pass as "no finding": each such file in
# directory $1 counts, appended to the findings file $2.
count_failures() {
  local rc base
  for rc in "$1"/*.rc; do
    base=${rc%.rc}
    if [ "$(cat "$rc")" != 0 ] && ! grep -qE "$finding" "$base.log"; then
      echo "tidy: clang-tidy exited $(cat "$rc") without a finding on $(basename "$base"): [clang-tidy-failed]" >> "$2"
      head -n 5 "$base.err"
    fi
  done
}
# shellcheck disable=SC2086
tidy_each "$out/flight" '' $sources
# A header finding is reported by every file that includes it: keep it once.
cat "$out"/flight/*.log | grep -E "$finding" | sed "s|^$(pwd)/||" | sort -u > "$out/tidy.txt" || true
count_failures "$out/flight" "$out/tidy.txt"
tidy_n=$(wc -l < "$out/tidy.txt")
echo "---- clang-tidy findings"
cat "$out/tidy.txt"
echo "---- clang-tidy findings per check"
sed -E 's/.*\[([A-Za-z0-9._,-]+)\]$/\1/' "$out/tidy.txt" | tr ',' '\n' | grep -v '^-warnings-as-errors' |
  sort | uniq -c | sort -rn || true

echo "---- cppcheck"
# shellcheck disable=SC2086
cppcheck --quiet --std=c++17 --language=c++ --enable=warning,style,performance,portability \
  --inline-suppr --suppressions-list=scripts/assurance/cppcheck-suppressions.txt \
  -I flight/include -I fixedpoint/include -I flight/c_api/include \
  --template='{file}:{line}:{column}: {severity}: {message} [{id}]' \
  $sources > "$out/cppcheck.out" 2> "$out/cppcheck.txt" || cpp_rc=$?
grep -E '^[^ ].*:[0-9]+:[0-9]+: ' "$out/cppcheck.txt" | sort -u > "$out/cppcheck_findings.txt" || true
# cppcheck exits 0 with findings (no --error-exitcode); non-zero is a failure
# of the tool itself (bad option, unreadable suppressions, no source).
if [ "${cpp_rc:-0}" != 0 ]; then
  echo "tidy: cppcheck exited $cpp_rc: [cppcheck-failed]" >> "$out/cppcheck_findings.txt"
  tail -n 5 "$out/cppcheck.out" "$out/cppcheck.txt"
fi
cat "$out/cppcheck_findings.txt"
echo "---- cppcheck findings per id"
sed -E 's/.*\[([A-Za-z0-9_]+)\]$/\1/' "$out/cppcheck_findings.txt" | sort | uniq -c | sort -rn || true
cpp_n=$(wc -l < "$out/cppcheck_findings.txt")

echo "---- ground function size (clang-tidy, ground/.clang-tidy)"
ground_sources=$(ls ground/*/src/*.cpp ground/cli/*.cpp ground/*/tools/*.cpp 2>/dev/null || true)
ground_start=$(date +%s)
# shellcheck disable=SC2086
tidy_each "$out/ground" --config-file=ground/.clang-tidy $ground_sources
# Each finding with the sizes that broke the limit, from the notes that
# follow it ("66 lines including whitespace and comments
# (threshold 60)", "nesting level 5 (threshold 4)").
for log in "$out"/ground/*.log; do
  finding="$finding" awk '
    function flush() {
      if (held != "" && details != "") sub(/ \[/, ": " details " [", held)
      if (held != "") print held
      held = ""; details = ""
    }
    $0 ~ ENVIRON["finding"] { flush(); held = $0; next }
    held != "" && / note: .*\(threshold [0-9]+\)$/ {
      note = $0; sub(/.* note: /, "", note)
      sub(/ starts here/, "", note)
      details = details (details == "" ? "" : ", ") note
    }
    END { flush() }' "$log"
done | sed "s|^$(pwd)/||" | sort -u > "$out/ground.txt" || true
count_failures "$out/ground" "$out/ground.txt"
ground_n=$(wc -l < "$out/ground.txt")
cat "$out/ground.txt"
echo "ground function size: $(echo "$ground_sources" | wc -l) files in $(( $(date +%s) - ground_start )) s"

echo "static_analysis tool=clang-tidy findings=$tidy_n"
echo "static_analysis tool=cppcheck findings=$cpp_n"
echo "static_analysis tool=clang-tidy-ground findings=$ground_n"
[ "$tidy_n" -eq 0 ] && [ "$cpp_n" -eq 0 ] && [ "$ground_n" -eq 0 ]

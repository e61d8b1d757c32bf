#!/usr/bin/env bash
# Static analysis of the flight code (flight/, fixedpoint/), docs/assurance.md:
#   clang-tidy with the repository's .clang-tidy (the MISRA C++:2023
#     approximation; docs/misra.md maps checks to rules) over every flight and
#     fixed-point source, headers included through its HeaderFilterRegex, with
#     the compile database of a host build (default: build/default, configured
#     if missing; nothing is compiled);
#   cppcheck --enable=warning,style,performance,portability over the same
#     sources, suppressions with reasons in scripts/assurance/cppcheck-suppressions.txt.
# Prints every finding once, the count per check, and one line per tool:
#   static_analysis tool=<clang-tidy|cppcheck> findings=<n>
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
# One process per file, two at a time; each writes its own log and exit code.
# shellcheck disable=SC2086,SC2016
printf '%s\n' $sources | xargs -P 2 -I{} sh -c \
  'log="$2/$(echo "{}" | tr / _)"; "$0" -p "$1" --quiet "{}" > "$log.log" 2> "$log.err"; echo $? > "$log.rc"' \
  "$tidy" "$build" "$out"
# A header finding is reported by every file that includes it: keep it once.
cat "$out"/*.log | grep -E "$finding" | sed "s|^$(pwd)/||" | sort -u > "$out/tidy.txt" || true
# clang-tidy failing without a finding (a crash, a file missing from the
# compile database) must not pass as "no finding": each such file counts.
for rc in "$out"/*.rc; do
  base=${rc%.rc}
  if [ "$(cat "$rc")" != 0 ] && ! grep -qE "$finding" "$base.log"; then
    echo "tidy: clang-tidy exited $(cat "$rc") without a finding on $(basename "$base"): [clang-tidy-failed]" >> "$out/tidy.txt"
    head -n 5 "$base.err"
  fi
done
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

echo "static_analysis tool=clang-tidy findings=$tidy_n"
echo "static_analysis tool=cppcheck findings=$cpp_n"
[ "$tidy_n" -eq 0 ] && [ "$cpp_n" -eq 0 ]

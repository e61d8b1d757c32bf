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
# Exit status: 0 with zero findings, 1 otherwise (the gate).
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
tidy=$(command -v clang-tidy-14 || command -v clang-tidy)
# One process per file, two at a time; each writes its own log.
# shellcheck disable=SC2086
printf '%s\n' $sources | xargs -P 2 -I{} sh -c \
  '"$0" -p "$1" --quiet "{}" > "$2/$(echo "{}" | tr / _).log" 2>/dev/null || true' "$tidy" "$build" "$out"
# A header finding is reported by every file that includes it: keep it once.
cat "$out"/*.log | grep -E '^/.*:[0-9]+:[0-9]+: (warning|error): .*\[[A-Za-z0-9._,-]+\]$' |
  sed "s|^$(pwd)/||" | sort -u > "$out/tidy.txt" || true
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
  $sources 2> "$out/cppcheck.txt" || true
grep -E '^[^ ].*:[0-9]+:[0-9]+: ' "$out/cppcheck.txt" | sort -u > "$out/cppcheck_findings.txt" || true
cat "$out/cppcheck_findings.txt"
echo "---- cppcheck findings per id"
sed -E 's/.*\[([A-Za-z0-9_]+)\]$/\1/' "$out/cppcheck_findings.txt" | sort | uniq -c | sort -rn || true
cpp_n=$(wc -l < "$out/cppcheck_findings.txt")

echo "static_analysis tool=clang-tidy findings=$tidy_n"
echo "static_analysis tool=cppcheck findings=$cpp_n"
[ "$tidy_n" -eq 0 ] && [ "$cpp_n" -eq 0 ]

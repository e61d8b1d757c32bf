#!/usr/bin/env bash
# Runs every libFuzzer harness of fuzz/ for a bounded time over its committed
# seed corpus (docs/assurance.md) and prints one line per harness:
#   fuzz harness=<name> seed=<n> seconds=<s> execs=<n> cov=<edges> corpus=<inputs> result=<ok|FAILED>
# A crash, a sanitizer finding, a failed range assertion or a leak fails the
# script; the input that caused it is kept in build/fuzz/artifacts/.
#
#   scripts/assurance/fuzz.sh [seconds per harness, default 25] [harness ...]
# SINKWATCH_FUZZ_SECONDS overrides the default too. New corpus entries found
# go to build/fuzz/corpus/<harness> (never back into fuzz/corpus/).
set -euo pipefail
cd "$(dirname "$0")/../.."

seconds=${1:-${SINKWATCH_FUZZ_SECONDS:-25}}
# A fixed seed, so that the mutations CI tries can be tried again by hand
# (set SINKWATCH_FUZZ_SEED to explore further).
seed=${SINKWATCH_FUZZ_SEED:-20261121}
shift || true
harnesses=("$@")
[ ${#harnesses[@]} -gt 0 ] || harnesses=(param_table rover_step soil_bin_csv telemetry_csv wide_divmod)

if ! command -v clang++ >/dev/null || ! ls /usr/lib/llvm-*/lib/clang/*/lib/linux/libclang_rt.fuzzer-x86_64.a >/dev/null 2>&1; then
  echo "fuzz: clang++ or libFuzzer (libclang-rt-14-dev) missing: skipped"
  exit 0
fi

cmake --preset fuzz >/dev/null
dir=build/fuzz
mkdir -p "$dir/artifacts"
failed=0
for h in "${harnesses[@]}"; do
  bin="$dir/fuzz/fuzz_$h"
  # One harness at a time: a broken library fails its harness, not the rest.
  if ! cmake --build --preset fuzz --target "fuzz_$h" >"$dir/build_$h.log" 2>&1; then
    echo "fuzz harness=$h seconds=0 execs=0 cov=0 corpus=0 result=BUILD-FAILED"
    grep -E 'error' "$dir/build_$h.log" | head -n 5
    failed=1
    continue
  fi
  work="$dir/corpus/$h"
  mkdir -p "$work"
  log="$dir/fuzz_$h.log"
  status=ok
  # -timeout: one input slower than 10 s is a hang; -rss_limit_mb: a leak
  # or runaway allocation is a finding. The seeds are read, never written.
  if ! "$bin" -seed="$seed" -max_total_time="$seconds" -timeout=10 -rss_limit_mb=2048 -print_final_stats=1 \
      -artifact_prefix="$dir/artifacts/${h}-" "$work" "fuzz/corpus/$h" >"$log" 2>&1; then
    status=FAILED
    failed=1
  fi
  execs=$(awk '/stat::number_of_executed_units/ {print $2}' "$log" | tail -n 1)
  cov=$(grep -oE 'cov: [0-9]+' "$log" | tail -n 1 | awk '{print $2}')
  corpus=$(find "$work" -type f | wc -l)
  echo "fuzz harness=$h seed=$seed seconds=$seconds execs=${execs:-0} cov=${cov:-0} corpus=$corpus result=$status"
  if [ "$status" != ok ]; then
    echo "---- tail of $log"
    tail -n 40 "$log"
  fi
done
exit "$failed"

#!/usr/bin/env bash
# Runs the libFuzzer harnesses of fuzz/ (docs/assurance.md, "Fuzzing").
#
# Smoke mode (CI): each harness for a bounded time over its committed seed
# corpus, one line per harness:
#   fuzz harness=<name> seed=<n> seconds=<s> execs=<n> cov=<edges> corpus=<inputs> result=<ok|FAILED>
#   scripts/assurance/fuzz.sh [seconds per harness, default 25] [harness ...]
# SINKWATCH_FUZZ_SECONDS overrides the default too. New corpus entries found
# go to build/fuzz/corpus/<harness> (never back into fuzz/corpus/).
#
# Long mode (issue 18; not run in CI, by hand, one harness at a time):
#   scripts/assurance/fuzz.sh --long [harness ...]
# runs each harness to SINKWATCH_FUZZ_RUNS executions (default 10,000,000,
# libFuzzer -runs=) starting from the committed corpus only, then merges the
# inputs it found that add coverage into fuzz/corpus/<harness>/ (-merge=1 into
# the kept corpus: the seeds stay, only new features are added, inputs above
# SINKWATCH_FUZZ_MAX_LEN bytes are not kept). One line per harness:
#   fuzz-long harness=<name> seed=<n> execs=<n> seconds=<s> exec_per_s=<n> corpus_before=<files> corpus_after=<files> cov=<edges> ft=<features> result=<ok|FAILED|TIME-CAPPED>
# SINKWATCH_FUZZ_LONG_MAX_SECONDS (default 0: none) caps one harness's run;
# a run that stops on the cap before its executions is TIME-CAPPED (reported,
# not a failure). Commit fuzz/corpus/ afterwards (check `du -sh fuzz/corpus/*`).
#
# A crash, a sanitizer finding, a failed range assertion or a leak fails the
# script in both modes; the input that caused it is kept in
# build/fuzz/artifacts/.
set -euo pipefail
cd "$(dirname "$0")/../.."

mode=smoke
if [ "${1:-}" = "--long" ]; then
  mode=long
  shift
  seconds=0
else
  seconds=${1:-${SINKWATCH_FUZZ_SECONDS:-25}}
  shift || true
fi
# A fixed seed, so that the mutations CI tries can be tried again by hand
# (set SINKWATCH_FUZZ_SEED to explore further).
seed=${SINKWATCH_FUZZ_SEED:-20261121}
runs=${SINKWATCH_FUZZ_RUNS:-10000000}
long_cap=${SINKWATCH_FUZZ_LONG_MAX_SECONDS:-0}
max_len=${SINKWATCH_FUZZ_MAX_LEN:-4096}
harnesses=("$@")
[ ${#harnesses[@]} -gt 0 ] || harnesses=(param_table rover_step step_differential soil_bin_csv telemetry_csv wide_divmod)

if ! command -v clang++ >/dev/null || ! ls /usr/lib/llvm-*/lib/clang/*/lib/linux/libclang_rt.fuzzer-x86_64.a >/dev/null 2>&1; then
  echo "fuzz: clang++ or libFuzzer (libclang-rt-14-dev) missing: skipped"
  exit 0
fi

cmake --preset fuzz >/dev/null
dir=build/fuzz
mkdir -p "$dir/artifacts"

# Prints the last "cov: N" or "ft: N" figure of a libFuzzer log.
last_figure() {
  grep -oE "$1: [0-9]+" "$2" | tail -n 1 | awk '{print $2}'
}

# The bounded smoke run of one harness ($1 name, $2 binary); returns 1 on a
# finding.
run_smoke() {
  local h=$1 bin=$2 work="$dir/corpus/$1" log="$dir/fuzz_$1.log" status=ok
  mkdir -p "$work"
  # -timeout: one input slower than 10 s is a hang; -rss_limit_mb: a leak
  # or runaway allocation is a finding. The seeds are read, never written.
  if ! "$bin" -seed="$seed" -max_total_time="$seconds" -timeout=10 -rss_limit_mb=2048 -print_final_stats=1 \
      -artifact_prefix="$dir/artifacts/${h}-" "$work" "fuzz/corpus/$h" >"$log" 2>&1; then
    status=FAILED
  fi
  local execs cov corpus
  execs=$(awk '/stat::number_of_executed_units/ {print $2}' "$log" | tail -n 1)
  cov=$(last_figure cov "$log")
  corpus=$(find "$work" -type f | wc -l)
  echo "fuzz harness=$h seed=$seed seconds=$seconds execs=${execs:-0} cov=${cov:-0} corpus=$corpus result=$status"
  [ "$status" = ok ] || { echo "---- tail of $log"; tail -n 40 "$log"; return 1; }
}

# The long run of one harness ($1 name, $2 binary) and the merge of what it
# found into the committed corpus; returns 1 on a finding.
run_long() {
  local h=$1 bin=$2 work="$dir/long/$1" log="$dir/fuzz_long_$1.log" status=ok
  local kept="fuzz/corpus/$h"
  # A fresh working corpus: the run starts from the committed corpus alone.
  rm -rf "$work"
  mkdir -p "$work" "$kept"
  local before start_ms end_ms
  before=$(find "$kept" -type f | wc -l)
  start_ms=$(date +%s%3N)
  if ! "$bin" -seed="$seed" -runs="$runs" -max_total_time="$long_cap" -max_len="$max_len" -timeout=10 \
      -rss_limit_mb=2048 -print_final_stats=1 -artifact_prefix="$dir/artifacts/${h}-" \
      "$work" "$kept" >"$log" 2>&1; then
    status=FAILED
  fi
  end_ms=$(date +%s%3N)
  local execs ms cov ft after
  execs=$(awk '/stat::number_of_executed_units/ {print $2}' "$log" | tail -n 1)
  execs=${execs:-0}
  ms=$((end_ms - start_ms > 0 ? end_ms - start_ms : 1))
  cov=$(last_figure cov "$log")
  ft=$(last_figure ft "$log")
  if [ "$status" = ok ] && [ "$execs" -lt "$runs" ]; then
    status=TIME-CAPPED
  fi
  if [ "$status" != FAILED ]; then
    # Only inputs that add coverage to the kept corpus are copied into it.
    "$bin" -merge=1 -max_len="$max_len" -timeout=10 -rss_limit_mb=2048 "$kept" "$work" \
      >"$dir/merge_long_$h.log" 2>&1 || status=FAILED
  fi
  after=$(find "$kept" -type f | wc -l)
  echo "fuzz-long harness=$h seed=$seed execs=$execs seconds=$((ms / 1000)).$(printf %03d $((ms % 1000))) exec_per_s=$((execs * 1000 / ms)) corpus_before=$before corpus_after=$after cov=${cov:-0} ft=${ft:-0} result=$status"
  [ "$status" != FAILED ] || { echo "---- tail of $log"; tail -n 40 "$log"; return 1; }
}

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
  if [ "$mode" = long ]; then
    run_long "$h" "$bin" || failed=1
  else
    run_smoke "$h" "$bin" || failed=1
  fi
done
exit "$failed"

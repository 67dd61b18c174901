#!/usr/bin/env bash
# Builds the libFuzzer targets (clang, ASan + UBSan) in build-check/ (shared with
# tools/sanitize.sh: one instrumented build serves both) and runs them side by side for a
# bounded time, each on a scratch copy of its seed corpus. Usage: tools/fuzz.sh [seconds]
# [target...]. Exits non-zero if a target finds a crash, leak, timeout or OOM;
# the input is kept in build-check/findings/<target>/ (add it to tests/fuzz/regressions/
# after the fix).
set -euo pipefail
cd "$(dirname "$0")/.."
seconds=${1:-20}
shift || true
targets=("$@")
[ ${#targets[@]} -gt 0 ] || targets=(fuzz_read fuzz_verify fuzz_pipeline)
jobs=$(nproc 2>/dev/null || echo 2)
root=$PWD

CC=clang CXX=clang++ cmake -S . -B build-check -DCMAKE_BUILD_TYPE=RelWithDebInfo -DDTHEX_FUZZ=ON >/dev/null
cmake --build build-check -j"$jobs" --target "${targets[@]}" >/dev/null

# One target's run: a scratch copy of its corpus, then libFuzzer for the given time; its
# exit status is the fuzzer's.
fuzz_one() {
  local target=$1 work=build-check/run/$1 findings=build-check/findings/$1
  rm -rf "$work"
  mkdir -p "$work/corpus" "$findings"
  cp tests/fuzz/corpus/"$target"/* "$work/corpus/"
  [ -d tests/fuzz/regressions/"$target" ] && cp tests/fuzz/regressions/"$target"/* "$work/corpus/" 2>/dev/null || true
  # -timeout: one input may take this long (the pipeline's own limits are 2 s per stage);
  # -rss_limit_mb: more than this is a memory bug on inputs of at most a few KB.
  local per_input=10
  [ "$target" = fuzz_pipeline ] && per_input=60
  (cd "$work" && OMP_NUM_THREADS=1 ASAN_OPTIONS=detect_leaks=1 "$root/build-check/tests/fuzz/$target" -max_total_time="$seconds" \
     -timeout="$per_input" -rss_limit_mb=2048 -max_len=4096 -print_final_stats=1 \
     -artifact_prefix="$root/$findings/" corpus >log.txt 2>&1)
}

# The targets run side by side, each on one thread (OMP_NUM_THREADS=1: the pipeline's
# untangler and measurement would take both cores), so the wall time is `seconds`, not their
# sum; with more targets than cores each gets its share of them.
declare -A pid_of
for target in "${targets[@]}"; do
  fuzz_one "$target" &
  pid_of[$target]=$!
done
failed=0
for target in "${targets[@]}"; do
  work=build-check/run/$target
  findings=build-check/findings/$target
  set +e
  wait "${pid_of[$target]}"
  status=$?
  set -e
  runs=$(grep -E "^stat::number_of_executed_units" "$work/log.txt" | awk '{print $2}')
  if [ $status -ne 0 ]; then
    echo "fuzz: $target FAILED after ${runs:-?} runs (exit $status); log $work/log.txt, input in $findings/"
    grep -E "ERROR|SUMMARY|Test unit written" "$work/log.txt" | head -5 || true
    failed=1
  else
    echo "fuzz: $target ok: ${runs:-?} runs in ${seconds} s, no finding"
  fi
done
exit $failed

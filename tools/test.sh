#!/usr/bin/env bash
# Runs everything CI checks (after tools/setup.sh built build/): the test suite, the
# sanitizer build of the input-facing suites (tools/sanitize.sh) and a bounded fuzzing
# run of every target (tools/fuzz.sh: the three side by side for FUZZ_SECONDS, default 30,
# on two cores about 20 s of one core each). Prints one line per
# part and "N passed, M failed"; exits non-zero if any part failed.
set -uo pipefail
cd "$(dirname "$0")/.."
jobs=$(nproc 2>/dev/null || echo 2)
passed=0
failed=0
part() {
  local name=$1
  shift
  local start=$SECONDS
  if "$@"; then
    echo "test.sh: $name passed ($((SECONDS - start)) s)"
    passed=$((passed + 1))
  else
    echo "test.sh: $name FAILED ($((SECONDS - start)) s)"
    failed=$((failed + 1))
  fi
}
part "test suite" ctest --test-dir build --output-on-failure -j"$jobs"
part "sanitizers" bash tools/sanitize.sh
part "fuzzing" bash tools/fuzz.sh "${FUZZ_SECONDS:-30}"
echo "test.sh: $passed passed, $failed failed"
[ "$failed" -eq 0 ]

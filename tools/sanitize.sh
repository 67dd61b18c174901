#!/usr/bin/env bash
# Builds the test suite with AddressSanitizer + UndefinedBehaviorSanitizer in
# build-sanitize/ and runs it. Usage: tools/sanitize.sh [ctest -R regex]. Without an
# argument it runs the suites that exercise untrusted input and failure paths (the
# readers, verification, writers, the command, the hostile catalogue, the fuzz
# regressions); the slow meshing suites on the big shared meshes would take too long
# 2-3x slower under ASan for CI's 15-minute budget.
set -euo pipefail
cd "$(dirname "$0")/.."
filter=${1:-'ReadSurface|VerifySurface|AtomicFile|OutputFile|WriteHexMesh|WriteSurface|Cli|HostileInput|HostileCatalogue|FailurePaths|MemoryBudget|FuzzRegression|Tetrahedralize'}
jobs=$(nproc 2>/dev/null || echo 2)
cmake -S . -B build-sanitize -DCMAKE_BUILD_TYPE=RelWithDebInfo -DDTHEX_SANITIZE=ON >/dev/null
cmake --build build-sanitize -j"$jobs" >/dev/null
# The ASan runtime must see every error as fatal; a leak at exit counts.
export ASAN_OPTIONS=detect_leaks=1:abort_on_error=1:halt_on_error=1
export UBSAN_OPTIONS=print_stacktrace=1:halt_on_error=1
ctest --test-dir build-sanitize --output-on-failure -j"$jobs" -R "$filter"

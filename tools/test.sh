#!/usr/bin/env bash
# Runs the whole test suite (after tools/setup.sh built build/).
set -euo pipefail
cd "$(dirname "$0")/.."
jobs=$(nproc 2>/dev/null || echo 2)
ctest --test-dir build --output-on-failure -j"$jobs"

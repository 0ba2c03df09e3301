#!/usr/bin/env bash
# README command 2: install what is missing, build, run the whole test suite (ctest).
# Long statistical tests carry the label "long" and run with a modest default budget here;
# ARCHWAVE_FULL_BUDGET=1 runs them at full size (see docs/testing.md).
set -euo pipefail
cd "$(dirname "$0")/.."
source scripts/prepare.sh
jobs=$(nproc 2>/dev/null || echo 2)
ctest --test-dir build --output-on-failure -j"$jobs" --timeout 600 "$@"

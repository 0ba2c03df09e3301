#!/usr/bin/env bash
# The test suite's host code under AddressSanitizer and UndefinedBehaviorSanitizer (issue 16;
# docs/testing.md#sanitizers). Builds with clang into build-asan/ (-DARCHWAVE_SANITIZE=
# address,undefined: every target, no recovery, so the first report fails its test; the same
# build dir holds scripts/fuzz.sh's targets) and runs the ctest labels given, by default those
# that exercise the loaders, the film, the BVH, the lobes and the material on the host (CI's
# subset); `scripts/sanitize.sh all` runs everything. Leaks inside the OpenCL runtimes and
# libraries archwave links are suppressed by tests/sanitizers/lsan.supp.
# Usage: scripts/sanitize.sh [all | LABEL ...]
set -euo pipefail
cd "$(dirname "$0")/.."
labels=("$@")
[ ${#labels[@]} -gt 0 ] || labels=(scene film types integrator bvh material lobes texture)
bash scripts/setup.sh clang libclang-rt-dev
CC=clang CXX=clang++ cmake -S . -B build-asan -DCMAKE_BUILD_TYPE=RelWithDebInfo -DARCHWAVE_FUZZ=ON \
  -DARCHWAVE_SANITIZE=address,undefined -DARCHWAVE_BUILD_BENCH=OFF >/dev/null
jobs=$(nproc 2>/dev/null || echo 2)
export ASAN_OPTIONS="detect_leaks=1:abort_on_error=1"
export LSAN_OPTIONS="suppressions=$PWD/tests/sanitizers/lsan.supp:print_suppressions=0"
export UBSAN_OPTIONS="print_stacktrace=1:halt_on_error=1"
export POCL_CACHE_DIR="$PWD/build-asan/pocl-cache" ARCHWAVE_KERNEL_CACHE="$PWD/build-asan/kernel-cache"
if [ "${labels[0]}" = all ]; then
  cmake --build build-asan -j"$jobs"
  ctest --test-dir build-asan --output-on-failure -j"$jobs" --timeout 1800
else
  cmake --build build-asan -j"$jobs" --target archwave "${labels[@]/#/test_}"
  regex=$(IFS='|'; echo "^(${labels[*]})\$")
  ctest --test-dir build-asan --output-on-failure -j"$jobs" --timeout 1800 -L "$regex" -LE "long|intel"
fi

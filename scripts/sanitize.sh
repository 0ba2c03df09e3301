#!/usr/bin/env bash
# The test suite's host code under AddressSanitizer and UndefinedBehaviorSanitizer (issue 16;
# docs/testing.md#sanitizers). Builds with clang into build-asan/ (-DARCHWAVE_SANITIZE=
# address,undefined: every target, no recovery, so the first report fails its test; the same
# build dir holds scripts/fuzz.sh's targets) and runs the ctest labels given, by default those
# that exercise the loaders, the film, the BVH, the lobes and the material on the host, the
# command line, and the render area's production-render and kernel-vs-scalar tests (CI's
# subset); `scripts/sanitize.sh all` runs everything. Leaks inside the OpenCL runtimes and
# libraries archwave links are suppressed by tests/sanitizers/lsan.supp. LeakSanitizer runs
# only in the areas that never start an OpenCL runtime (scene, film, integrator): in a test that
# ran PoCL its tracer crashed at exit (signal 11 inside LeakSanitizer, after the test had passed;
# 1 of 335 tests in a CI run of 2026-12-02), so the others run with AddressSanitizer's other
# checks and UBSan, leak detection off.
# Usage: scripts/sanitize.sh [all | LABEL ...]
set -euo pipefail
cd "$(dirname "$0")/.."
labels=("$@")
default=0
[ ${#labels[@]} -gt 0 ] || { labels=(scene film types integrator bvh material lobes texture cli); default=1; }
# CI's subset also takes the render area's production-render and kernel-vs-scalar tests (the
# film state, merge, resume, device failures, the extremes: host code the CLI tests reach too)
# but not its other renders, which spend their time in PoCL and the scalar path's arithmetic
# (render and cli took 18 min under the sanitizers on 2 cores, -j1; this slice about 40 s).
render_slice='^(Parts|Resume|Merge|Film|Extremes|KernelVsScalar)\.'
bash scripts/setup.sh clang libclang-rt-dev
CC=clang CXX=clang++ cmake -S . -B build-asan -DCMAKE_BUILD_TYPE=RelWithDebInfo -DARCHWAVE_FUZZ=ON \
  -DARCHWAVE_SANITIZE=address,undefined -DARCHWAVE_BUILD_BENCH=OFF >/dev/null
jobs=$(nproc 2>/dev/null || echo 2)
export ASAN_OPTIONS="abort_on_error=1"
export LSAN_OPTIONS="suppressions=$PWD/tests/sanitizers/lsan.supp:print_suppressions=0"
export UBSAN_OPTIONS="print_stacktrace=1:halt_on_error=1"
export POCL_CACHE_DIR="$PWD/build-asan/pocl-cache" ARCHWAVE_KERNEL_CACHE="$PWD/build-asan/kernel-cache"
# The 16384 x 16384 texture test holds 6 GB of texels (20 s); under AddressSanitizer's shadow
# memory and slowdown it would not fit beside another test in CI's machine. Its code paths (the
# loader, the packer, the lookups) run under the sanitizers on the texture area's other images.
asan_exclude='LargestImageReadsItsFarCornerAtLevelZero'
no_cl="^(scene|film|integrator)\$"  # the areas that never start an OpenCL runtime: leak-checked
run() {  # run LABEL_REGEX EXCLUDE_REGEX: the leak-checked areas, then the others in LABEL_REGEX
  local status=0
  ASAN_OPTIONS="$ASAN_OPTIONS:detect_leaks=1" ctest --test-dir build-asan --output-on-failure -j"$jobs" --timeout 1800 -E "$asan_exclude" \
    -L "$no_cl" -LE "$2" || status=1
  ASAN_OPTIONS="$ASAN_OPTIONS:detect_leaks=0" ctest --test-dir build-asan --output-on-failure -j"$jobs" --timeout 1800 -E "$asan_exclude" \
    -L "$1" -LE "$2|^(scene|film|integrator)\$" || status=1
  return $status
}
if [ "${labels[0]}" = all ]; then
  cmake --build build-asan -j"$jobs"
  run "." "^long\$"
else
  targets=("${labels[@]/#/test_}")
  [ $default = 0 ] || targets+=(test_render)
  cmake --build build-asan -j"$jobs" --target archwave "${targets[@]}"
  status=0
  run "^($(IFS='|'; echo "${labels[*]}"))\$" "^(long|intel)\$" || status=1
  if [ $default = 1 ]; then
    ASAN_OPTIONS="$ASAN_OPTIONS:detect_leaks=0" ctest --test-dir build-asan --output-on-failure -j"$jobs" --timeout 1800 -E "$asan_exclude" \
      -L '^render$' -LE '^(long|intel)$' -R "$render_slice" || status=1
  fi
  exit $status
fi

#!/usr/bin/env bash
# Fuzzes what archwave reads from users (issue 16; docs/testing.md#fuzzing): the scene loader,
# the OBJ reader (alone and with its .mtl), the glTF reader and the PNG/JPEG/EXR decoders.
# Builds the libFuzzer targets of tests/fuzz with clang, AddressSanitizer and UBSan into
# build-asan/ (the build scripts/sanitize.sh uses too) and runs each for SECONDS (default 60;
# $ARCHWAVE_FUZZ_SECONDS) from the seed corpus below, keeping what it finds in
# build-asan/fuzz/corpus/<target>/. A crash, a leak, a hang (> 10 s on one input) or a run
# over 2 GB leaves its input in build-asan/fuzz/crashes/ and fails the script: fix it and add
# the input to tests/data/bad (EXPECTED) or the loader tests.
# Usage: scripts/fuzz.sh [SECONDS] [TARGET ...]   (targets: scene obj gltf image)
set -euo pipefail
cd "$(dirname "$0")/.."
secs="${1:-${ARCHWAVE_FUZZ_SECONDS:-60}}"
shift || true
targets=("$@")
[ ${#targets[@]} -gt 0 ] || targets=(scene obj gltf image)
bash scripts/setup.sh clang libclang-rt-dev
CC=clang CXX=clang++ cmake -S . -B build-asan -DCMAKE_BUILD_TYPE=RelWithDebInfo -DARCHWAVE_FUZZ=ON \
  -DARCHWAVE_SANITIZE=address,undefined -DARCHWAVE_BUILD_BENCH=OFF >/dev/null
cmake --build build-asan -j"$(nproc 2>/dev/null || echo 2)" --target "${targets[@]/#/fuzz_}"
out=build-asan/fuzz

# Seeds: the repository's own inputs of each kind, good and bad.
seeds() {
  case "$1" in
    scene) ls scenes/*.json scenes/bench/*.json tests/data/bad/*.json tests/scene/data/*.json 2>/dev/null ;;
    obj) ls scenes/meshes/cup.obj tests/data/bad/*.obj tests/scene/data/*.obj 2>/dev/null ;;
    gltf) ls scenes/meshes/*.gltf tests/data/bad/*.gltf tests/data/bad/*.glb 2>/dev/null ;;
    # (tests/fuzz/seeds: a JPEG and a grey-alpha PNG written with stb_image_write, an EXR
    # written by archwave, a few hundred bytes each.)
    image) ls tests/fuzz/seeds/* scenes/meshes/*.png scenes/docs/textures/*.png tests/data/bad/*.png \
             tests/data/bad/*.exr 2>/dev/null ;;
  esac
}
mkdir -p $out/crashes
status=0
for t in "${targets[@]}"; do
  seed_dir="$out/seeds/$t"
  rm -rf "$seed_dir" && mkdir -p "$seed_dir" "$out/corpus/$t"
  for f in $(seeds "$t"); do [ -f "$f" ] && cp "$f" "$seed_dir/"; done
  echo "fuzz.sh: fuzz_$t for ${secs} s ($(ls "$seed_dir" | wc -l) seeds)" >&2
  # Leaks inside the OpenCL, LLVM and Embree libraries are theirs (tests/sanitizers/lsan.supp).
  if ! LSAN_OPTIONS="suppressions=$PWD/tests/sanitizers/lsan.supp" UBSAN_OPTIONS=print_stacktrace=1 \
      "./build-asan/tests/fuzz/fuzz_$t" -max_total_time="$secs" -timeout=10 -rss_limit_mb=2048 -print_final_stats=1 \
      -artifact_prefix="$out/crashes/$t-" "$out/corpus/$t" "$seed_dir" 2> "$out/fuzz_$t.log"; then
    echo "fuzz.sh: fuzz_$t FAILED; its input is in $out/crashes/, the log in $out/fuzz_$t.log:" >&2
    grep -E "ERROR|SUMMARY|Test unit written" "$out/fuzz_$t.log" | head -20 >&2 || tail -5 "$out/fuzz_$t.log" >&2
    status=1
  else
    grep -E "stat::number_of_executed_units|stat::peak_rss_mb" "$out/fuzz_$t.log" >&2 || true
  fi
done
exit $status

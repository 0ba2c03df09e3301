#!/usr/bin/env bash
# The GPU checks on a machine that has a GPU driver but no archwave build (docs/devices.md#gpus):
# build here, carry one file there, run it in a checkout of the same commit.
#
#   scripts/gpu_check.sh pack [BUILD_DIR] [BUNDLE]   here: archwave, the device tests, the bench
#       programs, the libraries they need beyond glibc and libstdc++ (Embree, OpenEXR, TBB, the
#       ICD loader, ...) and the device tests' filters into BUNDLE (default .gpu/bundle.tar.xz)
#   scripts/gpu_check.sh run BUNDLE [RESULTS_DIR]    there, from the checkout's root: registers
#       NVIDIA's OpenCL library for this process alone (OCL_ICD_VENDORS; nothing under /etc is
#       written), then renders, the traversal bench and the device tests on the GPU; logs, stats
#       and a summary go to RESULTS_DIR (default gpu-check-results/)
#
# `run` needs the checkout at the path the bundle was built from (the test programs carry it),
# or the right to make a symbolic link there. It takes 2-4 minutes on an H200; GPU_CHECK_SKIP
# (e.g. "bench tests") leaves phases out, GPU_CHECK_DEVICE runs on another device than "gpu"
# (to try the script on a CPU); exit 0 when every phase ran and every test passed.
set -uo pipefail

die() { echo "gpu_check: $*" >&2; exit 2; }

pack() {
  local build=${1:-build} bundle=${2:-.gpu/bundle.tar.xz}
  local progs=(archwave bench/bench_traversal bench/exr_compare)
  local area
  [ -f "$build/tests/device_test_filters.txt" ] || die "$build/tests/device_test_filters.txt is missing: build first (scripts/build.sh)"
  while IFS=$'\t' read -r area _; do progs+=("tests/test_$area"); done < "$build/tests/device_test_filters.txt"
  stage=$(mktemp -d)
  trap 'rm -rf "$stage"' EXIT
  mkdir -p "$stage/bin" "$stage/lib"
  local p
  for p in "${progs[@]}"; do
    [ -x "$build/$p" ] || die "$build/$p is missing: build first (scripts/build.sh)"
    cp "$build/$p" "$stage/bin/" && strip "$stage/bin/$(basename "$p")"
  done
  # Every library the programs load except glibc's and the C++ runtime, which the GPU machine
  # has (newer ones serve binaries built against older ones).
  ldd "${progs[@]/#/$build/}" | awk '/=> \// {print $3}' | sort -u |
    grep -vE '/(libc|libm|libdl|libpthread|librt|libgcc_s|libstdc\+\+|ld-linux[^/]*)\.so' |
    while read -r lib; do cp -L "$lib" "$stage/lib/"; done
  cp "$build/tests/device_test_filters.txt" "$stage/"
  { echo "commit $(git rev-parse HEAD 2>/dev/null || echo unknown)"; echo "source $(pwd)"; } > "$stage/manifest"
  mkdir -p "$(dirname "$bundle")"
  tar -C "$stage" -cJf "$bundle" . || die "cannot write $bundle"
  echo "wrote $bundle ($(du -h "$bundle" | cut -f1)); on the GPU machine: scripts/gpu_check.sh run $bundle"
}

run() {
  local bundle=${1:-} res=${2:-gpu-check-results}
  [ -f "$bundle" ] || die "no bundle '$bundle' (make one with: scripts/gpu_check.sh pack)"
  [ -d kernels ] && [ -d scenes ] || die "run it from the root of an archwave checkout"
  local B
  B=$(mktemp -d /tmp/archwave-gpu.XXXXXX)
  tar -C "$B" -xJf "$bundle" || die "cannot unpack $bundle"
  mkdir -p "$res" || die "cannot create $res"
  res=$(cd "$res" && pwd)
  local sum=$res/summary.txt
  : > "$sum"
  note() { echo "$*" | tee -a "$sum"; }
  export LD_LIBRARY_PATH=$B/lib${LD_LIBRARY_PATH:+:$LD_LIBRARY_PATH}
  export ARCHWAVE_KERNEL_CACHE=$B/kernel-cache
  local nv=""
  for f in /usr/lib/x86_64-linux-gnu/libnvidia-opencl.so.1 /usr/local/nvidia/lib64/libnvidia-opencl.so.1 /usr/lib64/libnvidia-opencl.so.1; do
    [ -e "$f" ] && nv=$f && break
  done
  [ -n "$nv" ] || nv=$(find / -xdev -name libnvidia-opencl.so.1 2>/dev/null | head -1)
  if [ -n "$nv" ]; then
    mkdir -p "$B/icd" && echo "$nv" > "$B/icd/nvidia.icd"
    export OCL_ICD_VENDORS=$B/icd
  fi
  note "bundle: $(tr '\n' ' ' < "$B/manifest")"
  note "checkout: $(pwd) at $(git rev-parse HEAD 2>/dev/null || echo '?'); NVIDIA OpenCL library: ${nv:-not found (using /etc/OpenCL/vendors)}"
  # The test programs name the build machine's checkout (ARCHWAVE_SOURCE_DIR) and its
  # build/archwave (ARCHWAVE_BINARY).
  local src
  src=$(awk '$1 == "source" {print $2}' "$B/manifest")
  if [ "$src" != "$(pwd)" ]; then
    if [ -e "$src" ] && [ "$(cd "$src" && pwd -P)" != "$(pwd -P)" ]; then
      die "the tests read $src, which is another directory; run from a checkout at $src"
    fi
    [ -e "$src" ] || { mkdir -p "$(dirname "$src")" && ln -s "$(pwd)" "$src"; } ||
      die "the tests read $src: make it a link to this checkout (or run there)"
  fi
  mkdir -p build
  [ -e build/archwave ] || ln -s "$B/bin/archwave" build/archwave
  local AW=$B/bin/archwave dev=${GPU_CHECK_DEVICE:-gpu}
  "$AW" --list-devices | tee -a "$sum"
  [ "$dev" != gpu ] || "$AW" --list-devices | grep -q '(GPU,' || die "no GPU among the OpenCL devices above"
  local failed=0 skip=${GPU_CHECK_SKIP:-}

  render() {  # name, seconds allowed, archwave arguments
    local n=$1 t=$2
    shift 2
    if timeout "$t" "$AW" "$@" -o "$res/$n.exr" --stats-json "$res/$n.json" -q --no-progress > "$res/$n.log" 2>&1 < /dev/null; then
      python3 - "$res/$n.json" "$n" <<'EOF' | tee -a "$sum"
import json, sys
s = json.load(open(sys.argv[1]))
r = s["render_seconds"]
stages = "; ".join("%s %.3g G/s" % (x["name"], x["items"] / x["seconds"] / 1e9) for x in s["stages"] if x["seconds"] > 0 and x["items"] > 0)
print("%-22s %s: %.3g samples, render %.3f s (setup %.3f s, build %.3f s), %.4g Msamples/s, pool %s; %s"
      % (sys.argv[2], s["device"], s["samples"], r, s.get("setup_seconds", 0), s["compile_seconds"],
         s["samples"] / r / 1e6 if r > 0 else 0, s["pool_size"], stages))
EOF
    else
      note "$n: FAILED (exit $?; $res/$n.log)"
      failed=1
    fi
  }

  if [[ " $skip " != *" renders "* ]]; then
    render cornell_256_cold 300 scenes/cornell.json --device "$dev" --spp 16 --width 256 --height 256
    render cornell_256 60 scenes/cornell.json --device "$dev" --spp 16 --width 256 --height 256
    render cornell_256_scalar 120 scenes/cornell.json --scalar --spp 16 --width 256 --height 256
    if [ -f "$res/cornell_256.exr" ] && [ -f "$res/cornell_256_scalar.exr" ]; then
      note "GPU against scalar: $("$B/bin/exr_compare" --json "$res/cornell_256.exr" "$res/cornell_256_scalar.exr")"
    fi
    render cornell_1024 120 scenes/cornell.json --device "$dev" --spp 64 --width 1024 --height 1024
    render cornell_1024_pool18 120 scenes/cornell.json --device "$dev" --spp 64 --width 1024 --height 1024 --pool 262144
    render materials_512 300 scenes/materials.json --device "$dev" --spp 32 --width 512 --height 512
    render knot_512 300 scenes/knot.json --device "$dev" --spp 32 --width 512 --height 512
    rm -f "$res"/*.exr "$res"/*.png
  fi
  if [[ " $skip " != *" bench "* ]]; then
    if timeout 180 "$B/bin/bench_traversal" --device "$dev" --scene scenes/cornell.json --json "$res/traversal_cornell.json" \
        > "$res/traversal_cornell.log" 2>&1; then
      python3 - "$res/traversal_cornell.json" <<'EOF' | tee -a "$sum"
import json, sys
d = json.load(open(sys.argv[1]))
for r in d["rows"]:
    print("traversal, Cornell box, %s rays: kernel %.4g Mrays/s on %s; Embree rtcIntersect1 %.4g on %d host threads"
          " (packets of 8: %.4g, 16: %.4g); %.3g%% of hits differ"
          % (r["kind"], r["opencl_mrays"], d["device"], r["embree_mrays"], d["hardware_threads"],
             r["embree8_mrays"], r["embree16_mrays"], 100 * r["mismatch"]))
EOF
    else
      note "traversal (Cornell box): FAILED (exit $?; $res/traversal_cornell.log)"
      failed=1
    fi
  fi
  if [[ " $skip " != *" tests "* ]]; then
    # One test program per area at a time, with the filters the build registers as @intel/@gpu.
    local area filter
    while IFS=$'\t' read -r area filter; do
      ARCHWAVE_DEVICE=$dev ARCHWAVE_SOURCE_DIR=$src timeout 600 "$B/bin/test_$area" --gtest_filter="$filter" \
        > "$res/test_$area.log" 2>&1 < /dev/null
      local rc=$?
      note "test_$area: exit $rc; $(grep -cE '^\[       OK \]' "$res/test_$area.log") passed, $(grep -cE '^\[  SKIPPED \]' "$res/test_$area.log") skipped, $(grep -cE '^\[  FAILED  \] [A-Za-z]+\.[A-Za-z]+ \(' "$res/test_$area.log") failed"
      grep -E '^\[  FAILED  \] [A-Za-z]+\.[A-Za-z]+ \(' "$res/test_$area.log" | tee -a "$sum"
      [ "$rc" -eq 0 ] || failed=1
    done < "$B/device_test_filters.txt"
  fi
  note "results in $res"
  return $failed
}

case ${1:-} in
  pack) shift; pack "$@" ;;
  run) shift; run "$@" ;;
  *) die "usage: scripts/gpu_check.sh pack [BUILD_DIR] [BUNDLE] | run BUNDLE [RESULTS_DIR]" ;;
esac

#!/usr/bin/env bash
# Specialised vs generic kernels, side by side per scene: render time (kernels cached) and
# kernel build time cold (empty PoCL cache) and warm. Prints a Markdown table.
# Usage: bench/bench_specialisation.sh [--spp N] [scene.json ...]
set -euo pipefail
cd "$(dirname "$0")/.."
bin=${ARCHWAVE_BIN:-./build/archwave}
spp=16
scenes=()
while [ $# -gt 0 ]; do
  case "$1" in
    --spp) spp=$2; shift 2 ;;
    *) scenes+=("$1"); shift ;;
  esac
done
[ ${#scenes[@]} -gt 0 ] || scenes=(scenes/cornell.json scenes/knot.json scenes/materials.json)
tmp=$(mktemp -d)
trap 'rm -rf "$tmp"' EXIT
field() { awk -v k="$1" '$1 == k {print $2}'; }
run() {  # scene cache flags... -> "render_seconds build_seconds"
  local scene=$1 cache=$2
  shift 2
  local log
  log=$(POCL_CACHE_DIR=$cache "$bin" "$scene" --spp "$spp" --width 320 --height 240 --no-progress \
        -o "$tmp/out.exr" "$@" 2>&1)
  local total build
  total=$(echo "$log" | awk '/^time/ {print $2}')
  build=$(echo "$log" | sed -n 's/.*kernel build \([0-9.]*\) s.*/\1/p')
  echo "$(awk -v t="$total" -v b="$build" 'BEGIN {printf "%.3f %.3f", t - b, b}')"
}
echo "Kernels specialised on the scene's features vs the generic build (every feature), 320x240,"
echo "$spp spp, $(nproc) cores, $(grep -m1 'model name' /proc/cpuinfo | cut -d: -f2 | sed 's/^ //'). Render time excludes"
echo "the kernel build; cold build = empty PoCL cache, warm = cached."
echo
echo "| scene | features | render specialised (s) | render generic (s) | speed-up | build cold spec / gen (s) | build warm spec / gen (s) |"
echo "|---|---|---|---|---|---|---|"
i=0
for scene in "${scenes[@]}"; do
  i=$((i + 1))  # a fresh pair of caches per scene: the generic program is the same for all
  features=$("$bin" "$scene" --spp 1 --width 4 --height 4 -o "$tmp/f.exr" 2>&1 | sed -n 's/^kernels *specialised: //p')
  read -r _ cold_s <<< "$(run "$scene" "$tmp/cache_s$i")"
  read -r _ cold_g <<< "$(run "$scene" "$tmp/cache_g$i" --generic-kernels)"
  read -r rs warm_s <<< "$(run "$scene" "$tmp/cache_s$i")"
  read -r rg warm_g <<< "$(run "$scene" "$tmp/cache_g$i" --generic-kernels)"
  speed=$(awk -v a="$rg" -v b="$rs" 'BEGIN {printf "%.2f", a / b}')
  echo "| $(basename "$scene") | $features | $rs | $rg | ${speed}x | $cold_s / $cold_g | $warm_s / $warm_g |"
done

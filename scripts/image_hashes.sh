#!/usr/bin/env bash
# Prints one line per (scene, renderer) with the SHA-256 of the rendered EXR, for checking
# that a refactor changes no image (docs/architecture.md, "Refactoring without changing an
# image"). Every scene under scenes/ plus the test scenes, small and at few samples so the
# whole set renders in a few minutes on 2 cores; the wavefront both specialised and generic,
# and the scalar path. Usage: scripts/image_hashes.sh [ARCHWAVE_BINARY] > hashes.txt, then
# diff two such files. Lobe splitting is exercised: 4 spp makes most `samples` split.
# Arguments after the binary are passed to every render (e.g. -D render.sampler=independent);
# renders are on PoCL unless they name a --device.
set -euo pipefail
cd "$(dirname "$0")/.."
bin=${1:-build/archwave}
shift || true
extra=("$@")
# One device for every render: with no --device archwave renders on the fastest device present,
# measured and cached per kernel build, and PoCL and Intel's runtime do not round alike, so two
# binaries could otherwise hash two devices' images (the Cornell box differs between them).
case " ${extra[*]} " in *" --device "*) ;; *) extra+=(--device pocl) ;; esac
out=$(mktemp -d)
trap 'rm -rf "$out"' EXIT
export POCL_CACHE_DIR=${POCL_CACHE_DIR:-$PWD/build/pocl-cache}
for scene in scenes/*.json scenes/docs/*.json tests/render/data/*.json; do
  for mode in spec generic scalar; do
    case $mode in
      spec) flags=() ;;
      generic) flags=(--generic-kernels) ;;
      scalar) flags=(--scalar) ;;
    esac
    f="$out/$(basename "$scene" .json)_$mode.exr"
    "$bin" "$scene" -q --no-progress --width 40 --height 30 --spp 4 "${flags[@]}" "${extra[@]}" -o "$f" >/dev/null 2>&1 \
      || { echo "$scene $mode FAILED"; continue; }
    echo "$scene $mode $(sha256sum < "$f" | cut -c1-16)"
  done
done

#!/usr/bin/env bash
# README command 1: install what is missing, build, render the default scene to
# cornell.exr and cornell.png in the current directory of the repository.
set -euo pipefail
cd "$(dirname "$0")/.."
source scripts/prepare.sh
./build/archwave scenes/cornell.json -o cornell.exr "$@"

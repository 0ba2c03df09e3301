#!/usr/bin/env bash
# Installs the Debian 12 packages archwave needs to build, test and benchmark.
# A no-op (no apt call at all) when everything is already installed. Then installs Intel's CPU
# OpenCL runtime beside PoCL (scripts/install_intel_opencl.sh; ARCHWAVE_INTEL_OPENCL=0 skips it).
# Extra Debian packages may be named as arguments (scripts/fuzz.sh adds clang and its runtime
# libraries). Run as root.
set -euo pipefail
packages=(
  cmake g++ make pkg-config python3
  pocl-opencl-icd ocl-icd-opencl-dev opencl-c-headers opencl-clhpp-headers clinfo
  libembree-dev libopenexr-dev libglm-dev libpng-dev
  nlohmann-json3-dev libtinyobjloader-dev libtinygltf-dev libstb-dev libcli11-dev libgtest-dev libbenchmark-dev
  python3-numpy python3-matplotlib python3-venv
  "$@"
)
missing=()
for p in "${packages[@]}"; do
  dpkg-query -W -f='${Status}' "$p" 2>/dev/null | grep -q "install ok installed" || missing+=("$p")
done
if [ ${#missing[@]} -gt 0 ]; then
  echo "setup: installing ${missing[*]}" >&2
  export DEBIAN_FRONTEND=noninteractive
  apt-get update -qq
  apt-get install -y -qq --no-install-recommends "${missing[@]}"
fi
bash "$(dirname "$0")/install_intel_opencl.sh"

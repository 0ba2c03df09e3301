#!/usr/bin/env bash
# Installs Intel's CPU OpenCL runtime (issue 12), archwave's second CPU device beside PoCL, from
# PyPI into a virtualenv the project owns, $ARCHWAVE_INTEL_OPENCL_PREFIX (default
# /opt/archwave/intel-opencl; the system Python is not touched), and registers it with the ICD
# loader by the full path of libintelocl.so in /etc/OpenCL/vendors/archwave-intel-cpu.icd, so
# that `archwave --list-devices` shows it with no environment variable set.
#
# The runtime links a TBB newer than Debian 12's (2021.8), and Embree loads Debian's first: the
# runtime's symbols then do not resolve and the ICD loader drops the platform without a word.
# So this script also links the runtime's libtbb* into PREFIX/tbb, and CMakeLists.txt gives
# archwave's executables that directory as an RPATH when it exists: Embree then runs on the
# newer TBB (its ABI is backward compatible, same soname libtbb.so.12), and both work.
# PREFIX/tbb holds only TBB, because PREFIX/lib also carries an ICD loader (libOpenCL.so.1)
# that must not shadow Debian's. Details: docs/devices.md.
#
# ARCHWAVE_INTEL_OPENCL=0 skips it (PoCL stays the only CPU device; the test suite is defined on
# PoCL either way). A no-op when the pinned version is installed and registered. Best effort:
# if PyPI cannot be reached the script says so and archwave runs on PoCL. Run as root.
set -uo pipefail
[ "${ARCHWAVE_INTEL_OPENCL:-1}" = 0 ] && { echo "install_intel_opencl: skipped (ARCHWAVE_INTEL_OPENCL=0)" >&2; exit 0; }
[ "$(uname -m)" = x86_64 ] || { echo "install_intel_opencl: skipped (Intel's CPU runtime is x86-64 only)" >&2; exit 0; }
VERSION=2026.2.0
PREFIX=${ARCHWAVE_INTEL_OPENCL_PREFIX:-/opt/archwave/intel-opencl}
ICD=/etc/OpenCL/vendors/archwave-intel-cpu.icd
# (pip's output is read whole: grep -q closing the pipe early would fail the pipeline.)
have() { local out; out=$("$PREFIX/bin/python" -m pip show intel-opencl-rt 2>/dev/null) && grep -qx "Version: $VERSION" <<<"$out"; }
if ! have; then
  echo "install_intel_opencl: installing intel-opencl-rt==$VERSION into $PREFIX (about 300 MB)" >&2
  if ! { /usr/bin/python3 -m venv "$PREFIX" &&
         "$PREFIX/bin/python" -m pip install -q --disable-pip-version-check \
           "intel-opencl-rt==$VERSION" "intel-cmplr-lib-rt==$VERSION"; }; then
    echo "install_intel_opencl: could not install intel-opencl-rt==$VERSION; archwave runs on PoCL only" >&2
    exit 0
  fi
fi
lib="$PREFIX/lib/libintelocl.so"
[ -e "$lib" ] || { echo "install_intel_opencl: $lib is missing after the install; archwave runs on PoCL only" >&2; exit 0; }
mkdir -p "$PREFIX/tbb"
for f in "$PREFIX"/lib/libtbb*.so*; do ln -sfn "$f" "$PREFIX/tbb/$(basename "$f")"; done
mkdir -p "$(dirname "$ICD")"
if [ "$(cat "$ICD" 2>/dev/null)" != "$lib" ]; then
  echo "$lib" > "$ICD"
  echo "install_intel_opencl: registered $lib in $ICD" >&2
fi
exit 0

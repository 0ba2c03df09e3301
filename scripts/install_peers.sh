#!/usr/bin/env bash
# Installs the peers of the benchmark suite's race section (issue 11), best effort: Debian's
# `blender` (Cycles), `libllvm19` (Mitsuba's LLVM backend needs an LLVM newer than 15; the race
# passes DRJIT_LIBLLVM_PATH=/usr/lib/x86_64-linux-gnu/libLLVM-19.so), and Mitsuba 3 from PyPI in
# the virtualenv build/peers-venv (over the system Python, so it sees Debian's numpy). A no-op
# when all are there. A peer that cannot be installed is skipped by the race with a message;
# ARCHWAVE_BENCH_PEERS=0 skips this script. Run as root from the repository root
# (scripts/bench.sh does).
set -uo pipefail
[ "${ARCHWAVE_BENCH_PEERS:-1}" = 0 ] && { echo "install_peers: skipped (ARCHWAVE_BENCH_PEERS=0)" >&2; exit 0; }
MITSUBA="mitsuba==3.9.1"
VENV=build/peers-venv
LLVM=/usr/lib/x86_64-linux-gnu/libLLVM-19.so
missing=()
for p in blender libllvm19 python3-venv; do
  dpkg-query -W -f='${Status}' "$p" 2>/dev/null | grep -q "install ok installed" || missing+=("$p")
done
if [ ${#missing[@]} -gt 0 ]; then
  echo "install_peers: installing ${missing[*]}" >&2
  export DEBIAN_FRONTEND=noninteractive
  { apt-get update -qq && apt-get install -y -qq --no-install-recommends "${missing[@]}"; } ||
    echo "install_peers: apt-get could not install ${missing[*]}; the race skips what is missing" >&2
fi
if ! DRJIT_LIBLLVM_PATH=$LLVM "$VENV/bin/python" -c "import mitsuba" >/dev/null 2>&1; then
  echo "install_peers: installing $MITSUBA into $VENV" >&2
  mkdir -p build
  { /usr/bin/python3 -m venv --system-site-packages "$VENV" &&
    "$VENV/bin/python" -m pip install -q "$MITSUBA"; } ||
    echo "install_peers: could not install $MITSUBA; the race skips Mitsuba 3" >&2
fi
exit 0

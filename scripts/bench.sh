#!/usr/bin/env bash
# The benchmark suite in one command (README): install what is missing, build, install the
# race's peers (scripts/install_peers.sh: Blender's Cycles, Mitsuba 3; ARCHWAVE_BENCH_PEERS=0
# skips them), then run scripts/bench_suite.py, which writes results/<timestamp>/report.md and
# its plots.
# Arguments go to the suite, e.g. --quick, --only sweeps,knobs, --budget-minutes 10,
# --update-docs (rewrites the generated blocks of docs/performance.md, leaving the reasoning
# around them, and copies the plots to docs/perf/).
set -euo pipefail
cd "$(dirname "$0")/.."
# The suite makes its own empty PoCL caches where it measures cold builds.
source scripts/prepare.sh
bash scripts/install_peers.sh
exec python3 scripts/bench_suite.py "$@"

#!/usr/bin/env bash
# ctest bench_suite_quick (label "bench"): the benchmark suite's smoke run into a fresh
# folder must succeed and write report.md with every section and every plot it links to.
# (The race section runs Cycles and Mitsuba 3 where they are installed, and says it skipped
# them where they are not: either way the section is there.)
# Usage: bench_suite_quick.sh BUILD_DIR
set -euo pipefail
build=$1
here=$(cd "$(dirname "$0")" && pwd)
out=$(mktemp -d "${TMPDIR:-/tmp}/archwave_bench_quick_XXXXXX")
trap 'rm -rf "$out"' EXIT
python3 "$here/../../scripts/bench_suite.py" --quick --build "$build" --results "$out"
report=$(find "$out" -name report.md)
[ -n "$report" ] || { echo "no report.md under $out" >&2; exit 1; }
for section in "Machine and run" "Sample-count sweeps" "Knob sweeps at equal time" "Throughput" \
               "Kernel specialisation" "Scaling" "Devices" "Lights, environment and AO" "The race"; do
  grep -q "^## $section" "$report" || { echo "report.md lacks the section '$section'" >&2; exit 1; }
done
grep -q "^- Issue 12" "$report" || { echo "report.md lacks the race's samples/s line (issue 12)" >&2; exit 1; }
grep -q "^### Dense launches vs queue launches" "$report" || { echo "report.md lacks the dense-launch table" >&2; exit 1; }
plots=$(grep -o '([a-z_]*\.png)' "$report" | tr -d '()' | sort -u)
[ "$(echo "$plots" | wc -w)" -ge 6 ] || { echo "report.md links too few plots: $plots" >&2; exit 1; }
for p in $plots; do
  [ -s "$(dirname "$report")/$p" ] || { echo "plot $p linked but not written" >&2; exit 1; }
done
echo "bench_suite --quick: $report with $(echo "$plots" | wc -w) plots"

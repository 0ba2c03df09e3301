#!/usr/bin/env python3
"""The benchmark suite (issue 4): the entry point of the archwave_bench package beside this
file (its docstring lists the sections and the modules). scripts/bench.sh and the ctest
bench_suite_quick run this file; `python3 -m archwave_bench` from scripts/ is the same.

Usage: scripts/bench_suite.py [--build DIR] [--results DIR] [--budget-minutes M] [--quick]
                              [--only SECTION,...] [--device I] [--update-docs]
"""

import os
import sys

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))

from archwave_bench import reexec_with_numpy  # noqa: E402

reexec_with_numpy(sys.argv)

from archwave_bench.cli import main  # noqa: E402

if __name__ == "__main__":
    sys.exit(main(sys.argv[1:]))

"""`python3 -m archwave_bench ARGS` (from scripts/, or with scripts/ on PYTHONPATH) is the same
as scripts/bench_suite.py ARGS."""

import os
import sys

from archwave_bench import reexec_with_numpy

# Re-executed as a module, with this package's parent folder on the path.
_parent = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))
_others = [p for p in os.environ.get("PYTHONPATH", "").split(os.pathsep) if p]
os.environ["PYTHONPATH"] = os.pathsep.join([_parent] + _others)
reexec_with_numpy(["-m", "archwave_bench"] + sys.argv[1:])

from archwave_bench.cli import main  # noqa: E402

sys.exit(main(sys.argv[1:]))

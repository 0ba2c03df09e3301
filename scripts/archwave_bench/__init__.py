"""The benchmark suite (issue 4): one command, a Markdown report and PNG plots.

Drives the built programs only (build/archwave, build/bench/exr_compare,
build/bench/bench_traversal), so what it measures is what a user runs. Sections:

  sweeps          error vs spp and vs time against a high-spp reference, log-log slopes
  knobs           lobe splitting, trace depth, cut-off, Russian roulette at equal time
  throughput      traversal vs Embree, stage breakdown, memory per path state / triangle
  specialisation  specialised vs generic kernels: render time, cold and warm builds
  scaling         time vs triangle count, memory and time vs sphere count (analytic, tessellated),
                  time and memory vs resolution
  devices         the same small table on every OpenCL device and the scalar path
  lights          many lights (light tree against power, 1 to 10,000 lights: time and error),
                  environment-map importance vs uniform sampling, AO against GI, AO samples
  race            archwave against Blender Cycles and Mitsuba 3 on the same scenes (issue 11):
                  time, RMSE, relMSE, time to equal error; peers that are missing are skipped

Output: RESULTS/<timestamp>/report.md plus its plots; --update-docs rewrites the generated
blocks of docs/performance.md (between its BEGIN/END GENERATED markers, leaving the
hand-written reasoning around them alone) and copies the plots to docs/perf/. References and
generated meshes are cached under RESULTS/refs and RESULTS/meshes so reruns reuse them.

The code prints numbers, tables and captions saying how each was measured; what the numbers
mean on a given machine is written in docs/performance.md, against a dated run.

Usage: scripts/bench_suite.py [--build DIR] [--results DIR] [--budget-minutes M] [--quick]
                              [--only SECTION,...] [--device I] [--update-docs]

Modules: tools (running the programs), scenes, refs (references), errors (error model and
fits), plots, tables (number and table formatting), exr (reading EXR images), report (the
report and docs/), context (the run's shared state and timed renders), one module per section,
cli (flags, run order). The race's exporters live in bench/ (race_scene.py, export_cycles.py,
export_mitsuba.py); scripts/install_peers.sh installs the peers.
"""

import importlib.util
import os
import sys

REPO = os.path.dirname(os.path.dirname(os.path.dirname(os.path.abspath(__file__))))
SECTIONS = ("sweeps", "knobs", "throughput", "specialisation", "scaling", "devices", "lights", "race")
# Fixed-size sections run first; what is left of the budget then goes to the adaptive ones
# (sweeps and knobs), which size themselves from calibration renders. The race is fixed-size
# too but runs last, so that it finds the sweeps' Cornell reference in the cache; the adaptive
# sections leave its allowance to it (race.allowance: minutes, by the peers found; added to
# the default budget).
RUN_ORDER = ("throughput", "specialisation", "devices", "scaling", "lights", "sweeps", "knobs", "race")
REF_SEED = 1000003  # references use another seed than the renders they judge (seed 0)
REF_FACTOR = 16     # reference spp over the largest spp it judges, when the budget allows
LARGE_GRID_JOBS = 1 << 18  # jobs that make every stage launch PoCL's large-grid kernel variant
DOCS_MARK = "@DOCS@/"  # stands for the path to docs/ in links, resolved when a report is written


def reexec_with_numpy(argv):
    """pyenv or a virtualenv may shadow the Debian interpreter that scripts/setup.sh gives
    numpy and matplotlib: rather than fail, run `argv` (the same program) under that one.
    Call before importing anything below that needs them."""
    if all(importlib.util.find_spec(m) for m in ("numpy", "matplotlib")):
        return
    system = "/usr/bin/python3"
    if os.path.realpath(sys.executable) != os.path.realpath(system) and os.access(system, os.X_OK):
        os.execv(system, [system] + list(argv))
    sys.exit("bench_suite: needs numpy and matplotlib (scripts/setup.sh installs python3-numpy "
             "python3-matplotlib)")

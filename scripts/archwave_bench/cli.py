"""Flags, the run order and the budget's shares, and main()."""

import argparse
import os
import shutil
import sys
import time

from . import REPO, RUN_ORDER, SECTIONS
from . import __doc__ as PACKAGE_DOC
from . import devices, knobs, lights, race, scaling, specialisation, sweeps, throughput
from .context import Context
from .report import blocks, compose, update_docs, write_report
from .tools import SuiteError, log

MODULES = {"sweeps": sweeps, "knobs": knobs, "throughput": throughput, "specialisation": specialisation,
           "scaling": scaling, "devices": devices, "lights": lights, "race": race}


def budget_share(ctx, name, only):
    """Seconds for an adaptive section: the sweeps take the larger part of what the fixed
    sections left, because their references are also the knobs' references. The race, which
    runs after them, keeps its allowance."""
    left = ctx.left() - (race.allowance(ctx) * 60.0 if "race" in only else 0.0)
    if name == "sweeps":
        return max(left * (0.72 if "knobs" in only else 0.95), 0.0)
    return max(left * 0.95, 0.0)


def run_sections(ctx, only):
    """{section: Markdown} and {section: seconds}, run in RUN_ORDER."""
    sections, seconds = {}, {}
    for name in RUN_ORDER:
        if name not in only:
            continue
        t = time.monotonic()
        log(f"section {name} ({ctx.elapsed():.0f} s elapsed, {ctx.left():.0f} s of budget left)")
        mod = MODULES[name]
        if name in ("sweeps", "knobs"):
            data = mod.measure(ctx, budget_share(ctx, name, only))
        else:
            data = mod.measure(ctx)
        sections[name] = mod.render(ctx, data)
        seconds[name] = time.monotonic() - t
    return sections, seconds


def parse(argv):
    prog = "python3 -m archwave_bench" if sys.argv[0].endswith("__main__.py") else None
    ap = argparse.ArgumentParser(prog=prog, description=PACKAGE_DOC.split("\n\n")[0],
                                 formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("--build", default=os.path.join(REPO, "build"), help="build folder with archwave and bench/")
    ap.add_argument("--results", default=os.path.join(REPO, "results"),
                    help="results root: <timestamp>/ for this run, refs/ and meshes/ caches (default results/)")
    ap.add_argument("--budget-minutes", type=float, default=None,
                    help="time budget for the whole run (default 16, 1.5 with --quick, plus the race's "
                         "allowance when it runs: about 6 with both peers installed, 0.4 with --quick)")
    ap.add_argument("--quick", action="store_true", help="smoke run: tiny sizes, about a minute")
    ap.add_argument("--only", default=",".join(SECTIONS), help="comma-separated sections: " + ",".join(SECTIONS))
    ap.add_argument("--device", default="pocl",
                    help="OpenCL device for the wavefront renders: an index or a name, as archwave --device "
                         "takes them (default pocl: the tables are defined on PoCL; the devices section runs on all)")
    ap.add_argument("--ref-renderer", choices=("scalar", "wavefront"), default="scalar",
                    help="renderer for references (default scalar: the faster one on a CPU)")
    ap.add_argument("--update-docs", action="store_true",
                    help="rewrite the generated blocks of docs/performance.md (the text around them is "
                         "kept) and copy the plots to docs/perf/")
    args = ap.parse_args(argv)
    only = [s.strip() for s in args.only.split(",") if s.strip()]
    args.budget_default = args.budget_minutes is None
    if args.budget_default:
        args.budget_minutes = 1.5 if args.quick else 16.0  # the race's allowance is added in main()
    bad = [s for s in only if s not in SECTIONS]
    if bad:
        ap.error(f"unknown section(s) {', '.join(bad)}; choose from {', '.join(SECTIONS)}")
    if args.update_docs and (set(only) != set(SECTIONS) or args.quick):
        ap.error("--update-docs needs a full run of every section (no --quick, no --only)")
    return args, only


def main(argv):
    args, only = parse(argv)
    ctx = None
    try:
        ctx = Context(args)
        log(f"writing {ctx.out}")
        if "race" in only and args.budget_default:
            extra = race.allowance(ctx)
            args.budget_minutes += extra
            ctx.budget += extra * 60.0
        sections, seconds = run_sections(ctx, only)
        parts = blocks(ctx, argv, sections, seconds, only)
    except SuiteError as e:
        where = f"\n(renders and commands.log kept in {ctx.out})" if ctx else ""
        print(f"bench_suite: {e}{where}", file=sys.stderr)
        return 1
    write_report(compose(parts), ctx.out)
    shutil.rmtree(ctx.work, ignore_errors=True)  # renders are scratch; refs and meshes are cached
    log(f"report: {os.path.join(ctx.out, 'report.md')} ({ctx.elapsed() / 60:.1f} min)")
    if args.update_docs:
        update_docs(ctx.out, ctx.plots, parts)
        log("docs/performance.md (its generated blocks) and docs/perf/ updated")
    return 0

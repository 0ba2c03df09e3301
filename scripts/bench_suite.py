#!/usr/bin/env python3
"""The benchmark suite (issue 4): one command, a Markdown report and PNG plots.

Drives the built programs only (build/archwave, build/bench/exr_compare,
build/bench/bench_traversal), so what it measures is what a user runs. Sections:

  sweeps          error vs spp and vs time against a high-spp reference, log-log slopes
  knobs           lobe splitting, trace depth, cut-off, Russian roulette at equal time
  throughput      traversal vs Embree, stage breakdown, memory per path state / triangle
  specialisation  specialised vs generic kernels: render time, cold and warm builds
  scaling         time vs triangle count and vs resolution, memory vs resolution
  devices         the same small table on every OpenCL device and the scalar path

Output: RESULTS/<timestamp>/report.md plus its plots; --update-docs copies them to
docs/performance.md and docs/perf/. References and generated meshes are cached under
RESULTS/refs and RESULTS/meshes so reruns reuse them.

Usage: scripts/bench_suite.py [--build DIR] [--results DIR] [--budget-minutes M] [--quick]
                              [--only SECTION,...] [--device I] [--update-docs]
"""

import importlib.util
import os
import sys


def _reexec_with_numpy():
    # pyenv or a virtualenv may shadow the Debian interpreter that scripts/setup.sh gives
    # numpy and matplotlib: rather than fail, run under that one.
    if not all(importlib.util.find_spec(m) for m in ("numpy", "matplotlib")):
        system = "/usr/bin/python3"
        if os.path.realpath(sys.executable) != os.path.realpath(system) and os.access(system, os.X_OK):
            os.execv(system, [system] + sys.argv)
        sys.exit("bench_suite: needs numpy and matplotlib (scripts/setup.sh installs python3-numpy "
                 "python3-matplotlib)")


_reexec_with_numpy()

import argparse  # noqa: E402
import datetime  # noqa: E402
import hashlib  # noqa: E402
import json  # noqa: E402
import math  # noqa: E402
import platform  # noqa: E402
import re  # noqa: E402
from statistics import median  # noqa: E402
import shlex  # noqa: E402
import shutil  # noqa: E402
import subprocess  # noqa: E402
import tempfile  # noqa: E402
import time  # noqa: E402
from dataclasses import dataclass, field  # noqa: E402

import matplotlib  # noqa: E402

matplotlib.use("Agg")  # no display on the machines this runs on
import matplotlib.pyplot as plt  # noqa: E402
import numpy as np  # noqa: E402

REPO = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))
SECTIONS = ("sweeps", "knobs", "throughput", "specialisation", "scaling", "devices")
# Fixed-size sections run first; what is left of the budget then goes to the adaptive ones
# (sweeps and knobs), which size themselves from calibration renders.
RUN_ORDER = ("throughput", "specialisation", "devices", "scaling", "sweeps", "knobs")
REF_SEED = 1000003  # references use another seed than the renders they judge (seed 0)
REF_FACTOR = 16     # reference spp over the largest spp it judges, when the budget allows
LARGE_GRID_JOBS = 1 << 18  # jobs that make every stage launch PoCL's large-grid kernel variant
DOCS_MARK = "@DOCS@/"  # stands for the path to docs/ in links, resolved when a report is written


class SuiteError(Exception):
    """A program the suite ran failed; the message names the command and its stderr."""


# ---- small helpers --------------------------------------------------------------------------

def log(msg):
    print(f"[bench {time.strftime('%H:%M:%S')}] {msg}", file=sys.stderr, flush=True)


def fmt(x, digits=3):
    """Significant digits, without scientific notation for ordinary magnitudes."""
    if x is None or (isinstance(x, float) and not math.isfinite(x)):
        return "–"
    if x == 0:
        return "0"
    if abs(x) >= 10 ** digits or abs(x) < 1e-3:
        return f"{x:.{digits - 1}e}"
    return f"{x:.{max(0, digits - 1 - int(math.floor(math.log10(abs(x)))))}f}"


def fmt_bytes(b):
    for unit, scale in (("GiB", 1 << 30), ("MiB", 1 << 20), ("KiB", 1 << 10)):
        if b >= scale:
            return f"{b / scale:.3g} {unit}"
    return f"{int(b)} B"


def md_table(headers, rows):
    """Markdown table; a column is right-aligned when every cell in it is a number."""
    def numeric(s):
        return re.fullmatch(r"[-+]?[\d.,]+(e[-+]?\d+)?[x%]?( [KMG]iB| B)?|–", str(s)) is not None
    align = ["---:" if rows and all(numeric(r[i]) for r in rows) else "---" for i in range(len(headers))]
    out = ["| " + " | ".join(headers) + " |", "|" + "|".join(align) + "|"]
    out += ["| " + " | ".join(str(c) for c in r) + " |" for r in rows]
    return "\n".join(out) + "\n"


def loglog_fit(x, y):
    """Least-squares line through (log x, log y): (slope, intercept). NaN with < 2 points."""
    x, y = np.asarray(x, float), np.asarray(y, float)
    ok = (x > 0) & (y > 0)
    if ok.sum() < 2:
        return float("nan"), float("nan")
    slope, icpt = np.polyfit(np.log(x[ok]), np.log(y[ok]), 1)
    return float(slope), float(icpt)


def nonneg_fit(f0, f1, y):
    """Least squares y = c0 f0 + c1 f1 with c0, c1 >= 0 (two columns: try both, each alone)."""
    cols = np.stack([np.asarray(f0, float), np.asarray(f1, float)], axis=1)
    y = np.asarray(y, float)
    best = (float("inf"), 0.0, 0.0)
    for use in ((0, 1), (0,), (1,)):
        sol, *_ = np.linalg.lstsq(cols[:, use], y, rcond=None)
        if np.any(sol < 0):
            continue
        coef = np.zeros(2)
        coef[list(use)] = sol
        resid = float(np.sum((cols @ coef - y) ** 2))
        if resid < best[0]:
            best = (resid, float(coef[0]), float(coef[1]))
    return best[1], best[2]


class ErrorModel:
    """MSE(spp) = a / spp + b and time(spp) = c0 + c1 spp, fitted to one setting's renders.
    a is its Monte Carlo noise; b what more samples do not remove (bias against the reference,
    the reference's own noise); c0 the fixed cost of a render (wavefront iterations that are
    not full), c1 the cost of a sample. Fitting error against spp and converting through
    the time model keeps a/t from being bent by c0. Residuals are relative (weights 1/MSE):
    otherwise the noisiest, lowest-spp point decides b. With `floor` given, b is that."""

    def __init__(self, spp, seconds, mse, floor=None):
        spp, seconds, mse = (np.asarray(v, float) for v in (spp, seconds, mse))
        w = 1.0 / mse
        if floor is None:
            self.a, self.b = nonneg_fit(w / spp, w, w * mse)
        else:
            x = w / spp
            self.a, self.b = max(0.0, float(np.sum(x * w * (mse - floor)) / np.sum(x * x))), floor
        self.c1, self.c0 = nonneg_fit(spp, np.ones_like(spp), seconds)
        if self.c1 <= 0:  # all points at one spp: cost per sample from the mean
            self.c0, self.c1 = 0.0, float(np.mean(seconds / spp))

    def rmse_at_time(self, t):
        spp = max(t - self.c0, 1e-9) / self.c1
        return math.sqrt(self.a / spp + self.b)

    def time_to_rmse(self, e):
        """Seconds to reach RMSE e; inf when the floor b alone is above it."""
        if e * e <= self.b * 1.0001 or self.a <= 0:
            return math.inf
        return self.c0 + self.c1 * self.a / (e * e - self.b)


def shared_floor(groups):
    """b in MSE_ij = a_i / spp_ij + b, fitted jointly over settings that converge to the same
    image as the reference (groups = [(spp, mse)]): their only floor is the reference's own
    noise, common to all, and many points pin it down where one setting's three cannot.
    Relative residuals, as in ErrorModel."""
    rows = []
    for i, (spp, mse) in enumerate(groups):
        for s, m in zip(spp, mse):
            row = np.zeros(len(groups) + 1)
            row[i], row[-1] = 1.0 / (s * m), 1.0 / m
            rows.append(row)
    sol, *_ = np.linalg.lstsq(np.array(rows), np.ones(len(rows)), rcond=None)
    return max(0.0, float(sol[-1]))


# ---- the programs under test ----------------------------------------------------------------

@dataclass
class Render:
    stats: dict
    exr: str
    wall: float  # seconds around the whole process (scene load and EXR write included)
    command: str

    @property
    def seconds(self):
        """The time the samples took: total minus kernel build and BVH build."""
        return self.stats["render_seconds"]

    @property
    def overhead(self):
        """Per-process cost besides the samples: start-up, scene load, BVH, EXR write. A cold
        kernel build is left out: it happens once per feature set, not per render."""
        return max(0.0, self.wall - self.seconds - self.stats["compile_seconds"])


class Tools:
    """Runs archwave, exr_compare and bench_traversal; every command goes to commands.log,
    and a failure raises SuiteError with the command and the tail of its stderr."""

    def __init__(self, build, work, device, log_path):
        self.archwave = os.path.join(build, "archwave")
        self.exr_compare = os.path.join(build, "bench", "exr_compare")
        self.traversal_bin = os.path.join(build, "bench", "bench_traversal")
        for prog in (self.archwave, self.exr_compare, self.traversal_bin):
            if not os.access(prog, os.X_OK):
                raise SuiteError(f"{prog} is missing: build first (scripts/build.sh, or --build DIR)")
        self.work = work
        self.device = device
        self.log_path = log_path
        self.count = 0

    def run(self, argv, env=None, timeout=3600):
        cmd = " ".join(shlex.quote(a) for a in argv)
        t0 = time.monotonic()
        try:
            p = subprocess.run(argv, capture_output=True, text=True, env=env, timeout=timeout)
        except subprocess.TimeoutExpired:
            raise SuiteError(f"command timed out after {timeout} s:\n  {cmd}")
        wall = time.monotonic() - t0
        with open(self.log_path, "a") as f:
            f.write(f"{wall:8.2f} s  {cmd}\n")
        if p.returncode != 0:
            tail = "\n".join(p.stderr.strip().splitlines()[-25:])
            raise SuiteError(f"command failed (exit {p.returncode}):\n  {cmd}\nstderr:\n{tail}")
        return p, wall, cmd

    def render(self, scene, name, spp, width, height, seed=0, defines=(), scalar=False, generic=False,
               device=None, pocl_cache=None, out_dir=None, extra_args=()):
        """One archwave render; returns its stats (from --stats-json), EXR path and times."""
        out_dir = out_dir or self.work
        self.count += 1
        stem = os.path.join(out_dir, f"{name}")
        argv = [self.archwave, scene, "-o", stem + ".exr", "--stats-json", stem + ".json", "-q", "--no-progress",
                "--spp", str(int(spp)), "--seed", str(seed), "--width", str(width), "--height", str(height)]
        for d in defines:
            argv += ["-D", d]
        if scalar:
            argv.append("--scalar")
        else:
            argv += ["--device", str(self.device if device is None else device)]
        if generic:
            argv.append("--generic-kernels")
        argv += list(extra_args)
        env = None
        if pocl_cache:
            env = dict(os.environ, POCL_CACHE_DIR=pocl_cache)
        _, wall, cmd = self.run(argv, env=env)
        with open(stem + ".json") as f:
            stats = json.load(f)
        return Render(stats, stem + ".exr", wall, cmd)

    def compare(self, exr, ref):
        p, _, _ = self.run([self.exr_compare, "--json", exr, ref])
        return json.loads(p.stdout)

    def traversal(self, args, out_json):
        _, _, cmd = self.run([self.traversal_bin, "--device", str(self.device), "--json", out_json] + args)
        with open(out_json) as f:
            return json.load(f), cmd

    def list_devices(self):
        """[(index, description)] from `archwave --list-devices` ("[i] name (...)" lines)."""
        p, _, _ = self.run([self.archwave, "--list-devices"])
        devs = []
        for line in p.stdout.splitlines():
            m = re.match(r"\s*\[(\d+)\]\s*(.*)", line)
            if m:
                devs.append((int(m.group(1)), m.group(2).strip()))
        return devs


# ---- scenes ---------------------------------------------------------------------------------

@dataclass
class BenchScene:
    key: str          # short name, part of file names and of the reference cache key
    title: str
    path: str         # scene file
    width: int
    height: int
    defines: list = field(default_factory=list)
    mesh: tuple = None  # (segments, rings) of a generated knot the defines point at

    def scene_hash(self):
        """Scene file (and any mesh it was pointed at) plus resolution and overrides: what
        determines the converged image besides the code."""
        h = hashlib.sha256()
        with open(self.path, "rb") as f:
            h.update(f.read())
        h.update(json.dumps([self.width, self.height, sorted(self.defines)]).encode())
        for d in self.defines:
            if ".file=" in d:  # a generated mesh: its name encodes its resolution
                h.update(os.path.basename(d.split("=", 1)[1]).encode())
        return h.hexdigest()[:16]


def scene_size(path, width):
    """(width, height) keeping the scene's own aspect ratio."""
    with open(path) as f:
        r = json.load(f).get("render", {})
    aspect = r.get("height", 480) / r.get("width", 640)
    return width, max(1, int(round(width * aspect)))


def knot_mesh(mesh_dir, segments, rings):
    """A (2,3) torus-knot tube of 2 * segments * rings triangles from scripts/gen_torus_knot.py,
    generated once and cached (large OBJs are never committed)."""
    os.makedirs(mesh_dir, exist_ok=True)
    path = os.path.join(mesh_dir, f"knot_{segments}x{rings}.obj")
    if not os.path.exists(path):
        log(f"generating {path} ({2 * segments * rings} triangles)")
        tmp = path + f".tmp{os.getpid()}"  # a run killed half-way leaves no truncated mesh behind
        argv = [sys.executable, os.path.join(REPO, "scripts", "gen_torus_knot.py"), tmp, str(segments), str(rings)]
        p = subprocess.run(argv, capture_output=True, text=True)
        if p.returncode != 0:
            raise SuiteError(f"command failed (exit {p.returncode}):\n  {' '.join(argv)}\nstderr:\n{p.stderr}")
        os.replace(tmp, path)
    return path


# ---- code identity and references -----------------------------------------------------------

def git(*args):
    try:
        return subprocess.run(["git", "-C", REPO] + list(args), capture_output=True, text=True,
                              check=True).stdout.strip()
    except (subprocess.CalledProcessError, FileNotFoundError):
        return ""


def code_key():
    """Git tree hashes of kernels/ and host/ (what decides the image), plus a hash of any
    uncommitted change there, so a reference is never reused across code that renders
    differently."""
    trees = [git("rev-parse", f"HEAD:{d}") or "untracked" for d in ("kernels", "host")]
    dirty = git("status", "--porcelain", "--untracked-files=all", "--", "kernels", "host")
    key = "-".join(t[:12] for t in trees)
    if dirty:
        h = hashlib.sha256(git("diff", "HEAD", "--", "kernels", "host").encode())
        for line in dirty.splitlines():
            path = os.path.join(REPO, line[3:])
            if line.startswith("??") and os.path.isfile(path):
                with open(path, "rb") as f:
                    h.update(f.read())
        key += "-dirty" + h.hexdigest()[:10]
    return key


class References:
    """High-spp references, rendered by the project with REF_SEED and cached under
    RESULTS/refs/<scene>-<hash>/ with ref.json (spp, seed, time, commit, command). A cached
    reference is reused when it has at least the spp asked for."""

    def __init__(self, tools, cache_dir, renderer):
        self.tools = tools
        self.cache_dir = cache_dir
        self.scalar = renderer == "scalar"
        self.code = code_key()

    def _dir(self, scene):
        key = hashlib.sha256((scene.scene_hash() + self.code + str(self.scalar)).encode()).hexdigest()[:16]
        return os.path.join(self.cache_dir, f"{scene.key}-{key}")

    def cached(self, scene):
        meta = os.path.join(self._dir(scene), "ref.json")
        if os.path.exists(meta) and os.path.exists(os.path.join(self._dir(scene), "ref.exr")):
            with open(meta) as f:
                return json.load(f)
        return None

    def get(self, scene, spp):
        """(exr path, metadata) of a reference with >= spp samples per pixel."""
        d = self._dir(scene)
        meta = self.cached(scene)
        if meta and meta["spp"] >= spp:
            meta["reused"] = True
            return os.path.join(d, "ref.exr"), meta
        os.makedirs(d, exist_ok=True)
        log(f"reference {scene.key}: {spp} spp ({'scalar' if self.scalar else 'wavefront'})")
        r = self.tools.render(scene.path, "ref", spp, scene.width, scene.height, seed=REF_SEED,
                              defines=scene.defines, scalar=self.scalar, out_dir=d)
        meta = {"scene": os.path.relpath(scene.path, REPO), "width": scene.width, "height": scene.height,
                "defines": scene.defines, "spp": spp, "seed": REF_SEED, "renderer": r.stats["renderer"],
                "device": r.stats["device"], "total_seconds": r.stats["total_seconds"],
                "render_seconds": r.seconds, "wall_seconds": r.wall, "git_commit": git("rev-parse", "HEAD"),
                "code_key": self.code, "command": r.command,
                "date": datetime.datetime.now().isoformat(timespec="seconds")}
        with open(os.path.join(d, "ref.json"), "w") as f:
            json.dump(meta, f, indent=2)
        meta["reused"] = False
        return os.path.join(d, "ref.exr"), meta

    def ref_cost(self, scene, spp, per_spp, overhead):
        """Seconds get(scene, spp) would take (0 when the cache already has it)."""
        meta = self.cached(scene)
        return 0.0 if meta and meta["spp"] >= spp else overhead + per_spp * spp


# ---- plots ----------------------------------------------------------------------------------

def loglog_figure(path, panels, title):
    """One row of log-log panels. panel = (xlabel, ylabel, [(label, x, y, slope, icpt)],
    guide_slope or None): points, their fitted line, and the expected slope as a dotted guide
    through the first series' first point."""
    fig, axes = plt.subplots(1, len(panels), figsize=(5.2 * len(panels), 4.0), squeeze=False)
    for ax, (xlabel, ylabel, series, guide) in zip(axes[0], panels):
        for i, (label, x, y, slope, icpt) in enumerate(series):
            color = f"C{i}"
            x, y = np.asarray(x, float), np.asarray(y, float)
            ok = (x > 0) & (y > 0)
            if not ok.any():
                continue
            fit_txt = f", slope {slope:.2f}" if math.isfinite(slope) else ""
            ax.loglog(x[ok], y[ok], "o-", color=color, ms=4, lw=1, label=f"{label}{fit_txt}")
            if math.isfinite(slope):
                xs = np.array([x[ok].min(), x[ok].max()])
                ax.loglog(xs, np.exp(icpt) * xs ** slope, "--", color=color, lw=0.8)
        if guide is not None and series and len(series[0][1]):
            x0, y0 = float(series[0][1][0]), float(series[0][2][0])
            xs = np.array([x0, max(float(np.max(s[1])) for s in series)])
            ax.loglog(xs, y0 * (xs / x0) ** guide, ":", color="gray", label=f"slope {guide}")
        ax.set_xlabel(xlabel)
        ax.set_ylabel(ylabel)
        ax.grid(True, which="both", alpha=0.3)
        ax.legend(fontsize=7)
    fig.suptitle(title, fontsize=10)
    fig.tight_layout()
    fig.savefig(path, dpi=110)
    plt.close(fig)


# ---- the suite ------------------------------------------------------------------------------

class Suite:
    def __init__(self, args):
        self.args = args
        self.quick = args.quick
        self.t0 = time.monotonic()
        self.budget = args.budget_minutes * 60.0
        stamp = datetime.datetime.now().strftime("%Y%m%d-%H%M%S")
        self.results = os.path.abspath(args.results)
        self.out = os.path.join(self.results, stamp)
        suffix = 1
        while os.path.exists(self.out):  # two runs in the same second (tests) get their own folder
            self.out = os.path.join(self.results, f"{stamp}-{suffix}")
            suffix += 1
        self.work = os.path.join(self.out, "renders")
        self.tools = Tools(os.path.abspath(args.build), self.work, args.device,
                           os.path.join(self.out, "commands.log"))
        os.makedirs(self.work)
        self.refs = References(self.tools, os.path.join(self.results, "refs"), args.ref_renderer)
        self.mesh_dir = os.path.join(self.results, "meshes")
        self.plots = []          # file names of the PNGs written into self.out
        self.sections = {}       # name -> Markdown
        self.section_seconds = {}
        self.notes = {}          # facts a section finds that other prose uses
        self.warm_kernels = set()  # (kernel features, device) whose large-grid variants are compiled
        w = 32 if self.quick else 128
        self.scenes = {
            "cornell": BenchScene("cornell", "Cornell box (Lambert only)", os.path.join(REPO, "scenes", "cornell.json"),
                                  *scene_size(os.path.join(REPO, "scenes", "cornell.json"), w)),
            "glossy": BenchScene("glossy", "glossy and refractive (every lobe)",
                                 os.path.join(REPO, "scenes", "materials.json"),
                                 *scene_size(os.path.join(REPO, "scenes", "materials.json"), w)),
        }
        docs_glossy = os.path.join(REPO, "scenes", "docs", "glossy_fresnel.json")
        self.scenes["docs_glossy"] = BenchScene("docs_glossy", "the documentation's glossy Fresnel example",
                                                docs_glossy, *scene_size(docs_glossy, w))
        segs, rings = (64, 32) if self.quick else (2048, 256)
        mesh = os.path.join(self.mesh_dir, f"knot_{segs}x{rings}.obj")
        self.scenes["mesh"] = BenchScene("mesh", f"torus knot, {2 * segs * rings:,} triangles",
                                         os.path.join(REPO, "scenes", "knot.json"),
                                         *scene_size(os.path.join(REPO, "scenes", "knot.json"), w),
                                         defines=[f"objects[0].file={mesh}"], mesh=(segs, rings))

    def elapsed(self):
        return time.monotonic() - self.t0

    def left(self):
        return self.budget - self.elapsed()

    def png(self, name):
        self.plots.append(name)
        return os.path.join(self.out, name)

    def ensure_mesh(self, scene):
        if scene.mesh:
            knot_mesh(self.mesh_dir, *scene.mesh)

    def docs_link(self, name):
        """A link to docs/NAME that works from the results folder; update_docs rewrites it."""
        return f"{DOCS_MARK}{name}"

    def warm_up(self, path, spp=1, defines=(), generic=False, device=None):
        """Compiles every kernel variant a timed render will use, before it is timed.

        PoCL builds a work-group function per kernel and grid class: one for small launches
        and one for launches above about 2^16 items. archwave's build step launches both now,
        so they count as kernel build; warming with a render of 2^18 jobs still guards the
        timings against anything compiled lazily. Same spp as the timed render, since
        spp decides whether lobe splitting is compiled in; no generated mesh (the kernels
        depend on materials and lights, not on the triangles)."""
        side = max(8, math.ceil(math.sqrt(LARGE_GRID_JOBS / spp)))
        defs = [d for d in defines if ".file=" not in d]
        r = self.tools.render(path, "warm_up", spp, side, side, defines=defs, generic=generic, device=device)
        self.warm_kernels.add((r.stats["kernel_features"], device))

    def render(self, path, name, spp, width, height, defines=(), scalar=False, generic=False, device=None,
               extra_args=()):
        """A timed render with warm kernels. A render whose kernel variant was not warmed yet
        (e.g. one that turns lobe splitting on) is warmed up and rendered again."""
        run = lambda: self.tools.render(path, name, spp, width, height, defines=defines, scalar=scalar,  # noqa: E731
                                        generic=generic, device=device, extra_args=extra_args)
        r = run()
        if scalar or (r.stats["kernel_features"], device) in self.warm_kernels:
            return r
        self.warm_up(path, spp, defines, generic, device)
        return run()

    # ---- 1. sample-count sweeps -------------------------------------------------------------

    def sweep_scene(self, scene, budget):
        """spp = 1, 2, 4, ... while the next point and a REF_FACTOR x reference for it still fit
        in `budget` seconds, then that reference and the errors against it."""
        t_start = time.monotonic()
        self.ensure_mesh(scene)
        self.warm_up(scene.path, 1, scene.defines)
        # The reference renderer's seconds per spp, to price references before choosing.
        cal_spp = 4 if self.quick else 16
        cal = self.tools.render(scene.path, f"sweep_{scene.key}_refcal", cal_spp, scene.width, scene.height,
                                seed=REF_SEED, defines=scene.defines, scalar=self.refs.scalar)
        ref_per_spp, ref_overhead = cal.seconds / cal_spp, cal.overhead
        max_spp = 16 if self.quick else 1024
        points = []
        spp = 1
        while spp <= max_spp:
            if spp > 4:  # the first points are cheap and always taken: they calibrate the rest
                last = points[-1]["render"]
                next_cost = last.overhead + last.seconds * spp / points[-1]["spp"]
                ref_cost = self.refs.ref_cost(scene, REF_FACTOR * spp, ref_per_spp, ref_overhead)
                if time.monotonic() - t_start + next_cost + ref_cost > budget:
                    break
            r = self.render(scene.path, f"sweep_{scene.key}_{spp}", spp, scene.width, scene.height,
                            defines=scene.defines)
            points.append({"spp": spp, "render": r})
            spp *= 2
        top = points[-1]["spp"]
        ref_exr, ref_meta = self.refs.get(scene, REF_FACTOR * top)
        for p in points:
            p["cmp"] = self.tools.compare(p["render"].exr, ref_exr)
        return {"scene": scene, "points": points, "ref": ref_meta, "top": top,
                "seconds": time.monotonic() - t_start}

    def section_sweeps(self, budget):
        keys = ["cornell", "glossy", "mesh"]
        results = []
        for i, k in enumerate(keys):
            share = (budget - sum(r["seconds"] for r in results)) / (len(keys) - i)
            log(f"sweeps: {k}, {share:.0f} s")
            results.append(self.sweep_scene(self.scenes[k], share))

        # Fits: RMSE ~ spp^-1/2 and relMSE ~ spp^-1 for an unbiased estimator. The reference's
        # own noise adds a constant to the MSE (independent seeds): estimate it from
        # MSE = a/spp + a/R with R the reference spp (same per-sample variance a), and report
        # both the raw slope and the slope with that floor taken out.
        rows, detail = [], []
        spp_series, rel_series, time_series, reltime_series = [], [], [], []
        for res in results:
            sc, pts, ref = res["scene"], res["points"], res["ref"]
            spp = np.array([p["spp"] for p in pts], float)
            secs = np.array([p["render"].seconds for p in pts])
            rmse = np.array([p["cmp"]["rmse"] for p in pts])
            rel = np.array([p["cmp"]["relmse"] for p in pts])
            R = ref["spp"]
            x = 1.0 / spp + 1.0 / R
            var = float(np.sum(rmse ** 2 * x) / np.sum(x * x))
            floor = math.sqrt(var / R)
            s_rmse, i_rmse = loglog_fit(spp, rmse)
            s_rel, i_rel = loglog_fit(spp, rel)
            s_t, i_t = loglog_fit(secs, rmse)
            s_rt, i_rt = loglog_fit(secs, rel)
            corrected = np.sqrt(np.maximum(rmse ** 2 - floor ** 2, 1e-300))
            s_corr, _ = loglog_fit(spp, corrected)
            res.update(slope=s_rmse, slope_floor_removed=s_corr, floor=floor)
            label = sc.key
            spp_series.append((label, spp, rmse, s_rmse, i_rmse))
            rel_series.append((label, spp, rel, s_rel, i_rel))
            time_series.append((label, secs, rmse, s_t, i_t))
            reltime_series.append((label, secs, rel, s_rt, i_rt))
            dev = s_rmse + 0.5
            rows.append([sc.key, f"1 – {int(spp.max())}", fmt(s_rmse), f"{dev:+.3f}", fmt(s_corr), fmt(s_rel),
                         fmt(s_t), fmt(floor), fmt(rmse[-1]), fmt(floor / rmse[-1] * 100, 2) + "%"])
            drow = [[int(p["spp"]), fmt(p["render"].stats["total_seconds"]), fmt(p["render"].seconds),
                     fmt(p["cmp"]["rmse"]), fmt(p["cmp"]["relmse"])] for p in pts]
            detail.append((sc, res, drow))
        loglog_figure(self.png("sweep_spp.png"),
                      [("samples per pixel", "RMSE", spp_series, -0.5),
                       ("samples per pixel", "relMSE", rel_series, -1.0)],
                      "Error vs spp (against a high-spp reference, another seed)")
        loglog_figure(self.png("sweep_time.png"),
                      [("render time (s)", "RMSE", time_series, -0.5),
                       ("render time (s)", "relMSE", reltime_series, -1.0)],
                      "Error vs render time (kernel and BVH build excluded)")

        md = ["## Sample-count sweeps\n",
              "Each scene is rendered at spp = 1, 2, 4, … (seed 0) up to the largest power of two the "
              "time budget allows (at most 1024), and compared with a reference of the same scene "
              "rendered by the project with another seed. RMSE is over all pixels and channels; relMSE "
              "divides each squared error by (reference² + 0.01). Monte Carlo error falls as "
              "spp^−1/2 (RMSE) and spp^−1 (relMSE): the fitted slopes (least squares in log–log) "
              "should be close to −0.5 and −1. Time is the render time from the stats (total minus "
              "kernel build and BVH build).\n",
              "The reference's own noise adds to every measured error. With the reference at R spp and "
              "the same per-sample variance a, MSE(spp) = a/spp + a/R; fitting a gives the reference's "
              "RMSE floor √(a/R) below, and the slope with that floor subtracted (\"slope, floor "
              "removed\").\n",
              "**AO scene: not available: AO is not implemented yet** (it belongs to the lights/AO "
              "issue; the `ao` keys parse and warn).\n",
              md_table(["scene", "spp", "RMSE slope vs spp", "deviation from −0.5", "slope, floor removed",
                        "relMSE slope vs spp", "RMSE slope vs time", "reference RMSE floor (est.)",
                        "RMSE at top spp", "floor / RMSE at top"], rows),
              "![error vs spp](sweep_spp.png)\n",
              "![error vs time](sweep_time.png)\n",
              "References (stored with ref.json beside ref.exr under `results/refs/`, reused by later runs "
              "of the same code):\n"]
        ref_rows = []
        for res in results:
            sc, ref = res["scene"], res["ref"]
            ref_rows.append([sc.key, f"`{os.path.relpath(sc.path, REPO)}`", f"{sc.width}x{sc.height}",
                             ref["spp"], f"{ref['spp'] // res['top']}x", ref["seed"], ref["renderer"],
                             fmt(ref["total_seconds"]), "yes" if ref.get("reused") else "no", fmt(res["floor"]),
                             ref["git_commit"][:10]])
        md.append(md_table(["scene", "file", "size", "reference spp", "× top sweep spp", "seed", "renderer",
                            "time (s)", "reused", "est. RMSE floor", "commit"], ref_rows))
        if any(res["ref"]["spp"] < REF_FACTOR * res["top"] for res in results):
            md.append("A reference below 16× the top sweep spp was all the budget allowed.\n")
        # A slope off -0.5 that the floor explains is the reference's limit, not the renderer's;
        # one it does not explain is worth a look (rare bright paths dominating low spp, or a bias).
        for res in results:
            key, s_raw, s_corr = res["scene"].key, res["slope"], res["slope_floor_removed"]
            if abs(s_raw + 0.5) <= 0.05:
                md.append(f"- {key}: RMSE slope {s_raw:+.3f}, within 0.05 of −0.5.")
            elif abs(s_corr + 0.5) <= 0.05:
                md.append(f"- {key}: RMSE slope {s_raw:+.3f}; with the reference floor removed {s_corr:+.3f}: "
                          "the deviation is the reference's own noise.")
            else:
                md.append(f"- {key}: RMSE slope {s_raw:+.3f}, {s_corr:+.3f} with the floor removed: a deviation "
                          "the reference floor does not explain (at low spp rare bright paths dominate the "
                          "error, so single points scatter; see every point below).")
        md.append("")
        for sc, res, drow in detail:
            md.append(f"\n<details><summary>{sc.title} ({sc.key}, {sc.width}x{sc.height}): every point"
                      f"</summary>\n\n" + md_table(["spp", "total (s)", "render (s)", "RMSE", "relMSE"], drow)
                      + "\n</details>\n")
        return "\n".join(md)

    def reference(self, scene, want, max_seconds):
        """A reference with `want` spp, or the most a calibration says fits in max_seconds
        (a power of two), or a cached one if that is better still."""
        cached = self.refs.cached(scene)
        if cached and cached["spp"] >= want:
            return self.refs.get(scene, want)
        cal = self.tools.render(scene.path, f"refcal_{scene.key}", 4, scene.width, scene.height, seed=REF_SEED,
                                defines=scene.defines, scalar=self.refs.scalar)
        spp = want
        while spp > 64 and cal.overhead + cal.seconds / 4 * spp > max_seconds:
            spp //= 2
        if cached and cached["spp"] >= spp:
            spp = cached["spp"]
        return self.refs.get(scene, spp)

    # ---- 2. knobs at equal time -------------------------------------------------------------

    @staticmethod
    def splitting_settings(path):
        """Lobe splitting on and off at a fixed split count, for the scene at `path`."""
        with open(path) as f:
            mats = json.load(f).get("materials", {})

        def samples(n):
            return [f"materials.{m}.{lobe}.samples={n}" for m in mats for lobe in ("reflection", "refraction")]

        def split(n, on=True):
            # samples = n * spp gives n rays per glossy lobe at the first hit (max(1,
            # round(samples / spp)), MATERIAL.md §6) whatever spp the equal-time search picks.
            return lambda spp: samples(n * spp) + ([] if on else ["render.lobe_splitting=false"])
        return [("default (the scene's lobe samples; below spp: no split)", [], "unbiased"),
                ("samples = 4·spp: 4 rays per glossy lobe at the first hit", split(4), "unbiased"),
                ("samples = 4·spp, lobe_splitting false", split(4, on=False), "unbiased"),
                ("samples = 16·spp: 16 rays per glossy lobe", split(16), "unbiased")]

    def knob_settings(self):
        cornell = [("default (max_depth 8, cutoff 0.001, RR from bounce 3)", [], "unbiased"),
                   ("max_depth 1 (direct light only)", ["render.max_depth=1"], "biased: shorter paths"),
                   ("max_depth 2", ["render.max_depth=2"], "biased: shorter paths"),
                   ("max_depth 4", ["render.max_depth=4"], "biased: shorter paths"),
                   ("max_depth 16", ["render.max_depth=16"], "another image: longer paths"),
                   ("cutoff 0", ["render.cutoff=0"], "unbiased"),
                   ("cutoff 0.01", ["render.cutoff=0.01"], "unbiased"),
                   ("cutoff 0.1", ["render.cutoff=0.1"], "unbiased"),
                   ("Russian roulette off (rr_depth 1000)", ["render.rr_depth=1000"], "unbiased"),
                   ("Russian roulette from bounce 1", ["render.rr_depth=1"], "unbiased")]
        glossy = self.splitting_settings(self.scenes["glossy"].path)
        if self.quick:
            cornell = [cornell[0], cornell[2], cornell[8]]
            glossy = glossy[:3]
            return [("cornell", cornell), ("glossy", glossy)]
        # The issue's own ask: the documentation's glossy example, splitting on and off.
        docs = self.splitting_settings(self.scenes["docs_glossy"].path)
        return [("cornell", cornell), ("glossy", glossy), ("docs_glossy", docs)]

    def knob_setting(self, scene, index, defines, target, per_spp_guess):
        """One setting at about T/16 (the calibration), T/4 and T seconds of render time: the
        points of its error-vs-time curve, the last one being the equal-time render."""
        tag = f"knob_{scene.key}_{index}"
        done = {}

        def at(spp):
            if spp not in done:
                defs = scene.defines + (defines(spp) if callable(defines) else list(defines))
                done[spp] = self.render(scene.path, f"{tag}_{spp}", spp, scene.width, scene.height, defines=defs)
            return done[spp]
        cal_spp = max(1, round(target / 16 / per_spp_guess))
        eq = max(1, round(target / (at(cal_spp).seconds / cal_spp)))
        at(max(1, eq // 4))
        # Time is not linear in spp (a fixed cost per wavefront iteration; splitting depends
        # on spp): up to two correction steps while the equal-time render misses T by > 25%.
        for _ in range(2):
            if abs(at(eq).seconds - target) <= 0.25 * target:
                break
            eq = max(1, round(eq * target / at(eq).seconds))
        at(eq)
        return sorted(done.values(), key=lambda r: r.seconds)

    def section_knobs(self, budget):
        settings = self.knob_settings()
        total_settings = sum(len(s) for _, s in settings)
        t_start = time.monotonic()
        md = ["## Knob sweeps at equal time\n",
              "Each setting is rendered at the spp that takes a common render time T (the spp comes from "
              "a calibration render at about T/16), and at a quarter of that spp. Through each setting's "
              "points the suite fits MSE(spp) = a/spp + b (a: its noise; b: what more samples do not "
              "remove — bias against the reference and the reference's own noise) and time(spp) = "
              "c0 + c1·spp, with relative residuals. Settings that converge to the reference's image "
              "(\"unbiased\") share one b, the reference's noise, fitted jointly over all their points; "
              "the others get their own. **Error at equal time** is that fit's RMSE at exactly T; the render nearest T "
              "and its measured RMSE are shown too. **Time to equal error** is the time at which the fit "
              "reaches E = the default setting's RMSE at T; \"never\" when b alone exceeds E². Errors are "
              "against the reference of the **default** settings: a setting that changes the converged "
              "image (max_depth below the default ends paths early: bias; max_depth 16 adds longer paths "
              "the reference lacks) shows the difference as the floor √b, which is what that knob trades "
              "away.\n",
              "**AO samples: not available: AO is not implemented yet.**\n"]
        for scene_key, opts in settings:
            scene = self.scenes[scene_key]
            self.warm_up(scene.path, 4, scene.defines)
            probe = self.render(scene.path, f"knob_{scene.key}_probe", 4, scene.width, scene.height,
                                defines=scene.defines)
            share = (budget - (time.monotonic() - t_start)) * len(opts) / total_settings
            total_settings -= len(opts)
            # A setting costs about (1 + 1/4 + 1/16) T plus four processes' overhead; a sixth of
            # the share stays for a reference when the sweeps did not leave one.
            target = max(0.05, (share * 0.85 / len(opts) - 4 * probe.overhead) / 1.4)
            if self.quick:
                target = min(target, 0.3)
            log(f"knobs: {scene_key}: {len(opts)} settings, T = {target:.2f} s")
            runs = [(name, kind, self.knob_setting(scene, i, defines, target, probe.seconds / 4))
                    for i, (name, defines, kind) in enumerate(opts)]
            top = max(r.stats["spp"] for _, _, rs in runs for r in rs)
            ref_exr, ref_meta = self.reference(scene, REF_FACTOR * 2 ** math.ceil(math.log2(top)), share * 0.15)
            measured = [(name, kind, rs, np.array([r.seconds for r in rs]),
                         np.array([self.tools.compare(r.exr, ref_exr)["rmse"] ** 2 for r in rs]))
                        for name, kind, rs in runs]
            floor = shared_floor([([r.stats["spp"] for r in rs], mse) for _, kind, rs, _, mse in measured
                                  if kind == "unbiased"])
            fits = []
            for name, kind, rs, t, mse in measured:
                model = ErrorModel([r.stats["spp"] for r in rs], t, mse, floor if kind == "unbiased" else None)
                nearest = int(np.argmin(np.abs(np.log(t / target))))
                fits.append({"name": name, "kind": kind, "runs": rs, "t": t, "mse": mse, "b": model.b,
                             "model": model, "nearest": rs[nearest], "rmse_nearest": math.sqrt(mse[nearest]),
                             "rmse_T": model.rmse_at_time(target)})
            base = fits[0]
            goal = base["rmse_T"]
            table, curves = [], []
            for f in fits:
                f["t_goal"] = f["model"].time_to_rmse(goal)
            for f in fits:
                finite = math.isfinite(f["t_goal"]) and math.isfinite(base["t_goal"])
                curves.append((f["name"].split(" (")[0], f["t"], np.sqrt(f["mse"]), float("nan"), 0.0))
                table.append([f["name"], f["kind"], f["nearest"].stats["spp"], fmt(f["nearest"].seconds),
                              fmt(f["rmse_nearest"]), fmt(f["rmse_T"]), fmt(f["rmse_T"] / goal, 3),
                              fmt(math.sqrt(f["b"])), fmt(f["t_goal"]) if math.isfinite(f["t_goal"]) else "never",
                              fmt(f["t_goal"] / base["t_goal"], 3) if finite else "–"])
            plot = f"knobs_{scene_key}.png"
            loglog_figure(self.png(plot), [("render time (s)", "RMSE vs default reference", curves, -0.5)],
                          f"{scene.title}: error vs time per setting")
            md.append(f"### {scene.title} (`{os.path.relpath(scene.path, REPO)}`, {scene.width}x{scene.height}, "
                      f"T = {fmt(target)} s)\n")
            md.append(md_table(["setting", "converges to", "spp nearest T", "its time (s)", "its RMSE",
                                "RMSE at T (fit)", "× default", "floor √b", f"time to RMSE {fmt(goal)} (s)",
                                "× default"], table))
            md.append(f"![{scene_key} knobs]({plot})\n")
            md.append(f"Reference: {ref_meta['spp']} spp, seed {ref_meta['seed']}, {ref_meta['renderer']} "
                      f"({'from the cache' if ref_meta.get('reused') else 'rendered in this run'}).\n")
            if scene_key in ("glossy", "docs_glossy"):
                md.append(self.splitting_note(fits))
        return "\n".join(md)

    @staticmethod
    def splitting_note(fits):
        """What splitting bought: the 4-ray setting against the same samples with splitting off
        (the stats name the 'split' kernel feature when some lobe gets more than one ray)."""
        split = [f["name"] for f in fits if re.search(r"\bsplit\b", f["nearest"].stats["kernel_features"])]
        text = ("Lobe splitting (MATERIAL.md §6) traces max(1, round(samples / spp)) rays per glossy lobe at "
                "the first hit, so it acts only while a lobe's `samples` exceeds spp; the settings above set "
                "samples = n·spp to hold n fixed across the equal-time search. Renders at T that split: "
                + (", ".join(split) if split else "none") + ". ")
        on = next((f for f in fits if f["name"].startswith("samples = 4·spp:")), None)
        off = next((f for f in fits if "lobe_splitting false" in f["name"]), None)
        if on and off and math.isfinite(on["t_goal"]) and math.isfinite(off["t_goal"]):
            text += (f"4-way splitting on vs off at equal time: RMSE × {fmt(on['rmse_T'] / off['rmse_T'], 3)}, "
                     f"time to the default's error × {fmt(on['t_goal'] / off['t_goal'], 3)} (below 1: "
                     "splitting pays).")
        return text + "\n"

    # ---- 3. throughput ----------------------------------------------------------------------

    def section_throughput(self):
        md = ["## Throughput\n"]
        # Traversal: the OpenCL intersect kernel and Embree on the same rays.
        targs = ["--tris", "20000", "--width", "128", "--height", "128"] if self.quick else []
        tj, tcmd = self.tools.traversal(targs, os.path.join(self.work, "traversal.json"))
        rows = []
        trav_ratios = []
        for r in tj["rows"]:
            ratio = r["opencl_mrays"] / r["embree_mrays"]
            trav_ratios.append(ratio)
            rows.append([r["kind"], r["rays"], fmt(r["opencl_mrays"]), fmt(r["embree_mrays"]), fmt(ratio),
                         fmt(r["embree1_mrays"]), f"{100 * r['mismatch']:.4f}%"])
        met = "Met" if min(trav_ratios) >= 1 / 3 else "Not met"
        self.notes["embree"] = tj["embree"]
        md += ["### Traversal: OpenCL intersect kernel vs Embree (`bench/bench_traversal`)\n",
               "Same ray batches through the flattened-BVH kernel on the OpenCL device and through "
               "Embree's `rtcIntersect1` on the host, with as many host threads as the device has "
               "compute units. Target (issue 2): OpenCL ≥ 1/3 of Embree's single-ray throughput on "
               f"the same cores; ambition ≥ 0.5. **{met}: {' and '.join(fmt(r, 2) for r in trav_ratios)} "
               "(primary, diffuse).**\n",
               f"Command: `{' '.join(['bench/bench_traversal'] + targs)}` (in the build folder); "
               f"geometry: {tj['geometry']}, {tj['triangles']:,} triangles, flat BVH "
               f"{tj['bvh_nodes']:,} nodes, depth {tj['bvh_depth']}; primary rays {tj['width']}x{tj['height']} "
               f"pinhole, diffuse rays one cosine bounce per primary hit; OpenCL kernel time only, Embree "
               f"wall time ({tj['embree']}, robust scene), best of 3 after a warm-up; device "
               f"{tj['device']}, {tj['compute_units']} compute units.\n",
               md_table(["ray kind", "rays", "OpenCL Mrays/s", f"Embree Mrays/s ({tj['compute_units']} threads)",
                         "ratio OpenCL/Embree", "Embree 1-thread Mrays/s", "hit mismatch"], rows),
               "The kernel is the stack-based Aila–Laine BVH2 traversal with the watertight triangle test "
               f"([bvh-layout.md]({self.docs_link('bvh-layout.md')})).\n"]

        # End to end, wavefront vs scalar, and the wavefront's stages.
        cases = [("cornell", 400, 400, 32), ("glossy", 320, 160, 32)]
        if self.quick:
            cases = [("cornell", 32, 32, 2), ("glossy", 32, 16, 2)]
        e2e, stage_md, ratios = [], [], {}
        for key, w, h, spp in cases:
            sc = self.scenes[key]
            self.warm_up(sc.path, spp)
            wf = self.render(sc.path, f"e2e_{key}_wavefront", spp, w, h)
            sl = self.render(sc.path, f"e2e_{key}_scalar", spp, w, h, scalar=True)
            ratios[key] = sl.seconds / wf.seconds
            for name, r in (("wavefront (OpenCL)", wf), ("scalar (host, Embree)", sl)):
                s = r.stats
                e2e.append([f"{key} {w}x{h}, {spp} spp", name, fmt(r.seconds), fmt(s["samples"] / r.seconds * 1e-6),
                            fmt((s["closest_rays"] + s["shadow_rays"]) / r.seconds * 1e-6),
                            fmt(sl.seconds / r.seconds, 3)])
            st = wf.stats["stages"]
            total = sum(x["seconds"] for x in st) or 1.0
            stage_md.append(f"**{sc.title}** (`{os.path.relpath(sc.path, REPO)}`, {w}x{h}, {spp} spp):\n\n" + md_table(
                ["stage", "time (s)", "share", "items", "M items/s"],
                [[x["name"], fmt(x["seconds"]), f"{100 * x['seconds'] / total:.1f}%", x["items"],
                  fmt(x["items"] / x["seconds"] * 1e-6 if x["seconds"] > 0 else float("nan"))] for x in st]))
        md += ["### End to end: wavefront vs scalar path\n",
               "Kernel build excluded (a warm-up render fills PoCL's cache first); time = render time "
               "from the stats. Rays = closest + shadow.\n",
               md_table(["scene", "renderer", "time (s)", "Msamples/s", "Mrays/s", "speed relative to scalar"], e2e),
               "### Per-stage time and throughput (wavefront)\n",
               "One shading kernel per lobe queue; `items` = paths through the stage (pixels for "
               "film_accumulate); the same columns appear in every render's stats summary.\n"]
        md += stage_md

        # Dense launches vs queue launches (docs/architecture.md, "Dense launches"): the same
        # renders with the default threshold, with every queue launched over its entries, and
        # with every dense-capable stage launched over the whole pool. Interleaved, best of
        # `reps`, so drift on a shared machine hits all three alike.
        dense_modes = [("default (0.25)", []), ("never (queue order)", ["--dense-fraction", "2"]),
                       ("always", ["--dense-fraction", "0"])]
        dense_rows, dense_gain = [], {}
        reps = 1 if self.quick else 2
        for key, w, h, spp in cases:
            sc = self.scenes[key]
            best = {}
            for rep_i in range(reps):
                for label, extra in dense_modes:
                    r = self.render(sc.path, f"dense_{key}_{rep_i}_{extra[-1] if extra else 'default'}", spp, w, h,
                                    extra_args=extra)
                    if label not in best or r.seconds < best[label].seconds:
                        best[label] = r
            base = best["never (queue order)"].seconds
            dense_gain[key] = base / best["default (0.25)"].seconds
            for label, _ in dense_modes:
                r = best[label]
                st = {x["name"]: x["seconds"] for x in r.stats["stages"]}
                dense_rows.append([f"{key} {w}x{h}, {spp} spp", label, fmt(r.seconds), fmt(base / r.seconds, 3),
                                   fmt(st.get("intersect_closest", 0)), fmt(st.get("classify_hit", 0)),
                                   fmt(sum(v for k, v in st.items() if k.startswith("shade_"))),
                                   fmt(st.get("intersect_shadow", 0))])
        md += ["### Dense launches vs queue launches\n",
               "A stage whose queue holds at least a quarter of the pool runs over the whole pool in slot "
               "order, one work-item per slot, instead of over the queue's scattered entries "
               f"([architecture.md]({self.docs_link('architecture.md')}), \"Dense launches\"); the image is "
               f"bit-identical. Render time (s) and the dense-capable stages' times, best of {reps}, "
               "interleaved; speed-up relative to queue order.\n",
               md_table(["scene", "dense launches", "render (s)", "speed-up", "intersect_closest (s)",
                         "classify_hit (s)", "shading (s)", "intersect_shadow (s)"], dense_rows)]

        # Memory: per path state and per triangle.
        mem_rows = []
        self.ensure_mesh(self.scenes["mesh"])
        mem_spp = 1 if self.quick else 4
        for key in ("cornell", "glossy", "mesh"):
            sc = self.scenes[key]
            self.warm_up(sc.path, mem_spp, sc.defines)
            r = self.render(sc.path, f"mem_{key}", mem_spp, 320, 240, defines=sc.defines)
            s = r.stats
            mem_rows.append([key, s["pool_size"], fmt_bytes(s["state_bytes"]),
                             s["state_bytes"] // max(1, s["pool_size"]),
                             f"{s['triangles']:,}", fmt_bytes(s["scene_bytes"]),
                             fmt(s["scene_bytes"] / max(1, s["triangles"])), fmt_bytes(s["film_bytes"]),
                             fmt_bytes(s["device_bytes"])])
            if key == "cornell":
                state_per_path = s["state_bytes"] // max(1, s["pool_size"])
        md += ["### Memory per path state and per triangle\n",
               "From the stats of a 320x240 render (`state_bytes` / `pool_size`, `scene_bytes` / "
               "`triangles`; scene bytes = BVH nodes + leaf triangles + triangle info + vertices + "
               "materials + lights on the device; film = film + sample counts + batch samples).\n",
               md_table(["scene", "path states", "path pool", "bytes per path state", "triangles", "scene data",
                         "bytes per triangle", "film", "all device buffers"], mem_rows)]
        c = ratios.get("cornell")
        g = ratios.get("glossy")
        md.append(
            f"What this says, honestly: on PoCL the wavefront runs at {fmt(c, 2)}× (Cornell) and {fmt(g, 2)}× "
            "(every lobe) the speed of the host scalar path on the same cores. The traversal kernel alone "
            f"is at {' and '.join(fmt(r, 2) for r in trav_ratios)}× "
            "Embree; the rest is the cost of the wavefront on a CPU: every stage reads and writes the "
            f"path state in memory ({state_per_path} bytes per path on the Cornell box; dense launches "
            f"keep those accesses in slot order and gain {fmt(dense_gain.get('cornell'), 2)}× on Cornell and "
            f"{fmt(dense_gain.get('glossy'), 2)}× on the every-lobe scene), each stage ends in a host "
            "synchronisation to read the queue counters, and PoCL runs every kernel one work-item at a "
            "time: its work-group vectoriser (LLVM's loop vectoriser over the work-item loop) gives up on "
            "a loop body that contains OpenCL vector types (\"instruction return type cannot be "
            "vectorized\" with `POCL_VECTORIZER_REMARKS=1`; a minimal kernel doing its arithmetic on a "
            "`float3` stays scalar while the same arithmetic on three floats is vectorised), and the "
            "kernels do their geometry in `float3`. Writing it on scalars would not be enough either: "
            "when PoCL builds the program, LLVM (evidently its SLP vectoriser) packs isomorphic scalar "
            "operations (x, y, z or r, g, b) into short vectors, which blocks the work-item loop just the "
            "same (seen on a synthetic diffuse stage written on scalars, which drew the same remark), and "
            "PoCL 3.1 accepts no build option to turn that off. The wavefront exists for GPUs, where the "
            "same kernels run unchanged.\n")
        return "\n".join(md)

    # ---- 4. specialisation ------------------------------------------------------------------

    def section_specialisation(self):
        keys = ["cornell"] if self.quick else ["cornell", "docs_glossy", "glossy", "knot"]
        w, h, spp = (32, 24, 2) if self.quick else (320, 240, 32)
        knot = BenchScene("knot", "torus knot (scenes/knot.json)", os.path.join(REPO, "scenes", "knot.json"), w, h)
        rows, cornell_ratio, caches, cornell_warm, cornell_spread = [], None, {}, None, None
        cold_root = tempfile.mkdtemp(prefix="pocl-cold-", dir=self.work)
        for key in keys:
            sc = knot if key == "knot" else self.scenes[key]
            tag = f"spec_{key}"
            # A fresh, empty PoCL cache per variant and scene: a cold build. Then the same
            # caches again, warm, in interleaved pairs (specialised, generic), so that the
            # machine's drift hits both alike: the speed-up is the median of the pairs' ratios,
            # with their range. Five pairs for the Lambert scene, whose ratio is the issue's
            # target, two for the others.
            cold = {}
            for generic in (False, True):
                cache = os.path.join(cold_root, f"{tag}_{int(generic)}")
                os.makedirs(cache)
                caches[(key, generic)] = cache
                cold[generic] = self.tools.render(sc.path, f"{tag}_{int(generic)}_cold", spp, w, h, generic=generic,
                                                  pocl_cache=cache)
            pairs = [tuple(self.tools.render(sc.path, f"{tag}_{int(generic)}_warm{i}", spp, w, h, generic=generic,
                                             pocl_cache=caches[(key, generic)]) for generic in (False, True))
                     for i in range(1 if self.quick else 5 if key == "cornell" else 2)]
            ratios = sorted(g.seconds / s.seconds for s, g in pairs)
            ratio = median(ratios)
            med_s = median([s.seconds for s, _ in pairs])
            med_g = median([g.seconds for _, g in pairs])
            warm_s = min((s for s, _ in pairs), key=lambda r: r.seconds)
            warm_g = min((g for _, g in pairs), key=lambda r: r.seconds)
            cold_s, cold_g = cold[False], cold[True]
            # The machine code PoCL compiled for each variant (its work-group functions, one
            # shared object per kernel and local size in the cache): what the cold build made.
            code = {g: sum(os.path.getsize(os.path.join(d, f)) for d, _, fs in os.walk(caches[(key, g)])
                           for f in fs if f.endswith(".so")) for g in (False, True)}
            if key == "cornell":
                cornell_ratio, cornell_warm, cornell_spread = ratio, (warm_s, warm_g), (ratios[0], ratios[-1])
            rows.append([f"`{os.path.relpath(sc.path, os.path.join(REPO, 'scenes'))}`",
                         warm_s.stats["kernel_features"].replace("specialised: ", ""),
                         fmt(med_s), fmt(med_g), f"{ratio:.2f}x",
                         f"{ratios[0]:.2f} – {ratios[-1]:.2f} ({len(pairs)})",
                         f"{fmt(cold_s.stats['compile_seconds'])} / {fmt(cold_g.stats['compile_seconds'])}",
                         f"{fmt(warm_s.stats['compile_seconds'])} / {fmt(warm_g.stats['compile_seconds'])}",
                         f"{fmt(cold_s.wall - warm_s.wall)} / {fmt(cold_g.wall - warm_g.wall)}",
                         f"{code[False] / 1024:.0f} / {code[True] / 1024:.0f}",
                         f"{cold_g.wall / cold_s.wall:.2f}x"])
        # Where the Lambert scene's difference lies: per stage, with dense launches (the default)
        # and with every queue in append order (--dense-fraction 2), warm caches, best of 2.
        stage_rows, diffuse_ratio = [], {}
        if cornell_warm:
            sc = self.scenes["cornell"]
            queued = {}
            for generic in (False, True):
                queued[generic] = min(
                    (self.tools.render(sc.path, f"spec_cornell_queued_{int(generic)}_{i}", spp, w, h, generic=generic,
                                       pocl_cache=caches[("cornell", generic)], extra_args=["--dense-fraction", "2"])
                     for i in range(2)), key=lambda r: r.seconds)
            per = lambda r: {x["name"]: x["seconds"] for x in r.stats["stages"]}  # noqa: E731
            ds, dg, qs, qg = per(cornell_warm[0]), per(cornell_warm[1]), per(queued[False]), per(queued[True])
            for name in ds:
                stage_rows.append([name, fmt(ds[name]), fmt(dg.get(name, float("nan"))),
                                   fmt(dg.get(name, float("nan")) / ds[name], 3) if ds[name] > 0 else "–",
                                   fmt(qs.get(name, float("nan"))), fmt(qg.get(name, float("nan"))),
                                   fmt(qg.get(name, float("nan")) / qs[name], 3) if qs.get(name) else "–"])
            diffuse_ratio = {"dense": dg["shade_diffuse"] / ds["shade_diffuse"],
                             "queued": qg["shade_diffuse"] / qs["shade_diffuse"],
                             "total_queued": queued[True].seconds / queued[False].seconds}
        shutil.rmtree(cold_root, ignore_errors=True)
        met = cornell_ratio is not None and cornell_ratio >= 1.5
        return "\n".join([
            "## Kernel specialisation\n",
            f"Kernels specialised on the scene's features vs the generic build (`--generic-kernels`, every "
            f"feature), {w}x{h}, {spp} spp. Render time excludes the kernel build: the median of the warm "
            "renders, which alternate specialised and generic (pairs); the speed-up is the median of the "
            "pairs' generic / specialised ratios, the range their smallest and largest. Cold = a fresh, "
            "empty `POCL_CACHE_DIR`, warm = the same cache again; cold − warm wall is the whole cost of a "
            "cold cache; compiled kernels = the size of the machine code PoCL generated (its shared "
            "objects in the cache). The last column is what a user sees the first time a feature set is rendered: "
            "the whole process (kernel build included) with a cold cache, generic / specialised; it is "
            "not the target's measure, which is the render with warm caches.\n",
            md_table(["scene", "features (specialised)", "render specialised (s)", "render generic (s)",
                      "speed-up (median)", "range (pairs)", "build cold spec / gen (s)", "build warm spec / gen (s)",
                      "cold − warm wall spec / gen (s)", "compiled kernels spec / gen (KiB)",
                      "whole process, cold cache: speed-up"], rows),
            "Specialisation removes absent lobes' kernels and code paths "
            f"([material.md]({self.docs_link('material.md')})). "
            "Each lobe's shading kernel is already compiled for its own lobe (the lobe id is a constant "
            "there), so what remains to remove at render time is branches: the energy split's Fresnel "
            "terms, BRDFs and Fresnel modes no lobe uses (Beckmann's erf and Newton sampler, "
            "Ashikhmin–Shirley, the conductor and curve Fresnel), thin walls, light types. A path takes "
            "such a branch the same way every time, so on a CPU the gain is mostly in the "
            "cold build, where there is less code to compile. Not always: with fewer code paths, LLVM "
            "inlines more of the shading code into each lobe's kernel, and a specialised build can come "
            "out larger and slower to compile than the generic one (compare the compiled sizes with the "
            "cold builds).\n",
            f"**The issue's target — a Lambert-only scene (Cornell box) ≥ 1.5× faster specialised than "
            f"generic — is {'met' if met else 'not met'}: {fmt(cornell_ratio, 3)}× (median of the pairs; "
            f"range {fmt(cornell_spread[0] if cornell_spread else None, 3)}–"
            f"{fmt(cornell_spread[1] if cornell_spread else None, 3)}×).**"
            + ("" if met else " Why, on this device: PoCL runs every kernel of both builds one work-item "
               "at a time (see Throughput: its vectoriser gives up on `float3` arithmetic), so "
               "specialisation can only remove branches, and the branches it removes are taken the same "
               "way by every path of a Lambert-only scene, which a CPU predicts almost for free. What "
               "remains measurable is the generic build's larger shading function (not inlined, so one "
               "path's loads overlap less with the previous path's work): the generic diffuse stage takes "
               f"{fmt(diffuse_ratio.get('queued'), 3)}× the specialised one's time with queues in append "
               f"order and {fmt(diffuse_ratio.get('dense'), 3)}× with dense launches, which put the state "
               "accesses in slot order (the table below); the whole render "
               f"{fmt(diffuse_ratio.get('total_queued'), 3)}× and {fmt(cornell_ratio, 3)}×. "
               "Fusing a whole Lambert bounce into one kernel was not faster (an earlier session); fusing "
               "classification and shading for a single-lobe build gained too little to keep. Where "
               "specialisation should pay: on a GPU (absent code also frees registers and raises "
               "occupancy; no GPU has been lent to this project's sessions yet), and on a CPU OpenCL "
               "that vectorises work-items, where the generic build's cutout-stepping loop and "
               "transcendental calls (EON's `acos`, sphere-light sampling) would keep it scalar while a "
               "Lambert-only build might not be.") + "\n",
            (f"Per stage, Cornell box, {w}x{h}, {spp} spp, warm caches (s); dense = the default, queued = "
             "every stage over its queue in append order (`--dense-fraction 2`); the fastest render of "
             "each (dense: of the pairs above; queued: of 2):\n\n"
             + md_table(["stage", "dense spec", "dense gen", "gen / spec", "queued spec", "queued gen",
                         "gen / spec"], stage_rows) + "\n") if stage_rows else "",
            "### Kernel build cost\n",
            "PoCL compiles a program at `clBuildProgram` and each kernel's work-group function at its first "
            "launch with a given local size; archwave launches every stage once on zero items right after "
            "the build, so both are reported as \"kernel build\" in the stats (`compile_seconds`). PoCL "
            "also keeps a second work-group function per kernel for launches above about 2^16 items; "
            "the same warm-up launches each stage once more on a large, empty grid, so that one is "
            "part of the kernel build too and the cold − warm wall time is close to the cold build "
            "column. The cache "
            "lives in `POCL_CACHE_DIR` (the scripts use `build/pocl-cache`; delete it to force cold "
            "builds).\n"])

    # ---- 5. scaling -------------------------------------------------------------------------

    def section_scaling(self):
        md = ["## Scaling\n"]
        # Triangle count: the same knot tube, finer and finer, in the same view (scenes/knot.json).
        sizes = [(64, 8), (128, 16)] if self.quick else [(200, 25), (400, 50), (800, 100), (1600, 200), (3200, 400)]
        w, h, spp = (32, 24, 2) if self.quick else (128, 96, 8)
        knot = os.path.join(REPO, "scenes", "knot.json")
        self.warm_up(knot, spp)
        rows, tris, bvh_t, render_t, per_tri = [], [], [], [], []
        for segs, rings in sizes:
            mesh = knot_mesh(self.mesh_dir, segs, rings)
            r = self.render(knot, f"scale_tris_{segs}x{rings}", spp, w, h, defines=[f"objects[0].file={mesh}"])
            s = r.stats
            tris.append(s["triangles"])
            bvh_t.append(s["bvh_seconds"])
            render_t.append(r.seconds)
            per_tri.append(s["scene_bytes"] / s["triangles"])
            rows.append([f"{s['triangles']:,}", fmt(r.wall), fmt(s["bvh_seconds"]), fmt(r.seconds),
                         fmt(s["samples"] / r.seconds * 1e-6),
                         fmt((s["closest_rays"] + s["shadow_rays"]) / r.seconds * 1e-6),
                         fmt_bytes(s["scene_bytes"]), fmt(per_tri[-1]), fmt_bytes(s["device_bytes"])])
        s_render, i_render = loglog_fit(tris, render_t)
        s_bvh, i_bvh = loglog_fit(tris, bvh_t)
        loglog_figure(self.png("scaling_triangles.png"),
                      [("triangles", "seconds", [("render", tris, render_t, s_render, i_render),
                                                 ("BVH build", tris, bvh_t, s_bvh, i_bvh)], None)],
                      f"Time vs triangle count (scenes/knot.json view, {w}x{h}, {spp} spp)")
        md += ["### Time vs triangle count\n",
               f"The knot of `scenes/knot.json` regenerated by `scripts/gen_torus_knot.py` at increasing "
               f"resolution (same view, same materials), {w}x{h}, {spp} spp. Wall = the whole process "
               f"(OBJ parsing included).\n",
               md_table(["triangles", "wall (s)", "BVH build (s)", "render (s)", "Msamples/s", "Mrays/s",
                         "scene data", "bytes per triangle", "all device buffers"], rows),
               f"Render time grows as triangles^{fmt(s_render, 2)} (a BVH makes traversal roughly "
               f"logarithmic in the triangle count); BVH build as triangles^{fmt(s_bvh, 2)}.\n",
               "![time vs triangles](scaling_triangles.png)\n"]

        # Resolution: the path pool is fixed (up to 2^18 states; smaller when the whole render
        # has fewer jobs), so memory should grow only with the film.
        sides = [16, 32] if self.quick else [64, 128, 256, 512]
        rspp = 2 if self.quick else 8
        cornell = self.scenes["cornell"]
        self.warm_up(cornell.path, rspp)
        rows, px, secs, film, dev, state = [], [], [], [], [], []
        for side in sides:
            r = self.render(cornell.path, f"scale_res_{side}", rspp, side, side)
            s = r.stats
            px.append(side * side)
            secs.append(r.seconds)
            film.append(s["film_bytes"])
            dev.append(s["device_bytes"])
            state.append(s["state_bytes"])
            rows.append([f"{side}x{side}", fmt(r.seconds), fmt(s["samples"] / r.seconds * 1e-6), s["pool_size"],
                         fmt_bytes(s["state_bytes"]), fmt_bytes(s["film_bytes"]), fmt_bytes(s["device_bytes"])])
        s_res, i_res = loglog_fit(px, secs)
        loglog_figure(self.png("scaling_resolution.png"),
                      [("pixels", "render time (s)", [("render", px, secs, s_res, i_res)], 1.0),
                       ("pixels", "bytes", [("all device buffers", px, dev, float("nan"), 0.0),
                                            ("film", px, film, float("nan"), 0.0),
                                            ("path pool", px, state, float("nan"), 0.0)], None)],
                      f"Cornell box, {rspp} spp: time and memory vs resolution")
        md += ["### Time and memory vs resolution\n",
               f"Cornell box, {rspp} spp. The path pool holds min(2^18, jobs) states, so it stops "
               "growing once a render has 2^18 jobs; from then on only the film (and the batch's sample "
               "buffer, 4 × pool) grows with the image.\n",
               md_table(["size", "render (s)", "Msamples/s", "path states", "path pool", "film",
                         "all device buffers"], rows),
               f"Render time grows as pixels^{fmt(s_res, 2)} (1 = linear).\n",
               "![time and memory vs resolution](scaling_resolution.png)\n"]
        return "\n".join(md)

    # ---- 6. devices -------------------------------------------------------------------------

    def section_devices(self):
        w, h, spp = (32, 32, 2) if self.quick else (256, 256, 16)
        sc = self.scenes["cornell"]
        rows = []
        devices = self.tools.list_devices()
        for idx, desc in devices:
            self.warm_up(sc.path, spp, device=idx)
            r = self.render(sc.path, f"dev{idx}", spp, w, h, device=idx)
            rows.append(self.device_row(f"[{idx}] {desc.split(' (')[0].strip()}", r))
        r = self.render(sc.path, "dev_scalar", spp, w, h, scalar=True)
        rows.append(self.device_row(f"host scalar path ({os.cpu_count()} threads, Embree)", r))
        return "\n".join([
            "## Devices\n",
            f"The Cornell box, {w}x{h}, {spp} spp, on every OpenCL device `archwave --list-devices` shows "
            "and on the host scalar path (`--scalar`). A GPU appears only when the machine has one.\n",
            md_table(["device", "render (s)", "Msamples/s", "Mrays/s", "kernel build, cached (s)"], rows)])

    @staticmethod
    def device_row(name, r):
        s = r.stats
        return [name, fmt(r.seconds), fmt(s["samples"] / r.seconds * 1e-6),
                fmt((s["closest_rays"] + s["shadow_rays"]) / r.seconds * 1e-6),
                fmt(s["compile_seconds"]) if s["renderer"] == "wavefront" else "–"]

    # ---- report -----------------------------------------------------------------------------

    def machine(self):
        cpu = "unknown CPU"
        with open("/proc/cpuinfo") as f:
            for line in f:
                if line.startswith("model name"):
                    cpu = line.split(":", 1)[1].strip()
                    break
        mem = 0
        with open("/proc/meminfo") as f:
            for line in f:
                if line.startswith("MemTotal:"):
                    mem = int(line.split()[1]) * 1024
        return cpu, os.cpu_count(), mem, self.tools.list_devices()

    def run(self, only):
        for name in RUN_ORDER:
            if name not in only:
                continue
            t = time.monotonic()
            log(f"section {name} ({self.elapsed():.0f} s elapsed, {self.left():.0f} s of budget left)")
            if name == "sweeps":
                # The adaptive sections share what the fixed ones left; the sweeps take the
                # larger part because their references are also the knobs' references.
                share = self.left() * (0.72 if "knobs" in only else 0.95)
                self.sections[name] = self.section_sweeps(max(share, 0.0))
            elif name == "knobs":
                self.sections[name] = self.section_knobs(max(self.left() * 0.95, 0.0))
            else:
                self.sections[name] = getattr(self, f"section_{name}")()
            self.section_seconds[name] = time.monotonic() - t

    def report(self, only, argv):
        cpu, cores, mem, devices = self.machine()
        commit = git("rev-parse", "HEAD")
        dirty = " (with uncommitted changes)" if git("status", "--porcelain", "--", "host", "kernels", "bench") else ""
        total = self.elapsed()
        timing = ", ".join(f"{n} {self.section_seconds[n]:.0f} s" for n in RUN_ORDER if n in self.section_seconds)
        head = [
            "# Performance\n",
            "Generated by `scripts/bench_suite.py` (`bash scripts/bench.sh` sets up, builds and runs it; "
            "`--update-docs` copies the report here and its plots to `docs/perf/`). **Every figure on this "
            "page comes from that one run on one machine.** The machines are shared and noisy: compare "
            "ratios within a table, not absolute numbers across runs.\n",
            "## Machine and run\n",
            f"- CPU: {cpu}, {cores} hardware threads, {fmt_bytes(mem)} RAM; {platform.system()} "
            f"{platform.release()}",
            "- OpenCL devices: " + "; ".join(f"[{i}] {d}" for i, d in devices),
            f"- Embree: {self.notes.get('embree', 'see bench_traversal')}",
            f"- git commit: `{commit[:12]}`{dirty}",
            f"- date: {datetime.datetime.now().strftime('%Y-%m-%d %H:%M')}",
            f"- mode: {'quick (smoke sizes)' if self.quick else 'full'}; budget {self.args.budget_minutes:g} min; "
            f"**total suite time {total / 60:.1f} min** ({timing}); {self.tools.count} renders",
            f"- command: `scripts/bench_suite.py {' '.join(shlex.quote(a) for a in argv)}`; every program call "
            "is in `commands.log` beside the report\n"]
        body = [self.sections[n] for n in SECTIONS if n in self.sections]
        missing = [n for n in SECTIONS if n not in only]
        if missing:
            body.append("Sections not run this time (`--only`): " + ", ".join(missing) + ".\n")
        return "\n".join(head) + "\n" + "\n".join(body)


def write_report(report, out_dir):
    """report.md in the results folder, its links to docs/ made relative to that folder."""
    docs = os.path.relpath(os.path.join(REPO, "docs"), out_dir)
    with open(os.path.join(out_dir, "report.md"), "w") as f:
        f.write(report.replace(DOCS_MARK, docs + "/"))


def update_docs(out_dir, plots, report):
    """docs/performance.md gets the report with plot links into docs/perf/."""
    perf = os.path.join(REPO, "docs", "perf")
    os.makedirs(perf, exist_ok=True)
    for p in plots:
        shutil.copy(os.path.join(out_dir, p), os.path.join(perf, p))
        report = report.replace(f"]({p})", f"](perf/{p})")
    with open(os.path.join(REPO, "docs", "performance.md"), "w") as f:
        f.write(report.replace(DOCS_MARK, ""))


def main(argv):
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0],
                                 formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("--build", default=os.path.join(REPO, "build"), help="build folder with archwave and bench/")
    ap.add_argument("--results", default=os.path.join(REPO, "results"),
                    help="results root: <timestamp>/ for this run, refs/ and meshes/ caches (default results/)")
    ap.add_argument("--budget-minutes", type=float, default=None,
                    help="time budget for the whole run (default 16; 1.5 with --quick)")
    ap.add_argument("--quick", action="store_true", help="smoke run: tiny sizes, about a minute")
    ap.add_argument("--only", default=",".join(SECTIONS), help="comma-separated sections: " + ",".join(SECTIONS))
    ap.add_argument("--device", type=int, default=0, help="OpenCL device for the wavefront renders")
    ap.add_argument("--ref-renderer", choices=("scalar", "wavefront"), default="scalar",
                    help="renderer for references (default scalar: the faster one on a CPU)")
    ap.add_argument("--update-docs", action="store_true",
                    help="copy the report to docs/performance.md and the plots to docs/perf/")
    args = ap.parse_args(argv)
    if args.budget_minutes is None:
        args.budget_minutes = 1.5 if args.quick else 16.0
    only = [s.strip() for s in args.only.split(",") if s.strip()]
    bad = [s for s in only if s not in SECTIONS]
    if bad:
        ap.error(f"unknown section(s) {', '.join(bad)}; choose from {', '.join(SECTIONS)}")
    if args.update_docs and (set(only) != set(SECTIONS) or args.quick):
        ap.error("--update-docs needs a full run of every section (no --quick, no --only)")
    suite = None
    try:
        suite = Suite(args)
        log(f"writing {suite.out}")
        suite.run(only)
        report = suite.report(only, argv)
    except SuiteError as e:
        where = f"\n(renders and commands.log kept in {suite.out})" if suite else ""
        print(f"bench_suite: {e}{where}", file=sys.stderr)
        return 1
    write_report(report, suite.out)
    shutil.rmtree(suite.work, ignore_errors=True)  # renders are scratch; refs and meshes are cached
    log(f"report: {os.path.join(suite.out, 'report.md')} ({suite.elapsed() / 60:.1f} min)")
    if args.update_docs:
        update_docs(suite.out, suite.plots, report)
        log("docs/performance.md and docs/perf/ updated")
    return 0


if __name__ == "__main__":
    sys.exit(main(sys.argv[1:]))

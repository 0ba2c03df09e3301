"""Section "The race" (issue 11): the same scenes rendered by archwave, Blender Cycles and
Mitsuba 3 (its multijitter and independent samplers), one after another on the same cores;
render time, RMSE and relMSE against one high-spp reference, time to equal error, error-vs-time
plots, and a check that each peer's converged image agrees with archwave's per image region
before its timing is trusted.

The peers get archwave's scenes through the exporters in bench/ (race_scene.py reads the
exportable subset; export_cycles.py runs inside Blender, export_mitsuba.py under a Python that
has Mitsuba). A peer that is not installed is skipped with a message; so is a scene that is
outside the subset."""

import json
import math
import os
import shutil
import subprocess
import sys
import time

import numpy as np

from . import REPO
from .errors import loglog_fit
from .exr import read_exr
from .plots import loglog_figure
from .scenes import BenchScene, scene_file, scene_size
from .tables import fmt, md_table
from .tools import SuiteError, log

sys.path.insert(0, os.path.join(REPO, "bench"))
import race_scene  # noqa: E402

EXPORT_CYCLES = os.path.join(REPO, "bench", "export_cycles.py")
EXPORT_MITSUBA = os.path.join(REPO, "bench", "export_mitsuba.py")
LLVM = "/usr/lib/x86_64-linux-gnu/libLLVM-19.so"
TOLERANCE = 0.005   # the issue's "within 0.5% per image region"
SIGMAS = 3.0        # a region disagrees when |difference| > TOLERANCE + SIGMAS * its standard error
GRID = 4            # regions: GRID x GRID blocks of the image
RATE_SCENE = "cornell"  # the scene of issue 12's target
ROUNDS = 3          # issue 12's samples/s: rounds of archwave and Mitsuba 3 in turn (run_rates)
LUMA = np.array([0.2126, 0.7152, 0.0722], np.float32)

# (key, title, scene file, width)
SCENES = [("cornell", "Cornell box (Lambert; quad and point light)", ("cornell.json",), 128),
          ("race_spheres", "glass, GGX and Lambert spheres under a quad light", ("bench", "race_spheres.json"), 160),
          ("race_small_light", "a small bright sphere light dominates (plus a dim quad light)",
           ("bench", "race_small_light.json"), 128)]


def setup(ctx):
    """(scenes, spp ladder, nominal spp, archwave reference spp wanted, its time cap (s),
    seconds for each peer's converged renders per scene)."""
    if ctx.quick:
        key, title, path, _ = SCENES[0]
        p = scene_file(*path)
        return [BenchScene(key, title, p, *scene_size(p, 32))], (4, 16), 16, 256, 10.0, 1.0
    scenes = [BenchScene(k, t, scene_file(*p), *scene_size(scene_file(*p), w)) for k, t, p, w in SCENES]
    return scenes, (4, 16, 64, 256), 64, 4096, 60.0, 24.0


# ---------------------------------------------------------------------------- the peers

def mitsuba_python():
    """The interpreter that has Mitsuba: $ARCHWAVE_MITSUBA_PYTHON, else the virtualenv
    scripts/install_peers.sh makes (build/peers-venv), else this one. (Set it to a Python
    without Mitsuba, e.g. /usr/bin/python3, to leave Mitsuba out.)"""
    env = os.environ.get("ARCHWAVE_MITSUBA_PYTHON")
    if env:
        return env
    venv = os.path.join(REPO, "build", "peers-venv", "bin", "python")
    return venv if os.access(venv, os.X_OK) else sys.executable


def mitsuba_env():
    env = dict(os.environ)
    if "DRJIT_LIBLLVM_PATH" not in env and os.path.exists(LLVM):
        env["DRJIT_LIBLLVM_PATH"] = LLVM
    return env


def blender():
    """The Blender binary: $ARCHWAVE_BLENDER (empty: none), else `blender` on the PATH."""
    path = os.environ.get("ARCHWAVE_BLENDER", "blender")
    return shutil.which(path) if path else None


def find_peers():
    """{name: None when usable, else the reason it is skipped}."""
    out = {}
    if blender():
        out["cycles"] = None
    else:
        out["cycles"] = "`blender` is not installed (scripts/install_peers.sh installs Debian's)"
    py = mitsuba_python()
    try:
        p = subprocess.run([py, "-c", "import mitsuba, drjit; mitsuba.set_variant('llvm_ad_rgb')"],
                           capture_output=True, text=True, env=mitsuba_env(), timeout=120)
        out["mitsuba"] = None if p.returncode == 0 else (
            f"Mitsuba 3 (`llvm_ad_rgb`) does not load under {py}: "
            + (p.stderr.strip().splitlines() or ["no message"])[-1][:300]
            + " (scripts/install_peers.sh installs it with libllvm19)")
    except (OSError, subprocess.TimeoutExpired) as e:
        out["mitsuba"] = f"Mitsuba 3 does not load under {py}: {e}"
    for name, why in out.items():
        if why:
            log(f"race: {name} skipped: {why}")
    return out


def peers(ctx):
    """find_peers(), once per run."""
    if "race_peers" not in ctx.notes:
        ctx.notes["race_peers"] = find_peers()
    return ctx.notes["race_peers"]


def allowance(ctx):
    """Minutes the race takes on the 2-core machine, by the peers it will run: what the
    adaptive sections leave to it and what the default budget adds for it."""
    n = sum(1 for why in peers(ctx).values() if why is None)
    # Issue 12's samples/s rounds (run_rates): about 13 s a round on the Cornell box, with Mitsuba.
    rates = rounds_wanted(ctx) * 13.0 / 60.0 if peers(ctx).get("mitsuba") is None else 0.0
    return ((0.1, 0.25, 0.4)[n] if ctx.quick else (1.5, 4.0, 6.0)[n]) + rates


# ---------------------------------------------------------------------------- images and errors

def load(path):
    return np.load(path).astype(np.float32) if path.endswith(".npy") else read_exr(path)


def errors(img, ref):
    """RMSE and relMSE over all pixels and channels, as build/bench/exr_compare computes them."""
    d = img.astype(np.float64) - ref.astype(np.float64)
    return float(np.sqrt(np.mean(d * d))), float(np.mean(d * d / (ref.astype(np.float64) ** 2 + 1e-2)))


def regions(h, w):
    return [(slice(i * h // GRID, (i + 1) * h // GRID), slice(j * w // GRID, (j + 1) * w // GRID))
            for i in range(GRID) for j in range(GRID)]


def agreement(img, var, ref, ref_var):
    """Per region: relative difference of the mean luminance of `img` against `ref`, and its
    standard error from the per-pixel variances `var`, `ref_var` of the two images (luminance);
    regions darker than 5% of the image mean are compared against that."""
    y, yr = img @ LUMA, ref @ LUMA
    floor = 0.05 * float(yr.mean())
    out = []
    for rs in regions(*yr.shape):
        n = yr[rs].size
        m, mr = float(y[rs].mean()), float(yr[rs].mean())
        den = max(mr, floor)
        sigma = math.sqrt(float(var[rs].sum() + ref_var[rs].sum())) / n / den
        out.append({"diff": (m - mr) / den, "sigma": sigma})
    return out


def verdict(regs):
    bad = [r for r in regs if abs(r["diff"]) > TOLERANCE + SIGMAS * r["sigma"]]
    worst = max(regs, key=lambda r: abs(r["diff"]))
    return {"agrees": not bad, "disagree": len(bad), "max_diff": worst["diff"], "max_diff_sigma": worst["sigma"],
            "max_sigma": max(r["sigma"] for r in regs),
            "unresolved": sum(1 for r in regs if SIGMAS * r["sigma"] > TOLERANCE)}


# ---------------------------------------------------------------------------- renderers

def run_archwave(ctx, scene, ladder, ref_want, ref_seconds):
    ctx.warm_up(scene.path, ladder[0], scene.defines)
    renders = [ctx.render_scene(scene, f"race_{scene.key}_aw_{spp}", spp) for spp in ladder]
    ref_exr, ref_meta = ctx.refs.within(scene, ref_want, ref_seconds)
    ref = read_exr(ref_exr)
    top = read_exr(renders[-1].exr)
    # The reference's own per-pixel variance, from the top ladder render's squared error
    # against it: e^2 = v/s + v/R (white noise; an upper estimate for stratified samplers).
    s, big_r = ladder[-1], ref_meta["spp"]
    ref_var = ((top - ref) @ LUMA) ** 2 * (s / big_r) / (1 + s / big_r)
    points = [{"spp": spp, "seconds": r.seconds, "wall": r.wall, "image": read_exr(r.exr)}
              for spp, r in zip(ladder, renders)]
    # The scalar path (host C++ from the same kernel headers, Embree rays, all cores): the same
    # numbers, so the same image per spp to rounding, at the host's speed. Reported beside the
    # wavefront, which stays the renderer the targets are judged on (the CLI's default).
    scalar = [ctx.render_scene(scene, f"race_{scene.key}_aws_{spp}", spp, scalar=True) for spp in ladder]
    scalar_points = [{"spp": spp, "seconds": r.seconds, "wall": r.wall, "image": read_exr(r.exr)}
                     for spp, r in zip(ladder, scalar)]
    out = {"points": points, "startup": _startup(renders[-1]), "ref": ref, "ref_var": ref_var,
           "ref_meta": ref_meta, "stats": renders[-1].stats,
           "scalar_points": scalar_points, "scalar_startup": _startup(scalar[-1])}
    # The device archwave picks itself (with no --device: the fastest CPU device it measured),
    # when it is not the suite's (PoCL by default, which the tables are defined on): issue 12's
    # target, samples/s against Mitsuba 3 on the Cornell box, is judged there.
    first = ctx.render_scene(scene, f"race_{scene.key}_awd_{ladder[0]}", ladder[0], device="")
    if first.stats["device"] != renders[0].stats["device"]:
        own = [first] + [ctx.render_scene(scene, f"race_{scene.key}_awd_{spp}", spp, device="") for spp in ladder[1:]]
        out["default_points"] = [{"spp": spp, "seconds": r.seconds, "wall": r.wall, "image": read_exr(r.exr)}
                                 for spp, r in zip(ladder, own)]
        out["default_startup"] = _startup(own[-1])
        out["default_device"] = own[-1].stats["device"]
    return out


def _startup(r):
    return {"kernel build": r.stats["compile_seconds"], "BVH build": r.stats.get("bvh_seconds"),
            "rest": r.wall - r.seconds - r.stats["compile_seconds"] - r.stats.get("bvh_seconds", 0),
            "process wall": r.wall}


def _peer_process(ctx, argv, env, result, label):
    """Runs a peer's exporter; its result JSON, or a SuiteError naming the failure."""
    t0 = time.monotonic()
    argv = argv + ["--t0", repr(time.time())]
    ctx.tools.run(argv, env=env)
    wall = time.monotonic() - t0
    with open(result) as f:
        res = json.load(f)
    res["process_wall"] = wall
    log(f"race: {label}: {wall:.1f} s")
    return res


def _converged(points, halves):
    """The spp-weighted mean of every render of a peer (they have independent seeds), and its
    per-pixel luminance variance estimated from the two equal halves `halves` (white-noise
    scaling to the total spp)."""
    total = sum(p["spp"] for p in points) + sum(h["spp"] for h in halves)
    img = sum(p["image"] * (p["spp"] / total) for p in points + halves)
    a, b = (h["image"] @ LUMA for h in halves)
    var_half = (a - b) ** 2 / 2.0  # one half's variance, per pixel
    return img, var_half * halves[0]["spp"] / total, total


def export_geometry(ctx, scene, work):
    """archwave's own triangles of the scene, for the exporters (host/scene/export_obj.h)."""
    path = os.path.join(work, "geometry.obj")
    argv = [ctx.tools.archwave, scene.path, "--export-geometry", path]
    for d in scene.defines:
        argv += ["-D", d]
    ctx.tools.run(argv)
    return path


def run_cycles(ctx, scene, ladder, check_seconds, work, geometry):
    out = os.path.join(work, "cycles")
    result = os.path.join(out, "result.json")
    jobs = [f"l{i}_{spp}:{spp}:{i + 1}" for i, spp in enumerate(ladder)]
    jobs += [f"c{k}:fit{check_seconds / 2:g}:{101 + k}" for k in range(2)]
    argv = [blender(), "-b", "--factory-startup", "--debug-cycles", "--python-exit-code", "3",
            "--python", EXPORT_CYCLES, "--", scene.path, "--out", out, "--result", result,
            "--width", str(scene.width), "--height", str(scene.height),
            "--geometry", geometry]
    for j in jobs:
        argv += ["--job", j]
    res = _peer_process(ctx, argv, None, result, f"cycles {scene.key}")
    imgs = {j["name"]: dict(j, image=read_exr(os.path.join(out, j["name"] + ".exr"))) for j in res["jobs"]}
    points = [imgs[j.split(":")[0]] for j in jobs[:len(ladder)]]
    conv, var, total = _converged(points, [imgs["c0"], imgs["c1"]])
    return {"cycles": {"points": points, "meta": res}}, (conv, var, total)


def _mitsuba_process(ctx, scene, out, geometry, jobs, label):
    """One Mitsuba 3 process (bench/export_mitsuba.py) rendering `jobs` of `scene` into `out`;
    its result JSON."""
    result = os.path.join(out, "result.json")
    argv = [mitsuba_python(), EXPORT_MITSUBA, scene.path, "--out", out, "--result", result,
            "--width", str(scene.width), "--height", str(scene.height),
            "--geometry", geometry]
    for j in jobs:
        argv += ["--job", j]
    return _peer_process(ctx, argv, mitsuba_env(), result, label)


def run_mitsuba(ctx, scene, ladder, check_seconds, work, geometry):
    out = os.path.join(work, "mitsuba")
    jobs = []
    for sampler in ("multijitter", "independent"):
        jobs += [f"{sampler}_{spp}:{sampler}:{spp}:{i + 1 + (50 if sampler == 'independent' else 0)}"
                 for i, spp in enumerate(ladder)]
    jobs += [f"c{k}:multijitter:fit{check_seconds / 2:g}:{201 + k}" for k in range(2)]
    res = _mitsuba_process(ctx, scene, out, geometry, jobs, f"mitsuba {scene.key}")
    imgs = {j["name"]: dict(j, image=np.load(os.path.join(out, j["name"] + ".npy"))) for j in res["jobs"]}
    rows = {}
    for sampler in ("multijitter", "independent"):
        rows[f"mitsuba_{sampler}"] = {"points": [imgs[f"{sampler}_{spp}"] for spp in ladder], "meta": res}
    every = rows["mitsuba_multijitter"]["points"] + rows["mitsuba_independent"]["points"]
    conv, var, total = _converged(every, [imgs["c0"], imgs["c1"]])
    return rows, (conv, var, total)


def rounds_wanted(ctx):
    """Rounds of issue 12's samples/s measurement: $ARCHWAVE_RACE_ROUNDS, else 3 (1 with --quick)."""
    env = os.environ.get("ARCHWAVE_RACE_ROUNDS")
    if env is None:
        return 1 if ctx.quick else ROUNDS
    try:
        n = int(env)
    except ValueError:
        n = -1
    if n < 0 or n > 50:
        raise SuiteError(f"ARCHWAVE_RACE_ROUNDS={env!r}: expected a whole number of rounds from 0 to 50")
    return n


def run_rates(ctx, scene, spp, device, work, geometry, rounds):
    """Issue 12's samples/s on `scene` at `spp`: `rounds` rounds, each archwave's render on
    `device` ("" its own pick, None the suite's) and then one Mitsuba 3 process rendering the
    same spp with each sampler (after its untimed warm-ups). Interleaved so that a machine
    whose speed drifts (these are shared) slows both sides of a round alike; each side's
    figure is the median over the rounds, and the ratio is also taken round by round.
    {row: [Msamples/s per round]}."""
    mega = scene.width * scene.height * spp / 1e6
    out = {"archwave": [], "mitsuba_multijitter": [], "mitsuba_independent": []}
    for k in range(rounds):
        r = ctx.render_scene(scene, f"race_{scene.key}_rate{k}", spp, device=device)
        out["archwave"].append(mega / r.seconds)
        jobs = [f"{sampler}_{spp}:{sampler}:{spp}:{301 + 10 * k + i}"
                for i, sampler in enumerate(("multijitter", "independent"))]
        res = _mitsuba_process(ctx, scene, os.path.join(work, f"mitsuba_rate{k}"), geometry, jobs,
                               f"mitsuba {scene.key} rate round {k + 1}")
        for j in res["jobs"]:
            out["mitsuba_" + j["name"].split("_")[0]].append(mega / j["seconds"])
    log("race: samples/s rounds: " + "; ".join(f"{n} " + ", ".join(f"{v:.3g}" for v in vs) for n, vs in out.items()))
    return out


# ---------------------------------------------------------------------------- measuring

def time_to(points, key, goal):
    """Seconds at which error `key` reaches `goal`: log-log interpolation between the two
    renders that bracket it, or extrapolation along the nearest two (flagged)."""
    t = np.array([p["seconds"] for p in points], float)
    e = np.array([p[key] for p in points], float)
    if len(t) < 2 or goal <= 0 or np.any(t <= 0) or np.any(e <= 0):
        return float("nan"), False
    lt, le, lg = np.log(t), np.log(e), math.log(goal)
    for i in range(len(t) - 1):
        lo, hi = sorted((le[i], le[i + 1]))
        if lo <= lg <= hi and le[i] != le[i + 1]:
            f = (lg - le[i]) / (le[i + 1] - le[i])
            return float(math.exp(lt[i] + f * (lt[i + 1] - lt[i]))), False
    i = 0 if lg > le[0] else len(t) - 2
    if le[i] == le[i + 1]:
        return float("nan"), True
    slope = (le[i + 1] - le[i]) / (lt[i + 1] - lt[i])
    return float(math.exp(lt[i] + (lg - le[i]) / slope)), True


def _failure(e):
    """A failed peer run in one line: the message's first line and its stderr's last three."""
    text = str(e).strip() or type(e).__name__
    head, _, err = text.partition("\nstderr:\n")
    tail = [ln.strip() for ln in err.splitlines() if ln.strip()][-3:]
    return (head.splitlines()[0] + (": " + " / ".join(tail) if tail else "")
            + " (the command is in commands.log)")[:500]


def measure_scene(ctx, scene, peers, ladder, nominal, ref_want, ref_seconds, check_seconds, rounds):
    try:
        race_scene.describe(scene.path, scene.width, scene.height)
    except race_scene.Unsupported as e:
        log(f"race: {scene.key}: not exported: {e}")
        return {"scene": scene, "skipped": str(e)}
    work = os.path.join(ctx.work, "race", scene.key)
    os.makedirs(work, exist_ok=True)
    log(f"race: {scene.key}: archwave")
    aw = run_archwave(ctx, scene, ladder, ref_want, ref_seconds)
    geometry = export_geometry(ctx, scene, work)
    rows = {"archwave": {"points": aw["points"], "meta": {"startup": aw["startup"]}},
            "archwave_scalar": {"points": aw["scalar_points"], "meta": {"startup": aw["scalar_startup"]}}}
    if "default_points" in aw:
        rows["archwave_default"] = {"points": aw["default_points"],
                                    "meta": {"startup": aw["default_startup"], "device": aw["default_device"]}}
    checks, failures = {}, {}
    for name, runner in (("cycles", run_cycles), ("mitsuba", run_mitsuba)):
        if peers.get(name):
            continue
        try:
            got, (conv, var, total) = runner(ctx, scene, ladder, check_seconds, work, geometry)
        except Exception as e:  # noqa: BLE001 -- a peer that fails is reported, never fatal to the suite
            failures[name] = _failure(e)
            log(f"race: {name} failed on {scene.key}: {failures[name]}")
            continue
        rows.update(got)
        mean = (conv.reshape(-1, 3).mean(0) / aw["ref"].reshape(-1, 3).mean(0) - 1.0).tolist()
        regs = agreement(conv, var, aw["ref"], aw["ref_var"])
        checks[name] = dict(verdict(regs), spp=total, mean=mean, regions=regs,
                            rmse=errors(conv, aw["ref"])[0])
    rates = None
    if rounds and scene.key == RATE_SCENE and peers.get("mitsuba") is None and "mitsuba" not in failures:
        device = "" if "archwave_default" in rows else None
        try:
            rates = run_rates(ctx, scene, ladder[-1], device, work, geometry, rounds)
        except Exception as e:  # noqa: BLE001 -- as a peer's failure above: reported, not fatal
            failures["mitsuba (samples/s rounds)"] = _failure(e)
            log(f"race: samples/s rounds failed: {failures['mitsuba (samples/s rounds)']}")
    for name, row in rows.items():
        for p in row["points"]:
            p["rmse"], p["relmse"] = errors(p["image"], aw["ref"])
            del p["image"]
    base = {p["spp"]: p for p in rows["archwave"]["points"]}[nominal]
    goals = {"rmse": base["rmse"], "relmse": base["relmse"]}
    for name, row in rows.items():
        row["to"] = {k: time_to(row["points"], k, g) for k, g in goals.items()}
    return {"scene": scene, "rows": rows, "checks": checks, "failures": failures, "goals": goals,
            "ref": aw["ref_meta"], "nominal": nominal, "ladder": ladder, "rates": rates}


def measure(ctx):
    scenes, ladder, nominal, ref_want, ref_seconds, check_seconds = setup(ctx)
    found = peers(ctx)
    rounds = rounds_wanted(ctx)
    results = [measure_scene(ctx, sc, found, ladder, nominal, ref_want, ref_seconds, check_seconds, rounds)
               for sc in scenes]
    return {"peers": found, "scenes": results, "ladder": ladder, "nominal": nominal}


# ---------------------------------------------------------------------------- the report

LABELS = {"archwave": "archwave (wavefront)", "archwave_scalar": "archwave (scalar path: host C++, Embree rays)",
          "cycles": "Cycles", "mitsuba_multijitter": "Mitsuba 3, multijitter",
          "mitsuba_independent": "Mitsuba 3, independent"}
PEER_OF = {"cycles": "cycles", "mitsuba_multijitter": "mitsuba", "mitsuba_independent": "mitsuba"}


def _label(name, row):
    meta = row["meta"]
    if name == "cycles":
        return f"Cycles {meta['version']} ({meta['sampling_pattern'].lower().replace('_', ' ')})"
    if name.startswith("mitsuba"):
        return f"Mitsuba {meta['version']} `{meta['variant']}`, {name.split('_', 1)[1]}"
    if name == "archwave_default":
        return f"archwave (wavefront) on the device it picks: {meta['device']}"
    return LABELS[name]


def _trusted(res, name):
    peer = PEER_OF.get(name)
    return peer is None or res["checks"].get(peer, {}).get("agrees", False)


def main_table(res):
    nominal, goals = res["nominal"], res["goals"]
    aw = res["rows"]["archwave"]["to"]
    rows = []
    for name, row in res["rows"].items():
        p = {q["spp"]: q for q in row["points"]}[nominal]
        cells = [_label(name, row) + ("" if _trusted(res, name) else " (**converged image disagrees**)"),
                 fmt(p["seconds"]), fmt(p["rmse"]), fmt(p["relmse"])]
        for k in ("rmse", "relmse"):
            t, extrap = row["to"][k]
            cells += [(fmt(t) + (" (extrap.)" if extrap else "")) if math.isfinite(t) else "–",
                      fmt(aw[k][0] / t, 3) if math.isfinite(t) and math.isfinite(aw[k][0]) else "–"]
        rows.append(cells)
    return md_table(["renderer", f"render time at {nominal} spp (s)", "RMSE", "relMSE",
                     f"time to RMSE {fmt(goals['rmse'])} (s)", "archwave's time ÷ this",
                     f"time to relMSE {fmt(goals['relmse'])} (s)", "archwave's time ÷ this"], rows)


def check_table(res):
    rows = []
    for peer, c in res["checks"].items():
        rows.append([peer, c["spp"], " / ".join(f"{100 * m:+.2f}%" for m in c["mean"]),
                     f"{100 * c['max_diff']:+.2f}% ± {100 * c['max_diff_sigma']:.2f}%",
                     f"{100 * c['max_sigma']:.2f}%", c["unresolved"], c["disagree"],
                     "agrees" if c["agrees"] else "**disagrees**"])
    return md_table(["peer", "its spp (all renders)", "mean R / G / B vs archwave", "largest region difference ± σ",
                     "largest σ", f"regions with {SIGMAS:g}σ > {100 * TOLERANCE:g}%", "regions outside", "verdict"],
                    rows)


def _startup_cells(name, row):
    meta = row["meta"]
    s = meta["startup"]
    if name.startswith("archwave"):
        return [f"kernel build {fmt(s['kernel build'])} (after a warm-up render), BVH build {fmt(s['BVH build'])}, "
                f"rest of the process {fmt(s['rest'])}", fmt(s["process wall"])]
    if name == "cycles":
        w = meta["warmup"]
        return [f"Blender start {fmt(s['blender_start'])}, scene build (Python) {fmt(s['scene_build'])}, "
                f"1-spp warm-up {fmt(w['wall'])}", fmt(meta["process_wall"])]
    warm = [w for w in meta["warmups"] if w["sampler"] == name.split("_", 1)[1]]
    return [f"interpreter {fmt(s['python_start'])}, import {fmt(s['import'])}, variant {fmt(s['variant'])}, "
            f"scene build {fmt(s['scene_build'])}, warm-up render {fmt(warm[0]['wall'] if warm else None)} "
            f"(JIT compilation {fmt(warm[0]['compile'] if warm else None)})", fmt(meta["process_wall"])]


def overhead_table(res):
    rows = []
    for name, row in res["rows"].items():
        top = row["points"][-1]
        extra = ""
        if name == "cycles":
            extra = f"; render call {fmt(top['wall'])} s, Cycles total {fmt(top['total'])} s"
        elif name.startswith("mitsuba"):
            extra = f"; JIT in the timed render {fmt(top['compile'])} s"
        rows.append([_label(name, row), top["spp"], fmt(top["seconds"]) + extra] + _startup_cells(name, row))
    return md_table(["renderer", "spp", "render time (s)", "outside the render time (s)", "whole process(es) (s)"],
                    rows)


def plot(ctx, res):
    sc = res["scene"]
    series = {k: [] for k in ("rmse", "relmse")}
    for name, row in res["rows"].items():
        t = [p["seconds"] for p in row["points"]]
        for k in series:
            e = [p[k] for p in row["points"]]
            series[k].append((_label(name, row).replace("`", ""), t, e, *loglog_fit(t, e)))
    name = f"race_{sc.key}.png"
    loglog_figure(ctx.png(name), [("render time (s)", "RMSE", series["rmse"], -0.5),
                                  ("render time (s)", "relMSE", series["relmse"], -1.0)],
                  f"The race: {sc.title} ({sc.width}x{sc.height}); error vs render time")
    return name


def target_line(scenes, row="archwave", what_aw=None):
    """Issue 11's target (archwave's time to equal error at most Cycles') and ambition (at
    most the better Mitsuba sampler's), over the scenes that ran, from the main tables; for
    archwave's row `row` (the wavefront: the renderer the targets are judged on)."""
    def ratio(res, peer, k):
        t_aw = res["rows"][row]["to"][k][0]
        ts = [row["to"][k][0] for name, row in res["rows"].items() if name.startswith(peer) and _trusted(res, name)]
        ts = [t for t in ts if math.isfinite(t)]
        return t_aw / min(ts) if ts and math.isfinite(t_aw) else None
    out = []
    pairs = (("cycles", "Target: at most Cycles'"), ("mitsuba", "Ambition: at most Mitsuba 3's (best sampler)"))
    if what_aw:
        pairs = tuple((p, f"{what_aw}: at most {w.split('at most ', 1)[1]}") for p, w in pairs)
    for peer, what in pairs:
        vals = [(res["scene"].key, k, ratio(res, peer, k)) for res in scenes if "rows" in res
                for k in ("rmse", "relmse")]
        known = [v for v in vals if v[2] is not None]
        if not known:
            out.append(f"- {what} time to equal RMSE and relMSE: not measured ({peer} did not run or was not trusted).")
            continue
        met = all(v[2] <= 1.0 for v in known) and len(known) == len(vals)
        out.append(f"- {what} time to equal RMSE and relMSE on every race scene: **{'met' if met else 'not met'}** "
                   "(archwave's time ÷ the peer's: " + ", ".join(f"{s} {k} {fmt(r, 3)}" for s, k, r in known) + ").")
    return "\n".join(out) + "\n"


def samples_line(scenes, key="cornell"):
    """Issue 12's target: on the fastest CPU device (the one archwave picks with no --device),
    samples/s on the Cornell box at least Mitsuba 3's `llvm_ad_rgb` (its faster sampler), at the
    ladder's top spp, in this run: from the interleaved rounds of run_rates where they ran, else
    from the ladder's one render each."""
    res = next((r for r in scenes if r["scene"].key == key and "rows" in r), None)
    if res is None:
        return "- Issue 12 (samples/s on the Cornell box): not measured (the scene did not run).\n"
    sc = res["scene"]
    name = "archwave_default" if "archwave_default" in res["rows"] else "archwave"

    def rate(row):
        top = max(row["points"], key=lambda p: p["spp"])
        return top["spp"] * sc.width * sc.height / top["seconds"] / 1e6
    aw_row = res["rows"][name]
    top_spp = max(p["spp"] for p in aw_row["points"])
    where = aw_row["meta"].get("device") or "the suite's device"
    peers = {n: rate(r) for n, r in res["rows"].items() if n.startswith("mitsuba") and _trusted(res, n)}
    if not peers:
        return (f"- Issue 12 (samples/s on the Cornell box): archwave {fmt(rate(aw_row), 3)} Msamples/s on {where}; "
                "Mitsuba 3 did not run or was not trusted.\n")
    rates = res.get("rates")
    if rates and rates["archwave"] and all(rates.get(n) for n in peers):
        # The interleaved rounds (run_rates): medians, and the verdict on the median of the
        # rounds' own ratios, so a round the machine slowed down counts once, on both sides.
        med = {n: float(np.median(v)) for n, v in rates.items() if v}
        best = max(peers, key=lambda n: med[n])
        ratios = [a / m for a, m in zip(rates["archwave"], rates[best])]
        r = float(np.median(ratios))
        spread = lambda v: f"{fmt(float(np.median(v)), 3)} ({fmt(min(v), 3)}–{fmt(max(v), 3)})"
        return (f"- Issue 12: samples/s on the Cornell box at {top_spp} spp, archwave on {where} at least Mitsuba 3's, "
                f"median of {len(ratios)} interleaved rounds: **{'met' if r >= 1.0 else 'not met'}** "
                f"(archwave {spread(rates['archwave'])} Msamples/s, {_label(best, res['rows'][best])} "
                f"{spread(rates[best])}; archwave ÷ Mitsuba per round "
                f"{', '.join(fmt(x, 3) for x in ratios)}: median **{fmt(r, 3)}×**; ambition 2×).\n")
    best = max(peers, key=peers.get)
    r = rate(aw_row) / peers[best]
    return (f"- Issue 12: samples/s on the Cornell box at the top spp, archwave on {where} at least Mitsuba 3's: "
            f"**{'met' if r >= 1.0 else 'not met'}** (archwave {fmt(rate(aw_row), 3)} Msamples/s, "
            f"{_label(best, res['rows'][best])} {fmt(peers[best], 3)}: {fmt(r, 3)}×; ambition 2×).\n")


CAPTION = (
    "Each scene is rendered by archwave and by the peers that are installed, one renderer after "
    "another on the same cores, at {ladder} spp (independent seeds). Errors are against one reference, "
    "archwave's high-spp render of the scene with another seed (the sweeps' reference cache); RMSE over all "
    "pixels and channels, relMSE dividing each squared error by (reference² + 0.01), as in the sweeps. "
    "**Time to equal error** is where a renderer's error-vs-time curve, interpolated in log–log between "
    "its two renders that bracket it (extrapolated along the nearest two when none does), reaches "
    "archwave's error at {nominal} spp. Render time: archwave, the stats' render time (kernel build, with "
    "a warm PoCL cache, and BVH build excluded); Cycles, its own \"render time without synchronization\" "
    "(path tracing; Blender start-up, the Blender-to-Cycles sync and the scene's device update — BVH, "
    "shaders, light tables — excluded), after an untimed 1-spp warm-up render in the same process; "
    "Mitsuba, the wall time of `mi.render` until the image is in memory (the integrator is traced "
    "again each call), after an untimed warm-up render of the same sampler in the same process, "
    "minus any kernel compilation Dr.Jit's kernel history reports inside it. What lies outside "
    "these times is in the last table.\n")

CHECK_CAPTION = (
    "Before a peer's timing is trusted its converged image — the spp-weighted mean of all its renders "
    "of the scene (the ladder and two equal renders with their own seeds) — is compared with "
    "archwave's reference in {grid}×{grid} regions: the relative difference of each region's mean "
    "luminance (regions darker than 5% of the image mean are compared against that), with a "
    "standard error σ from the per-pixel variances (the peer's from its two equal renders, "
    "archwave's from its top ladder render against the reference; white-noise scaling). A region "
    "disagrees when |difference| > {tol:g}% + {k:g}σ; the table also counts the regions where {k:g}σ "
    "alone exceeds {tol:g}%, where the check cannot resolve {tol:g}%. A disagreeing peer's rows are "
    "marked in the table above and left out of the target lines.\n")

SETTINGS = (
    "Settings: archwave's scene file as it is (`render.sampler` its default); Cycles: CPU, all cores, "
    "box pixel filter of width 1, adaptive sampling, denoising, clamping and glossy filtering off, "
    "caustics on, max bounces = max_depth − 1 (Cycles counts bounces after the first hit); Mitsuba: "
    "`path` integrator with max_depth + 1 (it counts path segments), Russian roulette its default, box "
    "filter of radius 0.5. The exporters and the conventions they translate are described in "
    "`bench/export_cycles.py` and `bench/export_mitsuba.py`.\n")


def render_scene(ctx, res, peers):
    sc = res["scene"]
    md = [f"### {sc.title} (`{sc.rel_path()}`, {sc.width}x{sc.height})\n"]
    if "skipped" in res:
        return md + [f"Not raced: the scene is outside the exported subset: {res['skipped']}\n"]
    md += [main_table(res), f"![race {sc.key}]({plot(ctx, res)})\n"]
    if res["checks"]:
        md += ["Converged images against archwave's reference:\n", check_table(res)]
    for peer, msg in res["failures"].items():
        md.append(f"{peer}: **failed**: {msg}\n")
    ref = res["ref"]
    md += [f"Reference: archwave {ref['renderer']}, {ref['spp']} spp, seed {ref['seed']} "
           f"({'from the cache' if ref.get('reused') else 'rendered in this run'}).\n",
           "Time outside the render times above (top-spp render; start-up once per scene and process):\n",
           overhead_table(res)]
    return md


def render(ctx, data):
    ladder = ", ".join(str(s) for s in data["ladder"])
    md = ["## The race: archwave, Cycles and Mitsuba 3\n",
          CAPTION.format(ladder=ladder, nominal=data["nominal"]),
          CHECK_CAPTION.format(grid=GRID, tol=100 * TOLERANCE, k=SIGMAS), SETTINGS]
    skipped = [f"{name}: {why}" for name, why in data["peers"].items() if why]
    if skipped:
        md.append("**Peers skipped:** " + "; ".join(skipped) + ".\n")
    md.append(target_line(data["scenes"]))
    md.append("For information, the same with archwave's scalar path (the cross-check renderer: the same "
              "kernel headers compiled for the host, Embree rays, all cores; not the CLI's default):\n")
    md.append(target_line(data["scenes"], row="archwave_scalar", what_aw="Scalar path"))
    md.append(samples_line(data["scenes"]))
    for res in data["scenes"]:
        md += render_scene(ctx, res, data["peers"])
    return "\n".join(md)

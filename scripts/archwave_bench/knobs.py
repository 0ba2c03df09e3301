"""Section "Knob sweeps at equal time": lobe splitting, trace depth, cut-off, Russian
roulette and the sampler, each setting's error at a common render time T and its time to a
common error."""

import json
import math
import re
import time

import numpy as np

from . import REF_FACTOR
from .errors import ErrorModel, shared_floor
from .plots import loglog_figure
from .tables import fmt, md_table
from .tools import log

CORNELL = [("default (max_depth 8, cutoff 0.001, RR from bounce 4)", [], "unbiased"),
           ("max_depth 1 (direct light only)", ["render.max_depth=1"], "biased: shorter paths"),
           ("max_depth 2", ["render.max_depth=2"], "biased: shorter paths"),
           ("max_depth 4", ["render.max_depth=4"], "biased: shorter paths"),
           ("max_depth 16", ["render.max_depth=16"], "another image: longer paths"),
           ("cutoff 0", ["render.cutoff=0"], "unbiased"),
           ("cutoff 0.01", ["render.cutoff=0.01"], "unbiased"),
           ("cutoff 0.1", ["render.cutoff=0.1"], "unbiased"),
           ("Russian roulette off (rr_depth 1000)", ["render.rr_depth=1000"], "unbiased"),
           ("Russian roulette from bounce 1", ["render.rr_depth=1"], "unbiased"),
           ("sampler independent (white noise instead of Sobol')", ["render.sampler=independent"], "unbiased"),
           ("sampler zsobol (Sobol' in blue-noise pixel order)", ["render.sampler=zsobol"], "unbiased")]


def splitting_settings(path):
    """Lobe splitting on and off at a fixed split count, for the scene at `path`."""
    with open(path) as f:
        mats = json.load(f).get("materials", {})

    def samples(n):
        return [f"materials.{m}.{lobe}.samples={n}" for m in mats for lobe in ("reflection", "refraction")]

    def split(n, on=True):
        # samples = n * spp gives n rays per glossy lobe at the first hit (max(1,
        # round(samples / spp)), docs/material.md §6) whatever spp the equal-time search picks.
        return lambda spp: samples(n * spp) + ([] if on else ["render.lobe_splitting=false"])
    return [("default (the scene's lobe samples; below spp: no split)", [], "unbiased"),
            ("samples = 4·spp: 4 rays per glossy lobe at the first hit", split(4), "unbiased"),
            ("samples = 4·spp, lobe_splitting false", split(4, on=False), "unbiased"),
            ("samples = 16·spp: 16 rays per glossy lobe", split(16), "unbiased"),
            ("sampler independent (white noise instead of Sobol')", ["render.sampler=independent"], "unbiased"),
            ("sampler zsobol (Sobol' in blue-noise pixel order)", ["render.sampler=zsobol"], "unbiased")]


def knob_settings(ctx):
    """[(scene key, [(name, defines or defines(spp), kind)])]; kind "unbiased" converges to
    the default's image."""
    glossy = splitting_settings(ctx.scenes["glossy"].path)
    if ctx.quick:
        return [("cornell", [CORNELL[0], CORNELL[2], CORNELL[8]]), ("glossy", glossy[:3])]
    # The issue's own ask: the documentation's glossy example, splitting on and off.
    docs = splitting_settings(ctx.scenes["docs_glossy"].path)
    return [("cornell", CORNELL), ("glossy", glossy), ("docs_glossy", docs)]


def knob_setting(ctx, scene, index, defines, target, per_spp_guess):
    """One setting at about T/16 (the calibration), T/4 and T seconds of render time: the
    points of its error-vs-time curve, the last one being the equal-time render."""
    tag = f"knob_{scene.key}_{index}"
    done = {}

    def at(spp):
        if spp not in done:
            defs = scene.defines + (defines(spp) if callable(defines) else list(defines))
            done[spp] = ctx.render(scene.path, f"{tag}_{spp}", spp, scene.width, scene.height, defines=defs)
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


def equal_time(ctx, probe, share, count):
    """T for `count` settings in `share` seconds: a setting costs about (1 + 1/4 + 1/16) T plus
    four processes' overhead; 15% of the share stays for a reference when the sweeps did not
    leave one."""
    target = max(0.05, (share * 0.85 / count - 4 * probe.overhead) / 1.4)
    return min(target, 0.3) if ctx.quick else target


def fit_settings(runs, errors, target):
    """Each setting's ErrorModel; the unbiased ones share the reference's noise as floor."""
    measured = [(name, kind, rs, np.array([r.seconds for r in rs]), np.array([e ** 2 for e in errs]))
                for (name, kind, rs), errs in zip(runs, errors)]
    floor = shared_floor([([r.stats["spp"] for r in rs], mse) for _, kind, rs, _, mse in measured
                          if kind == "unbiased"])
    fits = []
    for name, kind, rs, t, mse in measured:
        model = ErrorModel([r.stats["spp"] for r in rs], t, mse, floor if kind == "unbiased" else None)
        nearest = int(np.argmin(np.abs(np.log(t / target))))
        fits.append({"name": name, "kind": kind, "runs": rs, "t": t, "mse": mse, "b": model.b,
                     "model": model, "nearest": rs[nearest], "rmse_nearest": math.sqrt(mse[nearest]),
                     "rmse_T": model.rmse_at_time(target)})
    goal = fits[0]["rmse_T"]
    for f in fits:
        f["t_goal"] = f["model"].time_to_rmse(goal)
    return fits, goal


def measure_scene(ctx, scene, opts, probe, share):
    target = equal_time(ctx, probe, share, len(opts))
    log(f"knobs: {scene.key}: {len(opts)} settings, T = {target:.2f} s")
    runs = [(name, kind, knob_setting(ctx, scene, i, defines, target, probe.seconds / 4))
            for i, (name, defines, kind) in enumerate(opts)]
    top = max(r.stats["spp"] for _, _, rs in runs for r in rs)
    ref_exr, ref_meta = ctx.refs.within(scene, REF_FACTOR * 2 ** math.ceil(math.log2(top)), share * 0.15)
    errors = [[ctx.tools.compare(r.exr, ref_exr)["rmse"] for r in rs] for _, _, rs in runs]
    fits, goal = fit_settings(runs, errors, target)
    return {"scene": scene, "target": target, "fits": fits, "goal": goal, "ref": ref_meta}


def measure(ctx, budget):
    """Each scene's settings get their share of what is left of the budget."""
    settings = knob_settings(ctx)
    left_settings = sum(len(s) for _, s in settings)
    t_start = time.monotonic()
    scenes = []
    for scene_key, opts in settings:
        scene = ctx.scenes[scene_key]
        ctx.warm_up(scene.path, 4, scene.defines)
        probe = ctx.render_scene(scene, f"knob_{scene.key}_probe", 4)
        share = (budget - (time.monotonic() - t_start)) * len(opts) / left_settings
        left_settings -= len(opts)
        scenes.append(measure_scene(ctx, scene, opts, probe, share))
    return scenes


CAPTION = [
    "Each setting is rendered at the spp that takes a common render time T (the spp comes from "
    "a calibration render at about T/16), and at a quarter of that spp. Through each setting's "
    "points the suite fits MSE(spp) = a/spp + b (a: its noise; b: what more samples do not "
    "remove — bias against the reference and the reference's own noise) and time(spp) = "
    "c0 + c1·spp, with relative residuals. Settings that converge to the reference's image "
    "(\"unbiased\") share one b, the reference's noise, fitted jointly over all their points; "
    "the others get their own. **Error at equal time** is that fit's RMSE at exactly T; the render nearest T "
    "and its measured RMSE are shown too. **Time to equal error** is the time at which the fit "
    "reaches E = the default setting's RMSE at T; \"never\" when b alone exceeds E². Errors are "
    "against the reference of the **default** settings, so a setting that changes the converged "
    "image (max_depth below the default ends paths early; max_depth 16 adds longer paths the "
    "reference lacks) shows the difference in its floor √b.\n",
    "**AO samples: not available: AO is not implemented yet.**\n",
]


def setting_table(res):
    fits, goal = res["fits"], res["goal"]
    base = fits[0]
    rows = []
    for f in fits:
        finite = math.isfinite(f["t_goal"]) and math.isfinite(base["t_goal"])
        rows.append([f["name"], f["kind"], f["nearest"].stats["spp"], fmt(f["nearest"].seconds),
                     fmt(f["rmse_nearest"]), fmt(f["rmse_T"]), fmt(f["rmse_T"] / goal, 3),
                     fmt(math.sqrt(f["b"])), fmt(f["t_goal"]) if math.isfinite(f["t_goal"]) else "never",
                     fmt(f["t_goal"] / base["t_goal"], 3) if finite else "–"])
    return md_table(["setting", "converges to", "spp nearest T", "its time (s)", "its RMSE",
                     "RMSE at T (fit)", "× default", "floor √b", f"time to RMSE {fmt(goal)} (s)",
                     "× default"], rows)


def plot(ctx, res):
    key, scene = res["scene"].key, res["scene"]
    curves = [(f["name"].split(" (")[0], f["t"], np.sqrt(f["mse"]), float("nan"), 0.0) for f in res["fits"]]
    name = f"knobs_{key}.png"
    loglog_figure(ctx.png(name), [("render time (s)", "RMSE vs default reference", curves, -0.5)],
                  f"{scene.title}: error vs time per setting")
    return name


def splitting_summary(fits):
    """Which renders at T split (the stats name the 'split' kernel feature when some lobe gets
    more than one ray), and the 4-ray setting against the same samples with splitting off."""
    split = [f["name"] for f in fits if re.search(r"\bsplit\b", f["nearest"].stats["kernel_features"])]
    text = ("Lobe splitting (docs/material.md §6) traces max(1, round(samples / spp)) rays per glossy lobe at "
            "the first hit, so it acts only while a lobe's `samples` exceeds spp; the settings above set "
            "samples = n·spp to hold n fixed across the equal-time search. Renders at T that split: "
            + (", ".join(split) if split else "none") + ". ")
    on = next((f for f in fits if f["name"].startswith("samples = 4·spp:")), None)
    off = next((f for f in fits if "lobe_splitting false" in f["name"]), None)
    if on and off and math.isfinite(on["t_goal"]) and math.isfinite(off["t_goal"]):
        text += (f"4-way splitting on vs off at equal time: RMSE × {fmt(on['rmse_T'] / off['rmse_T'], 3)}, "
                 f"time to the default's error × {fmt(on['t_goal'] / off['t_goal'], 3)} (on / off).")
    return text + "\n"


def render_scene(ctx, res):
    scene, ref = res["scene"], res["ref"]
    md = [f"### {scene.title} (`{scene.rel_path()}`, {scene.width}x{scene.height}, T = {fmt(res['target'])} s)\n",
          setting_table(res),
          f"![{scene.key} knobs]({plot(ctx, res)})\n",
          f"Reference: {ref['spp']} spp, seed {ref['seed']}, {ref['renderer']} "
          f"({'from the cache' if ref.get('reused') else 'rendered in this run'}).\n"]
    if scene.key in ("glossy", "docs_glossy"):
        md.append(splitting_summary(res["fits"]))
    return md


def render(ctx, scenes):
    md = ["## Knob sweeps at equal time\n"] + CAPTION
    for res in scenes:
        md += render_scene(ctx, res)
    return "\n".join(md)

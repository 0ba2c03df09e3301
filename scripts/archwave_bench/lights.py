"""Section "Lights" (issue 13): light selection from 1 to 10,000 lights (tree against power),
environment-map importance sampling against uniform sampling, and the material's ambient
occlusion against GI, each at equal time or with its time beside its error."""

import json
import math
import os

import numpy as np

from . import REPO
from .errors import loglog_fit
from .exr import read_exr
from .plots import loglog_figure
from .tables import fmt, md_table, rate

FLOOR = {"shape": "quad", "corner": [-50, 0, 50], "edge_u": [100, 0, 0], "edge_v": [0, 0, -100], "material": "white"}
WHITE = {"white": {"diffuse": {"color": [1, 1, 1]}, "reflection": {"weight": 0}}}


def grid_scene(path, k, side=4.0, h=1.0, r=0.015, total=40.0):
    """k x k sphere lights of radius r over a side x side square at height h, the same total
    power whatever k, above a white floor seen at one point P by a narrow camera (as in
    tests/render/test_many_lights.cpp). Returns the exact radiance of P: E / pi with
    E = sum pi L (r/d)^2 (h/d)."""
    n = k * k
    L = total / (n * math.pi * 4 * math.pi * r * r)  # radiance giving each light total/n of power
    lights, e = [], 0.0
    for i in range(k):
        for j in range(k):
            x = -side / 2 + side * (i + 0.5) / k
            z = -side / 2 + side * (j + 0.5) / k
            lights.append({"type": "sphere", "center": [x, h, z], "radius": r, "intensity": L})
            d2 = x * x + h * h + z * z
            e += math.pi * L * (r * r / d2) * (h / math.sqrt(d2))
    scene = {"render": {"width": 64, "height": 64, "spp": 16, "max_depth": 1},
             "camera": {"position": [0, 0.3, 3], "look_at": [0, 0, 0], "up": [0, 1, 0], "fov": 0.2},
             "lights": lights, "materials": WHITE, "objects": [FLOOR]}
    with open(path, "w") as f:
        json.dump(scene, f)
    return e / math.pi


def rel_rmse_exact(exr, exact):
    rgb = read_exr(exr)
    g = np.asarray(rgb[..., 1], dtype=np.float64)
    return float(np.sqrt(np.mean((g - exact) ** 2)) / exact)


def measure_many(ctx):
    ks = [1, 3] if ctx.quick else [1, 3, 10, 32, 100]
    spp = 2 if ctx.quick else 16
    rows = []
    for k in ks:
        path = os.path.join(ctx.work, f"lights_grid_{k}.json")
        exact = grid_scene(path, k)
        row = {"n": k * k, "exact": exact}
        for mode in ("power", "tree"):
            d = [f"render.light_selection={mode}"]
            ctx.warm_up(path, spp, d)
            r = ctx.render(path, f"lights_{k}_{mode}", spp, 64, 64, defines=d)
            row[mode] = {"seconds": r.seconds, "per_sample_us": r.seconds / r.stats["samples"] * 1e6,
                         "err": rel_rmse_exact(r.exr, exact), "features": r.stats["kernel_features"]}
        rows.append(row)
    return {"spp": spp, "rows": rows}


def render_many(ctx, m):
    rows = m["rows"]
    table = []
    for r in rows:
        p, t = r["power"], r["tree"]
        # Efficiency: 1 / (error^2 x time); the tree's over power's at the same scene.
        eff = (p["err"] ** 2 * p["seconds"]) / (t["err"] ** 2 * t["seconds"]) if t["err"] > 0 else float("nan")
        table.append([f"{r['n']:,}", fmt(p["per_sample_us"]), fmt(t["per_sample_us"]), fmt(p["err"]), fmt(t["err"]),
                      fmt(eff)])
    n = [r["n"] for r in rows]
    fits = {mode: loglog_fit(n, [r[mode]["per_sample_us"] for r in rows]) for mode in ("power", "tree")}
    loglog_figure(ctx.png("lights_scaling.png"),
                  [("lights", "µs per sample", [(mode, n, [r[mode]["per_sample_us"] for r in rows], *fits[mode])
                                                 for mode in ("power", "tree")], None),
                   ("lights", "relative RMSE", [(mode, n, [r[mode]["err"] for r in rows], math.nan, 0.0)
                                                 for mode in ("power", "tree")], None)],
                  "Many lights: time per sample and error, by power vs light tree")
    return ["### Many lights: the light tree against selection by power\n",
            f"k × k sphere lights (radius 0.015) over a 4 × 4 m square 1 m above a white floor, the same total "
            f"power for every k, seen at one point by a narrow camera (64×64, {m['spp']} spp, max_depth 1): the "
            "exact radiance is known in closed form, so the error is the relative RMSE of the pixels against "
            "it. `power` = `render.light_selection=power` (alias table, every ray tests every light), `tree` = "
            "the light tree (chosen by importance at the shading point, lights found through its boxes). "
            "Efficiency = the tree's 1/(error² × time) over power's.\n",
            md_table(["lights", "power: µs/sample", "tree: µs/sample", "power: rel. RMSE", "tree: rel. RMSE",
                      "tree's efficiency ÷ power's"], table),
            f"Fitted log–log slopes of time per sample against the number of lights: power "
            f"{fmt(fits['power'][0], 2)}, tree {fmt(fits['tree'][0], 2)} (0 = constant, 1 = linear).\n",
            "![many lights](lights_scaling.png)\n"]


def measure_env(ctx):
    path = os.path.join(REPO, "scenes", "docs", "sky_fresnel_shallow.json")
    w, h = (48, 36) if ctx.quick else (128, 96)
    spp_ref, spp = (64, 4) if ctx.quick else (1024, 16)
    # The sky alone (the sun light only places it): its bright circumsolar region is what
    # importance sampling finds.
    base = ["lights[0].intensity=0", "environment.resolution=512"]
    ctx.warm_up(path, spp, base)
    ref = ctx.render(path, "env_ref", spp_ref, w, h, defines=base)
    out = {"size": (w, h), "ref_spp": spp_ref, "rows": []}
    for mode in ("importance", "uniform"):
        d = base + [f"environment.sampling={mode}"]
        r = ctx.render(path, f"env_{mode}", spp, w, h, defines=d)
        out["rows"].append({"mode": mode, "spp": spp, "seconds": r.seconds, "cmp": ctx.tools.compare(r.exr, ref.exr)})
    return out


def render_env(ctx, m):
    w, h = m["size"]
    rows = [[r["mode"], r["spp"], fmt(r["seconds"]), fmt(r["cmp"]["rmse"]), fmt(r["cmp"]["relmse"]),
             fmt(r["cmp"]["rmse"] ** 2 * r["seconds"])] for r in m["rows"]]
    return ["### Environment map: importance sampling against uniform sampling\n",
            f"`scenes/docs/sky_fresnel_shallow.json` lit by its Preetham sky alone (the sun light at intensity 0; "
            f"the sky baked at 512×256), {w}×{h}; reference: importance sampling at {m['ref_spp']} spp. "
            "`environment.sampling=uniform` draws light samples uniformly over the sphere (still MIS-weighted); "
            "the same spp costs the same time, so equal spp is equal time. MSE × time: lower is better.\n",
            md_table(["sampling", "spp", "time (s)", "RMSE", "relMSE", "MSE × time"], rows)]


def measure_ao(ctx):
    docs = os.path.join(REPO, "scenes", "docs")
    w, h = (48, 36) if ctx.quick else (128, 96)
    spp_ref, spp = (64, 4) if ctx.quick else (1024, 64)
    defs = ["environment.resolution=256"]
    gi = os.path.join(docs, "ao_3_gi.json")
    add = os.path.join(docs, "ao_2_add.json")
    ctx.warm_up(gi, spp, defs)
    ctx.warm_up(add, spp, defs)
    ref_gi = ctx.render(gi, "ao_ref_gi", spp_ref, w, h, defines=defs)
    r_gi = ctx.render(gi, "ao_gi", spp, w, h, defines=defs)
    # AO add at the largest power-of-two spp that takes no longer than GI. Not by scaling one
    # calibration: ao.samples (256) is per pixel, so fewer samples each trace more AO rays.
    r_add, spp_add = None, spp
    while spp_add >= 1:
        r_add = ctx.render(add, f"ao_add_{spp_add}", spp_add, w, h, defines=defs)
        if r_add.seconds <= r_gi.seconds or spp_add == 1:
            break
        spp_add //= 2
    eq = [{"what": "GI (path tracing)", "spp": spp, "r": r_gi, "cmp": ctx.tools.compare(r_gi.exr, ref_gi.exr)},
          {"what": "AO add, no GI (ao.samples 256)", "spp": spp_add, "r": r_add,
           "cmp": ctx.tools.compare(r_add.exr, ref_gi.exr)}]
    # AO samples as a knob, on the AO term alone (the sun and sky off: the image is
    # diffuse x AO / k), at the same spp, more AO rays at the first hit.
    # The rings' AO reaches 10 m here (2 in the gallery), so that the floor around them carries
    # AO noise worth reducing; at 2 m the pixels' own anti-aliasing noise hides it.
    alone = defs + ["lights[0].intensity=0", "environment.intensity=0", "materials.ao_floor.ao.max_distance=10",
                    "materials.ao_ring.ao.max_distance=10"]
    knob_spp = 4
    ref_add = ctx.render(add, "ao_ref_add", spp_ref, w, h,
                         defines=alone + ["materials.ao_floor.ao.samples=1", "materials.ao_ring.ao.samples=1"])
    knob = []
    for s in ([16] if ctx.quick else [16, 64, 256, 1024]):
        d = alone + [f"materials.ao_floor.ao.samples={s}", f"materials.ao_ring.ao.samples={s}"]
        r = ctx.render(add, f"ao_samples_{s}", knob_spp, w, h, defines=d)
        knob.append({"samples": s, "r": r, "cmp": ctx.tools.compare(r.exr, ref_add.exr)})
    return {"size": (w, h), "spp": spp, "knob_spp": knob_spp, "ref_spp": spp_ref, "eq": eq, "knob": knob}


def render_ao(ctx, m):
    w, h = m["size"]
    eq = [[e["what"], e["spp"], fmt(e["r"].seconds), fmt(e["cmp"]["rmse"]), fmt(e["cmp"]["relmse"])] for e in m["eq"]]
    knob = [[k["samples"], max(1, round(k["samples"] / m["knob_spp"])), fmt(k["r"].seconds),
             rate(k["r"].stats["samples"], k["r"].seconds), fmt(k["cmp"]["rmse"]),
             fmt(k["cmp"]["rmse"] ** 2 * k["r"].seconds)] for k in m["knob"]]
    return ["### Ambient occlusion against GI, and AO samples\n",
            f"The gallery's AO rings (`scenes/docs/ao_*.json`), {w}×{h}, the sky baked at 256×128. Against the GI "
            f"reference (`ao_3_gi` at {m['ref_spp']} spp): path-traced GI at {m['spp']} spp, and AO added as "
            "ambient light without GI (`ao_2_add`, its 256 AO samples per pixel) at the largest power-of-two spp "
            "that takes no longer. AO's error against GI is mostly its bias (it is a different image), GI's is "
            "noise.\n",
            md_table(["image", "spp", "time (s)", "RMSE vs GI reference", "relMSE"], eq),
            f"`ao.samples` at {m['knob_spp']} spp (n = round(samples / spp) AO rays at the first hit) on the AO term "
            f"alone (sun and sky off: the image is diffuse × AO / k; AO reaching 10 m), against the same at {m['ref_spp']} spp with "
            "one AO ray per sample (the same expectation: splitting is unbiased). MSE × time: lower is better.\n",
            md_table(["ao.samples", "AO rays at the first hit", "time (s)", "Msamples/s", "RMSE", "MSE × time"], knob)]


def measure(ctx):
    return {"many": measure_many(ctx), "env": measure_env(ctx), "ao": measure_ao(ctx)}


def render(ctx, m):
    return "\n".join(["## Lights, environment and AO\n"] + render_many(ctx, m["many"]) + render_env(ctx, m["env"]) +
                     render_ao(ctx, m["ao"]))

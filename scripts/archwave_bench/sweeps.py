"""Section "Sample-count sweeps": error vs spp and vs render time against a high-spp reference,
with log-log slopes and the reference's own noise floor."""

import time

import numpy as np

from . import REF_FACTOR
from .errors import loglog_fit, reference_floor, without_floor
from .plots import loglog_figure
from .tables import fmt, md_table
from .tools import log

KEYS = ("cornell", "glossy", "mesh")


def _next_fits(ctx, scene, points, spp, t_start, budget, ref_price):
    """Whether the render at `spp` and a REF_FACTOR x reference for it still fit in the budget.
    The first points (spp <= 4) are cheap and always taken: they calibrate the rest."""
    if spp <= 4:
        return True
    last = points[-1]["render"]
    next_cost = last.overhead + last.seconds * spp / points[-1]["spp"]
    ref_cost = ctx.refs.cost(scene, REF_FACTOR * spp, *ref_price)
    return time.monotonic() - t_start + next_cost + ref_cost <= budget


def sweep_scene(ctx, scene, budget):
    """spp = 1, 2, 4, ... while the next point and a REF_FACTOR x reference for it still fit
    in `budget` seconds, then that reference and the errors against it."""
    t_start = time.monotonic()
    ctx.ensure_mesh(scene)
    ctx.warm_up(scene.path, 1, scene.defines)
    # The reference renderer's seconds per spp, to price references before choosing.
    cal_spp = 4 if ctx.quick else 16
    cal = ctx.refs.calibrate(scene, f"sweep_{scene.key}_refcal", cal_spp)
    ref_price = (cal.seconds / cal_spp, cal.overhead)
    max_spp = 16 if ctx.quick else 1024
    points = []
    spp = 1
    while spp <= max_spp and _next_fits(ctx, scene, points, spp, t_start, budget, ref_price):
        r = ctx.render_scene(scene, f"sweep_{scene.key}_{spp}", spp)
        points.append({"spp": spp, "render": r})
        spp *= 2
    top = points[-1]["spp"]
    ref_exr, ref_meta = ctx.refs.get(scene, REF_FACTOR * top)
    for p in points:
        p["cmp"] = ctx.tools.compare(p["render"].exr, ref_exr)
    return {"scene": scene, "points": points, "ref": ref_meta, "top": top,
            "seconds": time.monotonic() - t_start}


def fit(res):
    """Slopes of RMSE and relMSE against spp and time, and the reference's noise floor (an
    unbiased estimator's RMSE ~ spp^-1/2, relMSE ~ spp^-1). Adds the fits to `res`."""
    pts = res["points"]
    spp = np.array([p["spp"] for p in pts], float)
    secs = np.array([p["render"].seconds for p in pts])
    rmse = np.array([p["cmp"]["rmse"] for p in pts])
    rel = np.array([p["cmp"]["relmse"] for p in pts])
    floor = reference_floor(spp, rmse, res["ref"]["spp"])
    res.update(spp=spp, secs=secs, rmse=rmse, rel=rel, floor=floor,
               fit_rmse=loglog_fit(spp, rmse), fit_rel=loglog_fit(spp, rel),
               fit_time=loglog_fit(secs, rmse), fit_reltime=loglog_fit(secs, rel))
    res["slope"] = res["fit_rmse"][0]
    res["slope_floor_removed"] = loglog_fit(spp, without_floor(rmse, floor))[0]
    return res


def measure(ctx, budget):
    """Each scene gets an equal share of what is left of the budget."""
    results = []
    for i, k in enumerate(KEYS):
        share = (budget - sum(r["seconds"] for r in results)) / (len(KEYS) - i)
        log(f"sweeps: {k}, {share:.0f} s")
        results.append(fit(sweep_scene(ctx, ctx.scenes[k], share)))
    return results


def plot(ctx, results):
    def series(x, y, fit_key):
        return [(r["scene"].key, r[x], r[y], *r[fit_key]) for r in results]
    loglog_figure(ctx.png("sweep_spp.png"),
                  [("samples per pixel", "RMSE", series("spp", "rmse", "fit_rmse"), -0.5),
                   ("samples per pixel", "relMSE", series("spp", "rel", "fit_rel"), -1.0)],
                  "Error vs spp (against a high-spp reference, another seed)")
    loglog_figure(ctx.png("sweep_time.png"),
                  [("render time (s)", "RMSE", series("secs", "rmse", "fit_time"), -0.5),
                   ("render time (s)", "relMSE", series("secs", "rel", "fit_reltime"), -1.0)],
                  "Error vs render time (kernel and BVH build excluded)")


CAPTION = [
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
]


def slope_table(results):
    rows = []
    for r in results:
        s_rmse, rmse, floor = r["slope"], r["rmse"], r["floor"]
        rows.append([r["scene"].key, f"1 – {int(r['spp'].max())}", fmt(s_rmse), f"{s_rmse + 0.5:+.3f}",
                     fmt(r["slope_floor_removed"]), fmt(r["fit_rel"][0]), fmt(r["fit_time"][0]), fmt(floor),
                     fmt(rmse[-1]), fmt(floor / rmse[-1] * 100, 2) + "%"])
    return md_table(["scene", "spp", "RMSE slope vs spp", "deviation from −0.5", "slope, floor removed",
                     "relMSE slope vs spp", "RMSE slope vs time", "reference RMSE floor (est.)",
                     "RMSE at top spp", "floor / RMSE at top"], rows)


def reference_table(results):
    rows = []
    for r in results:
        sc, ref = r["scene"], r["ref"]
        rows.append([sc.key, f"`{sc.rel_path()}`", f"{sc.width}x{sc.height}", ref["spp"],
                     f"{ref['spp'] // r['top']}x", ref["seed"], ref["renderer"], fmt(ref["total_seconds"]),
                     "yes" if ref.get("reused") else "no", fmt(r["floor"]), ref["git_commit"][:10]])
    return md_table(["scene", "file", "size", "reference spp", "× top sweep spp", "seed", "renderer",
                     "time (s)", "reused", "est. RMSE floor", "commit"], rows)


def slope_check(r):
    """Whether the RMSE slope is within 0.05 of −0.5, raw or with the reference floor removed."""
    key, s_raw, s_corr = r["scene"].key, r["slope"], r["slope_floor_removed"]
    if abs(s_raw + 0.5) <= 0.05:
        return f"- {key}: RMSE slope {s_raw:+.3f}, within 0.05 of −0.5."
    if abs(s_corr + 0.5) <= 0.05:
        return (f"- {key}: RMSE slope {s_raw:+.3f}; with the reference floor removed {s_corr:+.3f}, "
                "within 0.05 of −0.5.")
    return (f"- {key}: RMSE slope {s_raw:+.3f}, {s_corr:+.3f} with the floor removed: neither within 0.05 "
            "of −0.5 (every point below).")


def point_table(r):
    sc = r["scene"]
    rows = [[int(p["spp"]), fmt(p["render"].stats["total_seconds"]), fmt(p["render"].seconds),
             fmt(p["cmp"]["rmse"]), fmt(p["cmp"]["relmse"])] for p in r["points"]]
    return (f"\n<details><summary>{sc.title} ({sc.key}, {sc.width}x{sc.height}): every point"
            f"</summary>\n\n" + md_table(["spp", "total (s)", "render (s)", "RMSE", "relMSE"], rows)
            + "\n</details>\n")


def render(ctx, results):
    plot(ctx, results)
    md = ["## Sample-count sweeps\n"] + CAPTION
    md += [slope_table(results), "![error vs spp](sweep_spp.png)\n", "![error vs time](sweep_time.png)\n",
           "References (stored with ref.json beside ref.exr under `results/refs/`, reused by later runs "
           "of the same code):\n", reference_table(results)]
    if any(r["ref"]["spp"] < REF_FACTOR * r["top"] for r in results):
        md.append(f"A reference below {REF_FACTOR}× the top sweep spp was all the budget allowed.\n")
    md += [slope_check(r) for r in results] + [""]
    md += [point_table(r) for r in results]
    return "\n".join(md)

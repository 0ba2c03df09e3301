"""Section "Throughput": traversal against Embree, wavefront against the scalar path end to
end and per stage, dense against queue launches, and memory per path state and triangle."""

import os

from .tables import fmt, fmt_bytes, md_table, rate, ray_rate

DENSE_MODES = [("default (0.25)", []), ("never (queue order)", ["--dense-fraction", "2"]),
               ("always", ["--dense-fraction", "0"])]


def cases(ctx):
    """(scene key, width, height, spp) of the end-to-end and dense-launch renders."""
    if ctx.quick:
        return [("cornell", 32, 32, 2), ("glossy", 32, 16, 2)]
    return [("cornell", 400, 400, 32), ("glossy", 320, 160, 32)]


# ---- traversal ------------------------------------------------------------------------------

def measure_traversal(ctx):
    """The OpenCL intersect kernel and Embree on the same rays (bench/bench_traversal)."""
    args = ["--tris", "20000", "--width", "128", "--height", "128"] if ctx.quick else []
    tj, _ = ctx.tools.traversal(args, os.path.join(ctx.work, "traversal.json"))
    ctx.notes["embree"] = tj["embree"]
    ratios = [r["opencl_mrays"] / r["embree_mrays"] for r in tj["rows"]]
    return {"json": tj, "args": args, "ratios": ratios}


def render_traversal(ctx, t):
    tj, ratios = t["json"], t["ratios"]
    met = "Met" if min(ratios) >= 1 / 3 else "Not met"
    rows = [[r["kind"], r["rays"], fmt(r["opencl_mrays"]), fmt(r["embree_mrays"]), fmt(ratio),
             fmt(r["embree1_mrays"]), fmt(r["embree8_mrays"]), fmt(r["embree16_mrays"]),
             f"{100 * r['mismatch']:.4f}%"] for r, ratio in zip(tj["rows"], ratios)]
    return ["### Traversal: OpenCL intersect kernel vs Embree (`bench/bench_traversal`)\n",
            "Same ray batches through the flattened-BVH kernel on the OpenCL device and through "
            "Embree's `rtcIntersect1` on the host, with as many host threads as the device has "
            "compute units. Target (issue 2): OpenCL ≥ 1/3 of Embree's single-ray throughput on "
            f"the same cores; ambition ≥ 0.5. **{met}: {' and '.join(fmt(r, 2) for r in ratios)} "
            "(primary, diffuse).**\n",
            f"Command: `{' '.join(['bench/bench_traversal'] + t['args'])}` (in the build folder); "
            f"geometry: {tj['geometry']}, {tj['triangles']:,} triangles, flat BVH "
            f"{tj['bvh_nodes']:,} nodes, depth {tj['bvh_depth']}; primary rays {tj['width']}x{tj['height']} "
            f"pinhole, diffuse rays one cosine bounce per primary hit; OpenCL kernel time only, Embree "
            f"wall time ({tj['embree']}, robust scene), best of 3 after a warm-up; device "
            f"{tj['device']}, {tj['compute_units']} compute units.\n",
            md_table(["ray kind", "rays", "OpenCL Mrays/s", f"Embree Mrays/s ({tj['compute_units']} threads)",
                      "ratio OpenCL/Embree", "Embree 1-thread Mrays/s", "Embree rtcIntersect8 Mrays/s",
                      "Embree rtcIntersect16 Mrays/s", "hit mismatch"], rows),
            "The kernel is the stack-based BVH4 traversal (four boxes per float4 slab test) with the watertight triangle test "
            f"([bvh-layout.md]({ctx.docs_link('bvh-layout.md')})). The two packet columns trace the same rays "
            "through Embree's `rtcIntersect8`/`rtcIntersect16`, packets of consecutive rays of the batch on the same "
            "threads: what tracing several rays per SIMD instruction stream can gain on these rays.\n"]


# ---- end to end and per stage ---------------------------------------------------------------

def measure_end_to_end(ctx):
    """Each case rendered by the wavefront and by the scalar path, warm kernels."""
    out = []
    for key, w, h, spp in cases(ctx):
        sc = ctx.scenes[key]
        ctx.warm_up(sc.path, spp)
        wf = ctx.render(sc.path, f"e2e_{key}_wavefront", spp, w, h)
        sl = ctx.render(sc.path, f"e2e_{key}_scalar", spp, w, h, scalar=True)
        out.append({"scene": sc, "size": (w, h, spp), "wavefront": wf, "scalar": sl})
    return out


def case_label(key, size):
    w, h, spp = size
    return f"{key} {w}x{h}, {spp} spp"


def stage_table(r):
    st = r.stats["stages"]
    total = sum(x["seconds"] for x in st) or 1.0
    return md_table(["stage", "time (s)", "share", "items", "M items/s"],
                    [[x["name"], fmt(x["seconds"]), f"{100 * x['seconds'] / total:.1f}%", x["items"],
                      fmt(x["items"] / x["seconds"] * 1e-6 if x["seconds"] > 0 else float("nan"))] for x in st])


def render_end_to_end(e2e):
    rows, stages = [], []
    for c in e2e:
        sc, wf, sl = c["scene"], c["wavefront"], c["scalar"]
        for name, r in (("wavefront (OpenCL)", wf), ("scalar (host, Embree)", sl)):
            rows.append([case_label(sc.key, c["size"]), name, fmt(r.seconds), rate(r.stats["samples"], r.seconds),
                         ray_rate(r.stats, r.seconds), fmt(sl.seconds / r.seconds, 3)])
        w, h, spp = c["size"]
        stages.append(f"**{sc.title}** (`{sc.rel_path()}`, {w}x{h}, {spp} spp):\n\n" + stage_table(wf))
    return ["### End to end: wavefront vs scalar path\n",
            "Kernel build excluded (a warm-up render fills PoCL's cache first); time = render time "
            "from the stats. Rays = closest + shadow.\n",
            md_table(["scene", "renderer", "time (s)", "Msamples/s", "Mrays/s", "speed relative to scalar"], rows),
            "### Per-stage time and throughput (wavefront)\n",
            "One shading kernel per lobe queue; `items` = paths through the stage (pixels for "
            "film_accumulate); the same columns appear in every render's stats summary.\n"] + stages


# ---- dense launches -------------------------------------------------------------------------

def measure_dense(ctx):
    """The same renders with the default dense threshold, with every queue launched over its
    entries, and with every dense-capable stage over the whole pool (docs/architecture.md,
    "Dense launches"). Interleaved, best of `reps`, so drift on a shared machine hits all
    three alike."""
    reps = 1 if ctx.quick else 2
    out = []
    for key, w, h, spp in cases(ctx):
        sc = ctx.scenes[key]
        best = {}
        for rep_i in range(reps):
            for label, extra in DENSE_MODES:
                r = ctx.render(sc.path, f"dense_{key}_{rep_i}_{extra[-1] if extra else 'default'}", spp, w, h,
                               extra_args=extra)
                if label not in best or r.seconds < best[label].seconds:
                    best[label] = r
        out.append({"key": key, "size": (w, h, spp), "best": best})
    return {"reps": reps, "cases": out}


def dense_rows(c):
    base = c["best"]["never (queue order)"].seconds
    rows = []
    for label, _ in DENSE_MODES:
        r = c["best"][label]
        st = {x["name"]: x["seconds"] for x in r.stats["stages"]}
        rows.append([case_label(c["key"], c["size"]), label, fmt(r.seconds), fmt(base / r.seconds, 3),
                     fmt(st.get("intersect_closest", 0)), fmt(st.get("classify_hit", 0)),
                     fmt(sum(v for k, v in st.items() if k.startswith("shade_"))),
                     fmt(st.get("intersect_shadow", 0))])
    return rows


def render_dense(ctx, d):
    rows = [row for c in d["cases"] for row in dense_rows(c)]
    return ["### Dense launches vs queue launches\n",
            "A stage whose queue holds at least a quarter of the pool runs over the whole pool in slot "
            "order, one work-item per slot, instead of over the queue's scattered entries "
            f"([architecture.md]({ctx.docs_link('architecture.md')}), \"Dense launches\"); the image is "
            f"bit-identical. Render time (s) and the dense-capable stages' times, best of {d['reps']}, "
            "interleaved; speed-up relative to queue order.\n",
            md_table(["scene", "dense launches", "render (s)", "speed-up", "intersect_closest (s)",
                      "classify_hit (s)", "shading (s)", "intersect_shadow (s)"], rows)]


# ---- memory ---------------------------------------------------------------------------------

def measure_memory(ctx):
    """The stats of a 320x240 render of each scene."""
    ctx.ensure_mesh(ctx.scenes["mesh"])
    spp = 1 if ctx.quick else 4
    out = []
    for key in ("cornell", "glossy", "mesh"):
        sc = ctx.scenes[key]
        ctx.warm_up(sc.path, spp, sc.defines)
        out.append((key, ctx.render(sc.path, f"mem_{key}", spp, 320, 240, defines=sc.defines).stats))
    return out


def render_memory(mem):
    rows = [[key, s["pool_size"], fmt_bytes(s["state_bytes"]), s["state_bytes"] // max(1, s["pool_size"]),
             f"{s['triangles']:,}", fmt_bytes(s["scene_bytes"]), fmt(s["scene_bytes"] / max(1, s["triangles"])),
             fmt_bytes(s["film_bytes"]), fmt_bytes(s["device_bytes"])] for key, s in mem]
    return ["### Memory per path state and per triangle\n",
            "From the stats of a 320x240 render (`state_bytes` / `pool_size`, `scene_bytes` / "
            "`triangles`; scene bytes = BVH nodes + leaf triangles + triangle info + vertices + "
            "materials + lights on the device; film = film + sample counts + batch samples).\n",
            md_table(["scene", "path states", "path pool", "bytes per path state", "triangles", "scene data",
                      "bytes per triangle", "film", "all device buffers"], rows)]


# ---- the section ----------------------------------------------------------------------------

def measure(ctx):
    return {"traversal": measure_traversal(ctx), "e2e": measure_end_to_end(ctx),
            "dense": measure_dense(ctx), "memory": measure_memory(ctx)}


def render(ctx, m):
    md = ["## Throughput\n"]
    md += render_traversal(ctx, m["traversal"])
    md += render_end_to_end(m["e2e"])
    md += render_dense(ctx, m["dense"])
    md += render_memory(m["memory"])
    return "\n".join(md)

"""Section "Devices": the same small Cornell box render on every OpenCL device and on the
host scalar path, and each wavefront stage's items/s on every device for the Cornell box and
the every-lobe scene (issue 12: the stage shapes are chosen by these figures)."""

import os

from .tables import fmt, md_table, rate, ray_rate

STAGE_SCENES = ("cornell", "glossy")


def size(ctx):
    return (32, 32, 2) if ctx.quick else (256, 256, 16)


def measure(ctx):
    w, h, spp = size(ctx)
    rows, stages = [], {key: [] for key in STAGE_SCENES}
    for idx, desc in ctx.tools.list_devices():
        # "[0] Intel(R) OpenCL": the platform tells CPU runtimes apart (their device names are
        # both the CPU's); desc is "NAME  (TYPE, PLATFORM, VERSION, ...)".
        fields = desc.split(" (", 1)[1].split(", ") if " (" in desc else []
        name = f"[{idx}] {fields[1] if len(fields) > 1 else desc.split(' (')[0].strip()}"
        for key in STAGE_SCENES:
            sc = ctx.scenes[key]
            ctx.warm_up(sc.path, spp, defines=sc.defines, device=idx)
            r = ctx.render(sc.path, f"dev{idx}_{key}", spp, w, h, defines=sc.defines, device=idx)
            stages[key].append((name, r))
            if key == "cornell":
                rows.append((name, r))
    sc = ctx.scenes["cornell"]
    r = ctx.render(sc.path, "dev_scalar", spp, w, h, scalar=True)
    rows.append((f"host scalar path ({os.cpu_count()} threads, Embree)", r))
    return {"rows": rows, "stages": stages}


def device_row(name, r):
    s = r.stats
    return [name, fmt(r.seconds), rate(s["samples"], r.seconds), ray_rate(s, r.seconds),
            fmt(s["compile_seconds"]) if s["renderer"] == "wavefront" else "–"]


def stage_table(runs):
    """Rows: stages in pipeline order; columns: M items/s per device, then each device's
    figure over the first device's."""
    names = []
    for _, r in runs:
        for st in r.stats["stages"]:
            if st["name"] not in names:
                names.append(st["name"])

    def per_s(r, name):
        for st in r.stats["stages"]:
            if st["name"] == name and st["seconds"] > 0:
                return st["items"] / st["seconds"] / 1e6
        return None

    headers = ["stage"] + [f"{d} (M items/s)" for d, _ in runs] + [f"{d} ÷ {runs[0][0]}" for d, _ in runs[1:]]
    rows = []
    for name in names + ["(render: samples)"]:
        if name == "(render: samples)":
            vals = [r.stats["samples"] / r.stats["render_seconds"] / 1e6 if r.stats["render_seconds"] > 0 else None
                    for _, r in runs]
        else:
            vals = [per_s(r, name) for _, r in runs]
        ratios = [fmt(v / vals[0]) if v and vals[0] else "–" for v in vals[1:]]
        rows.append([name] + [fmt(v) if v else "–" for v in vals] + ratios)
    return md_table(headers, rows)


def render(ctx, m):
    w, h, spp = size(ctx)
    out = ["## Devices\n",
           f"The Cornell box, {w}x{h}, {spp} spp, on every OpenCL device `archwave --list-devices` shows "
           "and on the host scalar path (`--scalar`). A GPU appears only when the machine has one.\n",
           md_table(["device", "render (s)", "Msamples/s", "Mrays/s", "kernel build, cached (s)"],
                    [device_row(name, r) for name, r in m["rows"]]),
           "\n### Stages on every device\n",
           "Each wavefront stage's items (paths, or rays for the ray stages) per second of that stage, "
           f"from the render's own stage timers, {w}x{h}, {spp} spp, kernels warm; the last row is the "
           "whole render's samples per second of path tracing (kernel build and BVH excluded).\n"]
    for key in STAGE_SCENES:
        out += [f"\n{ctx.scenes[key].title}:\n", stage_table(m["stages"][key])]
    return "\n".join(out)

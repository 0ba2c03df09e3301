"""Section "Devices": the same small Cornell box render on every OpenCL device and on the
host scalar path."""

import os

from .tables import fmt, md_table, rate, ray_rate


def size(ctx):
    return (32, 32, 2) if ctx.quick else (256, 256, 16)


def measure(ctx):
    w, h, spp = size(ctx)
    sc = ctx.scenes["cornell"]
    rows = []
    for idx, desc in ctx.tools.list_devices():
        ctx.warm_up(sc.path, spp, device=idx)
        rows.append((f"[{idx}] {desc.split(' (')[0].strip()}", ctx.render(sc.path, f"dev{idx}", spp, w, h, device=idx)))
    r = ctx.render(sc.path, "dev_scalar", spp, w, h, scalar=True)
    rows.append((f"host scalar path ({os.cpu_count()} threads, Embree)", r))
    return rows


def device_row(name, r):
    s = r.stats
    return [name, fmt(r.seconds), rate(s["samples"], r.seconds), ray_rate(s, r.seconds),
            fmt(s["compile_seconds"]) if s["renderer"] == "wavefront" else "–"]


def render(ctx, rows):
    w, h, spp = size(ctx)
    return "\n".join([
        "## Devices\n",
        f"The Cornell box, {w}x{h}, {spp} spp, on every OpenCL device `archwave --list-devices` shows "
        "and on the host scalar path (`--scalar`). A GPU appears only when the machine has one.\n",
        md_table(["device", "render (s)", "Msamples/s", "Mrays/s", "kernel build, cached (s)"],
                 [device_row(name, r) for name, r in rows])])

#!/usr/bin/env python3
"""Vector width of the shading kernels on Intel's CPU OpenCL runtime (issue 12): what the
runtime chooses, and what forcing a width costs, measured per stage.

Intel's runtime vectorises a kernel across work-items when its cost model expects a gain; the
attribute intel_vec_len_hint(N) (cl_intel_vec_len_hint) overrides that choice. This script
copies kernels/ into a temporary folder once per variant, sets the attribute of the kernels that
AW_STAGE_KERNEL declares (the shading stages: as shipped they are built scalar like every other
stage, integrator/stage_kernel.h says why; "runtime's choice" removes the attribute), and renders
the same scene with each copy (`archwave --kernels DIR`), the variants interleaved run by run so that the machine's drift
falls on all of them alike. It prints, per variant, what the runtime's build log says of each
shading kernel (its width, or "scalar") and its gathers and scatters, then the median seconds
of every stage and each run's samples per second.

Usage: python3 bench/vector_width.py [--archwave build/archwave] [--scene scenes/cornell.json]
                                     [--spp 32] [--runs 3] [--device intel] [--widths 1,8,16]
Exit status 2 when the device is not Intel's runtime or a variant cannot be built.
docs/performance.md ("Vector width on an AVX-512 Xeon") has the measured tables and what they
mean.
"""
import argparse
import json
import os
import re
import shutil
import statistics
import subprocess
import sys
import tempfile

REPO = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))
# The attribute every one-path shading kernel's declaration carries (integrator/stage_kernel.h):
# scalar on Intel's runtime as shipped. The renders run with --no-lanes, so every shading
# launch is a one-path kernel (the lane program, kernels_lanes.cl, is its own vectorisation).
SHADE_ATTR = "#define AW_SHADE_KERNEL_ATTR AW_SCALAR_KERNEL"
LOG_KERNEL = re.compile(r'Kernel "(kernel_\w+)" was (successfully vectorized \((\d+)\)|not vectorized)')
LOG_GATHERS = re.compile(r"Kernel was (\d+)-way vectorized(\d+) gathers?(\d+) scatters?")


def die(msg):
    print(f"vector_width: {msg}", file=sys.stderr)
    sys.exit(2)


def make_variant(root, width):
    """kernels/ copied under root, the shading kernels carrying intel_vec_len_hint(width); width
    None gives them no attribute (the runtime's own choice; as shipped they carry width 1)."""
    dst = os.path.join(root, f"w{width or 'runtime'}")
    shutil.copytree(os.path.join(REPO, "kernels"), dst)
    path = os.path.join(dst, "integrator", "stage_kernel.h")
    with open(path) as f:
        src = f.read()
    if src.count(SHADE_ATTR) != 1:
        die(f"{path}: AW_SHADE_KERNEL_ATTR's definition changed; update SHADE_ATTR in this script")
    attr = "" if width is None else f"__attribute__((intel_vec_len_hint({width})))"
    with open(path, "w") as f:
        f.write(src.replace(SHADE_ATTR, f"#define AW_SHADE_KERNEL_ATTR {attr}"))
    return dst


def env_for(build_dir):
    env = dict(os.environ)
    env.setdefault("POCL_CACHE_DIR", os.path.join(build_dir, "pocl-cache"))
    env.setdefault("ARCHWAVE_KERNEL_CACHE", os.path.join(build_dir, "kernel-cache"))
    return env


def build_log(args, kdir, env, tmp):
    """What the runtime's compiler did with the shading kernels: {kernel: width, 0 = scalar}, and
    (width, gathers, scatters) of its largest vectorised candidate or None. A 1-spp render with
    the build log on and the binary cache off."""
    e = dict(env, ARCHWAVE_BUILD_LOG="1", ARCHWAVE_KERNEL_CACHE="0")
    p = subprocess.run([args.archwave, args.scene, "--kernels", kdir, "--no-lanes", "--device", args.device, "--spp", "1",
                        "-o", os.path.join(tmp, "log.exr"), "-q"], env=e, capture_output=True, text=True)
    if p.returncode != 0:
        die(f"building {kdir} failed (exit {p.returncode}):\n{p.stderr[-3000:]}")
    text = p.stdout + p.stderr
    widths = {name: int(width) if width else 0 for name, _, width in LOG_KERNEL.findall(text)
              if name.startswith("kernel_shade_")}
    # The remarks do not name their kernel; the largest candidate is the shading kernel of a lobe
    # the scene uses (the others are empty bodies with two scatters).
    remarks = LOG_GATHERS.findall(text)
    largest = tuple(map(int, max(remarks, key=lambda r: int(r[1]) + int(r[2])))) if remarks else None
    return widths, largest


def render(args, kdir, env, tmp):
    stats = os.path.join(tmp, "stats.json")
    p = subprocess.run([args.archwave, args.scene, "--kernels", kdir, "--no-lanes", "--device", args.device, "--spp",
                        str(args.spp), "-o", os.path.join(tmp, "r.exr"), "-q", "--stats-json", stats],
                       env=env, capture_output=True, text=True)
    if p.returncode != 0:
        die(f"render with {kdir} failed (exit {p.returncode}):\n{p.stderr[-3000:]}")
    with open(stats) as f:
        s = json.load(f)
    if "Intel" not in s.get("device", ""):
        die(f"device '{s.get('device')}' is not Intel's CPU runtime: intel_vec_len_hint means nothing there")
    return s


def main():
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    ap.add_argument("--archwave", default=os.path.join(REPO, "build", "archwave"))
    ap.add_argument("--scene", default=os.path.join(REPO, "scenes", "cornell.json"))
    ap.add_argument("--spp", type=int, default=32)
    ap.add_argument("--runs", type=int, default=3)
    ap.add_argument("--device", default="intel")
    ap.add_argument("--widths", default="1,8,16", help="forced widths besides the runtime's own choice")
    args = ap.parse_args()
    try:
        widths = [None] + [int(w) for w in args.widths.split(",") if w]
    except ValueError:
        die(f"--widths {args.widths}: a comma-separated list of integers")
    env = env_for(os.path.dirname(os.path.abspath(args.archwave)))
    with tempfile.TemporaryDirectory(prefix="archwave_vecw_") as tmp:
        dirs = {w: make_variant(tmp, w) for w in widths}
        logs = {w: build_log(args, d, env, tmp) for w, d in dirs.items()}
        runs = {w: [] for w in widths}
        for _ in range(args.runs):
            for w in widths:
                runs[w].append(render(args, dirs[w], env, tmp))
    label = {w: ("runtime's choice" if w is None else f"forced {w}" + (" (as shipped)" if w == 1 else "")) for w in widths}
    first = runs[widths[0]][0]
    print(f"device: {first['device']}; scene {os.path.relpath(args.scene, REPO)}, "
          f"{first['width']}x{first['height']}, {args.spp} spp, {args.runs} interleaved runs\n")
    print("| variant | shading kernels built (width; 0 = scalar) | largest candidate: width, gathers, scatters |")
    print("|---|---|---|")
    for w in widths:
        kernels, big = logs[w]
        kern = ", ".join(f"{k[len('kernel_shade_'):]} {v}" for k, v in sorted(kernels.items()))
        print(f"| {label[w]} | {kern} | {'%d, %d, %d' % big if big else '-'} |")
    stages = [st["name"] for st in first["stages"]]
    print("\n| stage | " + " | ".join(f"{label[w]} (s, median)" for w in widths) + " |")
    print("|---|" + "---:|" * len(widths))
    for name in stages:
        cells = []
        for w in widths:
            secs = [next(st["seconds"] for st in r["stages"] if st["name"] == name) for r in runs[w]]
            cells.append(f"{statistics.median(secs):.3f}")
        print(f"| {name} | " + " | ".join(cells) + " |")
    print("| (render, Msamples/s, each run) | " + " | ".join(
        ", ".join(f"{r['samples'] / r['render_seconds'] / 1e6:.3f}" for r in runs[w]) for w in widths) + " |")


if __name__ == "__main__":
    main()

#!/usr/bin/env python3
"""Renders an archwave scene (the subset of bench/race_scene.py) with Mitsuba 3.

  DRJIT_LIBLLVM_PATH=/usr/lib/x86_64-linux-gnu/libLLVM-19.so \
  python3 bench/export_mitsuba.py SCENE.json --out DIR --result RESULT.json \
      [--width W --height H] [--variant llvm_ad_rgb] --job NAME:SAMPLER:SPP:SEED ...

Each job (SAMPLER = multijitter or independent; SPP may be fitN: the largest power of two that
the previous jobs' speed says fits in N seconds) writes DIR/NAME.npy (float32, height x width x
RGB, radiance times the camera's exposure scale, as archwave's EXR). The scene is built once;
before a sampler's first timed job it is rendered once untimed (warm-up: Dr.Jit traces and
compiles the kernels, or finds them in its cache). RESULT.json holds the version, the
start-up costs (import, variant, scene build, warm-ups) and per job the wall time of
mi.render until the image is in memory, and the part of it Dr.Jit spent compiling kernels
(its kernel history), which the suite leaves out of the render time. `--dict` prints the
scene dictionary instead of rendering.

Conventions, each checked against archwave by the race (scripts/archwave_bench/race.py):
- archwave's max_depth counts scattering events; Mitsuba's counts path segments: + 1.
- Mitsuba's diffuse and conductor BSDFs are black from behind: wrapped in `twosided`, since
  archwave shades both sides. Glass (`dielectric`) tells inside from outside by the normal:
  boxes and spheres have outward normals, meshes keep their own.
- archwave's lights are opaque and black apart from their emission: the emitters' shapes get
  a black diffuse BSDF. A quad light is a `rectangle` whose normal is edge_u x edge_v (one
  sided, as archwave's); a sphere light a `sphere` (cone-sampled, as archwave's).
- Box filter of radius 0.5 (one pixel wide: every sample lands in its own pixel), hdrfilm in
  RGB float32; the perspective camera's fov is vertical (fov_axis y).
- Built-in shapes: quads as `rectangle`, boxes as `cube`, spheres as the analytic `sphere`
  when the transform keeps them spheres (archwave tessellates 128 x 64 with smooth normals);
  meshes and anything else as a PLY of archwave's own triangles.
"""

import argparse
import os
import shutil
import struct
import sys
import tempfile
import time

T_START = time.time()
sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
import race_scene  # noqa: E402

MAX_LANES = 1 << 24


def rgb(c):
    return {"type": "rgb", "value": [float(x) for x in c]}


def _black():
    return {"type": "diffuse", "reflectance": rgb([0, 0, 0])}


def bsdf(m):
    if m["kind"] == "lambert":
        return {"type": "twosided", "bsdf": {"type": "diffuse", "reflectance": rgb(m["albedo"])}}
    if m["kind"] == "glass":
        return {"type": "dielectric", "int_ior": m["ior"], "ext_ior": 1.0, "specular_transmittance": rgb(m["tint"])}
    if m["alpha"] < race_scene.MIRROR_ALPHA:
        inner = {"type": "conductor", "material": "none", "specular_reflectance": rgb(m["color"])}
    else:
        inner = {"type": "roughconductor", "material": "none", "distribution": m["distribution"],
                 "alpha": m["alpha"], "specular_reflectance": rgb(m["color"])}
    return {"type": "twosided", "bsdf": inner}


def _matrix(mi, rows):
    return mi.ScalarTransform4f([[float(x) for x in r] for r in rows])


def _rect_rows(corner, eu, ev):
    """Maps Mitsuba's rectangle ([-1, 1]^2 at z = 0, normal +z) onto the parallelogram."""
    n = race_scene.normalize(race_scene.cross(eu, ev))
    c = [corner[k] + 0.5 * eu[k] + 0.5 * ev[k] for k in range(3)]
    return [[0.5 * eu[k], 0.5 * ev[k], n[k], c[k]] for k in range(3)] + [[0, 0, 0, 1]]


def write_ply(path, pos, nrm, faces):
    """Binary little-endian PLY of triangles (faces with more corners are fanned)."""
    tris = [[f[0], f[k], f[k + 1]] for f in faces for k in range(1, len(f) - 1)]
    head = ["ply", "format binary_little_endian 1.0", f"element vertex {len(pos)}",
            "property float x", "property float y", "property float z"]
    if nrm:
        head += ["property float nx", "property float ny", "property float nz"]
    head += [f"element face {len(tris)}", "property list uchar int vertex_indices", "end_header"]
    with open(path, "wb") as f:
        f.write(("\n".join(head) + "\n").encode())
        for i, p in enumerate(pos):
            f.write(struct.pack("<3f", *p))
            if nrm:
                f.write(struct.pack("<3f", *nrm[i]))
        for t in tris:
            f.write(struct.pack("<B3i", 3, *t))


def shape(mi, o, mat, tmp):
    m = o["matrix"]
    if o["shape"] == "quad":
        rows = race_scene.mat_mul(m, _rect_rows(o["corner"], o["edge_u"], o["edge_v"]))
        return {"type": "rectangle", "to_world": _matrix(mi, rows), "bsdf": mat}
    if o["shape"] == "box":
        lo, hi = o["min"], o["max"]
        box = [[0.5 * (hi[0] - lo[0]), 0, 0, 0.5 * (hi[0] + lo[0])],
               [0, 0.5 * (hi[1] - lo[1]), 0, 0.5 * (hi[1] + lo[1])],
               [0, 0, 0.5 * (hi[2] - lo[2]), 0.5 * (hi[2] + lo[2])], [0, 0, 0, 1]]
        if min(hi[k] - lo[k] for k in range(3)) > 0:
            return {"type": "cube", "to_world": _matrix(mi, race_scene.mat_mul(m, box)), "bsdf": mat}
    if o["shape"] == "sphere":
        s = race_scene.similarity_scale(m)
        if s is not None:
            return {"type": "sphere", "center": race_scene.transform_point(m, o["center"]),
                    "radius": s * o["radius"], "bsdf": mat}
    pos, nrm, faces = race_scene.triangles(o)
    path = os.path.join(tmp, f"{len(os.listdir(tmp))}.ply")
    write_ply(path, pos, nrm, faces)
    return {"type": "ply", "filename": path, "face_normals": nrm is None, "bsdf": mat}


def scene_dict(mi, d, tmp):
    out = {"type": "scene", "integrator": {"type": "path", "max_depth": d["max_depth"] + 1}}
    if max(d["environment"]) > 0:
        out["environment"] = {"type": "constant", "radiance": rgb(d["environment"])}
    for i, l in enumerate(d["lights"]):
        if l["type"] == "point":
            out[f"light_{i}"] = {"type": "point", "position": l["position"], "intensity": rgb(l["intensity"])}
        elif l["type"] == "quad":
            out[f"light_{i}"] = {"type": "rectangle", "bsdf": _black(),
                                 "to_world": _matrix(mi, _rect_rows(l["corner"], l["edge_u"], l["edge_v"])),
                                 "emitter": {"type": "area", "radiance": rgb(l["radiance"])}}
        else:
            out[f"light_{i}"] = {"type": "sphere", "center": l["center"], "radius": l["radius"], "bsdf": _black(),
                                 "emitter": {"type": "area", "radiance": rgb(l["radiance"])}}
    bsdfs = {name: bsdf(m) for name, m in d["materials"].items()}
    for i, o in enumerate(d["objects"]):
        out[f"object_{i}"] = shape(mi, o, bsdfs[o["material"]], tmp)
    return out


def sensor_dict(mi, d, sampler, spp, seed):
    c = d["camera"]
    return {"type": "perspective", "fov": c["fov"], "fov_axis": "y", "near_clip": 1e-3, "far_clip": 1e6,
            "to_world": mi.ScalarTransform4f().look_at(origin=c["position"], target=c["look_at"], up=c["up"]),
            "sampler": {"type": sampler, "sample_count": spp, "seed": seed},
            "film": {"type": "hdrfilm", "width": d["width"], "height": d["height"], "rfilter": {"type": "box"},
                     "pixel_format": "rgb", "component_format": "float32"}}


def compile_ms(dr, history):
    """Milliseconds of kernel compilation in a kernel history (cache misses' backend time)."""
    return sum(k.get("backend_time", 0.0) + k.get("codegen_time", 0.0) for k in history
               if not k.get("cache_hit", True))


def main(argv):
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    race_scene.exporter_arguments(ap)
    ap.add_argument("--variant", default="llvm_ad_rgb")
    ap.add_argument("--job", action="append", default=[], help="NAME:SAMPLER:SPP:SEED")
    ap.add_argument("--dict", action="store_true", help="print the scene dictionary and exit")
    args = ap.parse_args(argv)
    try:
        d = race_scene.describe(args.scene, args.width, args.height, args.geometry)
    except race_scene.Unsupported as e:
        print(f"export_mitsuba: {args.scene}: {e}", file=sys.stderr)
        return 3
    t = {"python_start": T_START - args.t0 if args.t0 else None}
    t0 = time.perf_counter()
    import drjit as dr
    import mitsuba as mi
    import numpy as np
    t["import"] = time.perf_counter() - t0
    t0 = time.perf_counter()
    mi.set_variant(args.variant)
    dr.set_flag(dr.JitFlag.KernelHistory, True)
    t["variant"] = time.perf_counter() - t0
    tmp = tempfile.mkdtemp(prefix="race_mitsuba_")
    if args.dict:
        print(scene_dict(mi, d, tmp))
        return 0
    t0 = time.perf_counter()
    scene = mi.load_dict(scene_dict(mi, d, tmp))
    t["scene_build"] = time.perf_counter() - t0
    shutil.rmtree(tmp, ignore_errors=True)  # the PLY files are loaded by now
    dr.kernel_history()
    os.makedirs(args.out, exist_ok=True)
    result = {"peer": "mitsuba", "version": mi.__version__, "drjit": dr.__version__, "variant": args.variant,
              "threads": dr.thread_count(), "llvm": os.environ.get("DRJIT_LIBLLVM_PATH", ""),
              "startup": t, "warmups": [], "jobs": []}
    warmed = set()
    for spec in args.job:
        name, sampler, spp, seed = spec.split(":")
        spp, seed = race_scene.job_spp(spp, result["jobs"]), int(seed)
        if sampler not in warmed:
            # Untimed: the first render of a sampler traces and compiles (or loads) its kernels.
            t0 = time.perf_counter()
            sensor = mi.load_dict(sensor_dict(mi, d, sampler, spp, seed + 7919))
            img = mi.render(scene, sensor=sensor, spp=spp, seed=seed + 7919)
            np.array(img)
            hist = dr.kernel_history()
            result["warmups"].append({"sampler": sampler, "spp": spp, "wall": time.perf_counter() - t0,
                                      "compile": compile_ms(dr, hist) / 1e3,
                                      "kernels": len(hist), "cache_misses": sum(1 for k in hist if not k.get("cache_hit", True))})
            warmed.add(sampler)
        # One pass per at most MAX_LANES samples (Mitsuba renders a pass as one wavefront);
        # the timed renders of the race are single passes.
        passes = max(1, -(-spp * d["width"] * d["height"] // MAX_LANES))
        per = [spp // passes + (1 if k < spp % passes else 0) for k in range(passes)]
        sensor = mi.load_dict(sensor_dict(mi, d, sampler, per[0], seed))
        dr.kernel_history()
        t0 = time.perf_counter()
        arr = 0
        for k, n in enumerate(per):
            img = mi.render(scene, sensor=sensor, spp=n, seed=seed + 104729 * k)
            arr = arr + np.array(img, dtype=np.float32) * (n / spp)  # waits for the kernels, copies the image out
        wall = time.perf_counter() - t0
        hist = dr.kernel_history()
        comp = compile_ms(dr, hist) / 1e3
        np.save(os.path.join(args.out, name + ".npy"), arr[:, :, :3] * np.float32(d["exposure"]))
        result["jobs"].append({"name": name, "sampler": sampler, "spp": spp, "seed": seed, "passes": passes, "wall": wall,
                               "compile": comp, "seconds": wall - comp,
                               "execution": sum(k.get("execution_time", 0.0) for k in hist) / 1e3})
    race_scene.write_result(result, args.result, T_START)
    return 0


if __name__ == "__main__":
    sys.exit(main(sys.argv[1:]))

"""Renders an archwave scene (the subset of bench/race_scene.py) with Blender's Cycles.

  blender -b --factory-startup --debug-cycles --python bench/export_cycles.py -- \
      SCENE.json --out DIR --result RESULT.json [--width W --height H] [--t0 EPOCH] \
      --job NAME:SPP:SEED ...

Each job (SPP may be fitN: the largest power of two that the previous jobs' speed says fits in
N seconds) writes DIR/NAME.exr (32-bit float RGB, radiance times the camera's exposure scale, as
archwave's EXR). The scene is built once, rendered once at 1 spp untimed (warm-up), then once
per job. Cycles' own log (`--debug-cycles`, stderr, captured per job) gives the render time
without synchronisation (path tracing only) and the total (with the scene's device update:
BVH, shaders, lights); RESULT.json holds both, the wall time of the render call, and the
process's start-up and scene-build times. Settings: CPU, samples = spp, adaptive sampling,
denoising, clamping (direct and indirect) and glossy filtering off, box pixel filter of width
1, caustics on, Cycles' default sampling pattern, all cores.

Conventions, each checked against archwave by the race (scripts/archwave_bench/race.py):
- Bounces: Cycles' max_bounces counts bounces after the first hit (0 = direct light only),
  archwave's max_depth counts scattering events (1 = direct light only): max_depth - 1, for
  the total and each of diffuse, glossy and transmission.
- Cycles' lights are not geometry: rays pass through them (as transparent bounces) and they
  cast no shadows. archwave's quad lights are opaque and black behind, so each quad light
  also gets a black quad just behind its plane (1e-3 of its size); point lights are not hit
  by rays in either renderer. A sphere light becomes a point light with that radius, which
  Cycles 3.4 treats as a disc facing the shading point: the irradiance differs from the
  sphere's by about (radius / distance)^2 (scenes keep that small) and the disc does not
  occlude.
- Light units (Blender's Watts): area light radiance L = P / (4 A), point light intensity
  I = P / (4 pi), radiance of a point light of radius r: P / (4 pi^2 r^2).
- Lights are made visible to the camera (Blender hides them by default).
- Surfaces are two-sided in Cycles, as in archwave. Glass tells inside from outside by the
  geometric normal (the winding): boxes and spheres are wound outwards. Every object is
  archwave's own triangles (`archwave SCENE --export-geometry`, race_scene.read_geometry) with
  its vertex normals (custom split normals).
- Roughness: Cycles' roughness r has alpha = r^2.
"""

import math
import os
import sys
import time

T_START = time.time()
sys.dont_write_bytecode = True  # Blender ignores PYTHONDONTWRITEBYTECODE; keep bench/ clean
sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
import race_scene  # noqa: E402

import bpy  # noqa: E402
from mathutils import Matrix  # noqa: E402


def _node_material(name, build):
    mat = bpy.data.materials.new(name)
    mat.use_nodes = True
    nt = mat.node_tree
    nt.nodes.clear()
    out = nt.nodes.new("ShaderNodeOutputMaterial")
    nt.links.new(build(nt), out.inputs["Surface"])
    return mat


def _rgba(c):
    return (float(c[0]), float(c[1]), float(c[2]), 1.0)


def material(name, m):
    def diffuse(albedo):
        def build(nt):
            n = nt.nodes.new("ShaderNodeBsdfDiffuse")
            n.inputs["Color"].default_value = _rgba(albedo)
            n.inputs["Roughness"].default_value = 0.0
            return n.outputs[0]
        return build

    if m is None:
        return _node_material(name, diffuse([0, 0, 0]))
    if m["kind"] == "lambert":
        return _node_material(name, diffuse(m["albedo"]))
    if m["kind"] == "mirror":
        def build(nt):
            n = nt.nodes.new("ShaderNodeBsdfGlossy")
            if m["alpha"] < race_scene.MIRROR_ALPHA:
                n.distribution = "SHARP"
            else:
                n.distribution = "GGX" if m["distribution"] == "ggx" else "BECKMANN"
                n.inputs["Roughness"].default_value = math.sqrt(m["alpha"])
            n.inputs["Color"].default_value = _rgba(m["color"])
            return n.outputs[0]
        return _node_material(name, build)

    def glass(nt):
        if m["tint"] == [1.0, 1.0, 1.0]:
            n = nt.nodes.new("ShaderNodeBsdfGlass")
            n.distribution = "SHARP"
            n.inputs["IOR"].default_value = m["ior"]
            n.inputs["Color"].default_value = (1, 1, 1, 1)
            return n.outputs[0]
        # Tinted transmission only: Fresnel-weighted mix of a white mirror and tinted refraction.
        fres = nt.nodes.new("ShaderNodeFresnel")
        fres.inputs["IOR"].default_value = m["ior"]
        refr = nt.nodes.new("ShaderNodeBsdfRefraction")
        refr.distribution = "SHARP"
        refr.inputs["IOR"].default_value = m["ior"]
        refr.inputs["Color"].default_value = _rgba(m["tint"])
        refl = nt.nodes.new("ShaderNodeBsdfGlossy")
        refl.distribution = "SHARP"
        refl.inputs["Color"].default_value = (1, 1, 1, 1)
        mix = nt.nodes.new("ShaderNodeMixShader")
        nt.links.new(fres.outputs[0], mix.inputs[0])
        nt.links.new(refr.outputs[0], mix.inputs[1])
        nt.links.new(refl.outputs[0], mix.inputs[2])
        return mix.outputs[0]
    return _node_material(name, glass)


def add_mesh(name, pos, nrm, faces, mat):
    me = bpy.data.meshes.new(name)
    me.from_pydata([tuple(p) for p in pos], [], [tuple(f) for f in faces])
    me.validate()
    if nrm is not None:
        for poly in me.polygons:
            poly.use_smooth = True
        me.use_auto_smooth = True
        me.auto_smooth_angle = math.pi
        me.normals_split_custom_set_from_vertices([tuple(n) for n in nrm])
    me.materials.append(mat)
    ob = bpy.data.objects.new(name, me)
    bpy.context.scene.collection.objects.link(ob)
    return ob


def add_light(name, kind, energy, color, matrix=None, location=None, **props):
    li = bpy.data.lights.new(name, kind)
    li.energy = energy
    li.color = color
    for k, v in props.items():
        setattr(li, k, v)
    ob = bpy.data.objects.new(name, li)
    if matrix is not None:
        ob.matrix_world = matrix
    if location is not None:
        ob.location = location
    ob.visible_camera = True
    bpy.context.scene.collection.objects.link(ob)
    return ob


def _power(values, scale):
    """(Blender energy, colour) for per-channel power scale * values."""
    peak = max(values)
    if peak <= 0:
        return 0.0, (1.0, 1.0, 1.0)
    return scale * peak, tuple(v / peak for v in values)


def lights(d, black):
    for i, l in enumerate(d["lights"]):
        if l["type"] == "point":
            e, c = _power(l["intensity"], 4.0 * math.pi)
            add_light(f"light_{i}", "POINT", e, c, location=l["position"], shadow_soft_size=0.0)
        elif l["type"] == "sphere":
            r = l["radius"]
            e, c = _power(l["radiance"], 4.0 * math.pi ** 2 * r * r)
            add_light(f"light_{i}", "POINT", e, c, location=l["center"], shadow_soft_size=r)
        else:
            eu, ev = l["edge_u"], l["edge_v"]
            lu, lv = math.sqrt(race_scene.dot(eu, eu)), math.sqrt(race_scene.dot(ev, ev))
            if abs(race_scene.dot(eu, ev)) > 1e-6 * lu * lv:
                raise race_scene.Unsupported(f"lights[{i}].edge_v: not orthogonal to edge_u (Cycles' area "
                                             "lights are rectangles)")
            n = race_scene.normalize(race_scene.cross(eu, ev))
            x = [-a / lu for a in eu]  # local X, Y span the rectangle; local -Z is the emitting side
            y = [a / lv for a in ev]
            z = [-a for a in n]
            c = [l["corner"][k] + 0.5 * eu[k] + 0.5 * ev[k] for k in range(3)]
            mat = Matrix([[x[k], y[k], z[k], c[k]] for k in range(3)] + [[0, 0, 0, 1]])
            e, col = _power(l["radiance"], 4.0 * lu * lv)
            add_light(f"light_{i}", "AREA", e, col, matrix=mat, shape="RECTANGLE", size=lu, size_y=lv)
            # archwave's light is opaque and black behind: a black quad just behind its plane.
            eps = 1e-3 * max(lu, lv)
            corner = [l["corner"][k] - eps * n[k] for k in range(3)]
            pos = [corner, [corner[k] + eu[k] for k in range(3)], [corner[k] + eu[k] + ev[k] for k in range(3)],
                   [corner[k] + ev[k] for k in range(3)]]
            add_mesh(f"light_{i}_back", pos, None, [[0, 1, 2, 3]], black)


def camera(d):
    c = d["camera"]
    fwd = race_scene.normalize([c["look_at"][k] - c["position"][k] for k in range(3)])
    right = race_scene.normalize(race_scene.cross(fwd, c["up"]))
    up = race_scene.cross(right, fwd)
    cam = bpy.data.cameras.new("camera")
    cam.sensor_fit = "VERTICAL"
    cam.sensor_height = 24.0
    cam.lens_unit = "FOV"
    cam.angle_y = math.radians(c["fov"])
    cam.clip_start = 1e-3
    cam.clip_end = 1e6
    ob = bpy.data.objects.new("camera", cam)
    ob.matrix_world = Matrix([[right[k], up[k], -fwd[k], c["position"][k]] for k in range(3)] + [[0, 0, 0, 1]])
    bpy.context.scene.collection.objects.link(ob)
    bpy.context.scene.camera = ob


def settings(d):
    sc = bpy.context.scene
    sc.render.engine = "CYCLES"
    cy = sc.cycles
    cy.device = "CPU"
    cy.use_adaptive_sampling = False
    cy.use_denoising = False
    cy.sample_clamp_direct = 0.0
    cy.sample_clamp_indirect = 0.0
    cy.blur_glossy = 0.0
    cy.caustics_reflective = True
    cy.caustics_refractive = True
    cy.pixel_filter_type = "BOX"
    cy.filter_width = 1.0
    bounces = d["max_depth"] - 1
    cy.max_bounces = bounces
    cy.diffuse_bounces = bounces
    cy.glossy_bounces = bounces
    cy.transmission_bounces = bounces
    cy.volume_bounces = 0
    cy.transparent_max_bounces = 64  # rays pass through Cycles' lights as transparent bounces
    cy.film_exposure = d["exposure"]
    sc.render.threads_mode = "AUTO"
    sc.render.resolution_x = d["width"]
    sc.render.resolution_y = d["height"]
    sc.render.resolution_percentage = 100
    sc.render.pixel_aspect_x = sc.render.pixel_aspect_y = 1.0
    sc.render.film_transparent = False
    sc.render.dither_intensity = 0.0
    sc.render.use_compositing = False
    sc.render.use_sequencer = False
    sc.view_settings.view_transform = "Standard"
    sc.view_settings.look = "None"
    sc.view_settings.exposure = 0.0
    sc.view_settings.gamma = 1.0
    im = sc.render.image_settings
    im.file_format = "OPEN_EXR"
    im.color_depth = "32"
    im.color_mode = "RGB"
    im.exr_codec = "ZIP"
    world = bpy.data.worlds.new("world")
    world.use_nodes = True
    bg = world.node_tree.nodes["Background"]
    bg.inputs["Color"].default_value = _rgba(d["environment"])
    bg.inputs["Strength"].default_value = 1.0
    sc.world = world


def build(d):
    bpy.ops.wm.read_factory_settings(use_empty=True)
    settings(d)
    camera(d)
    black = material("__black", None)
    lights(d, black)
    mats = {name: material(name, m) for name, m in d["materials"].items()}
    for i, o in enumerate(d["objects"]):
        pos, nrm, faces = race_scene.triangles(o)
        add_mesh(f"object_{i}", pos, nrm, faces, mats[o["material"]])


def _cycles_times(log_path):
    """(render time without synchronisation, total render time) from Cycles' log."""
    pt = tot = None
    with open(log_path, errors="replace") as f:
        for line in f:
            if "Render time (without synchronization):" in line:
                pt = float(line.rsplit(":", 1)[1])
            elif "Total render time:" in line:
                tot = float(line.rsplit(":", 1)[1])
    return pt, tot


def render(path, spp, seed, log_path):
    sc = bpy.context.scene
    sc.cycles.samples = spp
    sc.cycles.seed = seed
    sc.render.filepath = path
    sys.stderr.flush()
    saved = os.dup(2)
    fd = os.open(log_path, os.O_WRONLY | os.O_CREAT | os.O_TRUNC, 0o644)
    os.dup2(fd, 2)
    try:
        t0 = time.perf_counter()
        bpy.ops.render.render(write_still=True)
        wall = time.perf_counter() - t0
    finally:
        sys.stderr.flush()
        os.dup2(saved, 2)
        os.close(fd)
        os.close(saved)
    pt, tot = _cycles_times(log_path)
    return wall, pt, tot


def main(argv):
    import argparse
    ap = argparse.ArgumentParser(prog="export_cycles.py")
    race_scene.exporter_arguments(ap)
    ap.add_argument("--job", action="append", default=[], help="NAME:SPP:SEED")
    args = ap.parse_args(argv)
    try:
        d = race_scene.describe(args.scene, args.width, args.height, args.geometry)
        t0 = time.perf_counter()
        build(d)
        t_build = time.perf_counter() - t0
    except race_scene.Unsupported as e:
        print(f"export_cycles: {args.scene}: {e}", file=sys.stderr)
        return 3
    os.makedirs(args.out, exist_ok=True)
    result = {"peer": "cycles", "version": bpy.app.version_string,
              "sampling_pattern": bpy.context.scene.cycles.sampling_pattern,
              "threads": bpy.context.scene.render.threads,
              "startup": {"blender_start": T_START - args.t0 if args.t0 else None, "scene_build": t_build},
              "jobs": []}
    log = os.path.join(args.out, "cycles_warmup.log")
    wall, pt, tot = render(os.path.join(args.out, "cycles_warmup.exr"), 1, 7919, log)
    result["warmup"] = {"spp": 1, "wall": wall, "render": pt, "total": tot}
    for spec in args.job:
        name, spp, seed = spec.split(":")
        spp = race_scene.job_spp(spp, result["jobs"])
        log = os.path.join(args.out, name + ".log")
        wall, pt, tot = render(os.path.join(args.out, name + ".exr"), spp, int(seed), log)
        if pt is None:
            raise SystemExit(f"export_cycles: no render time in Cycles' log {log} (run blender with --debug-cycles)")
        result["jobs"].append({"name": name, "spp": int(spp), "seed": int(seed), "wall": wall, "seconds": pt,
                               "total": tot})
    race_scene.write_result(result, args.result, T_START)
    return 0


if __name__ == "__main__":
    argv = sys.argv[sys.argv.index("--") + 1:] if "--" in sys.argv else []
    code = main(argv)
    if code:
        sys.exit(code)

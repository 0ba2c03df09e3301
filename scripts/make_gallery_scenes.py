#!/usr/bin/env python3
"""Writes scenes/docs/*.json: the material documentation's worked examples, on one stage.

Every example shares the stage (floor, backdrop, camera, a soft area light and a dim sky) so
that the pictures in docs/gallery.md differ only in what the example is about. Re-run after
changing the stage; the JSON files are committed so they can be rendered without Python.
"""
import json
import math
import os
import random
import struct
import zlib

HERE = os.path.dirname(os.path.abspath(__file__))
OUT = os.path.join(HERE, "..", "scenes", "docs")

STAGE_MATERIALS = {
    "stage_floor": {"diffuse": {"color": [0.55, 0.55, 0.55]}, "reflection": {"weight": 0}},
    "stage_back": {"diffuse": {"color": [0.35, 0.4, 0.45]}, "reflection": {"weight": 0}},
}
STAGE_OBJECTS = [
    {"shape": "quad", "corner": [-30, 0, 30], "edge_u": [60, 0, 0], "edge_v": [0, 0, -60], "material": "stage_floor"},
    {"shape": "quad", "corner": [-30, 0, -6], "edge_u": [60, 0, 0], "edge_v": [0, 30, 0], "material": "stage_back"},
]
AREA = {"type": "quad", "corner": [-1.5, 6, -0.5], "edge_u": [3, 0, 0], "edge_v": [0, 0, 2],
        "color": [1, 0.97, 0.92], "intensity": 6}


def scene(materials, objects, lights=None, width=400, height=300, spp=128, gi=True, env=0.25,
          camera=None, max_depth=10):
    mats = dict(STAGE_MATERIALS)
    mats.update(materials)
    return {
        "render": {"width": width, "height": height, "spp": spp, "seed": 0, "max_depth": max_depth, "gi": gi},
        "camera": camera or {"position": [0, 2.2, 8], "look_at": [0, 1, 0], "up": [0, 1, 0], "fov": 30},
        "environment": {"type": "constant", "color": [0.7, 0.8, 1.0], "intensity": env},
        "lights": lights if lights is not None else [AREA],
        "materials": mats,
        "objects": STAGE_OBJECTS + objects,
    }


def sphere(material, x=0.0, r=1.0, y=None):
    return {"shape": "sphere", "center": [x, r if y is None else y, 0], "radius": r, "material": material}


def row(names, r=0.9, gap=2.1):
    n = len(names)
    return [sphere(m, x=(i - (n - 1) / 2) * gap, r=r) for i, m in enumerate(names)]


EXAMPLES = {}

# Diffuse: tint 0.8, roughness 0 (Lambert) and 1 (energy-preserving Oren-Nayar), no GI.
for rough in (0, 1):
    EXAMPLES["diffuse_roughness_%d" % rough] = scene(
        {"s": {"diffuse": {"color": [0.8, 0.8, 0.8], "roughness": rough}, "reflection": {"weight": 0}}},
        [sphere("s")], gi=False, env=0.0)

# Fresnel plastic: curve facing 0.2, mirror-sharp.
EXAMPLES["fresnel_plastic"] = scene(
    {"s": {"diffuse": {"color": [0.6, 0.05, 0.05]},
           "reflection": {"weight": 1, "glossiness": 1, "fresnel": {"use_ior": False, "facing": 0.2, "perpendicular": 1}}}},
    [sphere("s")])

# Mirror: facing 1.
EXAMPLES["mirror"] = scene(
    {"s": {"diffuse": {"color": [0.6, 0.05, 0.05]},
           "reflection": {"weight": 1, "glossiness": 1, "fresnel": {"use_ior": False, "facing": 1, "perpendicular": 1}}}},
    [sphere("s")])

# Glossy Fresnel: facing 0.5, glossiness 0.6, 64 samples.
EXAMPLES["glossy_fresnel"] = scene(
    {"s": {"diffuse": {"color": [0.1, 0.2, 0.5]},
           "reflection": {"weight": 1, "glossiness": 0.6, "samples": 64,
                          "fresnel": {"use_ior": False, "facing": 0.5, "perpendicular": 1}}}},
    [sphere("s")])

# Highlights of a green area light and a red point light at glossiness 1.0, 0.5, 0.0.
hl_lights = [
    {"type": "quad", "corner": [-4, 3, 3], "edge_u": [1.5, 0, 0], "edge_v": [0, 1.5, 0.5], "color": [0.2, 1, 0.2], "intensity": 12},
    {"type": "point", "position": [4, 4, 4], "color": [1, 0.15, 0.15], "intensity": 12},
]
EXAMPLES["highlights"] = scene(
    {"g%d" % i: {"diffuse": {"color": [0.05, 0.05, 0.05]},
                 "reflection": {"weight": 1, "glossiness": g, "fresnel": {"use_ior": False, "facing": 0.5, "perpendicular": 1}}}
     for i, g in enumerate((1.0, 0.5, 0.0))},
    row(["g0", "g1", "g2"]), lights=hl_lights, env=0.15)

# Bronze metal with anisotropy -0.8.
EXAMPLES["bronze_anisotropic"] = scene(
    {"s": {"diffuse": {"color": [0.55, 0.35, 0.15]}, "metal": True,
           "reflection": {"weight": 1, "glossiness": 0.6, "brdf": "ggx",
                          "fresnel": {"use_ior": False, "facing": 0.8, "perpendicular": 1}},
           "anisotropy": {"amount": -0.8, "orientation": "uv"}}},
    [sphere("s")])

# Refraction: IOR 1.4, weight 0.8, glossiness 1.0 and 0.6.
for g in (1.0, 0.6):
    EXAMPLES["refraction_glossiness_%s" % str(g).replace(".", "")] = scene(
        {"s": {"diffuse": {"color": [0.5, 0.5, 0.5]}, "reflection": {"weight": 1, "glossiness": 1},
               "refraction": {"weight": 0.8, "ior": 1.4, "glossiness": g}}},
        [sphere("s")])

# Fog: a sphere of radius 4 with fog distance 7 (fade to black), seen from further away.
EXAMPLES["fog_sphere"] = scene(
    {"s": {"diffuse": {"weight": 0}, "reflection": {"weight": 1, "glossiness": 1},
           "refraction": {"weight": 1, "ior": 1.4, "fog": {"enable": True, "distance": 7}}}},
    [sphere("s", r=4)], camera={"position": [0, 5, 22], "look_at": [0, 3.5, 0], "up": [0, 1, 0], "fov": 30})

# Red glass: fog with end colour (0.53, 0.1, 0.1) at distance 1, against a tinted refraction colour.
EXAMPLES["red_glass_fog"] = scene(
    {"s": {"diffuse": {"weight": 0}, "reflection": {"weight": 1, "glossiness": 1},
           "refraction": {"weight": 1, "ior": 1.5,
                          "fog": {"enable": True, "distance": 1, "use_end_color": True, "end_color": [0.53, 0.1, 0.1]}}}},
    [sphere("s")])
EXAMPLES["red_glass_tint"] = scene(
    {"s": {"diffuse": {"weight": 0}, "reflection": {"weight": 1, "glossiness": 1},
           "refraction": {"weight": 1, "ior": 1.5, "color": [0.53, 0.1, 0.1]}}},
    [sphere("s")])

# Partially reflective / refractive sphere (0.3 / 0.3), with and without weak internal reflections.
for skip in (True, False):
    EXAMPLES["partial_%s" % ("skip_weak" if skip else "all_internal")] = scene(
        {"s": {"diffuse": {"color": [0.5, 0.5, 0.5]}, "reflection": {"weight": 0.3, "glossiness": 1},
               "refraction": {"weight": 0.3, "ior": 1.5},
               "optimizations": {"skip_weak_internal_reflections": skip}}},
        [sphere("s")])


# --- Daylight: sun, sky and photographic exposure (issue 13) ---------------------------------
# Physically scaled units: the sun's intensity is its illuminance in lux on a surface facing it
# (a clear day: ~100000), the Preetham sky's radiance is in cd/m^2, and the camera exposes with
# the sunny-16 rule (ISO 100, 1/100 s, f/16: k = 1/25600, docs/scene-format.md).
SUNNY16 = {"mode": "photographic", "iso": 100, "shutter": 100, "f_number": 16}
SUN = {"type": "sun", "direction": [-0.45, -0.75, -0.5], "angle": 0.53, "intensity": 100000}
SKY = {"type": "sky", "turbidity": 3, "ground_albedo": 0.2}
MESHES = os.path.join(HERE, "..", "scenes", "meshes")


def write_lathe_obj(path, profile, segments=96, normals=None):
    """A surface of revolution about +Y from a (radius, height) profile, with smooth normals:
    each vertex's normal is the mean of its two profile segments' normals (or `normals`, one
    (n_r, n_y) per profile point), turned with it."""
    import math
    seg_n = []
    for (r0, y0), (r1, y1) in zip(profile, profile[1:]):
        dr, dy = r1 - r0, y1 - y0
        ln = math.hypot(dr, dy)
        seg_n.append((dy / ln, -dr / ln))  # outward for a profile walked upwards on the outside
    vn = list(normals or [])
    for k in range(len(profile) if not normals else 0):
        a = seg_n[max(k - 1, 0)]
        b = seg_n[min(k, len(seg_n) - 1)]
        nr, ny = a[0] + b[0], a[1] + b[1]
        ln = math.hypot(nr, ny) or 1.0
        vn.append((nr / ln, ny / ln))
    lines = ["# lathed cup, written by scripts/make_gallery_scenes.py"]
    for i in range(segments):
        phi = 2 * math.pi * i / segments
        c, s_ = math.cos(phi), math.sin(phi)
        for (r, y), (nr, ny) in zip(profile, vn):
            lines.append("v %.6f %.6f %.6f" % (r * c, y, r * s_))
            lines.append("vn %.6f %.6f %.6f" % (nr * c, ny, nr * s_))
    m = len(profile)
    for i in range(segments):
        j = (i + 1) % segments
        for k in range(m - 1):
            a, b = i * m + k + 1, j * m + k + 1
            lines.append("f %d//%d %d//%d %d//%d" % (a, a, b, b, b + 1, b + 1))
            lines.append("f %d//%d %d//%d %d//%d" % (a, a, b + 1, b + 1, a + 1, a + 1))
    with open(path, "w") as f:
        f.write("\n".join(lines) + "\n")


# The cup: outer wall up from the foot, a rounded rim, the inner wall down to a flat inside
# bottom (walked so that the normals face out of the material everywhere).
CUP_PROFILE = [(0.0, 0.0), (0.30, 0.0), (0.34, 0.03), (0.36, 0.10), (0.40, 0.40), (0.44, 0.72), (0.45, 0.75),
               (0.44, 0.77), (0.42, 0.76), (0.41, 0.72), (0.37, 0.42), (0.33, 0.12), (0.25, 0.06), (0.0, 0.06)]


def daylight(materials, objects, camera, width=400, height=300, spp=128, extra_lights=(), env=SKY, sun=SUN):
    return {
        "render": {"width": width, "height": height, "spp": spp, "seed": 0, "max_depth": 8},
        "camera": dict(camera, exposure=SUNNY16),
        "environment": env,
        "lights": [sun] + list(extra_lights),
        "materials": materials,
        "objects": objects,
    }


# The documentation's Fresnel example: a floor and a cup of the DEFAULT material (grey diffuse,
# reflection 0.6 with Fresnel from IOR 1.5) under sun and sky. Seen at a shallow angle the floor
# mirrors the sky; seen from above it is mostly its diffuse grey.
CUP_OBJECTS = [
    {"shape": "quad", "corner": [-40, 0, 40], "edge_u": [80, 0, 0], "edge_v": [0, 0, -80], "material": "default"},
    {"shape": "mesh", "file": "../meshes/cup.obj", "material": "default", "transform": {"scale": 1.5}},
]
EXAMPLES["sky_fresnel_shallow"] = daylight(
    {"default": {}}, CUP_OBJECTS, {"position": [0, 0.45, 6], "look_at": [0, 0.5, 0], "up": [0, 1, 0], "fov": 30})
EXAMPLES["sky_fresnel_steep"] = daylight(
    {"default": {}}, CUP_OBJECTS, {"position": [0, 5.5, 2.2], "look_at": [0, 0.3, 0], "up": [0, 1, 0], "fov": 30})


# The documentation's AO sequence: rings lying on a floor under sun and sky, photographic
# exposure. No GI; AO added as ambient light (ambient 0.2 where un-occluded, black where
# occluded, 256 samples); GI; GI with AO multiplied in (shadow 0.2). The rings: tori, lathed from a circle with exact normals.
def ring_profile(R, a, n=48):
    import math
    pts = [(R + a * math.cos(2 * math.pi * k / n), a + a * math.sin(2 * math.pi * k / n)) for k in range(n + 1)]
    nrm = [(math.cos(2 * math.pi * k / n), math.sin(2 * math.pi * k / n)) for k in range(n + 1)]
    return pts, nrm


RING_OBJECTS = [
    {"shape": "quad", "corner": [-40, 0, 40], "edge_u": [80, 0, 0], "edge_v": [0, 0, -80], "material": "ao_floor"},
    {"shape": "mesh", "file": "../meshes/ring.obj", "material": "ao_ring", "transform": {"translate": [-1.1, 0, 0.3]}},
    {"shape": "mesh", "file": "../meshes/ring.obj", "material": "ao_ring",
     "transform": {"translate": [0.9, 0, -0.4], "scale": 0.7}},
    {"shape": "mesh", "file": "../meshes/ring.obj", "material": "ao_ring",
     "transform": {"translate": [0.4, 0, 1.2], "scale": 0.45}},
]


def ao_materials(ao):
    base = {"diffuse": {"color": [0.4, 0.4, 0.4]}, "reflection": {"weight": 0}}
    floor, ring = dict(base), dict(base, diffuse={"color": [0.55, 0.42, 0.3]})
    if ao:
        floor["ao"] = ao
        ring["ao"] = ao
    return {"ao_floor": floor, "ao_ring": ring}


AO_CAMERA = {"position": [0, 3.2, 5.2], "look_at": [0, 0.2, 0.2], "up": [0, 1, 0], "fov": 35}
AO_SUN = {"type": "sun", "direction": [0.35, -0.8, -0.5], "angle": 0.53, "intensity": 100000}
for name, gi, ao in [
        ("ao_1_no_gi", False, None),
        # shadow_color 0: with the default 0.2 an ambient of 0.2 would make AO = lerp(0.2, 0.2, v)
        # a constant, and the add step a flat ambient term.
        ("ao_2_add", False, {"enable": True, "combine": "add", "ambient_color": [0.2, 0.2, 0.2],
                             "shadow_color": [0, 0, 0], "samples": 256, "max_distance": 2,
                             "exposure_compensation": True}),
        ("ao_3_gi", True, None),
        ("ao_4_gi_multiply", True, {"enable": True, "combine": "multiply", "shadow_color": [0.2, 0.2, 0.2],
                                    "samples": 256, "max_distance": 2})]:
    sc = daylight(ao_materials(ao), RING_OBJECTS, AO_CAMERA, sun=AO_SUN)
    sc["render"]["gi"] = gi
    EXAMPLES[name] = sc


# Many lights: a hall with a 20 x 15 grid of small sphere lights under its ceiling (300 lights:
# the light tree chooses among them) and a ring fixture modelled as incandescent geometry that
# opts in to light sampling (its 9216 triangles are lights too).
def many_lights_scene():
    lights = []
    for i in range(20):
        for j in range(15):
            x, z = -9.5 + i, -12 + j
            warm = (i + j) % 3 == 0
            lights.append({"type": "sphere", "center": [x, 3.4, z], "radius": 0.06,
                           "color": [1, 0.8, 0.55] if warm else [0.85, 0.9, 1], "intensity": 12})
    objects = [
        {"shape": "quad", "corner": [-10, 0, 3], "edge_u": [20, 0, 0], "edge_v": [0, 0, -16], "material": "hall_floor"},
        {"shape": "quad", "corner": [-10, 4, -13], "edge_u": [20, 0, 0], "edge_v": [0, 0, 16], "material": "hall_wall"},
        {"shape": "quad", "corner": [-10, 0, -13], "edge_u": [20, 0, 0], "edge_v": [0, 4, 0], "material": "hall_wall"},
        {"shape": "mesh", "file": "../meshes/ring.obj", "material": "fixture", "light_sampling": True,
         "transform": {"translate": [0, 1.6, -5], "rotate": [90, 0, 0], "scale": 1.2}},
        {"shape": "sphere", "center": [-2.5, 0.7, -3], "radius": 0.7, "material": "hall_ball"},
        {"shape": "sphere", "center": [2.6, 0.5, -2], "radius": 0.5, "material": "hall_metal"},
    ]
    materials = {
        "hall_floor": {"diffuse": {"color": [0.3, 0.3, 0.32]}, "reflection": {"weight": 0.5, "glossiness": 0.8}},
        "hall_wall": {"diffuse": {"color": [0.6, 0.58, 0.55]}, "reflection": {"weight": 0}},
        "fixture": {"diffuse": {"weight": 0}, "reflection": {"weight": 0},
                    "incandescent": {"color": [1, 0.55, 0.25], "scale": 3}},
        "hall_ball": {"diffuse": {"color": [0.7, 0.2, 0.15]}},
        "hall_metal": {"diffuse": {"color": [0.9, 0.8, 0.6]}, "metal": True,
                       "reflection": {"weight": 1, "glossiness": 0.85}},
    }
    return {
        "render": {"width": 400, "height": 300, "spp": 128, "seed": 0, "max_depth": 8},
        "camera": {"position": [0, 1.7, 2.5], "look_at": [0, 1.4, -5], "up": [0, 1, 0], "fov": 60},
        "environment": {"type": "constant", "color": [0, 0, 0]},
        "lights": lights,
        "materials": materials,
        "objects": objects,
    }


EXAMPLES["many_lights"] = many_lights_scene()


def room_with_window(w=6.0, h=3.0, d=5.0, win=(-0.9, 0.9, 0.9, 2.2)):
    """A closed box room (inside faces), one window hole in the +X wall: win = (z0, y0, z1, y1)."""
    z0, y0, z1, y1 = win
    hz = d / 2
    q = lambda corner, eu, ev, mat: {"shape": "quad", "corner": corner, "edge_u": eu, "edge_v": ev, "material": mat}
    x = w / 2
    objs = [
        q([-x, 0, hz], [w, 0, 0], [0, 0, -d], "floor"),          # floor, facing up
        q([-x, h, -hz], [w, 0, 0], [0, 0, d], "wall"),           # ceiling, facing down
        q([-x, 0, -hz], [w, 0, 0], [0, h, 0], "wall"),           # back wall (-Z), facing +Z
        q([x, 0, hz], [-w, 0, 0], [0, h, 0], "wall"),            # front wall (+Z), facing -Z
        q([-x, 0, hz], [0, 0, -d], [0, h, 0], "wall"),           # -X wall, facing +X
        # +X wall around the window, facing -X: below, above, and the two sides.
        q([x, 0, -hz], [0, 0, d], [0, y0, 0], "wall"),
        q([x, y1, -hz], [0, 0, d], [0, h - y1, 0], "wall"),
        q([x, y0, -hz], [0, 0, z0 + hz], [0, y1 - y0, 0], "wall"),
        q([x, y0, z1], [0, 0, hz - z1], [0, y1 - y0, 0], "wall"),
    ]
    return objs


# Indoors the photographer opens up about three stops from sunny 16: ISO 100, 1/125 s, f/5.6.
INTERIOR_EXPOSURE = {"mode": "photographic", "iso": 100, "shutter": 125, "f_number": 5.6}
EXAMPLES["sun_window_interior"] = daylight(
    {"floor": {"diffuse": {"color": [0.45, 0.32, 0.2]}, "reflection": {"weight": 0.3, "glossiness": 0.7}},
     "wall": {"diffuse": {"color": [0.8, 0.8, 0.78]}, "reflection": {"weight": 0}}},
    room_with_window() + [{"shape": "sphere", "center": [0.2, 0.5, 0.3], "radius": 0.5, "material": "floor"}],
    {"position": [-2.6, 1.5, 2.2], "look_at": [1.5, 0.8, -0.6], "up": [0, 1, 0], "fov": 60},
    sun={"type": "sun", "direction": [-0.7, -0.45, 0.25], "angle": 0.53, "intensity": 100000}, spp=256)
EXAMPLES["sun_window_interior"]["camera"]["exposure"] = INTERIOR_EXPOSURE

# A glTF interior (scripts/make_gltf_interior.py writes it: a node hierarchy, instanced chairs,
# textured tiles, glass, a clear-coated table, an emissive lamp) in the morning sun through its
# window; every material comes from the file (docs/gltf.md).
EXAMPLES["gltf_interior"] = daylight(
    {}, [{"shape": "mesh", "file": "../meshes/interior.gltf"}],
    {"position": [-1.9, 1.45, -0.25], "look_at": [0.5, 0.85, -2.6], "up": [0, 1, 0], "fov": 58},
    sun={"type": "sun", "direction": [0.35, -0.45, 1], "angle": 0.53, "intensity": 100000}, spp=256)
EXAMPLES["gltf_interior"]["camera"]["exposure"] = INTERIOR_EXPOSURE


# ---- textures (issue 14): made here, procedurally, as small PNGs ---------------------------
TEXTURES = os.path.join(OUT, "textures")


def write_png(path, width, height, channels, pixel):
    """8-bit PNG (grey, grey+alpha, RGB or RGBA); pixel(x, y) gives channel values in 0..1."""
    rows = bytearray()
    for y in range(height):
        rows.append(0)  # filter: none
        for x in range(width):
            for v in pixel(x, y):
                rows.append(max(0, min(255, int(round(v * 255)))))
    colour_type = {1: 0, 2: 4, 3: 2, 4: 6}[channels]

    def chunk(kind, data):
        return struct.pack(">I", len(data)) + kind + data + struct.pack(">I", zlib.crc32(kind + data) & 0xffffffff)
    png = b"\x89PNG\r\n\x1a\n" + chunk(b"IHDR", struct.pack(">IIBBBBB", width, height, 8, colour_type, 0, 0, 0))
    png += chunk(b"IDAT", zlib.compress(bytes(rows), 9)) + chunk(b"IEND", b"")
    with open(path, "wb") as f:
        f.write(png)


def pounded_texture(path, size=256, cells=90, seed=7):
    """Hammered metal: Voronoi cells (one dent each, tiling), each a random anisotropy rotation."""
    rnd = random.Random(seed)
    pts = [(rnd.random(), rnd.random(), rnd.random()) for _ in range(cells)]

    def pixel(x, y):
        u, v = (x + 0.5) / size, (y + 0.5) / size
        best, val = 9.0, 0.0
        for px, py, r in pts:
            dx = min(abs(u - px), 1 - abs(u - px))
            dy = min(abs(v - py), 1 - abs(v - py))
            d = dx * dx + dy * dy
            if d < best:
                best, val = d, r
        return (val,)
    write_png(path, size, size, 1, pixel)


def leaf_texture(path, size=256):
    """A leaf: green with lighter veins inside a pointed outline (alpha), transparent outside."""
    def pixel(x, y):
        u, v = (x + 0.5) / size, 1.0 - (y + 0.5) / size  # v up
        t = v  # along the leaf, stem at v = 0.05, tip at 0.95
        half = 0.42 * math.sin(math.pi * min(1.0, max(0.0, (t - 0.05) / 0.9))) ** 0.8
        inside = abs(u - 0.5) < half and 0.05 < t < 0.95
        stem = abs(u - 0.5) < 0.012 and t <= 0.08
        vein = abs(u - 0.5) < 0.008 or any(abs((v - 0.1 - 0.12 * k) - 0.6 * abs(u - 0.5)) < 0.006 for k in range(7))
        g = 0.75 if vein else 0.45 + 0.1 * math.sin(20 * u) * math.sin(17 * v)
        a = 1.0 if (inside or stem) else 0.0
        return (0.25 * g, g, 0.12 * g, a)
    write_png(path, size, size, 4, pixel)


def tiles_texture(path, size=256, tiles=2, grout=0.08):
    """Tile heights: 1 on the tiles, falling to 0 in the grout over a rounded edge."""
    def pixel(x, y):
        h = 1.0
        for c in ((x + 0.5) / size * tiles, (y + 0.5) / size * tiles):
            f = c - math.floor(c)
            d = min(f, 1 - f)  # distance to the nearest grout line, in tiles
            h = min(h, 0.5 - 0.5 * math.cos(math.pi * min(1.0, d / grout)))
        return (h,)
    write_png(path, size, size, 1, pixel)


# Bronze (the scene format's example): anisotropic GGX whose rotation follows the pounded
# metal's dents.
EXAMPLES["bronze_pounded"] = scene(
    {"s": {"diffuse": {"color": [0.55, 0.35, 0.15]}, "metal": True,
           "reflection": {"weight": 1, "glossiness": 0.6, "brdf": "ggx",
                          "fresnel": {"use_ior": False, "facing": 0.8, "perpendicular": 1}},
           "anisotropy": {"amount": -0.8, "orientation": "uv", "rotation": {"texture": "pounded"}}}},
    [sphere("s")])
EXAMPLES["bronze_pounded"]["textures"] = {
    "pounded": {"file": "textures/pounded.png", "colorspace": "linear", "scale": [3, 2]}}

# A leaf lit from behind: its outline a cutout (the texture's alpha), its body translucent.
EXAMPLES["leaf_backlit"] = scene(
    {"leaf": {"diffuse": {"color": {"texture": "leaf"}, "weight": 0.3},
              "translucency": {"enable": True, "color": {"texture": "leaf"}, "weight": 1},
              "refraction": {"weight": 0.7, "thin_walled": True},
              "reflection": {"weight": 0.2, "glossiness": 0.5},
              "cutout_opacity": {"texture": "leaf", "channel": "a"}}},
    [{"shape": "quad", "corner": [-1.2, 0.2, 0], "edge_u": [2.4, 0, 0], "edge_v": [0, 2.4, 0.4], "material": "leaf"}],
    lights=[{"type": "sun", "direction": [0.25, -0.35, 1], "angle": 2, "color": [1, 0.95, 0.85], "intensity": 6}],
    env=0.15)
EXAMPLES["leaf_backlit"]["textures"] = {"leaf": {"file": "textures/leaf.png"}}
# No backdrop: the low sun behind the leaf would be behind the stage's wall.
EXAMPLES["leaf_backlit"]["objects"] = [STAGE_OBJECTS[0]] + EXAMPLES["leaf_backlit"]["objects"][2:]

# A glossy tiled floor with bump: every lobe bumped, then the reflection without bump (the
# grout shows in the diffuse shading only, the reflection stays a clean mirror image).
for name, disable in (("floor_bump", False), ("floor_bump_smooth_reflection", True)):
    EXAMPLES[name] = scene(
        {"tiles": {"diffuse": {"color": [0.22, 0.2, 0.18]},
                   "reflection": {"weight": 1, "glossiness": 0.97, "disable_bump": disable},
                   "bump": {"input": "tiles", "scale": 0.03}},
         "red": {"diffuse": {"color": [0.6, 0.08, 0.05]}, "reflection": {"weight": 0.6, "glossiness": 0.9}}},
        [{"shape": "quad", "corner": [-3, 0.001, 3], "edge_u": [6, 0, 0], "edge_v": [0, 0, -6], "material": "tiles"},
         sphere("red", r=0.8)],
        camera={"position": [0, 1.1, 6.5], "look_at": [0, 0.5, 0], "up": [0, 1, 0], "fov": 34})
    EXAMPLES[name]["textures"] = {"tiles": {"file": "textures/tiles.png", "colorspace": "linear", "scale": [4, 4]}}


# 100,000 analytic spheres (each one primitive in the BVH; tessellated, they would be 1.6 G
# triangles) on a plain under sun and sky. Written by main() but not committed (9 MB of JSON;
# .gitignore): scripts/render_gallery.sh runs this script first.
def spheres_100k():
    rnd = random.Random(1)
    mats = {"ground": {"diffuse": {"color": 0.35}, "reflection": {"weight": 0}}}
    for k in range(8):
        mats["m%d" % k] = {"diffuse": {"color": [round(0.1 + 0.7 * rnd.random(), 3) for _ in range(3)]},
                           "reflection": {"weight": 0.5, "glossiness": round(0.3 + 0.6 * rnd.random(), 3)}}
    objects = [{"shape": "quad", "corner": [-80, 0, 80], "edge_u": [160, 0, 0], "edge_v": [0, 0, -160], "material": "ground"}]
    for _ in range(100000):
        r = rnd.uniform(0.05, 0.25)
        objects.append({"shape": "sphere", "center": [round(rnd.uniform(-50, 50), 3), round(r, 3), round(rnd.uniform(-50, 50), 3)],
                        "radius": round(r, 3), "material": "m%d" % rnd.randrange(8)})
    return daylight(mats, objects, {"position": [0, 5, 32], "look_at": [0, 0, 0], "up": [0, 1, 0], "fov": 40}, spp=64)


# A forest of instances: two trees (a conifer of jagged stacked cones, 21,000 triangles, and a
# broadleaf whose crown is a displaced sphere, 18,000) placed 6,000 times with random turns and
# sizes, a fifth of the broadleaves in autumn colours (another material: another prototype),
# under sun and sky. 120 M triangles as rendered, a few MB as stored (docs/scene-format.md,
# "Instancing"). The meshes and the scene are written by main() but not committed (.gitignore).
def write_mesh_obj(path, verts, normals, faces, comment):
    lines = ["# " + comment + ", written by scripts/make_gallery_scenes.py"]
    lines += ["v %.5f %.5f %.5f" % v for v in verts]
    lines += ["vn %.4f %.4f %.4f" % n for n in normals]
    lines += ["f %d//%d %d//%d %d//%d" % (a + 1, a + 1, b + 1, b + 1, c + 1, c + 1) for a, b, c in faces]
    with open(path, "w") as f:
        f.write("\n".join(lines) + "\n")


def grid_surface(point, nu, nv, verts, normals, faces, closed_u=True):
    """Vertices point(u, v) on an (nu x nv) grid, u around (closed), v along; smooth normals
    from the grid's central differences; two triangles per cell, counter-clockwise outside."""
    base = len(verts)
    cols = nu if closed_u else nu + 1
    grid = [[point(i / nu, j / nv) for i in range(cols)] for j in range(nv + 1)]
    def normal(i, j):
        a = grid[j][(i + 1) % cols if closed_u else min(i + 1, cols - 1)]
        b = grid[j][(i - 1) % cols if closed_u else max(i - 1, 0)]
        c = grid[min(j + 1, nv)][i]
        d = grid[max(j - 1, 0)][i]
        du = [a[k] - b[k] for k in range(3)]
        dv = [c[k] - d[k] for k in range(3)]
        n = [du[1] * dv[2] - du[2] * dv[1], du[2] * dv[0] - du[0] * dv[2], du[0] * dv[1] - du[1] * dv[0]]
        ln = math.sqrt(sum(x * x for x in n))
        return tuple(-x / ln for x in n) if ln > 1e-12 else None
    for j in range(nv + 1):
        for i in range(cols):
            # A row collapsed to a point (an apex, a pole, a disc's centre) has no tangent
            # along u: it takes the normal of the nearest row that has one.
            n = normal(i, j)
            for dj in range(1, nv + 1):
                if n is not None:
                    break
                n = normal(i, min(max(j - dj if j > 0 else j + dj, 0), nv))
            verts.append(tuple(grid[j][i]))
            normals.append(n or (0.0, 1.0, 0.0))
    for j in range(nv):
        for i in range(nu):
            i1 = (i + 1) % cols if closed_u else i + 1
            a, b = base + j * cols + i, base + j * cols + i1
            c, d = base + (j + 1) * cols + i1, base + (j + 1) * cols + i
            faces.append((a, c, b))
            faces.append((a, d, c))


def conifer(path):
    rnd = random.Random(3)
    verts, normals, faces = [], [], []
    grid_surface(lambda u, v: (0.12 * (1 - 0.5 * v) * math.cos(2 * math.pi * u), 1.2 * v,
                               0.12 * (1 - 0.5 * v) * math.sin(2 * math.pi * u)), 24, 6, verts, normals, faces)
    jag = [rnd.uniform(0.75, 1.0) for _ in range(96)]
    for k in range(5):
        y0, h, r0 = 0.9 + 0.75 * k, 1.6 - 0.12 * k, 1.5 - 0.25 * k
        def cone(u, v, y0=y0, h=h, r0=r0):
            i = int(round(u * 96)) % 96
            r = r0 * (1 - v) * (jag[i] if v < 0.999 else 1.0) * (1 - 0.15 * math.sin(6 * math.pi * v))
            return (r * math.cos(2 * math.pi * u), y0 + h * v, r * math.sin(2 * math.pi * u))
        grid_surface(cone, 96, 20, verts, normals, faces)
        # The cone's underside, a disc, so the tree is closed.
        grid_surface(lambda u, v, y0=y0, r0=r0: (r0 * jag[int(round(u * 96)) % 96] * (1 - v) * math.cos(-2 * math.pi * u),
                                                  y0, r0 * jag[int(round(u * 96)) % 96] * (1 - v) * math.sin(-2 * math.pi * u)),
                     96, 1, verts, normals, faces)
    write_mesh_obj(path, verts, normals, faces, "conifer")
    return len(faces)


def broadleaf(path):
    verts, normals, faces = [], [], []
    grid_surface(lambda u, v: (0.16 * (1 - 0.4 * v) * math.cos(2 * math.pi * u), 2.2 * v,
                               0.16 * (1 - 0.4 * v) * math.sin(2 * math.pi * u)), 24, 8, verts, normals, faces)
    def crown(u, v):
        th, ph = math.pi * (1 - v), 2 * math.pi * u
        bump = 1 + 0.12 * math.sin(7 * ph + 3 * th) * math.sin(5 * th) + 0.06 * math.sin(19 * ph) * math.sin(13 * th)
        r = 1.5 * bump
        return (r * math.sin(th) * math.cos(ph), 3.3 + 1.25 * r * math.cos(th), r * math.sin(th) * math.sin(ph))
    grid_surface(crown, 128, 70, verts, normals, faces)
    write_mesh_obj(path, verts, normals, faces, "broadleaf tree")
    return len(faces)


def forest():
    rnd = random.Random(5)
    mats = {
        "ground": {"diffuse": {"color": [0.22, 0.2, 0.12]}, "reflection": {"weight": 0}},
        "bark": {"diffuse": {"color": [0.25, 0.16, 0.1]}, "reflection": {"weight": 0}},
        "needles": {"diffuse": {"color": [0.05, 0.16, 0.06]}, "reflection": {"weight": 0.15, "glossiness": 0.4}},
        "leaves": {"diffuse": {"color": [0.12, 0.3, 0.06]}, "translucency": {"weight": 0.3, "color": [0.4, 0.7, 0.2]},
                   "reflection": {"weight": 0.1, "glossiness": 0.5}},
        "autumn": {"diffuse": {"color": [0.55, 0.22, 0.04]}, "translucency": {"weight": 0.3, "color": [0.8, 0.4, 0.1]},
                   "reflection": {"weight": 0.1, "glossiness": 0.5}},
    }
    meshes = {"conifer": {"file": "../meshes/tree_conifer.obj", "material": "needles"},
              "broadleaf": {"file": "../meshes/tree_broadleaf.obj", "material": "leaves"}}
    objects = [{"shape": "quad", "corner": [-200, 0, 200], "edge_u": [400, 0, 0], "edge_v": [0, 0, -400], "material": "ground"}]
    for _ in range(6000):
        x, z = rnd.uniform(-60, 60), rnd.uniform(-110, 10)
        kind = "conifer" if rnd.random() < 0.55 else "broadleaf"
        s = round(rnd.uniform(0.7, 1.4), 3)
        inst = {"shape": "instance", "mesh": kind,
                "transform": {"scale": [s, round(s * rnd.uniform(0.85, 1.2), 3), s], "rotate": [0, round(rnd.uniform(0, 360), 1), 0],
                              "translate": [round(x, 2), 0, round(z, 2)]}}
        if kind == "broadleaf" and rnd.random() < 0.2:
            inst["material"] = "autumn"
        objects.append(inst)
    sc = daylight(mats, objects, {"position": [0, 16, 32], "look_at": [0, 0, -45], "up": [0, 1, 0], "fov": 40}, spp=64)
    sc["meshes"] = meshes
    return sc


def main():
    import make_gltf_interior  # imports this module for write_png: loaded lazily
    make_gltf_interior.main()
    os.makedirs(TEXTURES, exist_ok=True)
    pounded_texture(os.path.join(TEXTURES, "pounded.png"))
    leaf_texture(os.path.join(TEXTURES, "leaf.png"))
    tiles_texture(os.path.join(TEXTURES, "tiles.png"))
    os.makedirs(MESHES, exist_ok=True)
    write_lathe_obj(os.path.join(MESHES, "cup.obj"), CUP_PROFILE)
    ring, ring_n = ring_profile(0.6, 0.12)
    write_lathe_obj(os.path.join(MESHES, "ring.obj"), ring, segments=96, normals=ring_n)
    os.makedirs(OUT, exist_ok=True)
    for name, s in sorted(EXAMPLES.items()):
        with open(os.path.join(OUT, name + ".json"), "w") as f:
            json.dump(s, f, indent=1)
            f.write("\n")
    with open(os.path.join(OUT, "spheres_100k.json"), "w") as f:
        json.dump(spheres_100k(), f, separators=(",", ":"))
        f.write("\n")
    conifer(os.path.join(MESHES, "tree_conifer.obj"))
    broadleaf(os.path.join(MESHES, "tree_broadleaf.obj"))
    with open(os.path.join(OUT, "forest.json"), "w") as f:
        json.dump(forest(), f, separators=(",", ":"))
        f.write("\n")
    print("wrote %d scenes to %s" % (len(EXAMPLES) + 2, os.path.normpath(OUT)))


if __name__ == "__main__":
    main()

#!/usr/bin/env python3
"""Writes scenes/docs/*.json: the material documentation's worked examples, on one stage.

Every example shares the stage (floor, backdrop, camera, a soft area light and a dim sky) so
that the pictures in docs/gallery.md differ only in what the example is about. Re-run after
changing the stage; the JSON files are committed so they can be rendered without Python.
"""
import json
import os

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


def main():
    os.makedirs(OUT, exist_ok=True)
    for name, s in sorted(EXAMPLES.items()):
        with open(os.path.join(OUT, name + ".json"), "w") as f:
            json.dump(s, f, indent=1)
            f.write("\n")
    print("wrote %d scenes to %s" % (len(EXAMPLES), os.path.normpath(OUT)))


if __name__ == "__main__":
    main()

"""The part of archwave's scene format that other renderers reproduce exactly, read from an
archwave scene file (docs/scene-format.md) into a plain description that the exporters
(bench/export_cycles.py, bench/export_mitsuba.py) translate. Pure Python (no numpy), so that
Blender's interpreter, a Mitsuba virtualenv and the benchmark suite can all import it.

The subset (issue 11, "The race"): Lambert; smooth glass; GGX/Beckmann tinted mirrors without
Fresnel; quads, boxes, spheres (and OBJ meshes, passed through); point, quad and sphere lights;
a constant environment. Anything else is refused with Unsupported, whose message names the
key. Values are clamped to archwave's ranges as archwave's loader clamps them.

  describe(path, width=None, height=None, geometry=None) -> dict (see the end of this file)
  triangles(obj) -> (positions, normals or None, triangles): an object's world-space mesh,
                    archwave's own, read from the OBJ `archwave SCENE --export-geometry FILE`
                    writes (read_geometry); nothing here tessellates a shape again
"""

import json
import math
import os
import time

MIRROR_ALPHA = 1e-3      # below this alpha a lobe is a perfect mirror / smooth (kernels/lobes/microfacet.h)
PASS_THROUGH_EPS = 1e-3  # |ior - 1| below this is a pass-through (kernels/lobes/refraction.h)


class Unsupported(Exception):
    """The scene uses something outside the exported subset; the message names the key."""


# ---------------------------------------------------------------------------- small helpers

def _colour(v, key):
    if isinstance(v, (int, float)) and not isinstance(v, bool):
        return [float(v)] * 3
    if isinstance(v, list) and len(v) == 3 and all(isinstance(x, (int, float)) for x in v):
        return [float(x) for x in v]
    raise Unsupported(f"{key}: expected a colour, got {json.dumps(v)}")


def _vec3(v, key):
    if isinstance(v, list) and len(v) == 3 and all(isinstance(x, (int, float)) for x in v):
        return [float(x) for x in v]
    raise Unsupported(f"{key}: expected [x, y, z], got {json.dumps(v)}")


def _clamp01(c):
    return [min(1.0, max(0.0, x)) for x in c]


def _get(d, path, default):
    """d["a"]["b"] for path "a.b", or default."""
    cur = d
    for part in path.split("."):
        if not isinstance(cur, dict) or part not in cur:
            return default
        cur = cur[part]
    return cur


def _only_keys(d, allowed, where):
    for k in d:
        if k not in allowed:
            raise Unsupported(f"{where}.{k}: not in the exported subset")


def _lum(c):
    return 0.2126 * c[0] + 0.7152 * c[1] + 0.0722 * c[2]


def mat_mul(a, b):
    return [[sum(a[i][k] * b[k][j] for k in range(4)) for j in range(4)] for i in range(4)]


def transform_point(m, p):
    return [m[i][0] * p[0] + m[i][1] * p[1] + m[i][2] * p[2] + m[i][3] for i in range(3)]


def cross(a, b):
    return [a[1] * b[2] - a[2] * b[1], a[2] * b[0] - a[0] * b[2], a[0] * b[1] - a[1] * b[0]]


def dot(a, b):
    return a[0] * b[0] + a[1] * b[1] + a[2] * b[2]


def normalize(a):
    n = math.sqrt(dot(a, a))
    return [x / n for x in a]


def _cos_sin_degrees(deg):
    """Exact at multiples of 90 degrees, like archwave's loader."""
    q = deg / 90.0
    if q == round(q):
        k = int(round(q)) % 4
        return [(1.0, 0.0), (0.0, 1.0), (-1.0, 0.0), (0.0, -1.0)][k]
    r = math.radians(deg)
    return math.cos(r), math.sin(r)


def transform_matrix(t, where):
    """archwave's object transform: M = T * Rz * Ry * Rx * S, or a row-major 4x4 matrix."""
    ident = [[1.0 if i == j else 0.0 for j in range(4)] for i in range(4)]
    if t is None:
        return ident
    if not isinstance(t, dict):
        raise Unsupported(f"{where}: expected an object")
    _only_keys(t, ("translate", "rotate", "scale", "matrix"), where)
    if "matrix" in t:
        v = t["matrix"]
        return [[float(v[4 * i + j]) for j in range(4)] for i in range(4)]
    tr = _vec3(t.get("translate", [0, 0, 0]), where + ".translate")
    rot = _vec3(t.get("rotate", [0, 0, 0]), where + ".rotate")
    s = t.get("scale", 1)
    s = [float(s)] * 3 if isinstance(s, (int, float)) else _vec3(s, where + ".scale")
    cx, sx = _cos_sin_degrees(rot[0])
    cy, sy = _cos_sin_degrees(rot[1])
    cz, sz = _cos_sin_degrees(rot[2])

    def m3(r):
        return [r[0] + [0.0], r[1] + [0.0], r[2] + [0.0], [0.0, 0.0, 0.0, 1.0]]
    rx = m3([[1, 0, 0], [0, cx, -sx], [0, sx, cx]])
    ry = m3([[cy, 0, sy], [0, 1, 0], [-sy, 0, cy]])
    rz = m3([[cz, -sz, 0], [sz, cz, 0], [0, 0, 1]])
    sm = [[s[0], 0, 0, 0], [0, s[1], 0, 0], [0, 0, s[2], 0], [0, 0, 0, 1.0]]
    tm = [[1, 0, 0, tr[0]], [0, 1, 0, tr[1]], [0, 0, 1, tr[2]], [0, 0, 0, 1.0]]
    return mat_mul(tm, mat_mul(rz, mat_mul(ry, mat_mul(rx, sm))))


def similarity_scale(m):
    """s when the 3x3 part is s times a rotation (or a mirror), else None."""
    cols = [[m[i][j] for i in range(3)] for j in range(3)]
    lens = [math.sqrt(dot(c, c)) for c in cols]
    s = lens[0]
    if any(abs(x - s) > 1e-9 * max(1.0, s) for x in lens):
        return None
    if any(abs(dot(cols[i], cols[j])) > 1e-9 * s * s for i in range(3) for j in range(i + 1, 3)):
        return None
    return s


# ---------------------------------------------------------------------------- materials

# Keys whose value must stay at its default (archwave's) for a material to be exported: each
# changes the image in a way the peers cannot reproduce exactly.
_MUST_BE_DEFAULT = [
    ("translucency.enable", False), ("reflection2.weight", 0.0), ("metal", False),
    ("anisotropy.amount", 0.0), ("diffuse.roughness", 0.0), ("ao.enable", False),
    ("highlight_vs_reflection", 1.0), ("optimizations.specular_highlights_only", False),
    ("optimizations.trace_depth_override", False), ("refraction.thin_walled", False),
]
_MATERIAL_GROUPS = ("diffuse", "translucency", "reflection", "reflection2", "metal", "highlight_vs_reflection",
                    "anisotropy", "refraction", "ao", "optimizations", "cutout_opacity", "incandescent",
                    "propagate_alpha", "bump")


def _alpha(glossiness):
    g = min(1.0, max(0.0, float(glossiness)))
    return max(1e-4, (1.0 - g) ** 2)


def material(name, m):
    """{"kind": "lambert", "albedo"} | {"kind": "mirror", "distribution", "alpha", "color"}
    | {"kind": "glass", "ior", "tint"} for an archwave material (docs/material.md §2)."""
    where = f"materials.{name}"
    if not isinstance(m, dict):
        raise Unsupported(f"{where}: expected an object")
    _only_keys(m, _MATERIAL_GROUPS, where)
    for key, default in _MUST_BE_DEFAULT:
        v = _get(m, key, default)
        if (float(v) != default) if isinstance(default, float) else (v != default):
            raise Unsupported(f"{where}.{key}: {json.dumps(v)} is not in the exported subset "
                              f"(only the default {json.dumps(default)})")
    if float(_get(m, "cutout_opacity", 1.0)) < 0.5:
        raise Unsupported(f"{where}.cutout_opacity: cutouts are not in the exported subset")
    inc = _colour(_get(m, "incandescent.color", 0.0), where + ".incandescent.color")
    if max(inc) > 0 and float(_get(m, "incandescent.scale", 1.0)) > 0:
        raise Unsupported(f"{where}.incandescent.color: incandescence is not in the exported subset")
    if _get(m, "refraction.fog.enable", False) and float(_get(m, "refraction.fog.distance", 0.0)) > 0:
        raise Unsupported(f"{where}.refraction.fog.enable: fog is not in the exported subset")

    dw = min(1.0, max(0.0, float(_get(m, "diffuse.weight", 1.0))))
    dc = _clamp01(_colour(_get(m, "diffuse.color", 0.5), where + ".diffuse.color"))
    rw = min(1.0, max(0.0, float(_get(m, "reflection.weight", 0.6))))
    rc = _clamp01(_colour(_get(m, "reflection.color", 1.0), where + ".reflection.color"))
    tw = min(1.0, max(0.0, float(_get(m, "refraction.weight", 0.0))))
    tc = _clamp01(_colour(_get(m, "refraction.color", 1.0), where + ".refraction.color"))
    has_d = dw > 0 and max(dc) > 0
    has_r = rw > 0 and max(rc) > 0
    has_t = tw > 0

    if has_t:  # smooth glass: reflection F, refraction (1 - F) tinted
        key = None
        if tw != 1.0:
            key = "refraction.weight"
        elif _alpha(_get(m, "refraction.glossiness", 1.0)) >= MIRROR_ALPHA:
            key = "refraction.glossiness"
        elif rw != 1.0 or rc != [1.0, 1.0, 1.0]:
            key = "reflection.weight" if rw != 1.0 else "reflection.color"
        elif _alpha(_get(m, "reflection.glossiness", 1.0)) >= MIRROR_ALPHA:
            key = "reflection.glossiness"
        elif not _get(m, "reflection.fresnel.use_ior", True):
            key = "reflection.fresnel.use_ior"
        elif _get(m, "reflection.fresnel.medium", "dielectric") != "dielectric":
            key = "reflection.fresnel.medium"
        if key:
            raise Unsupported(f"{where}.{key}: refraction is exported only as smooth glass (refraction.weight 1 "
                              "and glossiness 1, reflection weight 1, colour 1, glossiness 1, dielectric Fresnel)")
        ior = max(0.01, float(_get(m, "refraction.ior", 1.4)))
        if not _get(m, "reflection.fresnel.lock_to_refraction_ior", True):
            if abs(max(0.01, float(_get(m, "reflection.fresnel.ior", 1.5))) - ior) > 1e-6:
                raise Unsupported(f"{where}.reflection.fresnel.ior: differs from refraction.ior "
                                  "(not a single dielectric interface)")
        if abs(ior - 1.0) < PASS_THROUGH_EPS:
            raise Unsupported(f"{where}.refraction.ior: an IOR of 1 (a pass-through) is not exported")
        if _get(m, "optimizations.skip_weak_internal_reflections", True):
            raise Unsupported(f"{where}.optimizations.skip_weak_internal_reflections: must be false for glass "
                              "(true drops partial internal reflections, which no peer does)")
        if has_d and _lum(tc) < 1.0 - 1e-6:
            raise Unsupported(f"{where}.diffuse.weight: a tinted glass with diffuse is not exported "
                              "(set diffuse.weight 0)")
        return {"kind": "glass", "ior": ior, "tint": tc}

    if has_r:  # a mirror without Fresnel: reflectance weight * colour * facing, nothing else
        if has_d:
            raise Unsupported(f"{where}.diffuse.weight: diffuse under a reflection (the energy split) is not "
                              "exported; a mirror needs diffuse.weight 0")
        brdf = _get(m, "reflection.brdf", "ggx")
        if brdf not in ("ggx", "beckmann"):
            raise Unsupported(f"{where}.reflection.brdf: {brdf} is not exported (ggx and beckmann are)")
        if _get(m, "reflection.fresnel.use_ior", True):
            raise Unsupported(f"{where}.reflection.fresnel.use_ior: Fresnel reflection is not exported; a mirror "
                              "needs use_ior false and facing = perpendicular")
        f0 = min(1.0, max(0.0, float(_get(m, "reflection.fresnel.facing", 0.2))))
        f90 = min(1.0, max(0.0, float(_get(m, "reflection.fresnel.perpendicular", 1.0))))
        if abs(f0 - f90) > 1e-9:
            raise Unsupported(f"{where}.reflection.fresnel.facing: differs from fresnel.perpendicular "
                              "(an angle-dependent reflectance is not exported)")
        return {"kind": "mirror", "distribution": brdf, "alpha": _alpha(_get(m, "reflection.glossiness", 1.0)),
                "color": [rw * f0 * c for c in rc]}

    return {"kind": "lambert", "albedo": [dw * c for c in dc] if has_d else [0.0, 0.0, 0.0]}


# ---------------------------------------------------------------------------- the scene

def _camera(c):
    c = c or {}
    _only_keys(c, ("position", "look_at", "up", "fov", "exposure"), "camera")
    e = c.get("exposure", {}) or {}
    _only_keys(e, ("mode", "stops", "iso", "shutter", "f_number", "whitepoint", "vignetting"), "camera.exposure")
    if _colour(e.get("whitepoint", 1.0), "camera.exposure.whitepoint") != [1.0, 1.0, 1.0]:
        raise Unsupported("camera.exposure.whitepoint: only [1, 1, 1] is exported")
    if float(e.get("vignetting", 0.0)) != 0.0:
        raise Unsupported("camera.exposure.vignetting: only 0 is exported")
    if e.get("mode", "stops") == "stops":
        k = 2.0 ** float(e.get("stops", 0.0))
    else:
        f = float(e.get("f_number", 16))
        k = (1.0 / float(e.get("shutter", 100))) * float(e.get("iso", 100)) / (f * f * 100.0)
    return {"position": _vec3(c.get("position", [0, 1, 4]), "camera.position"),
            "look_at": _vec3(c.get("look_at", [0, 1, 0]), "camera.look_at"),
            "up": _vec3(c.get("up", [0, 1, 0]), "camera.up"),
            "fov": float(c.get("fov", 40))}, k


def _light(i, l):
    where = f"lights[{i}]"
    typ = l.get("type")
    radiance = [float(l.get("intensity", 1.0)) * x for x in _colour(l.get("color", 1.0), where + ".color")]
    if typ == "point":
        _only_keys(l, ("type", "color", "intensity", "position"), where)
        return {"type": "point", "position": _vec3(l.get("position", [0, 0, 0]), where + ".position"),
                "intensity": radiance}
    if typ in ("quad", "sphere") and not l.get("visible", True):
        raise Unsupported(f"{where}.visible: lights hidden from the camera are not exported")
    if typ == "quad":
        _only_keys(l, ("type", "color", "intensity", "corner", "edge_u", "edge_v", "two_sided", "visible"), where)
        if l.get("two_sided", False):
            raise Unsupported(f"{where}.two_sided: two-sided quad lights are not exported")
        return {"type": "quad", "corner": _vec3(l.get("corner", [0, 0, 0]), where + ".corner"),
                "edge_u": _vec3(l.get("edge_u", [1, 0, 0]), where + ".edge_u"),
                "edge_v": _vec3(l.get("edge_v", [0, 0, 1]), where + ".edge_v"), "radiance": radiance}
    if typ == "sphere":
        _only_keys(l, ("type", "color", "intensity", "center", "radius", "visible"), where)
        return {"type": "sphere", "center": _vec3(l.get("center", [0, 0, 0]), where + ".center"),
                "radius": float(l.get("radius", 0.5)), "radiance": radiance}
    raise Unsupported(f"{where}.type: {json.dumps(typ)} lights are not exported (point, quad and sphere are)")


def _object(i, o, base_dir, materials):
    where = f"objects[{i}]"
    shape = o.get("shape")
    mat = o.get("material")
    if mat not in materials:
        raise Unsupported(f"{where}.material: unknown material {json.dumps(mat)}")
    m = transform_matrix(o.get("transform"), where + ".transform")
    common = {"shape": shape, "material": mat, "matrix": m, "where": where}
    if shape == "quad":
        _only_keys(o, ("shape", "material", "transform", "corner", "edge_u", "edge_v"), where)
        return dict(common, corner=_vec3(o.get("corner", [0, 0, 0]), where + ".corner"),
                    edge_u=_vec3(o.get("edge_u", [1, 0, 0]), where + ".edge_u"),
                    edge_v=_vec3(o.get("edge_v", [0, 0, 1]), where + ".edge_v"))
    if shape == "box":
        _only_keys(o, ("shape", "material", "transform", "min", "max"), where)
        return dict(common, min=_vec3(o.get("min", [-0.5] * 3), where + ".min"),
                    max=_vec3(o.get("max", [0.5] * 3), where + ".max"))
    if shape == "sphere":
        _only_keys(o, ("shape", "material", "transform", "center", "radius", "segments"), where)
        seg = o.get("segments", [128, 64])
        return dict(common, center=_vec3(o.get("center", [0, 0, 0]), where + ".center"),
                    radius=float(o.get("radius", 1.0)), segments=[int(seg[0]), int(seg[1])])
    if shape == "mesh":
        _only_keys(o, ("shape", "material", "transform", "file"), where)
        path = o["file"] if os.path.isabs(o["file"]) else os.path.join(base_dir, o["file"])
        if path.lower().endswith((".gltf", ".glb")):
            raise Unsupported(f"{where}.file: glTF meshes are not exported")
        return dict(common, file=os.path.abspath(path))
    raise Unsupported(f"{where}.shape: {json.dumps(shape)} is not exported (quad, box, sphere, mesh are)")


def describe(path, width=None, height=None, geometry=None):
    """The scene at `path` as the exporters' description; width/height override render.*;
    `geometry`, the OBJ archwave --export-geometry wrote for it, gives each object its mesh
    (triangles()). Raises Unsupported naming the first key outside the subset."""
    with open(path) as f:
        s = json.load(f)
    _only_keys(s, ("render", "camera", "environment", "lights", "textures", "materials", "objects"), "scene")
    if s.get("textures"):
        raise Unsupported("textures: textures are not exported")
    r = s.get("render", {}) or {}
    _only_keys(r, ("width", "height", "spp", "seed", "max_depth", "reflection_depth", "refraction_depth", "gi",
                   "cutoff", "lobe_splitting", "clamp", "rr_depth", "sampler"), "render")
    max_depth = int(r.get("max_depth", 8))
    if max_depth < 1:
        raise Unsupported("render.max_depth: below 1 is not exported (Cycles cannot render emitters only)")
    for key in ("reflection_depth", "refraction_depth"):
        if int(r.get(key, 8)) < max_depth:
            raise Unsupported(f"render.{key}: below max_depth is not exported (the peers have one depth)")
    if not r.get("gi", True):
        raise Unsupported("render.gi: false is not exported")
    if float(r.get("clamp", 0.0)) != 0.0:
        raise Unsupported("render.clamp: clamping is not exported (the race compares unbiased renders)")
    env = s.get("environment", {}) or {}
    _only_keys(env, ("type", "color", "intensity"), "environment")
    if env.get("type", "constant") != "constant":
        raise Unsupported(f"environment.type: {env.get('type')} is not exported (constant is)")
    camera, k = _camera(s.get("camera"))
    mats = {name: material(name, m) for name, m in (s.get("materials") or {}).items()}
    base = os.path.dirname(os.path.abspath(path))
    return {
        "file": os.path.abspath(path),
        "width": int(width or r.get("width", 640)), "height": int(height or r.get("height", 480)),
        "spp": int(r.get("spp", 64)), "max_depth": max_depth,
        "exposure": k, "camera": camera,
        "environment": [float(env.get("intensity", 1.0)) * x
                        for x in _colour(env.get("color", 0.0), "environment.color")],
        "lights": [_light(i, l) for i, l in enumerate(s.get("lights") or [])],
        "materials": mats,
        "objects": _with_meshes([_object(i, o, base, mats) for i, o in enumerate(s.get("objects") or [])],
                                geometry),
    }


def _with_meshes(objects, geometry):
    if geometry is None:
        return objects
    meshes = read_geometry(geometry)
    if sorted(meshes) != list(range(len(objects))):
        raise ValueError(f"{geometry}: meshes for objects {sorted(meshes)}, the scene has {len(objects)}")
    return [dict(o, mesh=meshes[i]) for i, o in enumerate(objects)]


def job_spp(token, done, lo=16, hi=8192):
    """A job's spp: an integer, or "fitN": the largest power of two in [lo, hi] that the
    speed of the largest job in `done` (dicts with spp and seconds) says fits in N seconds."""
    if not token.startswith("fit"):
        return int(token)
    budget = float(token[3:])
    per = max((j["seconds"] / j["spp"] for j in done if j["spp"] == max(k["spp"] for k in done)), default=None)
    spp = lo
    while per is not None and spp * 2 <= hi and per * spp * 2 <= budget:
        spp *= 2
    return spp


# ---------------------------------------------------------------------------- geometry

def read_geometry(path):
    """{object index: (positions, normals or None, triangles)} from the OBJ that
    `archwave SCENE --export-geometry PATH` writes (host/scene/export_obj.h): archwave's own
    tessellation, transforms and winding, so no shape is tessellated twice. Its groups are
    named after the objects ("objects[3] (sphere)"); normals, where present, are per vertex
    and indexed like the positions within a group."""
    groups, nv, cur = {}, 0, None
    with open(path) as f:
        for line in f:
            t = line.split()
            if not t or t[0] == "#":
                continue
            if t[0] == "o":
                name = line[2:].strip()
                if not name.startswith("objects["):
                    raise ValueError(f"{path}: unexpected group {name!r}")
                cur = {"pos": [], "nrm": [], "tris": [], "v0": nv}
                groups[int(name[len("objects["):name.index("]")])] = cur
            elif t[0] == "v":
                cur["pos"].append([float(x) for x in t[1:4]])
                nv += 1
            elif t[0] == "vn":
                cur["nrm"].append([float(x) for x in t[1:4]])
            elif t[0] == "f":  # global 1-based position indices; the normals' follow them
                cur["tris"].append([int(c.split("//")[0]) - 1 - cur["v0"] for c in t[1:4]])
    return {i: (g["pos"], g["nrm"] or None, g["tris"]) for i, g in groups.items()}


def triangles(obj):
    """(positions, normals or None, triangles) of an object in world space, as archwave builds
    it (read_geometry), wound counter-clockwise seen from the side the geometric normal
    points to; None normals = flat shading."""
    if "mesh" not in obj:
        raise Unsupported(f"{obj['where']}: no geometry: describe() needs the OBJ of archwave --export-geometry")
    return obj["mesh"]


def exporter_arguments(ap):
    """The command-line arguments both exporters take (scripts/archwave_bench/race.py passes
    them); each adds its own --job and extras."""
    ap.add_argument("scene")
    ap.add_argument("--out", default=".")
    ap.add_argument("--result", default=None)
    ap.add_argument("--width", type=int)
    ap.add_argument("--height", type=int)
    ap.add_argument("--geometry", required=True,
                    help="the OBJ `archwave SCENE --export-geometry FILE` wrote: archwave's own triangles")
    ap.add_argument("--t0", type=float, default=None, help="epoch seconds when the caller started this process")


# The description (describe's result):
#   file, width, height, spp, max_depth (archwave's: scattering events per path), exposure (k)
#   camera: position, look_at, up, fov (vertical, degrees)
#   environment: radiance [r, g, b]
#   lights: {type point, position, intensity W/sr} | {type quad, corner, edge_u, edge_v, radiance}
#           | {type sphere, center, radius, radiance}    (one-sided quads emit along edge_u x edge_v)
#   materials: name -> {kind lambert, albedo} | {kind mirror, distribution, alpha, color}
#                      | {kind glass, ior, tint}
#   objects: {shape quad|box|sphere|mesh, material, matrix (4x4 row-major), shape keys}


def write_result(result, path, t_start):
    """An exporter's result as JSON, to `path` or (without one) to standard output, with the
    whole process's wall time since `t_start` (its first line) added."""
    result["wall_in_process"] = time.time() - t_start
    text = json.dumps(result, indent=2)
    if path:
        with open(path, "w") as f:
            f.write(text)
    else:
        print(text)

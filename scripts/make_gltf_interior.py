#!/usr/bin/env python3
"""Writes scenes/meshes/interior.gltf: a small room as a modelling tool would export it.

A glTF 2.0 file (JSON, one base64 data-URI buffer, one PNG texture file) with a node
hierarchy (the room, a table group with its legs as child nodes with their own transforms, two
chairs instanced by two nodes), normals, UVs and these materials: a tiled floor (base colour
texture with KHR_texture_transform), painted walls, oak (rough), brushed steel (metallic), a
glass pane (KHR_materials_transmission + KHR_materials_ior), a lamp shade
(KHR_materials_emissive_strength) and a lacquered table top (KHR_materials_clearcoat). The
renderer's gallery scene scenes/docs/gltf_interior.json places it under a sun and sky.
"""
import base64
import json
import math
import os
import struct
import sys
import zlib

HERE = os.path.dirname(os.path.abspath(__file__))
sys.path.insert(0, HERE)
from make_gallery_scenes import write_png  # noqa: E402  (the gallery's own PNG writer)

OUT = os.path.join(HERE, "..", "scenes", "meshes")


class Builder:
    def __init__(self):
        self.bin = bytearray()
        self.accessors, self.views, self.meshes, self.nodes = [], [], [], []

    def _view(self, data, target):
        while len(self.bin) % 4:
            self.bin.append(0)
        self.views.append({"buffer": 0, "byteOffset": len(self.bin), "byteLength": len(data), "target": target})
        self.bin += data
        return len(self.views) - 1

    def _accessor(self, values, kind, comps):
        if kind == "index":
            data = struct.pack("<%dI" % len(values), *values)
            view = self._view(data, 34963)
            self.accessors.append({"bufferView": view, "componentType": 5125, "count": len(values), "type": "SCALAR"})
        else:
            flat = [c for v in values for c in v]
            data = struct.pack("<%df" % len(flat), *flat)
            view = self._view(data, 34962)
            acc = {"bufferView": view, "componentType": 5126, "count": len(values), "type": "VEC%d" % comps}
            if kind == "position":
                acc["min"] = [min(v[i] for v in values) for i in range(3)]
                acc["max"] = [max(v[i] for v in values) for i in range(3)]
            self.accessors.append(acc)
        return len(self.accessors) - 1

    def mesh(self, name, parts):
        """parts: list of (positions, normals, uvs, indices, material)."""
        prims = []
        for pos, nrm, uv, idx, mat in parts:
            prims.append({"attributes": {"POSITION": self._accessor(pos, "position", 3),
                                         "NORMAL": self._accessor(nrm, "normal", 3),
                                         "TEXCOORD_0": self._accessor(uv, "uv", 2)},
                          "indices": self._accessor(idx, "index", 1), "material": mat})
        self.meshes.append({"name": name, "primitives": prims})
        return len(self.meshes) - 1

    def node(self, name, mesh=None, children=None, **trs):
        n = {"name": name}
        if mesh is not None:
            n["mesh"] = mesh
        if children:
            n["children"] = children
        n.update(trs)
        self.nodes.append(n)
        return len(self.nodes) - 1


def box(lo, hi, uv_scale=1.0):
    """An axis-aligned box: 6 faces, outward normals, UVs in metres * uv_scale."""
    (x0, y0, z0), (x1, y1, z1) = lo, hi
    faces = [  # (normal, corner, edge u, edge v) with u x v = normal
        ((1, 0, 0), (x1, y0, z1), (0, 0, z0 - z1), (0, y1 - y0, 0)),
        ((-1, 0, 0), (x0, y0, z0), (0, 0, z1 - z0), (0, y1 - y0, 0)),
        ((0, 1, 0), (x0, y1, z1), (x1 - x0, 0, 0), (0, 0, z0 - z1)),
        ((0, -1, 0), (x0, y0, z0), (x1 - x0, 0, 0), (0, 0, z1 - z0)),
        ((0, 0, 1), (x0, y0, z1), (x1 - x0, 0, 0), (0, y1 - y0, 0)),
        ((0, 0, -1), (x1, y0, z0), (x0 - x1, 0, 0), (0, y1 - y0, 0)),
    ]
    pos, nrm, uv, idx = [], [], [], []
    for n, c, eu, ev in faces:
        lu, lv = math.sqrt(sum(a * a for a in eu)), math.sqrt(sum(a * a for a in ev))
        b = len(pos)
        for s, t in ((0, 0), (1, 0), (1, 1), (0, 1)):
            pos.append([c[i] + s * eu[i] + t * ev[i] for i in range(3)])
            nrm.append(list(n))
            uv.append([s * lu * uv_scale, 1 - t * lv * uv_scale])  # glTF: V down
        idx += [b, b + 1, b + 2, b, b + 2, b + 3]
    return pos, nrm, uv, idx


def quad(corner, eu, ev, n, uv_scale=1.0, flip=False):
    lu, lv = math.sqrt(sum(a * a for a in eu)), math.sqrt(sum(a * a for a in ev))
    pos = [[corner[i] + s * eu[i] + t * ev[i] for i in range(3)] for s, t in ((0, 0), (1, 0), (1, 1), (0, 1))]
    uv = [[s * lu * uv_scale, 1 - t * lv * uv_scale] for s, t in ((0, 0), (1, 0), (1, 1), (0, 1))]
    idx = [0, 2, 1, 0, 3, 2] if flip else [0, 1, 2, 0, 2, 3]
    return pos, [list(n)] * 4, uv, idx


def cylinder(r, h, seg=32):
    pos, nrm, uv, idx = [], [], [], []
    for k in range(seg + 1):
        a = 2 * math.pi * k / seg
        c, s = math.cos(a), math.sin(a)
        pos += [[r * c, 0, r * s], [r * c, h, r * s]]
        nrm += [[c, 0, s], [c, 0, s]]
        uv += [[k / seg, 1], [k / seg, 0]]
    for k in range(seg):
        b = 2 * k
        idx += [b, b + 1, b + 3, b, b + 3, b + 2]
    return pos, nrm, uv, idx


def main():
    os.makedirs(OUT, exist_ok=True)
    # Floor tiles: warm terracotta checks with grout, sRGB colour.
    def tile(x, y):
        u, v = x / 64.0, y / 64.0
        grout = min(u % 0.5, 0.5 - u % 0.5, v % 0.5, 0.5 - v % 0.5) < 0.015
        odd = (int(u * 2) + int(v * 2)) % 2
        base = (0.62, 0.36, 0.24) if odd else (0.55, 0.31, 0.2)
        return (0.8, 0.78, 0.74) if grout else base
    write_png(os.path.join(OUT, "interior_tiles.png"), 64, 64, 3, tile)

    b = Builder()
    W, H, D = 5.0, 2.8, 4.0  # room: x in [-W/2, W/2], y in [0, H], z in [-D, 0]
    M_FLOOR, M_WALL, M_OAK, M_STEEL, M_GLASS, M_SHADE, M_TOP = range(7)
    win = (-0.9, 0.9, 0.9, 2.2)  # window in the back wall: x0, x1, y0, y1
    parts = [quad([-W / 2, 0, 0], [W, 0, 0], [0, 0, -D], (0, 1, 0)) + (M_FLOOR,)]
    # walls facing inwards; the back wall (z = -D) has the window
    x0, x1, y0, y1 = win
    for c, eu, ev in (([-W / 2, 0, -D], [x0 + W / 2, 0, 0], [0, H, 0]), ([x1, 0, -D], [W / 2 - x1, 0, 0], [0, H, 0]),
                      ([x0, 0, -D], [x1 - x0, 0, 0], [0, y0, 0]), ([x0, y1, -D], [x1 - x0, 0, 0], [0, H - y1, 0])):
        parts.append(quad(c, eu, ev, (0, 0, 1)) + (M_WALL,))
    parts.append(quad([-W / 2, 0, 0], [0, 0, -D], [0, H, 0], (1, 0, 0)) + (M_WALL,))
    parts.append(quad([W / 2, 0, -D], [0, 0, D], [0, H, 0], (-1, 0, 0)) + (M_WALL,))
    parts.append(quad([-W / 2, H, -D], [W, 0, 0], [0, 0, D], (0, -1, 0)) + (M_WALL,))
    room = b.mesh("Room", [p[:4] + (p[4],) for p in parts])
    pane = b.mesh("WindowPane", [quad([x0, y0, -D + 0.05], [x1 - x0, 0, 0], [0, y1 - y0, 0], (0, 0, 1)) + (M_GLASS,)])
    top = b.mesh("TableTop", [box((-0.8, 0.72, -0.45), (0.8, 0.76, 0.45)) + (M_TOP,)])
    leg = b.mesh("TableLeg", [box((-0.03, 0, -0.03), (0.03, 0.72, 0.03)) + (M_STEEL,)])
    seat = b.mesh("Chair", [box((-0.22, 0.42, -0.22), (0.22, 0.46, 0.22)) + (M_OAK,),
                            box((-0.22, 0.46, 0.18), (0.22, 0.9, 0.22)) + (M_OAK,)] +
                 [box((sx * 0.2 - 0.02, 0, sz * 0.2 - 0.02), (sx * 0.2 + 0.02, 0.42, sz * 0.2 + 0.02)) + (M_STEEL,)
                  for sx in (-1, 1) for sz in (-1, 1)])
    lamp = b.mesh("Lamp", [cylinder(0.18, 0.25) + (M_SHADE,)])
    legs = [b.node("Leg.%d" % i, leg, translation=[sx * 0.72, 0, sz * 0.38])
            for i, (sx, sz) in enumerate(((-1, -1), (1, -1), (-1, 1), (1, 1)))]
    table_top = b.node("Top", top)
    table = b.node("Table", children=[table_top] + legs, translation=[0.3, 0, -2.2])
    def yaw(deg):
        a = math.radians(deg) / 2
        return [0, math.sin(a), 0, math.cos(a)]
    chair1 = b.node("Chair.001", seat, translation=[0.3, 0, -1.45], rotation=yaw(0))
    chair2 = b.node("Chair.002", seat, translation=[1.45, 0, -2.2], rotation=yaw(-90))
    # The lamp hangs from the ceiling: a matrix node (column-major, as glTF stores it).
    lamp_node = b.node("Lamp", lamp, matrix=[1, 0, 0, 0, 0, 1, 0, 0, 0, 0, 1, 0, 0.3, 2.2, -2.2, 1])
    room_node = b.node("Room", room)
    pane_node = b.node("Window", pane)
    root = b.node("Interior", children=[room_node, pane_node, table, chair1, chair2, lamp_node])

    materials = [
        {"name": "Tiles", "pbrMetallicRoughness": {"baseColorTexture": {"index": 0, "extensions": {
            "KHR_texture_transform": {"scale": [1.5, 1.5]}}}, "metallicFactor": 0, "roughnessFactor": 0.45}},
        {"name": "Plaster", "pbrMetallicRoughness": {"baseColorFactor": [0.82, 0.8, 0.76, 1], "metallicFactor": 0,
                                                      "roughnessFactor": 1}},
        {"name": "Oak", "pbrMetallicRoughness": {"baseColorFactor": [0.45, 0.28, 0.14, 1], "metallicFactor": 0,
                                                  "roughnessFactor": 0.6}},
        {"name": "Steel", "pbrMetallicRoughness": {"baseColorFactor": [0.75, 0.75, 0.77, 1], "metallicFactor": 1,
                                                    "roughnessFactor": 0.3}},
        {"name": "Glass", "pbrMetallicRoughness": {"baseColorFactor": [1, 1, 1, 1], "metallicFactor": 0,
                                                    "roughnessFactor": 0},
         "extensions": {"KHR_materials_transmission": {"transmissionFactor": 1}, "KHR_materials_ior": {"ior": 1.5}}},
        {"name": "LampShade", "pbrMetallicRoughness": {"baseColorFactor": [0.9, 0.85, 0.7, 1], "metallicFactor": 0},
         "emissiveFactor": [1, 0.85, 0.6], "extensions": {"KHR_materials_emissive_strength": {"emissiveStrength": 3000}}},
        {"name": "Lacquer", "pbrMetallicRoughness": {"baseColorFactor": [0.3, 0.12, 0.06, 1], "metallicFactor": 0,
                                                      "roughnessFactor": 0.5},
         "extensions": {"KHR_materials_clearcoat": {"clearcoatFactor": 1, "clearcoatRoughnessFactor": 0.05}}},
    ]
    gltf = {
        "asset": {"version": "2.0", "generator": "archwave scripts/make_gltf_interior.py"},
        "extensionsUsed": ["KHR_texture_transform", "KHR_materials_transmission", "KHR_materials_ior",
                           "KHR_materials_emissive_strength", "KHR_materials_clearcoat"],
        "scene": 0, "scenes": [{"nodes": [root]}], "nodes": b.nodes, "meshes": b.meshes,
        "materials": materials,
        "textures": [{"source": 0, "sampler": 0}], "images": [{"uri": "interior_tiles.png"}],
        "samplers": [{"wrapS": 10497, "wrapT": 10497}],
        "accessors": b.accessors, "bufferViews": b.views,
        "buffers": [{"byteLength": len(b.bin),
                     "uri": "data:application/octet-stream;base64," + base64.b64encode(bytes(b.bin)).decode()}],
    }
    with open(os.path.join(OUT, "interior.gltf"), "w") as f:
        json.dump(gltf, f, indent=1)
        f.write("\n")
    print("wrote %s (%d bytes of geometry)" % (os.path.normpath(os.path.join(OUT, "interior.gltf")), len(b.bin)))


if __name__ == "__main__":
    main()

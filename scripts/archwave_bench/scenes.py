"""The scenes the suite renders, and the generated torus-knot meshes."""

import hashlib
import json
import os
import subprocess
import sys
from dataclasses import dataclass, field

from . import REPO
from .tools import SuiteError, log


@dataclass
class BenchScene:
    key: str          # short name, part of file names and of the reference cache key
    title: str
    path: str         # scene file
    width: int
    height: int
    defines: list = field(default_factory=list)
    mesh: tuple = None  # (segments, rings) of a generated knot the defines point at

    def scene_hash(self):
        """Scene file (and any mesh it was pointed at) plus resolution and overrides: what
        determines the converged image besides the code."""
        h = hashlib.sha256()
        with open(self.path, "rb") as f:
            h.update(f.read())
        h.update(json.dumps([self.width, self.height, sorted(self.defines)]).encode())
        for d in self.defines:
            if ".file=" in d:  # a generated mesh: its name encodes its resolution
                h.update(os.path.basename(d.split("=", 1)[1]).encode())
        return h.hexdigest()[:16]

    def rel_path(self, start=REPO):
        return os.path.relpath(self.path, start)


def scene_file(*parts):
    return os.path.join(REPO, "scenes", *parts)


def scene_size(path, width):
    """(width, height) keeping the scene's own aspect ratio."""
    with open(path) as f:
        r = json.load(f).get("render", {})
    aspect = r.get("height", 480) / r.get("width", 640)
    return width, max(1, int(round(width * aspect)))


def knot_mesh(mesh_dir, segments, rings):
    """A (2,3) torus-knot tube of 2 * segments * rings triangles from scripts/gen_torus_knot.py,
    generated once and cached (large OBJs are never committed)."""
    os.makedirs(mesh_dir, exist_ok=True)
    path = os.path.join(mesh_dir, f"knot_{segments}x{rings}.obj")
    if not os.path.exists(path):
        log(f"generating {path} ({2 * segments * rings} triangles)")
        tmp = path + f".tmp{os.getpid()}"  # a run killed half-way leaves no truncated mesh behind
        argv = [sys.executable, os.path.join(REPO, "scripts", "gen_torus_knot.py"), tmp, str(segments), str(rings)]
        p = subprocess.run(argv, capture_output=True, text=True)
        if p.returncode != 0:
            raise SuiteError(f"command failed (exit {p.returncode}):\n  {' '.join(argv)}\nstderr:\n{p.stderr}")
        os.replace(tmp, path)
    return path


def bench_scenes(quick, mesh_dir):
    """The shared scenes by key, at the suite's sweep resolution (32 or 128 pixels wide)."""
    w = 32 if quick else 128

    def scene(key, title, path, **kw):
        return BenchScene(key, title, path, *scene_size(path, w), **kw)
    segs, rings = (64, 32) if quick else (2048, 256)
    mesh = os.path.join(mesh_dir, f"knot_{segs}x{rings}.obj")
    return {
        "cornell": scene("cornell", "Cornell box (Lambert only)", scene_file("cornell.json")),
        "glossy": scene("glossy", "glossy and refractive (every lobe)", scene_file("materials.json")),
        "docs_glossy": scene("docs_glossy", "the documentation's glossy Fresnel example",
                             scene_file("docs", "glossy_fresnel.json")),
        "mesh": scene("mesh", f"torus knot, {2 * segs * rings:,} triangles", scene_file("knot.json"),
                      defines=[f"objects[0].file={mesh}"], mesh=(segs, rings)),
    }

#!/usr/bin/env python3
"""bench/race_scene.py reads archwave's own triangles (archwave --export-geometry) instead of
tessellating shapes itself: every object of the race scenes gets its mesh, with the triangle
count archwave reports, vertex normals where archwave has them, and indices in range; a
scene description without the geometry refuses to give triangles.

Usage: race_scene_test.py ARCHWAVE_BINARY SOURCE_DIR"""
import os
import re
import subprocess
import sys
import tempfile

archwave, src = sys.argv[1], sys.argv[2]
sys.path.insert(0, os.path.join(src, "bench"))
import race_scene  # noqa: E402

failures = []
for rel in ("scenes/cornell.json", "scenes/bench/race_spheres.json", "scenes/bench/race_small_light.json"):
    scene = os.path.join(src, rel)
    with tempfile.TemporaryDirectory() as tmp:
        obj = os.path.join(tmp, "g.obj")
        p = subprocess.run([archwave, scene, "--export-geometry", obj], capture_output=True, text=True)
        if p.returncode != 0:
            failures.append(f"{rel}: archwave --export-geometry exited {p.returncode}: {p.stderr.strip()}")
            continue
        want = int(re.search(r"(\d+) triangles", p.stderr).group(1))
        d = race_scene.describe(scene, geometry=obj)
        got = 0
        for o in d["objects"]:
            pos, nrm, tris = race_scene.triangles(o)
            got += len(tris)
            if nrm is not None and len(nrm) != len(pos):
                failures.append(f"{rel} {o['where']}: {len(nrm)} normals for {len(pos)} positions")
            if o["shape"] == "sphere" and nrm is None:
                failures.append(f"{rel} {o['where']}: a sphere without vertex normals")
            if any(not (0 <= i < len(pos)) for t in tris for i in t):
                failures.append(f"{rel} {o['where']}: a triangle index out of range")
        if got != want:
            failures.append(f"{rel}: {got} triangles read, archwave reported {want}")
        try:
            race_scene.triangles(race_scene.describe(scene)["objects"][0])
            failures.append(f"{rel}: triangles() without geometry did not refuse")
        except race_scene.Unsupported:
            pass
for f in failures:
    print("FAIL:", f)
print("race_scene_test:", "failed" if failures else "ok")
sys.exit(1 if failures else 0)

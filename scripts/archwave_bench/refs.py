"""High-spp references, keyed by scene and by the code that renders it."""

import datetime
import hashlib
import json
import os

from . import REF_SEED, REPO
from .tools import git, log


def code_key():
    """Git tree hashes of kernels/ and host/ (what decides the image), plus a hash of any
    uncommitted change there, so a reference is never reused across code that renders
    differently."""
    trees = [git("rev-parse", f"HEAD:{d}") or "untracked" for d in ("kernels", "host")]
    dirty = git("status", "--porcelain", "--untracked-files=all", "--", "kernels", "host")
    key = "-".join(t[:12] for t in trees)
    if dirty:
        h = hashlib.sha256(git("diff", "HEAD", "--", "kernels", "host").encode())
        for line in dirty.splitlines():
            path = os.path.join(REPO, line[3:])
            if line.startswith("??") and os.path.isfile(path):
                with open(path, "rb") as f:
                    h.update(f.read())
        key += "-dirty" + h.hexdigest()[:10]
    return key


class References:
    """High-spp references, rendered by the project with REF_SEED and cached under
    RESULTS/refs/<scene>-<hash>/ with ref.json (spp, seed, time, commit, command). A cached
    reference is reused when it has at least the spp asked for."""

    def __init__(self, tools, cache_dir, renderer):
        self.tools = tools
        self.cache_dir = cache_dir
        self.scalar = renderer == "scalar"
        self.code = code_key()

    def _dir(self, scene):
        key = hashlib.sha256((scene.scene_hash() + self.code + str(self.scalar)).encode()).hexdigest()[:16]
        return os.path.join(self.cache_dir, f"{scene.key}-{key}")

    def cached(self, scene):
        meta = os.path.join(self._dir(scene), "ref.json")
        if os.path.exists(meta) and os.path.exists(os.path.join(self._dir(scene), "ref.exr")):
            with open(meta) as f:
                return json.load(f)
        return None

    def get(self, scene, spp):
        """(exr path, metadata) of a reference with >= spp samples per pixel."""
        d = self._dir(scene)
        meta = self.cached(scene)
        if meta and meta["spp"] >= spp:
            meta["reused"] = True
            return os.path.join(d, "ref.exr"), meta
        os.makedirs(d, exist_ok=True)
        log(f"reference {scene.key}: {spp} spp ({'scalar' if self.scalar else 'wavefront'})")
        r = self.tools.render(scene.path, "ref", spp, scene.width, scene.height, seed=REF_SEED,
                              defines=scene.defines, scalar=self.scalar, out_dir=d)
        meta = {"scene": os.path.relpath(scene.path, REPO), "width": scene.width, "height": scene.height,
                "defines": scene.defines, "spp": spp, "seed": REF_SEED, "renderer": r.stats["renderer"],
                "device": r.stats["device"], "total_seconds": r.stats["total_seconds"],
                "render_seconds": r.seconds, "wall_seconds": r.wall, "git_commit": git("rev-parse", "HEAD"),
                "code_key": self.code, "command": r.command,
                "date": datetime.datetime.now().isoformat(timespec="seconds")}
        with open(os.path.join(d, "ref.json"), "w") as f:
            json.dump(meta, f, indent=2)
        meta["reused"] = False
        return os.path.join(d, "ref.exr"), meta

    def cost(self, scene, spp, per_spp, overhead):
        """Seconds get(scene, spp) would take (0 when the cache already has it)."""
        meta = self.cached(scene)
        return 0.0 if meta and meta["spp"] >= spp else overhead + per_spp * spp

    def calibrate(self, scene, name, spp):
        """A render at REF_SEED with the reference renderer: its seconds per spp price a reference."""
        return self.tools.render(scene.path, name, spp, scene.width, scene.height, seed=REF_SEED,
                                 defines=scene.defines, scalar=self.scalar)

    def within(self, scene, want, max_seconds):
        """A reference with `want` spp, or the most a calibration says fits in max_seconds
        (a power of two, at least 64), or a cached one if that is better still."""
        cached = self.cached(scene)
        if cached and cached["spp"] >= want:
            return self.get(scene, want)
        cal = self.calibrate(scene, f"refcal_{scene.key}", 4)
        spp = want
        while spp > 64 and cal.overhead + cal.seconds / 4 * spp > max_seconds:
            spp //= 2
        if cached and cached["spp"] >= spp:
            spp = cached["spp"]
        return self.get(scene, spp)

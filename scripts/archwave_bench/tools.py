"""The programs under test: archwave, exr_compare and bench_traversal, run as a user runs them."""

import json
import os
import re
import shlex
import subprocess
import sys
import time
from dataclasses import dataclass

from . import REPO


class SuiteError(Exception):
    """A program the suite ran failed; the message names the command and its stderr."""


def log(msg):
    print(f"[bench {time.strftime('%H:%M:%S')}] {msg}", file=sys.stderr, flush=True)


def git(*args):
    try:
        return subprocess.run(["git", "-C", REPO] + list(args), capture_output=True, text=True,
                              check=True).stdout.strip()
    except (subprocess.CalledProcessError, FileNotFoundError):
        return ""


@dataclass
class Render:
    stats: dict
    exr: str
    wall: float  # seconds around the whole process (scene load and EXR write included)
    command: str

    @property
    def seconds(self):
        """The time the samples took: total minus kernel build and BVH build."""
        return self.stats["render_seconds"]

    @property
    def overhead(self):
        """Per-process cost besides the samples: start-up, scene load, BVH, EXR write. A cold
        kernel build is left out: it happens once per feature set, not per render."""
        return max(0.0, self.wall - self.seconds - self.stats["compile_seconds"])


class Tools:
    """Runs archwave, exr_compare and bench_traversal; every command goes to commands.log,
    and a failure raises SuiteError with the command and the tail of its stderr."""

    def __init__(self, build, work, device, log_path):
        self.archwave = os.path.join(build, "archwave")
        self.exr_compare = os.path.join(build, "bench", "exr_compare")
        self.traversal_bin = os.path.join(build, "bench", "bench_traversal")
        for prog in (self.archwave, self.exr_compare, self.traversal_bin):
            if not os.access(prog, os.X_OK):
                raise SuiteError(f"{prog} is missing: build first (scripts/build.sh, or --build DIR)")
        self.work = work
        self.device = device
        self.log_path = log_path
        self.count = 0

    def run(self, argv, env=None, timeout=3600):
        cmd = " ".join(shlex.quote(a) for a in argv)
        t0 = time.monotonic()
        try:
            p = subprocess.run(argv, capture_output=True, text=True, env=env, timeout=timeout)
        except subprocess.TimeoutExpired:
            raise SuiteError(f"command timed out after {timeout} s:\n  {cmd}")
        wall = time.monotonic() - t0
        with open(self.log_path, "a") as f:
            f.write(f"{wall:8.2f} s  {cmd}\n")
        if p.returncode != 0:
            tail = "\n".join(p.stderr.strip().splitlines()[-25:])
            raise SuiteError(f"command failed (exit {p.returncode}):\n  {cmd}\nstderr:\n{tail}")
        return p, wall, cmd

    def render(self, scene, name, spp, width, height, seed=0, defines=(), scalar=False, generic=False,
               device=None, pocl_cache=None, out_dir=None, extra_args=()):
        """One archwave render; returns its stats (from --stats-json), EXR path and times. `device`:
        None for the suite's (--device), "" for none (archwave renders on the device it picks)."""
        self.count += 1
        stem = os.path.join(out_dir or self.work, name)
        argv = [self.archwave, scene, "-o", stem + ".exr", "--stats-json", stem + ".json", "-q", "--no-progress",
                "--spp", str(int(spp)), "--seed", str(seed), "--width", str(width), "--height", str(height)]
        for d in defines:
            argv += ["-D", d]
        if scalar:
            argv.append("--scalar")
        elif device != "":  # "": the CLI's own choice (the fastest device it measured)
            argv += ["--device", str(self.device if device is None else device)]
        if generic:
            argv.append("--generic-kernels")
        argv += list(extra_args)
        env = dict(os.environ, POCL_CACHE_DIR=pocl_cache) if pocl_cache else None
        _, wall, cmd = self.run(argv, env=env)
        with open(stem + ".json") as f:
            stats = json.load(f)
        return Render(stats, stem + ".exr", wall, cmd)

    def compare(self, exr, ref):
        p, _, _ = self.run([self.exr_compare, "--json", exr, ref])
        return json.loads(p.stdout)

    def traversal(self, args, out_json):
        _, _, cmd = self.run([self.traversal_bin, "--device", str(self.device), "--json", out_json] + args)
        with open(out_json) as f:
            return json.load(f), cmd

    def list_devices(self):
        """[(index, description)] from `archwave --list-devices` ("[i] name (...)" lines)."""
        p, _, _ = self.run([self.archwave, "--list-devices"])
        devs = []
        for line in p.stdout.splitlines():
            m = re.match(r"\s*\[(\d+)\]\s*(.*)", line)
            if m:
                devs.append((int(m.group(1)), m.group(2).strip()))
        return devs

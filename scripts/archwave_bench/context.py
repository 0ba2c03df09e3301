"""One run's shared state: its folders, programs, references, scenes, budget clock and plots,
and the timed render every section uses (warm kernels first)."""

import datetime
import math
import os
import time

from . import DOCS_MARK, LARGE_GRID_JOBS
from .refs import References
from .scenes import bench_scenes, knot_mesh
from .tools import Tools


def _fresh_folder(results):
    """RESULTS/<timestamp>, with a suffix when two runs start in the same second (tests)."""
    stamp = datetime.datetime.now().strftime("%Y%m%d-%H%M%S")
    out = os.path.join(results, stamp)
    suffix = 1
    while os.path.exists(out):
        out = os.path.join(results, f"{stamp}-{suffix}")
        suffix += 1
    return out


class Context:
    def __init__(self, args):
        self.args = args
        self.quick = args.quick
        self.t0 = time.monotonic()
        self.budget = args.budget_minutes * 60.0
        self.results = os.path.abspath(args.results)
        self.out = _fresh_folder(self.results)
        self.work = os.path.join(self.out, "renders")
        self.tools = Tools(os.path.abspath(args.build), self.work, args.device,
                           os.path.join(self.out, "commands.log"))
        os.makedirs(self.work)
        self.refs = References(self.tools, os.path.join(self.results, "refs"), args.ref_renderer)
        self.mesh_dir = os.path.join(self.results, "meshes")
        self.scenes = bench_scenes(self.quick, self.mesh_dir)
        self.plots = []            # file names of the PNGs written into self.out
        self.notes = {}            # facts a section finds that the report's header uses
        self.warm_kernels = set()  # (kernel features, device) whose large-grid variants are compiled

    def elapsed(self):
        return time.monotonic() - self.t0

    def left(self):
        return self.budget - self.elapsed()

    def png(self, name):
        """The path to write plot NAME to; the report links it as NAME."""
        self.plots.append(name)
        return os.path.join(self.out, name)

    def ensure_mesh(self, scene):
        if scene.mesh:
            knot_mesh(self.mesh_dir, *scene.mesh)

    @staticmethod
    def docs_link(name):
        """A link to docs/NAME that works from the results folder; the report resolves it."""
        return f"{DOCS_MARK}{name}"

    def warm_up(self, path, spp=1, defines=(), generic=False, device=None):
        """Compiles every kernel variant a timed render will use, before it is timed.

        PoCL builds a work-group function per kernel and grid class: one for small launches
        and one for launches above about 2^16 items. archwave's build step launches both now,
        so they count as kernel build; warming with a render of 2^18 jobs still guards the
        timings against anything compiled lazily. Same spp as the timed render, since
        spp decides whether lobe splitting is compiled in; no generated mesh (the kernels
        depend on materials and lights, not on the triangles)."""
        side = max(8, math.ceil(math.sqrt(LARGE_GRID_JOBS / spp)))
        defs = [d for d in defines if ".file=" not in d]
        r = self.tools.render(path, "warm_up", spp, side, side, defines=defs, generic=generic, device=device)
        self.warm_kernels.add((r.stats["kernel_features"], device))

    def render(self, path, name, spp, width, height, defines=(), scalar=False, generic=False, device=None,
               extra_args=()):
        """A timed render with warm kernels. A render whose kernel variant was not warmed yet
        (e.g. one that turns lobe splitting on) is warmed up and rendered again."""
        def run():
            return self.tools.render(path, name, spp, width, height, defines=defines, scalar=scalar,
                                     generic=generic, device=device, extra_args=extra_args)
        r = run()
        if scalar or (r.stats["kernel_features"], device) in self.warm_kernels:
            return r
        self.warm_up(path, spp, defines, generic, device)
        return run()

    def render_scene(self, scene, name, spp, **kw):
        """ctx.render at the scene's own size and defines."""
        return self.render(scene.path, name, spp, scene.width, scene.height, defines=scene.defines, **kw)

"""``sylva warmup``: compile every kernel the commands use, ahead, on all cores.

A fresh install has no compiled kernels: numba compiles each the first time a command
reaches it (tens of seconds) and caches it on disk.  This command runs each command's work
once at a tiny size, one group per process, so that later runs only load from the cache.
Groups that build on the turtle and the mesh builder start after ``plants``, which
compiles those, so that no two processes compile the same kernel.  ``--profile FILE``
writes a JSON line per kernel compiled (group, process, kernel, signature, CPU seconds
with and without the kernels compiled inside it): where a cold start's time goes
(``benchmarks/cold_test.py`` sums it up).
"""

from __future__ import annotations

import contextlib
import io
import json
import multiprocessing
import os
import sys
import tempfile
import time
from concurrent.futures import FIRST_COMPLETED, ProcessPoolExecutor, wait
from pathlib import Path

__all__ = ["GROUPS", "register", "warm"]


_errors: list[str] = []  # of the group running in this (worker) process


def _cli(*argv: str) -> None:
    """Run ``sylva ARGV`` here, quietly; a failure is noted and the group goes on."""
    from . import main

    try:
        with contextlib.redirect_stdout(io.StringIO()), contextlib.redirect_stderr(io.StringIO()):
            rc = main(list(argv))
    except Exception as exc:  # a command that cannot run here (no OpenGL …) is reported
        rc = f"{type(exc).__name__}: {exc}".splitlines()[0][:160]
    if rc:
        _errors.append(f"sylva {argv[0]} {argv[1]}: {rc}")


def _derivation(tmp: Path) -> None:
    from ..data import examples
    from ..lsystem.environment import has_communication, has_queries
    from .derive import load_program

    for ex in examples():
        program = load_program(str(ex.path))
        if has_queries(program) or has_communication(program):
            continue  # the turtle answers between steps: the plants group runs these
        _cli("derive", str(ex.path), "-n", "3", "--stats")


def _plants(tmp: Path) -> None:
    from ..data import examples, find

    for ex in examples():
        _cli("export", str(ex.path), "-n", "2", "-o", str(tmp / "plant.glb"))
    bush = str(find("16-abop-1.25-bush").path)
    _cli("export", bush, "-n", "2", "--mode", "prism", "-o", str(tmp / "p.obj"))
    _cli("export", bush, "-n", "2", "--mode", "cone", "-o", str(tmp / "p.ply"))


def _textures(tmp: Path) -> None:
    from ..texture import PRESETS, TEXTURE_KINDS

    for kind in [*TEXTURE_KINDS, *PRESETS]:
        if not _walks(kind):
            _cli("texture", kind, "--size", "24x16", "-o", str(tmp / "t.png"))
    _cli("texture", "perlin", "--size", "24x16", "--tileable", "-o", str(tmp / "t.png"))
    from ..texture import _gridkernels32

    _gridkernels32.warm()  # noise_grid's float32 road (the default for arrays)
    _graphs()


def _walks(kind: str) -> bool:
    """Whether the texture ``kind`` (a kind or a preset) draws an L-system with the turtle
    (those run in the ``lsystems`` group, after ``plants`` compiled the turtle)."""
    from ..texture import PRESETS

    return kind == "lsystem" or PRESETS.get(kind, {}).get("kind") == "lsystem"


def _lsystem_textures(tmp: Path) -> None:
    from ..texture import PRESETS

    for kind in PRESETS:
        if _walks(kind):
            _cli("texture", kind, "--size", "24x16", "-o", str(tmp / "t.png"))
    _cli("texture", "--lsystem", "01-koch-snowflake", "--size", "24x16", "-o", str(tmp / "l.png"))


def _graphs() -> None:
    """The texture graphs' road (``sylva texture --graph``, the studio's texture mode, the
    baked bark and leaf of exports): the fused kernels of the built-in graphs and the
    point-wise and row kernels every graph calls, plus Worley orders above F3."""
    import numpy as np

    from ..texture import noise_grid, worley_features
    from ..texture.graph.library import marble_graph
    from ..texture.graph.surface import SURFACES, bake_surface

    for name in SURFACES:
        bake_surface(name, 8)
    for dtype in (np.float32, np.float64):
        marble_graph(seed=1).evaluate((4, 24), dtype=dtype)
    # a small graph of the tests or the studio runs its kernel as Python while that is not
    # compiled: the float64 lattice rows it then calls from Python (inlined in the kernels)
    from ..texture import graph as tg
    from ..texture.graph._compile import evaluate

    g = tg.Graph(tg.perlin(scale=2.0))
    for shape in ((2, 8), (2, 2, 8)):
        evaluate(g, shape, np.float64, road="python")
    worley_features([0.2, 3.7], [0.4, 1.1], order=6)
    noise_grid((4, 24), kind="worley", output="f4", dtype=np.float64)


def _worley32(tmp: Path) -> None:
    """The float32 Worley grids (among the slowest kernels to compile, about 21 CPU s), apart from
    the texture group so that they compile beside it (the texture group's
    ``_gridkernels32.warm()`` then loads them): every path its own warm-up takes."""
    import numpy as np

    from ..texture import noise_grid

    for shape in ((4, 24), (2, 3, 24)):
        for fractal in ("fbm", "ridged"):
            noise_grid(shape, kind="worley", fractal=fractal, octaves=2, dtype=np.float32)
    for output in ("f1", "f2"):
        for scale in (4.0, 1.0):
            noise_grid((2, 24), kind="worley", output=output, scale=scale, dtype=np.float32)


def _points32(tmp: Path) -> None:
    """noise_grid's float32 road of 4D grids, tileable simplex and domain warping (one
    serial kernel run on threads, about 20-24 CPU s), beside the texture group."""
    from ..texture import _points32

    _points32.warm()


def _render(tmp: Path) -> None:
    _cli("render", "01-koch-snowflake", "--size", "48x32", "-o", str(tmp / "r.png"))
    _cli("render", "16-abop-1.25-bush", "-n", "2", "--size", "48x32", "-o", str(tmp / "r.png"))
    _cli("animate", "10-abop-1.24a-plant", "-n", "2", "--size", "48x32", "--substeps", "2",
         "-o", str(tmp / "a.gif"))  # fmt: skip


def _trees(tmp: Path) -> None:
    from ..tree import species_names

    for name in species_names():
        _cli("tree", name, "--age", "2", "-o", str(tmp / "t.glb"))
    # the pruning trials' envelope test (no species prunes by age 2)
    _cli("tree", "weeping_willow", "--age", "3", "-o", str(tmp / "t.glb"))
    # and its road on NumPy's points, for a run too near the envelope for its own points
    import numpy as np

    from ..tree._kernels import envelope_exit

    envelope_exit(np.zeros((1, 3)), 1.0, 1.0, 0.5, 0.5, 0.5, 0.5)
    _cli("tree", species_names()[0], "--age", "2", "--animate", "wind", "--seconds", "0.2",
         "-o", str(tmp / "w.glb"))  # fmt: skip


def _world(tmp: Path) -> None:
    _cli("world", "--seed", "1", "--size", "32x32", "--chunk", "16", "--workers", "1",
         "--caves", "--quiet", "-o", str(tmp / "w.glb"))  # fmt: skip  (caves: the carver too)


def _studio(tmp: Path) -> None:
    from ..studio._work import _warm_up

    _warm_up()


#: name -> (what it compiles, the groups it waits for, the work)
GROUPS = {
    "derivation": ("rewriting kernels (every example)", (), _derivation),
    "plants": ("turtle and mesh kernels (every example)", ("derivation",), _plants),
    "textures": ("noise, pattern and fractal kernels (every kind and preset)", (), _textures),
    "render": ("rendering's textures, animation", ("plants",), _render),
    "trees": ("tree growth and wind (every species)", ("plants",), _trees),
    "world": ("terrain, biomes, vegetation, voxel meshing", ("plants",), _world),
    "studio": ("the studio's traced walk", ("plants",), _studio),
    "worley32": ("float32 Worley grids", (), _worley32),
    "lsystems": ("L-system textures (the turtle's)", ("plants",), _lsystem_textures),
    "points32": ("float32 4D, tileable-simplex and warped grids", (), _points32),
}

#: The order groups start in when a process is free: on two cores derivation and the long
#: texture group first, then the float32 Worley and 4D grids, then plants and what waits
#: for it (about 110 CPU s on each core instead of 141 beside 76; the 4D grids, last, had
#: made the second process the long pole: 181 s beside 143 on a znver3 VM).
_START = ("derivation", "textures", "worley32", "points32", "plants", "render", "trees",
          "world", "studio", "lsystems")


class _Profile:
    """Numba's compile events in this (worker) process: CPU seconds of each compile, in
    all and without the kernels compiled inside it."""

    def __init__(self):
        self.on = False
        self.group = ""
        self.stack: list[list[float]] = []
        self.records: list[dict] = []

    def install(self, group: str) -> None:
        self.group = group
        self.records = []
        if not self.on:
            from numba.core import event

            prof = self

            class _Listener(event.Listener):
                def on_start(self, ev):
                    prof.stack.append([time.process_time(), 0.0])

                def on_end(self, ev):
                    prof.end(ev)

            event.register("numba:compile", _Listener())
            self.on = True

    def end(self, ev) -> None:
        t0, inner = self.stack.pop()
        dt = time.process_time() - t0
        if self.stack:
            self.stack[-1][1] += dt
        f = ev.data["dispatcher"].py_func
        self.records.append({"group": self.group, "pid": os.getpid(), "module": f.__module__,
                             "name": f.__qualname__, "args": str(ev.data["args"]),
                             "cpu": round(dt, 4), "self": round(dt - inner, 4),
                             "depth": len(self.stack)})  # fmt: skip


_profile = _Profile()


def _run_group(name: str, profile: bool = False) -> tuple[str, int, float, str, list]:
    """In a worker process: run one group, silently; (name, kernels compiled, s, error,
    and with ``profile`` a record of each kernel compiled)."""
    from .._jit import announce, compiled, serialise_cache_saves

    serialise_cache_saves()  # the other workers compile into the same cache
    prog = announce(io.StringIO())
    if profile:
        _profile.install(name)
    # a worker process may have run other groups before: count and report this one's only
    before = {label: set(names) for label, names in prog.done.items()}
    _errors.clear()
    t = time.perf_counter()
    with tempfile.TemporaryDirectory(prefix="sylva-warmup-") as tmp:
        try:
            # compiled(): the work is tiny, and a cold cache would run it interpreted
            with contextlib.redirect_stderr(io.StringIO()), compiled():
                GROUPS[name][2](Path(tmp))
        except Exception as exc:
            _errors.append(f"{type(exc).__name__}: {exc}".splitlines()[0][:200])
    compiled = sum(len(v - before.get(label, set())) for label, v in prog.done.items())
    err = f"{len(_errors)} failed, first {_errors[0]}" if _errors else ""
    records = list(_profile.records) if profile else []
    return name, compiled, time.perf_counter() - t, err, records


def warm(names: list[str], jobs: int, out=sys.stderr, profile: list | None = None) -> int:
    """Run the groups ``names`` on ``jobs`` processes, each after the groups it waits for;
    print a line per group to ``out``; the number of groups that failed.  With a list
    ``profile``, a record of every kernel compiled is appended to it."""
    names = [n for n in (*_START, *GROUPS) if n in names]
    names = list(dict.fromkeys(names))
    left = list(names)
    done: set[str] = set()
    failed = 0
    t0 = time.perf_counter()
    out.write(f"sylva warmup: compiling sylva's kernels once, {len(names)} groups on "
              f"{jobs} process{'es' if jobs > 1 else ''} (later runs load them from the "
              "cache)\n")  # fmt: skip
    out.flush()
    ctx = multiprocessing.get_context("spawn")
    with ProcessPoolExecutor(max_workers=jobs, mp_context=ctx) as pool:
        running = {}
        while left or running:
            for n in list(left):
                if len(running) < jobs and all(d in done or d not in names
                                               for d in GROUPS[n][1]):  # fmt: skip
                    running[pool.submit(_run_group, n, profile is not None)] = n
                    left.remove(n)
            finished, _ = wait(running, return_when=FIRST_COMPLETED)
            for fut in finished:
                del running[fut]
                name, compiled, secs, err, records = fut.result()
                if profile is not None:
                    profile.extend(records)
                done.add(name)
                k = len(done)
                what = f"{compiled} kernels compiled" + (f" ({err})" if err else "")
                failed += bool(err)
                out.write(f"  [{k}/{len(names)}] {name:<9} {what} in {secs:.1f} s "
                          f"- {GROUPS[name][0]}\n")  # fmt: skip
                out.flush()
    out.write(f"sylva warmup: done in {time.perf_counter() - t0:.1f} s\n")
    out.flush()
    return failed


def register(sub) -> None:
    p = sub.add_parser(
        "warmup",
        help="compile every kernel ahead (a fresh install compiles on first use)",
        description="Compile the numba kernels that the commands use, once, on all cores, "
        "so that later runs start at once.  Groups: " + ", ".join(GROUPS) + ".",
    )
    p.add_argument("--only", metavar="GROUP[,GROUP]",
                   help="compile only these groups (default: all)")  # fmt: skip
    p.add_argument("--jobs", "-j", type=int, default=None,
                   help="worker processes (default: the number of cores)")
    p.add_argument("--profile", metavar="FILE",
                   help="write a JSON line per kernel compiled (group, kernel, CPU s) to FILE")
    p.set_defaults(func=run)


def run(args) -> int:
    from ..errors import SylvaError

    names = list(GROUPS) if not args.only else [n.strip() for n in args.only.split(",")]
    unknown = [n for n in names if n not in GROUPS]
    if unknown:
        raise SylvaError(f"--only: unknown group {', '.join(unknown)}; expected one of "
                         f"{', '.join(GROUPS)}")  # fmt: skip
    jobs = args.jobs or os.cpu_count() or 1
    if jobs < 1:
        raise SylvaError(f"--jobs: expected a number of processes >= 1, got {jobs}")
    records: list | None = [] if args.profile else None
    warm(names, jobs, profile=records)
    if records is not None:
        from .._atomic import atomic_write

        with atomic_write(args.profile, "w") as fh:
            fh.writelines(json.dumps(r) + "\n" for r in records)
    return 0

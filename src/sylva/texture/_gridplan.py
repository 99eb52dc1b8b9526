"""The plan of a noise grid: what :func:`~sylva.texture.noise_grid` derives from its arguments
before it samples (private; shared with the texture graph, whose generator nodes sample
exactly these coordinates), and the cold road of lattice noise on whole arrays.

The cold road: while the compiled noise drivers are not cached (a fresh install), a
fractal sum of value, classic or improved Perlin noise of at most :data:`ARRAY_WORK`
samples × octaves runs the kernels' own Python source (:func:`sylva._jit.interpreted`) on
NumPy arrays of all the coordinates at once (:func:`fractal_arrays`) instead of waiting
tens of seconds for numba: the source is arithmetic, ``math.floor`` and table indexing,
which NumPy evaluates element-wise in the same IEEE operations, so the values are the
compiled road's bit for bit (``tests/test_cold_start.py``)."""

from __future__ import annotations

import math
import os
import threading
from dataclasses import dataclass

import numpy as np

from .. import _jit

#: The base noise kinds (``_kernels.VALUE, PERLIN, IMPROVED``) whose source runs on arrays.
ARRAY_KINDS = (0, 1, 2)
#: The most samples × octaves a call runs on the cold road (about a second of NumPy, against
#: 10–25 s of compiling the drivers).
ARRAY_WORK = 1 << 23
#: Points evaluated together (bounds the temporaries: about 40 arrays of this many floats).
ARRAY_BLOCK = 1 << 15
_DEPS = ("sylva.texture._kernels", "sylva.texture._cellkernels")
#: The most samples a grid kernel that cannot run on arrays (simplex, Worley, 4D, tileable
#: simplex) runs by its Python source, sample by sample, while it is not compiled: 32²
#: Worley takes about 30 ms so, against 10–20 s of compiling (the blocks of a world's atlas).
SCALAR_WORK = 1 << 14
#: The grid kernels and the noise drivers, on the interpreted road for small grids.
GRID = _jit.road("sylva.texture._gridkernels", _DEPS, size=SCALAR_WORK)
SAMPLING = _jit.road("sylva.texture._sampling", _DEPS, size=SCALAR_WORK)


_pool: dict = {"pool": None, "size": 0}
_pool_lock = threading.Lock()
_in_pool = threading.local()


def _forget_pool() -> None:  # a forked child has none of its parent's threads
    _pool["pool"], _pool["size"] = None, 0


if hasattr(os, "register_at_fork"):
    os.register_at_fork(after_in_child=_forget_pool)


def _threads(n: int):
    """The process's pool of ``n`` or more threads for :func:`run_blocks`, started once: a
    grid of a few milliseconds (a 1024² Worley grid on two cores) cannot pay for starting
    threads on every call."""
    from concurrent.futures import ThreadPoolExecutor

    with _pool_lock:
        if _pool["size"] < n:
            # a bigger pool replaces the old one, which is not shut down: a call that took
            # it a moment ago may still submit to it; its idle threads end once it is freed
            _pool["pool"] = ThreadPoolExecutor(n, thread_name_prefix="sylva-blocks",
                                               initializer=_mark_pool_thread)  # fmt: skip
            _pool["size"] = n
        return _pool["pool"]


def _mark_pool_thread() -> None:
    _in_pool.inside = True


def run_blocks(kernel, nblocks, args):
    """``kernel(c0, c1, *args)`` over the blocks ``0 .. nblocks`` on numba's thread count of
    threads (the kernels are ``nogil``), handed out a few at a time so that a thread on a
    busier core takes fewer; on the calling thread alone where numba's thread count is 1
    (small work: ``noise._threads``) or where the caller is itself one of the pool's threads.
    The threads are one pool per process, started by the first call that needs them.  A
    serial kernel compiles in a third to a half of the time its ``parallel=True`` version
    takes (issue 25), and runs the same code."""
    import numba

    nt = min(numba.get_num_threads(), nblocks)
    if nt <= 1 or getattr(_in_pool, "inside", False):
        kernel(0, nblocks, *args)
        return
    step = max(1, nblocks // (8 * nt))
    _spread(nt, range(0, nblocks, step),
            lambda c0: kernel(c0, min(nblocks, c0 + step), *args))


def run_tasks(tasks):
    """The results of the callables ``tasks``, run side by side on :func:`run_blocks`' threads,
    each on one thread (numba's thread count 1 inside it: the ``parallel=True`` grid kernels
    then run on their caller's thread).  For a few independent grids, such as a warped
    grid's warp fields: one grid at a time on every thread left GNU OpenMP's threads
    spinning for milliseconds after each (its default wait policy), and on two cores that
    spin took the CPU from the :func:`run_blocks` rows that follow, which then ran no
    faster than on one core."""
    import numba

    nt = min(numba.get_num_threads(), len(tasks))
    if nt <= 1 or getattr(_in_pool, "inside", False) or not _concurrent_kernels():
        return [t() for t in tasks]
    out = [None] * len(tasks)

    def one(i):
        out[i] = tasks[i]()

    _spread(nt, range(len(tasks)), one, serial=True)
    return out


def _concurrent_kernels() -> bool:
    """Whether numba's threading layer takes ``parallel=True`` kernels from several threads at
    once: OpenMP and TBB do; numba's own workqueue (where neither library is installed)
    aborts the process on a concurrent launch (``run_tasks`` then runs its tasks one by
    one).  ``numba.get_num_threads`` chooses the layer if nothing has yet."""
    import numba

    try:
        return numba.threading_layer() in ("omp", "tbb")
    except ValueError:  # no parallel kernel has run in this process yet
        return False


def _spread(nt, items, do, serial=False):
    """``do(item)`` for every item, taken one by one by ``nt`` threads (the calling thread and
    ``nt - 1`` of the pool's); ``serial``: numba's thread count 1 on each while it works.  The
    first error stops the hand-out and is raised once every thread has stopped."""
    from concurrent.futures import wait

    import numba

    items = iter(items)
    lock = threading.Lock()
    failed = []

    def work():
        before = numba.get_num_threads()
        if serial:
            numba.set_num_threads(1)
        try:
            while True:
                with lock:
                    item = None if failed else next(items, None)
                if item is None:
                    return
                try:
                    do(item)
                except BaseException:
                    failed.append(True)  # the other threads take no more items
                    raise
        finally:
            if serial:
                numba.set_num_threads(before)

    pool = _threads(nt)
    futures = [pool.submit(work) for _ in range(nt - 1)]
    try:
        work()  # the calling thread takes its share too
    finally:
        wait(futures)  # no item is still being worked on when this returns
    for f in futures:
        f.result()


def grid_plan(shape, kind, fractal, scale, octaves, persistence, lacunarity, gain, seed,
               interpolation, tileable, time, offset, warp, normalize, output, metric, jitter,
               dtype, density):
    """Everything :func:`noise_grid` derives from its arguments before it samples: the
    checked shape, the noise set-up, per-axis coordinates and per-octave tables (also used by
    the texture graph, whose generator nodes sample exactly these coordinates)."""
    from . import _kernels as _k
    from .noise import (
        FRACTALS,
        NoiseError,
        _axis_flags,
        _dtype,
        _lookup,
        _octave_offsets,
        _octave_params,
        _setup,
        worley_order,
    )

    shape = tuple(int(s) for s in shape)
    if not 2 <= len(shape) <= 4 or min(shape) < 1:
        raise NoiseError(f"shape must have 2 to 4 positive sizes, got {shape}")
    if math.prod(shape) > 1 << 31:
        raise NoiseError(f"grid {shape} is too large")
    ndim = len(shape) + (time is not None)
    if ndim > 4:
        raise NoiseError("a 4D grid cannot take time as well (noise goes up to 4D)")
    mode = _lookup(FRACTALS, fractal, "fractal")
    norder = worley_order(output) if str(kind).lower() == "worley" else None
    setup = _setup(kind, seed, interpolation, "f3" if norder else output, metric, jitter,
                   density=density)
    octaves, persistence, lacunarity = _octave_params(octaves, persistence, lacunarity)
    if np.ndim(scale) == 0:
        scales = None
        if not np.isfinite(scale) or scale <= 0:
            raise NoiseError(f"scale must be a positive number, got {scale!r}")
    else:
        scales = [float(v) for v in scale]
        if len(scales) != len(shape) or not all(np.isfinite(v) and v > 0 for v in scales):
            raise NoiseError(f"scale needs {len(shape)} positive numbers (x, y, ...), got {scale}")
    flags = _axis_flags(tileable, len(shape))[::-1]  # x, y, z, w order
    sizes = list(shape[::-1])
    off = list(offset) + [0.0] * (4 - len(offset))
    dt = _dtype(dtype)
    width = sizes[0]
    torus = setup.kind == _k.SIMPLEX and any(flags)
    if torus and (len(shape) != 2 or not all(flags)):
        raise NoiseError(
            "tileable simplex supports 2D images (both axes, optionally with time); for"
            " tileable volumes use a lattice noise (value, perlin, improved or worley)"
        )
    if torus and warp:
        raise NoiseError("domain warping of tileable simplex is not supported")

    # per-axis base cell counts and coordinates (in base-octave lattice cells)
    cells = [scale * n / width for n in sizes] if scales is None else scales
    if any(flags):
        cells = [max(1, round(c)) if f else c for c, f in zip(cells, flags)]
    axes = []
    for a, n in enumerate(sizes):
        step = cells[a] / n
        axes.append(np.arange(n, dtype=np.float64) * step + off[a])
    if time is not None:
        axes.append(np.array([float(time) + off[len(sizes)]]))
    while len(axes) < 4:
        axes.append(np.zeros(1))
    allflags = flags + [False] * (4 - len(flags))

    amps = persistence ** np.arange(octaves, dtype=np.float64)
    freqs = np.empty((octaves, 4))
    pers = np.zeros((octaves, 4))
    for o in range(octaves):
        for a in range(4):
            f = lacunarity**o
            if allflags[a]:
                whole = max(1, round(cells[a] * f))
                pers[o, a] = whole
                f = whole / cells[a]
            freqs[o, a] = f
    offs = _octave_offsets(octaves)
    norm = 1.0 / amps.sum() if normalize else 1.0
    gain = float(gain)

    return _GridPlan(shape, ndim, mode, norder, setup, dt, torus, sizes, axes, freqs, amps,
                     offs, pers, norm, gain, cells, off)


@dataclass
class _GridPlan:
    shape: tuple
    ndim: int
    mode: int
    norder: int | None
    setup: object
    dt: np.dtype
    torus: bool
    sizes: list
    axes: list
    freqs: np.ndarray
    amps: np.ndarray
    offs: np.ndarray
    pers: np.ndarray
    norm: float
    gain: float
    cells: list
    offset: list


def by_arrays(kind: int, work: int, kernel) -> bool:
    """Whether ``work`` samples × octaves of noise ``kind``, which would run the compiled
    ``kernel``, take the cold road of :func:`fractal_arrays`."""
    return kind in ARRAY_KINDS and _jit.cold(kernel, work, ARRAY_WORK)


def fractal_arrays(kind, mode, ndim, px, py, pz, pw, freqs, amps, offs, pers, interp, perm,
                   perm12, vals, cg, wpar, norm, gain):
    """:func:`sylva.texture._sampling.run_points` (the fractal sum at ``n`` points) by the
    interpreted ``fractal_at`` on whole arrays, :data:`ARRAY_BLOCK` points at a time."""
    fractal_at = _jit.interpreted("sylva.texture._sampling", _DEPS).fractal_at
    n = px.shape[0]
    out = np.empty(n)
    with _jit._quiet():
        for a in range(0, n, ARRAY_BLOCK):
            b = min(n, a + ARRAY_BLOCK)
            out[a:b] = fractal_at(kind, mode, ndim, px[a:b], py[a:b], pz[a:b], pw[a:b],
                                  False, freqs, amps, offs, pers, interp, perm, perm12, vals,
                                  cg, wpar, norm, gain)  # fmt: skip
    return out


def grid_arrays(plan: _GridPlan) -> np.ndarray:
    """The float64 grid of ``plan`` (no warp, no torus) on the cold road: the grid's points
    (those of the compiled grid kernels, which equal the point-wise ones) through
    :func:`fractal_arrays`."""
    s, t = plan.setup, plan.setup.tables
    grids = np.meshgrid(*plan.axes[: plan.ndim][::-1], indexing="ij")[::-1]
    pts = [g.ravel() for g in grids]
    while len(pts) < 4:
        pts.append(np.zeros(pts[0].shape[0]))
    out = fractal_arrays(s.kind, plan.mode, plan.ndim, *pts, plan.freqs, plan.amps, plan.offs,
                         plan.pers, s.interp, t.perm, t.perm12, t.values, t.gradients, s.wpar,
                         plan.norm, plan.gain)  # fmt: skip
    return out.reshape(plan.shape)

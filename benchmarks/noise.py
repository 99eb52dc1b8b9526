"""Noise throughput of sylva.texture against FastNoise Lite and FastNoise2, same run.

Run:  .venv/bin/python benchmarks/noise.py [--repeat 11] [--size 1024]
      SYLVA_FASTNOISE2_LIB=/tmp/fn2/libsylva_fn2.so .venv/bin/python benchmarks/noise.py

Peers: FastNoise Lite (pyfastnoiselite, scalar C) always; FastNoise2 (MIT, C++17, SIMD with
runtime dispatch SSE2 .. AVX-512) when ``SYLVA_FASTNOISE2_LIB`` names a build of the small
C wrapper ``benchmarks/peers/fastnoise2_wrap.cpp`` (our code; nothing of FastNoise2 is in
the package or in CI).  Build it (about a minute; FastNoise2 v1.1.1 pins FastSIMD at
16450dae)::

    git clone --branch v1.1.1 https://github.com/Auburn/FastNoise2 /tmp/fn2
    git clone https://github.com/Auburn/FastSIMD /tmp/fastsimd
    git -C /tmp/fastsimd checkout 16450dae9528727e500e7254f635a671f9c7ee2d
    cd /tmp/fn2 && cmake -S . -B build -DCMAKE_BUILD_TYPE=Release -DBUILD_SHARED_LIBS=ON \
        -DFASTNOISE2_TOOLS=OFF -DFASTNOISE2_TESTS=OFF -DCPM_FastSIMD_SOURCE=/tmp/fastsimd
    cmake --build build -j2
    g++ -O2 -std=c++17 -shared -fPIC -I include -I /tmp/fastsimd/include \
        -I build/src/fastsimd/FastSIMD_FastNoise/include \
        <sylva>/benchmarks/peers/fastnoise2_wrap.cpp -o /tmp/fn2/libsylva_fn2.so \
        -L build/Release/lib -lFastNoise -Wl,-rpath,/tmp/fn2/build/Release/lib

FastNoise2 runs twice: at the best SIMD level of the CPU (printed) and capped at AVX2.
An AVX2 build of sylva's kernels on an AVX-512 machine (to compare with the capped
FastNoise2): ``NUMBA_CPU_NAME=haswell`` and ``NUMBA_CPU_FEATURES`` the host's features with
every ``avx512*`` / ``avx10*`` one turned off (``-``), ``SYLVA_BYTELANES=0`` and a
``NUMBA_CACHE_DIR`` of its own.
FastNoise2 generates the grid itself (``GenUniformGrid2D/3D``, one lattice cell per unit,
the same step as sylva's grid), single-threaded.  sylva runs both of its roads:
``dtype=float32`` (the default: float32 SIMD kernels) and ``dtype=float64`` (the
bit-exact road, rounded to float32 here would be the same work).

For each case every library produces the same number of samples: sylva evaluates a
regular grid with :func:`sylva.texture.noise_grid`; FastNoise Lite evaluates the same grid's
coordinates with ``FastNoiseLite.gen_from_coords`` (single-threaded).  sylva runs with
``numba.set_num_threads(1)`` for the one-core figures and with every core for the speed-up
(float32 road).

Measurement: ``--repeat`` rounds per case; a round times every contestant back to back
(each the best of ``--inner`` calls; the order within a round alternates), so that a slow
phase of a shared machine hits them alike.  Ratios and the speed-up are the medians of the
per-round ratios; the rates are the medians of the per-round rates, in million samples per
second.

The two-core speed-up of a shared virtual machine varies from moment to moment whatever the
code (the host decides where the virtual cores run), so every round also times a
trivially parallel arithmetic kernel on one and on all cores: its median speed-up
(``machine``) is what the machine gave during that case's rounds.
"""

from __future__ import annotations

import argparse
import ctypes
import math
import os
import statistics
import time

# the compiled kernels are what is measured: without this, a cold numba cache sends grids up
# to 2^23 samples down the interpreted cold-start road (sylva._jit.cold) and never compiles
os.environ.setdefault("SYLVA_JIT", "always")

import numba  # noqa: E402
import numpy as np  # noqa: E402
from pyfastnoiselite.pyfastnoiselite import FastNoiseLite, FractalType, NoiseType  # noqa: E402

from sylva.texture import noise_grid  # noqa: E402


@numba.njit(parallel=True)
def _probe_kernel(out):
    """Arithmetic only, rows in parallel: the machine's own multi-core speed-up."""
    ny, nx = out.shape
    for j in numba.prange(ny):
        for i in range(nx):
            x = (i + j) * 1e-3
            acc = 0.0
            for _ in range(12):
                acc = acc * 0.5 + x * (x * (x * 0.25 + 0.5) + math.sqrt(x))
            out[j, i] = acc


_PROBE_OUT = np.empty((1024, 1024), np.float32)


def _probe():
    _probe_kernel(_PROBE_OUT)


def _best(fn, inner: int) -> float:
    best = float("inf")
    for _ in range(inner):
        t0 = time.perf_counter()
        fn()
        best = min(best, time.perf_counter() - t0)
    return best


def _rounds(fns: dict, repeat: int, inner: int, cores: int):
    """Per-round times of ``fns`` (name -> (callable, threads)); the probe on one and on
    ``cores`` cores is added as ``probe1`` and ``probeN``."""
    fns = dict(fns, probe1=(_probe, 1), probeN=(_probe, cores))
    for fn, threads in fns.values():  # warm-up (and compile)
        numba.set_num_threads(threads)
        fn()
    rounds = []
    try:
        for r in range(repeat):
            order = list(fns)
            if r % 2:
                order.reverse()
            t = {}
            for what in order:
                fn, threads = fns[what]
                numba.set_num_threads(threads)
                t[what] = _best(fn, inner)
            rounds.append(t)
    finally:
        numba.set_num_threads(cores)
    return rounds


class _FastNoise2:
    """FastNoise2 through ``benchmarks/peers/fastnoise2_wrap.cpp`` (see the docstring)."""

    KINDS = {"improved": 0, "simplex": 1, "value": 2, "worley": 3}

    def __init__(self, path: str):
        lib = ctypes.CDLL(path)
        lib.sfn2_new.restype = ctypes.c_void_p
        lib.sfn2_new.argtypes = [ctypes.c_int, ctypes.c_int, ctypes.c_int]
        lib.sfn2_free.argtypes = [ctypes.c_void_p]
        lib.sfn2_level.restype = ctypes.c_char_p
        lib.sfn2_level.argtypes = [ctypes.c_void_p]
        fp = ctypes.POINTER(ctypes.c_float)
        lib.sfn2_grid2.argtypes = [ctypes.c_void_p, fp] + [ctypes.c_int] * 2 + [
            ctypes.c_float,
            ctypes.c_int,
        ]
        lib.sfn2_grid3.argtypes = [ctypes.c_void_p, fp] + [ctypes.c_int] * 3 + [
            ctypes.c_float,
            ctypes.c_int,
        ]
        # sfn2_grid4 and sfn2_new_warp: builds of the wrapper before them lack them
        self.more = hasattr(lib, "sfn2_grid4") and hasattr(lib, "sfn2_new_warp")
        if self.more:
            lib.sfn2_grid4.argtypes = [ctypes.c_void_p, fp] + [ctypes.c_int] * 4 + [
                ctypes.c_float,
                ctypes.c_int,
            ]
            lib.sfn2_new_warp.restype = ctypes.c_void_p
            lib.sfn2_new_warp.argtypes = [ctypes.c_int] * 3 + [ctypes.c_float]
        self.lib = lib

    def maker(self, kind: str, octaves: int, shape, step: float, avx2: bool, warp=None):
        """A callable filling a float32 grid of ``shape`` and the SIMD level it runs."""
        lib = self.lib
        if warp is None:
            h = lib.sfn2_new(self.KINDS[kind], octaves, int(avx2))
        else:
            h = lib.sfn2_new_warp(self.KINDS[kind], octaves, int(avx2), warp)
        if not h:
            return None, "n/a"
        out = np.empty(shape, np.float32)
        ptr = out.ctypes.data_as(ctypes.POINTER(ctypes.c_float))
        if len(shape) == 2:

            def run():
                lib.sfn2_grid2(h, ptr, shape[1], shape[0], step, 1337)
        elif len(shape) == 3:

            def run():
                lib.sfn2_grid3(h, ptr, shape[2], shape[1], shape[0], step, 1337)
        else:

            def run():
                lib.sfn2_grid4(h, ptr, shape[3], shape[2], shape[1], shape[0], step, 1337)

        run.keep = (h, out)
        return run, lib.sfn2_level(h).decode()


def _fnl(noise_type, octaves: int) -> FastNoiseLite:
    n = FastNoiseLite(1337)
    n.noise_type = noise_type
    n.frequency = 1.0
    if octaves > 1:
        n.fractal_type = FractalType.FractalType_FBm
        n.fractal_octaves = octaves
        n.fractal_gain = 0.5
        n.fractal_lacunarity = 2.0
    else:
        n.fractal_type = FractalType.FractalType_None
    return n


def main(argv=None) -> int:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--repeat", type=int, default=11, help="rounds per case")
    ap.add_argument("--inner", type=int, default=3, help="calls per timing (best is kept)")
    ap.add_argument(
        "--size", type=int, default=1024, help="2D grid side (3D: 16 x side/4 x side/4)"
    )
    ap.add_argument("--only", default="", help="run the cases whose name contains this")
    args = ap.parse_args(argv)
    n2 = args.size
    shape2 = (n2, n2)
    side3 = max(1, int(round((n2 * n2 / 16) ** 0.5)))
    shape3 = (16, side3, side3)  # as many samples as the 2D grid, rows as long as possible
    scale = 64.0  # lattice cells across the width

    def coords(shape):
        axes = [np.arange(s, dtype=np.float32) * np.float32(scale / shape[-1]) for s in shape]
        grids = np.meshgrid(*axes, indexing="ij")
        return np.ascontiguousarray(np.stack([g.ravel() for g in grids[::-1]]))

    c2 = coords(shape2)
    c3 = coords(shape3)
    cases = [
        ("2D improved Perlin", shape2, "improved", 1, c2, NoiseType.NoiseType_Perlin),
        ("2D simplex", shape2, "simplex", 1, c2, NoiseType.NoiseType_OpenSimplex2),
        ("2D value", shape2, "value", 1, c2, NoiseType.NoiseType_Value),
        ("3D improved Perlin", shape3, "improved", 1, c3, NoiseType.NoiseType_Perlin),
        ("3D simplex", shape3, "simplex", 1, c3, NoiseType.NoiseType_OpenSimplex2),
        ("2D fBm 6 oct improved", shape2, "improved", 6, c2, NoiseType.NoiseType_Perlin),
        ("2D fBm 6 oct simplex", shape2, "simplex", 6, c2, NoiseType.NoiseType_OpenSimplex2),
        ("3D fBm 6 oct improved", shape3, "improved", 6, c3, NoiseType.NoiseType_Perlin),
        ("2D Worley F1", shape2, "worley", 1, c2, NoiseType.NoiseType_Cellular),
        ("3D Worley F1", shape3, "worley", 1, c3, NoiseType.NoiseType_Cellular),
    ]
    ncores = numba.config.NUMBA_NUM_THREADS
    lib = os.environ.get("SYLVA_FASTNOISE2_LIB")
    fn2 = _FastNoise2(lib) if lib else None
    llvm_cpu = _llvm_cpu()
    print(
        f"sylva.texture vs FastNoise Lite{' and FastNoise2' if fn2 else ''}  ({os.cpu_count()}"
        f" CPUs, numba {numba.__version__}, {args.repeat} rounds, M samples/s, one core"
        " unless said)"
    )
    print(
        f"SIMD: sylva = numba/LLVM for {llvm_cpu}{_width()} (float32 road: 16 float32 lanes"
        " where the CPU has AVX-512, 8 with AVX2); FastNoise Lite = scalar C"
        + ("; FastNoise2 = runtime dispatch (level per case below)" if fn2 else
           "; FastNoise2: not measured (set SYLVA_FASTNOISE2_LIB, see the docstring)")
    )
    print(f"load average before the run: {os.getloadavg()[0]:.2f}")
    cols = ["f32", "f64", "FNL"] + (["FN2", "FN2avx2"] if fn2 else [])
    head = (
        f"{'case':<24}" + "".join(f"{c:>9}" for c in cols)
        + f"{'f32/FNL':>9}" + (f"{'f32/FN2':>9}{'/FN2avx2':>9}" if fn2 else "")
        + f"{'f32/f64':>9}{f'{ncores}c x':>8}{'machine':>9}  FN2 level"
    )
    print(head)
    print("-" * len(head))
    for name, shape, kind, octaves, c, ntype in cases:
        if args.only.lower() not in name.lower():
            continue
        count = int(np.prod(shape))

        def ours(dt, shape=shape, kind=kind, octaves=octaves):
            return lambda: noise_grid(
                shape, kind=kind, octaves=octaves, scale=scale, seed=1, dtype=dt
            )

        fnl = _fnl(ntype, octaves)
        fns = {
            "f32": (ours(np.float32), 1),
            "f64": (ours(np.float64), 1),
            "FNL": (lambda fnl=fnl, c=c: fnl.gen_from_coords(c), 1),
            "all": (ours(np.float32), ncores),
        }
        level = ""
        if fn2:
            step = scale / shape[-1]
            run, level = fn2.maker(kind, octaves, shape, step, False)
            run2, level2 = fn2.maker(kind, octaves, shape, step, True)
            fns["FN2"] = (run, 1)
            fns["FN2avx2"] = (run2, 1)
            level = f"{level} / {level2}"
        rounds = _rounds(fns, args.repeat, args.inner, ncores)

        def rate(w, rounds=rounds, count=count):
            return statistics.median(count / r[w] / 1e6 for r in rounds)

        def ratio(a, b, rounds=rounds):
            return statistics.median(r[b] / r[a] for r in rounds)

        line = f"{name:<24}" + "".join(f"{rate(w):>9.1f}" for w in cols)
        line += f"{ratio('f32', 'FNL'):>8.2f}x"
        if fn2:
            line += f"{ratio('f32', 'FN2'):>8.2f}x{ratio('f32', 'FN2avx2'):>8.2f}x"
        line += f"{ratio('f32', 'f64'):>8.2f}x{ratio('all', 'f32'):>7.2f}x"
        line += f"{ratio('probeN', 'probe1'):>8.2f}x  {level}"
        print(line)
    _more_rows(args, fn2, ncores, scale)
    if not args.only or "graph" in args.only.lower():
        _graph_rows(args, shape2, scale, c2)
    print(f"load average after the run: {os.getloadavg()[0]:.2f}")
    print(
        "\nf32 / f64 = sylva noise_grid with dtype float32 (SIMD float32 road) / float64"
        " (bit-exact road); FNL = FastNoise Lite; FN2 = FastNoise2 at its best level, FN2avx2"
        " = capped at AVX2; a/b = rate of a over rate of b (median of the rounds);"
        f" {ncores}c x = sylva float32 one core time / {ncores} cores time; machine = the same"
        " speed-up of a trivially parallel arithmetic kernel, measured in the same rounds."
    )
    return 0


def _graph_rows(args, shape, scale, coords) -> None:
    """Texture graphs (one fused kernel per graph) against today's hand-written paths and
    FastNoise Lite, one core, same rounds: a 6-octave fBm node and the marble preset built
    from primitive nodes (turbulence, x, arithmetic, sin, clamp)."""
    from sylva.texture import graph as tg
    from sylva.texture import marble
    from sylva.texture.graph.library import marble_graph

    fbm_graph = tg.Graph(tg.fbm(kind="improved", octaves=6, scale=scale, seed=1))
    mg = marble_graph(scale=3.0, stripes=3.0, turbulence=2.5, seed=11)
    cases = [
        ("graph: 2D fBm 6 oct", lambda: fbm_graph.evaluate(shape),
         lambda: noise_grid(shape, kind="improved", octaves=6, scale=scale, seed=1)),
        ("graph: marble preset", lambda: mg.evaluate(shape),
         lambda: marble(shape, scale=3.0, stripes=3.0, turbulence=2.5, seed=11)),
    ]
    fnl = _fnl(NoiseType.NoiseType_Perlin, 6)
    count = int(np.prod(shape))
    xs = np.linspace(0.0, 1.0, shape[1])[None, :]

    def fnl_fbm():
        return fnl.gen_from_coords(coords)

    def fnl_marble():
        # the same texture with FastNoise Lite: its 6-octave fBm, then marble's arithmetic
        t = fnl.gen_from_coords(coords).reshape(shape)
        return np.clip(0.5 + 0.5 * np.sin(2.0 * np.pi * (3.0 * xs + 2.5 * np.abs(t))), 0, 1)

    peers = [fnl_fbm, fnl_marble]
    print()
    head = (f"{'case (one core)':<24}{'graph':>9}{'hand':>9}{'FNL':>9}{'graph/hand':>12}"
            f"{'range':>14}{'vs FNL':>9}")
    print(head)
    print("-" * len(head))
    numba.set_num_threads(1)
    try:
        for (name, graph, hand), peer in zip(cases, peers):
            graph()
            hand()
            peer()
            rounds = []
            for r in range(args.repeat):
                fns = [graph, hand, peer]
                order = [0, 1, 2] if r % 2 == 0 else [2, 1, 0]
                t = {k: _best(fns[k], args.inner) for k in order}
                rounds.append((t[0], t[1], t[2]))
            ratio = sorted(g / h for g, h, _ in rounds)
            vs = statistics.median(f / g for g, _, f in rounds)
            rg, rh, rf = (statistics.median(count / r[k] / 1e6 for r in rounds)
                          for k in range(3))
            print(f"{name:<24}{rg:>9.1f}{rh:>9.1f}{rf:>9.1f}{statistics.median(ratio):>11.2f}x"
                  f"{ratio[0]:>8.2f}-{ratio[-1]:.2f}x{vs:>8.2f}x")
    finally:
        numba.set_num_threads(numba.config.NUMBA_NUM_THREADS)
    print("graph/hand = graph time / hand-written time (median; range over the rounds; the "
          "target is <= 1.15x); vs FNL = FastNoise Lite time / graph time (the target is >= 2x):"
          " its 6-octave Perlin fBm, and for marble that fBm followed by marble's arithmetic in"
          " NumPy (FastNoise Lite has no marble); rates in M samples/s.")


def _more_rows(args, fn2, ncores, scale) -> None:
    """The float32 road of ``_points32`` (4D grids, tileable simplex, domain warping): sylva's
    two roads, and FastNoise2 where it has the same thing (its 4D simplex, value and
    cellular F1 grids; for warping its gradient warp, ``DomainWarpGradient`` in independent
    fBm octaves, about as much work as sylva's fBm warp field per axis: the nearest, not the
    same texture).  FastNoise Lite has neither 4D noise nor grids of warped noise: not timed
    here.  As many samples as the 2D grid (3D: 16 x side/4 x side/4, 4D: 4 x 4 x side/4 x
    side/4)."""
    n2 = args.size
    s4 = max(1, n2 // 4)
    shape2, shape3, shape4 = (n2, n2), (16, s4, s4), (4, 4, s4, s4)
    cases = [
        ("4D simplex", shape4, "simplex", 1, {}, True),
        ("4D value", shape4, "value", 1, {}, True),
        ("4D fBm 4 oct simplex", shape4, "simplex", 4, {}, True),
        ("4D Worley F1", shape4, "worley", 1, {}, True),
        ("2D tileable simplex", shape2, "simplex", 1, {"tileable": True}, False),
        ("4D Worley cell id", shape4, "worley", 1, {"output": "cell"}, False),
        ("2D warp improved", shape2, "improved", 1, {"warp": 1.0}, True),
        ("2D warp fBm 3 oct simplex", shape2, "simplex", 3, {"warp": 1.0}, True),
        ("3D warp improved", shape3, "improved", 1, {"warp": 1.0}, True),
    ]
    cases = [c for c in cases if args.only.lower() in c[0].lower()]
    if not cases:
        return
    peer = bool(fn2 and fn2.more)
    cols = ["f32", "f64"] + (["FN2", "FN2avx2"] if peer else [])
    head = (f"{'case (_points32)':<26}" + "".join(f"{c:>9}" for c in cols)
            + (f"{'f32/FN2':>9}{'/FN2avx2':>9}" if peer else "")
            + f"{'f32/f64':>9}{f'{ncores}c x':>8}{'machine':>9}")
    print()
    print(head)
    print("-" * len(head))
    for name, shape, kind, octaves, extra, has_peer in cases:
        count = int(np.prod(shape))

        def ours(dt, shape=shape, kind=kind, octaves=octaves, extra=extra):
            return lambda: noise_grid(shape, kind=kind, octaves=octaves, scale=scale, seed=1,
                                      dtype=dt, **extra)

        fns = {"f32": (ours(np.float32), 1), "f64": (ours(np.float64), 1),
               "all": (ours(np.float32), ncores)}
        if peer and has_peer:
            step = scale / shape[-1]
            w = extra.get("warp")
            fns["FN2"] = (fn2.maker(kind, octaves, shape, step, False, w)[0], 1)
            fns["FN2avx2"] = (fn2.maker(kind, octaves, shape, step, True, w)[0], 1)
        rounds = _rounds(fns, args.repeat, args.inner, ncores)

        def rate(w, rounds=rounds, count=count):
            if w not in rounds[0]:
                return float("nan")
            return statistics.median(count / r[w] / 1e6 for r in rounds)

        def ratio(a, b, rounds=rounds):
            if b not in rounds[0]:
                return float("nan")
            return statistics.median(r[b] / r[a] for r in rounds)

        line = f"{name:<26}" + "".join(f"{rate(w):>9.1f}" for w in cols)
        if peer:
            line += f"{ratio('f32', 'FN2'):>8.2f}x{ratio('f32', 'FN2avx2'):>8.2f}x"
        line += f"{ratio('f32', 'f64'):>8.2f}x{ratio('all', 'f32'):>7.2f}x"
        line += f"{ratio('probeN', 'probe1'):>8.2f}x"
        print(line)
    print("(nan: not timed for FastNoise2: it has no torus of simplex noise, and its cell"
          " value is not sylva's cell id)")


def _width() -> str:
    """How wide LLVM vectorises the float32 kernels: 512 bits on AVX-512 CPUs
    (``sylva.texture._bytelanes.Wide``; ``SYLVA_VECTOR_WIDTH=256`` leaves LLVM's own
    choice, 256 bits on its Intel AVX-512 models, for comparison)."""
    from sylva.texture import _bytelanes

    if not _bytelanes.AVX512:
        return ""
    if os.environ.get("SYLVA_VECTOR_WIDTH") == "256":
        return ", LLVM's own vector width (SYLVA_VECTOR_WIDTH=256)"
    return ", 512-bit vectors"


def _llvm_cpu() -> str:
    if os.environ.get("NUMBA_CPU_NAME"):  # a build for another CPU (an AVX2 build here)
        return os.environ["NUMBA_CPU_NAME"] + " (NUMBA_CPU_NAME)"
    try:
        import llvmlite.binding as llvm

        return llvm.get_host_cpu_name()
    except Exception:  # noqa: BLE001 - only a label
        return "the host CPU"


if __name__ == "__main__":
    raise SystemExit(main())

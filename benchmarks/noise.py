"""Noise throughput of sylva.texture against FastNoise Lite (pyfastnoiselite), same run.

Run:  .venv/bin/python benchmarks/noise.py [--repeat 11] [--size 1024]

For each case both libraries produce the same number of float32 samples: sylva evaluates a
regular grid with :func:`sylva.texture.noise_grid`; FastNoise Lite evaluates the same grid's
coordinates with ``FastNoiseLite.gen_from_coords`` (single-threaded).  sylva runs with
``numba.set_num_threads(1)`` for the one-core figure and with every core for the speed-up.

Measurement: ``--repeat`` rounds per case; a round times sylva on one core, FastNoise Lite
and sylva on all cores back to back (each the best of ``--inner`` calls; the order within a
round alternates), so that a slow phase of a shared machine hits the three alike.  The
ratio and the speed-up are the medians of the per-round ratios; the rates are the medians
of the per-round rates, in million samples per second.

The two-core speed-up of a shared virtual machine varies from moment to moment whatever the
code (the host decides where the virtual cores run), so every round also times a
trivially parallel arithmetic kernel on one and on all cores: its median speed-up
(``machine``) is what the machine gave during that case's rounds.
"""

from __future__ import annotations

import argparse
import math
import os
import statistics
import time

import numba
import numpy as np
from pyfastnoiselite.pyfastnoiselite import FastNoiseLite, FractalType, NoiseType

from sylva.texture import noise_grid


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


def _rounds(ours, peer, repeat: int, inner: int, cores: int):
    """Per-round times: ours on one core, the peer, ours on ``cores`` cores, the probe on
    one core and on ``cores`` cores."""
    numba.set_num_threads(1)
    ours()  # warm-up (and compile)
    peer()
    _probe()
    numba.set_num_threads(cores)
    ours()
    _probe()
    rounds = []
    try:
        for r in range(repeat):
            t = {}
            order = ["one", "peer", "all", "probe1", "probeN"]
            if r % 2:
                order.reverse()
            for what in order:
                numba.set_num_threads(1 if what in ("one", "probe1") else cores)
                fn = _probe if what.startswith("probe") else peer if what == "peer" else ours
                t[what] = _best(fn, inner)
            rounds.append((t["one"], t["peer"], t["all"], t["probe1"], t["probeN"]))
    finally:
        numba.set_num_threads(cores)
    return rounds


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
    ]
    ncores = numba.config.NUMBA_NUM_THREADS
    print(
        f"sylva.texture vs FastNoise Lite  ({os.cpu_count()} CPUs, numba {numba.__version__},"
        f" {args.repeat} rounds, float32 output, M samples/s)"
    )
    print(f"load average before the run: {os.getloadavg()[0]:.2f}")
    head = (
        f"{'case':<24}{'samples':>10}{'sylva 1c':>10}{'FNL 1c':>9}{'ratio':>8}"
        f"{f'sylva {ncores}c':>11}{'speed-up':>10}{'machine':>9}{'ratio range':>15}"
    )
    print(head)
    print("-" * len(head))
    for name, shape, kind, octaves, c, ntype in cases:
        if args.only.lower() not in name.lower():
            continue
        count = int(np.prod(shape))

        def ours(shape=shape, kind=kind, octaves=octaves):
            return noise_grid(shape, kind=kind, octaves=octaves, scale=scale, seed=1)

        fnl = _fnl(ntype, octaves)
        rounds = _rounds(
            ours, lambda fnl=fnl, c=c: fnl.gen_from_coords(c), args.repeat, args.inner, ncores
        )
        r1 = statistics.median(count / r[0] / 1e6 for r in rounds)
        rf = statistics.median(count / r[1] / 1e6 for r in rounds)
        rn = statistics.median(count / r[2] / 1e6 for r in rounds)
        ratios = sorted(r[1] / r[0] for r in rounds)
        speedup = statistics.median(r[0] / r[2] for r in rounds)
        machine = statistics.median(r[3] / r[4] for r in rounds)
        print(
            f"{name:<24}{count:>10}{r1:>10.1f}{rf:>9.1f}{statistics.median(ratios):>7.2f}x"
            f"{rn:>11.1f}{speedup:>9.2f}x{machine:>8.2f}x{ratios[0]:>8.2f}-{ratios[-1]:.2f}x"
        )
    if not args.only or "graph" in args.only.lower():
        _graph_rows(args, shape2, scale, c2)
    print(f"load average after the run: {os.getloadavg()[0]:.2f}")
    print(
        "\nratio = sylva one core / FastNoise Lite one core (median of the rounds; range: the"
        " rounds' lowest and highest); speed-up = sylva one core time / sylva"
        f" {ncores} cores time (median of the rounds); machine = the same speed-up of a"
        " trivially parallel arithmetic kernel, measured in the same rounds."
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


if __name__ == "__main__":
    raise SystemExit(main())

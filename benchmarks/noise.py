"""Noise throughput of sylva.texture against FastNoise Lite (pyfastnoiselite), same run.

Run:  .venv/bin/python benchmarks/noise.py [--repeat 7] [--size 1024]

For each case both libraries produce the same number of float32 samples: sylva evaluates a
regular grid with :func:`sylva.texture.noise_grid`; FastNoise Lite evaluates the same grid's
coordinates with ``FastNoiseLite.gen_from_coords`` (single-threaded).  sylva runs with
``numba.set_num_threads(1)`` for the one-core figure and then with every core for the
speed-up.  Figures are the median of ``--repeat`` runs, in million samples per second.
"""

from __future__ import annotations

import argparse
import os
import statistics
import time

import numba
import numpy as np
from pyfastnoiselite.pyfastnoiselite import FastNoiseLite, FractalType, NoiseType

from sylva.texture import noise_grid


def _clock(fn) -> float:
    t0 = time.perf_counter()
    fn()
    return time.perf_counter() - t0


def _interleaved(ours, peer, repeat: int, cores: int) -> tuple[float, float, float]:
    """Median times of ours on one core, the peer, and ours on ``cores`` cores, measured
    in alternation so that a busy machine slows all three alike."""
    numba.set_num_threads(1)
    ours()  # warm-up (and compile)
    peer()
    t1, tp, tn = [], [], []
    for _ in range(repeat):
        numba.set_num_threads(1)
        t1.append(_clock(ours))
        tp.append(_clock(peer))
        numba.set_num_threads(cores)
        tn.append(_clock(ours))
    return statistics.median(t1), statistics.median(tp), statistics.median(tn)


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
    ap.add_argument("--repeat", type=int, default=7)
    ap.add_argument("--size", type=int, default=1024,
                    help="2D grid side (3D: 16 x side/4 x side/4)")
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
    print(f"sylva.texture vs FastNoise Lite  ({os.cpu_count()} CPUs, numba {numba.__version__},"
          f" median of {args.repeat}, float32 output, M samples/s)")
    print(f"load average before the run: {os.getloadavg()[0]:.2f}")
    head = (f"{'case':<24}{'samples':>10}{'sylva 1c':>10}{'FNL 1c':>9}{'ratio':>8}"
            f"{f'sylva {ncores}c':>11}{'speed-up':>10}")
    print(head)
    print("-" * len(head))
    for name, shape, kind, octaves, c, ntype in cases:
        count = int(np.prod(shape))

        def ours(shape=shape, kind=kind, octaves=octaves):
            return noise_grid(shape, kind=kind, octaves=octaves, scale=scale, seed=1)

        fnl = _fnl(ntype, octaves)
        t1, tf, tn = _interleaved(ours, lambda fnl=fnl, c=c: fnl.gen_from_coords(c),
                                  args.repeat, ncores)
        r1 = count / t1 / 1e6
        rf = count / tf / 1e6
        rn = count / tn / 1e6
        print(f"{name:<24}{count:>10}{r1:>10.1f}{rf:>9.1f}{r1 / rf:>7.2f}x{rn:>11.1f}"
              f"{t1 / tn:>9.2f}x")
    print("\nratio = sylva one core / FastNoise Lite one core; speed-up = sylva one core time /"
          f" sylva {ncores} cores time.")
    return 0


if __name__ == "__main__":
    raise SystemExit(main())

"""Warped noise grids made in a loop, as an application makes textures: time and minor page
faults a call, one core.

Run:  taskset -c 0 .venv/bin/python benchmarks/warp_loop.py [--calls 20] [--size 1024]

``benchmarks/noise.py`` times each grid in a process that also holds the peers' arrays; this
one makes nothing else, so it sees what the allocator does between calls: a warped grid's
warp fields are temporaries of several megabytes, and where they went back to the system
at the end of a call (glibc trims the freed top of its heap) the next call faulted them in
again page by page (``_points32._Scratch`` keeps their buffers).  Faults are
``getrusage``'s ``ru_minflt`` of the process over the timed calls.  No peer: FastNoise2
fills a buffer its caller allocates once.  Pin it to one CPU (``taskset -c 0``): on a
shared VM an unpinned process can run 1.5x slower throughout.
"""

from __future__ import annotations

import argparse
import resource
import time

import numba
import numpy as np

from sylva.texture import noise_grid


def _faults() -> int:
    return resource.getrusage(resource.RUSAGE_SELF).ru_minflt


def main(argv=None) -> int:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--calls", type=int, default=20, help="timed calls per case")
    ap.add_argument("--threads", type=int, default=1, help="numba threads (default: one)")
    ap.add_argument("--only", default="", help="run the cases whose name contains this")
    ap.add_argument("--size", type=int, default=1024,
                    help="2D grid side (3D: 16 x side/4 x side/4)")
    args = ap.parse_args(argv)
    numba.set_num_threads(min(args.threads, numba.config.NUMBA_NUM_THREADS))
    n = args.size
    s3 = max(1, n // 4)
    cases = [
        ("2D warp improved", (n, n), "improved", 1),
        ("2D warp fBm 3 oct simplex", (n, n), "simplex", 3),
        ("3D warp improved", (16, s3, s3), "improved", 1),
    ]
    print(f"warped grids in a loop, {numba.get_num_threads()} of {numba.config.NUMBA_NUM_THREADS}"
          f" threads, {args.calls} calls (median ms; minor faults a call)")
    print(f"{'case':28s}{'shape':>18s}{'ms':>9s}{'faults':>9s}")
    for name, shape, kind, octaves in [c for c in cases if args.only in c[0]]:
        def make(shape=shape, kind=kind, octaves=octaves):
            return noise_grid(shape, kind=kind, octaves=octaves, scale=64.0, seed=1, warp=1.0)

        for _ in range(3):  # compile or load, and settle the allocator
            make()
        times = []
        f0 = _faults()
        for _ in range(args.calls):
            t0 = time.perf_counter()
            make()
            times.append(time.perf_counter() - t0)
        faults = (_faults() - f0) / args.calls
        print(f"{name:28s}{str(shape):>18s}{np.median(times) * 1e3:9.2f}{faults:9.0f}")
    return 0


if __name__ == "__main__":
    raise SystemExit(main())

"""Voxel world throughput on the Dask road: generate a world with vegetation into a store.

Run: ``python benchmarks/world.py [--size 1024x1024] [--chunk 32] [--workers 2] [--seed 7]``

Measures, after a warm-up chunk that loads the compiled kernels:

* ``serial``: chunks generated and meshed one by one in this process (fields, voxels,
  greedy skin, plant placement), a sample of ``--sample`` chunks: chunks/s and blocks/s;
* ``block``: the same sample as one block (:func:`sylva.world.chunks.generate_chunks`);
* ``sync``: the whole world into a world store on Dask's synchronous scheduler, in this
  process (what ``--workers 1`` and one-block worlds use);
* ``dask N``: the whole world on a ``LocalCluster`` of 1 … ``--workers`` worker processes
  (started before the clock; its start-up is reported apart), chunks written to the store
  by the workers;
* the speed-up of N workers over 1, the Dask overhead per chunk (1-worker cluster minus the
  synchronous road, per chunk, against a chunk's own time), and the peak RSS of the client
  and of each worker.

The figure before the Dask road (the home-made process pool, now removed): 512 × 512 in
5.8 s, 70 chunks/s, on this project's 2-core CI machine.
"""

from __future__ import annotations

import argparse
import logging
import os
import resource
import sys
import tempfile
import time
import warnings
from pathlib import Path

from sylva.world import World, WorldConfig, generate_chunk
from sylva.world.chunks import generate_chunks


def _size(text: str) -> tuple[int, int]:
    w, _, d = text.lower().partition("x")
    return int(w), int(d or w)


def _rss_mb() -> float:
    return resource.getrusage(resource.RUSAGE_SELF).ru_maxrss / 1024


def main(argv=None) -> int:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--size", type=_size, default=(1024, 1024))
    ap.add_argument("--chunk", type=int, default=32)
    ap.add_argument("--workers", type=int, default=2, help="largest local cluster measured")
    ap.add_argument("--seed", type=int, default=7)
    ap.add_argument("--sample", type=int, default=16, help="chunks timed serially")
    ap.add_argument("--block", type=int, default=128, help="columns per task side")
    args = ap.parse_args(argv)
    cfg = WorldConfig(seed=args.seed, chunk_size=args.chunk)
    world = World(cfg, size=args.size)
    coords = world.chunk_coords()
    n = len(coords)
    print(f"world {args.size[0]}x{args.size[1]}, chunk {args.chunk}, height {cfg.height}, "
          f"{n} chunks in {len(world.blocks(args.block))} tasks, {os.cpu_count()} cores")

    generate_chunk(cfg, -100, -100)  # warm-up: load compiled kernels
    sample = coords[: args.sample]
    t0 = time.perf_counter()
    for cx, cz in sample:
        world.chunk(cx, cz)
    dt = time.perf_counter() - t0
    print(f"serial : {len(sample) / dt:8.1f} chunks/s  "
          f"{len(sample) * args.chunk**2 * cfg.height / dt / 1e6:8.2f} M blocks/s")
    side = max(1, int(len(sample) ** 0.5))
    t0 = time.perf_counter()
    block = generate_chunks(cfg, coords[0][0], coords[0][1], side, side, bounds=world.bounds)
    dt = time.perf_counter() - t0
    print(f"block  : {len(block) / dt:8.1f} chunks/s  ({side}x{side} chunks)")

    with tempfile.TemporaryDirectory() as folder:
        t0 = time.perf_counter()
        store = world.generate(Path(folder) / "sync.zarr", workers=1, block_columns=args.block)
        t_sync = time.perf_counter() - t0
        print(f"sync   : {t_sync:8.2f} s  {n / t_sync:8.1f} chunks/s  {store.n_quads} quads, "
              f"{store.n_plants} plants + grass  (client RSS {_rss_mb():.0f} MB)")
        times = {}
        for k in range(1, args.workers + 1):
            times[k] = _on_cluster(world, k, Path(folder) / f"dask{k}.zarr", args.block)
        t1 = times[1]
        per_chunk = t_sync / n
        over = (t1 - t_sync) / n
        print(f"speed-up {args.workers} workers over 1: {t1 / times[args.workers]:.2f}x")
        print(f"overhead: {over * 1e3:+.2f} ms per chunk on the 1-worker cluster, "
              f"{100 * over / per_chunk:+.1f} % of a chunk's {per_chunk * 1e3:.1f} ms")
    return 0


def _on_cluster(world: World, k: int, path: Path, block: int) -> float:
    from distributed import Client, LocalCluster

    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        t0 = time.perf_counter()
        cluster = LocalCluster(n_workers=k, threads_per_worker=1, processes=True,
                               host="127.0.0.1", dashboard_address=None,
                               silence_logs=logging.ERROR, memory_limit="2GiB")
        client = Client(cluster, set_as_default=False)
        client.run(generate_chunk, world.config, -100, -100)  # load the kernels everywhere
        t_start = time.perf_counter() - t0
        try:
            t0 = time.perf_counter()
            world.generate(path, scheduler=cluster.scheduler_address, block_columns=block)
            dt = time.perf_counter() - t0
            rss = client.run(_rss_mb)
        finally:
            client.close()
            cluster.close()
    n = len(world.chunk_coords())
    print(f"dask {k} : {dt:8.2f} s  {n / dt:8.1f} chunks/s  (cluster start {t_start:.1f} s; "
          f"peak RSS client {_rss_mb():.0f} MB, workers "
          + ", ".join(f"{v:.0f}" for v in rss.values()) + " MB)")
    return dt


if __name__ == "__main__":
    sys.exit(main())

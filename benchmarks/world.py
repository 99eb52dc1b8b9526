"""Voxel world throughput on the Dask road: generate a world with vegetation into a store.

Run: ``python benchmarks/world.py [--size 1024x1024] [--chunk 32] [--workers 2] [--seed 7]
[--big 4096]``

Prints, after a warm-up chunk that loads the compiled kernels:

* ``before``: the figure before issue 20 (the home-made process pool, since removed, so
  quoted, not measured): 512 × 512 in 5.8 s, 70 chunks/s, on this project's 2-core machine;
* ``serial``: chunks generated and meshed one by one in this process (fields, voxels,
  greedy skin, plant placement), a sample of ``--sample`` chunks: chunks/s and blocks/s;
* ``block``: the same sample as one block (:func:`sylva.world.chunks.generate_chunks`);
* ``sync``: the whole world into a world store on Dask's synchronous scheduler, in this
  process (what ``--workers 1`` and one-block worlds use);
* ``dask N``: the whole world on a ``LocalCluster`` of 1 … ``--workers`` worker processes
  (started before the clock; its start-up is reported apart), chunks written to the store
  by the workers: wall time, chunks/s, the **task time** per chunk (what the tasks took
  inside the workers, from the scheduler's task stream), the **CPU time** per chunk (user +
  system of every worker process, from ``getrusage``; on a machine shared with other jobs
  it is the fairer figure, since wall time there depends on the neighbours), and the peak
  RSS of the client and of each worker;
* the speed-up of N workers over 1 (wall and CPU per chunk), and the **Dask overhead** per
  chunk: wall × workers minus the task time, per chunk, against a chunk's task time (what
  the workers spend outside the tasks: scheduling, transfers, idling at the ends);
* with ``--big SIDE``: a SIDE × SIDE world on ``--workers`` workers with their memory limit
  (2 GiB each, what ``sylva world`` gives a local worker), its wall time and the peak RSS
  of each worker against that limit.
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

#: The figure before issue 20 (the process pool): 512² in 5.8 s, 70 chunks/s.
BEFORE = (512, 5.8, 70.0)


def _size(text: str) -> tuple[int, int]:
    w, _, d = text.lower().partition("x")
    return int(w), int(d or w)


def _rss_mb() -> float:
    return resource.getrusage(resource.RUSAGE_SELF).ru_maxrss / 1024


def _cpu_s() -> float:
    r = resource.getrusage(resource.RUSAGE_SELF)
    return r.ru_utime + r.ru_stime


def main(argv=None) -> int:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--size", type=_size, default=(1024, 1024))
    ap.add_argument("--chunk", type=int, default=32)
    ap.add_argument("--workers", type=int, default=2, help="largest local cluster measured")
    ap.add_argument("--seed", type=int, default=7)
    ap.add_argument("--sample", type=int, default=16, help="chunks timed serially")
    ap.add_argument("--block", type=int, default=128, help="columns per task side")
    ap.add_argument("--big", type=int, default=None, metavar="SIDE",
                    help="also a SIDE x SIDE world on --workers workers: peak RSS per worker")
    args = ap.parse_args(argv)
    cfg = WorldConfig(seed=args.seed, chunk_size=args.chunk)
    world = World(cfg, size=args.size)
    coords = world.chunk_coords()
    n = len(coords)
    print(f"world {args.size[0]}x{args.size[1]}, chunk {args.chunk}, height {cfg.height}, "
          f"{n} chunks in {len(world.blocks(args.block))} tasks, {os.cpu_count()} cores, "
          f"load average {os.getloadavg()[0]:.1f}")
    side, secs, rate = BEFORE
    print(f"before : {side}x{side} in {secs} s, {rate:.0f} chunks/s (the process pool before "
          "issue 20, quoted: it is gone)")

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
        t0, c0 = time.perf_counter(), _cpu_s()
        store = world.generate(Path(folder) / "sync.zarr", workers=1, block_columns=args.block)
        t_sync, c_sync = time.perf_counter() - t0, _cpu_s() - c0
        print(f"sync   : {t_sync:8.2f} s  {n / t_sync:8.1f} chunks/s  CPU "
              f"{c_sync / n * 1e3:.1f} ms/chunk  {store.n_quads} quads, {store.n_plants} "
              f"plants + grass  (client peak RSS {_rss_mb():.0f} MB)")
        runs = {}
        for k in range(1, args.workers + 1):
            runs[k] = _on_cluster(world, k, Path(folder) / f"dask{k}.zarr", args.block)
        one, top = runs[1], runs[args.workers]
        print(f"speed-up {args.workers} workers over 1: {one['wall'] / top['wall']:.2f}x wall "
              f"(CPU per chunk {one['cpu'] / n * 1e3:.1f} -> {top['cpu'] / n * 1e3:.1f} ms)")
        for k, r in runs.items():
            over = (k * r["wall"] - r["task"]) / n
            per = r["task"] / n
            print(f"overhead: {over * 1e3:+.2f} ms per chunk on {k} worker(s), "
                  f"{100 * over / per:+.1f} % of a chunk's task time {per * 1e3:.1f} ms "
                  f"(wall x workers - task time)")
    if args.big:
        big = World(cfg, size=(args.big, args.big))
        with tempfile.TemporaryDirectory() as folder:
            r = _on_cluster(big, args.workers, Path(folder) / "big.zarr", args.block,
                            label=f"big {args.big}x{args.big}")  # fmt: skip
        worst = max(r["rss"])
        print(f"memory : {args.big}x{args.big} on {args.workers} workers: peak worker RSS "
              f"{worst:.0f} MB of the 2048 MB limit ({'within' if worst <= 2048 else 'OVER'});"
              f" client {r['client_rss']:.0f} MB")
    return 0


def _on_cluster(world: World, k: int, path: Path, block: int, label: str | None = None) -> dict:
    from distributed import Client, LocalCluster, get_task_stream

    n = len(world.chunk_coords())
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
            cpu0 = client.run(_cpu_s)
            with get_task_stream(client) as ts:
                t0 = time.perf_counter()
                world.generate(path, scheduler=cluster.scheduler_address, block_columns=block)
                dt = time.perf_counter() - t0
            cpu = sum(v - cpu0[w] for w, v in client.run(_cpu_s).items())
            rss = list(client.run(_rss_mb).values())
        finally:
            client.close()
            cluster.close()
    task = sum(s["stop"] - s["start"] for t in ts.data for s in t["startstops"]
               if s["action"] == "compute")  # fmt: skip
    name = label or f"dask {k}"
    print(f"{name} : {dt:8.2f} s  {n / dt:8.1f} chunks/s  task {task / n * 1e3:.1f} ms/chunk, "
          f"CPU {cpu / n * 1e3:.1f} ms/chunk  (cluster start {t_start:.1f} s; peak RSS "
          f"client {_rss_mb():.0f} MB, workers " + ", ".join(f"{v:.0f}" for v in rss) + " MB)")
    return {"wall": dt, "task": task, "cpu": cpu, "rss": rss, "client_rss": _rss_mb()}


if __name__ == "__main__":
    sys.exit(main())

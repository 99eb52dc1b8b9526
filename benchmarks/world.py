"""Voxel world throughput: generate and mesh a world with vegetation.

Run: ``python benchmarks/world.py [--size 512x512] [--chunk 32] [--workers N] [--seed 7]``

Measures, after a warm-up chunk that loads the compiled kernels:

* ``serial``: chunks generated and meshed one by one in this process (fields, voxels,
  greedy skin, plant placement), a sample of ``--sample`` chunks: chunks/s and blocks/s
  (columns × height voxels decided per second);
* ``block``: the same sample as one block (:func:`sylva.world.chunks.generate_chunks`,
  noise fields computed once for the block), still in this process;
* ``world``: the whole world with :meth:`sylva.world.World.generate` over ``--workers``
  processes (default: all cores), chunks streamed to disk — wall time including the
  workers' start-up;
* ``plants``: building every distinct plant model the world uses (the salted executor,
  the turtle and the cube meshes), and the instance count;
* ``total``: world + plants, i.e. the time to generate and mesh the world with vegetation.
"""

from __future__ import annotations

import argparse
import os
import sys
import tempfile
import time

from sylva.world import PlantLibrary, World, WorldConfig, generate_chunk
from sylva.world.chunks import generate_chunks


def _size(text: str) -> tuple[int, int]:
    w, _, d = text.lower().partition("x")
    return int(w), int(d or w)


def main(argv=None) -> int:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--size", type=_size, default=(512, 512))
    ap.add_argument("--chunk", type=int, default=32)
    ap.add_argument("--workers", type=int, default=None)
    ap.add_argument("--seed", type=int, default=7)
    ap.add_argument("--sample", type=int, default=16, help="chunks timed serially")
    args = ap.parse_args(argv)
    cfg = WorldConfig(seed=args.seed, chunk_size=args.chunk)
    world = World(cfg, size=args.size)
    coords = world.chunk_coords()
    workers = args.workers or os.cpu_count() or 1
    print(f"world {args.size[0]}x{args.size[1]}, chunk {args.chunk}, height {cfg.height}, "
          f"{len(coords)} chunks, {workers} workers, {os.cpu_count()} cores")  # fmt: skip

    generate_chunk(cfg, -100, -100)  # warm-up: load compiled kernels
    sample = coords[: args.sample]
    t0 = time.perf_counter()
    quads = 0
    for cx, cz in sample:
        quads += len(world.chunk(cx, cz).quads)
    dt = time.perf_counter() - t0
    blocks = len(sample) * args.chunk**2 * cfg.height
    print(f"serial : {len(sample) / dt:8.1f} chunks/s  {blocks / dt / 1e6:8.2f} M blocks/s  "
          f"({quads / len(sample):.0f} quads per chunk)")  # fmt: skip

    side = max(1, int(len(sample) ** 0.5))
    t0 = time.perf_counter()
    block = generate_chunks(cfg, coords[0][0], coords[0][1], side, side, bounds=world.bounds)
    dt = time.perf_counter() - t0
    blocks = len(block) * args.chunk**2 * cfg.height
    print(f"block  : {len(block) / dt:8.1f} chunks/s  {blocks / dt / 1e6:8.2f} M blocks/s  "
          f"({side}x{side} chunks)")  # fmt: skip

    with tempfile.TemporaryDirectory() as folder:
        t0 = time.perf_counter()
        store = world.generate(folder, workers=workers)
        t_world = time.perf_counter() - t0
        n = len(store)
        total_blocks = n * args.chunk**2 * cfg.height
        print(f"world  : {t_world:8.2f} s  {n / t_world:8.1f} chunks/s  "
              f"{total_blocks / t_world / 1e6:8.2f} M blocks/s  {store.n_quads} quads, "
              f"{store.n_plants} plants + grass")  # fmt: skip
        t0 = time.perf_counter()
        inst = store.instances()
        lib = PlantLibrary.for_config(cfg)
        tris = 0
        for key in inst:
            tris += lib.model(key).n_triangles
        t_plants = time.perf_counter() - t0
        print(f"plants : {t_plants:8.2f} s  {len(inst)} models ({tris} triangles), "
              f"{sum(len(v) for v in inst.values())} instances")  # fmt: skip
        t0 = time.perf_counter()
        mesh = store.terrain_mesh()
        t_mesh = time.perf_counter() - t0
        print(f"mesh   : {t_mesh:8.2f} s  terrain {mesh.n_triangles} triangles")
    print(f"total  : {t_world + t_plants + t_mesh:8.2f} s to generate and mesh the world "
          "with vegetation")  # fmt: skip
    return 0


if __name__ == "__main__":
    sys.exit(main())

"""A finite world: chunks generated as Dask tasks, written to a world store.

:class:`World` covers ``size`` columns from ``origin`` with chunks of
``config.chunk_size``.  :meth:`World.generate` runs blocks of chunks
(:func:`~sylva.world.chunks.generate_chunks`) as tasks through :mod:`sylva.cluster` — a
local cluster of worker processes, an existing cluster, or this process for a small
world — and each task writes its chunks into a :class:`~sylva.world.store.WorldStore`
(Zarr arrays and Parquet tables) and returns only a summary; a bounded number of tasks is
in flight, so memory stays bounded however large the world.  Every chunk is a pure
function of the world seed and its coordinates, so the store is the same whichever
worker made which chunk, and a task a dead worker lost is simply run again.

Examples
--------
>>> from sylva.world.terrain import WorldConfig
>>> w = World(WorldConfig(seed=5, chunk_size=8), size=(16, 8))
>>> w.chunk_coords()
[(0, 0), (1, 0)]
>>> store = w.generate(workers=1)
>>> len(store), store.biome_map().shape
(2, (8, 16, 3))
>>> store.close()
"""

from __future__ import annotations

import math
import tempfile
from pathlib import Path

import numpy as np

from .. import _jit
from ..errors import SylvaError
from .chunks import Chunk, generate_chunk, generate_chunks
from .plants import PlantLibrary
from .store import Instances, WorldStore, biome_image, expand_instances
from .terrain import WorldConfig, columns

__all__ = [
    "BLOCK_COLUMNS",
    "Instances",
    "World",
    "biome_image",
    "chunk_count",
    "expand_instances",
]

#: Columns per side of the blocks of chunks a task generates at once (noise calls have a
#: fixed cost, so bigger blocks are faster; memory per block stays small).
BLOCK_COLUMNS = 128
#: Columns up to which a world is small: on a cold cache its terrain kernels run their
#: Python source (:data:`sylva.world.terrain.K`) instead of compiling.
SMALL_COLUMNS = 128 * 128


def _block_task(job) -> dict:
    """One Dask task: generate a block of chunks and write it into the store."""
    path, cfg, block, bounds = job
    chunks = generate_chunks(cfg, *block, bounds=bounds, keep_voxels=True)
    return WorldStore(path).write_block(block, chunks)


class World:
    """A rectangle of the infinite terrain, cut into chunks.

    Parameters
    ----------
    config : WorldConfig
    size : (int, int)
        Columns along x and z.
    origin : (int, int)
        World ``(x, z)`` of the first column (a multiple of the chunk size keeps chunk
        boundaries on the terrain's chunk grid).
    closed : bool
        Close the outer walls of the world (else the terrain is cut open at its edges).
    """

    def __init__(self, config: WorldConfig, size=(512, 512), origin=(0, 0),
                 closed: bool = True) -> None:  # fmt: skip
        self.config = config
        self.size = (int(size[0]), int(size[1]))
        if min(self.size) < 1:
            raise SylvaError(f"a world needs at least one column each way, got {size}")
        self.origin = (int(origin[0]), int(origin[1]))
        self.closed = closed
        s = config.chunk_size
        self._c0 = (self.origin[0] // s, self.origin[1] // s)
        x1, z1 = self.origin[0] + self.size[0], self.origin[1] + self.size[1]
        self._c1 = (-(-x1 // s), -(-z1 // s))

    @property
    def bounds(self) -> tuple[int, int, int, int]:
        """``(x0, z0, x1, z1)`` in columns."""
        x0, z0 = self.origin
        return x0, z0, x0 + self.size[0], z0 + self.size[1]

    def chunk_coords(self) -> list[tuple[int, int]]:
        """Chunk coordinates covering the world, row by row (z outer)."""
        return [(cx, cz) for cz in range(self._c0[1], self._c1[1])
                for cx in range(self._c0[0], self._c1[0])]  # fmt: skip

    def library(self) -> PlantLibrary:
        """The plant library of this world's seed and settings."""
        c = self.config
        return PlantLibrary.for_config(c)

    def blocks(self, block_columns: int = BLOCK_COLUMNS) -> list[tuple[int, int, int, int]]:
        """The world's chunks in blocks ``(cx0, cz0, ncx, ncz)`` of about ``block_columns``
        columns a side: the work units of :meth:`generate`."""
        b = max(1, block_columns // self.config.chunk_size)
        out = []
        for cz in range(self._c0[1], self._c1[1], b):
            for cx in range(self._c0[0], self._c1[0], b):
                out.append((cx, cz, min(b, self._c1[0] - cx), min(b, self._c1[1] - cz)))
        return out

    def chunk(self, cx: int, cz: int, *, keep_voxels: bool = False) -> Chunk:
        """Generate one chunk in this process."""
        return generate_chunk(self.config, cx, cz, bounds=self.bounds if self.closed else None,
                              keep_voxels=keep_voxels)  # fmt: skip

    def generate(self, directory=None, *, workers: int | None = None,
                 scheduler: str | None = None, progress=None,
                 block_columns: int = BLOCK_COLUMNS, resume: bool = False,
                 runner=None) -> WorldStore:  # fmt: skip
        """Generate every chunk into a world store at ``directory``.

        Parameters
        ----------
        directory : path, optional
            The store's folder (see :mod:`sylva.world.store`); default: a temporary folder
            that :meth:`WorldStore.close` removes.
        workers : int, optional
            Worker processes of the local Dask cluster (default: all cores); 1, or a world
            of one block, runs in this process on Dask's synchronous scheduler.  Workers
            are processes, so a script that calls this needs the usual
            ``if __name__ == "__main__":`` guard.
        scheduler : str, optional
            ``tcp://HOST:PORT`` of a running Dask scheduler (default
            ``$SYLVA_SCHEDULER``); its workers need ``directory`` on a shared file system.
        progress : bool or callable, optional
            True: a progress bar on stderr; a callable gets ``(chunks done, total)``.
        block_columns : int
            Side of the blocks of chunks each task generates (see :meth:`blocks`).
        resume : bool
            Continue the store at ``directory``: generate only the blocks not yet written.
        runner : sylva.cluster.Runner, optional
            Run on this (already connected) runner instead of connecting for this call.

        Returns
        -------
        WorldStore
        """
        from ..cluster import using

        owned = directory is None
        if owned:
            directory = Path(tempfile.mkdtemp(prefix="sylva-world-", suffix=".zarr"))
        path = Path(directory)
        if resume and (path / "manifest.json").exists():
            store = WorldStore(path)
            store.check_matches(self, block_columns)
        else:
            store = WorldStore.create(path, self, block_columns=block_columns)
        store.owned = owned
        todo = store.missing(block_columns)
        total = sum(b[2] * b[3] for b in self.blocks(block_columns))
        done = total - sum(b[2] * b[3] for b in todo)
        bounds = self.bounds if self.closed else None
        jobs = [(str(path), self.config, b, bounds) for b in todo]
        if callable(progress) and not isinstance(progress, bool):
            report = progress
            progress = lambda d, t: report(d + done, total)  # noqa: E731
        try:
            with (_jit.small(total <= SMALL_COLUMNS),
                  using(runner, scheduler, workers=workers, tasks=len(jobs)) as run):
                for _ in run.map(_block_task, jobs, progress=bool(progress) and progress,
                                 weight=lambda j: j[2][2] * j[2][3], unit="chunk"):  # fmt: skip
                    pass
        except BaseException:
            if owned:
                store.close()
            raise
        store.finish()
        final = WorldStore(path, owned=owned)
        return final

    def biome_map(self) -> np.ndarray:
        """The biome of every column: uint8[z, x] of :class:`~sylva.world.biomes.Biome`."""
        x0, z0 = self.origin
        f = columns(self.config, x0, z0, self.size[0], self.size[1])
        return np.ascontiguousarray(f.biome.T)


def chunk_count(size, chunk_size: int) -> int:
    """Chunks needed for ``size`` columns."""
    return math.ceil(size[0] / chunk_size) * math.ceil(size[1] / chunk_size)

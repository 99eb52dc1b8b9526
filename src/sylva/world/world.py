"""A finite world: chunks generated in parallel and streamed to disk, then assembled.

:class:`World` covers ``size`` columns from ``origin`` with chunks of
``config.chunk_size``.  :meth:`World.generate` runs :func:`~sylva.world.chunks.generate_chunk`
over the chunks in worker processes (all cores by default); each worker writes its chunk to
an ``.npz`` file and returns only a summary, and at most two chunks per worker are in
flight, so memory stays bounded however large the world.  The :class:`ChunkStore` it
returns reads the chunks back one at a time: the terrain mesh, the plant instances per
model, the biome map.

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

import json
import math
import multiprocessing
import os
import shutil
import tempfile
from collections.abc import Iterator
from concurrent.futures import FIRST_COMPLETED, ProcessPoolExecutor, wait
from dataclasses import asdict, dataclass
from pathlib import Path

import numpy as np

from .._atomic import atomic_write
from ..errors import SylvaError
from ..geometry.mesh import Material, Mesh, Scene
from .biomes import BIOME_COLORS, Biome
from .chunks import Chunk, generate_chunk, generate_chunks, load_chunk
from .meshing import quads_to_mesh
from .plants import PlantLibrary
from .terrain import WorldConfig, columns

__all__ = [
    "BLOCK_COLUMNS",
    "ChunkStore",
    "Instances",
    "World",
    "biome_image",
    "chunk_count",
    "expand_instances",
]


@dataclass
class Instances:
    """Copies of one plant model: ``translation`` float32[k, 3], ``yaw`` float32[k]."""

    key: str
    translation: np.ndarray
    yaw: np.ndarray

    def __len__(self) -> int:
        return int(self.translation.shape[0])

    def rotation(self) -> np.ndarray:
        """Unit quaternions ``(x, y, z, w)`` about +Y: float32[k, 4]."""
        q = np.zeros((len(self), 4), np.float32)
        q[:, 1] = np.sin(self.yaw / 2.0)
        q[:, 3] = np.cos(self.yaw / 2.0)
        return q


def expand_instances(mesh: Mesh, inst: Instances) -> Mesh:
    """One mesh with a transformed copy of ``mesh`` per instance (for rasterisers that do
    not instance)."""
    k = len(inst)
    c, s = np.cos(inst.yaw)[:, None], np.sin(inst.yaw)[:, None]
    v = mesh.vertices.astype(np.float64)[None]
    x = c * v[..., 0] + s * v[..., 2]
    z = -s * v[..., 0] + c * v[..., 2]
    verts = np.stack([x, np.broadcast_to(v[..., 1], x.shape), z], -1)
    verts = verts + inst.translation[:, None, :]
    n = mesh.normals.astype(np.float64)[None]
    nx = c * n[..., 0] + s * n[..., 2]
    nz = -s * n[..., 0] + c * n[..., 2]
    normals = np.stack([nx, np.broadcast_to(n[..., 1], nx.shape), nz], -1)
    idx = mesh.indices.astype(np.int64)[None] + (np.arange(k) * mesh.n_vertices)[:, None, None]
    return Mesh(verts.reshape(-1, 3), idx.reshape(-1, 3), normals=normals.reshape(-1, 3),
                uvs=None if mesh.uvs is None else np.tile(mesh.uvs, (k, 1)),
                material_ids=np.tile(mesh.triangle_materials(), k),
                materials=list(mesh.materials), name=f"{mesh.name}_x{k}")  # fmt: skip


def _worker(cfg_dict: dict, block: tuple[int, int, int, int], bounds, directory: str,
            atomic: bool = True) -> list:
    cfg = WorldConfig(**cfg_dict)
    out = []
    for chunk in generate_chunks(cfg, *block, bounds=bounds):
        path = Path(directory) / f"chunk_{chunk.cx}_{chunk.cz}.npz"
        chunk.save(path, atomic=atomic)
        out.append((chunk.cx, chunk.cz, int(chunk.quads.shape[0]), len(chunk.plants), str(path)))
    return out


#: Columns per side of the blocks of chunks a worker generates at once (noise calls have a
#: fixed cost, so bigger blocks are faster; memory per block stays small).
BLOCK_COLUMNS = 128


def _cfg_dict(cfg: WorldConfig) -> dict:
    d = asdict(cfg)
    return d


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
                 progress=None, block_columns: int = BLOCK_COLUMNS) -> ChunkStore:  # fmt: skip
        """Generate every chunk and store it in ``directory``.

        Parameters
        ----------
        directory : path, optional
            Where the chunk files go (created); default: a temporary folder that
            :meth:`ChunkStore.close` removes.
        workers : int, optional
            Worker processes (default: all cores; 1 runs in this process).  Workers are
            *spawned*, so a script that calls this with several workers needs the usual
            ``if __name__ == "__main__":`` guard.
        progress : callable, optional
            Called with ``(chunks done, total)`` after each block of chunks.
        block_columns : int
            Side of the blocks of chunks each task generates (see :meth:`blocks`).

        Returns
        -------
        ChunkStore
        """
        owned = directory is None
        folder = Path(tempfile.mkdtemp(prefix="sylva-world-")) if owned else Path(directory)
        folder.mkdir(parents=True, exist_ok=True)
        blocks = self.blocks(block_columns)
        total = len(self.chunk_coords())
        bounds = self.bounds if self.closed else None
        workers = max(1, min(workers or os.cpu_count() or 1, len(blocks)))
        summaries: list = []
        cfg = _cfg_dict(self.config)

        def record(result):
            summaries.extend(result)
            if progress:
                progress(len(summaries), total)

        if workers <= 1:
            for block in blocks:
                record(_worker(cfg, block, bounds, str(folder), not owned))
        else:
            ctx = multiprocessing.get_context("spawn")
            with ProcessPoolExecutor(max_workers=workers, mp_context=ctx) as pool:
                pending: set = set()
                it = iter(blocks)
                while True:
                    while len(pending) < 2 * workers:
                        nxt = next(it, None)
                        if nxt is None:
                            break
                        pending.add(pool.submit(_worker, cfg, nxt, bounds, str(folder),
                                                not owned))
                    if not pending:
                        break
                    finished, pending = wait(pending, return_when=FIRST_COMPLETED)
                    for fut in finished:
                        record(fut.result())
        summaries.sort(key=lambda t: (t[1], t[0]))
        index = {
            "config": cfg,
            "size": list(self.size), "origin": list(self.origin),
            "chunks": [{"cx": s[0], "cz": s[1], "quads": s[2], "plants": s[3],
                        "file": Path(s[4]).name} for s in summaries],
        }  # fmt: skip
        with atomic_write(folder / "world.json", "w") as fh:  # the index last: chunks first
            fh.write(json.dumps(index, indent=1))
        return ChunkStore(folder, owned=owned, config=self.config)

    def biome_map(self) -> np.ndarray:
        """The biome of every column: uint8[z, x] of :class:`~sylva.world.biomes.Biome`."""
        x0, z0 = self.origin
        f = columns(self.config, x0, z0, self.size[0], self.size[1])
        return np.ascontiguousarray(f.biome.T)


def biome_image(biomes: np.ndarray) -> np.ndarray:
    """Colour a biome array with :data:`~sylva.world.biomes.BIOME_COLORS`: uint8[..., 3]."""
    lut = np.array([BIOME_COLORS[b] for b in Biome], np.uint8)
    return lut[np.asarray(biomes, np.int64)]


class ChunkStore:
    """Chunks on disk, read back one at a time.

    Parameters
    ----------
    directory : path
        A folder written by :meth:`World.generate` (with its ``world.json``).
    owned : bool
        Remove the folder on :meth:`close`.
    """

    def __init__(self, directory, *, owned: bool = False,
                 config: WorldConfig | None = None) -> None:  # fmt: skip
        self.directory = Path(directory)
        meta = json.loads((self.directory / "world.json").read_text(encoding="utf-8"))
        self.meta = meta
        self.config = config or WorldConfig(**meta["config"])
        self.size = tuple(meta["size"])
        self.origin = tuple(meta["origin"])
        self.owned = owned

    def __len__(self) -> int:
        return len(self.meta["chunks"])

    def __iter__(self) -> Iterator[Chunk]:
        for c in self.meta["chunks"]:
            yield load_chunk(self.directory / c["file"])

    def __enter__(self) -> ChunkStore:
        return self

    def __exit__(self, *exc) -> None:
        self.close()

    def close(self) -> None:
        """Remove the folder when this store owns it."""
        if self.owned and self.directory.exists():
            shutil.rmtree(self.directory, ignore_errors=True)

    # ------------------------------------------------------------------ summaries
    @property
    def n_quads(self) -> int:
        return sum(c["quads"] for c in self.meta["chunks"])

    @property
    def n_plants(self) -> int:
        return sum(c["plants"] for c in self.meta["chunks"])

    def biome_map(self) -> np.ndarray:
        """The world's biomes as an sRGB image, uint8[z, x, 3] (row 0 at the lowest z)."""
        w, d = self.size
        ox, oz = self.origin
        img = np.zeros((d, w), np.uint8)
        for ch in self:
            x0, z0 = ch.origin
            xs = slice(max(x0, ox), min(x0 + ch.size, ox + w))
            zs = slice(max(z0, oz), min(z0 + ch.size, oz + d))
            if xs.start >= xs.stop or zs.start >= zs.stop:
                continue
            part = ch.biome[xs.start - x0 : xs.stop - x0, zs.start - z0 : zs.stop - z0]
            img[zs.start - oz : zs.stop - oz, xs.start - ox : xs.stop - ox] = part.T
        return biome_image(img)

    # ------------------------------------------------------------------ geometry
    def terrain_mesh(self, materials: list[Material] | None = None) -> Mesh:
        """All chunks' skins in one mesh (world coordinates)."""
        quads = [ch.quads for ch in self]
        q = np.concatenate(quads) if quads else np.zeros((0, 7), np.int32)
        return quads_to_mesh(q, materials=materials, name="terrain")

    def instances(self) -> dict[str, Instances]:
        """Plant instances grouped by model key (sorted keys)."""
        keys, pos, yaw = [], [], []
        for ch in self:
            keys.append(ch.plants.keys)
            pos.append(ch.plants.position)
            yaw.append(ch.plants.yaw)
        if not keys or sum(len(k) for k in keys) == 0:
            return {}
        k = np.concatenate(keys)
        p = np.concatenate(pos)
        y = np.concatenate(yaw)
        out = {}
        for key in sorted(set(k.tolist())):
            sel = k == key
            out[key] = Instances(key, p[sel], y[sel])
        return out

    def scene(self, library: PlantLibrary | None = None,
              materials: list[Material] | None = None, *, plants: bool = True,
              grass: bool = True) -> Scene:  # fmt: skip
        """Terrain plus every plant expanded into meshes (one mesh per model)."""
        c = self.config
        lib = library or PlantLibrary.for_config(c)
        if materials is not None:
            lib.materials = materials
        scene = Scene([self.terrain_mesh(materials or lib.materials)], name="world")
        if plants:
            for key, inst in self.instances().items():
                if not grass and key.startswith("grass#"):
                    continue
                scene.add(expand_instances(lib.model(key), inst))
        return scene


def chunk_count(size, chunk_size: int) -> int:
    """Chunks needed for ``size`` columns."""
    return math.ceil(size[0] / chunk_size) * math.ceil(size[1] / chunk_size)

"""Chunks: one square of columns, generated on its own, meshed, stored to disk.

:func:`generate_chunk` computes a chunk's column fields with a margin (two columns, for
plant spacing), its voxels with a margin of one (the neighbours' blocks, so its skin is
exact at the borders), the greedy-merged skin quads and its plants.  Nothing depends on
other chunks or on the order of generation, which is what lets chunks be generated in
parallel and streamed: a :class:`Chunk` holds only small arrays (the quads, not the
voxels, unless asked) and saves to one ``.npz`` file.

Examples
--------
>>> from sylva.world.terrain import WorldConfig
>>> c = generate_chunk(WorldConfig(seed=2, chunk_size=8), 0, 0)
>>> c.height.shape, c.quads.shape[1]
((8, 8), 7)
"""

from __future__ import annotations

from dataclasses import dataclass
from pathlib import Path

import numpy as np

from .._atomic import atomic_write
from ..geometry.mesh import Material, Mesh
from .blocks import Block
from .meshing import quads_to_mesh, skin_quads
from .plants import PlantLibrary
from .terrain import ColumnFields, WorldConfig, columns, voxels
from .vegetation import MARGIN, Placement, place_in, tree_candidates

__all__ = ["Chunk", "generate_chunk", "generate_chunks", "load_chunk"]


@dataclass
class Chunk:
    """A generated chunk.

    Attributes
    ----------
    cx, cz : int
        Chunk coordinates; its columns are ``x in [cx·s, cx·s + s)`` for chunk size ``s``.
    size : int
    height, humidity, temperature, biome : arrays [s, s]
        Per-column metadata (seed 004 keeps it "to save chunk to a file").
    quads : int32[q, 7]
        The greedy-merged skin in world voxel coordinates (see
        :data:`sylva.world.meshing.QUAD_FIELDS`).
    plants : Placement
    voxels : uint8[s, height, s] or None
        Only when generated with ``keep_voxels=True``.
    """

    cx: int
    cz: int
    size: int
    height: np.ndarray
    humidity: np.ndarray
    temperature: np.ndarray
    biome: np.ndarray
    quads: np.ndarray
    plants: Placement
    voxels: np.ndarray | None = None

    @property
    def origin(self) -> tuple[int, int]:
        """World ``(x, z)`` of the chunk's first column."""
        return self.cx * self.size, self.cz * self.size

    def mesh(self, materials: list[Material] | None = None) -> Mesh:
        """The chunk's skin as triangles (world coordinates), material id = tile."""
        return quads_to_mesh(self.quads, materials=materials, name=f"chunk_{self.cx}_{self.cz}")

    def save(self, path, *, atomic: bool = True) -> Path:
        """Write the chunk to ``path`` (``.npz``, compressed).

        ``atomic`` (default) writes a temporary file beside it and renames it over ``path``
        (see :mod:`sylva._atomic`); a private scratch folder may skip that (and its fsync).
        """
        path = Path(path)
        arrays = dict(
            meta=np.array([self.cx, self.cz, self.size], np.int64),
            height=self.height, humidity=self.humidity, temperature=self.temperature,
            biome=self.biome, quads=self.quads, plant_keys=self.plants.keys,
            plant_position=self.plants.position, plant_yaw=self.plants.yaw,
            plant_column=self.plants.column,
        )  # fmt: skip
        if self.voxels is not None:
            arrays["voxels"] = self.voxels
        with atomic_write(path) if atomic else open(path, "wb") as fh:
            np.savez_compressed(fh, **arrays)
        return path


def load_chunk(path) -> Chunk:
    """Read a chunk written by :meth:`Chunk.save`."""
    with np.load(Path(path), allow_pickle=False) as z:
        cx, cz, size = (int(v) for v in z["meta"])
        plants = Placement(z["plant_keys"], z["plant_position"], z["plant_yaw"],
                           z["plant_column"])  # fmt: skip
        return Chunk(cx, cz, size, z["height"], z["humidity"], z["temperature"], z["biome"],
                     z["quads"], plants, z.get("voxels"))  # fmt: skip


def generate_chunk(
    cfg: WorldConfig,
    cx: int,
    cz: int,
    *,
    library: PlantLibrary | None = None,
    bounds: tuple[int, int, int, int] | None = None,
    keep_voxels: bool = False,
    greedy: bool = True,
    fields: ColumnFields | None = None,
    candidates: np.ndarray | None = None,
) -> Chunk:
    """Generate chunk ``(cx, cz)``.

    Parameters
    ----------
    cfg : WorldConfig
    cx, cz : int
        Chunk coordinates.
    library : PlantLibrary, optional
        For plant model keys (default: one made from ``cfg``).
    bounds : (x0, z0, x1, z1), optional
        The world's extent in columns: voxels outside it count as air, so the world's
        outer walls are closed.  ``None``: the terrain goes on (no walls).
    keep_voxels : bool
        Keep the chunk's voxels (``uint8[s, height, s]``) in the result.
    greedy : bool
        Merge faces (default); ``False`` gives one quad per face.
    fields, candidates : optional
        The chunk's column fields with a margin of :data:`~sylva.world.vegetation.MARGIN`
        and their tree candidates, when computed already (see :func:`generate_chunks`).

    Returns
    -------
    Chunk
    """
    s = cfg.chunk_size
    x0, z0 = cx * s, cz * s
    m = MARGIN
    f = columns(cfg, x0 - m, z0 - m, s + 2 * m, s + 2 * m) if fields is None else fields
    if (f.x0, f.z0, f.height.shape) != (x0 - m, z0 - m, (s + 2 * m, s + 2 * m)):
        raise ValueError("fields must cover the chunk and a margin of MARGIN columns")
    vox = voxels(cfg, f.crop(m - 1))  # one column of margin
    if bounds is not None:
        bx0, bz0, bx1, bz1 = bounds
        xs = np.arange(x0 - 1, x0 + s + 1)
        zs = np.arange(z0 - 1, z0 + s + 1)
        outside = ((xs < bx0) | (xs >= bx1))[:, None] | ((zs < bz0) | (zs >= bz1))[None, :]
        vox[outside[:, None, :].repeat(vox.shape[1], 1)] = Block.AIR
    quads = skin_quads(vox, greedy=greedy)
    quads[:, 1:4] += _shift(quads[:, 0], x0 - 1, z0 - 1)
    plants = place_in(cfg, f, vox, library, candidates)
    inner = f.crop(m)
    return Chunk(cx, cz, s, inner.height, inner.humidity, inner.temperature, inner.biome,
                 quads, plants, vox[1:-1, :, 1:-1].copy() if keep_voxels else None)  # fmt: skip


def generate_chunks(cfg: WorldConfig, cx0: int, cz0: int, ncx: int, ncz: int,
                    **options) -> list[Chunk]:  # fmt: skip
    """A block of ``ncx × ncz`` chunks from ``(cx0, cz0)``, row by row (z outer).

    The same chunks as :func:`generate_chunk` gives one by one, but the noise fields and
    tree candidates are computed once for the whole block (each noise call has a fixed
    cost, so blocks of chunks are much faster).  ``options`` go to :func:`generate_chunk`.
    """
    s = cfg.chunk_size
    m = MARGIN
    region = columns(cfg, cx0 * s - m, cz0 * s - m, ncx * s + 2 * m, ncz * s + 2 * m)
    cand = tree_candidates(cfg, region) if cfg.vegetation else None
    out = []
    for j in range(ncz):
        for i in range(ncx):
            sl = (slice(i * s, i * s + s + 2 * m), slice(j * s, j * s + s + 2 * m))
            f = ColumnFields(region.x0 + i * s, region.z0 + j * s, region.height[sl],
                             region.humidity[sl], region.temperature[sl], region.biome[sl])
            c = None if cand is None else cand[sl]
            out.append(generate_chunk(cfg, cx0 + i, cz0 + j, fields=f, candidates=c,
                                      **options))  # fmt: skip
    return out


def _shift(direction: np.ndarray, dx: int, dz: int) -> np.ndarray:
    """Offsets of (layer, b0, c0) that move quads from array to world coordinates."""
    a = direction // 2
    axis_off = np.array([dx, 0, dz], np.int32)
    out = np.empty((direction.shape[0], 3), np.int32)
    out[:, 0] = axis_off[a]
    out[:, 1] = axis_off[(a + 1) % 3]
    out[:, 2] = axis_off[(a + 2) % 3]
    return out

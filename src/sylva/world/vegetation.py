"""Where plants grow: biome density, local maxima of noise, and the ground rules.

Seed 004 (Appendix A.4 / §5.2) places a tree where a per-biome octave-noise field has a
3 × 3 local maximum and no positive-offset neighbour ``(+1, 0)``, ``(0, +1)``, ``(+1, +1)``
is also a candidate (which keeps it deterministic); grass goes where ``hash01`` passes the
biome's threshold and no plant stands.  Beyond the thesis every plant must stand on solid
ground: the surface block is opaque, the column is above the sea level (never in water),
and no 4-neighbour's surface differs by more than ``max_slope`` (no steep slopes).

All fields are functions of world coordinates, so a chunk decides its plants alone and
neighbouring chunks agree (:func:`place` reads a margin of two columns).

Examples
--------
>>> from sylva.world.terrain import WorldConfig
>>> p = place(WorldConfig(seed=3), 0, 0, 16, 16)
>>> p.keys.dtype.kind, p.position.shape[1]
('U', 3)
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from ..texture import fbm
from .biomes import GRASS_DENSITY, TREE_DENSITY, Biome
from .blocks import SOLID
from .hashing import UINT_MAX, hash2d, hash3d
from .plants import PlantLibrary
from .terrain import ColumnFields, K, WorldConfig, columns, voxels  # K: the kernels' road

__all__ = ["BIOME_PLANTS", "MARGIN", "Placement", "place", "place_in", "tree_candidates"]

#: The plants of each biome: ``(species, probability)``; A.4 (oak if hash01 > 0.3,
#: baobab if hash01 > 0.7, acacia in the savanna, shrubs, cacti), extended to the forest
#: biomes that A.4 gives a density but no plant.
BIOME_PLANTS: dict[Biome, tuple[tuple[str, float], ...]] = {
    Biome.SHRUBLAND: (("shrub", 1.0),),
    Biome.TUNDRA: (("shrub", 1.0),),
    Biome.SUBTROPICAL_DESERT: (("cactus", 1.0),),
    Biome.SAVANNA: (("acacia", 1.0),),
    Biome.GRASSLAND: (("oak", 0.7), ("birch", 0.3)),
    Biome.WOODLAND: (("oak", 0.7), ("birch", 0.3)),
    Biome.SEASONAL_FOREST: (("oak", 0.5), ("birch", 0.5)),
    Biome.BOREAL_FOREST: (("birch", 0.8), ("shrub", 0.2)),
    Biome.TEMPERATE_RAINFOREST: (("oak", 0.6), ("jungle", 0.4)),
    Biome.TROPICAL_FOREST: (("jungle", 0.7), ("baobab", 0.3)),
    Biome.TROPICAL_RAINFOREST: (("jungle", 0.7), ("baobab", 0.3)),
}


@dataclass
class Placement:
    """The plants of a rectangle of columns.

    Attributes
    ----------
    keys : str array [n]
        Model key of each plant (see :class:`~sylva.world.plants.PlantLibrary`).
    position : float32[n, 3]
        Where the plant's base stands: the middle of the top of its ground block.
    yaw : float32[n]
        Rotation about +Y in radians (grass only; block plants stay axis-aligned).
    column : int32[n, 2]
        World ``(x, z)`` of the ground block; its layer is ``position[:, 1] − 1``.
    """

    keys: np.ndarray
    position: np.ndarray
    yaw: np.ndarray
    column: np.ndarray

    @classmethod
    def empty(cls) -> Placement:
        return cls(np.zeros(0, "U1"), np.zeros((0, 3), np.float32), np.zeros(0, np.float32),
                   np.zeros((0, 2), np.int32))  # fmt: skip

    def __len__(self) -> int:
        return int(self.position.shape[0])


def tree_candidates(cfg: WorldConfig, fields: ColumnFields) -> np.ndarray:
    """Columns where a tree may grow: 3 × 3 local maxima of each column's biome field.

    Returns
    -------
    bool[w, d]
        The shape of ``fields``; the outermost ring is False (its neighbours are unknown).
    """
    return _tree_candidates(cfg, fields.biome, fields.x0, fields.z0)


def _tree_candidates(cfg: WorldConfig, biome: np.ndarray, x0: int, z0: int) -> np.ndarray:
    w, d = biome.shape
    out = np.zeros((w, d), np.bool_)
    x = np.arange(x0, x0 + w, dtype=np.float64)[:, None] * np.ones((1, d))
    z = np.arange(z0, z0 + d, dtype=np.float64)[None, :] * np.ones((w, 1))
    groups: dict[tuple[float, int], list[int]] = {}
    for b in np.unique(biome):
        dens = TREE_DENSITY.get(Biome(int(b)))
        if dens is not None and Biome(int(b)) in BIOME_PLANTS:
            groups.setdefault((dens.frequency, dens.octaves), []).append(int(b))
    for (freq, octaves), members in groups.items():
        field = fbm(x / freq, z / freq, kind="perlin", octaves=octaves, seed=cfg.sub_seed(20),
                    dtype=np.float64)  # fmt: skip
        peak = K.local_maxima(field, 1)
        out |= peak & np.isin(biome, members)
    return out


def _choose(cfg: WorldConfig, lib: PlantLibrary, biome: int, x: int, z: int) -> str | None:
    options = BIOME_PLANTS.get(Biome(biome))
    if cfg.plants is not None:
        names = cfg.plants.get(Biome(biome).name.lower())
        if names is not None:
            options = tuple((n, 1.0 / len(names)) for n in names) if names else None
    if not options:
        return None
    r = hash2d(x, z, seed=cfg.sub_seed(21)) / UINT_MAX
    acc = 0.0
    name = options[-1][0]
    for n, p in options:
        acc += p
        if r < acc:
            name = n
            break
    if name == "shrub":
        return lib.shrub_key(lib.shrub_entry(x, z))
    if name == "grass":
        return f"grass#{int(hash3d(x, 0, z, seed=cfg.sub_seed(22)) * 4 // (UINT_MAX + 1))}"
    sp = lib.species.get(name)
    if sp is not None and sp.kind in ("cactus", "lsystem", "tree"):
        v = 8 if sp.kind == "cactus" else (lib.tree_variants or 8)
        return f"{name}#{int(hash2d(x, z, seed=cfg.sub_seed(23)) % v)}"
    return lib.tree_key(name, x, z)


def place(cfg: WorldConfig, x0: int, z0: int, w: int, d: int,
          library: PlantLibrary | None = None) -> Placement:  # fmt: skip
    """Plants and grass of the columns ``[x0, x0+w) × [z0, z0+d)``.

    Parameters
    ----------
    cfg : WorldConfig
    x0, z0, w, d : int
        The rectangle (a chunk).
    library : PlantLibrary, optional
        Gives the model keys (shrub cache entries, tree variants); its models are not
        built here.

    Returns
    -------
    Placement
        Plants first (row-major by x then z), then grass.
    """
    f = columns(cfg, x0 - MARGIN, z0 - MARGIN, w + 2 * MARGIN, d + 2 * MARGIN)
    return place_in(cfg, f, voxels(cfg, f.crop(MARGIN)), library)


MARGIN = 2
"""Columns of margin :func:`place_in` needs around its rectangle."""


def place_in(cfg: WorldConfig, fields: ColumnFields, vox: np.ndarray,
             library: PlantLibrary | None = None,
             candidates: np.ndarray | None = None) -> Placement:  # fmt: skip
    """:func:`place` on fields computed already.

    Parameters
    ----------
    cfg : WorldConfig
    fields : ColumnFields
        The rectangle plus a margin of :data:`MARGIN` columns.
    vox : uint8[w', height, d']
        Voxels of the rectangle with any margin ``(w' − w)/2`` (0 or more) on x and z.
    library : PlantLibrary, optional
    candidates : bool array, optional
        :func:`tree_candidates` of ``fields`` (or of a larger rectangle, sliced), when
        computed already.

    Returns
    -------
    Placement
    """
    if not cfg.vegetation:
        return Placement.empty()
    lib = library or PlantLibrary.for_config(cfg)
    m = MARGIN
    f = fields
    x0, z0 = f.x0 + m, f.z0 + m
    w, d = f.height.shape[0] - 2 * m, f.height.shape[1] - 2 * m
    vm = (vox.shape[0] - w) // 2
    h = f.height
    # ground rules on the padded grid (valid where a 4-neighbourhood exists)
    slope = np.zeros_like(h)
    slope[1:-1, 1:-1] = np.maximum.reduce([
        np.abs(h[1:-1, 1:-1] - h[:-2, 1:-1]), np.abs(h[1:-1, 1:-1] - h[2:, 1:-1]),
        np.abs(h[1:-1, 1:-1] - h[1:-1, :-2]), np.abs(h[1:-1, 1:-1] - h[1:-1, 2:]),
    ])  # fmt: skip
    inner = (slice(m, m + w), slice(m, m + d))
    wi, di = np.meshgrid(np.arange(w) + vm, np.arange(d) + vm, indexing="ij")
    hh = h[inner]
    ground = vox[wi, np.clip(hh, 0, cfg.height - 1), di]  # the ground block itself
    above = vox[wi, np.clip(hh + 1, 0, cfg.height - 1), di]
    ok = (
        SOLID[ground]
        & (above == 0)
        & (hh >= cfg.sea_level)
        & (hh + 1 < cfg.height)
        & (f.biome[inner] != Biome.WATER)
        & (slope[inner] <= cfg.max_slope)
    )
    cand = tree_candidates(cfg, f) if candidates is None else candidates
    # a candidate yields to a candidate at (+1, 0), (0, +1) or (+1, +1)
    blocked = np.zeros_like(cand)
    blocked[:-1, :] |= cand[1:, :]
    blocked[:, :-1] |= cand[:, 1:]
    blocked[:-1, :-1] |= cand[1:, 1:]
    tree = (cand & ~blocked)[inner] & ok
    keys: list[str] = []
    pos: list[tuple[float, float, float]] = []
    yaw: list[float] = []
    col: list[tuple[int, int]] = []
    biome = f.biome[inner]
    for i, k in zip(*np.nonzero(tree), strict=True):
        x, z = x0 + int(i), z0 + int(k)
        key = _choose(cfg, lib, int(biome[i, k]), x, z)
        if key is None:
            tree[i, k] = False
            continue
        keys.append(key)
        pos.append((x + 0.5, float(hh[i, k] + 1), z + 0.5))
        yaw.append(0.0)
        col.append((x, z))
    if cfg.grass:
        xs = np.arange(x0, x0 + w, dtype=np.int64)[:, None]
        zs = np.arange(z0, z0 + d, dtype=np.int64)[None, :]
        r = hash2d(xs, zs, seed=cfg.sub_seed(24)) / UINT_MAX
        thr = np.full(Biome.WATER + 1, 2.0)
        for b, t in GRASS_DENSITY.items():
            thr[b] = t
        grass = ok & ~tree & (r > thr[biome])
        quart = hash3d(xs, hh, zs, seed=cfg.sub_seed(25)) * 4 // (UINT_MAX + 1)
        turn = hash2d(xs, zs, seed=cfg.sub_seed(26)) / UINT_MAX * (np.pi / 2)
        for i, k in zip(*np.nonzero(grass), strict=True):
            keys.append(f"grass#{int(quart[i, k])}")
            pos.append((x0 + i + 0.5, float(hh[i, k] + 1), z0 + k + 0.5))
            yaw.append(float(turn[i, k]))
            col.append((x0 + int(i), z0 + int(k)))
    if not keys:
        return Placement.empty()
    return Placement(np.array(keys), np.array(pos, np.float32), np.array(yaw, np.float32),
                     np.array(col, np.int32))  # fmt: skip

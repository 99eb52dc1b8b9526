"""Terrain: heights, humidity, temperature and biomes from octave noise; voxel columns.

Every field is a pure function of the world seed and of world coordinates ``(x, z)`` (noise
from :mod:`sylva.texture` sampled point-wise, hashes from :mod:`sylva.world.hashing`), so
any rectangle of columns can be computed on its own and neighbouring chunks agree at their
borders.  Seed 004 Appendix A.3 / §5.2 gives the recipe:

* **height** — ``base + amplitude·fbm(x/λ, z/λ)`` plus seed 004's 2-octave hills
  (``10·Perlin01``), then the smoothing that snaps columns on steep 4-neighbourhoods;
* **humidity** — a smooth noise field quantised to levels 0..9;
* **temperature** — latitude bands along z (150 blocks, alternating 9→0 and 0→9, edges
  fluctuating with x and bent by slow 2D noise), minus up to 5 levels at the maximum height;
* **biome** — the 10 × 10 table, two candidates chosen by noise at 128-block zones with
  a ±5-block hash jitter (fuzzy borders); columns below the sea level are Water;
* **voxels** — surface block on top, the biome's under-block below, stone from 3 blocks
  down; water fills up to the sea level (ice in frozen biomes); optional caves carved by 3D
  noise.

Examples
--------
>>> cfg = WorldConfig(seed=1)
>>> f = columns(cfg, 0, 0, 4, 3)
>>> f.height.shape, f.biome.dtype.name
((4, 3), 'uint8')
>>> bool(np.array_equal(columns(cfg, 2, 1, 2, 2).height, f.height[2:4, 1:3]))
True
"""

from __future__ import annotations

from dataclasses import dataclass, field

import numpy as np

from .. import _jit
from ..errors import SylvaError
from ..texture import fbm
from .biomes import SURFACE_BLOCKS, Biome, select
from .blocks import Block
from .hashing import hash2d, limited

#: The world kernels; inside :meth:`World.generate` of a small world on a cold cache, their
#: Python source (:func:`sylva._jit.road`: a 64² world's heights and columns take some
#: 50 ms so, against seconds of compiling).  Caves are carved compiled (``_compiled``): a
#: voxel loop is too long for Python.
K = _jit.road("sylva.world._kernels", ("sylva.turtle._state", "sylva.turtle._kernels"))
_compiled = _jit.lazy("sylva.world._kernels")

__all__ = ["ColumnFields", "WorldConfig", "WorldConfigError", "columns", "voxels"]


class WorldConfigError(SylvaError, ValueError):
    """An impossible world setting."""


@dataclass(frozen=True)
class WorldConfig:
    """Everything that decides a world besides its extent.

    Parameters
    ----------
    seed : int
        The world seed: noise tables and every hash derive from it.
    chunk_size : int
        Columns per chunk edge (seed 004 leaves it unresolved; 32 by default).  The
        terrain does not depend on it.
    height : int
        Voxel layers (``MAX_BLOCK_HEIGHT``).
    sea_level : int
        Water fills columns up to this layer.
    base_height, amplitude, wavelength : float
        Height = ``base_height + amplitude·fbm(x/wavelength, z/wavelength)`` + hills.
    hills : float
        Amplitude of seed 004's 2-octave hill noise (10 in the thesis code).
    humidity_wavelength : float
        Wavelength of the humidity field in blocks.
    temperature_band : float
        Latitude band size along z (150 in the thesis code).
    caves : bool
        Carve caves with 3D noise.
    vegetation, grass : bool
        Place plants and grass.
    tree_variants : int or None
        Distinct individuals per tree species (instanced); ``None`` grows every tree from
        its own position salt as seed 004 does (no two alike, nothing to instance).
    shrub_count : int
        Shrub cache entries per shrub species (``SHRUB_COUNT``; stage = i mod 3).
    max_slope : int
        Plants stand only where no 4-neighbour surface differs by more than this.
    plants : dict, optional
        Biome name (``"savanna"``) → list of plant names overriding
        :data:`sylva.world.vegetation.BIOME_PLANTS` (equal shares; ``"shrub"`` is the
        shrub cache).
    species : dict, optional
        Extra :class:`~sylva.world.plants.Species` by name (e.g. a ``.lsys`` file or a
        :mod:`sylva.tree` species) that ``plants`` may name.
    """

    seed: int = 0
    chunk_size: int = 32
    height: int = 96
    sea_level: int = 30
    base_height: float = 34.0
    amplitude: float = 40.0
    wavelength: float = 220.0
    hills: float = 10.0
    humidity_wavelength: float = 260.0
    temperature_band: float = 150.0
    caves: bool = False
    vegetation: bool = True
    grass: bool = True
    tree_variants: int | None = 16
    shrub_count: int = 12
    max_slope: int = 1
    plants: dict | None = field(default=None, hash=False, compare=False)
    species: dict | None = field(default=None, hash=False, compare=False)

    def __post_init__(self) -> None:
        if self.species:
            from .plants import Species  # species given as dicts (from JSON or asdict)

            conv = {k: v if isinstance(v, Species) else Species(**{
                f: tuple(x) if isinstance(x, list) else x for f, x in v.items()})
                for k, v in self.species.items()}  # fmt: skip
            object.__setattr__(self, "species", conv)
        if not 4 <= self.chunk_size <= 512:
            raise WorldConfigError(f"chunk_size must be in 4..512, got {self.chunk_size}")
        if not 8 <= self.height <= 255:
            raise WorldConfigError(f"height must be in 8..255 layers, got {self.height}")
        if not 0 <= self.sea_level < self.height - 1:
            raise WorldConfigError(
                f"sea_level must be in 0..{self.height - 2}, got {self.sea_level}"
            )
        if self.wavelength <= 0 or self.humidity_wavelength <= 0 or self.temperature_band <= 0:
            raise WorldConfigError("wavelengths and the temperature band must be > 0")
        if self.tree_variants is not None and self.tree_variants < 1:
            raise WorldConfigError(f"tree_variants must be >= 1 or None, got {self.tree_variants}")
        if self.shrub_count < 3:
            raise WorldConfigError(
                f"shrub_count must be >= 3 (three stages), got {self.shrub_count}"
            )
        if self.max_slope < 0:
            raise WorldConfigError(f"max_slope must be >= 0, got {self.max_slope}")

    # seeds of the independent fields (the noise tables of sylva.texture take int seeds)
    def sub_seed(self, k: int) -> int:
        """The seed of field ``k`` (a hash of the world seed; non-negative, < 2³¹)."""
        return int(hash2d(self.seed, k, seed=0x5EED)) & 0x7FFFFFFF


@dataclass
class ColumnFields:
    """Per-column fields of a rectangle of the world, indexed ``[x − x0, z − z0]``.

    Attributes
    ----------
    x0, z0 : int
        World coordinates of element ``[0, 0]``.
    height : int32[w, d]
        Surface layer (the topmost solid block).
    humidity, temperature : uint8[w, d]
        Levels 0..9.
    biome : uint8[w, d]
        :class:`~sylva.world.biomes.Biome` values.
    """

    x0: int
    z0: int
    height: np.ndarray
    humidity: np.ndarray
    temperature: np.ndarray
    biome: np.ndarray

    def crop(self, m: int) -> ColumnFields:
        """The fields without a margin of ``m`` columns on every side."""
        s = (slice(m, -m or None), slice(m, -m or None))
        return ColumnFields(self.x0 + m, self.z0 + m, self.height[s], self.humidity[s],
                            self.temperature[s], self.biome[s])  # fmt: skip


def _grid(x0: int, z0: int, w: int, d: int) -> tuple[np.ndarray, np.ndarray]:
    x = np.arange(x0, x0 + w, dtype=np.float64)[:, None]
    z = np.arange(z0, z0 + d, dtype=np.float64)[None, :]
    return np.broadcast_to(x, (w, d)), np.broadcast_to(z, (w, d))


def _noise01(x, z, seed, octaves, kind="perlin") -> np.ndarray:
    """Octave noise mapped to about [0, 1] (Perlin01 of seed 004)."""
    v = fbm(x, z, kind=kind, octaves=octaves, seed=seed, dtype=np.float64)
    return np.clip(0.5 + v, 0.0, 1.0)


def _raw_height(cfg: WorldConfig, x, z) -> np.ndarray:
    lam = cfg.wavelength
    big = fbm(x / lam, z / lam, kind="improved", octaves=5, seed=cfg.sub_seed(1),
              dtype=np.float64)
    hills = _noise01(x / 80.0, z / 80.0, cfg.sub_seed(2), 2)
    h = cfg.base_height + cfg.amplitude * big + cfg.hills * hills
    return np.clip(h, 1.0, cfg.height - 2.0)


def columns(cfg: WorldConfig, x0: int, z0: int, w: int, d: int) -> ColumnFields:
    """Heights, humidity, temperature and biome of the columns ``[x0, x0+w) × [z0, z0+d)``.

    Parameters
    ----------
    cfg : WorldConfig
    x0, z0 : int
        World coordinates of the first column.
    w, d : int
        Columns along x and z (≥ 1).

    Returns
    -------
    ColumnFields
        Arrays of shape ``(w, d)``; the same columns get the same values whatever
        rectangle they are computed in.
    """
    if w < 1 or d < 1:
        raise WorldConfigError(f"a column rectangle needs w, d >= 1, got {w} x {d}")
    x, z = _grid(x0 - 1, z0 - 1, w + 2, d + 2)  # one more on each side for smoothing
    height = K.smooth_heights(_raw_height(cfg, x, z))[1:-1, 1:-1]
    x, z = x[1:-1, 1:-1], z[1:-1, 1:-1]

    hum01 = fbm(x / cfg.humidity_wavelength, z / cfg.humidity_wavelength, kind="perlin",
                octaves=3, seed=cfg.sub_seed(3), dtype=np.float64)
    humidity = np.clip(np.floor((0.5 + 1.8 * hum01) * 10.0), 0, 9).astype(np.uint8)

    band = cfg.temperature_band
    wobble = fbm(x * 0.01, np.zeros_like(x), kind="perlin", octaves=2, seed=cfg.sub_seed(4),
                 dtype=np.float64)
    drift = fbm(x / (2.0 * band), z / (2.0 * band), kind="perlin", octaves=2,
                seed=cfg.sub_seed(8), dtype=np.float64)  # bends the bands
    zz = z + (0.5 + wobble) * band * 0.1 * 2.0 + 0.5 * band + drift * band
    k = np.floor(zz / band)
    frac = zz / band - k
    level = np.where(k % 2 == 0, 10.0 * (1.0 - frac), 10.0 * frac)
    level -= np.maximum(height - cfg.sea_level, 0) / (cfg.height - cfg.sea_level) * 10.0 * 0.5
    temperature = np.clip(np.floor(level), 0, 9).astype(np.uint8)

    xi = x.astype(np.int64)
    zi = z.astype(np.int64)
    shift = limited(hash2d(xi, zi, seed=cfg.sub_seed(5)), 5)
    pick = _noise01((x + shift) / 128.0, (z + shift) / 128.0, cfg.sub_seed(6), 1)
    pick = np.clip(0.5 + (pick - 0.5) * 3.0, 0.0, 1.0)  # Perlin01 rarely leaves [0.3, 0.7]
    biome = select(humidity, temperature, pick)
    biome = np.where(height < cfg.sea_level, np.uint8(Biome.WATER), biome).astype(np.uint8)
    return ColumnFields(int(x0), int(z0), np.ascontiguousarray(height, np.int32), humidity,
                        temperature, biome)  # fmt: skip


def voxels(cfg: WorldConfig, fields: ColumnFields) -> np.ndarray:
    """The voxel blocks of the columns of ``fields``.

    Returns
    -------
    uint8[w, cfg.height, d]
        :class:`~sylva.world.blocks.Block` ids indexed ``[x − x0, y, z − z0]``.
    """
    b = fields.biome
    top = SURFACE_BLOCKS[b, 0].copy()
    under = SURFACE_BLOCKS[b, 1].copy()
    deep = np.full(b.shape, np.uint8(Block.STONE))
    h = fields.height
    # beaches and lake floors: sand where warm, gravel where cold
    wet = h <= cfg.sea_level
    cold = fields.temperature <= 1
    top = np.where(wet, np.where(cold, np.uint8(Block.GRAVEL), np.uint8(Block.SAND)), top)
    under = np.where(wet, np.uint8(Block.SAND), under)
    # high peaks carry snow
    peak = h >= cfg.height - max(6, cfg.height // 8)
    top = np.where(peak & ~wet, np.uint8(Block.SNOW), top)
    water_top = np.where(cold, np.uint8(Block.ICE), np.uint8(Block.WATER))
    vox = K.fill_columns(h, top.astype(np.uint8), under.astype(np.uint8), deep, cfg.sea_level,
                         cfg.height, water_top.astype(np.uint8))  # fmt: skip
    if cfg.caves:
        w, ny, d = vox.shape
        xs = np.arange(fields.x0, fields.x0 + w, dtype=np.float64)[:, None, None]
        ys = np.arange(ny, dtype=np.float64)[None, :, None]
        zs = np.arange(fields.z0, fields.z0 + d, dtype=np.float64)[None, None, :]
        xs, ys, zs = np.broadcast_arrays(xs, ys, zs)
        dens = fbm(xs / 24.0, ys / 16.0, zs / 24.0, kind="improved", octaves=2,
                   seed=cfg.sub_seed(7), dtype=np.float64)
        vox = _compiled.carve(vox, dens, h, 0.22, 2)
    return vox

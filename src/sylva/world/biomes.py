"""Biomes: seed 004's 10 × 10 humidity/temperature table, surface blocks and vegetation rules.

The table (Appendix A.3) is indexed ``[humidity][temperature]``, both levels in 0..9, and
each cell holds one or two candidate biomes; a smooth noise field chooses between two
(:func:`select`).  Columns under the sea level belong to :attr:`Biome.WATER`.

Examples
--------
>>> candidates(0, 0)
(<Biome.ICE: 0>,)
>>> candidates(5, 3), candidates(7, 9)
((<Biome.SEASONAL_FOREST: 7>,), (<Biome.TROPICAL_FOREST: 10>, <Biome.SAVANNA: 11>))
>>> SURFACE[Biome.SAVANNA]
(<Block.COTTON_RED: 10>, <Block.DIRT: 3>)
"""

from __future__ import annotations

from dataclasses import dataclass
from enum import IntEnum

import numpy as np

from .blocks import Block

__all__ = [
    "BIOME_COLORS",
    "BIOME_TABLE",
    "GRASS_DENSITY",
    "SURFACE",
    "TREE_DENSITY",
    "Biome",
    "TreeDensity",
    "candidates",
    "select",
]


class Biome(IntEnum):
    """Seed 004's biomes (Appendix A.3), Water last."""

    ICE = 0
    TUNDRA = 1
    GRASSLAND = 2
    COLD_DESERT = 3
    WOODLAND = 4
    BOREAL_FOREST = 5
    SHRUBLAND = 6
    SEASONAL_FOREST = 7
    TEMPERATE_RAINFOREST = 8
    SUBTROPICAL_DESERT = 9
    TROPICAL_FOREST = 10
    SAVANNA = 11
    TROPICAL_RAINFOREST = 12
    WATER = 13


_I, _T = Biome.ICE, Biome.TUNDRA
_GC = (Biome.GRASSLAND, Biome.COLD_DESERT)
_WS = (Biome.WOODLAND, Biome.SHRUBLAND)
_B, _S, _TR = Biome.BOREAL_FOREST, Biome.SEASONAL_FOREST, Biome.TEMPERATE_RAINFOREST
_SD = Biome.SUBTROPICAL_DESERT
_TS = (Biome.TROPICAL_FOREST, Biome.SAVANNA)
_RF = Biome.TROPICAL_RAINFOREST


def _row(*cells) -> tuple[tuple[Biome, ...], ...]:
    return tuple(c if isinstance(c, tuple) else (c,) for c in cells)


#: ``BIOME_TABLE[humidity][temperature]``: the candidate biomes of each cell (A.3).
BIOME_TABLE: tuple[tuple[tuple[Biome, ...], ...], ...] = (
    _row(_I, _T, _GC, _GC, _GC, _SD, _SD, _SD, _SD, _SD),
    _row(_I, _T, _GC, _GC, _GC, _GC, _SD, _SD, _SD, _SD),
    _row(_I, _T, _GC, _GC, _GC, _GC, _SD, _SD, _SD, _SD),
    _row(_I, _T, _WS, _WS, _WS, _GC, _TS, _TS, _TS, _TS),
    _row(_I, _T, _WS, _WS, _WS, _WS, _TS, _TS, _TS, _TS),
    _row(_I, _T, _B, _S, _WS, _WS, _TS, _TS, _TS, _TS),
    _row(_I, _T, _B, _S, _S, _S, _TS, _TS, _TS, _TS),
    _row(_I, _T, _B, _S, _S, _S, _RF, _RF, _RF, _TS),
    _row(_I, _T, _B, _TR, _S, _S, _RF, _RF, _RF, _RF),
    _row(_I, _T, _B, _TR, _TR, _TR, _RF, _RF, _RF, _RF),
)

# flat lookup arrays for vectorised selection: [hum, temp, 2] and counts
_CAND = np.array([[(c[0], c[-1]) for c in row] for row in BIOME_TABLE], np.uint8)
_COUNT = np.array([[len(c) for c in row] for row in BIOME_TABLE], np.uint8)


def candidates(humidity: int, temperature: int) -> tuple[Biome, ...]:
    """The candidate biomes of the table cell ``[humidity][temperature]`` (levels 0..9).

    Raises
    ------
    ValueError
        When a level is outside 0..9.
    """
    if not (0 <= humidity <= 9 and 0 <= temperature <= 9):
        raise ValueError(
            f"humidity and temperature levels must be in 0..9, got {humidity}, {temperature}"
        )
    return BIOME_TABLE[humidity][temperature]


def select(humidity, temperature, pick) -> np.ndarray:
    """Biomes of many columns.

    Parameters
    ----------
    humidity, temperature : int array, levels 0..9 (clipped)
    pick : float array in [0, 1]
        Chooses between two candidates: the first below 0.5, the second from 0.5 (seed
        004's ``floor(count · noise)``); ignored for cells with one candidate.

    Returns
    -------
    uint8 ndarray of :class:`Biome` values, the broadcast shape of the inputs.
    """
    h = np.clip(np.asarray(humidity, np.int64), 0, 9)
    t = np.clip(np.asarray(temperature, np.int64), 0, 9)
    p = np.asarray(pick, np.float64)
    count = _COUNT[h, t]
    idx = np.minimum(np.floor(count * np.clip(p, 0.0, 1.0)).astype(np.int64), count - 1)
    idx = np.minimum(idx, 1)
    return _CAND[h, t, idx]


#: Surface block and the block below it, per biome (A.3; stone from 3 blocks down).
SURFACE: dict[Biome, tuple[Block, Block]] = {
    Biome.ICE: (Block.ICE, Block.ICE),
    Biome.TUNDRA: (Block.GRASS_TUNDRA, Block.DIRT),
    Biome.GRASSLAND: (Block.GRASS, Block.DIRT),
    Biome.WOODLAND: (Block.GRASS, Block.DIRT),
    Biome.BOREAL_FOREST: (Block.GRASS, Block.DIRT),
    Biome.SEASONAL_FOREST: (Block.GRASS, Block.DIRT),
    Biome.TEMPERATE_RAINFOREST: (Block.GRASS, Block.DIRT),
    Biome.COLD_DESERT: (Block.GREYSAND, Block.GREYSAND),
    Biome.SHRUBLAND: (Block.GRAVEL_DIRT, Block.DIRT),
    Biome.SUBTROPICAL_DESERT: (Block.SAND, Block.SAND),
    Biome.TROPICAL_FOREST: (Block.GRASS_JUNGLE, Block.DIRT),
    Biome.TROPICAL_RAINFOREST: (Block.GRASS_JUNGLE, Block.DIRT),
    Biome.SAVANNA: (Block.COTTON_RED, Block.DIRT),
    Biome.WATER: (Block.SAND, Block.SAND),
}

#: ``uint8[n_biomes, 2]``: :data:`SURFACE` as an array (top, under).
SURFACE_BLOCKS = np.array([[int(b) for b in SURFACE[bi]] for bi in Biome], np.uint8)


@dataclass(frozen=True)
class TreeDensity:
    """How a biome spaces its trees: local maxima of octave noise (A.4).

    A column gets a tree where ``fbm(x / frequency, z / frequency, octaves)`` is a 3 × 3
    local maximum.  Larger ``frequency`` (a wavelength, in blocks) spaces trees further
    apart; more ``octaves`` add small bumps and so more maxima (denser).
    """

    frequency: float
    octaves: int


# seed 004 leaves FREQ_* and DENSITY_* unresolved; these wavelengths and octave counts
# give about one tree per 25 (dense) to 300 (rare) columns.
_FREQ_NORMAL, _FREQ_RARE, _FREQ_SPARSE = 6.0, 9.0, 7.0
_SPARSE, _NORMAL, _DENSE = 1, 2, 3

#: Tree spacing per biome (A.4); biomes without an entry have no trees.
TREE_DENSITY: dict[Biome, TreeDensity] = {
    Biome.TROPICAL_FOREST: TreeDensity(_FREQ_NORMAL * 1.5, _DENSE),
    Biome.TROPICAL_RAINFOREST: TreeDensity(_FREQ_NORMAL * 1.5, _DENSE),
    Biome.TEMPERATE_RAINFOREST: TreeDensity(_FREQ_NORMAL * 1.5, _DENSE),
    Biome.TUNDRA: TreeDensity(_FREQ_NORMAL * 1.5, _DENSE),
    Biome.SUBTROPICAL_DESERT: TreeDensity(_FREQ_RARE, _SPARSE),
    Biome.GRASSLAND: TreeDensity(_FREQ_RARE * 2.2, _SPARSE),
    Biome.WOODLAND: TreeDensity(_FREQ_NORMAL, _NORMAL),
    Biome.SEASONAL_FOREST: TreeDensity(_FREQ_NORMAL, _NORMAL),
    Biome.BOREAL_FOREST: TreeDensity(_FREQ_NORMAL, _NORMAL),
    Biome.SHRUBLAND: TreeDensity(_FREQ_SPARSE / 1.9, _DENSE),
    Biome.SAVANNA: TreeDensity(_FREQ_RARE * 1.5, _DENSE),
}

#: Grass threshold per biome: grass where ``hash01 > threshold`` (A.4); absent: no grass.
GRASS_DENSITY: dict[Biome, float] = {
    Biome.TUNDRA: 0.8,
    Biome.WOODLAND: 0.5,
    Biome.BOREAL_FOREST: 0.5,
    Biome.SEASONAL_FOREST: 0.5,
    Biome.TEMPERATE_RAINFOREST: 0.5,
    Biome.TROPICAL_FOREST: 0.5,
    Biome.SAVANNA: 0.5,
    Biome.TROPICAL_RAINFOREST: 0.5,
    Biome.GRASSLAND: 0.2,
    Biome.SHRUBLAND: 0.2,
}

#: sRGB colours of the biome map (:meth:`sylva.world.World.biome_map`).
BIOME_COLORS: dict[Biome, tuple[int, int, int]] = {
    Biome.ICE: (235, 245, 255),
    Biome.TUNDRA: (150, 170, 150),
    Biome.GRASSLAND: (140, 200, 90),
    Biome.COLD_DESERT: (190, 185, 160),
    Biome.WOODLAND: (90, 160, 60),
    Biome.BOREAL_FOREST: (40, 100, 70),
    Biome.SHRUBLAND: (160, 150, 80),
    Biome.SEASONAL_FOREST: (60, 140, 40),
    Biome.TEMPERATE_RAINFOREST: (20, 110, 60),
    Biome.SUBTROPICAL_DESERT: (235, 210, 140),
    Biome.TROPICAL_FOREST: (70, 170, 40),
    Biome.SAVANNA: (200, 170, 70),
    Biome.TROPICAL_RAINFOREST: (10, 120, 30),
    Biome.WATER: (40, 90, 190),
}

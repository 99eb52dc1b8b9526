"""The 10 x 10 humidity/temperature table and the surface blocks (seed 004 A.3)."""

import numpy as np
import pytest

from sylva.world.biomes import BIOME_TABLE, SURFACE, Biome, candidates, select
from sylva.world.blocks import Block

B = Biome


@pytest.mark.parametrize(
    ("hum", "temp", "expected"),
    [
        (0, 0, (B.ICE,)),
        (9, 0, (B.ICE,)),
        (4, 1, (B.TUNDRA,)),
        (0, 2, (B.GRASSLAND, B.COLD_DESERT)),
        (0, 5, (B.SUBTROPICAL_DESERT,)),
        (1, 5, (B.GRASSLAND, B.COLD_DESERT)),
        (3, 5, (B.GRASSLAND, B.COLD_DESERT)),
        (3, 2, (B.WOODLAND, B.SHRUBLAND)),
        (4, 5, (B.WOODLAND, B.SHRUBLAND)),
        (5, 2, (B.BOREAL_FOREST,)),
        (5, 3, (B.SEASONAL_FOREST,)),
        (5, 4, (B.WOODLAND, B.SHRUBLAND)),
        (6, 4, (B.SEASONAL_FOREST,)),
        (8, 3, (B.TEMPERATE_RAINFOREST,)),
        (9, 5, (B.TEMPERATE_RAINFOREST,)),
        (3, 6, (B.TROPICAL_FOREST, B.SAVANNA)),
        (7, 6, (B.TROPICAL_RAINFOREST,)),
        (7, 9, (B.TROPICAL_FOREST, B.SAVANNA)),
        (8, 9, (B.TROPICAL_RAINFOREST,)),
        (2, 9, (B.SUBTROPICAL_DESERT,)),
    ],
)
def test_table_cells(hum, temp, expected):
    assert candidates(hum, temp) == expected


def test_table_shape_and_counts():
    assert len(BIOME_TABLE) == 10 and all(len(r) == 10 for r in BIOME_TABLE)
    assert all(1 <= len(c) <= 2 for r in BIOME_TABLE for c in r)
    # every land biome of the enum appears somewhere
    seen = {b for r in BIOME_TABLE for c in r for b in c}
    assert seen == set(Biome) - {Biome.WATER}
    with pytest.raises(ValueError):
        candidates(10, 0)


def test_select_picks_between_two_candidates():
    hum = np.array([0, 0, 0, 5, 5])
    temp = np.array([2, 2, 2, 3, 3])
    pick = np.array([0.0, 0.49, 0.5, 0.0, 1.0])
    got = select(hum, temp, pick)
    assert got.tolist() == [B.GRASSLAND, B.GRASSLAND, B.COLD_DESERT, B.SEASONAL_FOREST,
                            B.SEASONAL_FOREST]


def test_select_agrees_with_the_table_everywhere():
    h, t = np.meshgrid(np.arange(10), np.arange(10), indexing="ij")
    for p in (0.1, 0.9):
        got = select(h, t, np.full(h.shape, p))
        for i in range(10):
            for j in range(10):
                c = BIOME_TABLE[i][j]
                assert got[i, j] == c[0 if p < 0.5 else -1]


def test_surface_blocks():
    assert SURFACE[B.GRASSLAND] == (Block.GRASS, Block.DIRT)
    assert SURFACE[B.SHRUBLAND] == (Block.GRAVEL_DIRT, Block.DIRT)
    assert SURFACE[B.SUBTROPICAL_DESERT] == (Block.SAND, Block.SAND)
    assert SURFACE[B.COLD_DESERT] == (Block.GREYSAND, Block.GREYSAND)
    assert SURFACE[B.TROPICAL_RAINFOREST] == (Block.GRASS_JUNGLE, Block.DIRT)
    assert SURFACE[B.SAVANNA] == (Block.COTTON_RED, Block.DIRT)
    assert SURFACE[B.ICE] == (Block.ICE, Block.ICE)
    assert SURFACE[B.TUNDRA] == (Block.GRASS_TUNDRA, Block.DIRT)
    assert set(SURFACE) == set(Biome)

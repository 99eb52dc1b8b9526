"""Block types of the voxel world and the texture each of their faces shows.

Voxels are ``uint8`` block ids.  :data:`FACE_TEXTURES` gives each block the texture of its
top, side and bottom faces (a grass block is assembled from three parts, seed 004 Fig. 1.1),
as indices into :data:`TEXTURES`, the tiles of the texture atlas
(:mod:`sylva.world.atlas`).  Plant materials (bark, leaves, grass tufts) are atlas tiles too.

Examples
--------
>>> int(Block.GRASS), TEXTURES[FACE_TEXTURES[Block.GRASS, 0]]
(4, 'grass_top')
>>> bool(OPAQUE[Block.WATER]), bool(OPAQUE[Block.STONE])
(False, True)
"""

from __future__ import annotations

from enum import IntEnum

import numpy as np

__all__ = ["FACE_TEXTURES", "OPAQUE", "SOLID", "TEXTURES", "Block", "texture_id"]


class Block(IntEnum):
    """Voxel ids (``uint8``)."""

    AIR = 0
    WATER = 1
    STONE = 2
    DIRT = 3
    GRASS = 4
    GRASS_TUNDRA = 5
    GRASS_JUNGLE = 6
    SAND = 7
    GREYSAND = 8
    GRAVEL_DIRT = 9
    COTTON_RED = 10
    ICE = 11
    GRAVEL = 12
    SNOW = 13


#: Atlas tile names, in atlas order.
TEXTURES: tuple[str, ...] = (
    "stone", "dirt", "grass_top", "grass_side", "tundra_top", "tundra_side", "jungle_top",
    "jungle_side", "sand", "greysand", "gravel_dirt", "cotton_red", "ice", "water", "gravel",
    "snow", "bark", "bark_white", "bark_orange", "leaves", "leaves_birch", "leaves_jungle",
    "leaves_orange", "leaves_shrub", "cactus", "grass_tuft",
)  # fmt: skip


def texture_id(name: str) -> int:
    """Index of the atlas tile ``name``.

    Raises
    ------
    KeyError
        Naming the known tiles when ``name`` is not one.
    """
    try:
        return TEXTURES.index(name)
    except ValueError:
        raise KeyError(f"unknown block texture {name!r}; expected one of {TEXTURES}") from None


_FACES = {
    Block.AIR: ("stone", "stone", "stone"),
    Block.WATER: ("water", "water", "water"),
    Block.STONE: ("stone", "stone", "stone"),
    Block.DIRT: ("dirt", "dirt", "dirt"),
    Block.GRASS: ("grass_top", "grass_side", "dirt"),
    Block.GRASS_TUNDRA: ("tundra_top", "tundra_side", "dirt"),
    Block.GRASS_JUNGLE: ("jungle_top", "jungle_side", "dirt"),
    Block.SAND: ("sand", "sand", "sand"),
    Block.GREYSAND: ("greysand", "greysand", "greysand"),
    Block.GRAVEL_DIRT: ("gravel_dirt", "gravel_dirt", "dirt"),
    Block.COTTON_RED: ("cotton_red", "cotton_red", "dirt"),
    Block.ICE: ("ice", "ice", "ice"),
    Block.GRAVEL: ("gravel", "gravel", "gravel"),
    Block.SNOW: ("snow", "snow", "dirt"),
}

#: ``int32[n_blocks, 3]``: texture of the top, side and bottom face of each block.
FACE_TEXTURES = np.array([[texture_id(t) for t in _FACES[b]] for b in Block], np.int32)
FACE_TEXTURES.setflags(write=False)

#: ``bool[n_blocks]``: blocks that hide the faces behind them (all but air and water).
OPAQUE = np.array([b not in (Block.AIR, Block.WATER) for b in Block], np.bool_)
OPAQUE.setflags(write=False)

#: ``bool[n_blocks]``: blocks a plant can stand on (opaque ones).
SOLID = OPAQUE

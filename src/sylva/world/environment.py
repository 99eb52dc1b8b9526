"""The voxel world as the environment of an open L-system: terrain, blocks, biome, rocks.

A plant stands on the ground at the centre column of a square of the world; its turtle
units are ``scale`` per block.  Each communication module ``?E(d, block, height,
biome)`` looks ``d`` units ahead of the turtle (along its heading) and gets the
:class:`~sylva.world.blocks.Block` there (0 air, 1 water, 2 stone…), the height of that
point above the ground of its column (in turtle units, negative below) and the column's
:class:`~sylva.world.biomes.Biome`.  ``d`` is the module's own input; a module with fewer
parameters gets the first answers.  Branches stop where ``block > 1`` (terrain, rock);
roots grow while they are in the soil and stop at stone.  Rocks are spheres of stone put
on the terrain (:class:`WorldEnvironment` ``rocks``), so a plant grows around them.

Examples
--------
>>> import numpy as np
>>> env = WorldEnvironment(size=8, rocks=[(2.0, 0.0, 0.0, 1.5)])
>>> env.probe(np.array([[0.0, 5.0, 0.0], [0.0, -3.0, 0.0], [2.0, 0.5, 0.0]]))[:, 0]
array([0., 3., 2.])
"""

from __future__ import annotations

from collections.abc import Sequence

import numpy as np

from ..errors import SylvaError
from ..lsystem.environment import Communication
from .blocks import Block
from .terrain import WorldConfig, columns, voxels

__all__ = ["WorldEnvironment"]


class WorldEnvironment:
    """A square of the voxel world that answers ``?E(d, block, height, biome)``.

    Parameters
    ----------
    config : WorldConfig, optional
        The world (default ``WorldConfig(seed=1)``).
    x, z : int
        The world column the plant stands on (the square is centred there).
    size : int
        Columns per side of the square (4..512).
    scale : float
        Turtle units per block.
    rocks : sequence of (x, y, z, r)
        Spheres of stone in the plant's coordinates (the plant's foot is ``(0, 0, 0)``,
        ``y`` up), stamped into the voxels.
    """

    name = "world"

    def __init__(self, config: WorldConfig | None = None, *, x: int = 0, z: int = 0,
                 size: int = 32, scale: float = 1.0,
                 rocks: Sequence[Sequence[float]] = ()) -> None:  # fmt: skip
        size = int(size)
        if not 4 <= size <= 512:
            raise SylvaError(f"world environment: size must be 4..512 columns, got {size}")
        if not (np.isfinite(scale) and scale > 0):
            raise SylvaError(f"world environment: scale must be > 0, got {scale}")
        self.config = config or WorldConfig(seed=1)
        self.scale = float(scale)
        self.x0, self.z0 = int(x) - size // 2, int(z) - size // 2
        fields = columns(self.config, self.x0, self.z0, size, size)
        self.height = fields.height  # int32[w, d], the topmost solid layer
        self.biome = fields.biome
        self.blocks = voxels(self.config, fields)  # uint8[w, H, d]
        c = size // 2
        # the plant's foot: on top of the surface block of the centre column
        self.foot = np.array([self.x0 + c + 0.5, float(self.height[c, c] + 1),
                              self.z0 + c + 0.5])  # fmt: skip
        for rock in rocks:
            self.add_rock(*rock)

    @classmethod
    def from_options(cls, opts: dict) -> WorldEnvironment:
        """From the options of ``environment = world(…)`` (one rock: ``rock_x rock_y rock_z
        rock_r``, none when ``rock_r`` is 0)."""
        seed = float(opts.get("seed", 1))
        if not seed.is_integer() or seed < 0:
            raise SylvaError(f"world environment: seed must be a whole number >= 0, got {seed}")
        rocks = []
        if float(opts.get("rock_r", 0)) > 0:
            rocks.append(tuple(float(opts[k]) for k in ("rock_x", "rock_y", "rock_z", "rock_r")))
        return cls(WorldConfig(seed=int(seed)), x=int(opts.get("x", 0)), z=int(opts.get("z", 0)),
                   size=int(opts.get("size", 32)), scale=float(opts.get("scale", 1.0)),
                   rocks=rocks)  # fmt: skip

    def to_world(self, points: np.ndarray) -> np.ndarray:
        """Plant coordinates ``float64[m, 3]`` to world (block) coordinates."""
        return self.foot + np.asarray(points, np.float64).reshape(-1, 3) / self.scale

    def add_rock(self, x: float, y: float, z: float, r: float) -> None:
        """Stamp a sphere of stone (plant coordinates and units) into the voxels."""
        w, ny, d = self.blocks.shape
        c = self.to_world(np.array([[x, y, z]]))[0]
        rb = float(r) / self.scale
        ii, jj, kk = np.meshgrid(np.arange(w) + self.x0 + 0.5, np.arange(ny) + 0.5,
                                 np.arange(d) + self.z0 + 0.5, indexing="ij")  # fmt: skip
        inside = (ii - c[0]) ** 2 + (jj - c[1]) ** 2 + (kk - c[2]) ** 2 <= rb * rb
        self.blocks[inside] = np.uint8(Block.STONE)

    def probe(self, points: np.ndarray) -> np.ndarray:
        """``float64[m, 3]``: block, height above the ground (turtle units) and biome at
        ``points`` (plant coordinates).  Past the square's sides the border column
        answers; above the world is air, below it stone."""
        wp = self.to_world(points)
        w, ny, d = self.blocks.shape
        i = np.clip(np.floor(wp[:, 0]).astype(np.int64) - self.x0, 0, w - 1)
        k = np.clip(np.floor(wp[:, 2]).astype(np.int64) - self.z0, 0, d - 1)
        j = np.floor(wp[:, 1]).astype(np.int64)
        block = np.where(j >= ny, Block.AIR, Block.STONE).astype(np.float64)
        inside = (j >= 0) & (j < ny)
        block[inside] = self.blocks[i[inside], j[inside], k[inside]]
        ground = self.height[i, k] + 1.0
        out = np.empty((wp.shape[0], 3))
        out[:, 0] = block
        out[:, 1] = (wp[:, 1] - ground) * self.scale
        out[:, 2] = self.biome[i, k]
        return out

    def __call__(self, comm: Communication) -> np.ndarray:
        if comm.positions is None:
            raise SylvaError("the world environment needs the turtle's positions: derive "
                             "with locate=sylva.plant.turtle_locate(program)")  # fmt: skip
        res = comm.params.copy()
        k = res.shape[1]
        if k == 0:
            return res
        ahead = np.nan_to_num(res[:, 0])
        pts = comm.positions + ahead[:, None] * comm.frames[:, 0]
        out = self.probe(pts)
        n = min(k - 1, 3)
        res[:, 1 : 1 + n] = out[:, :n]
        return res + 0.0

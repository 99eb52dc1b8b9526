"""The block texture atlas, made from :mod:`sylva.texture` patterns.

Every tile of :data:`sylva.world.blocks.TEXTURES` is a seamless square image computed from
procedural textures (granite for stone, fBm for dirt and sand, the grass pattern for grass
tops, bark for trunks, Worley cells for leaves and ice …).  :func:`make_atlas` packs them
into one image with a UV rectangle per tile; :meth:`Atlas.tile` cuts one out, and
:meth:`Atlas.atlas_uvs` maps block-unit UVs of unmerged faces into the atlas.

Greedy-merged quads repeat their texture across several blocks, which one atlas rectangle
cannot do without a custom shader; meshes and glTF files therefore use one material per
tile (with the tile as a repeating texture), and the atlas is the single source of those
tiles.

Examples
--------
>>> a = make_atlas(tile=16, seed=3)
>>> a.image.shape[2], a.tile("stone").shape
(4, (16, 16, 4))
>>> bool(np.array_equal(a.image, make_atlas(tile=16, seed=3).image))
True
"""

from __future__ import annotations

import math
from dataclasses import dataclass
from pathlib import Path

import numpy as np

from .._atomic import save_buffered
from ..geometry.mesh import Material
from ..texture import bark, granite, grass, noise_grid
from .blocks import TEXTURES

__all__ = ["Atlas", "make_atlas", "tile_image", "tile_materials"]


def _rgb(hexcode: str) -> np.ndarray:
    h = hexcode.lstrip("#")
    return np.array([int(h[i : i + 2], 16) / 255.0 for i in (0, 2, 4)])


def _shade(v: np.ndarray, dark: str, light: str) -> np.ndarray:
    v = np.clip(np.asarray(v, np.float64), 0.0, 1.0)[..., None]
    return (1.0 - v) * _rgb(dark) + v * _rgb(light)


def _n(size, scale, seed, octaves=3, kind="improved"):
    v = noise_grid((size, size), kind=kind, scale=scale, octaves=octaves, seed=seed,
                   tileable=True, dtype=np.float64)  # fmt: skip
    return np.clip(0.5 + v, 0.0, 1.0)


def _cells(size, scale, seed, output="f1"):
    return noise_grid((size, size), kind="worley", scale=scale, output=output, seed=seed,
                      tileable=True, dtype=np.float64)  # fmt: skip


def _side(size, seed, top: str, top_light: str, depth: float = 0.28) -> np.ndarray:
    """Dirt with a ragged strip of the top colour along the upper edge (v up: row 0)."""
    img = _shade(_n(size, 4, seed + 1, 4), "#5a3d24", "#8a6240")
    edge = depth + 0.12 * _n(size, 3, seed + 2, 2)[0]  # per-column strip depth
    rows = (np.arange(size) / size)[:, None]
    strip = rows < edge[None, :]
    img[strip] = _shade(_n(size, 6, seed + 3, 3), top, top_light)[strip]
    return img


def tile_image(name: str, size: int = 32, seed: int = 0) -> np.ndarray:
    """One seamless tile.

    Parameters
    ----------
    name : str
        A name of :data:`~sylva.world.blocks.TEXTURES`.
    size : int
        Pixels per side (≥ 4).
    seed : int

    Returns
    -------
    uint8[size, size, 4]
        sRGB with alpha (only ``grass_tuft`` has transparent pixels); row 0 is the top.
    """
    if name not in TEXTURES:
        raise KeyError(f"unknown block texture {name!r}; expected one of {TEXTURES}")
    if size < 4:
        raise ValueError(f"tile size must be >= 4, got {size}")
    s = int(seed) * 97 + TEXTURES.index(name) * 13 + 1
    alpha = np.ones((size, size))
    if name == "stone":
        img = _shade(granite((size, size), scale=6, seed=s, tileable=True), "#5e5e62", "#a9a9ad")
    elif name == "dirt":
        img = _shade(_n(size, 4, s, 4), "#5a3d24", "#8a6240")
    elif name in ("grass_top", "tundra_top", "jungle_top"):
        col = {"grass_top": ("#3f7a26", "#79b94a"), "tundra_top": ("#62775d", "#97a58d"),
               "jungle_top": ("#1f6a1c", "#4fa236")}[name]  # fmt: skip
        # 0.4 shader units a tile (16 blade cells), the contrast of the blocks before
        g = grass((size, size), scale=0.4, seed=s, tileable=True, dtype=np.float64)
        img = _shade(0.5 + 1.4 * (g - 0.5), *col)
    elif name in ("grass_side", "tundra_side", "jungle_side"):
        col = {"grass_side": ("#3f7a26", "#6ea943"), "tundra_side": ("#62775d", "#8d9c86"),
               "jungle_side": ("#1f6a1c", "#46962f")}[name]  # fmt: skip
        img = _side(size, s, *col)
    elif name == "sand":
        img = _shade(_n(size, 8, s, 3), "#cdb77a", "#efdfa5")
    elif name == "greysand":
        img = _shade(_n(size, 8, s, 3), "#8e8a80", "#bdb8ab")
    elif name == "gravel_dirt":
        g = _cells(size, 6, s, "f2-f1")
        img = _shade(np.clip(g * 3.0, 0, 1) * 0.6 + 0.4 * _n(size, 4, s + 1), "#4d3a28", "#9c8f7b")
    elif name == "gravel":
        g = _cells(size, 7, s, "f2-f1")
        img = _shade(np.clip(g * 3.0, 0, 1), "#57534e", "#9d978f")
    elif name == "cotton_red":
        img = _shade(_n(size, 5, s, 4), "#a3542e", "#d4864a")
    elif name == "ice":
        c = _cells(size, 3, s, "f2-f1")
        img = _shade(0.6 + 0.4 * np.clip(c * 4.0, 0, 1), "#9cc4e8", "#e8f4ff")
    elif name == "snow":
        img = _shade(_n(size, 6, s, 2), "#dfe6ee", "#ffffff")
    elif name == "water":
        img = _shade(_n(size, 3, s, 3, kind="simplex"), "#1f4f9a", "#3f7cc6")
    elif name in ("bark", "bark_white", "bark_orange"):
        v = bark((size, size), scale=4, seed=s, tileable=True)
        col = {"bark": ("#3b2716", "#7a5534"), "bark_white": ("#3a3a36", "#e9e6dc"),
               "bark_orange": ("#6d3712", "#c97a3a")}[name]  # fmt: skip
        if name == "bark_white":
            v = np.clip(0.35 + 0.8 * v, 0.0, 1.0) ** 3
        img = _shade(v, *col)
    elif name.startswith("leaves"):
        col = {"leaves": ("#1d4a17", "#4d8d2c"), "leaves_birch": ("#4a7a22", "#97c24a"),
               "leaves_jungle": ("#0f4a14", "#2f8a2a"), "leaves_orange": ("#8a4a12", "#e0962f"),
               "leaves_shrub": ("#385a1f", "#6f9a3a")}[name]  # fmt: skip
        f1 = _cells(size, 5, s, "f1")
        img = _shade(np.clip(1.0 - f1 * 1.3, 0, 1) * 0.7 + 0.3 * _n(size, 8, s + 1), *col)
    elif name == "cactus":
        x = np.arange(size) / size
        ribs = 0.5 + 0.5 * np.cos(2 * math.pi * 4 * x)[None, :]
        img = _shade(0.6 * ribs + 0.4 * _n(size, 6, s), "#1d5a26", "#5fa24a")
    else:  # grass_tuft: blades on a transparent background
        rng = np.random.default_rng(s)
        rows = np.arange(size)[:, None] / size
        cols = np.arange(size)[None, :] / size
        alpha = np.zeros((size, size))
        for _ in range(9):
            x0 = rng.uniform(0.1, 0.9)
            lean = rng.uniform(-0.25, 0.25)
            top = rng.uniform(0.05, 0.45)
            t = np.clip((1.0 - rows - 0.0) / max(1.0 - top, 1e-6), 0.0, 1.0)  # 0 bottom, 1 top
            center = x0 + lean * t**2
            width = 0.06 * (1.0 - t) + 0.01
            alpha = np.maximum(alpha, ((np.abs(cols - center) < width) & (rows >= top)) * 1.0)
        img = _shade(0.3 + 0.7 * (1.0 - rows) * np.ones((1, size)), "#2f6a1f", "#8cc850")
    rgba = np.concatenate([img, alpha[..., None]], axis=-1)
    return np.clip(np.rint(rgba * 255.0), 0, 255).astype(np.uint8)


@dataclass
class Atlas:
    """Tiles packed in a grid.

    Attributes
    ----------
    image : uint8[H, W, 4]
        The atlas (row 0 at the top).
    tile_size : int
    names : tuple of str
        Tile order (:data:`~sylva.world.blocks.TEXTURES`).
    columns : int
        Tiles per atlas row.
    """

    image: np.ndarray
    tile_size: int
    names: tuple[str, ...]
    columns: int

    def index(self, name: str) -> int:
        return self.names.index(name)

    def rect(self, name: str) -> tuple[float, float, float, float]:
        """UV rectangle ``(u0, v0, u1, v1)`` of a tile (v = 0 at the bottom of the image)."""
        i = self.index(name)
        h, w = self.image.shape[:2]
        r, c = divmod(i, self.columns)
        t = self.tile_size
        return (c * t / w, 1.0 - (r + 1) * t / h, (c + 1) * t / w, 1.0 - r * t / h)

    def tile(self, name: str) -> np.ndarray:
        """The pixels of one tile: uint8[t, t, 4]."""
        r, c = divmod(self.index(name), self.columns)
        t = self.tile_size
        return self.image[r * t : (r + 1) * t, c * t : (c + 1) * t]

    def atlas_uvs(self, uvs: np.ndarray, texture_ids: np.ndarray) -> np.ndarray:
        """Block-unit UVs in [0, 1] of unmerged faces mapped into their tiles.

        Parameters
        ----------
        uvs : float[n, 2]
        texture_ids : int[n]
            Tile index of each vertex.

        Returns
        -------
        float32[n, 2]
        """
        h, w = self.image.shape[:2]
        t = self.tile_size
        r, c = np.divmod(np.asarray(texture_ids, np.int64), self.columns)
        inset = 0.5 / t  # keep bilinear filtering inside the tile
        uv = np.clip(np.asarray(uvs, np.float64), inset, 1.0 - inset)
        u = (c + uv[:, 0]) * t / w
        v = 1.0 - (r + 1.0 - uv[:, 1]) * t / h
        return np.stack([u, v], 1).astype(np.float32)

    def save(self, path) -> Path:
        """Write the atlas as PNG."""
        from PIL import Image

        path = Path(path)
        image = Image.fromarray(self.image, "RGBA")
        save_buffered(path, lambda fh: image.save(fh, format="PNG"))
        return path

    def save_tiles(self, folder) -> dict[str, Path]:
        """Write every tile as ``<folder>/<name>.png``; returns the paths by name."""
        from PIL import Image

        folder = Path(folder)
        folder.mkdir(parents=True, exist_ok=True)
        out = {}
        for name in self.names:
            p = folder / f"{name}.png"
            image = Image.fromarray(np.ascontiguousarray(self.tile(name)), "RGBA")
            save_buffered(p, lambda fh, image=image: image.save(fh, format="PNG"))
            out[name] = p
        return out


def make_atlas(tile: int = 32, seed: int = 0, names=TEXTURES) -> Atlas:
    """Render every tile and pack them into one image.

    Parameters
    ----------
    tile : int
        Pixels per tile side.
    seed : int
        Seed of the procedural textures.
    names : sequence of str
        Tiles to include (default: all of :data:`~sylva.world.blocks.TEXTURES`).

    Returns
    -------
    Atlas
    """
    names = tuple(names)
    cols = math.ceil(math.sqrt(len(names)))
    rows = math.ceil(len(names) / cols)
    img = np.zeros((rows * tile, cols * tile, 4), np.uint8)
    for i, name in enumerate(names):
        r, c = divmod(i, cols)
        img[r * tile : (r + 1) * tile, c * tile : (c + 1) * tile] = tile_image(name, tile, seed)
    return Atlas(img, tile, names, cols)


_TRANSLUCENT = {"water"}
_CUTOUT = {"grass_tuft"}


def tile_materials(textures: dict[str, str] | None = None) -> list[Material]:
    """One material per tile, in :data:`~sylva.world.blocks.TEXTURES` order.

    Parameters
    ----------
    textures : dict, optional
        Tile name → image path, for renderers that read textures from files (e.g. from
        :meth:`Atlas.save_tiles`); without it the materials carry only a base colour.

    Returns
    -------
    list of Material
        Water is translucent (alpha 0.7); the grass tuft is a double-sided cut-out.
    """
    out = []
    for name in TEXTURES:
        tex = None if textures is None else str(textures[name])
        color = (1.0, 1.0, 1.0, 0.75 if name in _TRANSLUCENT else 1.0)
        out.append(Material(
            f"block_{name}", color, roughness=0.35 if name in ("water", "ice") else 0.9,
            texture=tex, double_sided=name in _CUTOUT,
            alpha_cutoff=0.5 if name in _CUTOUT else None,
        ))  # fmt: skip
    return out


def _mean_colors(atlas: Atlas) -> dict[str, tuple[float, float, float]]:
    """Average sRGB colour of each tile (opaque pixels), in [0, 1]."""
    out = {}
    for name in atlas.names:
        t = atlas.tile(name).astype(np.float64) / 255.0
        a = t[..., 3] > 0.5
        out[name] = tuple(float(x) for x in t[a][:, :3].mean(axis=0)) if a.any() else (0, 0, 0)
    return out


"""The contact sheet of ``sylva tree --sheet``: every species at three ages, one scale.

Each species gets a cell of three side views (orthographic, the same metres per pixel in
every tile): a quarter of its ``Age``, half of it and mature (its ``Age``), on a
ground line with a height scale.  The trees are grown at ``quality`` (fewer twigs carrying
the same foliage, :class:`~sylva.tree.Tree`), which keeps the sheet quick.
"""

from __future__ import annotations

import time
from collections.abc import Sequence

import numpy as np
from PIL import Image, ImageDraw

__all__ = ["AGES", "contact_sheet"]

AGES = (0.25, 0.5, 1.0)
"""The three ages of the sheet, as fractions of each species' ``Age``."""


def contact_sheet(species: Sequence[str] | None = None, *, tile=(150, 230), columns: int = 4,
                  height: float | None = None, seed: int = 0, quality: float = 0.5,
                  log=None) -> Image.Image:
    """Render the contact sheet.

    Parameters
    ----------
    species : list of str, optional
        Species names or files (default: every shipped and user species).
    tile : (int, int)
        Pixel size of one view.
    columns : int
        Species per row.
    height : float, optional
        World height (m) of a tile; default the tallest mature tree plus 8 %.
    seed : int
    quality : float
        Twig density (0, 1] (see :class:`~sylva.tree.Tree`).
    log : callable, optional
        Called with one line per species (name and seconds).
    """
    from ..geometry.mesh import Scene
    from ..render import Camera, render
    from ..tree import Tree, species_names

    names = list(species) if species is not None else species_names()
    tw, th = tile
    views: list[list] = []
    tallest = 1.0
    for name in names:
        t0 = time.perf_counter()
        tree = Tree(name, seed=seed, quality=quality)
        row = []
        for frac in AGES:
            age = max(frac * tree.default_age, 0.5)
            tree.grow(age)
            mesh = tree.mesh().mesh
            top = float(mesh.bounds()[1, 1]) if mesh.n_vertices else 0.0
            tallest = max(tallest, top)
            row.append((age, mesh))
        views.append([tree.name, row])
        if log is not None:
            log(f"{name:20s} grown in {time.perf_counter() - t0:5.2f} s")
    world_h = height if height is not None else 1.08 * tallest
    cam = Camera(mode="orthographic", target=np.array([0.0, 0.42 * world_h, 0.0]), yaw=0.0,
                 pitch=0.0, distance=4.0 * world_h, height=world_h)
    cap = 34
    cw, ch = 3 * tw, th + cap
    rows = (len(views) + columns - 1) // columns
    sheet = Image.new("RGB", (columns * cw, rows * ch), "white")
    draw = ImageDraw.Draw(sheet)
    for i, (title, row) in enumerate(views):
        x0, y0 = (i % columns) * cw, (i // columns) * ch
        for j, (age, mesh) in enumerate(row):
            img = render(Scene([mesh]), size=(tw, th), camera=cam, ground=False,
                         shadows=False)
            sheet.paste(img, (x0 + j * tw, y0))
            draw.text((x0 + j * tw + 4, y0 + th + 2), f"{age:g} y", fill=(90, 90, 90))
        draw.text((x0 + 4, y0 + th + 16), title, fill=(0, 0, 0))
        draw.line([(x0, y0 + int(0.92 * th)), (x0 + cw, y0 + int(0.92 * th))],
                  fill=(150, 120, 90))
        draw.rectangle([x0, y0, x0 + cw - 1, y0 + ch - 1], outline=(220, 220, 220))
    # a scale bar: 5 m
    px = 5.0 / world_h * th
    draw.line([(6, 8), (6, 8 + px)], fill=(200, 0, 0), width=3)
    draw.text((10, 8), "5 m", fill=(200, 0, 0))
    return sheet

"""Which predefined surface each leaf of a word draws (cpfg's ``~X``).

The walk records ``~X`` as a leaf whose module is the name ``X`` after the ``~``
(:attr:`~sylva.geometry.records.Geometry.leaf_module`); :func:`assign` gives each leaf the
template of the surface that name stands for: the view file's ``surface: X file.s scale
[s t]`` (the setting ``surfaces``), else sylva's own :data:`~sylva.geometry.surfaces.BUILTIN`
(``~"leaf"``, ``~"petal"``), else the default leaf (``~`` alone, or a name no surface has).
"""

from __future__ import annotations

import os
from collections.abc import Mapping
from functools import lru_cache

import numpy as np

from ..geometry.records import Geometry
from ..geometry.surfaces import BUILTIN, Surface, load_surface
from ..lsystem.lstring import ModuleString

__all__ = ["assign", "table"]


def _err(message: str):
    from .interpreter import TurtleSettingsError  # the interpreter imports this module

    return TurtleSettingsError(message)


@lru_cache(maxsize=64)
def _file(path: str, mtime: float) -> Surface:
    return load_surface(path)


_TEMPLATES: dict[tuple, tuple] = {}


def _template(key, surface: Surface, scale: float, s, t):
    """The template of ``surface`` (kept by ``key``: a built-in's name, a file and its time)."""
    k = (key, scale, s, t)
    hit = _TEMPLATES.get(k)
    if hit is None:
        hit = surface.template(s, t, scale)
        for a in hit:
            a.setflags(write=False)
        if len(_TEMPLATES) > 256:
            _TEMPLATES.clear()
        _TEMPLATES[k] = hit
    return hit


def _spec(name: str, spec) -> tuple:
    """``(key, Surface, scale, s, t)`` of one entry of the setting ``surfaces``."""
    if isinstance(spec, (Surface, str, os.PathLike)):
        spec = (spec,)
    try:
        src, *rest = spec
        scale = float(rest[0]) if rest else 1.0
        s = int(rest[1]) if len(rest) > 1 and rest[1] else None
        t = int(rest[2]) if len(rest) > 2 and rest[2] else None
    except (TypeError, ValueError):
        raise _err(f"surface {name!r}: expected a Surface or a .s path, optionally with a "
                   f"scale and the polygons along rows and columns, got {spec!r}") from None
    if isinstance(src, Surface):
        return ("obj", id(src)), src, scale, s, t
    path = os.fspath(src)
    try:
        mtime = os.stat(path).st_mtime
    except OSError as e:
        raise _err(f"surface {name!r}: cannot read the surface file {path} "
                   f"({e.strerror or e})") from None
    return ("file", path, mtime), _file(path, mtime), scale, s, t


def table(surfaces: Mapping | None) -> dict[str, tuple]:
    """Surface name -> ``(name, vertices, uvs, tris)``: the built-in surfaces, then those of
    ``surfaces`` (which win)."""
    out = {}
    specs = {name: (("builtin", name), surf, 1.0, None, None) for name, surf in BUILTIN.items()}
    if surfaces:
        if not isinstance(surfaces, Mapping):
            raise _err(f"setting 'surfaces' must map names to surfaces, got {surfaces!r}")
        specs.update({str(k): _spec(str(k), v) for k, v in surfaces.items()})
    for name, (key, surf, scale, s, t) in specs.items():
        if key[0] == "obj":
            tpl = surf.template(s, t, scale)
        else:
            tpl = _template(key, surf, scale, s, t)
        out[name] = (name, *tpl)
    return out


def assign(geo: Geometry, word: ModuleString, surfaces: Mapping | None) -> None:
    """Set ``geo.leaf_surface`` and ``geo.surfaces`` from the names of the leaves' modules."""
    _stretch(geo, word)
    names = word.alphabet.names
    ids = word.ids[geo.leaf_module]
    used = np.unique(ids)
    if not any(names[i] in BUILTIN or (surfaces and names[i] in surfaces)
               for i in used.tolist()):  # fmt: skip
        return
    tab = table(surfaces)
    chosen: list[tuple] = []
    index = np.full(len(names), -1, np.int32)
    for i in used.tolist():
        entry = tab.get(names[i])
        if entry is not None:
            index[i] = len(chosen)
            chosen.append(entry)
    geo.leaf_surface = index[ids]
    geo.surfaces = tuple(chosen)


def _stretch(geo: Geometry, word: ModuleString) -> None:
    """``geo.leaf_stretch`` for the leaves drawn by ``~X(sx, sy, sz)`` (three parameters:
    cpfg scales the surface's x, y, z by them; the walk took ``sx`` as the size)."""
    if not word.has_params:
        return
    m = geo.leaf_module
    off = word.offsets
    three = (off[m + 1] - off[m]) >= 3
    if not three.any():
        return
    st = np.ones((m.size, 3), np.float32)
    a = off[m[three]]
    sx = word.values[a]
    safe = np.where(sx == 0.0, 1.0, sx)
    st[three, 1] = word.values[a + 1] / safe
    st[three, 2] = word.values[a + 2] / safe
    geo.leaf_stretch = st

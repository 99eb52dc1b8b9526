"""Which predefined surface each leaf of a word draws (cpfg's ``~X``).

The walk records ``~X`` as a leaf whose module is the name ``X`` after the ``~``
(:attr:`~sylva.geometry.records.Geometry.leaf_module`); :func:`assign` gives each leaf the
template of the surface that name stands for: the view file's ``surface: X file.s scale
[s t]`` (the setting ``surfaces``), else sylva's own :data:`~sylva.geometry.surfaces.BUILTIN`
(``~"leaf"``, ``~"petal"``), else the default leaf (``~`` alone, or a name no surface has).

A leaf is textured (:func:`texture`) by the texture number its surface line gives (``surface:
X file.s scale [s t] n``: ``n > 0`` fixed, ``0`` none), else by the turtle's current ``@Tx(n)``
(kept through ``[`` ``]`` as cpfg's turtle keeps it); ``n`` counts the view file's
``texture:`` lines from 1 (the setting ``textures``).
"""

from __future__ import annotations

import os
from collections.abc import Mapping
from functools import lru_cache

import numpy as np

from ..geometry.records import Geometry
from ..geometry.surfaces import BUILTIN, Surface, load_surface
from ..lsystem.lstring import ModuleString

__all__ = ["assign", "table", "texture", "texture_segments", "turtle_textures"]


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


def assign(geo: Geometry, word: ModuleString, surfaces: Mapping | None,
           textures=None) -> None:  # fmt: skip
    """Set ``geo.leaf_surface`` and ``geo.surfaces`` from the names of the leaves' modules,
    and the textures of textured surfaces (:func:`texture`)."""
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
    if textures:
        texture(geo, word, surfaces, textures)


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


def turtle_textures(word: ModuleString, positions: np.ndarray) -> np.ndarray:
    """``int32[k]``: the turtle's texture (cpfg's ``@Tx(n)``; 0: none) at each of the module
    ``positions`` of ``word``, as the last ``@Tx`` before it on its path from the root sets
    it (a branch inherits its parent's and gives it back at ``]``)."""
    out = np.zeros(positions.shape[0], np.int32)
    alpha = word.alphabet
    at, tee, x = alpha.get("@"), alpha.get("T"), alpha.get("x")
    ids = word.ids
    n = ids.shape[0]
    if min(at, tee, x) < 0 or n < 3 or not word.values.size:
        return out
    marks = np.flatnonzero((ids[:-2] == at) & (ids[1:-1] == tee) & (ids[2:] == x))
    if marks.size == 0:
        return out
    off = word.offsets
    value = {int(p): (int(word.values[off[p + 2]]) if off[p + 3] > off[p + 2] else 0)
             for p in marks.tolist()}  # fmt: skip
    where = {int(p): k for k, p in enumerate(positions.tolist())}
    events = np.union1d(np.flatnonzero((ids == 0) | (ids == 1)), marks)
    events = np.union1d(events, positions)
    cur, stack = 0, []
    for p in events.tolist():
        if p in value:
            cur = value[p]
        elif ids[p] == 0:
            stack.append(cur)
        elif ids[p] == 1 and stack:
            cur = stack.pop()
        if p in where:
            out[where[p]] = cur
    return out


def _image(path: str, mtime: float):
    """The RGBA pixels of a texture image, bottom row first (the mesh's ``v = 0``)."""
    hit = _IMAGES.get((path, mtime))
    if hit is None:
        from PIL import Image

        try:
            with Image.open(path) as im:
                hit = np.ascontiguousarray(np.asarray(im.convert("RGBA"))[::-1])
        except Exception as e:  # noqa: BLE001 - Pillow raises many kinds for a bad image
            raise _err(f"texture {path}: cannot read the image ({e})") from None
        if len(_IMAGES) > 16:
            _IMAGES.clear()
        _IMAGES[(path, mtime)] = hit
    return hit


_IMAGES: dict[tuple, np.ndarray] = {}


def _textured(mats: list, m: int, t: int, tex: dict, cache: dict) -> int:
    """The index in ``mats`` of material ``m`` carrying texture ``t`` (added once)."""
    import dataclasses

    from ..geometry.mesh import with_images

    if (m, t) not in cache:
        path = str(tex["file"])
        try:
            mtime = os.stat(path).st_mtime
        except OSError as e:
            raise _err(f"texture {t}: cannot read {path} ({e.strerror or e})") from None
        base = mats[m]
        color = base.color if tex.get("mode") != "decal" else (1.0, 1.0, 1.0, 1.0)
        mat = dataclasses.replace(base, name=f"{base.name}_texture{t}", color=color,
                                  texture=path)  # fmt: skip
        cache[(m, t)] = len(mats)
        mats.append(with_images(mat, _image(path, mtime), alpha_cutoff=0.5))
    return cache[(m, t)]


def texture_segments(geo: Geometry, word: ModuleString, textures) -> None:
    """The segments drawn under ``@Tx(n)`` (cylinders and generalised cylinders; the cpfg
    manual §6.7.4) take a copy of their material that carries texture ``n``'s image, laid
    over the tubes' coordinates: ``u`` around, ``v`` along the length in circumferences,
    as cpfg's ``length / (π · width)`` (its ``R:`` ratio and the image's aspect are not
    applied: exact for square images at ``R: 1``)."""
    if not geo.n_segments or not textures:
        return
    tid = turtle_textures(word, geo.seg_module)
    ok = (tid >= 1) & (tid <= len(textures))
    if not ok.any():
        return
    mats, cache = list(geo.materials), {}
    sm = geo.seg_material.copy()
    for i in np.flatnonzero(ok).tolist():
        sm[i] = _textured(mats, int(sm[i]), int(tid[i]), textures[int(tid[i]) - 1], cache)
    geo.seg_material, geo.materials = sm, mats


def texture(geo: Geometry, word: ModuleString, surfaces: Mapping | None, textures) -> None:
    """Give the leaves on textured surfaces cpfg's texture coordinates (per patch, or per
    surface with ``S:``; :meth:`~sylva.geometry.surfaces.Surface.texture_uvs`) and a copy of
    their material that carries the image: ``texture`` its path (the renderer modulates the
    colour by it and drops the pixels whose alpha is under 0.5), ``images`` its pixels (the
    formats that embed images, glTF)."""
    if not geo.surfaces or geo.leaf_surface is None:
        return
    names = [entry[0] for entry in geo.surfaces]
    fixed = np.full(len(names), -1, np.int32)  # the surface line's texture, -1: the turtle's
    for k, name in enumerate(names):
        spec = (surfaces or {}).get(name)
        if isinstance(spec, (tuple, list)) and len(spec) >= 5 and spec[4] is not None:
            fixed[k] = int(spec[4])
    which = geo.leaf_surface
    on = which >= 0
    tid = np.zeros(which.shape[0], np.int32)
    tid[on] = fixed[which[on]]
    turtle = tid < 0
    if turtle.any():
        tid[turtle] = turtle_textures(word, geo.leaf_module[turtle])
    ok = on & (tid >= 1) & (tid <= len(textures))
    if not ok.any():
        return
    combos = np.unique(np.stack([which[ok], tid[ok], geo.leaf_material[ok]], 1), axis=0)
    surfs = list(geo.surfaces)
    mats = list(geo.materials)
    new_surface: dict[tuple[int, int], int] = {}
    new_material: dict[tuple[int, int], int] = {}
    for k, t, m in combos.tolist():
        tex = textures[t - 1]
        if (k, t) not in new_surface:
            spec = _spec(names[k], (surfaces or {}).get(names[k], BUILTIN.get(names[k])))
            _, surf, _, s, tt = spec
            name, verts, _, tris = surfs[k]
            uv = surf.texture_uvs(s, tt, bool(tex.get("per_surface")))
            new_surface[(k, t)] = len(surfs)
            surfs.append((f"{name}#texture{t}", verts, uv, tris))
        _textured(mats, m, t, tex, new_material)
    sel = np.flatnonzero(ok)
    keys = zip(which[sel].tolist(), tid[sel].tolist(), geo.leaf_material[sel].tolist(),
               strict=True)  # fmt: skip
    ls, lm = geo.leaf_surface.copy(), geo.leaf_material.copy()
    for i, (k, t, m) in zip(sel.tolist(), keys, strict=True):
        ls[i] = new_surface[(k, t)]
        lm[i] = new_material[(m, t)]
    geo.leaf_surface, geo.leaf_material = ls, lm
    geo.surfaces = tuple(surfs)
    geo.materials = mats

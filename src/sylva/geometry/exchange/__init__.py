"""Mesh export: one module per format, a dict from file extension to writer.

Every writer takes the thing to write (a :class:`~sylva.geometry.mesh.Scene`, a
:class:`~sylva.geometry.mesh.Mesh`, or turtle :class:`~sylva.geometry.records.Geometry`,
which is meshed with :func:`~sylva.geometry.build.build_mesh` defaults) and a path or a
file object (binary for ``glb``, ``ply``, ``stl``, ``usd*``; text for the others).

========  =================================================  ======================
ext       format                                             module
========  =================================================  ======================
glb       binary glTF 2.0 (materials, colours, normals, UV)  :mod:`.gltf`
gltf      glTF 2.0 JSON with an embedded buffer              :mod:`.gltf`
obj       Wavefront OBJ + MTL                                :mod:`.obj`
ply       binary PLY                                         :mod:`.ply`
stl       binary STL                                         :mod:`.stl`
scad      OpenSCAD polyhedra (seed 001)                      :mod:`.scad`
pov       POV-Ray 3.7 scene (seed 002)                       :mod:`.pov`
svg       SVG of 2D systems / flat projections               :mod:`.svg`
usd[ac]   USD, when ``usd-core`` is installed                :mod:`.usd`
========  =================================================  ======================

Examples
--------
>>> import io, numpy as np
>>> from sylva.geometry.mesh import Mesh
>>> m = Mesh(np.array([[0, 0, 0], [1, 0, 0], [0, 1, 0]]), np.array([[0, 1, 2]]))
>>> buf = io.BytesIO()
>>> write(m, buf, format="stl")
>>> sorted(WRITERS)[:4]
['glb', 'gltf', 'obj', 'ply']
"""

from __future__ import annotations

import os
from collections.abc import Callable

from ...errors import SylvaError
from ..records import Geometry
from ._common import PathOrFile, as_scene
from .gltf import write_glb, write_gltf
from .obj import write_obj
from .ply import write_ply
from .pov import write_pov
from .scad import write_scad
from .stl import write_stl
from .svg import write_svg
from .usd import available as usd_available
from .usd import write_usd

__all__ = [
    "BINARY",
    "WRITERS",
    "ExportError",
    "format_of",
    "usd_available",
    "write",
    "write_glb",
    "write_gltf",
    "write_obj",
    "write_ply",
    "write_pov",
    "write_scad",
    "write_stl",
    "write_svg",
    "write_usd",
]


class ExportError(SylvaError, ValueError):
    """An unknown or unusable export format."""


WRITERS: dict[str, Callable[..., None]] = {
    "glb": write_glb,
    "gltf": write_gltf,
    "obj": write_obj,
    "ply": write_ply,
    "pov": write_pov,
    "scad": write_scad,
    "stl": write_stl,
    "svg": write_svg,
    "usd": write_usd,
    "usda": write_usd,
    "usdc": write_usd,
}

BINARY = frozenset({"glb", "ply", "stl", "usd", "usdc"})


def format_of(path: str | os.PathLike) -> str:
    """The format key of a file name (its extension, lower case)."""
    ext = os.path.splitext(os.fspath(path))[1].lower().lstrip(".")
    if ext not in WRITERS:
        raise ExportError(
            f"cannot tell the export format of {os.fspath(path)!r}: expected an extension "
            "among " + ", ".join("." + k for k in sorted(WRITERS))
        )
    return ext


def write(obj, target: PathOrFile, format: str | None = None, **options) -> None:  # noqa: A002
    """Write ``obj`` to ``target`` in ``format`` (default: from the target's extension).

    ``options`` go to the writer (e.g. ``size=`` for SVG, ``scale=`` for OpenSCAD).
    """
    if format is None:
        name = target if isinstance(target, (str, os.PathLike)) else getattr(target, "name", None)
        if not isinstance(name, (str, os.PathLike)):
            raise ExportError("writing to a file object needs format=")
        format = format_of(name)  # noqa: A001
    fmt = format.lower().lstrip(".")
    if fmt not in WRITERS:
        raise ExportError(
            f"unknown export format {format!r}: expected one of {', '.join(sorted(WRITERS))}"
        )
    if fmt.startswith("usd"):
        if not usd_available():
            raise ExportError("USD export needs the usd-core package (pip install usd-core)")
        options.setdefault("suffix", "." + fmt)
    if fmt != "svg" and isinstance(obj, Geometry):
        obj = as_scene(obj)
    WRITERS[fmt](obj, target, **options)

"""Shared plumbing of the writers: opening targets, coercing inputs, grouping by material."""

from __future__ import annotations

import contextlib
import io
import os
from collections.abc import Iterator

import numpy as np

from ..._atomic import atomic_write
from ..mesh import Material, Mesh, Scene
from ..records import Geometry

PathOrFile = str | os.PathLike | io.IOBase


def as_scene(obj) -> Scene:
    """A :class:`Scene` from a Scene, a Mesh, a list of meshes or turtle :class:`Geometry`."""
    if isinstance(obj, Scene):
        return obj
    if isinstance(obj, Mesh):
        return Scene([obj], name=obj.name)
    if isinstance(obj, Geometry):
        from ..build import build_mesh

        return build_mesh(obj)
    if isinstance(obj, (list, tuple)) and all(isinstance(m, Mesh) for m in obj):
        return Scene(obj)
    raise TypeError(f"cannot export a {type(obj).__name__}: expected a Scene, Mesh or Geometry")


@contextlib.contextmanager
def open_target(target: PathOrFile, binary: bool) -> Iterator[io.IOBase]:
    """Yield a writable file for ``target``: a path is written atomically (a temporary file
    beside it, renamed over it only once the writer succeeds; see :mod:`sylva._atomic`), a
    file object is used as is."""
    if isinstance(target, (str, os.PathLike)):
        with atomic_write(target, "wb" if binary else "w") as fh:
            yield fh
    else:
        yield target


def target_path(target: PathOrFile) -> str | None:
    if isinstance(target, (str, os.PathLike)):
        return os.fspath(target)
    name = getattr(target, "name", None)
    return name if isinstance(name, str) else None


def material_groups(mesh: Mesh) -> list[tuple[int, np.ndarray]]:
    """``[(material index, int64 triangle indices)]`` for the materials a mesh uses."""
    ids = mesh.triangle_materials()
    if ids.size == 0:
        return []
    order = np.argsort(ids, kind="stable")
    sids = ids[order]
    cuts = np.flatnonzero(np.diff(sids)) + 1
    starts = np.concatenate([[0], cuts])
    ends = np.concatenate([cuts, [sids.size]])
    return [(int(sids[a]), order[a:b]) for a, b in zip(starts, ends)]


def material_of(mesh: Mesh, index: int) -> Material:
    if 0 <= index < len(mesh.materials):
        return mesh.materials[index]
    return Material(f"material_{index}")


def safe_name(name: str) -> str:
    out = "".join(c if c.isalnum() or c in "_-." else "_" for c in name)
    return out or "unnamed"


def rows(fmt: str, arr: np.ndarray) -> str:
    """Format every row of a 2D array with ``fmt`` (one line each)."""
    arr = np.asarray(arr)
    if arr.shape[0] == 0:
        return ""
    line = fmt + "\n"
    return (line * arr.shape[0]) % tuple(arr.reshape(-1).tolist())

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


# --------------------------------------------------------------------------- colours
def vertex_materials(mesh: Mesh) -> np.ndarray:
    """``int32[n]``: the material index of a triangle that uses each vertex (0 if none).

    sylva's builders never share a vertex between materials, so this is *the* material
    of the vertex."""
    out = np.zeros(mesh.n_vertices, np.int32)
    if mesh.n_triangles:
        ids = mesh.triangle_materials()
        for k in range(3):
            out[mesh.indices[:, k]] = ids
    return out


def material_colors(mesh: Mesh) -> np.ndarray:
    """``float32[len(materials) + 1, 4]``: the material colours (a grey default last)."""
    table = [material_of(mesh, i).color for i in range(len(mesh.materials))]
    return np.array([*table, Material("default").color], np.float32).reshape(-1, 4)


def shaded_colors(mesh: Mesh) -> np.ndarray:
    """``float32[n, 4]``: the colour every vertex is drawn with, clamped to [0, 1].

    A mesh's vertex colours are a tint that multiplies the material colour (as glTF's
    ``COLOR_0`` multiplies ``baseColorFactor``, and as the renderer draws it); formats that
    carry one colour per vertex or per face (PLY, POV-Ray, USD ``displayColor``, OBJ,
    OpenSCAD) write this product.  This is the one place that computes it."""
    mids = vertex_materials(mesh)
    mids = np.where(mids < len(mesh.materials), mids, len(mesh.materials))
    col = material_colors(mesh)[mids]
    if mesh.colors is not None:
        col = col * mesh.colors
    return np.clip(col, 0.0, 1.0).astype(np.float32)


def tint_scales(meshes) -> dict[str, float]:
    """Per material name, the factor ``k >= 1`` that glTF writers fold into
    ``baseColorFactor`` so that the vertex tints, divided by it, fit ``COLOR_0``'s [0, 1]
    (the validator's ``ACCESSOR_NON_CLAMPED``): ``base·k · tint/k = base·tint`` exactly
    while ``base·k <= 1``; beyond that, the colour clamps as it would on screen."""
    out: dict[str, float] = {}
    for mesh in meshes:
        if mesh.colors is None or mesh.n_triangles == 0:
            continue
        mids = vertex_materials(mesh)
        used = np.zeros(mesh.n_vertices, bool)
        used[mesh.indices.reshape(-1)] = True
        peak = np.zeros(len(mesh.materials) + 1)
        np.maximum.at(peak, np.minimum(mids[used], len(mesh.materials)),
                      mesh.colors[used, :3].max(axis=1))  # fmt: skip
        for i, mat in enumerate(mesh.materials):
            top = float(max(mat.color[:3]))
            k = min(float(peak[i]), 1.0 / top if top > 0 else 1.0)
            out[mat.name] = max(out.get(mat.name, 1.0), k, 1.0)
    return out


def gltf_color0(mesh: Mesh, scales: dict[str, float]) -> np.ndarray:
    """``float32[n, 4]`` ``COLOR_0`` of ``mesh``: its tint divided by its material's
    :func:`tint_scales` factor, clamped to [0, 1]."""
    k = np.array([scales.get(m.name, 1.0) for m in mesh.materials] + [1.0])
    mids = np.minimum(vertex_materials(mesh), len(mesh.materials))
    col = np.array(mesh.colors, np.float64)
    col[:, :3] /= k[mids][:, None]
    return np.clip(col, 0.0, 1.0).astype(np.float32)


def scaled_base(mat: Material, scales: dict[str, float]) -> list[float]:
    """The glTF ``baseColorFactor`` of ``mat``: its colour times its tint scale."""
    k = scales.get(mat.name, 1.0)
    r, g, b, a = (float(x) for x in mat.color)
    return [min(r * k, 1.0), min(g * k, 1.0), min(b * k, 1.0), a]


# --------------------------------------------------------------------------- up axis
UP_AXES = ("y", "z")


def check_up(up: str) -> str:
    """``up`` lower-cased, or a SylvaError naming the option."""
    from ...errors import SylvaError

    u = str(up).lower()
    if u not in UP_AXES:
        raise SylvaError(f"up: expected 'y' or 'z', got {up!r}")
    return u


def to_up(arr: np.ndarray, up: str) -> np.ndarray:
    """Points or normals of sylva's Y-up frame in the ``up`` frame: unchanged for ``"y"``;
    for ``"z"`` the proper rotation ``(x, y, z) -> (x, -z, y)`` (right-handed, +Z up,
    sylva's -Z, the view direction, becoming +Y)."""
    if check_up(up) == "y":
        return arr
    a = np.asarray(arr)
    return np.stack([a[:, 0], -a[:, 2], a[:, 1]], axis=1).astype(a.dtype, copy=False)


def oriented(mesh: Mesh, up: str) -> Mesh:
    """``mesh`` with its points and normals in the ``up`` frame (the same mesh for Y)."""
    if check_up(up) == "y":
        return mesh
    return Mesh(to_up(mesh.vertices, up), mesh.indices, normals=to_up(mesh.normals, up),
                uvs=mesh.uvs, colors=mesh.colors, material_ids=mesh.material_ids,
                materials=mesh.materials, name=mesh.name,
                attributes=mesh.attributes)  # fmt: skip


def oriented_scene(scene: Scene, up: str) -> Scene:
    """``scene`` with every mesh :func:`oriented`."""
    if check_up(up) == "y":
        return scene
    return Scene([oriented(m, up) for m in scene.meshes], name=scene.name)

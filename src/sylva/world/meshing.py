"""The visible skin of voxels as greedy-merged quads, and quads as triangle meshes.

Only faces between an opaque block and a non-opaque one (air or water), and water faces
against air, become geometry.  Coplanar faces with the same texture merge into rectangles
(greedy meshing), so a flat meadow of a chunk is one quad.  A chunk is meshed from its
voxels plus a one-column margin of its neighbours, which are generated from the same pure
terrain function: each face between two chunks is emitted once, by the chunk that owns
its solid block, and the faces of neighbouring chunks meet without gaps or overlaps.

UVs are in block units (a merged quad of 5 × 3 faces spans u ∈ [0, 5], v ∈ [0, 3]) with
``v`` up on side faces, so the texture of a material repeats once per block.

Examples
--------
>>> import numpy as np
>>> vox = np.zeros((3, 4, 3), np.uint8); vox[1, 0, 1] = 2   # one stone block
>>> q = skin_quads(vox, lo=(1, 0, 1), hi=(2, 4, 2))
>>> len(q)                                                   # no face toward y < 0
5
>>> m = quads_to_mesh(q)
>>> m.n_triangles, m.bounds().tolist()
(10, [[1.0, 0.0, 1.0], [2.0, 1.0, 2.0]])
"""

from __future__ import annotations

import numpy as np

from .. import _jit
from ..geometry.mesh import Material, Mesh
from .blocks import FACE_TEXTURES, OPAQUE, TEXTURES

# compiled whatever the work: greedy meshing visits every voxel six times, too slow for Python
K = _jit.lazy("sylva.world._kernels")

__all__ = ["QUAD_FIELDS", "skin_quads", "quad_area", "quads_to_mesh"]

QUAD_FIELDS = ("direction", "layer", "b0", "c0", "b_size", "c_size", "texture")
"""Columns of a quad array: direction (0 +X, 1 −X, 2 +Y, 3 −Y, 4 +Z, 5 −Z), the plane's
coordinate on the normal axis, the corner and size on the two in-face axes, the texture."""

_NORMALS = np.array(
    [[1, 0, 0], [-1, 0, 0], [0, 1, 0], [0, -1, 0], [0, 0, 1], [0, 0, -1]], np.float32
)


def skin_quads(
    vox: np.ndarray,
    lo=None,
    hi=None,
    *,
    greedy: bool = True,
    face_textures: np.ndarray = FACE_TEXTURES,
    opaque: np.ndarray = OPAQUE,
) -> np.ndarray:
    """Visible faces of the voxels in the box ``[lo, hi)``.

    Parameters
    ----------
    vox : uint8[X, Y, Z]
        Block ids; the box must leave one voxel of margin on x and z (the neighbours).
    lo, hi : sequence of 3 int, optional
        The box (default: everything but a one-voxel margin on x and z).
    greedy : bool
        Merge coplanar faces of one texture into rectangles.
    face_textures : int32[n_blocks, 3]
        Texture of each block's top, side and bottom (default :data:`FACE_TEXTURES`).
    opaque : bool[n_blocks]

    Returns
    -------
    int32[q, 7]
        One row per quad, columns :data:`QUAD_FIELDS`.
    """
    vox = np.ascontiguousarray(vox, np.uint8)
    if vox.ndim != 3:
        raise ValueError(f"voxels must be a 3D array [x, y, z], got shape {vox.shape}")
    X, Y, Z = vox.shape
    lo = np.array((1, 0, 1) if lo is None else lo, np.int64)
    if hi is None:
        # layers above the highest non-air voxel hold no faces: skip them
        filled = np.flatnonzero(vox.reshape(X, Y, Z).any(axis=(0, 2)))
        hi = (X - 1, int(filled[-1]) + 1 if filled.size else 0, Z - 1)
    hi = np.array(hi, np.int64)
    if lo[0] < 1 or lo[2] < 1 or hi[0] > X - 1 or hi[2] > Z - 1 or lo[1] < 0 or hi[1] > Y:
        raise ValueError("the box must leave a margin of one voxel on x and z")
    if np.any(hi < lo):
        raise ValueError(f"empty box {lo.tolist()}..{hi.tolist()}")
    if vox.size and int(vox.max()) >= len(opaque):
        raise ValueError(f"unknown block id {int(vox.max())}")
    return K.greedy_quads(vox, np.ascontiguousarray(face_textures, np.int32),
                          np.ascontiguousarray(opaque, np.bool_), lo, hi, greedy)  # fmt: skip


def quad_area(quads: np.ndarray) -> np.ndarray:
    """Faces covered by each quad (``b_size · c_size``): int64[q]."""
    return quads[:, 4].astype(np.int64) * quads[:, 5]


def quads_to_mesh(
    quads: np.ndarray,
    *,
    offset=(0.0, 0.0, 0.0),
    materials: list[Material] | None = None,
    name: str = "chunk",
) -> Mesh:
    """Two triangles per quad, with normals, block-unit UVs and a material per texture.

    Parameters
    ----------
    quads : int32[q, 7]
        From :func:`skin_quads`.
    offset : sequence of 3 float
        Added to every vertex (the voxel array's origin in the world).
    materials : list of Material, optional
        One per texture id (default: plain materials named after :data:`TEXTURES`).

    Returns
    -------
    Mesh
        ``4q`` vertices, ``2q`` counter-clockwise triangles, ``material_ids`` = texture.
    """
    quads = np.asarray(quads, np.int64).reshape(-1, 7)
    q = quads.shape[0]
    d = quads[:, 0]
    a = d // 2
    b = (a + 1) % 3
    c = (a + 2) % 3
    rows = np.arange(q)
    corner = np.zeros((q, 3), np.float64)
    corner[rows, a] = quads[:, 1]
    corner[rows, b] = quads[:, 2]
    corner[rows, c] = quads[:, 3]
    eb = np.zeros((q, 3))
    ec = np.zeros((q, 3))
    eb[rows, b] = quads[:, 4]
    ec[rows, c] = quads[:, 5]
    v = np.empty((q, 4, 3))
    v[:, 0] = corner
    v[:, 1] = corner + eb
    v[:, 2] = corner + eb + ec
    v[:, 3] = corner + ec
    v += np.asarray(offset, np.float64)
    # uv: side faces keep v up (world y); top and bottom use (x, z)
    sb = quads[:, 4].astype(np.float32)
    sc = quads[:, 5].astype(np.float32)
    uv = np.empty((q, 4, 2), np.float32)
    # in-face coordinates of the four corners
    cb = np.stack([np.zeros(q), sb, sb, np.zeros(q)], 1).astype(np.float32)
    cc = np.stack([np.zeros(q), np.zeros(q), sc, sc], 1).astype(np.float32)
    x_axis = a == 0  # (b, c) = (Y, Z): u = z, v = y
    y_axis = a == 1  # (b, c) = (Z, X): u = x, v = z
    z_axis = a == 2  # (b, c) = (X, Y): u = x, v = y
    uv[x_axis, :, 0] = cc[x_axis]
    uv[x_axis, :, 1] = cb[x_axis]
    uv[y_axis, :, 0] = cc[y_axis]
    uv[y_axis, :, 1] = cb[y_axis]
    uv[z_axis, :, 0] = cb[z_axis]
    uv[z_axis, :, 1] = cc[z_axis]
    base = (np.arange(q, dtype=np.int64) * 4)[:, None]
    pos_tris = np.array([[0, 1, 2], [0, 2, 3]], np.int64)
    neg_tris = np.array([[0, 2, 1], [0, 3, 2]], np.int64)
    tris = np.where((d % 2 == 0)[:, None, None], pos_tris[None], neg_tris[None]) + base[:, :, None]
    normals = np.repeat(_NORMALS[d], 4, axis=0)
    if materials is None:
        materials = [Material(t) for t in TEXTURES]
    return Mesh(
        v.reshape(-1, 3).astype(np.float32),
        tris.reshape(-1, 3).astype(np.uint32),
        normals=normals,
        uvs=uv.reshape(-1, 2),
        material_ids=np.repeat(quads[:, 6], 2).astype(np.int32),
        materials=list(materials),
        name=name,
    )

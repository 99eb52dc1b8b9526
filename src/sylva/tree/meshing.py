"""Tree geometry → a sylva :class:`~sylva.geometry.mesh.Mesh` (bark tubes and leaf blades).

Bark: every :class:`~sylva.tree.stem.Stem` becomes rings stitched into a tube (one vectorised
pass for the whole tree).  Leaves: each is a double-sided pointed blade of 6 vertices and 4
triangles in its frame (``u`` across, main vein at ``u = 0.5``, ``v`` from base to tip, which
is what the renderer's procedural ``leaf`` texture expects), tinted per leaf by the
material's ``variation``.  Besides the mesh, the result keeps for each vertex the skeleton
joint it moves with and, for leaves, the flutter displacement (used by wind and glTF).

Examples
--------
>>> from sylva.tree.model import Tree
>>> tm = Tree("quaking_aspen", seed=1).grow(3.0).mesh()
>>> tm.mesh.n_triangles > 0, len(tm.vertex_joint) == tm.mesh.n_vertices
(True, True)
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from ..geometry.mesh import Mesh
from .geometry_turtle import TreeGeometry
from .materials import MaterialDatabase
from .stem import stems_to_arrays

__all__ = ["TreeMesh", "build_tree_mesh", "leaf_blade"]


@dataclass
class TreeMesh:
    """A tree mesh and what animation needs to move it.

    Attributes
    ----------
    mesh : Mesh
    geometry : TreeGeometry
    vertex_joint : int64[n]
        Joint each vertex is bound to (rigidly).
    vertex_leaf : int64[n]
        Leaf index of leaf vertices, -1 for bark.
    flutter : float32[n, 3]
        Displacement of each vertex at full leaf flutter (zero for bark).
    n_bark_vertices : int
    """

    mesh: Mesh
    geometry: TreeGeometry
    vertex_joint: np.ndarray
    vertex_leaf: np.ndarray
    flutter: np.ndarray
    n_bark_vertices: int


def leaf_blade(width: float = 0.5) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """The unit leaf: vertices float[6, 3] (x across, y along, z normal), uvs float[6, 2],
    triangles int[4, 3] (counter-clockwise seen from +z)."""
    w = width
    v = np.array([[0, 0, 0], [-0.5 * w, 0.3, 0], [0.5 * w, 0.3, 0],
                  [-0.42 * w, 0.68, 0], [0.42 * w, 0.68, 0], [0, 1.0, 0]], np.float64)
    uv = np.column_stack([0.5 + v[:, 0] / max(w, 1e-9) * 0.98, v[:, 1]])
    tri = np.array([[0, 2, 1], [1, 2, 4], [1, 4, 3], [3, 4, 5]])
    return v, uv, tri


def build_tree_mesh(geo: TreeGeometry, materials: MaterialDatabase | None = None, *,
                    seed: int = 0, leaves: bool = True, flutter: float = 0.25) -> TreeMesh:
    """Mesh a :class:`TreeGeometry`.

    Parameters
    ----------
    geo : TreeGeometry
    materials : MaterialDatabase
        Bark and leaf materials by name (unknown ``bark.x``/``leaf.x`` fall back to
        ``bark``/``leaf``).
    seed : int
        Seeds the per-leaf tint.
    leaves : bool
        Include the leaves.
    flutter : float
        Leaf-tip displacement at full flutter, relative to the blade length.
    """
    db = materials or MaterialDatabase.default()
    v, n, uv, tri, vj, tri_stem = stems_to_arrays(geo.stems)
    mat_names: list[str] = []
    index: dict[str, int] = {}
    specs: dict = {}

    def mat_id(name: str, fallback: str) -> int:
        if name not in index:
            index[name] = len(mat_names)
            mat_names.append(name)
            specs[name] = db.get(name, fallback)
        return index[name]

    stem_mat = np.array([mat_id(s.material, "bark") for s in geo.stems], np.int64)
    bark_mids = stem_mat[tri_stem] if len(tri_stem) else np.zeros(0, np.int64)
    colors_v = [np.ones((len(v), 4), np.float32)]
    verts, norms, uvs, tris, mids_all = [v], [n], [uv], [tri], [bark_mids]
    joint = [vj]
    leaf_of = [np.full(len(v), -1, np.int64)]
    flut = [np.zeros((len(v), 3), np.float32)]
    nb = len(v)
    k = geo.n_leaves if leaves else 0
    live = np.nonzero(geo.leaf_size > 1e-6)[0] if k else np.zeros(0, np.int64)
    if len(live):
        rng = np.random.default_rng([seed & 0xFFFFFFFF, 99])
        width = geo.leaf_width[live]
        size = geo.leaf_size[live]
        fr = geo.leaf_frame[live]
        pos = geo.leaf_pos[live]
        bv, buv, btri = leaf_blade(1.0)
        local = bv[None, :, :] * np.stack([width * size, size, size], 1)[:, None, :]
        wv = pos[:, None, :] + np.einsum("kij,kvj->kvi", fr, local)
        # normals: the blade's +z, bent a little outward along the blade for softer shading
        nz = fr[:, :, 2]
        wn = np.repeat(nz[:, None, :], 6, axis=1)
        q = len(live)
        base = nb
        idx = (btri[None, :, :] + (base + 6 * np.arange(q))[:, None, None]).reshape(-1, 3)
        names = [geo.leaf_material[i] for i in live]
        mid = np.array([mat_id(nm, "leaf") for nm in names])
        var = np.array([specs[nm].variation for nm in names])
        tint = 1.0 + var[:, None] * rng.uniform(-1.0, 1.0, (q, 3)) * np.array([0.6, 1.0, 0.5])
        tint = np.clip(tint * (1.0 + var[:, None] * rng.uniform(-1, 1, (q, 1))), 0.3, 1.6)
        cols = np.concatenate([np.repeat(tint[:, None, :], 6, axis=1),
                               np.ones((q, 6, 1))], axis=2).reshape(-1, 4)
        verts.append(wv.reshape(-1, 3))
        norms.append(wn.reshape(-1, 3))
        uvs.append(np.tile(buv, (q, 1)))
        tris.append(idx)
        mids_all.append(np.repeat(mid, 4))
        colors_v.append(cols)
        joint.append(np.repeat(geo.leaf_joint[live], 6))
        leaf_of.append(np.repeat(live, 6))
        # flutter: the blade bends about its base, tips move along the normal
        along = np.tile(bv[:, 1], q).reshape(q, 6)
        flut.append((nz[:, None, :] * (along * size[:, None] * flutter)[:, :, None]).reshape(-1, 3))
    mesh = Mesh(
        np.concatenate(verts), np.concatenate(tris), normals=np.concatenate(norms),
        uvs=np.concatenate(uvs), colors=np.concatenate(colors_v),
        material_ids=np.concatenate(mids_all),
        materials=[specs[nm].to_material() for nm in mat_names] or None, name="tree",
    )
    if not mat_names:
        mesh.materials = [db.get("bark").to_material()]
    return TreeMesh(mesh, geo, np.concatenate(joint), np.concatenate(leaf_of),
                    np.concatenate(flut).astype(np.float32), nb)

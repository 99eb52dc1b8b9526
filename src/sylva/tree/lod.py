"""Levels of detail and wind vertex data of Weber–Penn trees.

:func:`tree_lods` meshes a tree again at lower detail, as tree tools do: stems with fewer
sides (8 → 4 → 3, lobes flattened) and fewer rings (every ``k``-th point kept, the tip
too), the thinnest stems dropped by radius with the leaves they carry kept as cards, and
the leaves merged into cards (:func:`sylva.geometry.lod.leaf_cards`).  Budgets and
coverage are those of :mod:`sylva.geometry.lod`.

:func:`tree_wind` is the ``WIND`` vertex data of a :class:`~sylva.tree.meshing.TreeMesh`
(layout in :mod:`sylva.geometry.lod`): the joint's level, one phase per stem (component),
the distance along the skeleton from the root over the largest, and the leaf's position
along its blade.

Examples
--------
>>> from sylva.tree.model import Tree
>>> chain = tree_lods(Tree("quaking_aspen", seed=1).grow(6.0))
>>> r = chain.ratios()
>>> bool(r[1] <= 0.25 and r[2] <= 0.05)
True
"""

from __future__ import annotations

import dataclasses

import numpy as np

from .. import _jit
from ..geometry.lod import (
    BUDGETS,
    COVERAGE,
    LodChain,
    LodError,
    LodLevel,
    _coverage,
    _named,
    check_lods,
    leaf_cards,
    path_length,
    phase_of,
    wind_attribute,
)
from ..geometry.mesh import Mesh, Scene
from ._kernels import blade_wind
from .geometry_turtle import TreeGeometry
from .meshing import TreeMesh, build_tree_mesh
from .stem import Stem

__all__ = ["tree_lods", "tree_wind"]

_BLADE_VERTICES = 200_000
"""Leaf vertices up to which the blades' wind columns are NumPy's while
:func:`~sylva.tree._kernels.blade_wind` is not compiled (as the mesher's leaf fill)."""


def _joint_reach(geo: TreeGeometry) -> np.ndarray:
    pos = geo.joint_matrix[:, :3, 3]
    par = geo.joint_parent
    ln = np.where(par >= 0, np.linalg.norm(pos - pos[np.maximum(par, 0)], axis=1), 0.0)
    reach = path_length(par, ln)
    return reach / max(float(reach.max()) if reach.size else 1.0, 1e-12)


def tree_wind(tm: TreeMesh) -> np.ndarray:
    """``float32[n, 4]`` wind vertex data of a tree mesh (see :mod:`sylva.geometry.lod`)."""
    geo = tm.geometry
    n = tm.mesh.n_vertices
    if geo.n_joints == 0:
        return np.zeros((n, 4), np.float32)
    j = np.clip(tm.vertex_joint, 0, geo.n_joints - 1)
    reach = _joint_reach(geo)
    leaf = tm.vertex_leaf >= 0
    level = geo.joint_level[j].astype(np.float64) + leaf
    phase = np.where(leaf, phase_of(np.maximum(tm.vertex_leaf, 0), 11),
                     phase_of(geo.joint_component[j]))
    flutter = np.zeros(n)
    if leaf.any():
        fl = np.linalg.norm(tm.flutter, axis=1)
        li = tm.vertex_leaf[leaf]
        top = np.zeros(geo.n_leaves)
        fli = fl[leaf]
        if li.size and np.all(li[1:] >= li[:-1]):  # a leaf's vertices together (the mesher's)
            starts = np.flatnonzero(np.concatenate([[True], li[1:] != li[:-1]]))
            top[li[starts]] = np.maximum(np.maximum.reduceat(fli, starts), 0.0)
        else:
            np.maximum.at(top, li, fli)
        flutter[leaf] = fl[leaf] / np.maximum(top[li], 1e-12)
    return wind_attribute(level, phase, reach[j], flutter)


def with_wind(tm: TreeMesh, blades: tuple[np.ndarray, int] | None = None) -> Mesh:
    """The tree mesh with its ``WIND`` attribute set (the same object).  ``blades``: the
    live leaf indices and the vertices per blade when the leaves follow the bark in blocks
    of that many vertices each (the mesher's layout), for :func:`_blade_wind`."""
    wind = tree_wind(tm) if blades is None else _blade_wind(tm, *blades)
    tm.mesh.attributes = {**(tm.mesh.attributes or {}), "WIND": wind}
    return tm.mesh


def _blade_wind(tm: TreeMesh, live: np.ndarray, nv: int) -> np.ndarray:
    """:func:`tree_wind` of a mesh whose leaf ``live[q]`` has the ``nv`` vertices from
    ``n_bark_vertices + q · nv`` on: the same numbers (each column is an element-wise
    function of the vertex's joint or leaf, its flutter over its blade's largest), with the
    per-leaf columns worked out once per leaf rather than once per vertex."""
    geo = tm.geometry
    nb, q = tm.n_bark_vertices, len(live)
    if geo.n_joints == 0 or not q:
        return tree_wind(tm)
    reach = _joint_reach(geo)
    out = np.empty((nb + q * nv, 4), np.float32)
    jb = np.clip(tm.vertex_joint[:nb], 0, geo.n_joints - 1)
    out[:nb, 0] = geo.joint_level[jb]
    out[:nb, 1] = np.mod(phase_of(geo.joint_component[jb]), 1.0)
    out[:nb, 2] = np.clip(reach[jb].astype(np.float32), 0.0, 1.0)
    out[:nb, 3] = 0.0
    jl = np.clip(tm.vertex_joint[nb::nv], 0, geo.n_joints - 1)
    blade = out[nb:].reshape(q, nv, 4)
    level = (geo.joint_level[jl].astype(np.float64) + 1.0).astype(np.float32)
    phase = np.ascontiguousarray(np.mod(phase_of(live, 11), 1.0), np.float64)
    reach_l = np.clip(reach[jl].astype(np.float32), 0.0, 1.0)
    flutter = tm.flutter[nb:].reshape(q, nv, 3)
    if _jit.cold(blade_wind, q * nv, _BLADE_VERTICES):  # the NumPy road (the reference)
        blade[:, :, 0], blade[:, :, 1], blade[:, :, 2] = (
            level[:, None], phase[:, None], reach_l[:, None])
        fl = np.linalg.norm(tm.flutter[nb:], axis=1).reshape(q, nv)
        top = np.maximum(fl.max(axis=1), 0.0).astype(np.float64)
        blade[:, :, 3] = np.clip((fl / np.maximum(top, 1e-12)[:, None]).astype(np.float32),
                                 0.0, 1.0)
    else:  # one compiled pass over the million leaf vertices of a mature tree
        blade_wind(blade, level, phase, reach_l, np.ascontiguousarray(flutter, np.float32))
    return out


def _reduced_stems(geo: TreeGeometry, sides: int, every: int, drop: float) -> list:
    stems = [s for s in geo.stems if s.n_points >= 2]
    if not stems:
        return []
    rmax = np.array([float(s.radii.max()) for s in stems])
    cut = np.quantile(rmax, drop) if drop > 0 else -1.0
    out = []
    for s, r in zip(stems, rmax):
        if r < cut or (drop > 0 and r <= cut and s.level > 0):
            continue
        n = s.n_points
        keep = np.unique(np.concatenate([np.arange(0, n, every), [n - 1]]))
        if keep.size < 2:
            continue
        t = Stem(s.material, sides=min(sides, s.sides), lobes=0, level=s.level)
        t.add_points(s.positions[keep], s.frames()[keep], s.radii[keep], s.joints[keep])
        out.append(t)
    return out


def _tree_level(tree, geo: TreeGeometry, sides: int, every: int, drop: float,
                cards: int) -> Scene:
    red = dataclasses.replace(geo, stems=_reduced_stems(geo, sides, every, drop))
    tm = build_tree_mesh(red, tree.materials, seed=tree.seed, leaves=False)
    bark = with_wind(tm)
    bark.name = "bark"
    meshes = [bark] if bark.n_triangles else []
    live = np.nonzero(geo.leaf_size > 1e-6)[0]
    if live.size and cards:
        fr = geo.leaf_frame[live]  # columns: across, along, normal
        names = [geo.leaf_material[i] for i in live]
        uniq = sorted(set(names))
        mats = [tree.materials.get(nm, "leaf").to_material() for nm in uniq]
        mids = np.array([uniq.index(nm) for nm in names])
        mesh, cl = leaf_cards(geo.leaf_pos[live], fr[:, :, 2], fr[:, :, 1],
                              geo.leaf_size[live] * np.sqrt(np.maximum(geo.leaf_width[live],
                                                                       0.05)),
                              target=cards, material_ids=mids, materials=mats,
                              keys=live)  # fmt: skip
        if mesh.n_triangles:
            reach = _joint_reach(geo)
            j = geo.leaf_joint[live]
            k = int(cl.max()) + 1
            cnt = np.maximum(np.bincount(cl, minlength=k), 1)
            w = mesh.attributes["WIND"]
            w[:, 0] = np.repeat(np.round(np.bincount(cl, geo.joint_level[j] + 1.0, k) / cnt), 4)
            w[:, 2] = np.repeat(np.bincount(cl, reach[j], k) / cnt, 4)
            meshes.append(mesh)
    return Scene(meshes, name=tree.name.replace(" ", "_"))


def tree_lods(tree, *, levels: int = 3, coverage=COVERAGE, budgets=BUDGETS,
              leaves: bool = True) -> LodChain:
    """The mesh levels of detail of a grown :class:`~sylva.tree.model.Tree`.

    Parameters
    ----------
    tree : Tree
    levels : int
        1, 2 or 3 mesh levels (the impostor is added by
        :func:`sylva._impostor.add_impostor`).
    coverage, budgets
        As :func:`sylva.geometry.lod.plant_lods`.
    leaves : bool
        Include the leaves.

    Returns
    -------
    LodChain
        LOD0 is the tree's mesh with its ``WIND`` data.
    """
    n = check_lods(levels, "levels")
    if n > 3:
        raise LodError(f"levels: tree_lods makes 1…3 mesh levels, got {n}")
    cov = _coverage(coverage, n)
    tm = tree.mesh(leaves=leaves)
    base = Scene([with_wind(tm)], name=tree.name.replace(" ", "_"))
    out = [LodLevel(base, cov[0])]
    geo = tm.geometry
    t0 = base.n_triangles
    n_leaves = int(np.count_nonzero(geo.leaf_size > 1e-6)) if leaves else 0
    plans = [  # (sides, every k-th ring, drop fraction of stems, leaves per card)
        [(4, 2, 0.3, 6), (3, 2, 0.5, 10), (3, 3, 0.7, 20), (3, 4, 0.85, 40)],
        [(3, 4, 0.6, 60), (3, 6, 0.8, 150), (3, 8, 0.9, 400), (3, 12, 0.97, 1000)],
    ]
    for lv in range(1, n):
        limit = budgets[lv - 1] * t0
        scene = None
        for sides, every, drop, per in plans[lv - 1]:
            cards = max(1, n_leaves // per) if n_leaves else 0
            scene = _tree_level(tree, geo, sides, every, drop, cards)
            if scene.n_triangles <= limit:
                spare = int(0.8 * (limit - scene.n_triangles) / 2)
                if spare > 0 and n_leaves:
                    more = _tree_level(tree, geo, sides, every, drop, cards + spare)
                    if more.n_triangles <= limit:
                        scene = more
                break
        out.append(LodLevel(scene, cov[lv]))
    return LodChain(_named(out), name=tree.name.replace(" ", "_"))

"""Tree geometry → a sylva :class:`~sylva.geometry.mesh.Mesh` (bark tubes and leaf blades).

Bark: every :class:`~sylva.tree.stem.Stem` becomes rings stitched into a tube (one vectorised
pass for the whole tree).  Leaves: each is a double-sided flat blade in its frame (``u``
across, main vein at ``u = 0.5``, ``v`` from base to tip, which is what the renderer's
procedural ``leaf`` texture expects), tinted per leaf by the material's ``variation``.

The blade's outline is the Weber–Penn ``LeafShape`` (the paper leaves the shapes to the
renderer; this set is ours, see :data:`LEAF_SHAPES`).  Every outline lies in the box
``x ∈ [−w/2, w/2]``, ``y ∈ [0, 1]`` (``w = LeafScaleX``), touches the stalk at ``(0, 0)``
and is mirror-symmetric about ``x = 0``:

===  ==========  ==============================================================  ==========
 #   name        outline                                                          area/box
===  ==========  ==============================================================  ==========
 0   blade       the default pointed blade (6 vertices, 4 triangles)              0.63
 1   ellipse     the ellipse inscribed in the box (``oval``)                      π/4
 2   disc        a circle of diameter 1 (``round``; ignores ``LeafScaleX``)       π/4
 3   triangle    base edge across the stalk, apex at the tip                      1/2
 4   palm        five pointed lobes fanned from the stalk (a palmate leaf)        ≈ 0.33
 5   square      the whole box                                                    1
 6   hexagon     corners at y = 0, 1/4, 3/4, 1 (Blender Sapling's ``hex``)        3/4
 7   needles     a fascicle: five needles fanned from the stalk (conifers)        ≈ 0.2
 8   oak         a lobed blade, rounded lobes either side (oaks)                  ≈ 0.5
 9   ovate       egg-shaped, broadest below the middle, pointed tip (aspen,…)     ≈ 0.55
===  ==========  ==============================================================  ==========

Shapes 8 and 9 are half-width profiles along the midrib, meshed as strips either side of
it (so any profile that rises from the stalk and returns to the tip works).

Besides the mesh, the result keeps for each vertex the skeleton joint it moves with and,
for leaves, the flutter displacement (used by wind and glTF).

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

from .. import _jit
from ..geometry.mesh import Mesh
from ._kernels import leaf_fill
from .geometry_turtle import TreeGeometry
from .materials import MaterialDatabase
from .stem import stems_to_arrays

__all__ = ["LEAF_SHAPES", "TreeMesh", "build_tree_mesh", "leaf_blade", "leaf_outline",
           "leaf_shape_index"]

LEAF_SHAPES = ("blade", "ellipse", "disc", "triangle", "palm", "square", "hexagon", "needles",
               "oak", "ovate")
"""The ``LeafShape`` values by number (a name, or one of the aliases below, also works)."""

_LEAF_VERTICES = 200_000
"""Leaf vertices up to which a mesh is filled by NumPy while :func:`~sylva.tree._kernels.leaf_fill`
is not compiled (a sapling; a mature tree compiles it, ``sylva warmup`` does ahead)."""

_ALIASES = {"default": 0, "pointed": 0, "oval": 1, "round": 2, "circle": 2, "hex": 6}


def leaf_shape_index(shape) -> int:
    """The number of a ``LeafShape`` given as a number or a name.

    Examples
    --------
    >>> leaf_shape_index("oval"), leaf_shape_index(3), leaf_shape_index("Palm")
    (1, 3, 4)
    """
    if isinstance(shape, str):
        key = shape.strip().lower()
        if key.lstrip("-").isdigit():
            shape = int(key)
        elif key in LEAF_SHAPES:
            return LEAF_SHAPES.index(key)
        elif key in _ALIASES:
            return _ALIASES[key]
        else:
            raise ValueError(f"unknown LeafShape {shape!r}: expected 0…{len(LEAF_SHAPES) - 1} "
                             f"or one of {', '.join(LEAF_SHAPES)}")
    if isinstance(shape, float) and not shape.is_integer():
        raise ValueError(f"LeafShape must be a whole number or a name, got {shape}")
    i = int(shape)
    if not 0 <= i < len(LEAF_SHAPES):
        raise ValueError(f"LeafShape {i} out of range: expected 0…{len(LEAF_SHAPES) - 1} "
                         f"({', '.join(LEAF_SHAPES)})")
    return i


def leaf_outline(shape=0, width: float = 1.0) -> np.ndarray:
    """The closed outline of a leaf shape: float[n, 2], counter-clockwise from the stalk
    point ``(0, 0)`` (not repeated at the end)."""
    k = leaf_shape_index(shape)
    w = float(width)
    if k == 0:
        v, _, _ = leaf_blade(w)
        return v[[0, 2, 4, 5, 3, 1], :2]
    if k in (1, 2):
        ww = w if k == 1 else 1.0
        a = -0.5 * np.pi + np.linspace(0.0, 2.0 * np.pi, 48, endpoint=False)
        return np.column_stack([0.5 * ww * np.cos(a), 0.5 + 0.5 * np.sin(a)])
    if k == 3:
        return np.array([[0, 0], [0.5 * w, 0], [0, 1.0], [-0.5 * w, 0]])
    if k == 4:
        # five pointed leaflets fanned over ±75° from the blade axis (tips at radius 1,
        # notches between them at 0.35), listed right to left, then fit to the box
        return _fan(w, spread=75.0, edge=0.12, side=0.09, shoulder=0.8, notch=0.35, base=0.3)
    if k == 5:
        return np.array([[0, 0], [0.5 * w, 0], [0.5 * w, 1.0], [-0.5 * w, 1.0], [-0.5 * w, 0]])
    if k == 6:
        return np.array([[0, 0], [0.5 * w, 0.25], [0.5 * w, 0.75], [0, 1.0], [-0.5 * w, 0.75],
                         [-0.5 * w, 0.25]])
    if k == 7:
        # five needles over ±30° from the stalk, each a thin spike; notches near the base
        return _fan(w, spread=30.0, edge=0.05, side=0.035, shoulder=0.85, notch=0.1, base=0.08)
    y, h = _profile(k, w)
    right = np.column_stack([h[1:-1], y[1:-1]])
    left = right[::-1] * [-1.0, 1.0]
    return np.concatenate([[[0.0, 0.0]], right, [[0.0, 1.0]], left])


def _fan(w: float, *, spread: float, edge: float, side: float, shoulder: float, notch: float,
         base: float) -> np.ndarray:
    """An outline of five spikes fanned over ±``spread`` degrees (tips at radius 1, their
    sides at ``shoulder``, notches between them at ``notch``), fit to width ``w`` and
    height 1; ``edge`` and ``base`` place the first and last points beside the stalk."""
    tips = np.radians(np.linspace(spread, -spread, 5))
    ang, rad = [tips[0] + edge], [base]
    for j, t in enumerate(tips):
        ang += [t + side, t, t - side]
        rad += [shoulder, 1.0, shoulder]
        if j < len(tips) - 1:
            ang.append(0.5 * (t + tips[j + 1]))
            rad.append(notch)
    ang.append(tips[-1] - edge)
    rad.append(base)
    ang, rad = np.array(ang), np.array(rad)
    pts = np.concatenate([[[0.0, 0.0]], np.column_stack([rad * np.sin(ang), rad * np.cos(ang)])])
    pts[:, 0] *= w / (2.0 * np.abs(pts[:, 0]).max())
    pts[:, 1] /= pts[:, 1].max()
    return pts


def _profile(k: int, w: float) -> tuple[np.ndarray, np.ndarray]:
    """Heights ``y`` (0…1) and half-widths along the midrib of a profile shape (8, 9); the
    widest point is ``w / 2``."""
    y = np.linspace(0.0, 1.0, 13 if k == 8 else 9)
    if k == 8:  # oak: an obovate blade cut into five rounded lobes a side
        env = y ** 0.5 * (1.0 - y) ** 0.6
        h = env * (0.6 + 0.4 * np.abs(np.cos(2.5 * np.pi * y)))
    else:  # ovate: broadest at about a third of the length, a pointed tip
        h = y ** 0.55 * (1.0 - y) ** 1.1
    h[0] = h[-1] = 0.0
    return y, h * (0.5 * w / h.max())


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


def leaf_blade(width: float = 0.5, shape=0) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """The unit leaf of a ``LeafShape``: vertices float[n, 3] (x across, y along, z normal),
    uvs float[n, 2], triangles int[m, 3] (counter-clockwise seen from +z).  Shape 0 is the
    pointed blade of 6 vertices and 4 triangles; the others are their outline fanned from
    the stalk point (every outline is star-shaped from it)."""
    w = width
    k = leaf_shape_index(shape)
    if k == 0:
        v = np.array([[0, 0, 0], [-0.5 * w, 0.3, 0], [0.5 * w, 0.3, 0],
                      [-0.42 * w, 0.68, 0], [0.42 * w, 0.68, 0], [0, 1.0, 0]], np.float64)
        tri = np.array([[0, 2, 1], [1, 2, 4], [1, 4, 3], [3, 4, 5]])
    elif k in (8, 9):  # bands across the midrib: trapezoids R_j R_j+1 L_j+1 L_j
        y, h = _profile(k, w)
        m = len(y)
        v = np.zeros((2 * m, 3))
        v[0::2, 1] = v[1::2, 1] = y
        v[0::2, 0], v[1::2, 0] = h, -h
        tri = []
        for j in range(m - 1):
            R, L, R2, L2 = 2 * j, 2 * j + 1, 2 * j + 2, 2 * j + 3
            tri += [[L, R, R2], [L, R2, L2]]
        tri = np.array(tri)
        a, b = v[tri[:, 1], :2] - v[tri[:, 0], :2], v[tri[:, 2], :2] - v[tri[:, 0], :2]
        tri = tri[a[:, 0] * b[:, 1] - a[:, 1] * b[:, 0] > 1e-12]
    else:
        o = leaf_outline(shape, w)
        v = np.column_stack([o, np.zeros(len(o))])
        j = np.arange(1, len(o) - 1)
        tri = np.column_stack([np.zeros_like(j), j, j + 1])
    uw = max(w, 1.0) if leaf_shape_index(shape) == 2 else w
    uv = np.column_stack([0.5 + v[:, 0] / max(uw, 1e-9) * 0.98, v[:, 1]])
    return v, uv, tri


def build_tree_mesh(geo: TreeGeometry, materials: MaterialDatabase | None = None, *,
                    seed: int = 0, leaves: bool = True, flutter: float = 0.25,
                    leaf_shape=0) -> TreeMesh:
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
    leaf_shape : int or str
        The ``LeafShape`` of every leaf (see :data:`LEAF_SHAPES`).
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
        bv, buv, btri = leaf_blade(1.0, leaf_shape)
        nv = len(bv)
        if leaf_shape_index(leaf_shape) == 2:  # a disc is round whatever LeafScaleX says
            width = np.ones_like(width)
        q = len(live)
        mid, var = _leaf_materials(geo.leaf_material, live, mat_id, specs)
        tint = 1.0 + var[:, None] * rng.uniform(-1.0, 1.0, (q, 3)) * np.array([0.6, 1.0, 0.5])
        tint = np.clip(tint * (1.0 + var[:, None] * rng.uniform(-1, 1, (q, 1))), 0.3, 1.6)
        if not _jit.cold(leaf_fill, q * nv, _LEAF_VERTICES):
            return _filled(geo, specs, mat_names, db, (v, n, uv, tri, vj, bark_mids),
                           (pos, fr, width, size, live, mid, tint), (bv, buv, btri), flutter)
        local = bv[None, :, :] * np.stack([width * size, size, size], 1)[:, None, :]
        # the frame times each blade vertex, summed in einsum("kij,kvj->kvi")'s order (the
        # same numbers, in two thirds of its time)
        wv = pos[:, None, :] + (fr[:, None, :, 0] * local[:, :, 0, None]
                                + fr[:, None, :, 1] * local[:, :, 1, None]
                                + fr[:, None, :, 2] * local[:, :, 2, None])
        # normals: the blade's +z, bent a little outward along the blade for softer shading
        nz = fr[:, :, 2]
        wn = np.repeat(nz[:, None, :], nv, axis=1)
        base = nb
        idx = (btri[None, :, :] + (base + nv * np.arange(q))[:, None, None]).reshape(-1, 3)
        cols = np.concatenate([np.repeat(tint[:, None, :], nv, axis=1),
                               np.ones((q, nv, 1))], axis=2).reshape(-1, 4)
        verts.append(wv.reshape(-1, 3))
        norms.append(wn.reshape(-1, 3))
        uvs.append(np.tile(buv, (q, 1)))
        tris.append(idx)
        mids_all.append(np.repeat(mid, len(btri)))
        colors_v.append(cols)
        joint.append(np.repeat(geo.leaf_joint[live], nv))
        leaf_of.append(np.repeat(live, nv))
        # flutter: the blade bends about its base, tips move along the normal
        along = np.tile(bv[:, 1], q).reshape(q, nv)
        flut.append((nz[:, None, :] * (along * size[:, None] * flutter)[:, :, None]).reshape(-1, 3))
    mesh = Mesh(
        np.concatenate(verts), np.concatenate(tris), normals=np.concatenate(norms),
        uvs=np.concatenate(uvs), colors=np.concatenate(colors_v),
        material_ids=np.concatenate(mids_all),
        materials=[specs[nm].to_material() for nm in mat_names] or None, name="tree",
    )
    if not mat_names:
        mesh.materials = [db.get("bark").to_material()]
    tm = TreeMesh(mesh, geo, np.concatenate(joint), np.concatenate(leaf_of),
                  np.concatenate(flut).astype(np.float32), nb)
    from .lod import with_wind  # the WIND vertex data (sylva.geometry.lod's layout)

    with_wind(tm)
    return tm


def _leaf_materials(names: list, live: np.ndarray, mat_id, specs: dict):
    """The material id (int64, numbered in order of first use) and the tint variation of each
    live leaf, looked up once per distinct material name."""
    if len(live) != len(names):
        names = [names[i] for i in live.tolist()]
    keys = list(dict.fromkeys(names))
    ids = [mat_id(nm, "leaf") for nm in keys]
    var = np.array([specs[nm].variation for nm in keys])
    if len(keys) == 1:
        return np.full(len(names), ids[0], np.int64), np.full(len(names), var[0])
    slot = {nm: i for i, nm in enumerate(keys)}
    k = np.fromiter(map(slot.__getitem__, names), np.int64, len(names))
    return np.array(ids, np.int64)[k], var[k]


def _filled(geo: TreeGeometry, specs: dict, mat_names: list, db, bark, leaves, blade,
            flutter: float) -> TreeMesh:
    """The mesh written straight into its float32 arrays (bark rows first, then the leaves
    by :func:`~sylva.tree._kernels.leaf_fill`): the numbers of the NumPy road of
    :func:`build_tree_mesh`, without its float64 copies of a million leaf vertices."""
    v, n, uv, tri, vj, bark_mids = bark
    pos, fr, width, size, live, mid, tint = leaves
    bv, buv, btri = blade
    nb, q, nv, nt = len(v), len(live), len(bv), len(btri)
    tot, ntb = nb + q * nv, len(tri)
    V = np.empty((tot, 3), np.float32)
    N = np.empty((tot, 3), np.float32)
    UV = np.empty((tot, 2), np.float32)
    C = np.empty((tot, 4), np.float32)
    I = np.empty((ntb + q * nt, 3), np.uint32)
    M = np.empty(ntb + q * nt, np.int32)
    J = np.empty(tot, np.int64)
    L = np.empty(tot, np.int64)
    FL = np.empty((tot, 3), np.float32)
    V[:nb], N[:nb], UV[:nb], C[:nb] = v, n, uv, 1.0
    I[:ntb], M[:ntb], J[:nb], L[:nb], FL[:nb] = tri, bark_mids, vj, -1, 0.0
    M[ntb:].reshape(q, nt)[:] = mid[:, None]
    leaf_fill(np.ascontiguousarray(pos, np.float64), np.ascontiguousarray(fr, np.float64),
              np.ascontiguousarray(width, np.float64), np.ascontiguousarray(size, np.float64),
              np.ascontiguousarray(bv, np.float64), np.ascontiguousarray(buv, np.float64),
              np.ascontiguousarray(btri, np.int64), float(flutter),
              np.ascontiguousarray(tint, np.float64), np.ascontiguousarray(live, np.int64),
              np.ascontiguousarray(geo.leaf_joint[live], np.int64), nb, V, N, UV, C, I[ntb:],
              J, L, FL)
    mesh = Mesh(V, I, normals=N, uvs=UV, colors=C, material_ids=M,
                materials=[specs[nm].to_material() for nm in mat_names] or None, name="tree")
    if not mat_names:
        mesh.materials = [db.get("bark").to_material()]
    tm = TreeMesh(mesh, geo, J, L, FL, nb)
    from .lod import with_wind

    with_wind(tm, (live, nv))
    return tm

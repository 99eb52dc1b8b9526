"""Meshes from turtle geometry: branches, leaves, polygons and voxel blocks.

:func:`build_mesh` turns a :class:`~sylva.geometry.records.Geometry` into a
:class:`~sylva.geometry.mesh.Scene` of up to four meshes: ``branches``, ``leaves``,
``polygons`` and ``blocks``.  Branch modes:

``"tube"`` (default)
    Continuous generalised cylinders along each axis of the branching structure (the Stem of
    seed 002 §5.6): one ring of ``detail`` sides per segment end, oriented by a
    parallel-transported frame (no twist), rings shared between a segment and the child that
    continues its axis, and mitred at joints (the circle is slid along the axis onto the
    bisecting plane, where both cylinders meet exactly), so there are no gaps and none of
    the hemisphere artefacts of seed 000 §2.5.  Where the colour or material changes along
    an axis the tube goes on: the next segment starts on a copy of the ring (same
    positions and normals, its own colour).  Every tube is closed by a cap at each end,
    so each is a closed 2-manifold.  UVs: u in [0, 1] around, v along the length
    (length / mean circumference, so a square texel stays square).
``"prism"``
    Seed 001: every segment is the mantle of a regular prism with ``detail`` flat faces
    (``detail < 3``: one rectangle, both sides), without caps.
``"cone"``
    Seed 000: every segment is a frustum whose bottom base is a hemisphere of the base
    radius, closed by a flat top.

``taper`` chooses the radii: ``None`` keeps the turtle's (``reduction``, ``!`` …);
``"leonardo"`` applies Leonardo's rule (seed 004 §4.3): ``r(parent)^e = Σ r(child)^e``
with ``e = 2``, starting from the tip radii.

Examples
--------
>>> from sylva.turtle import interpret
>>> g = interpret("F[+F]F", dialect="abop", rot=45, thick=0.2)
>>> scene = build_mesh(g, detail=8)
>>> [m.name for m in scene.meshes], scene.n_triangles
(['branches'], 80)
"""

from __future__ import annotations

import dataclasses
import math

import numpy as np

from .. import _jit
from ..errors import SylvaError
from .buffers import empty
from .mesh import Material, Mesh, Scene
from .records import Geometry

__all__ = [
    "MODES",
    "triangulate_polygons",
    "BuildError",
    "build_blocks",
    "build_branches",
    "build_leaves",
    "build_mesh",
    "build_polygons",
    "leaf_template",
]

#: The kernels; while they are not compiled, a :func:`build_mesh` of at most :data:`SMALL`
#: records runs their Python source instead (:func:`sylva._jit.road`: well under a second
#: against some 9 s of compiling; tests compare the two roads on every built-in example).
K = _jit.road("sylva.geometry._kernels", ("sylva.geometry._simd",))
SMALL = 50_000

MODES = ("tube", "prism", "cone")


class BuildError(SylvaError, ValueError):
    """Impossible mesh-building options (an unknown mode, too few sides …)."""


def _sides(detail: int | None, geometry: Geometry, mode: str) -> int:
    from_program = detail is None
    if detail is None:
        detail = geometry.detail if geometry.detail is not None else 8
    d = int(math.floor(detail))
    if mode == "prism":
        return d if d >= 3 else 1  # seed 001: detail < 3 means one rectangle
    if d < 3 and from_program:  # a program's flat detail means the thinnest round tube
        return 3
    if d < 3:
        raise BuildError(f"a {mode} needs at least 3 sides, got detail={detail}")
    return d


def _radii(geometry: Geometry, taper: str | None, exponent: float) -> np.ndarray:
    if taper is None:
        return geometry.seg_radius
    if taper == "leonardo":
        if exponent <= 0:
            raise BuildError(f"Leonardo's exponent must be > 0, got {exponent}")
        return K.leonardo(geometry.seg_parent, geometry.seg_radius, float(exponent))
    raise BuildError(f"unknown taper {taper!r}: expected None or 'leonardo'")


def build_branches(
    geometry: Geometry,
    *,
    detail: int | None = None,
    mode: str = "tube",
    taper: str | None = None,
    exponent: float = 2.0,
    max_bend: float = 140.0,
    colors: bool | None = None,
) -> Mesh:
    """The branch mesh of ``geometry``'s segments.

    Parameters
    ----------
    geometry : Geometry
    detail : int, optional
        Sides around a branch (default: the program's ``detail``, else 8).
    mode : {"tube", "prism", "cone"}
    taper : {None, "leonardo"}
    exponent : float
        Leonardo's exponent (2 keeps the cross-section area).
    max_bend : float
        Degrees; a tube is broken (capped and restarted) at sharper joints, where a mitre
        would pinch.
    colors : bool, optional
        Write vertex colours (default: :attr:`Geometry.vertex_colors`).

    Returns
    -------
    Mesh
        ``n·d`` … triangles: a tube has ``2d`` per segment plus ``d`` per cap.
    """
    if mode not in MODES:
        raise BuildError(f"unknown branch mode {mode!r}: expected one of {', '.join(MODES)}")
    geometry = _drop_degenerate(geometry)
    d = _sides(detail, geometry, mode)
    want = geometry.vertex_colors if colors is None else bool(colors)
    n = geometry.n_segments
    radius = _radii(geometry, taper, exponent)
    args = (
        geometry.seg_start, geometry.seg_end, radius, geometry.seg_ref, geometry.seg_color,
        geometry.seg_material,
    )  # fmt: skip
    if mode == "tube":
        cont, prev, dup, v1, voff, toff = _tube_plan(geometry, radius, max_bend, want, d)
        nv, nt = int(voff[-1]), int(toff[-1])
        mats = geometry.seg_material
        single = n > 0 and int(mats.min()) == int(mats.max())
        V, N, UV, C, I, M = _alloc(nv, 0 if single else nt, want, nt)
        K.tube_fill(*args, geometry.seg_parent, cont, prev, dup, v1, voff, toff, d, want,
                    V, N, UV, C, I, M)  # fmt: skip
        if single:  # one material: no per-triangle ids to write
            k = int(mats[0])
            return Mesh(
                V, I, normals=N, uvs=UV, colors=C if want else None,
                materials=[geometry.materials[k] if k < len(geometry.materials)
                           else Material(f"material_{k}")],
                name="branches",
            )  # fmt: skip
    elif mode == "prism":
        faces = d if d >= 3 else 2
        V, N, UV, C, I, M = _alloc(n * faces * 4, n * faces * 2, want)
        K.prism_fill(*args, d, want, V, N, UV, C, I, M)
    else:
        h = max(2, d // 4)
        nv = (d + 1) * (h + 2) + 2
        nt = 2 * d * h + 4 * d
        V, N, UV, C, I, M = _alloc(n * nv, n * nt, want)
        K.cone_fill(*args, d, h, want, V, N, UV, C, I, M)
    return Mesh(
        V, I, normals=N, uvs=UV, colors=C if want else None, material_ids=M,
        materials=list(geometry.materials), name="branches",
    )  # fmt: skip


_SEGMENT_FIELDS = ("seg_start", "seg_end", "seg_radius", "seg_color", "seg_material",
                   "seg_module", "seg_parent", "seg_depth", "seg_ref")


def _drop_degenerate(geometry: Geometry) -> Geometry:
    """``geometry`` without the segments too short to have a direction (below 1e-9 of the
    plant's size: cpfg's ``F(func(…))`` can draw 4.9e-18 long; a tube cannot be framed on
    them, and they show nothing), each child re-parented to its nearest kept ancestor."""
    n = geometry.n_segments
    if n == 0:
        return geometry
    axis = geometry.seg_end - geometry.seg_start
    length = np.sqrt(np.einsum("ij,ij->i", axis, axis))
    lo = np.minimum(geometry.seg_start.min(axis=0), geometry.seg_end.min(axis=0))
    hi = np.maximum(geometry.seg_start.max(axis=0), geometry.seg_end.max(axis=0))
    keep = length > 1e-9 * max(float(np.max(hi - lo)), 1e-300)
    if keep.all():
        return geometry
    parent = geometry.seg_parent.astype(np.int64).copy()
    while True:  # pointer jumping over the dropped ones: each pass halves a run of them
        p = np.maximum(parent, 0)
        skip = (parent >= 0) & ~keep[p]
        if not skip.any():
            break
        parent[skip] = parent[p[skip]]
    new_index = np.cumsum(keep) - 1
    fields = {f: getattr(geometry, f)[keep] for f in _SEGMENT_FIELDS}
    par = parent[keep]
    fields["seg_parent"] = np.where(par >= 0, new_index[np.maximum(par, 0)], -1).astype(
        geometry.seg_parent.dtype
    )
    return dataclasses.replace(geometry, **fields)


def _tube_plan(geometry: Geometry, radius: np.ndarray, max_bend: float, split_colors: bool, d: int):
    """The layout of the continuous tubes of ``geometry``'s segments at ``d`` sides:
    ``(cont, prev, dup, v1, voff, toff)``, see :func:`sylva.geometry._kernels.tube_plan`."""
    n = geometry.n_segments
    cont, prev, dup = empty(n, np.int64), empty(n, np.bool_), empty(n, np.bool_)
    v1, voff, toff = empty(n, np.float64), empty(n + 1, np.int64), empty(n + 1, np.int64)
    K.tube_plan(
        geometry.seg_start, geometry.seg_end, radius, geometry.seg_parent, geometry.seg_depth,
        geometry.seg_material, geometry.seg_color, math.cos(math.radians(max_bend)),
        split_colors, d, cont, prev, dup, v1, voff, toff,
    )  # fmt: skip
    return cont, prev, dup, v1, voff, toff


def _alloc(nv: int, nt: int, want_colors: bool, n_idx: int | None = None):
    # from the buffer pool: a mesh built again (studio, animation) reuses touched pages
    return (
        empty((nv, 3), np.float32),
        empty((nv, 3), np.float32),
        empty((nv, 2), np.float32),
        empty((nv if want_colors else 0, 4), np.float32),
        empty((nt if n_idx is None else n_idx, 3), np.uint32),
        empty(nt, np.int32),
    )


# --------------------------------------------------------------------------- leaves
def leaf_template(
    rows: int = 6, width: float = 0.36, fold: float = 0.3, droop: float = 0.12
) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """A unit leaf in its own frame: x to the right (−L), y along H, z along U.

    The blade is ovate (half-width ``width·sin(πt)·(1 − 0.35t)`` at ``t`` along the
    midrib), folded into a shallow V along the midrib (``z = fold·|x|``) and drooping
    (``z −= droop·y²``), so it keeps an area seen edge-on.

    Returns
    -------
    vertices : float64[m, 3]; uvs : float32[m, 2] (u across, v along); tris : int64[k, 3]
        Counter-clockwise about +z (the upper side).
    """
    t = np.linspace(0.0, 1.0, rows + 2)[1:-1]
    hw = width * np.sin(np.pi * t) * (1.0 - 0.35 * t)
    verts = [(0.0, 0.0, 0.0)]
    uvs = [(0.5, 0.0)]
    for ti, w in zip(t, hw):
        for x in (-w, 0.0, w):
            verts.append((x, ti, fold * abs(x)))
            uvs.append((0.5 + x / (2 * width), ti))
    verts.append((0.0, 1.0, 0.0))
    uvs.append((0.5, 1.0))
    v = np.array(verts)
    v[:, 2] -= droop * v[:, 1] ** 2
    tip = len(verts) - 1
    tris = [(0, 2, 1), (0, 3, 2)]
    for r in range(rows - 1):
        a = 1 + 3 * r
        b = a + 3
        for k in range(2):
            tris.append((a + k, a + k + 1, b + k + 1))
            tris.append((a + k, b + k + 1, b + k))
    a = 1 + 3 * (rows - 1)
    tris += [(a, a + 1, tip), (a + 1, a + 2, tip)]
    return v, np.array(uvs, np.float32), np.array(tris, np.int64)


def build_leaves(geometry: Geometry, *, template=None, colors: bool | None = None) -> Mesh:
    """Leaves as shaped, one-faced meshes with double-sided materials.

    Each leaf is a template scaled by its size and placed in its frame: the one of its
    predefined surface (:attr:`Geometry.leaf_surface` into :attr:`Geometry.surfaces`, cpfg's
    ``~X``: the tessellated Bézier patches of :mod:`sylva.geometry.surfaces`, its contact
    point at the turtle), else ``template`` (default :func:`leaf_template`).  A leaf
    is one surface, written once: its materials are marked ``double_sided``, which the
    renderer (no culling, the normal flipped on the back) and every format with such a flag
    (glTF ``doubleSided``) honour.  Two coincident opposite faces would be dropped as
    duplicates by Blender and make STL non-manifold.
    """
    default = template if template is not None else leaf_template()
    which = geometry.leaf_surface
    kinds = np.unique(which) if which.size else np.zeros(0, np.int32)
    if kinds.size <= 1:
        t = default if not kinds.size or kinds[0] < 0 else geometry.surfaces[kinds[0]][1:]
        return _leaves(geometry, np.arange(geometry.n_leaves), t, colors)
    parts = []
    for kind in kinds.tolist():
        t = default if kind < 0 else geometry.surfaces[kind][1:]
        parts.append(_leaves(geometry, np.flatnonzero(which == kind), t, colors))
    return _concat_meshes(parts)


def _concat_meshes(parts: list[Mesh]) -> Mesh:
    """One mesh of ``parts`` (same materials, all with or all without colours)."""
    base = np.cumsum([0] + [p.vertices.shape[0] for p in parts])[:-1]
    colors = None
    if parts[0].colors is not None:
        colors = np.concatenate([p.colors for p in parts])
    return Mesh(
        np.concatenate([p.vertices for p in parts]),
        np.concatenate([p.indices.astype(np.int64) + b for p, b in zip(parts, base)]),
        normals=np.concatenate([p.normals for p in parts]),
        uvs=np.concatenate([p.uvs for p in parts]),
        colors=colors,
        material_ids=np.concatenate([p.triangle_materials() for p in parts]),
        materials=parts[0].materials,
        name="leaves",
    )


def _leaves(geometry: Geometry, sel: np.ndarray, template, colors: bool | None) -> Mesh:
    k = sel.size
    tv, tuv, tt = template
    tv = np.asarray(tv, np.float64)
    tn = Mesh(tv, tt).normals.astype(np.float64)
    fr = geometry.leaf_frame[sel]  # rows H, L, U
    basis = np.stack([-fr[:, 1], fr[:, 0], fr[:, 2]], axis=1)  # rows: x, y, z axes
    size = geometry.leaf_size[sel].astype(np.float64)[:, None, None]
    if geometry.leaf_stretch is None:
        verts = geometry.leaf_pos[sel][:, None, :] + np.einsum("mj,kjc->kmc", tv, basis) * size
        nrm = np.einsum("mj,kjc->kmc", tn, basis)
    else:  # ~X(sx, sy, sz): each axis of the template scaled; normals by the inverse
        st = geometry.leaf_stretch[sel].astype(np.float64)[:, None, :]
        verts = geometry.leaf_pos[sel][:, None, :] + np.einsum(
            "kmj,kjc->kmc", tv[None] * st, basis) * size
        nrm = np.einsum("kmj,kjc->kmc", tn[None] / np.where(st == 0.0, 1e-30, st), basis)
    nrm /= np.maximum(np.linalg.norm(nrm, axis=2, keepdims=True), 1e-30)
    m = tv.shape[0]
    front = tt[None, :, :] + (np.arange(k) * m)[:, None, None]
    M = np.repeat(geometry.leaf_material, tt.shape[0]) if k == geometry.n_leaves else \
        np.repeat(geometry.leaf_material[sel], tt.shape[0])
    want = geometry.vertex_colors if colors is None else bool(colors)
    C = None
    if want:
        c = np.concatenate([geometry.leaf_color[sel], np.ones((k, 1), np.float32)], axis=1)
        C = np.repeat(c, m, axis=0)
    return Mesh(
        verts.reshape(-1, 3),
        front.reshape(-1, 3),
        normals=nrm.reshape(-1, 3),
        uvs=np.tile(tuv, (k, 1)),
        colors=C,
        material_ids=M,
        materials=_double_sided(geometry.materials, geometry.leaf_material),
        name="leaves",
    )


def _double_sided(materials, ids: np.ndarray) -> list[Material]:
    """``materials`` with those that ``ids`` uses marked double-sided (one-faced surfaces)."""
    used = set(np.unique(ids).tolist()) if len(ids) else set()
    return [
        dataclasses.replace(mat, double_sided=True) if k in used and not mat.double_sided
        else mat
        for k, mat in enumerate(materials)
    ]


# --------------------------------------------------------------------------- polygons
def triangulate_polygons(vertices: np.ndarray, offsets: np.ndarray):
    """Triangles of the polygons ``vertices[offsets[i]:offsets[i + 1]]`` (concave ones too).

    Convex polygons are fanned; a concave one is triangulated by mapbox's earcut
    (``mapbox_earcut``, the ear-clipping library of Mapbox GL) in its plane.  Triangles of
    (near) zero area are left out.

    Returns
    -------
    tris : int64[t, 3]
        Indices into ``vertices``, wound like the polygon (counter-clockwise about its
        Newell normal).
    owner : int64[t]
        The polygon of each triangle.
    normals : float64[p, 3]
        The unit Newell normal of each polygon.

    Examples
    --------
    >>> v = np.array([[0, 0, 0], [2, 0, 0], [2, 2, 0], [1, 1, 0], [0, 2, 0]], float)
    >>> tris, owner, n = triangulate_polygons(v, np.array([0, 5]))
    >>> len(tris), n[0].tolist()   # a concave pentagon: 3 triangles, not a fan over the notch
    (3, [0.0, 0.0, 1.0])
    """
    import mapbox_earcut

    vertices = np.ascontiguousarray(vertices, np.float64)
    offsets = np.asarray(offsets, np.int64)
    normals, flat, convex = K.polygon_planes(vertices, offsets)
    counts = np.diff(offsets)
    parts_t, parts_o = [], []
    fan = np.flatnonzero(convex & (counts >= 3))
    if fan.size:
        per = counts[fan] - 2
        owner = np.repeat(fan, per)
        first = np.repeat(offsets[fan], per)
        step = np.arange(per.sum()) - np.repeat(np.cumsum(per) - per, per)
        parts_t.append(np.stack([first, first + step + 1, first + step + 2], axis=1))
        parts_o.append(owner)
    for i in np.flatnonzero(~convex).tolist():
        o, k = int(offsets[i]), int(counts[i])
        idx = mapbox_earcut.triangulate_float64(flat[o : o + k], np.array([k], np.uint32))
        t = idx.astype(np.int64).reshape(-1, 3) + o
        parts_t.append(t)
        parts_o.append(np.full(t.shape[0], i, np.int64))
    if not parts_t:
        return np.zeros((0, 3), np.int64), np.zeros(0, np.int64), normals
    tris = np.concatenate(parts_t)
    owner = np.concatenate(parts_o)
    a, b, c = flat[tris[:, 0]], flat[tris[:, 1]], flat[tris[:, 2]]
    area2 = (b[:, 0] - a[:, 0]) * (c[:, 1] - a[:, 1]) - (c[:, 0] - a[:, 0]) * (b[:, 1] - a[:, 1])
    edge2 = np.maximum.reduce([((b - a) ** 2).sum(1), ((c - b) ** 2).sum(1),
                               ((a - c) ** 2).sum(1)])  # fmt: skip
    keep = np.abs(area2) > 1e-10 * edge2  # collinear vertices make no triangle
    return tris[keep], owner[keep], normals


def build_polygons(geometry: Geometry, *, colors: bool | None = None) -> Mesh:
    """Polygons ``{ … }`` triangulated (concave ones too, :func:`triangulate_polygons`),
    one-faced with double-sided materials (as leaves are)."""
    tris, owner, pn = triangulate_polygons(geometry.poly_vertices, geometry.poly_offsets)
    used = np.unique(tris)
    remap = np.full(geometry.poly_vertices.shape[0], -1, np.int64)
    remap[used] = np.arange(used.size)
    # a vertex may belong to one polygon only (offsets partition the vertices)
    poly_of_vertex = np.repeat(np.arange(geometry.n_polygons), np.diff(geometry.poly_offsets))
    pv = geometry.poly_vertices[used]
    nrm = pn[poly_of_vertex[used]]
    # planar UVs: the polygon's own bounding box in its plane
    e1 = np.where(np.abs(nrm[:, :1]) < 0.9, np.cross([1.0, 0, 0], nrm), np.cross([0, 1.0, 0], nrm))
    e1 /= np.linalg.norm(e1, axis=1, keepdims=True)
    e2 = np.cross(nrm, e1)
    uv = np.stack([(pv * e1).sum(1), (pv * e2).sum(1)], axis=1)
    pid = poly_of_vertex[used]
    lo = np.full((geometry.n_polygons, 2), np.inf)
    hi = np.full((geometry.n_polygons, 2), -np.inf)
    np.minimum.at(lo, pid, uv)
    np.maximum.at(hi, pid, uv)
    span = np.maximum(hi - lo, 1e-12)
    uv = (uv - lo[pid]) / span[pid]
    nu = used.size
    M = geometry.poly_material[owner]
    want = geometry.vertex_colors if colors is None else bool(colors)
    C = None
    if want:
        C = np.concatenate([geometry.poly_color[pid], np.ones((nu, 1), np.float32)], axis=1)
    return Mesh(
        pv,
        remap[tris],
        normals=nrm,
        uvs=uv,
        colors=C,
        material_ids=M,
        materials=_double_sided(geometry.materials, M),
        name="polygons",
    )


# --------------------------------------------------------------------------- blocks
_CUBE_FACES = np.array(
    [  # normal, then two in-face axes (u, v) with u x v = normal
        [[1, 0, 0], [0, 0, -1], [0, 1, 0]],
        [[-1, 0, 0], [0, 0, 1], [0, 1, 0]],
        [[0, 1, 0], [1, 0, 0], [0, 0, -1]],
        [[0, -1, 0], [1, 0, 0], [0, 0, 1]],
        [[0, 0, 1], [1, 0, 0], [0, 1, 0]],
        [[0, 0, -1], [-1, 0, 0], [0, 1, 0]],
    ],
    np.float64,
)


def _unit_cube() -> tuple[np.ndarray, np.ndarray, np.ndarray, np.ndarray]:
    corners = np.array([[-1, -1], [1, -1], [1, 1], [-1, 1]], np.float64)
    v, n, uv, t = [], [], [], []
    for f, (nn, u, w) in enumerate(_CUBE_FACES):
        for cu, cw in corners:
            v.append(0.5 * (nn + cu * u + cw * w))
            n.append(nn)
            uv.append(((cu + 1) / 2, (cw + 1) / 2))
        b = 4 * f
        t += [(b, b + 1, b + 2), (b, b + 2, b + 3)]
    return np.array(v), np.array(n), np.array(uv, np.float32), np.array(t, np.int64)


def build_blocks(geometry: Geometry) -> Mesh:
    """Seed 004's voxel blocks: an axis-aligned cube per block, material per output buffer.

    Each cube has 24 vertices (flat normals, a full [0, 1]² UV square per face) and 12
    triangles.
    """
    b = geometry.n_blocks
    cv, cn, cuv, ct = _unit_cube()
    V = geometry.block_center[:, None, :] + cv[None] * geometry.block_size[:, None, None]
    N = np.broadcast_to(cn, (b, 24, 3))
    UV = np.tile(cuv, (b, 1))
    I = ct[None] + (np.arange(b) * 24)[:, None, None]
    M = np.repeat(geometry.block_buffer, 12)
    return Mesh(
        V.reshape(-1, 3),
        I.reshape(-1, 3),
        normals=N.reshape(-1, 3),
        uvs=UV,
        material_ids=M,
        materials=list(geometry.materials),
        name="blocks",
    )


# --------------------------------------------------------------------------- all together
def build_mesh(
    geometry: Geometry,
    detail: int | None = None,
    mode: str = "tube",
    *,
    taper: str | None = None,
    leaves: bool = True,
    polygons: bool = True,
    blocks: bool = True,
    colors: bool | None = None,
    prune_materials: bool = True,
) -> Scene:
    """A scene with the meshes of every kind of record in ``geometry``.

    Parameters
    ----------
    geometry : Geometry
        From :func:`sylva.turtle.interpret`.
    detail : int, optional
        Sides around a branch (default: the program's ``detail``, else 8).
    mode : {"tube", "prism", "cone"}
        Branch construction (see the module docstring).
    taper : {None, "leonardo"}
        Radii from the turtle, or by Leonardo's rule.
    leaves, polygons, blocks : bool
        Whether to build those meshes (when there are records).
    colors : bool, optional
        Vertex colours (default: :attr:`Geometry.vertex_colors`).
    prune_materials : bool
        Keep only the materials the triangles use.

    Returns
    -------
    Scene
        Meshes named ``branches``, ``leaves``, ``polygons``, ``blocks`` (those that are not
        empty), and ``background`` (:attr:`Geometry.scenery`, cpfg's background scene).

    Examples
    --------
    >>> from sylva.turtle import interpret
    >>> g = interpret("F(2)[&L]F", dialect="classic", reduction=0.9, radius=0.2)
    >>> s = build_mesh(g, detail=6)
    >>> [(m.name, m.n_triangles) for m in s.meshes]
    [('branches', 36), ('leaves', 24)]
    """
    n = geometry.n_segments + geometry.n_leaves + geometry.n_polygons + geometry.n_blocks
    with _jit.small(n <= SMALL):
        return _build_mesh(geometry, detail, mode, taper, leaves, polygons, blocks, colors,
                           prune_materials)  # fmt: skip


def _build_mesh(geometry, detail, mode, taper, leaves, polygons, blocks, colors,
                prune_materials) -> Scene:  # fmt: skip
    meshes = []
    if geometry.n_segments:
        meshes.append(
            build_branches(geometry, detail=detail, mode=mode, taper=taper, colors=colors)
        )
    if leaves and geometry.n_leaves:
        meshes.append(build_leaves(geometry, colors=colors))
    if polygons and geometry.n_polygons:
        meshes.append(build_polygons(geometry, colors=colors))
    if blocks and geometry.n_blocks:
        meshes.append(build_blocks(geometry))
    meshes = [m for m in meshes if m.n_triangles]  # e.g. only degenerate polygons
    # a material that a one-faced leaf or polygon uses is double-sided in every mesh, so
    # that the scene's material table (unified by name) agrees
    two = {mat.name for m in meshes for mat in m.materials if mat.double_sided}
    for m in meshes:
        m.materials = [dataclasses.replace(mat, double_sided=True)
                       if mat.name in two and not mat.double_sided else mat
                       for mat in m.materials]  # fmt: skip
    if prune_materials:
        meshes = [_prune(m) for m in meshes]
    if geometry.scenery is not None and geometry.scenery.n_triangles:
        meshes.append(geometry.scenery)  # cpfg's background scene, as drawn around the plant
    return Scene(meshes, name="plant")


def _prune(mesh: Mesh) -> Mesh:
    ids = mesh.triangle_materials()
    used = np.unique(ids)
    if used.size == len(mesh.materials) and np.array_equal(used, np.arange(used.size)):
        return mesh
    remap = np.zeros(len(mesh.materials), np.int32)
    remap[used] = np.arange(used.size, dtype=np.int32)
    mesh.material_ids = remap[ids]
    mesh.materials = [mesh.materials[i] for i in used]
    return mesh

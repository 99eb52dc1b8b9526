"""Levels of detail of a plant, made the way tree tools make them, and wind as vertex data.

An :class:`LodChain` is a list of :class:`LodLevel` (a :class:`~sylva.geometry.mesh.Scene`
each, with the screen coverage below which an engine switches to the next level).  The
mesh levels are not the output of a generic decimator: they are meshed again from the
plant's own records with

* **fewer sides** around each branch (8 → 4 → 3),
* **fewer rings** along each axis (runs of ``k`` segments that continue one another become
  one segment),
* **thin twigs dropped by radius** (the thinnest branches, with everything that grows on
  them), and
* **leaves merged into cards**: the leaves are clustered on a grid and each cluster becomes
  one double-sided quad in the cluster's mean plane, sized to cover its leaves' area.

The budgets are LOD1 ≤ 25 % and LOD2 ≤ 5 % of LOD0's triangles (:data:`BUDGETS`); each
level tightens its settings until it fits.  The last level of a full chain is an
impostor (crossed quads with a baked colour + alpha + normal atlas), which needs the
renderer and is added above this package by :func:`sylva._impostor.add_impostor`.

:func:`plant_lods` makes the chain of an L-system plant (turtle
:class:`~sylva.geometry.records.Geometry`); :func:`sylva.tree.lod.tree_lods` that of a tree.

Wind vertex data
----------------
:func:`wind_attribute` packs, per vertex, what an engine's wind shader needs (the
SpeedTree way, as an open layout).  Meshes carry it as ``Mesh.attributes["WIND"]``,
float32 ``[n, 4]``, which glTF writes as the custom attribute ``_WIND`` (``VEC4``,
``FLOAT``):

=====  ===========  ===================================================================
 comp   name         meaning
=====  ===========  ===================================================================
 x      level        branch level: 0 trunk / main axis, 1 its branches, …; leaves get
                     their branch's level + 1
 y      phase        in [0, 1): one value per branch (and per leaf), so that branches
                     sway out of step; multiply by 2π
 z      flex         stiffness weight in [0, 1]: 0 at the base of the trunk (does not
                     move), 1 at the farthest tip; the distance along the skeleton from
                     the root over the largest such distance
 w      flutter      leaves: 0 at the stalk to 1 at the tip of the blade; bark: 0
=====  ===========  ===================================================================

Examples
--------
>>> from sylva.turtle import interpret
>>> g = interpret("F(2)[&L]F[+F[-F]F]F", dialect="classic", reduction=0.8, radius=0.2)
>>> chain = plant_lods(g)
>>> [lv.name for lv in chain.levels], chain.ratios()[1] <= 0.25
(['LOD0', 'LOD1', 'LOD2'], True)
"""

from __future__ import annotations

import dataclasses
import math
from dataclasses import dataclass, field

import numpy as np

from ..errors import SylvaError
from .mesh import Material, Mesh, Scene
from .records import Geometry

__all__ = [
    "BUDGETS",
    "COVERAGE",
    "LodChain",
    "LodError",
    "LodLevel",
    "check_lods",
    "leaf_cards",
    "path_length",
    "phase_of",
    "plant_lods",
    "simplify_segments",
    "wind_attribute",
]

#: Largest triangle fraction of LOD0 for LOD1 and LOD2.
BUDGETS = (0.25, 0.05)
#: Default screen coverage (fraction of the screen height) at which each level starts
#: to be shown (glTF ``MSFT_screencoverage``); the last is where the plant is culled.
COVERAGE = (0.5, 0.2, 0.06, 0.01)


class LodError(SylvaError, ValueError):
    """A level-of-detail setting that makes no sense (the message names the option)."""


def check_lods(lods, option: str = "lod") -> int:
    """``lods`` as an int in 1 … 4 (the number of levels), or a LodError naming ``option``.

    1 is the plant alone, 2 adds LOD1, 3 adds LOD2, 4 adds the impostor.
    """
    try:
        n = int(lods)
        if n != float(lods):
            raise ValueError
    except (TypeError, ValueError):
        raise LodError(f"{option}: expected a whole number of levels 1…4, got {lods!r}") from None
    if not 1 <= n <= 4:
        raise LodError(f"{option}: expected 1…4 levels (LOD0, LOD1, LOD2, impostor), got {n}")
    return n


@dataclass
class LodLevel:
    """One level: its scene, the screen coverage at which it starts, and its kind.

    Attributes
    ----------
    scene : Scene
    coverage : float
        Fraction of the screen height below which the engine moves on to the next level.
    kind : {"mesh", "impostor"}
    images : dict
        For an impostor, ``{material name: {"color": uint8[h, w, 4], "normal":
        uint8[h, w, 3]}}``: the baked atlas its quads sample (writers embed it).
    """

    scene: Scene
    coverage: float
    kind: str = "mesh"
    images: dict = field(default_factory=dict)
    name: str = ""

    @property
    def n_triangles(self) -> int:
        return self.scene.n_triangles


@dataclass
class LodChain:
    """The levels of detail of one plant, finest first."""

    levels: list[LodLevel]
    name: str = "plant"

    def ratios(self) -> list[float]:
        """Each level's triangles over LOD0's."""
        t0 = max(self.levels[0].n_triangles, 1)
        return [lv.n_triangles / t0 for lv in self.levels]

    def coverage(self) -> list[float]:
        return [lv.coverage for lv in self.levels]

    def __len__(self) -> int:
        return len(self.levels)


def _named(levels: list[LodLevel]) -> list[LodLevel]:
    for i, lv in enumerate(levels):
        lv.name = f"LOD{i}"
    return levels


# --------------------------------------------------------------------------- helpers
def path_length(parent: np.ndarray, length: np.ndarray) -> np.ndarray:
    """``float64[n]``: the length from the root to the end of each element along
    ``parent`` links (-1: a root), by pointer jumping (no order assumed)."""
    val = np.asarray(length, np.float64).copy()
    p = np.asarray(parent, np.int64).copy()
    m = p >= 0
    while m.any():
        val[m] += val[p[m]]
        p[m] = p[p[m]]
        m = p >= 0
    return val


def phase_of(keys: np.ndarray, salt: int = 0) -> np.ndarray:
    """``float32[n]`` in [0, 1): a stable hash of integer ``keys`` (one wind phase per key)."""
    x = (np.asarray(keys, np.uint64) + np.uint64(salt * 0x9E3779B9 + 1)) * np.uint64(
        0x9E3779B97F4A7C15
    )
    x ^= x >> np.uint64(31)
    x *= np.uint64(0xBF58476D1CE4E5B9)
    x ^= x >> np.uint64(29)
    return ((x >> np.uint64(40)).astype(np.float64) / float(1 << 24)).astype(np.float32)


def wind_attribute(level, phase, flex, flutter) -> np.ndarray:
    """The ``float32[n, 4]`` wind vertex data (see the module docstring for the layout)."""
    cols = np.broadcast_arrays(*(np.asarray(c, np.float32) for c in (level, phase, flex,
                                                                       flutter)))
    out = np.stack(cols, axis=1).astype(np.float32)
    out[:, 1] = np.mod(out[:, 1], 1.0)
    out[:, 2:] = np.clip(out[:, 2:], 0.0, 1.0)
    return out


def _head(cparent: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """For continuation links ``cparent`` (-1: an axis starts here): each element's axis
    head and its position along the axis (0 at the head), by pointer jumping."""
    n = cparent.shape[0]
    head = np.where(cparent >= 0, cparent, np.arange(n))
    pos = (cparent >= 0).astype(np.int64)
    while True:
        nxt = head[head]
        if np.array_equal(nxt, head):
            return head, pos
        pos = pos + pos[head]
        head = nxt


# --------------------------------------------------------------------------- branches
def simplify_segments(geometry: Geometry, *, join: int = 1, drop: float = 0.0,
                      cos_limit: float = 0.5) -> Geometry:
    """``geometry`` with fewer, longer and fewer thin segments.

    Parameters
    ----------
    join : int
        Runs of ``join`` segments that continue one another (the only child of their
        parent at the same bracket depth and material, bending less than 60°) become one.
    drop : float
        Fraction in [0, 1): the thinnest segments (by radius rank, then by bracket depth
        when radii are all equal) with everything growing on them are left out.
    """
    g = geometry
    n = g.n_segments
    if n == 0 or (join <= 1 and drop <= 0):
        return g
    par = g.seg_parent
    keep = np.ones(n, bool)
    if drop > 0:
        r = g.seg_radius.max(axis=1).astype(np.float64)
        # thinnest first; equal radii: deepest, then last drawn, first
        order = np.lexsort((-np.arange(n), -g.seg_depth, r))
        cut = np.zeros(n, bool)
        cut[order[: int(drop * n)]] = True
        # a dropped segment takes its whole subtree: propagate along parents
        bad = cut.copy()
        p = par.copy()
        m = p >= 0
        while m.any():
            bad[m] |= bad[p[m]]
            p[m] = p[p[m]]
            m = p >= 0
        keep = ~bad
    # continuation links among the kept segments
    kids = np.bincount(par[(par >= 0) & keep], minlength=n)
    seg = g.seg_end - g.seg_start
    ln = np.linalg.norm(seg, axis=1)
    pp = np.maximum(par, 0)
    cosb = (seg * seg[pp]).sum(1) / np.maximum(ln * ln[pp], 1e-30)
    cont = ((par >= 0) & keep & (kids[pp] == 1) & (g.seg_depth == g.seg_depth[pp])
            & (g.seg_material == g.seg_material[pp]) & (cosb >= cos_limit))
    if g.vertex_colors:
        cont &= np.all(g.seg_color == g.seg_color[pp], axis=1)
    cparent = np.where(cont, par, -1)
    head, pos = _head(cparent)
    k = max(int(join), 1)
    first = np.arange(n)
    for i in range(k - 1):  # walk back to the first segment of each run of k
        first = np.where((pos % k) > i, np.maximum(cparent[first], 0), first)
    first = np.where(keep, first, -1)
    starts = np.flatnonzero(keep & (first == np.arange(n)))
    new_id = np.full(n, -1, np.int64)
    new_id[starts] = np.arange(starts.size)
    group = np.where(keep, new_id[np.maximum(first, 0)], -1)
    # the last segment of each group: the largest position along the axis
    last = np.full(starts.size, -1, np.int64)
    kept = np.flatnonzero(keep)
    order = kept[np.argsort(pos[kept], kind="stable")]
    last[group[order]] = order  # later (farther) writes win
    sp = par[starts]
    new_parent = np.where(sp >= 0, group[np.maximum(sp, 0)], -1)
    return dataclasses.replace(
        g,
        seg_start=g.seg_start[starts], seg_end=g.seg_end[last],
        seg_radius=np.stack([g.seg_radius[starts, 0], g.seg_radius[last, 1]], axis=1),
        seg_color=g.seg_color[starts], seg_material=g.seg_material[starts],
        seg_module=g.seg_module[starts], seg_parent=new_parent,
        seg_depth=g.seg_depth[starts], seg_ref=g.seg_ref[starts],
    )  # fmt: skip


# --------------------------------------------------------------------------- leaf cards
def leaf_cards(pos, normal, axis, size, *, target: int, material_ids=None, colors=None,
               materials=None, keys=None, name: str = "leaf_cards") -> tuple[Mesh, np.ndarray]:
    """Leaves merged into about ``target`` cards (double-sided quads, 2 triangles each).

    The leaves are clustered on a cubic grid whose cell is chosen (by bisection) so that
    about ``target`` cells are occupied; each cluster becomes a square card at its leaves'
    centroid, in the plane of their mean normal (turned up where it points down), one side
    along their mean axis, its area the sum of their blades' (``size²`` each, times 0.6).

    Parameters
    ----------
    pos, normal, axis : float[k, 3]
        Leaf base, blade normal and blade direction (base to tip).
    size : float[k]
        Blade length.
    target : int
        Wanted number of cards (at least 1).
    material_ids : int[k], optional; colors : float[k, 4], optional
        The material and tint of each leaf (each card takes its first leaf's material and
        the mean tint).
    materials : list of Material
    keys : int[k], optional
        What each card's wind phase is hashed from (default: the cluster number).

    Returns
    -------
    mesh : Mesh
        With UVs (the card's square), double-sided materials and a ``WIND`` attribute.
    cluster : int64[k]
        The card of each leaf.
    """
    pos = np.asarray(pos, np.float64).reshape(-1, 3)
    k = pos.shape[0]
    mats = [dataclasses.replace(m, double_sided=True) for m in (materials or [Material("leaf")])]
    if k == 0:
        return Mesh(np.zeros((0, 3)), np.zeros((0, 3)), materials=mats, name=name), np.zeros(
            0, np.int64)
    target = max(int(target), 1)
    lo = pos.min(0)
    ext = float(max(np.ptp(pos, axis=0).max(), 1e-9))

    def cells(h):
        c = np.floor((pos - lo) / h).astype(np.int64)
        return np.unique(c, axis=0, return_inverse=True)[1].ravel()

    a, b = ext / 4096.0, ext * 2.0  # cell sides with too many / too few clusters
    cl = cells(b)
    for _ in range(30):
        mid = math.sqrt(a * b)
        c = cells(mid)
        if c.max() + 1 > target:
            a = mid
        else:
            b, cl = mid, c
        if b / a < 1.05:
            break
    m = int(cl.max()) + 1
    cnt = np.bincount(cl, minlength=m).astype(np.float64)
    centre = np.stack([np.bincount(cl, pos[:, j], m) for j in range(3)], 1) / cnt[:, None]
    nrm = np.asarray(normal, np.float64).reshape(-1, 3).copy()
    nrm[nrm[:, 1] < 0] *= -1.0  # double-sided leaves: one hemisphere, so they do not cancel
    nsum = np.stack([np.bincount(cl, nrm[:, j], m) for j in range(3)], 1)
    ax = np.asarray(axis, np.float64).reshape(-1, 3)
    asum = np.stack([np.bincount(cl, ax[:, j], m) for j in range(3)], 1)
    sz = np.asarray(size, np.float64).ravel()
    area = np.bincount(cl, 0.6 * sz**2, m)
    # the card's centre: halfway along the blades (the base positions are at the stalks)
    centre += np.stack([np.bincount(cl, 0.5 * sz * ax[:, j], m) for j in range(3)], 1) / cnt[
        :, None]
    n_ = nsum / np.maximum(np.linalg.norm(nsum, axis=1, keepdims=True), 1e-12)
    bad = np.linalg.norm(nsum, axis=1) < 1e-9
    n_[bad] = [0.0, 1.0, 0.0]
    # one side along the mean axis projected into the card's plane
    u = asum - (asum * n_).sum(1, keepdims=True) * n_
    un = np.linalg.norm(u, axis=1, keepdims=True)
    alt = np.cross(n_, np.where(np.abs(n_[:, :1]) < 0.9, [[1.0, 0, 0]], [[0, 0, 1.0]]))
    u = np.where(un > 1e-9, u / np.maximum(un, 1e-12), alt / np.linalg.norm(alt, axis=1,
                                                                             keepdims=True))
    v = np.cross(n_, u)
    half = 0.5 * np.sqrt(np.maximum(area, 1e-12))[:, None]
    corners = np.array([[-1, -1], [1, -1], [1, 1], [-1, 1]], np.float64)
    V = (centre[:, None, :] + half[:, None] * (corners[None, :, 0, None] * v[:, None, :]
                                              + corners[None, :, 1, None] * u[:, None, :]))
    N = np.repeat(n_[:, None, :], 4, axis=1)
    UV = np.tile(np.array([[0, 0], [1, 0], [1, 1], [0, 1]], np.float32), (m, 1))
    I = np.array([[0, 1, 2], [0, 2, 3]])[None] + (4 * np.arange(m))[:, None, None]
    first = np.full(m, k, np.int64)
    np.minimum.at(first, cl, np.arange(k))
    mid_ = (np.zeros(k, np.int32) if material_ids is None
            else np.asarray(material_ids, np.int32).ravel())[first]
    C = None
    if colors is not None:
        col = np.asarray(colors, np.float64).reshape(k, -1)
        C = np.stack([np.bincount(cl, col[:, j], m) for j in range(col.shape[1])], 1) / cnt[
            :, None]
        C = np.repeat(C, 4, axis=0)
    kk = np.arange(m) if keys is None else np.asarray(keys, np.int64).ravel()[first]
    wind = wind_attribute(np.zeros(4 * m), np.repeat(phase_of(kk, 7), 4), 1.0,
                          np.tile([0.0, 0.0, 1.0, 1.0], m))
    mesh = Mesh(V.reshape(-1, 3), I.reshape(-1, 3), normals=N.reshape(-1, 3), uvs=UV,
                colors=C, material_ids=np.repeat(mid_, 2), materials=mats, name=name,
                attributes={"WIND": wind})  # fmt: skip
    return mesh, cl


# --------------------------------------------------------------------------- L-system plants
def _plant_wind(geometry: Geometry, seg_of_vertex: np.ndarray) -> np.ndarray:
    """Wind data of branch vertices that belong to segments ``seg_of_vertex``."""
    g = geometry
    ln = np.linalg.norm(g.seg_end - g.seg_start, axis=1)
    reach = path_length(g.seg_parent, ln)
    top = max(float(reach.max()) if reach.size else 1.0, 1e-12)
    # one phase per axis: the head of its chain of same-depth continuations
    par = g.seg_parent
    pp = np.maximum(par, 0)
    cparent = np.where((par >= 0) & (g.seg_depth == g.seg_depth[pp]), par, -1)
    head, _ = _head(cparent)
    per_segment = wind_attribute(g.seg_depth, phase_of(head), reach / top, 0.0)
    return per_segment[seg_of_vertex]


def _mesh_levels(geometry: Geometry, detail, mode, taper):
    """The branch mesh of ``geometry`` with its wind data."""
    from .build import _radii, _sides, _tube_plan, build_branches

    mesh = build_branches(geometry, detail=detail, mode=mode, taper=taper)
    n = geometry.n_segments
    if mode == "tube":
        radius = _radii(geometry, taper, 2.0)
        d = _sides(detail, geometry, mode)
        voff = _tube_plan(geometry, radius, 140.0, geometry.vertex_colors, d)[4]
        seg = np.repeat(np.arange(n), np.diff(voff))
    else:
        seg = np.repeat(np.arange(n), mesh.n_vertices // max(n, 1))
    mesh.attributes = {"WIND": _plant_wind(geometry, seg)}
    return mesh


def _leaf_wind(geometry: Geometry, per_leaf: int, along: np.ndarray) -> np.ndarray:
    """Wind data of the template leaves (``per_leaf`` vertices each, ``along`` their v)."""
    g = geometry
    k = g.n_leaves
    lvl = np.zeros(k)
    flex = np.ones(k)
    if g.n_segments:  # the segment whose end is nearest each leaf's base: its branch
        ends = g.seg_end
        ln = np.linalg.norm(g.seg_end - g.seg_start, axis=1)
        reach = path_length(g.seg_parent, ln)
        near = _nearest(ends, g.leaf_pos)
        lvl = g.seg_depth[near] + 1.0
        flex = reach[near] / max(float(reach.max()), 1e-12)
    rep = np.repeat
    return wind_attribute(rep(lvl, per_leaf), rep(phase_of(np.arange(k), 3), per_leaf),
                          rep(flex, per_leaf), np.tile(along, k))


def _nearest(points: np.ndarray, queries: np.ndarray) -> np.ndarray:
    """Index of the nearest of ``points`` to each query (a k-d tree)."""
    from scipy.spatial import cKDTree

    return cKDTree(points).query(queries)[1].astype(np.int64)


def plant_scene(geometry: Geometry, *, detail=None, mode: str = "tube", taper=None,
                leaves: bool = True, polygons: bool = True) -> Scene:
    """:func:`~sylva.geometry.build.build_mesh`'s scene with ``WIND`` vertex data on the
    branches and leaves."""
    from .build import build_blocks, build_leaves, build_polygons, leaf_template

    g = geometry
    meshes = []
    if g.n_segments:
        meshes.append(_mesh_levels(g, detail, mode, taper))
    if leaves and g.n_leaves:
        m = build_leaves(g)
        tv, tuv, _ = leaf_template()
        m.attributes = {"WIND": _leaf_wind(g, tv.shape[0], tuv[:, 1])}
        meshes.append(m)
    if polygons and g.n_polygons:
        meshes.append(build_polygons(g))
    if g.n_blocks:
        meshes.append(build_blocks(g))
    meshes = [m for m in meshes if m.n_triangles]
    # as build_mesh: a material one-faced surfaces use is double-sided everywhere
    two = {mat.name for m in meshes for mat in m.materials if mat.double_sided}
    for m in meshes:
        m.materials = [dataclasses.replace(mat, double_sided=True)
                       if mat.name in two and not mat.double_sided else mat
                       for mat in m.materials]  # fmt: skip
    return Scene([_prune_materials(m) for m in meshes], name="plant")


def _cards_of(geometry: Geometry, target: int) -> Mesh:
    g = geometry
    fr = g.leaf_frame  # rows H, L, U
    cols = np.concatenate([g.leaf_color, np.ones((g.n_leaves, 1), np.float32)], 1)
    mesh, cl = leaf_cards(g.leaf_pos, fr[:, 2], fr[:, 0], g.leaf_size, target=target,
                          material_ids=g.leaf_material, materials=list(g.materials),
                          colors=cols if g.vertex_colors else None)  # fmt: skip
    if g.n_segments and mesh.n_vertices:
        w = mesh.attributes["WIND"]
        k = int(cl.max()) + 1
        lw = _leaf_wind(g, 1, np.zeros(1))
        lvl = np.bincount(cl, lw[:, 0], k) / np.bincount(cl, minlength=k)
        flex = np.bincount(cl, lw[:, 2], k) / np.bincount(cl, minlength=k)
        w[:, 0] = np.repeat(np.round(lvl), 4)
        w[:, 2] = np.repeat(flex, 4)
    return mesh


def _poly_cards(geometry: Geometry, target: int) -> Mesh:
    """Polygons (leaves drawn with ``{ … }``) merged into cards, as leaves are."""
    g = geometry
    off = g.poly_offsets
    cnt = np.diff(off)
    owner = np.repeat(np.arange(g.n_polygons), cnt)
    pv = g.poly_vertices
    c = np.stack([np.bincount(owner, pv[:, j], g.n_polygons) for j in range(3)], 1)
    c /= np.maximum(cnt, 1)[:, None]
    # Newell normals and the farthest vertex as the blade axis
    nxt = np.arange(pv.shape[0]) + 1
    nxt[off[1:] - 1] = off[:-1]
    cr = np.cross(pv, pv[nxt])
    nrm = np.stack([np.bincount(owner, cr[:, j], g.n_polygons) for j in range(3)], 1)
    area = 0.5 * np.linalg.norm(nrm, axis=1)
    d = pv - c[owner]
    far = np.zeros(g.n_polygons, np.int64)
    dist = np.linalg.norm(d, axis=1)
    order = np.lexsort((dist, owner))
    far[owner[order]] = order
    ax = d[far] / np.maximum(dist[far], 1e-12)[:, None]
    size = np.sqrt(np.maximum(area, 1e-12) / 0.6)
    base = c - 0.5 * size[:, None] * ax
    cols = np.concatenate([g.poly_color, np.ones((g.n_polygons, 1), np.float32)], 1)
    mesh, _ = leaf_cards(base, nrm, ax, size, target=target, material_ids=g.poly_material,
                         materials=list(g.materials), name="polygon_cards",
                         colors=cols if g.vertex_colors else None)  # fmt: skip
    return mesh


def _prune_materials(mesh: Mesh) -> Mesh:
    from .build import _prune

    return _prune(mesh)


def _level_scene(geometry: Geometry, *, detail, mode, taper, join, drop, cards,
                 polygons: bool) -> Scene:
    meshes = []
    g = simplify_segments(geometry, join=join, drop=drop)
    if g.n_segments:
        meshes.append(_mesh_levels(g, detail, mode, taper))
    if geometry.n_leaves and cards:
        meshes.append(_cards_of(geometry, cards))
    if geometry.n_polygons:
        if polygons:
            from .build import build_polygons

            meshes.append(build_polygons(geometry))
        elif cards:
            meshes.append(_poly_cards(geometry, cards))
    meshes = [_prune_materials(m) for m in meshes if m.n_triangles]
    return Scene(meshes, name="plant")


def plant_lods(geometry: Geometry, *, detail: int | None = None, mode: str = "tube",
               taper: str | None = None, levels: int = 3,
               coverage=COVERAGE, budgets=BUDGETS) -> LodChain:
    """The mesh levels of detail of an L-system plant.

    Parameters
    ----------
    geometry : Geometry
        From :func:`sylva.turtle.interpret`.
    detail, mode, taper
        LOD0's branch options (as :func:`~sylva.geometry.build.build_mesh`).
    levels : int
        1, 2 or 3 mesh levels (an impostor is added by :func:`sylva._impostor.add_impostor`).
    coverage : sequence of float
        Screen coverage at which each level starts (see :data:`COVERAGE`).
    budgets : (float, float)
        The largest triangle fractions of LOD0 for LOD1 and LOD2.

    Returns
    -------
    LodChain
        LOD0 is :func:`plant_scene` (with ``WIND`` data); LOD1 has about half the sides,
        runs of 2 segments joined, the thinnest 30 % of twigs dropped and the leaves in
        cards of about 4; LOD2 has 3 sides, runs of 4, half the twigs and cards of about
        40 leaves.  Either is made coarser until it fits its budget.
    """
    n = check_lods(levels, "levels")
    if n > 3:
        raise LodError(f"levels: plant_lods makes 1…3 mesh levels, got {n} (the impostor "
                       "is added by sylva._impostor.add_impostor)")
    cov = _coverage(coverage, n)
    base = plant_scene(geometry, detail=detail, mode=mode, taper=taper)
    out = [LodLevel(base, cov[0])]
    t0 = base.n_triangles
    from .build import _sides

    d0 = _sides(detail, geometry, mode) if geometry.n_segments else 8
    plans = [  # (sides, join, drop, leaves per card), finest first, per level
        [(max(3, d0 // 2), 2, 0.3, 4), (3, 2, 0.4, 6), (3, 3, 0.5, 10), (3, 4, 0.6, 16)],
        [(3, 4, 0.5, 40), (3, 6, 0.6, 80), (3, 8, 0.75, 160), (3, 12, 0.85, 400)],
    ]
    for lv in range(1, n):
        limit = budgets[lv - 1] * t0
        scene = None
        for sides, join, drop, per_card in plans[lv - 1]:
            dd = sides if mode != "prism" or sides >= 3 else 1
            scene = _level_scene(geometry, detail=dd, mode=mode, taper=taper, join=join,
                                 drop=drop, polygons=lv == 1,
                                 cards=max(1, geometry.n_leaves // per_card))  # fmt: skip
            if scene.n_triangles <= limit:
                spare = int(0.8 * (limit - scene.n_triangles) / 2)
                if spare > 0 and (geometry.n_leaves or geometry.n_polygons):
                    more = _level_scene(geometry, detail=dd, mode=mode, taper=taper, join=join,
                                        drop=drop, polygons=lv == 1,
                                        cards=max(1, geometry.n_leaves // per_card) + spare)
                    if more.n_triangles <= limit:  # the spare budget goes to the leaves
                        scene = more
                break
        if scene.n_triangles > limit:  # the last resort: the main axes and few cards
            scene = _level_scene(geometry, detail=3, mode=mode, taper=taper, join=64,
                                 drop=0.95, polygons=False,
                                 cards=max(1, int(limit // 8)))  # fmt: skip
        out.append(LodLevel(scene, cov[lv]))
    return LodChain(_named(out), name="plant")


def _coverage(coverage, n: int) -> list[float]:
    try:
        cov = [float(c) for c in coverage]
    except (TypeError, ValueError):
        raise LodError(f"coverage: expected numbers, got {coverage!r}") from None
    if len(cov) < n:
        raise LodError(f"coverage: expected at least {n} values, got {len(cov)}")
    if any(not 0.0 < c <= 1.0 for c in cov) or any(a <= b for a, b in zip(cov, cov[1:])):
        raise LodError(f"coverage: expected decreasing fractions in (0, 1], got {cov}")
    return cov[:n]

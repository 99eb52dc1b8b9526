"""OpenSCAD source: closed, coloured ``polyhedron`` solids (seed 001's export).

Seed 001 names an OpenSCAD export without describing it.  OpenSCAD renders (F6) and exports
to STL through CGAL, which accepts only closed solids, so the surfaces sylva draws are made
into solids first (:func:`solids`):

* triangles are grouped by the colour they are drawn with (the vertex tint times the
  material colour, :func:`~._common.shaded_colors`, rounded to ``1/levels`` steps per
  channel) and each group becomes one ``color([r, g, b, a]) polyhedron(...)``;
* within a group, vertices at the same place are welded, degenerate and repeated triangles
  dropped;
* one-faced surfaces (leaves and polygons: double-sided materials) are thickened into thin
  slabs (``thickness``, default 0.4 % of the scene's diagonal): the face, a copy pushed
  back along the normals and reversed, and walls along the open edges;
* the open ends of other surfaces (a tube cut where its colour changes) are capped with a
  fan from the middle of each hole.

Every polyhedron is then a closed, consistently oriented 2-manifold (each edge used once in
each direction).  OpenSCAD is Z-up and wants faces clockwise seen from outside: points are
rotated from sylva's Y-up (``(x, y, z) -> (x, -z, y)``, a proper rotation) and faces are
reversed.  sylva's unit is the metre (as the USD writer's ``metersPerUnit = 1`` says) and
OpenSCAD's the millimetre, so ``scale`` defaults to 1000; it also keeps the finest details
of a union well above OpenSCAD's merging grid (about 1e-6 units).

Examples
--------
>>> import io, numpy as np
>>> from sylva.geometry.mesh import Mesh
>>> m = Mesh(np.array([[0, 0, 0], [1, 0, 0], [0, 1, 0], [0, 0, 1]]),
...          np.array([[0, 2, 1], [0, 1, 3], [0, 3, 2], [1, 2, 3]]))
>>> out = io.StringIO(); write_scad(m, out)
>>> out.getvalue().count("polyhedron(")
1
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from ._common import PathOrFile, as_scene, material_of, open_target, shaded_colors, to_up

__all__ = ["ONE_SOLID_ABOVE", "Solid", "solids", "write_scad"]


@dataclass
class Solid:
    """A closed triangle mesh of one colour: ``points`` float64[n, 3] (sylva's frame),
    ``faces`` int64[m, 3] counter-clockwise seen from outside, ``color`` RGBA."""

    color: tuple[float, float, float, float]
    points: np.ndarray
    faces: np.ndarray


def _weld(points: np.ndarray, tris: np.ndarray, tol: float, apart: bool = False):
    """Merge points closer than ``tol`` (on a grid), drop degenerate and repeated triangles;
    with ``apart``, only within each connected piece (leaves that touch stay two)."""
    key = np.round(points / tol).astype(np.int64)
    if apart and len(tris):
        from scipy.sparse import coo_matrix
        from scipy.sparse.csgraph import connected_components

        n = len(points)
        e = np.concatenate([tris[:, [0, 1]], tris[:, [1, 2]]])
        graph = coo_matrix((np.ones(len(e)), (e[:, 0], e[:, 1])), shape=(n, n))
        label = connected_components(graph, directed=False)[1]
        key = np.concatenate([key, label[:, None]], axis=1)
    _, first, inv = np.unique(key, axis=0, return_index=True, return_inverse=True)
    pts = points[first]
    t = inv.reshape(-1)[tris]
    ok = (t[:, 0] != t[:, 1]) & (t[:, 1] != t[:, 2]) & (t[:, 2] != t[:, 0])
    t = t[ok]
    if len(t):
        # a triangle and a rotation of it are the same; keep one
        r = np.argmin(t, axis=1)
        canon = np.stack([t[np.arange(len(t)), (r + k) % 3] for k in range(3)], axis=1)
        _, keep = np.unique(canon, axis=0, return_index=True)
        t = t[np.sort(keep)]
    return pts, t


def _boundary(tris: np.ndarray) -> np.ndarray:
    """Directed edges ``(a, b)`` of ``tris`` whose reverse ``(b, a)`` no triangle has."""
    if len(tris) == 0:
        return np.zeros((0, 2), np.int64)
    e = np.concatenate([tris[:, [0, 1]], tris[:, [1, 2]], tris[:, [2, 0]]])
    n = int(tris.max()) + 1
    code = e[:, 0] * n + e[:, 1]
    rev = e[:, 1] * n + e[:, 0]
    return e[~np.isin(rev, code)]


def _cap(points: np.ndarray, tris: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """Close every hole of ``tris`` with a fan from the hole's centroid."""
    edges = _boundary(tris)
    if len(edges) == 0:
        return points, tris
    nxt: dict[int, list[int]] = {}
    for a, b in edges.tolist():
        nxt.setdefault(a, []).append(b)
    new_pts = [points]
    new_tris = [tris]
    base = len(points)
    for start in list(nxt):
        while nxt.get(start):
            loop = [start]
            cur = nxt[start].pop()
            while cur != start and nxt.get(cur):
                loop.append(cur)
                cur = nxt[cur].pop()
            if cur != start or len(loop) < 2:
                continue  # an open chain (non-manifold input): nothing to fan
            c = points[loop].mean(axis=0)
            new_pts.append(c[None, :])
            ring = np.array(loop + [loop[0]])
            # the hole's edge a -> b is met by the cap's b -> a
            new_tris.append(np.stack([ring[1:], ring[:-1], np.full(len(loop), base)], axis=1))
            base += 1
    return np.concatenate(new_pts), np.concatenate(new_tris)


def _thicken(points: np.ndarray, tris: np.ndarray, thickness: float):
    """A one-faced sheet as a closed slab: the face pushed ``thickness / 2`` out along the
    vertex normals, a reversed copy as far in, and a wall of two triangles on every open
    edge.  (Centred, so that sheets meeting at a point, as leaves on one node, and the cap
    of the stalk they sit on keep apart: OpenSCAD merges points at the same place.)"""
    tri = points[tris]
    fn = np.cross(tri[:, 1] - tri[:, 0], tri[:, 2] - tri[:, 0])
    vn = np.zeros_like(points)
    for k in range(3):
        np.add.at(vn, tris[:, k], fn)
    ln = np.linalg.norm(vn, axis=1, keepdims=True)
    vn = np.divide(vn, ln, out=np.zeros_like(vn), where=ln > 0)
    n = len(points)
    front = points + vn * (thickness / 2)
    back = points - vn * (thickness / 2)
    walls = _boundary(tris)  # a -> b on the front: wall (b, a, a'), (b, a', b')
    a, b = walls[:, 0], walls[:, 1]
    side = np.concatenate([np.stack([b, a, a + n], 1), np.stack([b, a + n, b + n], 1)])
    faces = np.concatenate([tris, tris[:, ::-1] + n, side])
    return np.concatenate([front, back]), faces


def _union(points: np.ndarray, tris: np.ndarray, tol: float) -> tuple[np.ndarray, np.ndarray]:
    """The union of the closed shells of ``tris`` (they may cross one another: a twig
    inside its branch, leaves through a stem), by the ``manifold3d`` boolean kernel, so
    that the solid CGAL gets is one valid 2-manifold.  Points closer than ``tol`` are
    merged (manifold's simplification keeps it a manifold): OpenSCAD would merge points
    closer than its grid (about 1e-6) and break the solid."""
    import manifold3d as mf
    from scipy.sparse import coo_matrix
    from scipy.sparse.csgraph import connected_components

    n = len(points)
    e = np.concatenate([tris[:, [0, 1]], tris[:, [1, 2]]])
    graph = coo_matrix((np.ones(len(e)), (e[:, 0], e[:, 1])), shape=(n, n))
    label = connected_components(graph, directed=False)[1][tris[:, 0]]
    order = np.argsort(label, kind="stable")
    cuts = np.flatnonzero(np.diff(label[order])) + 1
    shells = []
    for part in np.split(order, cuts):
        t = tris[part]
        used, local = np.unique(t, return_inverse=True)
        m = mf.Manifold(mf.Mesh(vert_properties=points[used].astype(np.float32),
                                tri_verts=local.reshape(-1, 3).astype(np.uint32)))  # fmt: skip
        if m.status() == mf.Error.NoError and not m.is_empty():
            shells.append(m)
    if not shells:
        return np.zeros((0, 3)), np.zeros((0, 3), np.int64)
    whole = mf.Manifold.batch_boolean(shells, mf.OpType.Add) if len(shells) > 1 else shells[0]
    mesh = whole.as_original().simplify(tol).to_mesh64()
    return (np.asarray(mesh.vert_properties, np.float64)[:, :3],
            np.asarray(mesh.tri_verts, np.int64))  # fmt: skip


def _clusters(colors: np.ndarray, spread: float) -> np.ndarray:
    """A cluster number per row of ``colors`` (RGBA): greedily, the most common colours
    first, each joins the first cluster whose seed is within ``spread`` (RGB distance)."""
    q = np.round(colors * 32).astype(np.int64)
    uniq, inv, counts = np.unique(q, axis=0, return_inverse=True, return_counts=True)
    seeds: list[np.ndarray] = []
    label = np.empty(len(uniq), np.int64)
    for u in np.argsort(-counts, kind="stable"):
        c = uniq[u] / 32.0
        for k, sd in enumerate(seeds):
            if np.linalg.norm(c[:3] - sd[:3]) <= spread and c[3] == sd[3]:
                label[u] = k
                break
        else:
            label[u] = len(seeds)
            seeds.append(c)
    return label[inv.reshape(-1)]


def solids(scene, *, thickness: float | None = None, spread: float = 0.2) -> list[Solid]:
    """The closed solids that :func:`write_scad` writes, one per colour (see the module
    docstring).  Triangles whose colours lie within ``spread`` of one another (RGB
    distance: the tints of one leaf colour) are one solid, drawn in their mean colour; few
    solids keep CGAL's union of them, the slow part of OpenSCAD's render, short."""
    scene = as_scene(scene)
    lo, hi = scene.bounds().astype(np.float64)
    diag = float(np.linalg.norm(hi - lo)) or 1.0
    tol = diag * 1e-7
    if thickness is None:
        thickness = diag * 0.004
    meshes = [m for m in scene.meshes if m.n_triangles]
    cols = [shaded_colors(m)[m.indices[:, 0]] for m in meshes]
    if not meshes:
        return []
    label = np.split(_clusters(np.concatenate(cols), spread),
                     np.cumsum([m.n_triangles for m in meshes])[:-1])  # fmt: skip
    groups: dict[int, list[tuple[np.ndarray, np.ndarray, bool]]] = {}
    paint: dict[int, list[np.ndarray]] = {}
    for mesh, col, lab in zip(meshes, cols, label):
        sheet_mat = np.array([material_of(mesh, i).double_sided
                              for i in range(len(mesh.materials))] + [False])  # fmt: skip
        sheet = sheet_mat[np.minimum(mesh.triangle_materials(), len(mesh.materials))]
        for g in np.unique(lab):
            for flat in (False, True):
                sel = np.flatnonzero((lab == g) & (sheet == flat))
                if len(sel) == 0:
                    continue
                used, local = np.unique(mesh.indices[sel].astype(np.int64), return_inverse=True)
                pts = mesh.vertices[used].astype(np.float64)
                groups.setdefault(int(g), []).append((pts, local.reshape(-1, 3), flat))
                paint.setdefault(int(g), []).append(col[sel])
    out = []
    for key, parts in groups.items():
        all_pts, all_faces, base = [], [], 0
        for sheet in (False, True):
            chunk = [(p, t) for p, t, s in parts if s == sheet]
            if not chunk:
                continue
            offs = np.cumsum([0] + [len(p) for p, _ in chunk])
            pts = np.concatenate([p for p, _ in chunk])
            tris = np.concatenate([t + o for (_, t), o in zip(chunk, offs)])
            pts, tris = _weld(pts, tris, tol, apart=sheet)
            pts, tris = _thicken(pts, tris, thickness) if sheet else _cap(pts, tris)
            all_pts.append(pts)
            all_faces.append(tris + base)
            base += len(pts)
        color = tuple(float(c) for c in np.concatenate(paint[key]).mean(axis=0))
        pts, faces = _union(np.concatenate(all_pts), np.concatenate(all_faces), diag * 1e-5)
        if len(faces):
            out.append(Solid(color, pts, faces))  # type: ignore[arg-type]
    return out


#: Above this many faces the colour solids are written as one (:func:`write_scad`).
ONE_SOLID_ABOVE = 100_000


def _one_solid(parts: list[Solid], scene) -> tuple[list[Solid], str]:
    """``parts`` unioned into one solid in the colour of the largest, and what the file's
    header says about it."""
    offs = np.cumsum([0] + [len(p.points) for p in parts])
    pts = np.concatenate([p.points for p in parts])
    faces = np.concatenate([p.faces + o for p, o in zip(parts, offs)])
    lo, hi = scene.bounds().astype(np.float64)
    diag = float(np.linalg.norm(hi - lo)) or 1.0
    pts, faces = _union(pts, faces, diag * 1e-5)
    big = max(parts, key=lambda p: len(p.faces))
    colours = "; ".join("[" + ",".join(f"{c:.3g}" for c in p.color) + "]" for p in parts)
    note = (f"the {len(parts)} colour solids ({colours}) unioned into one in the colour of "
            "the largest: OpenSCAD 2021's own union of solids this large fails")
    return [Solid(big.color, pts, faces)], note


_GRID = 2.0**-20  # OpenSCAD 2021 rounds points to this grid before it makes a CGAL solid


def _separate(pts: np.ndarray, faces: np.ndarray, grid: float = _GRID) -> np.ndarray:
    """Move apart the distinct vertices that OpenSCAD's grid would merge into one.

    A union may leave two parts touching at a point or nearly so (two vertices a hair
    apart); OpenSCAD snaps both to one grid point, the solid pinches there and CGAL
    refuses it ("mesh is not closed").  Each such vertex is slid a few grid steps
    towards the middle of its own neighbours, which parts them (a move of a few
    millionths of a unit)."""
    pts = pts.copy()
    if len(faces) == 0:
        return pts
    nbr = np.zeros_like(pts)
    deg = np.zeros(len(pts))
    for a, b in ((0, 1), (1, 2), (2, 0), (1, 0), (2, 1), (0, 2)):
        np.add.at(nbr, faces[:, a], pts[faces[:, b]])
        np.add.at(deg, faces[:, a], 1.0)
    centre = nbr / np.maximum(deg, 1.0)[:, None]
    from scipy.spatial import cKDTree

    rng = np.random.default_rng(0)
    for k in range(10):
        # OpenSCAD snaps a point onto an occupied grid point up to one step away on each
        # axis, so points within 2 steps (Chebyshev) can become one
        pairs = cKDTree(pts).query_pairs(3 * grid, p=np.inf, output_type="ndarray")
        if len(pairs) == 0:
            break
        clash = np.unique(pairs.reshape(-1))
        if k < 4:
            d = centre[clash] - pts[clash]
            ln = np.linalg.norm(d, axis=1, keepdims=True)
            pts[clash] += d * np.minimum(1.0, 16 * grid / np.maximum(ln, 1e-300))
        else:  # neighbours as close as the points themselves: part them at random
            pts[clash] += rng.normal(size=(len(clash), 3)) * 8 * grid
    return pts


def _list(fmt: str, arr: np.ndarray) -> str:
    if arr.shape[0] == 0:
        return "[]"
    item = "[" + ",".join([fmt] * arr.shape[1]) + "]"
    return "[" + ",".join([item] * arr.shape[0]) % tuple(arr.reshape(-1).tolist()) + "]"


def write_scad(
    scene,
    target: PathOrFile,
    *,
    scale: float = 1000.0,
    convexity: int = 10,
    thickness: float | None = None,
    up: str = "z",
    one_solid_above: int | None = ONE_SOLID_ABOVE,
) -> None:
    """Write an OpenSCAD file to a path or a text file object.

    Parameters
    ----------
    scale : float
        Multiplies every coordinate: 1000 (the default) writes sylva's metres as
        OpenSCAD's millimetres.
    convexity : int
        OpenSCAD's preview hint.
    thickness : float, optional
        Of leaves and polygons, in scene units (default 0.4 % of the scene's diagonal).
    up : {"z", "y"}
        OpenSCAD's convention is Z up.
    one_solid_above : int or None
        When the colour solids have more faces than this together, they are unioned here
        (``manifold3d``) into one solid in the colour of the largest: OpenSCAD 2021's own
        union of them (CGAL, at every render) ends in an assertion for a full-size tree,
        while one polyhedron renders and exports at once.  ``None`` keeps one solid per
        colour at any size.  The file's header says which it did.
    """
    scene = as_scene(scene)
    parts = solids(scene, thickness=thickness)
    note = "one per colour"
    if (one_solid_above is not None and len(parts) > 1
            and sum(len(p.faces) for p in parts) > one_solid_above):  # fmt: skip
        parts, note = _one_solid(parts, scene)
    with open_target(target, binary=False) as fh:
        fh.write(f"// sylva: {scene.name}\n// {up.upper()} up; {scene.n_triangles} triangles "
                 f"as {len(parts)} closed solid{'s' if len(parts) != 1 else ''}, "
                 f"{note}\nunion() {{\n")  # fmt: skip
        for s in parts:
            pts = _separate(to_up(s.points * scale, up), s.faces)
            r, g, b, a = s.color
            fh.write(f"  color([{r:.4g},{g:.4g},{b:.4g},{a:.4g}]) polyhedron(\n")
            fh.write("    points=" + _list("%.17g", pts) + ",\n")
            fh.write("    faces=" + _list("%d", s.faces[:, ::-1]) +
                     f",\n    convexity={convexity});\n")  # fmt: skip
        fh.write("}\n")

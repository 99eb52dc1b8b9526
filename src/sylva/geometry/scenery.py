"""Meshes of cpfg's background scene primitives (the cpfg manual §8.3).

:func:`scenery_mesh` turns the primitives that ``sylva.lsystem.dialects._cpfg_scene``
reads from a ``background scene:`` file (each a kind, its numbers, its local-to-world
matrix and its material) into one mesh named ``background``: polygons fanned from their
first vertex (as cpfg draws them), quads of meshes, rectangles and boxes, cones and
cylinders along local y with their caps, and spheres, every vertex through its matrix
(normals through its inverse transpose).  Each material command becomes a material
``background_k``: the diffuse plus emissive colour (sRGB in the file, linear here), the
diffuse alpha, a roughness from the specular exponent; all are double-sided, as cpfg lights
both faces of its background polygons.

Examples
--------
>>> ident = (1.0, 0, 0, 0, 0, 1, 0, 0, 0, 0, 1, 0, 0, 0, 0, 1)
>>> m = scenery_mesh([("box", (1.0, 2.0, 3.0), ident, None)])
>>> m.name, m.n_triangles, m.bounds().tolist()
('background', 12, [[0.0, 0.0, 0.0], [1.0, 2.0, 3.0]])
"""

from __future__ import annotations

import numpy as np

from .colormaps import srgb_to_linear
from .mesh import Material, Mesh

__all__ = ["scenery_mesh"]

#: Sides around cones and cylinders, and the rings of a sphere (twice as many segments).
DETAIL = 16


def _fan(n: int) -> np.ndarray:
    return np.stack([np.zeros(n - 2, np.int64), np.arange(1, n - 1), np.arange(2, n)], 1)


def _flat(v: np.ndarray, tris: np.ndarray) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """Vertices repeated per triangle with the triangle's normal (flat shading)."""
    p = v[tris.reshape(-1)]
    a, b, c = p[0::3], p[1::3], p[2::3]
    n = np.cross(b - a, c - a)
    n /= np.maximum(np.linalg.norm(n, axis=1, keepdims=True), 1e-30)
    return p, np.repeat(n, 3, axis=0), np.arange(p.shape[0]).reshape(-1, 3)


def _box(a: float, b: float, c: float):
    corners = np.array([[x * a, y * b, z * c] for x in (0, 1) for y in (0, 1) for z in (0, 1)],
                       np.float64)  # fmt: skip
    faces = [(0, 1, 3, 2), (4, 6, 7, 5), (0, 4, 5, 1), (2, 3, 7, 6), (0, 2, 6, 4), (1, 5, 7, 3)]
    tris = np.array([t for f in faces for t in ((f[0], f[1], f[2]), (f[0], f[2], f[3]))])
    return _flat(corners, tris)


def _cone(r1: float, r2: float, h: float, sides: int = DETAIL):
    a = np.linspace(0.0, 2.0 * np.pi, sides, endpoint=False)
    ring = np.stack([np.cos(a), np.zeros(sides), -np.sin(a)], 1)
    bottom, top = ring * r1, ring * r2 + [0.0, h, 0.0]
    v = np.concatenate([bottom, top])
    slope = (r1 - r2) / h if h else 0.0
    nrm = ring + [0.0, slope, 0.0]
    nrm /= np.linalg.norm(nrm, axis=1, keepdims=True)
    k = np.arange(sides)
    j = (k + 1) % sides
    side = np.concatenate([np.stack([k, j, k + sides], 1), np.stack([j, j + sides, k + sides], 1)])
    pv, pn, pt = [v], [np.concatenate([nrm, nrm])], [side]
    base = 2 * sides
    for y, r, up in ((0.0, r1, -1.0), (h, r2, 1.0)):  # the caps (cpfg's Circle3D discs)
        if r <= 0.0:
            continue
        cap = np.concatenate([[[0.0, y, 0.0]], ring * r + [0.0, y, 0.0]])
        fan = np.stack([np.zeros(sides, np.int64), 1 + k, 1 + j], 1)
        pv.append(cap)
        pn.append(np.tile([0.0, up, 0.0], (sides + 1, 1)))
        pt.append((fan if up > 0 else fan[:, ::-1]) + base)
        base += sides + 1
    return np.concatenate(pv), np.concatenate(pn), np.concatenate(pt)


def _sphere(r: float, rings: int = DETAIL):
    segs = 2 * rings
    th = np.linspace(0.0, np.pi, rings + 1)[:, None]
    ph = np.linspace(0.0, 2.0 * np.pi, segs + 1)[None, :]
    n = np.stack([np.sin(th) * np.cos(ph), np.cos(th) + 0 * ph, -np.sin(th) * np.sin(ph)], -1)
    n = n.reshape(-1, 3)
    q = (np.arange(rings)[:, None] * (segs + 1) + np.arange(segs)[None, :]).ravel()
    tris = np.concatenate([np.stack([q, q + segs + 1, q + 1], 1),
                           np.stack([q + 1, q + segs + 1, q + segs + 2], 1)])  # fmt: skip
    return n * r, n.copy(), tris


def _primitive(kind: str, p: tuple[float, ...]):
    """``(vertices, normals, triangles)`` of one primitive in its local frame."""
    if kind == "polygon":
        v = np.asarray(p, np.float64).reshape(-1, 3)
        return _flat(v, _fan(v.shape[0]))
    if kind == "polygonuv":
        vn = np.asarray(p, np.float64).reshape(-1, 6)
        return vn[:, :3], vn[:, 3:], _fan(vn.shape[0])
    if kind == "rectangle":
        a, b = p[0], p[1]
        x, y = (p[2], p[3]) if len(p) >= 4 else (0.0, 0.0)
        v = np.array([[x, y, 0], [x + a, y, 0], [x + a, y + b, 0], [x, y + b, 0]], np.float64)
        return _flat(v, _fan(4))
    if kind == "mesh":
        v = np.asarray(p, np.float64).reshape(-1, 3)
        i = np.arange(0, v.shape[0] - 2, 2)
        tris = np.concatenate([np.stack([i, i + 2, i + 3], 1), np.stack([i, i + 3, i + 1], 1)])
        return _flat(v, tris)
    if kind == "box":
        return _box(*p[:3])
    if kind == "cone":
        return _cone(p[0], p[1], p[2])
    if kind == "cylinder":
        return _cone(p[0], p[0], p[1])
    if kind == "sphere":
        return _sphere(p[0])
    raise ValueError(f"unknown background primitive {kind!r}")


def _material(values, k: int, default: tuple[float, ...]) -> Material:
    if values is None:
        return Material("background", default, roughness=0.8, double_sided=True)
    v = list(values) + [0.0] * (17 - len(values))
    diffuse = np.asarray(v[4:7] if len(values) >= 8 else v[0:3], np.float64)
    emissive = np.asarray(v[12:15] if len(values) >= 16 else [0.0] * 3, np.float64)
    alpha = float(v[7]) if len(values) >= 8 else 1.0
    rgb = srgb_to_linear(np.clip(diffuse + emissive, 0.0, 1.0))
    rough = float(np.sqrt(2.0 / (max(float(v[16]), 0.0) + 2.0))) if len(values) >= 17 else 0.8
    return Material(f"background_{k}", (*map(float, rgb), float(np.clip(alpha, 0.0, 1.0))),
                    roughness=rough, double_sided=True)  # fmt: skip


def scenery_mesh(primitives, default_color=(0.8, 0.8, 0.8, 1.0)) -> Mesh:
    """One mesh, named ``background``, of background scene ``primitives`` (``(kind, params,
    matrix, material)`` each, as ``sylva.lsystem.dialects._cpfg_scene.Primitive``); those
    before any material take ``default_color`` (linear RGBA).

    Returns
    -------
    Mesh
        Flat-shaded where cpfg shades flat (polygons, meshes, boxes), smooth on cones,
        cylinders and spheres; one double-sided material per material command.
    """
    verts, norms, tris, mids = [], [], [], []
    materials: list[Material] = []
    index: dict = {}
    base = 0
    for kind, params, matrix, material in primitives:
        v, n, t = _primitive(kind, tuple(params))
        m = np.asarray(matrix, np.float64).reshape(4, 4)
        v = v @ m[:3, :3].T + m[:3, 3]
        lin = m[:3, :3]
        det = np.linalg.det(lin)
        if abs(det) > 1e-300:
            n = n @ np.linalg.inv(lin)  # the inverse transpose, on row vectors
            if det < 0:  # a mirroring matrix turns the triangles over
                t = t[:, ::-1]
        n /= np.maximum(np.linalg.norm(n, axis=1, keepdims=True), 1e-30)
        key = None if material is None else tuple(material)
        if key not in index:
            index[key] = len(materials)
            materials.append(_material(material, len(materials), tuple(default_color)))
        verts.append(v)
        norms.append(n)
        tris.append(t + base)
        mids.append(np.full(t.shape[0], index[key], np.int32))
        base += v.shape[0]
    if not verts:
        return Mesh(np.zeros((0, 3)), np.zeros((0, 3), np.int64), name="background",
                    materials=[_material(None, 0, tuple(default_color))])  # fmt: skip
    return Mesh(np.concatenate(verts), np.concatenate(tris), normals=np.concatenate(norms),
                material_ids=np.concatenate(mids), materials=materials,
                name="background")  # fmt: skip

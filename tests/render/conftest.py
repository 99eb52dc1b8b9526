"""Shared scenes and helpers for the renderer tests (all rendering runs on the shared context).

Images are small: llvmpipe renders them on the CPU.
"""

from __future__ import annotations

from types import SimpleNamespace

import numpy as np
import pytest

from sylva.geometry.mesh import Material, Mesh, Scene
from sylva.render.camera import Camera
from sylva.render.context import get_context

BLACK = Material("black", color=(0.0, 0.0, 0.0, 1.0), roughness=1.0)


def frustum(p0, p1, r0, r1, sections=24, material=BLACK, caps=True) -> Mesh:
    """A closed truncated cone from ``p0`` (radius ``r0``) to ``p1`` (radius ``r1``).

    ``uvs``: u around (0..1), v along (0 at ``p0``, 1 at ``p1``).
    """
    p0, p1 = np.asarray(p0, float), np.asarray(p1, float)
    axis = p1 - p0
    length = np.linalg.norm(axis)
    a = axis / length
    helper = np.array([1.0, 0, 0]) if abs(a[0]) < 0.9 else np.array([0, 0, 1.0])
    e1 = np.cross(a, helper)
    e1 /= np.linalg.norm(e1)
    e2 = np.cross(a, e1)  # e1 × e2 = a
    k = np.arange(sections + 1)
    t = 2 * np.pi * k / sections
    ring = np.cos(t)[:, None] * e1 + np.sin(t)[:, None] * e2
    bottom = p0 + r0 * ring
    top = p1 + r1 * ring
    verts = [bottom, top]
    u = k / sections
    uvs = [np.c_[u, np.zeros_like(u)], np.c_[u, np.ones_like(u)]]
    n = sections + 1
    faces = []
    for i in range(sections):
        # counter-clockwise seen from outside (the ring turns from e1 to e2, i.e. about +a)
        faces += [[i, i + 1, n + i + 1], [i, n + i + 1, n + i]]
    if caps:
        base = 2 * n
        verts += [p0[None], p1[None]]
        uvs += [np.zeros((1, 2)), np.array([[0.0, 1.0]])]
        for i in range(sections):
            faces.append([base, i + 1, i])  # bottom cap faces -a
            faces.append([base + 1, n + i, n + i + 1])  # top cap faces +a
    v = np.concatenate(verts)
    return Mesh(v, np.array(faces), uvs=np.concatenate(uvs), materials=[material])


def box(lo, hi, material=BLACK) -> Mesh:
    """An axis-aligned closed box with outward (counter-clockwise) faces and flat normals."""
    lo, hi = np.asarray(lo, float), np.asarray(hi, float)
    verts, faces, normals = [], [], []
    for axis in range(3):
        for side in (0, 1):
            n = np.zeros(3)
            n[axis] = 1 if side else -1
            u_axis, v_axis = (axis + 1) % 3, (axis + 2) % 3
            quad = []
            for du, dv in ((0, 0), (1, 0), (1, 1), (0, 1)):
                p = lo.copy()
                p[axis] = hi[axis] if side else lo[axis]
                p[u_axis] = hi[u_axis] if du else lo[u_axis]
                p[v_axis] = hi[v_axis] if dv else lo[v_axis]
                quad.append(p)
            base = len(verts)
            verts += quad
            normals += [n] * 4
            tri = [[0, 1, 2], [0, 2, 3]] if side else [[0, 2, 1], [0, 3, 2]]
            faces += [[base + a, base + b, base + c] for a, b, c in tri]
    return Mesh(np.array(verts), np.array(faces), normals=np.array(normals), materials=[material])


def small_plant(material=BLACK) -> Scene:
    """A trunk with three tapered branches and a box: a stand-in for a turtle plant."""
    parts = [frustum((0, 0, 0), (0, 2.0, 0), 0.22, 0.16, material=material)]
    for k, (dx, dz) in enumerate(((0.9, 0.2), (-0.7, 0.5), (0.1, -0.9))):
        h = 1.0 + 0.4 * k
        parts.append(frustum((0, h, 0), (dx, h + 0.9, dz), 0.12, 0.07, material=material))
    parts.append(box((-0.3, 2.0, -0.3), (0.3, 2.5, 0.3), material=material))
    return Scene(parts)


def silhouette(scene: Scene, camera: Camera, size) -> np.ndarray:
    """Boolean coverage ``(h, w)`` of the projected triangles, sampled at pixel centres.

    An exact CPU rasteriser (edge functions), independent of OpenGL: the reference the rendered
    silhouette is compared with.
    """
    w, h = size
    mesh = scene.merged()
    m = camera.projection_matrix(w / h, *camera.clip_planes(mesh.bounds())) @ camera.view_matrix()
    hv = np.c_[mesh.vertices.astype(float), np.ones(mesh.n_vertices)] @ m.T
    ndc = hv[:, :2] / hv[:, 3:4]
    px = (ndc[:, 0] + 1) / 2 * w  # pixel (i, j) has its centre at (i + 0.5, j + 0.5)
    py = (1 - ndc[:, 1]) / 2 * h
    out = np.zeros((h, w), bool)
    for tri in mesh.indices:
        x, y = px[tri], py[tri]
        i0, i1 = max(int(np.floor(x.min())), 0), min(int(np.ceil(x.max())), w)
        j0, j1 = max(int(np.floor(y.min())), 0), min(int(np.ceil(y.max())), h)
        if i0 >= i1 or j0 >= j1:
            continue
        cx, cy = np.meshgrid(np.arange(i0, i1) + 0.5, np.arange(j0, j1) + 0.5)
        e = [
            (x[(k + 1) % 3] - x[k]) * (cy - y[k]) - (y[(k + 1) % 3] - y[k]) * (cx - x[k])
            for k in range(3)
        ]
        pos = (e[0] >= 0) & (e[1] >= 0) & (e[2] >= 0)
        neg = (e[0] <= 0) & (e[1] <= 0) & (e[2] <= 0)
        inside = pos | neg
        out[j0:j1, i0:i1] |= inside
    return out


def iou(a: np.ndarray, b: np.ndarray) -> float:
    return float(np.logical_and(a, b).sum() / max(np.logical_or(a, b).sum(), 1))


@pytest.fixture(scope="session")
def geo():
    """The helpers above (test modules cannot import conftest under importlib import mode)."""
    return SimpleNamespace(
        BLACK=BLACK,
        box=box,
        frustum=frustum,
        small_plant=small_plant,
        silhouette=silhouette,
        iou=iou,
    )


@pytest.fixture(scope="session")
def ctx():
    return get_context()


@pytest.fixture(scope="session")
def plant() -> Scene:
    return small_plant()

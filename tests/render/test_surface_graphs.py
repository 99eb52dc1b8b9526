"""Bark and leaf are texture graphs (issue 22, GLSL from the same graph): the renderer runs
the graphs' GLSL on plant surfaces and the exports bake the same graphs on the CPU, so a
rendered stem shows, pixel for pixel, the CPU's values at that pixel's (u, v)."""

from __future__ import annotations

import numpy as np
import pytest

from sylva.assets import _bake_fields, _surface_fields
from sylva.geometry.mesh import Material, Mesh, Scene
from sylva.render import Camera, render_array
from sylva.texture.graph.surface import bark_graph, evaluate_uv, leaf_graph
from sylva.tree.stem import Stem, stems_to_arrays

BARK = Material("bark", color=(0.40, 0.26, 0.14, 1.0), texture="bark")
LEAF = Material("leaf", color=(0.12, 0.40, 0.08, 1.0), texture="leaf", double_sided=True)
SIZE = (96, 160)  # (w, h)


def _pixel_uvs(mesh: Mesh, camera: Camera, size):
    """Per pixel centre, the (u, v) of the nearest triangle covering it (an exact CPU
    rasteriser: barycentric interpolation, linear under an orthographic camera), and
    whether the pixel lies two pixels or more inside the silhouette."""
    w, h = size
    m = camera.projection_matrix(w / h, *camera.clip_planes(mesh.bounds())) @ camera.view_matrix()
    hv = np.c_[mesh.vertices.astype(float), np.ones(mesh.n_vertices)] @ m.T
    ndc = hv[:, :3] / hv[:, 3:4]
    px, py, pz = (ndc[:, 0] + 1) / 2 * w, (1 - ndc[:, 1]) / 2 * h, ndc[:, 2]
    uv = np.zeros((h, w, 2))
    depth = np.full((h, w), np.inf)
    cx, cy = np.meshgrid(np.arange(w) + 0.5, np.arange(h) + 0.5)
    for a, b, c in mesh.indices:
        det = (px[b] - px[a]) * (py[c] - py[a]) - (px[c] - px[a]) * (py[b] - py[a])
        if abs(det) < 1e-12:
            continue
        wb = ((cx - px[a]) * (py[c] - py[a]) - (px[c] - px[a]) * (cy - py[a])) / det
        wc = ((px[b] - px[a]) * (cy - py[a]) - (cx - px[a]) * (py[b] - py[a])) / det
        wa = 1.0 - wb - wc
        inside = (wa >= 0) & (wb >= 0) & (wc >= 0)
        z = wa * pz[a] + wb * pz[b] + wc * pz[c]
        near = inside & (z < depth)
        depth[near] = z[near]
        for k in range(2):
            val = wa * mesh.uvs[a, k] + wb * mesh.uvs[b, k] + wc * mesh.uvs[c, k]
            uv[..., k][near] = val[near]
    cover = np.isfinite(depth)
    core = cover.copy()
    for _ in range(2):  # off the silhouette, where coverage decides a pixel
        core[1:-1, 1:-1] &= core[:-2, 1:-1] & core[2:, 1:-1] & core[1:-1, :-2] & core[1:-1, 2:]
        core[[0, -1], :] = False
        core[:, [0, -1]] = False
    return uv, core


def _srgb8(linear):
    """The renderer's output of a linear colour: gamma 2.2, then the 8-bit framebuffer."""
    return np.round(np.clip(linear, 0.0, 1.0) ** (1 / 2.2) * 255.0)


def _stem():
    s = Stem(sides=48)
    y = np.linspace(0.0, 3.0, 33)
    s.add_points(np.c_[np.zeros_like(y), y, np.zeros_like(y)], None, np.full_like(y, 0.3))
    v, n, uv, tri, _, _ = stems_to_arrays([s])
    return Mesh(v, tri, normals=n, uvs=uv, materials=[BARK])


def _compare(mesh, material, camera, combine):
    got = render_array(Scene([mesh]), SIZE, camera, lit=False, msaa=0)[..., :3].astype(float)
    uv, core = _pixel_uvs(mesh, camera, SIZE)
    assert core.sum() > 2000  # most of the stem's face is compared
    graph = bark_graph() if material is BARK else leaf_graph()
    t = evaluate_uv(graph, uv[core][:, 0], uv[core][:, 1])  # float64, the export's kernel
    want = _srgb8(combine(np.asarray(material.color[:3]), t))
    diff = np.abs(got[core] - want)
    # float32 on the GPU against float64 on the CPU: at most one 8-bit step, and exact almost
    # everywhere (a different pattern would differ by tens of steps)
    assert diff.max() <= 1.0, diff.max()
    assert (diff > 0).mean() < 0.05
    return got[core]


def test_rendered_bark_stem_is_the_cpu_bark_graph_at_each_pixels_uv():
    mesh = _stem()
    cam = Camera(mode="2d", target=(0.0, 1.5, 0.0), height=3.2, distance=10)
    got = _compare(mesh, BARK, cam, lambda base, t: base * t[:, :1])
    assert got.std() > 5  # cracks and stripes, not a flat colour


def test_rendered_leaf_is_the_cpu_leaf_graph_at_each_pixels_uv():
    quad = Mesh(np.array([[-0.5, 0, 0], [0.5, 0, 0], [0.5, 2, 0], [-0.5, 2, 0]], float),
                np.array([[0, 1, 2], [0, 2, 3]]), normals=np.tile([0.0, 0.0, 1.0], (4, 1)),
                uvs=np.array([[0, 0], [1, 0], [1, 1], [0, 1]], float), materials=[LEAF])
    cam = Camera(mode="2d", target=(0.0, 1.0, 0.0), height=2.2, distance=10)

    def combine(base, t):
        bright = np.minimum(base * 1.7 + (0.06, 0.07, 0.03), 1.0)
        return base * t[:, :1] + t[:, 1:2] * (bright - base * t[:, :1])

    got = _compare(quad, LEAF, cam, combine)
    assert got.std() > 5  # veins


@pytest.mark.parametrize("tex,kind", [("bark", 2), ("leaf", 3)])
def test_the_gpu_bake_equals_the_cpu_bake(tex, kind):
    """``render/shaders/bake.frag.glsl`` (the graphs' GLSL at the pixel centres) against the
    CPU kernel the exports use, as float fields."""
    color = (0.3, 0.22, 0.15)
    gpu_rgba, gpu_h = _bake_fields(kind, color, 32)
    cpu_rgba, cpu_h = _surface_fields(tex, color, 32)
    assert cpu_h.std() > 0.05
    np.testing.assert_allclose(gpu_rgba, cpu_rgba, atol=1e-4)
    np.testing.assert_allclose(gpu_h, cpu_h, atol=1e-4)

"""Bark that follows the stem (issue 18, item 5): the procedural bark is laid in the stem's
own coordinates (u around, v along in circumferences of the stem's base radius), so a trunk
and a twig do not share one grain size, in the tree mesher's uvs and in the renderer."""

from __future__ import annotations

import numpy as np
import pytest

from sylva.geometry.mesh import Material, Mesh, Scene
from sylva.render import Camera, render_array
from sylva.tree.stem import Stem, stems_to_arrays

BARK = Material("bark", color=(0.40, 0.26, 0.14, 1.0), texture="bark")
LENGTH = 4.0
RADII = (0.5, 0.125)


def _stems():
    stems = []
    for k, r in enumerate(RADII):
        s = Stem(sides=48)
        y = np.linspace(0.0, LENGTH, 65)
        s.add_points(np.c_[np.full_like(y, 1.5 * k), y, np.zeros_like(y)], None, np.full_like(y, r))
        stems.append(s)
    v, n, uv, tri, _, tri_stem = stems_to_arrays(stems)
    return Mesh(v, tri, normals=n, uvs=uv, materials=[BARK]), tri_stem


def test_tree_uvs_run_around_and_along_in_circumferences():
    mesh, _ = _stems()
    per_stem = mesh.n_vertices // 2
    for k, r in enumerate(RADII):
        uv = mesh.uvs[k * per_stem:(k + 1) * per_stem]
        y = mesh.vertices[k * per_stem:(k + 1) * per_stem, 1]
        assert uv[:, 0].min() == 0.0 and uv[:, 0].max() == 1.0  # once around
        # v grows by one for every circumference of length: the grain follows the radius
        np.testing.assert_allclose(uv[:, 1], y / (2 * np.pi * r), rtol=1e-5, atol=1e-5)


@pytest.fixture(scope="module")
def bark_image():
    mesh, _ = _stems()
    cam = Camera(mode="2d", target=(0.75, LENGTH / 2, 0.0), height=LENGTH * 1.02, distance=10)
    return render_array(Scene([mesh]), (160, 256), cam, lit=False, msaa=0)[..., :3].mean(-1)


def _face(img, x_centre, radius, px_per_unit=256 / (LENGTH * 1.02)):
    """The middle third of a cylinder's visible face, rows of the middle of its length."""
    c = 80 + (x_centre - 0.75) * px_per_unit
    half = max(2, int(radius * px_per_unit / 3))
    return img[20:-20, int(c) - half:int(c) + half + 1]


def _grain_length(profile_block) -> float:
    """Mean run length (pixels along the stem) of the pattern: its std over the mean
    absolute step between rows."""
    steps = np.abs(np.diff(profile_block, axis=0)).mean()
    return float(profile_block.std() / max(steps, 1e-9))


def test_renderer_bark_grain_scales_with_the_radius(bark_image):
    thick = _face(bark_image, 0.0, RADII[0])
    thin = _face(bark_image, 1.5, RADII[1])
    assert thick.std() > 5 and thin.std() > 5  # cracks on both
    # along the stem the cracks of the trunk (4x the radius) are several times longer in
    # pixels than the twig's; with the old world-space breakup both shared one length
    ratio = _grain_length(thick) / _grain_length(thin)
    assert ratio > 2.0, ratio

"""Procedural GLSL textures of seed 000 §2.6: bark cracks, leaf veins and grass."""

from __future__ import annotations

import numpy as np
import pytest

from sylva.geometry.mesh import Material, Mesh, Scene
from sylva.render import Camera, Ground, render_array

BARK = Material("bark", color=(0.40, 0.26, 0.14, 1.0), texture="bark")
LEAF = Material("leaf", color=(0.12, 0.40, 0.08, 1.0), texture="leaf", double_sided=True)


def grey(a: np.ndarray) -> np.ndarray:
    return a[..., :3].astype(float).mean(axis=-1)


def trunk_image(geo, **kw):
    trunk = geo.frustum((0, 0, 0), (0, 4, 0), 0.5, 0.5, sections=64, material=BARK)
    cam = Camera.auto(trunk, "orthographic", yaw=0, pitch=0, aspect=0.5)
    return render_array(Scene([trunk]), (64, 128), cam, lit=False, msaa=0, **kw)


def test_bark_cracks_run_along_the_branch(geo):
    img = grey(trunk_image(geo))
    core = img[10:-10, 22:42]  # the middle of the trunk's face
    across = np.abs(np.diff(core, axis=1)).mean()
    along = np.abs(np.diff(core, axis=0)).mean()
    assert across > 2.5 * along
    assert core.std() > 6  # visible cracks, not a flat colour
    # dark cracks: a long tail of dark pixels below the bark's median tone
    assert np.percentile(core, 2) < 0.7 * np.median(core)


def test_bark_follows_a_tilted_branch(geo):
    """The stripes follow the branch axis (from its uvs), not the global Y axis."""
    tilted = geo.frustum((0, 0, 0), (4, 0, 0), 0.5, 0.5, sections=64, material=BARK)
    cam = Camera(mode="2d", target=(2, 0, 0), height=1.1, distance=10)
    img = grey(render_array(Scene([tilted]), (128, 32), cam, lit=False, msaa=0))
    core = img[8:24, 8:-8]
    along = np.abs(np.diff(core, axis=1)).mean()
    across = np.abs(np.diff(core, axis=0)).mean()
    assert across > 2.5 * along


def test_textures_off_gives_the_plain_colour(geo):
    img = grey(trunk_image(geo, textures=False))
    assert img[10:-10, 22:42].std() < 0.5


def test_bark_without_uvs_still_has_cracks(geo):
    trunk = geo.frustum((0, 0, 0), (0, 4, 0), 0.5, 0.5, sections=64, material=BARK)
    bare = Mesh(trunk.vertices, trunk.indices, materials=[BARK])
    cam = Camera.auto(bare, "orthographic", yaw=0, pitch=0, aspect=0.5)
    img = grey(render_array(Scene([bare]), (64, 128), cam, lit=False, msaa=0))[10:-10, 22:42]
    assert img.std() > 4
    assert np.abs(np.diff(img, axis=1)).mean() > 2 * np.abs(np.diff(img, axis=0)).mean()


@pytest.fixture(scope="module")
def leaf_image():
    quad = Mesh(
        np.array([[-1, 0, 0], [1, 0, 0], [1, 4, 0], [-1, 4, 0]], float),
        np.array([[0, 1, 2], [0, 2, 3]]),
        uvs=np.array([[0, 0], [1, 0], [1, 1], [0, 1]], float),
        materials=[LEAF],
    )
    cam = Camera(mode="2d", target=(0, 2, 0), height=4.0, distance=5)
    return grey(render_array(Scene([quad]), (64, 128), cam, lit=False, msaa=0))


def test_leaf_main_vein_is_the_brightest(leaf_image):
    cols = leaf_image.mean(axis=0)  # 64 columns span u = 0 .. 1 (width 2 over 64 px)
    centre = cols[31:33].mean()
    assert centre > 1.25 * np.median(cols[8:24])
    assert centre == pytest.approx(cols.max(), abs=1.0)


def test_leaf_edges_are_darker(leaf_image):
    blade = np.median(leaf_image[:, 16:24], axis=0).mean()
    edge = np.median(leaf_image[:, 1:3], axis=0).mean()
    assert edge < 0.9 * blade


def test_leaf_side_veins_are_periodic_along_the_blade(leaf_image):
    profile = leaf_image[:, 20]  # u ≈ 0.32, left of the main vein
    bright = profile > (profile.max() + np.median(profile)) / 2
    bands = np.count_nonzero(np.diff(bright.astype(int)) == 1)
    assert 5 <= bands <= 9  # seven sine periods along v
    # no randomness: the right half mirrors the left half
    assert np.abs(leaf_image[:, :32] - leaf_image[:, 32:][:, ::-1]).mean() < 1.5


def test_grass_has_no_mirrored_cross_at_the_origin():
    grass = Ground(height=0.0, size=8.0, center=(0.0, 0.0))
    plane = grass.mesh(np.zeros((2, 3)))
    cam = Camera(mode="orthographic", pitch=90.0, distance=10.0, height=6.0)
    img = grey(render_array(Scene([plane]), (96, 96), cam, lit=False, msaa=0))
    assert img.std() > 4
    z = img - img.mean()

    def corr(a, b):
        return float((a * b).sum() / np.sqrt((a * a).sum() * (b * b).sum()))

    # a noise fed abs(position) would be mirror-symmetric about both axes through the origin
    assert abs(corr(z, z[:, ::-1])) < 0.35
    assert abs(corr(z, z[::-1, :])) < 0.35
    assert abs(corr(z, z[::-1, ::-1])) < 0.35

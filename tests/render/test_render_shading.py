"""Phong lighting, point-light attenuation, specular maps and shadows, checked analytically."""

from __future__ import annotations

import numpy as np
import pytest
from PIL import Image
from scipy.spatial import ConvexHull

from sylva.geometry.mesh import Material, Mesh, Scene
from sylva.render import Camera, Ground, PointLight, Sun, attenuation, render_array
from sylva.render.camera import project

WHITE = Material("white", color=(1.0, 1.0, 1.0, 1.0), roughness=1.0)
GREY = Material("grey", color=(0.8, 0.8, 0.8, 1.0), roughness=1.0)
RED = Material("red", color=(1.0, 0.0, 0.0, 1.0), roughness=1.0)


def decode(value) -> np.ndarray:
    """sRGB-ish 8-bit output back to linear intensity (the shader encodes with 1/2.2)."""
    return (np.asarray(value, float) / 255.0) ** 2.2


def pixel(cam: Camera, point, size) -> tuple[int, int]:
    """Row and column of the pixel that shows the world ``point``."""
    w, h = size
    ndc = project(cam, np.array([point], float), w / h, 0.1, 100.0)[0]
    return int((1 - ndc[1]) / 2 * h), int((ndc[0] + 1) / 2 * w)


def top_down(extent: float, size) -> Camera:
    return Camera(mode="orthographic", pitch=90.0, distance=20.0, height=extent)


def test_attenuation_formula():
    assert attenuation(0.0) == 1.0
    d = np.array([1.0, 10.0, 100.0])
    assert attenuation(d) == pytest.approx(1 / (1 + 0.045 * d + 0.0075 * d**2))
    assert attenuation(100.0) == pytest.approx(1 / 80.5)


@pytest.mark.parametrize("offset", [0.0, 3.0, 6.0, 10.0])
def test_point_light_diffuse_follows_lambert_and_attenuation(offset):
    size = (96, 96)
    plane = Ground(height=0.0, size=30.0, center=(0.0, 0.0), material=WHITE).mesh(np.zeros((2, 3)))
    light = PointLight(position=(0.0, 5.0, 0.0), color=1.0, ambient=0.0, specular=0.0)
    cam = top_down(26.0, size)
    img = render_array(Scene([plane]), size, cam, lights=[light], ground=False, msaa=0)
    r, c = pixel(cam, (offset, 0.0, 0.0), size)
    d = np.hypot(5.0, offset)
    expected = attenuation(d) * 5.0 / d  # albedo 1, N·L = h / d
    assert decode(img[r, c]) == pytest.approx([expected] * 3, abs=0.012)


def test_sun_ambient_plus_diffuse_and_specular_map(tmp_path):
    # a quad facing the camera (+Z), the sun shining straight at it: V·R = 1 everywhere
    quad = Mesh(
        np.array([[-1, -1, 0], [1, -1, 0], [1, 1, 0], [-1, 1, 0]], float),
        np.array([[0, 1, 2], [0, 2, 3]]),
        uvs=np.array([[0, 0], [1, 0], [1, 1], [0, 1]], float),
    )
    Image.new("RGB", (8, 8), (128, 128, 128)).save(tmp_path / "crate.png")
    spec = np.zeros((8, 8), np.uint8)
    spec[:, 4:] = 255  # metal on the right, wood on the left
    Image.fromarray(spec).save(tmp_path / "crate_specular.png")
    Image.new("RGB", (8, 8), (128, 128, 128)).save(tmp_path / "plain.png")
    sun = Sun(direction=(0, 0, -1), color=0.5, ambient=0.2, specular=0.6, shadows=False)
    cam = Camera(mode="2d", height=2.0, distance=5.0)
    size = (64, 64)

    def shot(texture, roughness):
        tex = str(tmp_path / texture)
        mat = Material("m", color=(1, 1, 1, 1), roughness=roughness, texture=tex)
        quad.materials = [mat]
        return decode(render_array(Scene([quad]), size, cam, lights=[sun], msaa=0)[32])

    albedo = (128 / 255) ** 2.2
    matte = shot("crate.png", 1.0)  # roughness 1: no specular at all
    assert matte[8] == pytest.approx([0.7 * albedo] * 3, abs=0.01)
    assert matte[56] == pytest.approx(matte[8], abs=0.004)
    shiny = shot("crate.png", 0.5)  # specular strength 1 - r = 0.5, map 0 | 1
    assert shiny[8] == pytest.approx(matte[8], abs=0.004)
    assert shiny[56] == pytest.approx(matte[56] + 0.5 * 0.6, abs=0.02)
    unmapped = shot("plain.png", 0.5)  # no specular map: intensity 1 everywhere
    assert unmapped[8] == pytest.approx(unmapped[56], abs=0.004)
    assert unmapped[8] == pytest.approx(shiny[56], abs=0.01)


def _shadow_scene(geo):
    floating = geo.box((-0.5, 1.5, -0.5), (0.5, 2.0, 0.5), RED)
    ground = Ground(height=0.0, size=8.0, center=(0.0, 0.0), material=GREY)
    return Scene([floating]), ground


def test_shadow_darkens_the_ground_where_the_box_projects(geo):
    scene, ground = _shadow_scene(geo)
    sun = Sun(direction=(0.45, -1.0, 0.3), color=0.8, ambient=0.25, specular=0.0)
    size = (120, 120)
    cam = top_down(6.0, size)
    lit = render_array(scene, size, cam, lights=[sun], ground=ground, msaa=0, shadow_size=1024)
    flat = render_array(scene, size, cam, lights=[sun], ground=ground, msaa=0, shadows=False)
    # the analytic shadow: the box's corners slid along the rays onto y = 0
    corners = np.array([[x, y, z] for x in (-0.5, 0.5) for y in (1.5, 2.0) for z in (-0.5, 0.5)])
    d = sun.direction
    feet = corners - d * (corners[:, 1:2] / d[1])
    hull = ConvexHull(feet[:, [0, 2]])
    pts = feet[hull.vertices]
    fan = np.array([[0, k, k + 1] for k in range(1, len(pts) - 1)])
    want = geo.silhouette(Scene([Mesh(pts, fan)]), cam, size)
    rgb = lit.astype(int)
    on_ground = np.abs(rgb[..., 0] - rgb[..., 1]) < 12  # grey, not the red box
    level_lit = np.median(rgb[on_ground & ~want, 1])
    level_dark = np.median(rgb[on_ground & want, 1])
    assert level_dark < 0.65 * level_lit  # darkened: only the ambient term is left
    got = on_ground & (rgb[..., 1] < (level_lit + level_dark) / 2)
    assert geo.iou(got, want & on_ground) >= 0.9
    # without shadows the same ground is evenly lit
    flat_ground = flat[..., 1][on_ground].astype(int)
    assert flat_ground.max() - flat_ground.min() <= 2
    assert abs(np.median(flat_ground) - level_lit) <= 2


def test_shadow_falls_on_the_ground_in_the_default_3d_view(geo):
    scene, ground = _shadow_scene(geo)
    sun = Sun(direction=(0.45, -1.0, 0.3))
    size = (96, 72)
    cam = Camera.auto(scene, "perspective", yaw=-30, pitch=40, aspect=size[0] / size[1])
    cam.distance *= 2.2
    on = render_array(scene, size, cam, lights=[sun], ground=ground, msaa=0)
    off = render_array(scene, size, cam, lights=[sun], ground=ground, msaa=0, shadows=False)
    centre = (-0.5 * 0 + 1.75 * 0.45, 0.0, 1.75 * 0.3)  # where the box centre's ray lands
    r, c = pixel(cam, centre, size)
    r = int(np.clip(r, 0, size[1] - 1))
    assert on[r, c, 1] < 0.7 * off[r, c, 1]
    assert np.abs(on[0:5].astype(int) - off[0:5].astype(int)).max() <= 2  # far ground: no shadow

"""The sky: a gradient by ray elevation behind 3D views, and the ground fading into its haze."""

from __future__ import annotations

import math

import numpy as np
import pytest

from sylva.geometry.mesh import Material, Scene
from sylva.render import Camera, Ground, Renderer, Sky, render, render_array

SIZE = (96, 64)
SKY = Sky()
ZENITH = np.array(SKY.zenith) * 255
HORIZON = np.array(SKY.horizon) * 255


def pixel_rays(camera: Camera, size) -> np.ndarray:
    """World directions ``(h, w, 3)`` through the pixel centres (row 0 at the top), on the CPU.

    Unprojects each pixel's near and far points with the inverse view-projection in float64.
    """
    w, h = size
    m = camera.projection_matrix(w / h, 0.1, 100.0) @ camera.view_matrix()
    inv = np.linalg.inv(m)
    x = (np.arange(w) + 0.5) / w * 2 - 1
    y = 1 - (np.arange(h) + 0.5) / h * 2
    xx, yy = np.meshgrid(x, y)
    ends = []
    for z in (-1.0, 1.0):
        p = np.stack([xx, yy, np.full_like(xx, z), np.ones_like(xx)], axis=-1) @ inv.T
        ends.append(p[..., :3] / p[..., 3:4])
    d = ends[1] - ends[0]
    return d / np.linalg.norm(d, axis=-1, keepdims=True)


def expected_sky(rays: np.ndarray, sky: Sky = SKY) -> np.ndarray:
    s = 1 - (1 - np.clip(rays[..., 1], 0.0, 1.0)) ** sky.exponent
    return (1 - s[..., None]) * np.array(sky.horizon) * 255 + s[..., None] * np.array(
        sky.zenith
    ) * 255


def level_camera(plant) -> Camera:
    """Looking level at the plant from afar: the horizon crosses the middle of the image."""
    b = np.asarray(plant.bounds())
    target = 0.5 * (b[0] + b[1])
    return Camera(mode="perspective", target=target, yaw=30, pitch=0, distance=14, fov=50)


def test_sky_colour_follows_the_elevation_of_each_ray(plant):
    cam = level_camera(plant)
    img = render_array(plant, SIZE, cam, sky=True, ground=False, msaa=0, lit=False)
    rays = pixel_rays(cam, SIZE)
    want = expected_sky(rays)
    background = img.astype(int).sum(axis=-1) > 300  # the plant is black
    assert background.mean() > 0.8
    diff = np.abs(img.astype(float) - want)[background]
    assert diff.max() <= 3
    # higher pixels are nearer the zenith colour, and the top row is nearer it than the horizon
    col = img[:, 2].astype(float)
    to_zenith = np.linalg.norm(col - ZENITH, axis=-1)
    above = rays[:, 2, 1] > 0
    assert np.all(np.diff(to_zenith[above]) >= -0.5)  # rows run downwards: distance grows
    assert to_zenith[0] < np.linalg.norm(HORIZON - ZENITH) - 40
    # rays at or below the horizon (no ground to hit) see the horizon colour
    below = rays[..., 1] <= 0
    assert below.mean() > 0.3
    assert np.abs(img[below & background].astype(float) - HORIZON).max() <= 1


def test_sky_ignores_the_plain_background_and_is_not_flat(plant):
    cam = level_camera(plant)
    img = render_array(plant, SIZE, cam, sky=True, bg="black", ground=False, msaa=0)
    top, bottom = img[0, 0].astype(float), img[-1, 0].astype(float)
    assert np.linalg.norm(top - bottom) > 30
    assert top[2] > top[0] + 40  # blue


def test_below_the_horizon_past_the_ground_is_the_horizon_colour(plant):
    cam = level_camera(plant)
    img = render_array(plant, SIZE, cam, sky=True, msaa=0, lit=False)
    rays = pixel_rays(cam, SIZE)
    h = SIZE[1]
    # rows just below the horizon: their rays pass over the ground's far edge or hit its
    # faded rim; both must be the horizon colour
    rows = [j for j in range(h) if -0.02 < rays[j, 0, 1] <= 0]
    assert rows
    for j in rows:
        for i in (0, 1, SIZE[0] - 2, SIZE[0] - 1):
            assert np.abs(img[j, i].astype(float) - HORIZON).max() <= 2, (j, i)


@pytest.mark.parametrize(
    "camera",
    [
        Camera(mode="perspective", yaw=30, pitch=2, fov=50),
        Camera(mode="orthographic", yaw=-40, pitch=8),
    ],
    ids=["perspective", "orthographic"],
)
def test_sky_is_continuous_across_tiles(plant, camera, geo):
    size = (97, 61)  # odd sizes: tiles of unequal width at the edges
    cam = Camera.auto(
        plant,
        camera.mode,
        yaw=camera.yaw,
        pitch=camera.pitch,
        fov=camera.fov,
        aspect=size[0] / size[1],
    )
    whole = render_array(plant, size, cam, msaa=0, sky=True)
    tiled = render_array(plant, size, cam, msaa=0, sky=True, tile_size=32)
    diff = np.abs(whole.astype(int) - tiled.astype(int))
    assert diff.mean() < 0.5
    assert (diff.max(axis=-1) > 8).mean() < 0.002
    # there is a sky to compare: the top row is sky blue, not the white background
    assert whole[0, :, 2].mean() > whole[0, :, 0].mean() + 10


def test_orthographic_sky_is_a_gradient_too(plant):
    cam = Camera.auto(plant, "orthographic", yaw=20, pitch=0, aspect=SIZE[0] / SIZE[1])
    img = render_array(plant, SIZE, cam, sky=True, ground=False, msaa=0)
    assert img[0, 0, 2] - img[0, 0, 0] > img[SIZE[1] // 2 - 3, 0, 2] - img[SIZE[1] // 2 - 3, 0, 0]


@pytest.mark.parametrize("off", [None, False])
def test_no_sky_gives_the_old_pixels(plant, off):
    old = render_array(plant, SIZE, msaa=0)
    assert np.array_equal(render_array(plant, SIZE, msaa=0, sky=off), old)
    assert not np.array_equal(render_array(plant, SIZE, msaa=0, sky=True), old)


def test_sky_is_off_in_2d(plant):
    old = render_array(plant, SIZE, "2d", msaa=0)
    assert np.array_equal(render_array(plant, SIZE, "2d", msaa=0, sky=True), old)


def test_transparent_wins_over_the_sky(plant):
    cam = level_camera(plant)
    plain = render_array(plant, SIZE, cam, transparent=True, msaa=0)
    sky = render_array(plant, SIZE, cam, transparent=True, msaa=0, sky=Sky())
    assert sky.shape == (SIZE[1], SIZE[0], 4)
    assert sky[0, 0, 3] == 0 and sky[0, -1, 3] == 0
    assert np.array_equal(sky, plain)
    img = render(plant, SIZE, cam, transparent=True, msaa=0, sky=True)
    assert img.mode == "RGBA" and img.getpixel((0, 0))[3] == 0


@pytest.mark.parametrize("bad", ["blue", 1, (0.3, 0.5, 0.8)])
def test_bad_sky_is_a_clear_error(plant, bad):
    with pytest.raises(TypeError, match="sky must be a Sky"):
        render_array(plant, SIZE, msaa=0, sky=bad)


def test_sky_checks_its_colours():
    with pytest.raises(ValueError, match="zenith"):
        Sky(zenith=(0.2, 0.3, 1.5))
    with pytest.raises(TypeError, match="horizon"):
        Sky(horizon="haze")
    with pytest.raises(ValueError, match="exponent"):
        Sky(exponent=0)
    assert Sky(zenith=[0, 0, 1]).zenith == (0.0, 0.0, 1.0)


def ground_hits(camera: Camera, size, height: float) -> np.ndarray:
    """Where each pixel's ray meets the plane y = height: ``(h, w, 3)``, NaN where it misses."""
    rays = pixel_rays(camera, size)
    eye = camera.eye
    t = (height - eye[1]) / np.where(rays[..., 1] < 0, rays[..., 1], np.nan)
    return eye + t[..., None] * rays


def test_ground_fades_into_the_horizon_at_its_edge(plant, geo):
    grass = Ground(size=12.0)
    cam = Camera(mode="perspective", target=(0, 0, 0), yaw=30, pitch=40, distance=22, fov=45)
    img = render_array(plant, SIZE, cam, sky=True, ground=grass, msaa=0)
    hits = ground_hits(cam, SIZE, 0.0)
    b = np.asarray(plant.bounds())
    cx, cz = 0.5 * (b[0, 0] + b[1, 0]), 0.5 * (b[0, 2] + b[1, 2])
    dist = np.hypot(hits[..., 0] - cx, hits[..., 2] - cz)
    on_square = (np.abs(hits[..., 0] - cx) < 6) & (np.abs(hits[..., 2] - cz) < 6)
    covered = geo.silhouette(plant, cam, SIZE)
    # the whole square is in view, with the world beyond it on every side
    assert (on_square & (dist > 5.99)).sum() > 30
    assert (~on_square & (dist < 9)).sum() > 30
    # at (and past) the inscribed circle the ground is the horizon colour: no visible edge
    rim = (dist >= 6.0) & ~covered
    diff = np.abs(img[rim].astype(float) - HORIZON).max(axis=-1)
    assert np.mean(diff <= 2) > 0.97 and diff.max() <= 8
    # right under the plant it is still grass
    near = (dist < 1.2) & ~covered
    near &= ~np.roll(covered, 1, 0) & ~np.roll(covered, -1, 0)
    assert near.sum() > 20
    px = img[near].astype(float)
    assert np.all(np.abs(px - HORIZON).max(axis=-1) > 50)
    assert np.mean(px[:, 1] > px[:, 2] + 20) > 0.95  # green, not haze


def test_ground_without_fade_keeps_its_colour_to_the_edge(plant, geo):
    grass = Ground(size=12.0)
    cam = Camera(mode="perspective", target=(0, 0, 0), yaw=30, pitch=40, distance=22, fov=45)
    img = render_array(plant, SIZE, cam, sky=Sky(ground_fade=False), ground=grass, msaa=0)
    hits = ground_hits(cam, SIZE, 0.0)
    on_rim = (np.abs(hits[..., 0]) < 5.8) & (np.abs(hits[..., 2]) < 5.8)
    on_rim &= np.hypot(hits[..., 0], hits[..., 2]) > 5.2
    px = img[on_rim].astype(float)
    assert len(px) > 10
    assert np.mean(px[:, 1] > px[:, 2] + 20) > 0.95


def test_default_ground_grows_under_a_sky_but_shadows_keep_their_map(plant):
    r = Renderer.default()
    cam = Camera.auto(plant, "perspective", aspect=SIZE[0] / SIZE[1])
    with r.upload(plant) as gpu:
        r.render(gpu, SIZE, cam, msaa=0)
        plain = gpu._shadow_cache["sun"].matrix.copy()
        r.render(gpu, SIZE, cam, msaa=0, sky=True)
        sky = gpu._shadow_cache["sun"].matrix.copy()
    assert np.allclose(plain, sky)
    # the ground near the plant (shadow included) looks the same with and without the sky
    old = render_array(plant, SIZE, cam, msaa=0).astype(int)
    new = render_array(plant, SIZE, cam, msaa=0, sky=True).astype(int)
    b = np.asarray(plant.bounds())
    hits = ground_hits(cam, SIZE, float(b[0, 1]))
    c = 0.5 * (b[0] + b[1])
    ext = float(np.max(b[1] - b[0]))
    near = np.hypot(hits[..., 0] - c[0], hits[..., 2] - c[2]) < 1.5 * ext
    assert near.sum() > 200
    diff = np.abs(old - new)[near].max(axis=-1)
    assert np.mean(diff > 8) < 0.01
    # while the old ground's edge (2 extents out) is gone: the ground goes on under the sky
    edge = np.hypot(hits[..., 0] - c[0], hits[..., 2] - c[2])
    beyond = (edge > 2.2 * ext) & (edge < 2.5 * ext)
    beyond &= (np.abs(hits[..., 0] - c[0]) > 2.1 * ext) | (np.abs(hits[..., 2] - c[2]) > 2.1 * ext)
    assert beyond.sum() > 10
    assert np.mean(np.abs(new[beyond] - old[beyond]).max(axis=-1) > 20) > 0.9


def test_fade_does_not_reach_the_ground_of_a_plain_render(plant):
    """A sky with ground_fade off leaves the ground's size and colours as they were."""
    cam = Camera.auto(plant, "perspective", aspect=SIZE[0] / SIZE[1], pitch=35)
    old = render_array(plant, SIZE, cam, msaa=0).astype(int)
    new = render_array(plant, SIZE, cam, msaa=0, sky=Sky(ground_fade=False)).astype(int)
    ground = (old[..., 1] > old[..., 2] + 20) & (new[..., 1] > new[..., 2] + 20)
    assert ground.mean() > 0.3
    assert np.abs(old - new)[ground].max() <= 2


def test_growth_frames_take_a_sky(geo):
    from sylva.render import growth_frames

    bark = Material("bark", color=(0.4, 0.25, 0.1, 1))
    scenes = [
        Scene([geo.frustum((0, 0, 0), (0, h, 0), 0.2, 0.1, material=bark)]) for h in (1.0, 2.0)
    ]
    frames = list(growth_frames(scenes, SIZE, "perspective", pitch=0, msaa=0, sky=True))
    assert len(frames) == 2
    top = np.asarray(frames[0])[0, 0].astype(int)
    assert top[2] > top[0] + 20  # blue sky at the top


def test_sky_rays_match_the_inverse_view_projection():
    from sylva.render.camera import tile_matrix
    from sylva.render.offscreen import _sky_rays

    cam = Camera(mode="perspective", yaw=70, pitch=-25, fov=40, distance=5)
    aspect = 1.7
    m = cam.projection_matrix(aspect, 0.5, 50.0) @ cam.view_matrix()
    tile = tile_matrix(-0.2, 0.1, 0.6, 0.9)
    inv = np.linalg.inv(tile @ m)
    rays = _sky_rays(cam, aspect, tile)
    for x, y in ((-1, -1), (0.3, 0.7), (1, 1)):
        a, b = inv @ [x, y, -1, 1], inv @ [x, y, 1, 1]
        want = b[:3] / b[3] - a[:3] / a[3]
        got = rays @ [x, y, 1]
        assert np.allclose(got / np.linalg.norm(got), want / np.linalg.norm(want))
    assert math.isclose(np.linalg.norm(_sky_rays(cam, aspect) @ [0, 0, 1]), 1.0)

"""Depth images: the view-axis distance of every pixel equals the analytic value of a plane
at a known place, for perspective and orthographic cameras; the background reads 0."""

import math

import numpy as np
import pytest

from sylva.geometry.mesh import Mesh, Scene
from sylva.render.camera import Camera
from sylva.render.offscreen import Renderer

W, H = 64, 48


def _plane(normal, through, half=40.0) -> Scene:
    n = np.asarray(normal, np.float64) / np.linalg.norm(normal)
    a = np.cross(n, [0.0, 1.0, 0.0] if abs(n[1]) < 0.9 else [1.0, 0.0, 0.0])
    a /= np.linalg.norm(a)
    b = np.cross(n, a)
    c = np.asarray(through, np.float64)
    v = np.array([c + half * (sa * a + sb * b) for sa, sb in ((-1, -1), (1, -1), (1, 1),
                                                                (-1, 1))])  # fmt: skip
    return Scene([Mesh(v, np.array([[0, 1, 2], [0, 2, 3]]))])


def _rays(cam: Camera):
    """Origin and direction (view-axis component 1) of the ray through each pixel centre."""
    r, u, back = cam.basis()
    x = (2 * (np.arange(W) + 0.5) / W - 1)[None, :]
    y = (1 - 2 * (np.arange(H) + 0.5) / H)[:, None]
    if cam.mode == "perspective":
        t = math.tan(math.radians(cam.fov) / 2)
        d = (x * t * W / H)[..., None] * r + (y * t)[..., None] * u - back
        return np.broadcast_to(cam.eye, d.shape), d
    h = cam.height / 2
    o = cam.eye + (x * h * W / H)[..., None] * r + (y * h)[..., None] * u
    return o, np.broadcast_to(-back, o.shape)


def _depth(scene, cam):
    return Renderer.default().render(scene, (W, H), cam, msaa=0, lit=False, ground=False,
                                     shadows=False, depth=True)  # fmt: skip


@pytest.mark.parametrize("mode", ["perspective", "orthographic"])
def test_plane_facing_the_camera_at_a_known_distance(mode):
    cam = Camera(mode=mode, target=np.zeros(3), yaw=0, pitch=0, distance=7.0, fov=40,
                 height=6.0)  # fmt: skip
    _, depth = _depth(_plane([0, 0, 1], [0, 0, 0]), cam)
    assert depth.values.shape == (H, W) and depth.values.dtype == np.float32
    assert depth.near < 7.0 < depth.far
    np.testing.assert_allclose(depth.values, 7.0, rtol=1e-5)


@pytest.mark.parametrize("mode", ["perspective", "orthographic"])
def test_tilted_plane_pixel_by_pixel(mode):
    """A plane turned 35° about y and 20° about x: at each pixel centre the ray meets it at
    the analytic view-axis distance (the rasteriser samples pixel centres)."""
    cam = Camera(mode=mode, target=np.array([0.5, 1.0, 0.0]), yaw=25, pitch=15,
                 distance=9.0, fov=45, height=10.0, near=2.0, far=30.0)  # fmt: skip
    n = np.array([math.sin(math.radians(35)), math.sin(math.radians(20)), 1.0])
    p0 = np.array([0.3, 1.2, -0.4])
    _, depth = _depth(_plane(n, p0), cam)
    o, d = _rays(cam)
    t = ((p0 - o) @ n) / (d @ n)  # d has view-axis component 1: t is the depth
    assert float(t.max() - t.min()) > 1.0  # the plane is far from facing the camera
    # a pixel's rounding: the depth changes by at most |∇t| per pixel; the drawn value is
    # that of the centre, within the depth buffer's 24-bit precision
    step = max(np.abs(np.diff(t, axis=0)).max(), np.abs(np.diff(t, axis=1)).max())
    err = np.abs(depth.values - t)
    assert err.max() < 0.01 * step + 1e-5 * t.max(), err.max()


def test_background_is_zero_and_msaa_is_refused():
    cam = Camera(mode="perspective", target=np.zeros(3), yaw=0, pitch=0, distance=5.0,
                 fov=60)  # fmt: skip
    small = _plane([0, 0, 1], [0, 0, 0], half=1.0)  # a 2 × 2 square in a ~5.8 wide view
    _, depth = _depth(small, cam)
    drawn = depth.values > 0
    assert 0 < drawn.sum() < drawn.size
    assert drawn[H // 2, W // 2] and not drawn[0, 0]
    np.testing.assert_allclose(depth.values[drawn], 5.0, rtol=1e-5)
    with pytest.raises(ValueError, match="msaa"):
        Renderer.default().render(small, (W, H), cam, msaa=4, depth=True)


def test_tiled_render_has_the_same_depth():
    cam = Camera(mode="perspective", target=np.zeros(3), yaw=20, pitch=10, distance=6.0,
                 fov=50, near=1.0, far=20.0)  # fmt: skip
    scene = _plane([0.4, 0.2, 1.0], [0.0, 0.0, 0.0])
    whole = _depth(scene, cam)[1].values
    tiled = Renderer.default().render(scene, (W, H), cam, msaa=0, lit=False, ground=False,
                                      shadows=False, depth=True, tile_size=20)[1].values
    assert (whole > 0).all()
    np.testing.assert_allclose(tiled, whole, rtol=1e-5)  # 24-bit depth, other frustums

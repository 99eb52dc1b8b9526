"""Camera matrices and automatic framing (no GL needed)."""

from __future__ import annotations

import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st

from sylva.render.camera import MODES, Camera, box_corners, project, tile_matrix

BOX = np.array([[-1.0, 0.0, -0.5], [1.5, 4.0, 0.7]])


@pytest.mark.parametrize("mode", MODES)
@pytest.mark.parametrize("aspect", [0.5, 1.0, 16 / 9])
def test_auto_frames_every_corner_inside_with_the_margin(mode, aspect):
    cam = Camera.auto(BOX, mode, yaw=37, pitch=25, aspect=aspect, margin=0.1)
    ndc = project(cam, box_corners(BOX), aspect)
    assert np.all(np.abs(ndc[:, :2]) <= 0.9 + 1e-9)
    assert np.all(np.abs(ndc[:, 2]) <= 1.0)
    # tight: some corner touches the margin in x or y
    assert np.max(np.abs(ndc[:, :2])) == pytest.approx(0.9, abs=1e-6)


@settings(max_examples=40, deadline=None)
@given(
    yaw=st.floats(-360, 360),
    pitch=st.floats(-85, 85),
    fov=st.floats(10, 120),
    aspect=st.floats(0.3, 3.0),
)
def test_perspective_fit_holds_for_any_view(yaw, pitch, fov, aspect):
    cam = Camera.auto(BOX, "perspective", yaw=yaw, pitch=pitch, fov=fov, aspect=aspect)
    ndc = project(cam, box_corners(BOX), aspect)
    assert np.all(np.abs(ndc[:, :2]) <= 0.95 + 1e-7)


def test_view_matrix_puts_the_target_in_front_of_the_eye():
    cam = Camera(target=(1, 2, 3), yaw=50, pitch=-20, distance=7)
    t = cam.view_matrix() @ np.array([1, 2, 3, 1.0])
    assert t[:3] == pytest.approx([0, 0, -7])
    assert np.linalg.norm(cam.eye - cam.target) == pytest.approx(7)
    r, u, b = cam.basis()
    assert np.cross(r, u) == pytest.approx(b)


def test_yaw_zero_pitch_zero_looks_down_minus_z():
    cam = Camera(target=(0, 0, 0), distance=5)
    assert cam.eye == pytest.approx([0, 0, 5])
    assert cam.basis()[0] == pytest.approx([1, 0, 0])


def test_2d_camera_is_orthographic_and_locks_rotation():
    cam = Camera.auto(BOX, "2d", yaw=45, pitch=30)
    assert (cam.yaw, cam.pitch) == (0.0, 0.0)
    assert cam.orthographic
    assert cam.orbit(yaw=90, pitch=10).basis()[2] == pytest.approx([0, 0, 1])
    direct = Camera(mode="2d", yaw=10, pitch=10)
    assert (direct.yaw, direct.pitch) == (0.0, 0.0)
    # XY maps straight to the screen: +X right, +Y up
    ndc = project(cam, np.array([[0.0, 2.0, 0.0], [1.0, 2.0, 0.0], [0.0, 3.0, 0.0]]), 1.0)
    assert ndc[1, 0] > ndc[0, 0] and ndc[1, 1] == pytest.approx(ndc[0, 1])
    assert ndc[2, 1] > ndc[0, 1] and ndc[2, 0] == pytest.approx(ndc[0, 0])


def test_overrides_are_kept():
    cam = Camera.auto(BOX, yaw=10, pitch=5, distance=42.0, target=(0, 1, 0))
    assert (cam.yaw, cam.pitch, cam.distance) == (10, 5, 42.0)
    assert cam.target.tolist() == [0, 1, 0]
    wide = Camera.auto(BOX, "orthographic", yaw=0, pitch=0)
    zoomed = Camera.auto(BOX, "orthographic", yaw=0, pitch=0, distance=wide.distance / 2)
    assert zoomed.height == pytest.approx(wide.height / 2)


def test_orbit_turns_and_clamps_pitch():
    cam = Camera(yaw=10, pitch=80).orbit(yaw=20, pitch=30)
    assert cam.yaw == 30 and cam.pitch == pytest.approx(89.9)


@pytest.mark.parametrize("mode", ["perspective", "orthographic"])
def test_tiles_partition_the_full_projection(mode):
    cam = Camera.auto(BOX, mode, yaw=20, pitch=10, aspect=1.5)
    pts = np.random.default_rng(1).uniform(BOX[0], BOX[1], (50, 3))
    full = project(cam, pts, 1.5, 0.5, 50.0)
    p = cam.projection_matrix(1.5, 0.5, 50.0) @ cam.view_matrix()
    tile = tile_matrix(0.0, -1.0, 1.0, 0.5)
    h = np.c_[pts, np.ones(50)] @ (tile @ p).T
    ndc = h[:, :3] / h[:, 3:]
    assert ndc[:, 0] == pytest.approx((full[:, 0] - 0.5) * 2)
    assert ndc[:, 1] == pytest.approx((full[:, 1] + 0.25) / 0.75)
    assert ndc[:, 2] == pytest.approx(full[:, 2])


def test_clip_planes_enclose_the_box():
    for mode in MODES:
        cam = Camera.auto(BOX, mode, yaw=30, pitch=20)
        near, far = cam.clip_planes(BOX)
        assert 0 < near < far
        assert np.all(np.abs(project(cam, box_corners(BOX), 1.0, near, far)[:, 2]) < 1)


@pytest.mark.parametrize(
    "kwargs",
    [{"mode": "fisheye"}, {"distance": 0}, {"fov": 180}, {"height": -1}],
)
def test_bad_parameters_are_rejected(kwargs):
    with pytest.raises(ValueError):
        Camera(**kwargs)

"""Turntables, growth sequences and GIF/MP4 writing with a progress bar."""

from __future__ import annotations

import imageio.v3 as iio
import imageio_ffmpeg
import numpy as np
import pytest
from PIL import Image

from sylva.geometry.mesh import Scene
from sylva.render import (
    Camera,
    growth_frames,
    render_frames,
    turntable_frames,
    tween,
    write_animation,
)

SIZE = (48, 36)


def test_turntable_orbits_at_a_constant_distance(plant):
    spin = turntable_frames(plant, n_frames=4, size=SIZE, msaa=0, ground=False, lit=False)
    assert len(spin) == 4
    frames = list(spin)
    assert len(frames) == 4 and all(f.size == SIZE for f in frames)
    assert np.array_equal(np.asarray(next(iter(spin))), np.asarray(frames[0]))  # re-iterable
    arrays = [np.asarray(f) for f in frames]
    assert not np.array_equal(arrays[0], arrays[1])
    # half a turn of an orthographic view shows the mirror image of the silhouette
    cam = Camera.auto(plant, "orthographic", yaw=0, pitch=0)
    ortho = [
        np.asarray(f).sum(axis=-1) < 384
        for f in turntable_frames(plant, 2, SIZE, cam, msaa=0, ground=False, lit=False)
    ]
    assert np.array_equal(ortho[0], ortho[1][:, ::-1])


def test_turntable_in_2d_cannot_turn(plant):
    a, b = turntable_frames(plant, 2, SIZE, "2d", msaa=0, lit=False)
    assert np.array_equal(np.asarray(a), np.asarray(b))


def test_growth_keeps_the_camera_still(geo):
    stem = geo.frustum((0, 0, 0), (0, 1, 0), 0.2, 0.15)
    taller = Scene([stem, geo.frustum((0, 1, 0), (0, 2, 0), 0.15, 0.1)])
    frames = [
        np.asarray(f)
        for f in growth_frames([Scene([stem]), taller], SIZE, msaa=0, lit=False, ground=False)
    ]
    m0, m1 = (f.sum(axis=-1) < 384 for f in frames)
    assert m0.sum() < m1.sum()
    assert np.all(m1[m0])  # the first step's pixels stay where they were


def test_render_frames_is_lazy(plant):
    gen = render_frames(iter([plant, plant]), SIZE, msaa=0)
    first = next(gen)
    assert isinstance(first, Image.Image)
    assert sum(1 for _ in gen) == 1


def test_gif_round_trip_and_progress_on_stderr(tmp_path, capsys):
    frames = [np.full((20, 30, 3), 40 * k, np.uint8) for k in range(5)]
    path = write_animation(frames, tmp_path / "grow.gif", fps=10)
    back = iio.imread(path, index=None)
    assert back.shape == (5, 20, 30, 3)
    assert back[3, 0, 0, 0] == 120
    err = capsys.readouterr().err
    assert "grow.gif" in err and "5/5" in err


def test_mp4_has_every_frame(tmp_path, plant):
    frames = turntable_frames(plant, n_frames=6, size=(47, 35), msaa=0, shadows=False)
    path = write_animation(frames, tmp_path / "spin.mp4", fps=12, progress=False)
    n_frames, _ = imageio_ffmpeg.count_frames_and_secs(str(path))
    assert n_frames == 6


def test_transparent_frames_are_flattened(tmp_path):
    frame = np.zeros((8, 8, 4), np.uint8)
    path = write_animation([frame], tmp_path / "t.gif", bg="red", progress=False)
    assert tuple(iio.imread(path, index=None)[0, 0, 0]) == (255, 0, 0)


@pytest.mark.parametrize(
    ("frames", "name", "kwargs", "match"),
    [
        ([], "x.gif", {}, "no frames"),
        ([np.zeros((4, 4, 3), np.uint8)], "x.avi", {}, "gif"),
        ([np.zeros((4, 4, 3), np.uint8)], "x.gif", {"fps": 0}, "fps"),
        ([np.zeros((4, 4, 3), np.uint8), np.zeros((5, 4, 3), np.uint8)], "x.gif", {}, "frame 1"),
    ],
)
def test_bad_animations(tmp_path, frames, name, kwargs, match):
    with pytest.raises(ValueError, match=match):
        write_animation(frames, tmp_path / name, progress=False, **kwargs)
    assert not (tmp_path / name).exists()


def test_smooth_growth_interpolates_equal_topologies(geo):
    short = Scene([geo.frustum((0, 0, 0), (0, 1, 0), 0.2, 0.15)])
    tall = Scene([geo.frustum((0, 0, 0), (0, 2, 0), 0.2, 0.15)])
    grow = growth_frames([short, tall], SIZE, "2d", substeps=4, msaa=0, lit=False)
    assert len(grow) == 5  # 1 + 3 in-between + 1
    frames = list(grow)
    assert len(frames) == 5
    heights = [int((np.asarray(f).sum(axis=-1) < 384).any(axis=1).sum()) for f in frames]
    assert heights == sorted(heights) and len(set(heights)) == 5
    mid = tween(short.merged(), tall.merged(), 0.5)
    assert mid.bounds()[1, 1] == pytest.approx(1.5)
    other = Scene([geo.box((0, 0, 0), (1, 1, 1))])
    assert tween(short.merged(), other.merged(), 0.5) is None
    held = list(growth_frames([short, other], SIZE, "2d", substeps=2, msaa=0, lit=False))
    assert np.array_equal(np.asarray(held[0]), np.asarray(held[1]))
    with pytest.raises(ValueError, match="substeps"):
        growth_frames([short], SIZE, substeps=0)


def test_turntable_keeps_an_uploaded_scene(plant):
    from sylva.render import Renderer

    gpu = Renderer.default().upload(plant)
    list(turntable_frames(gpu, 2, SIZE, msaa=0, ground=False))
    assert not gpu.empty  # the caller's upload is not released
    gpu.release()

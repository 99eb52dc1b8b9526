"""Colour maps, gradients and normal maps."""

import numpy as np
import pytest

from sylva.texture import (
    COLORMAPS,
    ColormapError,
    apply_colormap,
    get_colormap,
    gradient,
    normal_map,
    normalize,
)
from sylva.texture.colormap import parse_color


def test_gradient_interpolates_linearly():
    cm = gradient([(0.0, "#000000"), (0.25, (255, 0, 0)), (1.0, "#ffffff")])
    np.testing.assert_allclose(cm(0.125), [0.5, 0, 0])
    np.testing.assert_allclose(cm([0.0, 1.0]), [[0, 0, 0], [1, 1, 1]])
    np.testing.assert_allclose(cm(2.0), [1, 1, 1])  # clipped
    np.testing.assert_allclose(cm(0.75, cycles=2), cm(0.5))


def test_named_maps_and_reverse():
    assert {"gray", "marble", "wood", "bark", "leaf", "grass", "terrain"} <= set(COLORMAPS)
    np.testing.assert_allclose(get_colormap("gray_r")(0.0), [1, 1, 1])
    with pytest.raises(ColormapError, match="unknown colour map"):
        get_colormap("nope")


def test_apply_colormap_and_normalize():
    rgb = apply_colormap(np.array([[-1.0, 0.0, 1.0]]), "gray", vmin=-1, vmax=1)
    assert rgb.dtype == np.uint8 and rgb[0, :, 0].tolist() == [0, 128, 255]
    assert normalize([5.0, 5.0]).tolist() == [0.0, 0.0]


def test_parse_color():
    assert parse_color("#f00") == (1.0, 0.0, 0.0)
    with pytest.raises(ColormapError):
        parse_color("#12345")
    with pytest.raises(ColormapError):
        parse_color((300, 0, 0))


def test_normal_map():
    flat = normal_map(np.zeros((4, 4)))
    assert flat[1, 1].tolist() == [128, 128, 255]
    ramp = np.tile(np.arange(8.0), (8, 1))  # height grows with x
    n = normal_map(ramp, strength=1.0, encode=False)
    np.testing.assert_allclose(n[4, 4], [-1 / np.sqrt(2), 0, 1 / np.sqrt(2)], atol=1e-6)
    rows = np.tile(np.arange(8.0)[:, None], (1, 8))  # height grows downwards (-y)
    n = normal_map(rows, encode=False)
    assert n[4, 4, 1] > 0.5
    wave = np.sin(np.linspace(0, 2 * np.pi, 16, endpoint=False))[None, :].repeat(4, 0)
    t = normal_map(wave, tileable=True, encode=False)
    np.testing.assert_allclose(t[:, 0], normal_map(np.roll(wave, -1, 1), tileable=True,
                                                   encode=False)[:, -1], atol=1e-12)

"""Escape-time fractals and IFS."""

import math

import numpy as np
import pytest

from sylva.texture import (
    BARNSLEY_FERN,
    FractalError,
    Ifs,
    barnsley_j1,
    burning_ship,
    colorize,
    ifs,
    in_mandelbrot,
    julia,
    mandelbrot,
)

MEMBERS = [0, -1, -2, 1j, -1j, -0.1 + 0.1j, 0.25, -0.123 + 0.745j, -1.75, -0.5 + 0.5j]
NON_MEMBERS = [1, 0.26, -2.01, 0.5 + 0.5j, -0.75 + 0.1j, 2j, 0.4 + 0.4j, -1.5 + 0.5j]


def test_known_members_and_non_members():
    assert in_mandelbrot(MEMBERS, maxiter=5000).all()
    assert not in_mandelbrot(NON_MEMBERS, maxiter=5000).any()
    assert in_mandelbrot(0) is True


def test_mandelbrot_grid_inside_and_smooth_count():
    # a 3x3 image of width 6 centred at 0: pixels at re, im in {-2, 0, 2} ... step 2
    m = mandelbrot((3, 3), center=0, width=6.0, maxiter=200, bailout=256.0,
                   dtype=np.float64)
    assert m[1, 1] == -1.0  # c = 0
    # c = 2 (right middle pixel): z = 2, 6, 38, 1446 escapes |z| >= 256 after n = 4
    zs = [2.0, 6.0, 38.0, 1446.0]
    nu = 4 + 1 - math.log2(math.log(zs[-1]) / math.log(256.0))
    assert m[1, 2] == pytest.approx(nu, abs=1e-9)
    ints = mandelbrot((3, 3), center=0, width=6.0, maxiter=200, bailout=256.0, smooth=False)
    assert ints[1, 2] == 4


def test_smooth_colouring_is_continuous_along_the_real_axis():
    kw = {"center": (1.45, 0), "width": 1.7, "maxiter": 500}
    row = mandelbrot((1, 400), dtype=np.float64, **kw)[0]
    ints = mandelbrot((1, 400), smooth=False, **kw)[0]
    assert np.all(row > 0)
    assert np.abs(np.diff(ints)).max() >= 1  # integer counts jump ...
    assert np.abs(np.diff(row)).max() < 0.5  # ... smooth counts do not
    assert np.all(np.diff(row) <= 1e-12)  # escape gets faster as c grows


def test_julia_and_burning_ship():
    j = julia((3, 3), c=0, center=0, width=3.0, maxiter=100)
    # c = 0: |z0| < 1 stays, |z0| > 1 escapes
    assert j[1, 1] == -1.0 and j[0, 0] > 0
    b = burning_ship((3, 3), center=0, width=4.5, maxiter=100)
    assert b[1, 1] == -1.0 and b[0, 0] > 0


def _uf_barnsley(z, c, maxiter=149, bound=4.0):
    """Ultra Fractal barnsleyj1 listing (seed 003 §5.5), literally."""
    n = 0
    while n < maxiter and (z.real**2 + z.imag**2) < bound:
        z = (z - 1) * c if z.real >= 0 else (z + 1) * c
        n += 1
    return n if (z.real**2 + z.imag**2) >= bound else -1


def test_barnsley_j1_follows_the_ultra_fractal_formula():
    b = barnsley_j1((9, 11), start=(0.6, 1.1), width=4.0, smooth=False)
    re = (np.arange(11) - 5) * 4.0 / 11
    im = (4 - np.arange(9)) * 4.0 / 11
    want = [[_uf_barnsley(complex(x, y), 0.6 + 1.1j) for x in re] for y in im]
    np.testing.assert_array_equal(b, want)
    b3 = barnsley_j1((9, 11), width=4.0, uf_bailout=3.0, smooth=False)
    want3 = [[_uf_barnsley(complex(x, y), 0.6 + 1.1j, bound=3.0) for x in re] for y in im]
    np.testing.assert_array_equal(b3, want3)
    with pytest.raises(FractalError):
        barnsley_j1((4, 4), variant="zzz")


def test_colorize():
    counts = np.array([[-1.0, 0.0, 5.0, 10.0]])
    rgb = colorize(counts, "gray", inside="#ff0000")
    assert rgb.shape == (1, 4, 3) and rgb.dtype == np.uint8
    assert rgb[0, 0].tolist() == [255, 0, 0]
    assert rgb[0, 1].tolist() == [0, 0, 0] and rgb[0, 3].tolist() == [255, 255, 255]


def test_sierpinski_has_an_empty_middle_and_fern_is_deterministic():
    s = ifs((128, 128), "sierpinski", points=200_000, seed=1, margin=0.0)
    # the middle triangle (centroid at x = 0.5, y = sqrt(3)/6 of the unit triangle) is empty
    h = 128
    ty = h - 1 - int((math.sqrt(3) / 6 + (h / 128 - math.sqrt(3) / 2) / 2) * 128)
    assert s[ty - 2:ty + 3, 62:67].max() == 0.0
    assert s.max() == 1.0 and (s > 0).mean() > 0.05
    a = ifs((64, 64), BARNSLEY_FERN, points=50_000, seed=3)
    b = ifs((64, 64), "fern", points=50_000, seed=3)
    np.testing.assert_array_equal(a, b)
    with pytest.raises(FractalError, match="sum to 1"):
        Ifs([[[1, 0], [0, 1]]], [[0, 0]], [0.5], (0, 1, 0, 1))
    with pytest.raises(FractalError, match="unknown IFS"):
        ifs((8, 8), "dragon")

"""Worley cellular noise: exact values on a regular grid of points, and an exhaustive
search check for jittered points."""

import math

import numpy as np
import pytest

from sylva.texture import WORLEY_OUTPUTS, noise_grid, worley, worley_features
from sylva.texture._cellkernels import hash32

SQ = math.sqrt


# jitter = 0 puts one feature point at every cell centre (i + 0.5, j + 0.5)
@pytest.mark.parametrize("x,y,metric,f1,f2,f3", [
    (0.5, 0.5, "euclidean", 0.0, 1.0, 1.0),
    (0.2, 0.5, "euclidean", 0.3, 0.7, SQ(0.3**2 + 1)),
    (1.0, 1.0, "euclidean", SQ(0.5), SQ(0.5), SQ(0.5)),
    (0.2, 0.4, "manhattan", 0.4, 0.8, 1.2),
    (0.2, 0.4, "chebyshev", 0.3, 0.7, 0.9),
    (0.2, 0.5, "euclidean2", 0.09, 0.49, 1.09),
])
def test_regular_points_give_exact_distances(x, y, metric, f1, f2, f3):
    got = worley_features(x, y, metric=metric, jitter=0.0, dtype=np.float64)
    assert got[0] == pytest.approx(f1, abs=1e-12)
    assert got[1] == pytest.approx(f2, abs=1e-12)
    assert got[2] == pytest.approx(f3, abs=1e-12)


def test_combinations_follow_seed_003():
    x, y = 0.2, 0.5  # F1 = 0.3, F2 = 0.7, F3 = sqrt(1.09)
    f1, f2, f3 = 0.3, 0.7, SQ(1.09)
    want = {"f1": f1, "f2": f2, "f3": f3, "f2-f1": f2 - f1, "f1+f2": f1 + f2,
            "f1*f2": f1 * f2, "sqrt(f1*f2)": SQ(f1 * f2), "sqrt(f2-f1)": SQ(f2 - f1),
            "1-f1": 1 - f1, "1-f2": 1 - f2}
    for out, v in want.items():
        assert worley(x, y, jitter=0.0, output=out) == pytest.approx(v, abs=1e-12), out
    lin = worley(x, y, jitter=0.0, output="linear", coefficients=(-1.0, 0.5, 2.0))
    assert lin == pytest.approx(-f1 + 0.5 * f2 + 2 * f3, abs=1e-12)
    assert set(want) | {"cell", "linear"} == set(WORLEY_OUTPUTS)


def _brute(x, y, seed, jitter=1.0):
    """All feature points within 6 cells, placed with the library's documented hash."""
    d = []
    hs = hash32.py_func(seed)
    for i in range(math.floor(x) - 6, math.floor(x) + 7):
        for j in range(math.floor(y) - 6, math.floor(y) + 7):
            h = hash32.py_func(hs ^ (i & 0xFFFFFFFF))
            h = hash32.py_func(h ^ (j & 0xFFFFFFFF))
            px = i + 0.5 + jitter * (hash32.py_func(h ^ 0x68E31DA4) / 2**32 - 0.5)
            py = j + 0.5 + jitter * (hash32.py_func(h ^ 0xB5297A4D) / 2**32 - 0.5)
            d.append(math.hypot(px - x, py - y))
    return sorted(d)[:3]


def test_jittered_search_finds_the_true_nearest_points():
    pts = np.random.default_rng(5).uniform(-30, 30, (150, 2))
    f1, f2, f3, _ = worley_features(pts[:, 0], pts[:, 1], seed=9, dtype=np.float64)
    for k, (x, y) in enumerate(pts):
        want = _brute(x, y, 9)
        assert [f1[k], f2[k], f3[k]] == pytest.approx(want, abs=1e-12)


def test_ordering_ids_and_3d():
    pts = np.random.default_rng(6).uniform(-10, 10, (200, 3))
    f1, f2, f3, cell = worley_features(*pts.T, seed=2)
    assert np.all(f1 <= f2) and np.all(f2 <= f3) and np.all(f1 >= 0)
    assert np.all((cell >= 0) & (cell < 1))
    # points very close together share their nearest cell's id
    a = worley(pts[:, 0], pts[:, 1], pts[:, 2], output="cell", seed=2)
    b = worley(pts[:, 0] + 1e-7, pts[:, 1], pts[:, 2], output="cell", seed=2)
    assert np.mean(a == b) > 0.99
    f4 = worley(0.3, 0.4, 0.5, 0.6, jitter=0.0)
    assert f4 == pytest.approx(SQ(0.2**2 + 0.1**2 + 0.0 + 0.1**2), abs=1e-12)


def test_f2_minus_f1_vanishes_on_cell_borders():
    # between two regular points the border is equidistant
    assert worley(1.0, 0.5, jitter=0.0, output="f2-f1") == pytest.approx(0.0, abs=1e-12)


def test_worley_grid_matches_points():
    g = noise_grid((5, 6), kind="worley", output="f2-f1", metric="manhattan", scale=6 * 0.7,
                   seed=3, dtype=np.float64)
    yy, xx = np.mgrid[0:5, 0:6] * 0.7
    p = worley(xx, yy, output="f2-f1", metric="manhattan", seed=3, dtype=np.float64)
    np.testing.assert_allclose(g, p, atol=1e-12)

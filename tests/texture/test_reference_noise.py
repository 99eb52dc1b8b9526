"""Improved Perlin noise and simplex noise against the published reference implementations
(transliterated in ``reference_impls``), value for value."""

import numpy as np
import pytest

from sylva.texture import improved_perlin, noise_grid, simplex

from . import reference_impls as ref

RNG = np.random.default_rng(20260101)
# dozens of points: random in a wide range, near-lattice, negative, on lattice planes
PTS = np.concatenate([
    RNG.uniform(-300.0, 300.0, (40, 4)),
    RNG.uniform(-2.0, 2.0, (20, 4)),
    np.round(RNG.uniform(-50, 50, (10, 4))) + RNG.choice([0.0, 1e-9, -1e-9, 0.5], (10, 4)),
    [[3.14, 42.0, 7.0, 0.0], [0.0, 0.0, 0.0, 0.0], [-0.5, 255.5, 256.25, -1.0],
     [1e4 + 0.1, -1e4 + 0.7, 123.456, 78.9]],
])


def test_improved_perlin_literal_value():
    assert improved_perlin(3.14, 42, 7) == 0.13691995878400012
    assert ref.improved_noise(3.14, 42, 7) == 0.13691995878400012


@pytest.mark.parametrize("p", PTS[:, :3].tolist())
def test_improved_perlin_3d_matches_perlin_reference(p):
    assert improved_perlin(*p) == pytest.approx(ref.improved_noise(*p), abs=1e-12)


def test_improved_perlin_2d_is_the_reference_at_z0():
    got = improved_perlin(PTS[:, 0], PTS[:, 1], dtype=np.float64)
    want = [ref.improved_noise(x, y, 0.0) for x, y in PTS[:, :2]]
    np.testing.assert_allclose(got, want, rtol=0, atol=1e-12)


def test_improved_perlin_arrays_match_reference():
    got = improved_perlin(PTS[:, 0], PTS[:, 1], PTS[:, 2], dtype=np.float64)
    want = [ref.improved_noise(*p) for p in PTS[:, :3]]
    np.testing.assert_allclose(got, want, rtol=0, atol=1e-12)


@pytest.mark.parametrize("p", PTS[:, :2].tolist())
def test_simplex_2d_matches_gustavson(p):
    assert simplex(*p) == pytest.approx(ref.simplex2(*p), abs=1e-12)


@pytest.mark.parametrize("p", PTS[:, :3].tolist())
def test_simplex_3d_matches_gustavson(p):
    assert simplex(*p) == pytest.approx(ref.simplex3(*p), abs=1e-12)


@pytest.mark.parametrize("p", PTS.tolist())
def test_simplex_4d_matches_gustavson(p):
    assert simplex(*p) == pytest.approx(ref.simplex4(*p), abs=1e-12)


def test_simplex_arrays_match_gustavson():
    for nd, fn in ((2, ref.simplex2), (3, ref.simplex3), (4, ref.simplex4)):
        got = simplex(*PTS[:, :nd].T, dtype=np.float64)
        want = [fn(*p) for p in PTS[:, :nd]]
        np.testing.assert_allclose(got, want, rtol=0, atol=1e-12)


@pytest.mark.parametrize("kind,fn", [("improved", lambda x, y, z: ref.improved_noise(x, y, z)),
                                     ("simplex", lambda x, y, z: ref.simplex3(x, y, z))])
def test_grid_fast_path_matches_reference(kind, fn):
    # an 8x12 image with 3 cells across: x = i * 3/12, y = j * 3/12, z = time
    g = noise_grid((8, 12), kind=kind, scale=3.0, time=0.3, dtype=np.float64)
    want = np.array([[fn(i * 0.25, j * 0.25, 0.3) for i in range(12)] for j in range(8)])
    np.testing.assert_allclose(g, want, rtol=0, atol=1e-12)


def test_grid_2d_fast_path_matches_reference():
    g = noise_grid((5, 7), kind="simplex", scale=7 * 0.37, offset=(-3.0, 2.0),
                   dtype=np.float64)
    want = [[ref.simplex2(-3.0 + i * 0.37, 2.0 + j * 0.37) for i in range(7)] for j in range(5)]
    np.testing.assert_allclose(g, want, rtol=0, atol=1e-12)
    g = noise_grid((5, 7), kind="improved", scale=7 * 0.37, offset=(-3.0, 2.0),
                   dtype=np.float64)
    want = [[ref.improved_noise(-3.0 + i * 0.37, 2.0 + j * 0.37, 0.0) for i in range(7)]
            for j in range(5)]
    np.testing.assert_allclose(g, want, rtol=0, atol=1e-12)

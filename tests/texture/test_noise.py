"""Properties of the noise functions: lattice zeros, periodicity, ranges, seeds, options."""

import math

import numpy as np
import pytest

from sylva.errors import SylvaError
from sylva.texture import (
    KINDS,
    REFERENCE_PERMUTATION,
    NoiseError,
    domain_warp,
    fbm,
    improved_perlin,
    noise_grid,
    noise_tables,
    perlin,
    ridged,
    simplex,
    turbulence,
    value_noise,
    worley,
)

LATTICE = [value_noise, perlin, improved_perlin]


def _seam_ratio(img, axis):
    """Mean |jump| across the wrap edge / mean |jump| between neighbours."""
    a = np.moveaxis(np.asarray(img, dtype=np.float64), axis, 0)
    inner = np.abs(np.diff(a, axis=0)).mean()
    edge = np.abs(a[0] - a[-1]).mean()
    return edge / inner


@pytest.mark.parametrize("fn", [perlin, improved_perlin])
@pytest.mark.parametrize("seed", [None, 0, 12345])
def test_gradient_noise_is_zero_at_lattice_points(fn, seed):
    ij = np.random.default_rng(1).integers(-400, 400, (50, 4)).astype(float)
    for nd in (2, 3, 4):
        v = fn(*ij[:, :nd].T, seed=seed, dtype=np.float64)
        assert np.all(v == 0.0)


def test_value_noise_interpolates_lattice_values():
    t = noise_tables(5)
    p, vals = t.perm, t.values

    def lattice(i, j):
        return vals[p[p[i & 255] + (j & 255)]]

    assert value_noise(3.0, 7.0, seed=5) == pytest.approx(lattice(3, 7), abs=1e-15)
    # linear: halfway is the mean; cosine at t = 0.25 weighs by (1 - cos(pi/4)) / 2
    half = value_noise(3.5, 7.0, seed=5, interpolation="linear")
    assert half == pytest.approx((lattice(3, 7) + lattice(4, 7)) / 2, abs=1e-15)
    f = (1 - math.cos(math.pi * 0.25)) / 2
    q = value_noise(3.25, 7.0, seed=5, interpolation="cosine")
    assert q == pytest.approx(lattice(3, 7) * (1 - f) + lattice(4, 7) * f, abs=1e-15)
    f = 3 * 0.25**2 - 2 * 0.25**3
    q = value_noise(3.25, 7.0, seed=5, interpolation="cubic")
    assert q == pytest.approx(lattice(3, 7) * (1 - f) + lattice(4, 7) * f, abs=1e-15)
    f = 6 * 0.25**5 - 15 * 0.25**4 + 10 * 0.25**3
    q = value_noise(3.25, 7.0, seed=5, interpolation="quintic")
    assert q == pytest.approx(lattice(3, 7) * (1 - f) + lattice(4, 7) * f, abs=1e-15)


def test_interpolation_changes_improved_noise():
    a = improved_perlin(1.3, 2.6, 0.2, interpolation="quintic")
    b = improved_perlin(1.3, 2.6, 0.2, interpolation="cubic")
    assert a != b


@pytest.mark.parametrize("fn", LATTICE)
@pytest.mark.parametrize("nd", [2, 3, 4])
def test_period_makes_noise_repeat(fn, nd):
    pts = np.random.default_rng(2).uniform(-20, 20, (64, nd))
    per = (5, 7, 3, 4)[:nd]
    a = fn(*pts.T, period=per, seed=3, dtype=np.float64)
    shifted = pts + np.array(per) * np.array([1, -2, 3, -1])[:nd]
    b = fn(*shifted.T, period=per, seed=3, dtype=np.float64)
    np.testing.assert_allclose(a, b, rtol=0, atol=1e-12)


def test_worley_period_and_fbm_period():
    pts = np.random.default_rng(3).uniform(-9, 9, (50, 3))
    a = worley(*pts.T, period=4, seed=1, dtype=np.float64)
    b = worley(*(pts + [4, 8, -12]).T, period=4, seed=1, dtype=np.float64)
    np.testing.assert_allclose(a, b, atol=1e-12)
    a = fbm(pts[:, 0], pts[:, 1], period=3, octaves=4, dtype=np.float64)
    b = fbm(pts[:, 0] + 3, pts[:, 1] - 6, period=3, octaves=4, dtype=np.float64)
    np.testing.assert_allclose(a, b, atol=1e-12)


def test_simplex_has_no_lattice_period():
    with pytest.raises(NoiseError, match="torus"):
        simplex(0.5, 0.5, dtype=None) and simplex([0.5], [0.5]) and fbm(
            0.5, 0.5, kind="simplex", period=4)


@pytest.mark.parametrize("kind", list(KINDS))
def test_tileable_grids_have_no_seam(kind):
    img = noise_grid((48, 64), kind=kind, scale=5.3, octaves=3, seed=9, tileable=True)
    assert _seam_ratio(img, 0) < 2.0
    assert _seam_ratio(img, 1) < 2.0
    plain = noise_grid((48, 64), kind=kind, scale=5.3, octaves=3, seed=9)
    assert max(_seam_ratio(plain, 0), _seam_ratio(plain, 1)) > 2.5


@pytest.mark.parametrize("kind", ["value", "perlin", "improved", "worley"])
def test_tileable_lattice_grid_continues_exactly(kind):
    # the grid samples x = i * P / W; its continuation at x + P equals column i
    w, h, cells = 40, 20, 4
    img = noise_grid((h, w), kind=kind, scale=cells, seed=2, tileable=True, dtype=np.float64)
    x = np.arange(w) * cells / w
    y = np.full(w, 3 * (cells * h / w) / h)  # row 3
    kw = {"seed": 2, "dtype": np.float64, "period": (cells, cells * h // w)}
    fn = {"value": value_noise, "perlin": perlin, "improved": improved_perlin,
          "worley": worley}[kind]
    np.testing.assert_allclose(fn(x + cells, y, **kw), img[3], atol=1e-12)


def test_tileable_volume_and_animation():
    vol = noise_grid((16, 16, 16), kind="improved", scale=4, tileable=True, octaves=2)
    for ax in range(3):
        assert _seam_ratio(vol, ax) < 2.0
    f0 = noise_grid((32, 32), kind="simplex", tileable=True, time=0.0, seed=1)
    f1 = noise_grid((32, 32), kind="simplex", tileable=True, time=0.5, seed=1)
    assert _seam_ratio(f1, 1) < 2.0 and not np.allclose(f0, f1)
    with pytest.raises(NoiseError, match="tileable simplex"):
        noise_grid((8, 8, 8), kind="simplex", tileable=True)


@pytest.mark.parametrize("kind", ["value", "perlin", "improved", "simplex"])
def test_range_and_mean(kind):
    img = noise_grid((256, 256), kind=kind, scale=32, seed=4, dtype=np.float64)
    assert img.min() >= -1.0 and img.max() <= 1.0
    assert abs(img.mean()) < 0.05
    assert img.std() > 0.1
    f = noise_grid((128, 128), kind=kind, scale=8, octaves=6, seed=4)
    assert f.min() >= -1.0 and f.max() <= 1.0
    t = noise_grid((128, 128), kind=kind, scale=8, octaves=6, fractal="turbulence", seed=4)
    assert t.min() >= 0.0 and t.max() <= 1.0
    r = noise_grid((128, 128), kind=kind, scale=8, octaves=6, fractal="ridged", seed=4)
    assert r.min() >= 0.0 and r.max() <= 1.0


def test_fractal_sums_reduce_to_the_base_noise():
    x, y, z = 1.37, -4.2, 0.77
    n = improved_perlin(x, y, z)
    assert fbm(x, y, z, octaves=1) == pytest.approx(n, abs=1e-15)
    assert turbulence(x, y, z, octaves=1) == pytest.approx(abs(n), abs=1e-15)
    assert ridged(x, y, z, octaves=1) == pytest.approx((1 - abs(n)) ** 2, abs=1e-15)
    # unnormalised fBm of two octaves with frequency/persistence as documented
    two = fbm(x, y, z, octaves=2, persistence=0.25, lacunarity=3.0, normalize=False)
    nn = fbm(x, y, z, octaves=2, persistence=0.25, lacunarity=3.0)
    assert two == pytest.approx(nn * 1.25, abs=1e-14)


def test_grid_and_point_paths_agree():
    g = noise_grid((6, 9), kind="value", scale=9 * 0.3, octaves=4, seed=8, dtype=np.float64)
    yy, xx = np.mgrid[0:6, 0:9] * 0.3
    p = fbm(xx, yy, kind="value", octaves=4, seed=8, dtype=np.float64)
    np.testing.assert_allclose(g, p, atol=1e-12)


def test_seeds_are_deterministic_and_distinct():
    a = noise_grid((32, 32), kind="simplex", seed=11, octaves=3)
    b = noise_grid((32, 32), kind="simplex", seed=11, octaves=3)
    c = noise_grid((32, 32), kind="simplex", seed=12, octaves=3)
    assert np.array_equal(a, b) and not np.allclose(a, c)
    np.testing.assert_array_equal(noise_tables(None).perm[:256], REFERENCE_PERMUTATION)
    assert not np.array_equal(noise_tables(0).perm[:256], REFERENCE_PERMUTATION)
    # the seeded permutation is numpy's PCG64 permutation: stable across machines
    np.testing.assert_array_equal(noise_tables(7).perm[:256],
                                  np.random.default_rng(7).permutation(256))


def test_dtypes():
    assert noise_grid((4, 4)).dtype == np.float32
    assert noise_grid((4, 4), dtype=np.float64).dtype == np.float64
    assert improved_perlin([0.5], [0.5]).dtype == np.float32
    assert isinstance(improved_perlin(0.5, 0.5), float)
    with pytest.raises(NoiseError):
        noise_grid((4, 4), dtype=np.int32)


def test_4d_grids_and_time():
    g = noise_grid((3, 4, 5, 6), kind="simplex", octaves=2)
    assert g.shape == (3, 4, 5, 6)
    a = noise_grid((4, 5, 6), kind="improved", time=0.0)
    b = noise_grid((4, 5, 6), kind="improved", time=0.4)
    assert a.shape == b.shape == (4, 5, 6) and not np.allclose(a, b)


def test_domain_warp():
    wx, wy = domain_warp([0.1, 2.0], [0.3, -1.0], amount=0.0)
    assert wx.tolist() == [0.1, 2.0] and wy.tolist() == [0.3, -1.0]
    wx, wy = domain_warp([0.1, 2.0], [0.3, -1.0], amount=0.5, seed=1)
    assert not np.allclose(wx, [0.1, 2.0])
    a = noise_grid((32, 32), warp=1.0, seed=1, octaves=3)
    b = noise_grid((32, 32), warp=0.0, seed=1, octaves=3)
    assert not np.allclose(a, b)
    t = noise_grid((32, 48), warp=1.0, seed=1, octaves=3, tileable=True)
    assert _seam_ratio(t, 0) < 2.0 and _seam_ratio(t, 1) < 2.0


@pytest.mark.parametrize("kwargs,match", [
    ({"kind": "blue"}, "unknown noise kind"),
    ({"octaves": 0}, "octaves"),
    ({"persistence": -1}, "persistence"),
    ({"fractal": "wobbly"}, "unknown fractal"),
    ({"interpolation": "bezier"}, "unknown interpolation"),
    ({"seed": -3}, "seed"),
    ({"seed": 1.5}, "seed"),
    ({"kind": "worley", "metric": "cosine"}, "unknown metric"),
    ({"kind": "worley", "jitter": 2.0}, "jitter"),
    ({"scale": 0}, "scale"),
])
def test_bad_parameters_raise_sylva_errors(kwargs, match):
    with pytest.raises(SylvaError, match=match):
        noise_grid((4, 4), **kwargs)


def test_bad_coordinates():
    with pytest.raises(NoiseError, match="broadcast"):
        improved_perlin([1, 2], [1, 2, 3])
    with pytest.raises(NoiseError, match="finite"):
        simplex(np.nan, 1.0)
    with pytest.raises(NoiseError, match="period"):
        value_noise(1.0, 2.0, period=(3,))


def test_results_do_not_depend_on_the_thread_count():
    import numba

    before = numba.get_num_threads()
    try:
        numba.set_num_threads(1)
        one = [noise_grid((33, 17), kind=k, octaves=3, seed=5) for k in KINDS]
        numba.set_num_threads(numba.config.NUMBA_NUM_THREADS)
        many = [noise_grid((33, 17), kind=k, octaves=3, seed=5) for k in KINDS]
    finally:
        numba.set_num_threads(before)
    for a, b in zip(one, many):
        np.testing.assert_array_equal(a, b)

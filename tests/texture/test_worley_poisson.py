"""Worley noise over a Poisson point process (``density=``), checked against the published
distribution of nearest-neighbour distances of a homogeneous Poisson process, against an
exhaustive search over the same points, and for bit-identical defaults."""

import math

import numpy as np
import pytest

from sylva.texture import NoiseError, fbm, noise_grid, worley, worley_features
from sylva.texture._cellkernels import hash32, poisson_cell_points
from sylva.texture.presets import render

N_SAMPLES = 200_000


def _f1_sample(lam, metric="euclidean", output="f1", n=N_SAMPLES, seed=12):
    """The output at ``n`` uniformly random points of a large window (many cells)."""
    pts = np.random.default_rng(2024).uniform(-400.0, 400.0, (n, 2))
    return worley(
        pts[:, 0], pts[:, 1], seed=seed, density=lam, metric=metric, output=output, dtype=np.float64
    )


# -- the nearest-neighbour distance law of a 2D Poisson process (e.g. Chiu, Stoyan, Kendall
# & Mecke, "Stochastic Geometry and its Applications", 3rd ed., §2.4; Illian et al. 2008):
# P(F_k > r) = P(Poisson(lam * |B(r)|) < k), |B(r)| = pi r^2 (Euclidean), 2 r^2 (Manhattan),
# 4 r^2 (Chebyshev).  Hence E[F1] = 1 / (2 sqrt(lam)) and E[F1^2] = 1 / (lam pi).
@pytest.mark.parametrize("lam", [1.0, 3.0])
def test_mean_f1_is_half_over_root_density(lam):
    f1 = _f1_sample(lam)
    mean = 1.0 / (2.0 * math.sqrt(lam))
    var = 1.0 / (lam * math.pi) - mean**2  # (4 - pi) / (4 pi lam)
    se = math.sqrt(var / f1.size)
    assert abs(f1.mean() - mean) < 4.0 * se, (f1.mean(), mean, se)
    # E[F1^2] = 1 / (lam pi); Var(F1^2) = E[F1^4] - E[F1^2]^2 = 2/(lam pi)^2 - 1/(lam pi)^2
    m2 = 1.0 / (lam * math.pi)
    assert abs((f1**2).mean() - m2) < 4.0 * math.sqrt(m2**2 / f1.size)


def _poisson_cdf_ge(k, mu):
    """P(Poisson(mu) >= k)."""
    return 1.0 - sum(np.exp(-mu) * mu**j / math.factorial(j) for j in range(k))


@pytest.mark.parametrize("lam", [1.0, 3.0])
@pytest.mark.parametrize(
    "metric,area,power",
    [
        ("euclidean", math.pi, 2),
        ("manhattan", 2.0, 2),
        ("chebyshev", 4.0, 2),
        ("euclidean2", math.pi, 1),  # squared distance s = r^2: |B| = pi s
    ],
)
@pytest.mark.parametrize("k", [1, 2, 3])
def test_distance_distribution_matches_poisson_process(lam, metric, area, power, k):
    fk = np.sort(_f1_sample(lam, metric, output=f"f{k}", n=50_000))
    # Kolmogorov-Smirnov distance to P(F_k <= r) = P(Poisson(lam |B(r)|) >= k); the 99.9 %
    # critical value for n = 50 000 is 1.95 / sqrt(n) = 0.0087 (samples are nearly
    # independent: 50 000 points in 640 000 cells)
    emp_hi = np.arange(1, fk.size + 1) / fk.size
    emp_lo = np.arange(0, fk.size) / fk.size
    cdf = _poisson_cdf_ge(k, lam * area * fk**power)
    ks = max(np.max(emp_hi - cdf), np.max(cdf - emp_lo))
    assert ks < 0.0087, ks


def _cells(lam, n=200, seed=5, ndim=2):
    return [
        poisson_cell_points(ndim, i, j, 0, 0, 0, 0, 0, 0, lam, seed)
        for i in range(-n // 2, n // 2)
        for j in range(-n // 2, n // 2)
    ]


@pytest.mark.parametrize("lam", [0.5, 1.0, 3.0, 8.0])
def test_points_per_cell_are_poisson(lam):
    counts = np.array([len(c[1]) for c in _cells(lam)])
    n = counts.size
    assert abs(counts.mean() - lam) < 4.0 * math.sqrt(lam / n)
    assert abs(counts.var() - lam) < 0.05 * lam  # Poisson: variance = mean
    for j in range(6):
        p = math.exp(-lam) * lam**j / math.factorial(j)  # e^-lam for empty cells
        assert abs(np.mean(counts == j) - p) < 4.0 * math.sqrt(p * (1 - p) / n) + 1e-9, j
    # each point lies inside its own cell, uniformly
    pts = np.concatenate([c[0] - np.floor(c[0]) for c in _cells(lam, n=60)])
    assert pts.min() >= 0.0 and pts.max() < 1.0
    assert abs(pts.mean() - 0.5) < 4.0 * math.sqrt(1 / 12 / pts.size)


def _window(ndim, lo, hi, lam, seed, period=(0, 0, 0, 0)):
    pts, hs = [], []
    rng = range(lo, hi)
    for idx in np.ndindex(*(len(rng),) * ndim):
        c = [lo + i for i in idx] + [0] * (4 - ndim)
        p, h = poisson_cell_points(ndim, *c, *period, lam, seed)
        pts.append(p)
        hs.append(h)
    return np.concatenate(pts), np.concatenate(hs)


def _brute(q, pts, hs, metric):
    dd = pts - q
    if metric == "manhattan":
        d = np.abs(dd).sum(axis=1)
    elif metric == "chebyshev":
        d = np.abs(dd).max(axis=1)
    else:
        d = np.zeros(len(pts))
        for a in range(dd.shape[1]):
            d = d + dd[:, a] * dd[:, a]
        if metric == "euclidean":
            d = np.sqrt(d)
    order = np.argsort(d, kind="stable")
    cid = hash32.py_func(int(hs[order[0]]) ^ 0x2545F491) / 2**32
    return d[order[0]], d[order[1]], d[order[2]], cid


@pytest.mark.parametrize(
    "ndim,lam,lo,hi",
    [
        (2, 0.05, -30, 40),
        (2, 0.4, -12, 22),
        (2, 3.0, -5, 15),
        (3, 0.3, -8, 14),
        (3, 2.0, -4, 10),
        (4, 1.0, -3, 7),
    ],
)
@pytest.mark.parametrize("metric", ["euclidean", "manhattan", "chebyshev", "euclidean2"])
def test_search_is_exact_against_brute_force(ndim, lam, lo, hi, metric):
    pts, hs = _window(ndim, lo, hi, lam, seed=31)
    m = 0.3 * (hi - lo)
    q = np.random.default_rng(ndim).uniform(lo + m, hi - m, (40, ndim))
    got = worley_features(*q.T, seed=31, metric=metric, density=lam, dtype=np.float64)
    got = np.array(got)
    assert (got[0] <= got[1]).all() and (got[1] <= got[2]).all()
    for i in range(len(q)):
        want = _brute(q[i], pts, hs, metric)
        # the window reaches far enough: F3 is within the distance to its border
        assert want[2] < min(q[i].min() - lo, hi - q[i].max()) ** (
            1 if metric != "euclidean2" else 2
        )
        np.testing.assert_allclose(got[:, i], want, rtol=1e-14, atol=0)


def test_grid_matches_points_and_jitter_is_ignored():
    for ndim in (2, 3):
        shape = (5, 6) if ndim == 2 else (3, 5, 6)
        g = noise_grid(
            shape,
            kind="worley",
            output="f2-f1",
            metric="manhattan",
            scale=6 * 0.7,
            seed=3,
            density=1.7,
            dtype=np.float64,
        )
        grids = np.mgrid[tuple(slice(0, s) for s in shape)] * 0.7
        p = worley(
            *grids[::-1], output="f2-f1", metric="manhattan", seed=3, density=1.7, dtype=np.float64
        )
        np.testing.assert_allclose(g, p, atol=1e-12)
    pts = np.random.default_rng(1).uniform(-5, 5, (200, 2)).T
    for out in ("f1", "f3", "cell"):
        a = worley(*pts, density=2.0, jitter=0.0, output=out, seed=4)
        b = worley(*pts, density=2.0, jitter=1.0, output=out, seed=4)
        np.testing.assert_array_equal(a, b)
    # and the Poisson process is a different point set from the jittered grid
    assert not np.allclose(worley(*pts, density=1.0, seed=4), worley(*pts, seed=4))


@pytest.mark.parametrize("ndim,period", [(2, (3, 5)), (2, (1, 2)), (3, (4, 2, 3))])
def test_periodic_output_repeats(ndim, period):
    # a seed whose tile holds at least one point (an empty tile gives infinite distances)
    full = (period + (0, 0))[:4]
    seed = next(s for s in range(6, 100) if len(_window(ndim, 0, max(period), 1.3, s, full)[1]))
    rng = np.random.default_rng(8)
    q = rng.uniform(-3.0, 3.0, (300, ndim))
    shift = rng.integers(-3, 4, (300, ndim)) * np.array(period)
    for out in ("f1", "f2", "f3", "cell"):
        a = worley(*q.T, density=1.3, period=period, output=out, seed=seed, dtype=np.float64)
        b = worley(
            *(q + shift).T, density=1.3, period=period, output=out, seed=seed, dtype=np.float64
        )
        assert np.isfinite(a).all()
        np.testing.assert_allclose(b, a, rtol=0, atol=1e-9)
    # a tileable grid wraps: the tile is one period of the same point set
    g = noise_grid(
        (16, 24), kind="worley", scale=6.0, tileable=True, density=2.0, seed=5, dtype=np.float64
    )
    xx, yy = np.meshgrid(np.arange(24) * 0.25, np.arange(16) * 0.25)
    p = worley(xx + 6.0, yy - 4.0, density=2.0, period=(6, 4), seed=5, dtype=np.float64)
    np.testing.assert_allclose(g, p, atol=1e-12)


def test_empty_periodic_tile_gives_infinite_distances():
    seed = next(
        s for s in range(100) if len(poisson_cell_points(2, 0, 0, 0, 0, 1, 1, 0, 0, 0.5, s)[1]) == 0
    )
    assert math.isinf(worley(0.3, 0.6, density=0.5, period=1, seed=seed))
    full = next(
        s for s in range(100) if len(poisson_cell_points(2, 0, 0, 0, 0, 1, 1, 0, 0, 0.5, s)[1]) == 1
    )
    f1, f2, f3, _ = worley_features(0.3, 0.6, density=0.5, period=1, seed=full)
    assert f1 < 1.0 and f2 <= f3 <= math.sqrt(2) + 1.0


# -- density=None: the jittered grid, bit-identical to the output before the option existed
# (values computed with the code before the change)
XS = [0.3, -2.7, 5.125, 11.9]
YS = [1.7, 0.25, -3.5, 7.05]
BEFORE = {
    "pts_f1": [0.6920756412114425, 0.34042229785260153, 0.46195865179934686, 0.4475463663369394],
    "pts_cell_man": [
        0.8349023954942822,
        0.7256077784113586,
        0.5300536807626486,
        0.4173098986502737,
    ],
    "pts3_f3": [0.9955449377041071, 0.996142370948989, 0.9418322614748625, 0.6966535954648125],
    "pts4_f2f1": [
        0.25186822931282227,
        0.027312411740422426,
        0.1847534247208386,
        0.058612802252173246,
    ],
    "fbm": [0.479418435838926, 0.4344366638678055, 0.35550335649525633, 0.5347784254855394],
    "grid2": [0.3487088130281479, 0.7643266238118621, 0.45867194406722117],
    "grid2_sum": 172.22304184058714,
    "grid3": [0.4270704687283978, 0.7180564592086951, 0.36935560014808333],
    "grid3_sum": 131.7868936447784,
    "grid_cell_sum": 124.58795934806886,
    "grid_cell": 0.5817570139188319,
}


@pytest.mark.parametrize("extra", [{}, {"density": None}])
def test_default_is_bit_identical_to_before(extra):
    f64 = np.float64
    assert worley(XS, YS, seed=7, dtype=f64, **extra).tolist() == BEFORE["pts_f1"]
    assert (
        worley(XS, YS, seed=3, metric="manhattan", output="cell", dtype=f64, **extra).tolist()
        == BEFORE["pts_cell_man"]
    )
    z = [0.5, 1.5, -0.2, 3.3]
    assert (
        worley(XS, YS, z, seed=5, output="f3", jitter=0.7, dtype=f64, **extra).tolist()
        == BEFORE["pts3_f3"]
    )
    assert (
        worley(
            XS,
            YS,
            z,
            [2.0, -1, 0.3, 0.9],
            seed=5,
            output="f2-f1",
            metric="chebyshev",
            dtype=f64,
            **extra,
        ).tolist()
        == BEFORE["pts4_f2f1"]
    )
    assert (
        fbm(XS, YS, kind="worley", octaves=3, seed=2, dtype=f64, **extra).tolist() == BEFORE["fbm"]
    )
    g = noise_grid((16, 24), kind="worley", scale=5.0, seed=11, dtype=f64, **extra)
    assert g[[0, 5, 15], [0, 13, 23]].tolist() == BEFORE["grid2"]
    assert float(g.sum()) == BEFORE["grid2_sum"]
    g = noise_grid(
        (4, 8, 8),
        kind="worley",
        scale=3.0,
        seed=4,
        output="f2",
        metric="euclidean2",
        tileable=True,
        dtype=f64,
        **extra,
    )
    assert g[[0, 2, 3], [0, 5, 7], [1, 4, 6]].tolist() == BEFORE["grid3"]
    assert float(g.sum()) == BEFORE["grid3_sum"]
    g = noise_grid(
        (16, 16),
        kind="worley",
        scale=4.0,
        seed=1,
        output="cell",
        tileable=True,
        octaves=2,
        dtype=f64,
        **extra,
    )
    assert float(g.sum()) == BEFORE["grid_cell_sum"] and float(g[3, 9]) == BEFORE["grid_cell"]


@pytest.mark.parametrize(
    "bad", [0, 0.0, -1.0, float("nan"), float("inf"), "2", True, 9.0, 0.001, [1.0], complex(1, 0)]
)
def test_bad_density_raises(bad):
    for call in (
        lambda: worley(0.1, 0.2, density=bad),
        lambda: worley_features(0.1, 0.2, density=bad),
        lambda: fbm(0.1, 0.2, kind="worley", density=bad),
        lambda: noise_grid((4, 4), kind="worley", density=bad),
    ):
        with pytest.raises(NoiseError, match="density"):
            call()


def test_preset_recipes_take_a_density():
    a = render({"kind": "worley", "size": [24, 16], "seed": 2, "density": 2.5})
    b = render({"kind": "worley", "size": [24, 16], "seed": 2})
    assert a.shape == b.shape and not np.array_equal(a, b)
    with pytest.raises(NoiseError, match="density"):
        render({"kind": "worley", "size": [8, 8], "density": -1})

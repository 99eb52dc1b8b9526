"""The grid fast paths of ``noise_grid`` (lattice tables, split simplex passes, Worley runs)
give exactly the values of the point-wise kernels, for every kind, fractal, dimension and
tiling; and small calls do not pay for waking numba's thread pool."""

import numba
import numpy as np
import pytest

from sylva.texture import METRICS, WORLEY_OUTPUTS, fbm, noise_grid, ridged, turbulence
from sylva.texture import noise as nz
from sylva.texture._sampling import CHUNK

FRACTAL = {"fbm": fbm, "turbulence": turbulence, "ridged": ridged}
OFFSET = (-2.3, 1.1, 0.4, 0.9)


def _points(shape, scale, tileable, time):
    """The sample coordinates of ``noise_grid`` (x, y, ... order) and the lattice periods,
    computed with the documented formulas."""
    sizes = shape[::-1]
    cells = [scale * n / sizes[0] for n in sizes]
    if tileable:
        cells = [max(1, round(c)) for c in cells]
    axes = [np.arange(n) * (cells[a] / n) + OFFSET[a] for a, n in enumerate(sizes)]
    if time is not None:
        axes.append(np.array([time + OFFSET[len(sizes)]]))
    mesh = np.meshgrid(*axes[::-1], indexing="ij")[::-1]
    period = None
    if tileable:
        period = tuple(cells) + ((0,) if time is not None else ())
    return mesh, period


def _both(
    shape, kind, fractal="fbm", octaves=1, seed=None, scale=5.3, tileable=False, time=None, **worley
):
    grid = noise_grid(
        shape,
        kind=kind,
        fractal=fractal,
        octaves=octaves,
        seed=seed,
        scale=scale,
        tileable=tileable,
        time=time,
        offset=OFFSET,
        dtype=np.float64,
        **worley,
    )
    mesh, period = _points(shape, scale, tileable, time)
    points = FRACTAL[fractal](
        *mesh, kind=kind, octaves=octaves, seed=seed, period=period, dtype=np.float64, **worley
    )
    return grid, points.reshape(grid.shape)


# rows longer than the simplex block (256 samples) and a few rows; a volume; an animated image
SHAPES = [((3, 300), None), ((3, 4, 270), None), ((4, 260), 0.7)]


@pytest.mark.parametrize("kind", ["value", "perlin", "improved", "simplex", "worley"])
@pytest.mark.parametrize("shape,time", SHAPES)
@pytest.mark.parametrize(
    "fractal,octaves", [("fbm", 1), ("fbm", 4), ("turbulence", 3), ("ridged", 5)]
)
def test_grid_equals_points(kind, shape, time, fractal, octaves):
    for seed in (None, 3):
        grid, points = _both(shape, kind, fractal, octaves, seed, time=time)
        np.testing.assert_array_equal(grid, points)
        assert np.ptp(grid) > 0.1  # a real texture, not a constant


@pytest.mark.parametrize("kind", ["value", "perlin", "improved", "worley"])
@pytest.mark.parametrize("shape,time", SHAPES)
def test_tileable_grid_equals_periodic_points(kind, shape, time):
    grid, points = _both(shape, kind, "fbm", 3, 5, tileable=True, time=time)
    np.testing.assert_array_equal(grid, points)


@pytest.mark.parametrize("kind", ["value", "improved", "simplex", "worley"])
def test_4d_grid_equals_points(kind):
    grid, points = _both((2, 3, 4, 5), kind, "fbm", 2, 1)
    np.testing.assert_array_equal(grid, points)


@pytest.mark.parametrize("scale", [0.7, 5.3, 300.0])
def test_simplex_grid_at_any_frequency(scale):
    # from many samples per simplex to several simplices per sample
    for shape in ((2, 333), (2, 2, 333)):
        grid, points = _both(shape, "simplex", "fbm", 2, 9, scale=scale)
        np.testing.assert_array_equal(grid, points)


@pytest.mark.parametrize("metric", list(METRICS))
@pytest.mark.parametrize("jitter", [1.0, 0.6, 0.0])
def test_worley_grid_equals_points_for_every_output(metric, jitter):
    # jitter 0 puts the feature points on a regular lattice: ties everywhere, which the
    # grid path must break like the point-wise search (it decides the "cell" output)
    for shape, time in [((5, 41), None), ((3, 2, 37), None), ((4, 33), 0.35)]:
        for scale in (3.1, 40.0):
            for out in WORLEY_OUTPUTS:
                grid, points = _both(
                    shape,
                    "worley",
                    "fbm",
                    1,
                    4,
                    scale=scale,
                    time=time,
                    output=out,
                    metric=metric,
                    jitter=jitter,
                )
                np.testing.assert_array_equal(grid, points, err_msg=f"{out} {shape} {scale}")


def test_worley_grid_needs_the_wider_search_sometimes():
    # F3 is often farther than the 3x3 neighbourhood can guarantee; those samples go to
    # the full search, and the values still agree
    grid, points = _both((16, 64), "worley", "fbm", 1, 2, scale=6.0, output="f3")
    np.testing.assert_array_equal(grid, points)
    x = np.arange(64) * 6.0 / 64 + OFFSET[0]
    frac = x - np.floor(x)
    # some F3 values exceed the distance to the neighbourhood's edge (the widening case)
    assert (grid > 1.0 + np.minimum(frac, 1 - frac)).any()


def test_big_grids_do_not_depend_on_the_thread_count():
    before = numba.get_num_threads()
    shape = (300, 260)  # above the single-thread threshold
    assert np.prod(shape) >= nz._SERIAL_WORK
    try:
        numba.set_num_threads(1)
        one = [noise_grid(shape, kind=k, seed=5) for k in ("improved", "simplex", "worley")]
        numba.set_num_threads(numba.config.NUMBA_NUM_THREADS)
        many = [noise_grid(shape, kind=k, seed=5) for k in ("improved", "simplex", "worley")]
    finally:
        numba.set_num_threads(before)
    for a, b in zip(one, many):
        np.testing.assert_array_equal(a, b)


def test_small_calls_run_on_one_thread_and_restore_the_settings():
    before = numba.get_num_threads()
    chunk = numba.get_parallel_chunksize()
    seen = []
    with nz._threads(10):
        seen.append((numba.get_num_threads(), numba.get_parallel_chunksize()))
    with nz._threads(nz._SERIAL_WORK):  # big: all threads, blocks handed out one by one
        seen.append((numba.get_num_threads(), numba.get_parallel_chunksize()))
    if before > 1:
        assert seen == [(1, chunk), (before, 1)]
    assert (numba.get_num_threads(), numba.get_parallel_chunksize()) == (before, chunk)
    noise_grid((8, 8))
    noise_grid((300, 260))
    fbm(0.1, 0.2)
    assert (numba.get_num_threads(), numba.get_parallel_chunksize()) == (before, chunk)


def test_point_batches_split_into_rows_exactly():
    # more points than one row: the padding of the last row must not shift any point
    rng = np.random.default_rng(3)
    pts = rng.uniform(-20, 20, (2, CHUNK * 2 + 7))
    whole = fbm(*pts, kind="simplex", octaves=2, dtype=np.float64)
    parts = [
        fbm(*pts[:, i : i + 1000], kind="simplex", octaves=2, dtype=np.float64)
        for i in range(0, pts.shape[1], 1000)
    ]
    np.testing.assert_array_equal(whole, np.concatenate(parts))
    assert fbm(pts[0, 5], pts[1, 5], kind="simplex", octaves=2) == whole[5]

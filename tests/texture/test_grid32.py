"""The float32 road of noise_grid (``dtype=np.float32``, the default) against the float64
road, which stays bit-exact to the reference values (test_reference_noise, test_grid_paths).

The float32 road computes in float32 with its own SIMD kernels (``_gridkernels32``): its
values agree with the float64 road within ``_gridkernels32.TOLERANCE`` on every kind it
covers, with the same statistics (so the same images to the eye).
"""

import numpy as np
import pytest

from sylva import _jit
from sylva.texture import _gridkernels32 as gk32
from sylva.texture import noise_grid

TOL = gk32.TOLERANCE

# a row longer than a block (256) and one shorter, 2D and 3D
SHAPES = [(20, 300), (5, 12, 72)]


@pytest.fixture(autouse=True)
def _compiled():
    # on a cold numba cache small grids take the interpreted float64 road: these tests are
    # about the compiled float32 road (else they would compare float64 with float64)
    with _jit.compiled():
        yield


@pytest.mark.parametrize("shape", SHAPES, ids=["2d", "3d"])
@pytest.mark.parametrize("kind", ["value", "perlin", "improved", "simplex"])
@pytest.mark.parametrize(
    "fractal,octaves", [("fbm", 1), ("fbm", 6), ("ridged", 4), ("turbulence", 3)]
)
def test_float32_road_within_tolerance_of_float64(shape, kind, fractal, octaves):
    kw = dict(kind=kind, fractal=fractal, octaves=octaves, scale=24.0, seed=5)
    a = noise_grid(shape, **kw)
    b = noise_grid(shape, dtype=np.float64, **kw)
    assert a.dtype == np.float32 and b.dtype == np.float64
    assert np.abs(a.astype(np.float64) - b).max() < TOL
    assert abs(float(a.mean()) - b.mean()) < TOL
    assert abs(float(a.std()) - b.std()) < TOL
    assert b.std() > 0.05  # a real pattern, not a constant


@pytest.mark.parametrize("use", [True, False], ids=["bytelanes", "packed"])
@pytest.mark.parametrize(
    "offset",
    [(3000.0, 100.0), (1e5, -1e5), (2.0**30, 5.0), (0.5, 3e9), (20.0, 0.3)],
    ids=["3e3", "1e5", "2^30", "y", "octaves-cross"],
)
def test_2d_simplex_far_from_the_origin(monkeypatch, use, offset):
    # 2D simplex locates in float32 near the origin only: float32 coordinates of 3,000
    # cells were 5.9e-4 off the float64 road, of 1e5 cells 0.02; beyond ~32 cells an
    # octave's amplitude (_simplex32._s2_fits32) it locates in float64 (in the last case
    # the finer of six octaves cross over); both roads
    monkeypatch.setattr(gk32._bl, "USE", use)
    kw = dict(kind="simplex", octaves=6, scale=24.0, seed=5, offset=offset)
    a = noise_grid((5, 300), **kw)
    b = noise_grid((5, 300), dtype=np.float64, **kw)
    assert np.abs(a.astype(np.float64) - b).max() < TOL
    assert b.std() > 0.05


@pytest.mark.parametrize("use", [True, False], ids=["bytelanes", "packed"])
@pytest.mark.parametrize(
    "offset",
    [(3e9, 1.5, 2.5), (0.5, -3e9, 2.5), (0.5, 1.5, 7e9), (2.0**26 + 0.3, 0.7, -1.2)],
    ids=["x", "y", "z", "octaves-cross"],
)
def test_3d_simplex_far_from_the_origin(monkeypatch, use, offset):
    # the 3D locate converts cells to int32 below 2^29 and takes the float64 road's exact
    # "& 255" beyond (in the last case the finer of six octaves cross the bound); both
    # roads (byte lanes: scalar lookups on CPUs without VBMI, the same results)
    monkeypatch.setattr(gk32._bl, "USE", use)
    kw = dict(kind="simplex", octaves=6, scale=24.0, seed=5, offset=offset)
    a = noise_grid((3, 5, 300), **kw)
    b = noise_grid((3, 5, 300), dtype=np.float64, **kw)
    assert np.abs(a.astype(np.float64) - b).max() < TOL
    assert b.std() > 0.05


def test_float32_road_is_the_default_and_float64_keeps_its_road(monkeypatch):
    calls = []
    real = gk32.lattice_grid32

    def spy(*args):
        calls.append(args[6].dtype)
        return real(*args)

    monkeypatch.setattr(gk32, "lattice_grid32", spy)
    a = noise_grid((8, 40), kind="improved", octaves=2, seed=1)
    noise_grid((8, 40), kind="improved", octaves=2, seed=1, dtype=np.float32)
    b = noise_grid((8, 40), kind="improved", octaves=2, seed=1, dtype=np.float64)
    assert calls == [np.float32, np.float32]
    # float32 arithmetic: not merely the float64 values rounded
    assert not np.array_equal(a, b.astype(np.float32))


def test_float32_road_offsets_tiling_and_periods_match():
    # tileable lattice noise (integer periods per octave) and offsets go through the same
    # axis tables on both roads
    kw = dict(kind="improved", octaves=3, scale=6.0, tileable=True, offset=(3.5, -2.25))
    a = noise_grid((32, 48), **kw)
    b = noise_grid((32, 48), dtype=np.float64, **kw)
    assert np.abs(a - b).max() < TOL


@pytest.mark.parametrize("shape", SHAPES + [(2, 3, 5, 72)], ids=["2d", "3d", "4d"])
@pytest.mark.parametrize(
    "output,metric,fractal,octaves",
    [
        ("f1", "euclidean", "fbm", 1),
        ("f2", "manhattan", "ridged", 3),
        ("f2-f1", "chebyshev", "fbm", 2),
        ("f3", "euclidean2", "turbulence", 2),
    ],
)
def test_worley_float32_road_within_tolerance(shape, output, metric, fractal, octaves):
    kw = dict(kind="worley", output=output, metric=metric, fractal=fractal, octaves=octaves,
              scale=24.0, seed=5)
    a = noise_grid(shape, **kw)
    b = noise_grid(shape, dtype=np.float64, **kw)
    assert a.dtype == np.float32
    assert np.abs(a.astype(np.float64) - b).max() < TOL
    assert b.std() > 0.02
    # float32 distances, not the float64 ones rounded
    assert not np.array_equal(a, b.astype(np.float32))


def test_worley_float32_tileable_and_jitter():
    kw = dict(kind="worley", octaves=2, scale=5.0, tileable=True, jitter=0.6, seed=3)
    a = noise_grid((40, 64), **kw)
    b = noise_grid((40, 64), dtype=np.float64, **kw)
    assert np.abs(a - b).max() < TOL
    # periodic: shifted by one period (5 cells) along x it is the same image
    c = noise_grid((40, 64), offset=(5.0, 0.0), **kw)
    assert np.abs(c - a).max() < TOL


@pytest.mark.parametrize("scale,output", [(200.0, "f1"), (200.0, "f3"), (4.5, "f2")],
                         ids=["small-cells-f1", "small-cells-f3", "wide-cells-f2"])
def test_worley_float32_4d_rows(monkeypatch, scale, output):
    # 4D Worley goes by rows too (27 cells a lattice column): small cells (under half a
    # sample a cell: run by run) and wide ones (16 samples a cell: blocks against columns)
    from sylva.texture import _points32, _worley32

    rows = []
    real = _worley32.worley_grid32
    monkeypatch.setattr(_worley32, "worley_grid32", lambda *a: rows.append(a[0]) or real(*a))
    monkeypatch.setattr(_points32, "grid_kernel", None)  # not the points road
    kw = dict(kind="worley", output=output, octaves=2, scale=scale, seed=4)
    for shape, extra in (((3, 2, 4, 72), {}), ((3, 4, 72), {"time": 1.7})):
        a = noise_grid(shape, **kw, **extra)
        b = noise_grid(shape, dtype=np.float64, **kw, **extra)
        assert np.abs(a.astype(np.float64) - b).max() < TOL
        assert b.std() > 0.02 and not np.array_equal(a, b.astype(np.float32))
    assert rows == [4, 4]


def test_worley_float32_4d_tiles_along_every_axis():
    kw = dict(kind="worley", octaves=2, scale=5.0, tileable=True, jitter=0.8, seed=6)
    shape = (3, 4, 5, 40)  # (w, z, y, x): 5 cells across x, 5 * 3/40 ... along the others
    a = noise_grid(shape, **kw)
    b = noise_grid(shape, dtype=np.float64, **kw)
    assert np.abs(a - b).max() < TOL
    cells = [5.0 * n / shape[-1] for n in shape[::-1]]  # x, y, z, w
    periods = [max(1, round(c)) for c in cells]
    for axis in range(4):  # one period along each axis: the same grid
        off = [0.0] * 4
        off[axis] = float(periods[axis])
        c = noise_grid(shape, offset=tuple(off), **kw)
        assert np.abs(c - a).max() < TOL, axis


@pytest.mark.parametrize("output", ["f1", "f2-f1"])
def test_worley_float32_wide_cells_3d(output):
    # 16 samples per cell: the row goes by blocks of 16 lanes against whole columns of
    # candidates (the path of large cells), 3D with its nine cells per column
    kw = dict(kind="worley", output=output, octaves=2, scale=5.0, seed=9)
    a = noise_grid((3, 8, 80), **kw)
    b = noise_grid((3, 8, 80), dtype=np.float64, **kw)
    assert np.abs(a.astype(np.float64) - b).max() < TOL
    assert b.std() > 0.02


@pytest.mark.parametrize("kind", ["value", "perlin", "improved"])
@pytest.mark.parametrize("shape", [(6, 200), (3, 5, 120)], ids=["2d", "3d"])
def test_lattice_cell_road_within_tolerance(kind, shape):
    # 20+ samples a cell in the first octaves: those go by cells (hashed once per cell,
    # lanes pick their cell's coefficients by selects); the finest octave (2.5 samples a
    # cell) by samples; tileable periods and an offset through both
    kw = dict(kind=kind, octaves=4, scale=(10.0, 4.0, 3.0)[: len(shape)], tileable=True,
              offset=(0.37, -1.5, 2.25), seed=11)
    a = noise_grid(shape, **kw)
    b = noise_grid(shape, dtype=np.float64, **kw)
    assert np.abs(a.astype(np.float64) - b).max() < TOL
    assert b.std() > 0.02
    # the cell tables of the x axis send the first octave by cells and the last by samples
    from sylva.texture import _gridkernels as gk
    from sylva.texture.noise import _setup

    st = _setup(kind, 11, None, "f1", "euclidean", 1.0)
    xs = np.arange(shape[-1]) * (10.0 / shape[-1])
    freqs = 2.0 ** np.arange(4)
    tab = gk.axis_tables(xs, freqs, np.zeros(4), np.zeros(4), st.interp)
    kspan = gk32.lattice_tables32(tab, st.tables.perm, True)[7]
    assert kspan[0] <= gk32.KMAX < kspan[3]


@pytest.mark.parametrize("kind", ["value", "perlin", "improved"])
@pytest.mark.parametrize("shape", [(3, 1500), (2, 3, 700)], ids=["2d", "3d"])
def test_lattice_cell_road_over_rows_of_several_blocks(kind, shape):
    # rows of several 256-sample blocks, every octave by cells: the cells of the whole row
    # are hashed and reduced at once, and each block reads its own cells' coefficients; in
    # 2D the finest octave has more cells in a row than a block has samples
    nx = shape[-1]
    sx = 40.0 if len(shape) == 2 else 20.0
    kw = dict(kind=kind, octaves=4, scale=(sx, 6.0, 5.0)[: len(shape)],
              offset=(0.41, -2.5, 1.75)[: len(shape)], seed=5)
    a = noise_grid(shape, **kw)
    b = noise_grid(shape, dtype=np.float64, **kw)
    assert np.abs(a.astype(np.float64) - b).max() < TOL
    assert b.std() > 0.02
    from sylva.texture import _gridkernels as gk
    from sylva.texture.noise import _setup

    st = _setup(kind, 5, None, "f1", "euclidean", 1.0)
    xs = np.arange(nx) * (sx / nx)
    freqs = 2.0 ** np.arange(4)
    tab = gk.axis_tables(xs, freqs, np.zeros(4), np.zeros(4), st.interp)
    cid, kspan = gk32.lattice_tables32(tab, st.tables.perm, True)[4::3]
    assert nx > 2 * gk.BLOCK and (kspan <= gk32.KMAX).all()  # all four octaves by cells
    assert (cid[3, -1] + 1 > gk.BLOCK) == (len(shape) == 2)


@pytest.mark.parametrize("kind", ["value", "perlin", "improved"])
@pytest.mark.parametrize("tile", [False, True])
def test_lattice_cell_road_reuses_a_rows_cells_only_in_the_same_lattice_rows(kind, tile):
    # the cell road keeps a row's hashed cells for the next row in the same lattice rows
    # (y0, y1, z0, z1): runs of rows in one lattice row, rows that change only y or only z
    # (one row a slice: consecutive rows differ in z alone), and tileable lattices whose
    # rows wrap; each must equal the float64 road, which hashes every sample.  Over
    # gk32.CHUNKS rows, so that a work item (whose cache it is) has several rows
    rng = np.random.default_rng(3)
    for shape, scale in (((300, 320), (5.0, 3.7)), ((200, 1, 300), (4.0, 1.0, 29.0)),
                         ((8, 24, 200), (3.0, 4.3, 2.2))):
        kw = dict(kind=kind, octaves=2, scale=scale, seed=int(rng.integers(100)),
                  offset=tuple(rng.uniform(-3, 3, len(shape))), tileable=tile)
        a = noise_grid(shape, **kw)
        b = noise_grid(shape, dtype=np.float64, **kw)
        assert np.abs(a.astype(np.float64) - b).max() < TOL, shape
        assert np.prod(shape[:-1]) >= 3 * gk32.CHUNKS
        rows = a.reshape(-1, shape[-1])
        assert (np.abs(np.diff(rows, axis=0)).max(axis=1) > 1e-4).all()  # no row repeated


@pytest.mark.parametrize("n,octaves,period", [(1024, 1, 0), (300, 6, 0), (77, 3, 1),
                                              (500, 4, 5), (1, 2, 0), (17, 2, 0)])
@pytest.mark.parametrize("interp", [0, 1, 2, 3])
def test_x_tables_in_one_pass_equal_the_numpy_tables(n, octaves, period, interp):
    # noise_grid's x axis tables and cells in one compiled pass, the same as the axis
    # tables followed by lattice_tables32's NumPy passes (cells, spans), bit for bit
    from sylva.texture import _gridkernels as gk
    from sylva.texture.noise import noise_tables

    perm = noise_tables(5).perm
    rng = np.random.default_rng(n)
    coords = np.arange(n) * (64.0 / n) - 3.3
    freqs = 2.0 ** np.arange(octaves)
    if period:
        freqs = np.round(freqs * period) / period
    offs = rng.uniform(-10.0, 10.0, octaves)
    pers = np.full(octaves, float(period))
    want = gk32.lattice_tables32(gk.axis_tables(coords, freqs, offs, pers, interp), perm, True)
    got = gk32.x_tables32(coords, freqs, offs, pers, interp, perm)
    assert len(got) == len(want) == 8
    for g, w in zip(got, want):
        assert g.dtype == w.dtype and g.shape == w.shape
        np.testing.assert_array_equal(g, w)


@pytest.mark.parametrize("kind", ["value", "perlin", "improved"])
@pytest.mark.parametrize("fractal,tile", [("fbm", False), ("ridged", True), ("turbulence", False)])
def test_lattice_sample_road_row_tables_3d(kind, fractal, tile):
    # octaves too fine for the cell road on rows of 300 samples: 3D improved and value
    # noise look their corners up in row tables (every perm[x0] of the row's lattice rows
    # y0, y1, z0, z1, built once a row and octave: two lookups a sample instead of
    # fourteen chained ones); classic Perlin keeps its chains.  Each equals the float64
    # road, which hashes every sample, with and without tiling, over several rows and slices
    shape = (3, 5, 300)
    kw = dict(kind=kind, fractal=fractal, octaves=3, scale=(170.0, 2.5, 1.5),
              offset=(0.3, -1.2, 2.6), tileable=tile, seed=7)
    a = noise_grid(shape, **kw)
    b = noise_grid(shape, dtype=np.float64, **kw)
    assert np.abs(a.astype(np.float64) - b).max() < TOL
    assert b.std() > 0.05
    from sylva.texture import _gridkernels as gk
    from sylva.texture.noise import _setup

    st = _setup(kind, 7, None, "f1", "euclidean", 1.0)
    xs = np.arange(shape[-1]) * (170.0 / shape[-1])
    freqs = 2.0 ** np.arange(3)
    tab = gk.axis_tables(xs, freqs, np.zeros(3), np.zeros(3), st.interp)
    kspan = gk32.lattice_tables32(tab, st.tables.perm, True)[7]
    assert (kspan > gk32.KMAX).all()  # every octave by samples


@pytest.mark.parametrize("kind", ["value", "perlin", "improved"])
@pytest.mark.parametrize(
    "shape,kw",
    [((3, 4, 6, 120), dict(octaves=4, scale=(8.0, 2.0, 1.5, 1.2))),  # cells, then samples
     ((2, 3, 4, 300), dict(octaves=2, scale=(150.0, 2.0, 1.5, 1.0), fractal="ridged")),
     ((2, 3, 5, 64), dict(octaves=3, scale=(6.0, 3.0, 2.0, 2.0), tileable=True,
                          fractal="turbulence")),
     ((3, 7, 90), dict(octaves=3, scale=(5.0, 2.0, 1.5), time=0.7))],
    ids=["cells-samples", "samples-ridged", "tileable", "3d+time"],
)
def test_lattice_4d_rows_within_tolerance(monkeypatch, kind, shape, kw):
    # 4D lattice noise by rows (_lattice4_32): a row's cells hashed once (four or more
    # samples a cell) or every sample its own cell, the sixteen corners' gradients blended
    # along y, z, w into a cell's four coefficients; against the float64 road, which
    # locates and hashes every sample
    from sylva.texture import _lattice4_32 as l4

    _rows_match_float64(monkeypatch, l4, "grid4", shape,
                        dict(kind=kind, seed=9, offset=(0.3, -1.1, 2.2, 0.6), **kw))


def _rows_match_float64(monkeypatch, module, grid, shape, kw):
    """The 4D rows kernel behind ``module.grid`` ran, within tolerance of the float64
    road, in float32 arithmetic."""
    ran = []
    real_grid = getattr(module, grid)
    monkeypatch.setattr(module, grid, lambda *a: ran.append(1) or real_grid(*a))
    a = noise_grid(shape, **kw)
    b = noise_grid(shape, dtype=np.float64, **kw)
    assert ran and a.dtype == np.float32 and a.shape == b.shape
    assert np.abs(a.astype(np.float64) - b).max() < TOL
    assert abs(float(a.std()) - b.std()) < TOL and b.std() > 0.03
    assert not np.array_equal(a, b.astype(np.float32))  # float32 arithmetic


@pytest.mark.parametrize(
    "shape,kw",
    [((3, 4, 6, 300), dict(octaves=4, scale=(9.0, 3.0, 2.0, 1.5))),
     ((2, 3, 4, 90), dict(octaves=3, scale=7.0, fractal="ridged",
                          offset=(-40.3, -7.1, -2.2, -0.6))),
     ((2, 2, 3, 70), dict(octaves=2, scale=5.0, fractal="turbulence",
                          offset=(0.5, 1.5, 2.5, 3e9))),
     ((3, 7, 90), dict(octaves=3, scale=6.0, time=0.7))],
    ids=["fbm", "ridged-negative", "turbulence-far-w", "3d+time"],
)
def test_simplex_4d_rows_within_tolerance(monkeypatch, shape, kw):
    # 4D simplex by rows (_simplex32.rows4s): located in float64 as the float64 road (its
    # kernel jumps across simplex faces too), the sixteen corners' chains from one table
    # load per (k, l) plane, past 2^29 the exact "& 255"
    from sylva.texture import _simplex32 as s32

    _rows_match_float64(monkeypatch, s32, "grid4s", shape, dict(kind="simplex", seed=9, **kw))


@pytest.mark.parametrize("scale", [16.0, 64.0], ids=["quarter-cells", "whole-cells"])
def test_simplex_4d_rows_on_a_regular_grid(monkeypatch, scale):
    # On a grid of quarter or whole cells many samples sit on simplex faces in exact
    # arithmetic, where the float64 road's rank ordering is decided by its rounding and
    # the kernel (r² = 0.6) jumps by up to ~1e-2: the float32 road must take the same
    # comparisons (the sign bits of the float64 differences, _simplex32._s4_locate), not
    # compare the offsets after rounding them to float32.
    from sylva.texture import _simplex32 as s32

    kw = dict(kind="simplex", seed=1, octaves=2, scale=scale)
    _rows_match_float64(monkeypatch, s32, "grid4s", (4, 4, 16, 64), kw)


@pytest.mark.parametrize("use", [True, False], ids=["bytelanes", "packed"])
@pytest.mark.parametrize("scale", [6.0, 24.0], ids=["quarter-cells", "whole-cells"])
def test_3d_simplex_on_a_regular_grid(monkeypatch, use, scale):
    # as the 4D test above: 3D simplex on a grid of quarter or whole cells, where the
    # six-way choice of many samples is a float64 rounding, on both roads (the packed
    # road's comparisons are sign bits, _simplex32._diff_sign; the byte-lane road packs
    # its own) and warped
    monkeypatch.setattr(gk32._bl, "USE", use)
    kw = dict(kind="simplex", seed=3, octaves=2, scale=scale)
    for extra in ({}, {"warp": 0.5}):
        a = noise_grid((6, 8, 24), **kw, **extra)
        b = noise_grid((6, 8, 24), dtype=np.float64, **kw, **extra)
        assert np.abs(a.astype(np.float64) - b).max() < TOL
        assert b.std() > 0.05

"""The float32 road of the noise grids beyond ``_gridkernels32`` (``_points32``): 4D grids
and 3D grids with time, tileable simplex (the 4D torus) and domain warping, of every kind
(Worley: its jittered grid, F1..F3, combinations, cell id; 4D F1..F3 go by rows, as
:mod:`._worley32` takes 2D and 3D), against the
float64 road (bit-exact to the reference values, test_reference_noise): within
``_points32.TOLERANCE`` on small grids, and the float32 kernel is the one that ran."""

import numpy as np
import pytest

from sylva import _jit
from sylva.texture import _gridkernels32 as gk32
from sylva.texture import _kernels as k
from sylva.texture import _lattice4_32 as l4
from sylva.texture import _points32 as p32
from sylva.texture import _simplex32 as s32
from sylva.texture import _warp32 as wp32
from sylva.texture import _worley32 as w32
from sylva.texture import noise_grid
from sylva.texture._gridplan import grid_plan

TOL = p32.TOLERANCE
KINDS = ["value", "perlin", "improved", "simplex"]


@pytest.fixture(autouse=True)
def _compiled():
    # small grids take the float64 road while a kernel is not compiled (a cold cache):
    # these tests are about the compiled float32 road
    with _jit.compiled():
        yield


def _spy(monkeypatch, name):
    calls = []
    real = getattr(p32, name)

    def spy(*args):
        calls.append((args[0], args[1]))  # (points, kind)
        return real(*args)

    monkeypatch.setattr(p32, name, spy)
    return calls


def _both(shape, **kw):
    a = noise_grid(shape, **kw)
    b = noise_grid(shape, dtype=np.float64, **kw)
    assert a.dtype == np.float32 and b.dtype == np.float64 and a.shape == b.shape
    assert b.std() > 0.03  # a real pattern, not a constant
    # within tolerance, and float32 arithmetic: not merely the float64 values rounded
    assert np.abs(a.astype(np.float64) - b).max() < TOL
    assert abs(float(a.mean()) - b.mean()) < TOL
    assert not np.array_equal(a, b.astype(np.float32))
    return a, b


def _road(shape, warp=0.0, **kw):
    plan = grid_plan(shape, kw.get("kind", "improved"), kw.get("fractal", "fbm"), 4.0, 2,
                     0.5, 2.0, 2.0, None, None, kw.get("tileable", False), kw.get("time"),
                     (0.0,) * 4, warp, True, kw.get("output", "f1"), "euclidean", 1.0,
                     kw.get("dtype"), None)
    return p32.road(plan, warp)


@pytest.mark.parametrize("kind", KINDS)
@pytest.mark.parametrize(
    "shape,extra",
    [((2, 3, 5, 40), {}), ((3, 4, 40), {"time": 0.7}),
     ((2, 3, 4, 36), {"tileable": True, "fractal": "ridged"})],
    ids=["4d", "3d+time", "4d-tileable-ridged"],
)
def test_4d_grid_float32_within_tolerance(monkeypatch, kind, shape, extra):
    if kind == "simplex" and "tileable" in extra:
        extra = {"fractal": "ridged"}  # simplex tiles 2D images only (its torus)
    calls = _spy(monkeypatch, "grid_kernel")
    rows = []
    for mod, name in ((l4, "grid4"), (s32, "grid4s")):
        real = getattr(mod, name)
        monkeypatch.setattr(mod, name, lambda *a, real=real: rows.append(a[0].kind) or real(*a))
    _both(shape, kind=kind, octaves=4, scale=5.0, seed=3, **extra)
    # 4D lattice and simplex noise go by rows (_lattice4_32, _simplex32), not by points
    assert not calls and rows == [p32.KINDS[KINDS.index(kind)]]


@pytest.mark.parametrize("fractal", ["fbm", "turbulence"])
def test_4d_grid_six_octaves(fractal):
    _both((2, 2, 6, 64), kind="simplex", fractal=fractal, octaves=6, scale=12.0, seed=8)


@pytest.mark.parametrize("extra", [{}, {"time": 1.3, "fractal": "ridged"}], ids=["2d", "time"])
def test_tileable_simplex_float32(monkeypatch, extra):
    calls = _spy(monkeypatch, "grid_kernel")
    kw = dict(kind="simplex", octaves=3, scale=5.0, seed=4, tileable=True, **extra)
    a, _ = _both((32, 48), **kw)
    assert calls
    # seamless: across the wrap (last column to first, last row to first) the image steps
    # no more than between neighbours inside it
    inside = np.abs(np.diff(a, axis=1)).mean()
    assert np.abs(a[:, 0] - a[:, -1]).mean() < 2.0 * inside
    assert np.abs(a[0] - a[-1]).mean() < 2.0 * np.abs(np.diff(a, axis=0)).mean()


@pytest.mark.parametrize("kind", KINDS)
@pytest.mark.parametrize(
    "shape,fractal", [((16, 40), "fbm"), ((3, 6, 40), "turbulence"), ((2, 2, 3, 32), "ridged")],
    ids=["2d", "3d", "4d"],
)
def test_warp_float32_within_tolerance(monkeypatch, kind, shape, fractal):
    calls = _spy(monkeypatch, "grid_kernel")
    fields = []
    real = gk32.grid32
    monkeypatch.setattr(gk32, "grid32", lambda *a: fields.append(a[7]) or real(*a))
    rows = _warp_rows(monkeypatch)
    _both(shape, kind=kind, fractal=fractal, octaves=3, scale=5.0, seed=2, warp=0.8)
    # the warp field of each axis is fBm on the grid's own points: the grid roads take it,
    # then the warped noise goes on rows of points (2D and 3D: rows at the warped points,
    # _warp32.warp_rows)
    pairs = len(shape) == 2 and kind == "simplex"  # both fields at once: simplex_pair32
    assert fields == [k.FBM] * len(shape) * (not pairs)
    by_rows = len(shape) in (2, 3)
    assert calls == [] if by_rows else calls == [(True, p32.KINDS[KINDS.index(kind)])]
    assert rows == [p32.KINDS[KINDS.index(kind)]] * by_rows


@pytest.mark.parametrize("use", [True, False], ids=["bytelanes", "packed"])
@pytest.mark.parametrize("offset,octaves", [((0.0, 0.0), 1), ((-7.25, 3.5), 3),
                                            ((3000.0, 100.0), 2)], ids=["one", "fbm", "far"])
def test_2d_simplex_warp_fields_as_a_pair_equal_each_field_alone(monkeypatch, use, offset,
                                                                   octaves):
    # a warped 2D simplex grid's two fields go in one pass (one locate a block, the kernel
    # weights shared): bit for bit the fields of the grid road one by one, in float32 near
    # the origin and located in float64 far from it, on both hash roads
    from sylva.texture.noise import _setup

    monkeypatch.setattr(s32._bl, "USE", use)
    plan = grid_plan((9, 300), "simplex", "fbm", 7.0, octaves, 0.5, 2.0, 2.0, 4, None, False,
                     None, offset, 0.8, True, "f1", "euclidean", 1.0, np.float32, None)
    sets = [_setup("simplex", 4 + 7919 * a, None) for a in (1, 2)]
    axes = [np.ascontiguousarray(a, np.float64) for a in plan.axes]
    pair = s32.simplex_pair32(sets, axes, plan.freqs, plan.amps, plan.offs, plan.norm,
                              plan.gain)
    for ws, got in zip(sets, pair):
        alone = gk32.grid32(ws, 2, axes, plan.freqs, plan.amps, plan.offs, plan.pers, k.FBM,
                            plan.norm, plan.gain, False, (300, 9, 1, 1))
        np.testing.assert_array_equal(got, alone.reshape(9, 300))
    assert not np.array_equal(pair[0], pair[1]) and pair[0].std() > 0.05


def _warp_rows(monkeypatch):
    rows = []
    real = wp32.warp_grid
    monkeypatch.setattr(wp32, "warp_grid", lambda *a: rows.append(a[0].kind) or real(*a))
    return rows


@pytest.mark.parametrize("kind", KINDS)
@pytest.mark.parametrize("fractal,octaves", [("fbm", 1), ("ridged", 4), ("turbulence", 2)])
@pytest.mark.parametrize("shape", [(7, 300), (3, 4, 300)], ids=["2d", "3d"])
def test_warped_rows(monkeypatch, kind, fractal, octaves, shape):
    # rows longer than a block (256), negative offsets: lattice noise located in float64
    # at the warped points (cells from the packed corner table, in 3D then the z chain),
    # 2D simplex in float32 (no jump at its faces), 3D simplex in float64
    rows = _warp_rows(monkeypatch)
    _both(shape, kind=kind, fractal=fractal, octaves=octaves, scale=9.0, seed=6,
          warp=1.3, offset=(-20.5, -3.25, 7.75)[: len(shape)])
    assert rows == [p32.KINDS[KINDS.index(kind)]]


@pytest.mark.parametrize("interpolation", ["linear", "cosine", "cubic", "quintic"])
@pytest.mark.parametrize("kind", ["value", "perlin", "improved"])
@pytest.mark.parametrize("shape", [(5, 64), (2, 3, 64)], ids=["2d", "3d"])
def test_warped_rows_interpolation(kind, interpolation, shape):
    # every curve of the lattice noises (the cosine by its polynomial, within tolerance)
    _both(shape, kind=kind, interpolation=interpolation, octaves=2, scale=6.0, seed=3,
          warp=0.9)


@pytest.mark.parametrize(
    "shape,offset",
    [((4, 96), (3000.0, 100.0)), ((4, 96), (2.0**30, -(2.0**31) + 7.3)),
     ((4, 96), (3e9, -1e9)), ((2, 3, 96), (2.0**30, -(2.0**31) + 7.3, 3e9))],
)
@pytest.mark.parametrize("kind", ["improved", "simplex"])
def test_warped_rows_far_from_the_origin(kind, shape, offset):
    # beyond int32 the cells' & 255 is the float64 road's exact one, not a conversion's;
    # 2D simplex beyond a few hundred cells locates in float64 (float32 coordinates would
    # round by more than the tolerance).  Not beyond ~1e10 cells: there one float64 step
    # of a warped point exceeds the fields' float32 rounding times warp, and so does the
    # difference from the float64 road
    _both(shape, kind=kind, octaves=2, scale=6.0, seed=3, warp=1.1, offset=offset)


@pytest.mark.parametrize("kind", ["value", "perlin", "improved"])
@pytest.mark.parametrize("shape", [(6, 300), (2, 3, 300)], ids=["2d", "3d"])
def test_warped_lattice_octaves_beyond_the_float32_budget_locate_in_float64(kind, shape):
    # warped lattice noise locates an octave in float32 while sum(amplitude x coordinate
    # magnitude) stays within _warp32._LAT_REACH (128 cells; its value is continuous at
    # cell faces, so a float32 floor differing at a face costs rounding only): at 100 cells
    # across, the first two of three octaves do, the third goes in float64
    assert wp32._LAT_REACH == 128.0
    _both(shape, kind=kind, octaves=3, scale=100.0, seed=4, warp=1.0)


@pytest.mark.parametrize("kind,extra", [
    ("value", {"warp": 0.7}), ("simplex", {"warp": 0.7}), ("worley", {"warp": 0.7}),
    ("improved", {"warp": 0.7, "tileable": True}), ("worley", {"output": "cell"}),
])
def test_points_far_from_the_origin_take_the_float64_road(monkeypatch, kind, extra):
    # the points road converts cells to int32 (0.4-1.0 off at 3e9 cells before): beyond
    # 2^29 the grid goes by the float64 road, rounded
    calls = _spy(monkeypatch, "grid_kernel")
    kw = dict(kind=kind, octaves=2, scale=6.0, seed=3, offset=(3e9, 1.0, -5e9, 2.5), **extra)
    a = noise_grid((2, 2, 3, 64), **kw)
    b = noise_grid((2, 2, 3, 64), dtype=np.float64, **kw)
    assert b.std() > 0.03 and np.abs(a.astype(np.float64) - b).max() < TOL
    assert calls == []


def test_warped_tileable_lattice_stays_on_points(monkeypatch):
    # a lattice period wraps a cell's far corner, which the corner tables do not: points
    calls = _spy(monkeypatch, "grid_kernel")
    rows = _warp_rows(monkeypatch)
    _both((16, 40), kind="value", octaves=2, scale=4.0, seed=2, warp=0.7, tileable=True)
    assert rows == [] and calls == [(True, k.VALUE)]


def test_lattice2_table_holds_the_float64_roads_corners():
    # the packed corners of cell (i, j) are the float64 road's chained lookups
    from sylva.texture.noise import _setup

    perm = _setup("improved", 11, "quintic").tables.perm
    imp = wp32.lattice2_table(k.IMPROVED, 11, perm)
    val = wp32.lattice2_table(k.VALUE, 11, perm).view(np.uint32)
    for i, j in [(0, 0), (255, 255), (17, 255), (255, 3), (128, 64)]:
        for c, (di, dj) in enumerate([(0, 0), (1, 0), (0, 1), (1, 1)]):
            x, y = (i + di) & 255, (j + dj) & 255
            h = perm[perm[x] + y]
            assert (int(val[i * 256 + j]) >> (8 * c)) & 255 == h
            assert (int(imp[i * 256 + j]) >> (4 * c)) & 15 == perm[h] & 15


@pytest.mark.parametrize(
    "shape,extra",
    [((2, 3, 5, 40), {}),
     ((3, 4, 40), {"time": 0.7, "output": "f2-f1", "metric": "manhattan"}),
     ((2, 3, 4, 36), {"tileable": True, "fractal": "ridged", "output": "f2"}),
     ((16, 40), {"warp": 0.8}),
     ((4, 8, 40), {"warp": 0.8, "metric": "chebyshev", "output": "f3"}),
     ((2, 2, 3, 32), {"output": "cell"})],
    ids=["4d", "3d+time-f2-f1", "4d-tileable-f2", "warp-2d", "warp-3d-f3", "cell-4d"],
)
def test_worley_float32_within_tolerance(monkeypatch, shape, extra):
    calls = _spy(monkeypatch, "grid_kernel")
    rows = []
    real = w32.worley_grid32
    monkeypatch.setattr(w32, "worley_grid32", lambda *a: rows.append(a[0]) or real(*a))
    _both(shape, kind="worley", octaves=3, scale=5.0, seed=3, **extra)
    if "warp" in extra:  # the warp fields (F1..F3) by rows on the grid, then the points
        assert calls == [(True, 4)] and rows == [len(shape)] * len(shape)
    elif extra.get("output") == "cell":  # points, Worley's kind
        assert calls and all(c[1] == 4 for c in calls) and not rows
    else:  # F1..F3 of a 4D grid (3D with time) go by rows, as in 2D and 3D
        assert rows == [4] and not calls


@pytest.mark.parametrize("extra", [{}, {"metric": "euclidean2"}, {"tileable": True}],
                         ids=["euclidean", "euclidean2", "tileable"])
def test_worley_cell_id_float32_is_the_float64_cell(extra):
    # the id is a hash of the nearest cell: float32 distances pick the same cell (ties
    # apart), so one octave of 4D cell id is the float64 road's value exactly
    kw = dict(kind="worley", output="cell", scale=5.0, seed=3, **extra)
    a = noise_grid((2, 3, 4, 36), **kw)
    b = noise_grid((2, 3, 4, 36), dtype=np.float64, **kw)
    assert np.array_equal(a, b.astype(np.float32))
    assert b.std() > 0.1 and len(np.unique(a)) > 4  # many cells (tileable: periods of 1-5)


def test_roads():
    for kind in ("value", "perlin", "improved", "simplex"):  # by rows: _lattice4_32, _simplex32
        assert _road((2, 3, 4, 20), kind=kind) is None
        assert _road((3, 4, 20), kind=kind, time=0.5) is None
    assert _road((8, 20), kind="simplex", tileable=True) == "torus"
    assert _road((8, 20), warp=0.5, kind="value") == "warp"
    assert _road((2, 3, 4, 20), kind="worley") is None  # _worley32's rows
    assert _road((2, 3, 4, 20), kind="worley", output="cell") == "grid"
    # the float64 road stays; 2D/3D grids are _gridkernels32's
    assert _road((2, 3, 4, 20), dtype=np.float64) is None
    assert _road((3, 4, 20)) is None
    assert _road((3, 4, 20), kind="worley") is None
    assert _road((3, 4, 20), kind="worley", output="cell") is None  # float64's runs: faster


def test_warp_field_buffers_are_reused_and_never_leak_into_results(monkeypatch):
    # the warp fields' buffers go from one warped grid to the next (_Scratch: fresh
    # multi-megabyte arrays each call page-faulted as long as the arithmetic took); a
    # result is never one of them, and a later call does not change an earlier result
    kw = dict(kind="improved", octaves=2, scale=5.0, seed=2, warp=0.8)
    first = noise_grid((24, 40), **kw)
    kept = first.copy()
    taken = []
    real = p32._SCRATCH.take
    monkeypatch.setattr(p32._SCRATCH, "take", lambda n: taken.append(real(n)) or taken[-1])
    again = noise_grid((24, 40), **kw)
    other = noise_grid((24, 40), **dict(kw, seed=9))
    np.testing.assert_array_equal(first, kept)
    np.testing.assert_array_equal(again, first)
    assert not np.array_equal(other, first)
    assert len(taken) == 4 and len({id(b) for b in taken}) == 2  # two buffers, reused
    assert not any(np.shares_memory(b, r) for b in taken for r in (first, again, other))


def test_scratch_keeps_the_newest_buffers_within_its_budget(monkeypatch):
    monkeypatch.setattr(p32, "SCRATCH_BYTES", 3 * 400)
    sc = p32._Scratch()
    a, b = sc.take(100), sc.take(100)
    assert a is not b and a.dtype == np.float32 and a.size == 100
    sc.give([a, b])
    assert sc.take(100) is a and sc.take(50).size == 50  # a size it has not: a new one
    sc.give([a])
    c, d = sc.take(100), sc.take(100)
    assert {id(c), id(d)} == {id(a), id(b)}
    sc.give([c, d, np.empty(100, np.float32), np.empty(100, np.float32)])
    assert len(sc.free) == 3 and sc.free[0] is d  # the oldest (c) beyond the budget dropped

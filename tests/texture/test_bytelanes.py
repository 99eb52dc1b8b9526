"""The corner hashes in byte lanes (``_bytelanes``, AVX-512 VBMI byte permutes where the
CPU has them, scalar loads elsewhere) against the chained table lookups of Gustavson's
simplex and Perlin's improved-noise reference code, and both float32 roads (byte lanes
and table loads) against the float64 one."""

import os
import subprocess
import sys
from pathlib import Path

import numpy as np
import pytest
from numba import njit, prange, uint64

from sylva import _jit
from sylva.texture import _bytelanes as bl
from sylva.texture import _gridkernels32 as gk32
from sylva.texture import _simplex32 as s32
from sylva.texture import noise_grid
from sylva.texture.noise import noise_tables

N = 4 * bl.LANES


def _rows(seed, ndim):
    rng = np.random.default_rng(seed)
    rows = np.zeros((8, N), np.uint8)
    rows[:3] = rng.integers(0, 256, (3, N))  # i, j, k & 255: every byte, 255 included
    rows[0, :3] = 255
    # 3D: the six codes of Gustavson's six-way choice; 2D: 0 or 1
    codes = np.array([0b011001, 0b101001, 0b101100, 0b110100, 0b110010, 0b011010], np.uint8)
    rows[3] = codes[rng.integers(0, 6, N)] if ndim == 3 else rng.integers(0, 2, N)
    return rows


def _tables(seed):
    t = noise_tables(seed)
    return t.perm, t.perm12, np.concatenate([t.perm[:256], t.perm12[:256]]).astype(np.uint8)


def _hash_caller(ndim):
    # a fresh function per call: the intrinsic's code is generated when this compiles, for
    # the road that ``bl.VBMI`` names at that moment
    fn = bl.simplex3_hash if ndim == 3 else bl.simplex2_hash

    @njit(cache=False)
    def run(tab, rows):
        for o in range(0, rows.shape[1], bl.LANES):
            fn(tab.ctypes.data, rows.ctypes.data + uint64(o), uint64(rows.shape[1]))

    return run


def _reference(ndim, perm, perm12, rows):
    i, j, k, c = (rows[r].astype(np.int64) for r in range(4))
    if ndim == 2:
        offs = [(0, 0), (c, 1 - c), (1, 1)]
        return [perm12[i + di + perm[j + dj]] for di, dj in offs]
    bits = [(c >> n) & 1 for n in range(6)]
    offs = [(0, 0, 0), tuple(bits[:3]), tuple(bits[3:]), (1, 1, 1)]
    return [perm12[i + di + perm[j + dj + perm[k + dk]]] for di, dj, dk in offs]


@pytest.mark.parametrize("vbmi", [True, False], ids=["vbmi", "scalar"])
@pytest.mark.parametrize("ndim", [2, 3])
@pytest.mark.parametrize("seed", [None, 7])
def test_corner_hashes_are_gustavsons_chained_lookups(monkeypatch, vbmi, ndim, seed):
    if vbmi and not bl.VBMI:
        pytest.skip("this CPU has no AVX-512 VBMI (the scalar road runs here)")
    monkeypatch.setattr(bl, "VBMI", vbmi)
    perm, perm12, tab = _tables(seed)
    rows = _rows(3 if seed is None else seed, ndim)
    _hash_caller(ndim)(tab, rows)
    for corner, ref in enumerate(_reference(ndim, perm, perm12, rows)):
        np.testing.assert_array_equal(rows[4 + corner], ref)


def test_corner_code_is_the_six_way_choice():
    # _code3 from the comparisons equals Gustavson's if/else (his reference code)
    for x0, y0, z0 in [(3, 2, 1), (3, 1, 2), (2, 1, 3), (1, 2, 3), (1, 3, 2), (2, 3, 1),
                       (1, 1, 1), (2, 2, 1), (1, 2, 2)]:  # fmt: skip
        if x0 >= y0:
            o = ((1, 0, 0, 1, 1, 0) if y0 >= z0 else
                 (1, 0, 0, 1, 0, 1) if x0 >= z0 else (0, 0, 1, 1, 0, 1))  # fmt: skip
        else:
            o = ((0, 0, 1, 0, 1, 1) if y0 < z0 else
                 (0, 1, 0, 0, 1, 1) if x0 < z0 else (0, 1, 0, 1, 1, 0))  # fmt: skip
        code = int(s32._code3(x0 >= y0, y0 >= z0, x0 >= z0))
        assert tuple((code >> n) & 1 for n in range(6)) == o, (x0, y0, z0)


def _lattice_caller(ndim):
    fn = bl.lattice3_hash if ndim == 3 else bl.lattice2_hash

    @njit(cache=False)
    def run(tab, rows, y0, y1, z0, z1):
        for o in range(0, rows.shape[1], bl.LANES):
            a = rows.ctypes.data + uint64(o)
            if ndim == 3:
                fn(tab.ctypes.data, a, uint64(rows.shape[1]), y0, y1, z0, z1)
            else:
                fn(tab.ctypes.data, a, uint64(rows.shape[1]), y0, y1)

    return run


@pytest.mark.parametrize("vbmi", [True, False], ids=["vbmi", "scalar"])
@pytest.mark.parametrize("ndim", [2, 3])
@pytest.mark.parametrize("yz", [(0, 1, 254, 255), (255, 0, 7, 8)])
def test_lattice_hashes_are_perlins_chained_lookups(monkeypatch, vbmi, ndim, yz):
    if vbmi and not bl.VBMI:
        pytest.skip("this CPU has no AVX-512 VBMI (the scalar road runs here)")
    monkeypatch.setattr(bl, "VBMI", vbmi)
    perm = noise_tables(4).perm
    rng = np.random.default_rng(1)
    x0 = rng.integers(0, 256, N)
    x0[:2] = (0, 255)
    x1 = (x0 + 1) % 256
    rows = np.zeros((10, N), np.uint8)
    rows[0], rows[1] = perm[x0], perm[x1]  # the x axis table holds perm[x] already
    y0, y1, z0, z1 = yz
    _lattice_caller(ndim)(perm[:256].astype(np.uint8), rows, *map(np.uint64, yz))
    px = [perm[x0], perm[x1]]
    if ndim == 3:  # Perlin's improved noise: perm[perm[perm[x] + y] + z], corner c = zyx bits
        for c in range(8):
            h = perm[perm[px[c & 1] + (y1 if c & 2 else y0)] + (z1 if c & 4 else z0)]
            np.testing.assert_array_equal(rows[2 + c], h)
    else:  # 2D: perm[perm[perm[x] + y]] & 15, two nibbles a byte
        g = [perm[perm[px[c & 1] + (y1 if c & 2 else y0)]] & 15 for c in range(4)]
        np.testing.assert_array_equal(rows[2], g[0] | (g[1] << 4))
        np.testing.assert_array_equal(rows[3], g[2] | (g[3] << 4))


def _chain_caller(fn):
    @njit(cache=False)
    def run(tab, rows):
        for o in range(0, rows.shape[1], bl.LANES):
            fn(tab.ctypes.data, rows.ctypes.data + uint64(o), uint64(rows.shape[1]))

    return run


@pytest.mark.parametrize("vbmi", [True, False], ids=["vbmi", "scalar"])
@pytest.mark.parametrize("name", ["lattice_chain2", "lattice_chain2i", "lattice_chain3",
                                  "lattice_chain4", "simplex_chain2", "simplex_chain3",
                                  "simplex_chain4"])  # fmt: skip
def test_point_chains_are_the_float64_roads_chains(monkeypatch, vbmi, name):
    # the _points32 road's hashes: every corner of 4D, 3D and 2D lattice noise (Perlin's
    # chain, w first in 4D as the float64 road's) and of Gustavson's simplices
    if vbmi and not bl.VBMI:
        pytest.skip("this CPU has no AVX-512 VBMI (the scalar road runs here)")
    monkeypatch.setattr(bl, "VBMI", vbmi)
    perm, perm12, tab = _tables(9)
    rng = np.random.default_rng(5)
    rows = np.zeros((25, N), np.uint8)
    I0 = rng.integers(0, 256, (4, N))
    I0[:, 0] = 255
    I1 = (I0 + 1) % 256
    if name.startswith("lattice"):
        rows[0:4], rows[4:8] = I0, I1
    else:  # simplex: corner c's indices i, j, k, l in rows 4c ..
        rows[:20] = rng.integers(0, 256, (20, N))
    _chain_caller(getattr(bl, name))(tab, rows)
    if name.startswith("lattice"):
        nd = int(name[13])
        for c in range(1 << nd):
            x, y, z, w = ((I1 if c >> a & 1 else I0)[a] for a in range(4))
            if name == "lattice_chain4":
                h = perm[perm[perm[perm[w] + x] + y] + z]
            elif name == "lattice_chain3":
                h = perm[perm[perm[x] + y] + z]
            elif name == "lattice_chain2i":
                h = perm[perm[perm[x] + y]]
            else:
                h = perm[perm[x] + y]
            np.testing.assert_array_equal(rows[8 + c], h)
    else:
        nd = int(name[-1])
        for c in range(nd + 1):
            i, j, k, l = (rows[4 * c + a].astype(np.int64) for a in range(4))
            if nd == 4:
                h = perm[i + perm[j + perm[k + perm[l]]]] & 31
            elif nd == 3:
                h = perm12[i + perm[j + perm[k]]]
            else:
                h = perm12[i + perm[j]]
            np.testing.assert_array_equal(rows[20 + c], h)


@pytest.mark.parametrize("avx512", [True, False], ids=["vpermps", "scalar"])
def test_cell_lerp16_picks_each_lanes_cell(monkeypatch, avx512):
    # the cell road's permute: lane q blends cell cid[q] - cf's coefficients (p0, q0, p1,
    # q1) as lerp(u, p0 x + q0, p1 (x - 1) + q1); 16 lanes over up to 16 cells
    if avx512 and not bl.AVX512:
        pytest.skip("this CPU has no AVX-512")
    monkeypatch.setattr(bl, "AVX512", avx512)

    @njit(cache=False)
    def run(cc, cid, cf, xf, xu, out):
        bl.cell_lerp16(cc.ctypes.data, uint64(cc.shape[1] * 4), cid.ctypes.data, cf,
                       xf.ctypes.data, xu.ctypes.data, out.ctypes.data)

    rng = np.random.default_rng(2)
    cc = rng.uniform(-1, 1, (4, 40)).astype(np.float32)
    for cells in ([7] * 16, list(range(7, 23)), sorted(rng.integers(7, 12, 16))):
        cid = np.asarray(cells, np.int32)
        xf = rng.uniform(0, 1, 16).astype(np.float32)
        xu = rng.uniform(0, 1, 16).astype(np.float32)
        out = np.zeros(16, np.float32)
        run(cc[:, 7:].copy(), cid, 7, xf, xu, out)
        c = cc[:, cid].astype(np.float64)
        a = c[0] * xf + c[1]
        b = c[2] * (xf - 1.0) + c[3]
        np.testing.assert_allclose(out, a + xu * (b - a), rtol=0, atol=1e-6)


@pytest.fixture
def _compiled():
    with _jit.compiled():
        yield


@pytest.mark.usefixtures("_compiled")
@pytest.mark.parametrize("use", [True, False], ids=["bytelanes", "packed"])
@pytest.mark.parametrize("shape", [(20, 300), (5, 12, 333)], ids=["2d", "3d"])
@pytest.mark.parametrize("fractal,octaves", [("fbm", 1), ("fbm", 6), ("ridged", 3)])
def test_both_float32_simplex_roads_within_tolerance(monkeypatch, use, shape, fractal,
                                                     octaves):  # fmt: skip
    monkeypatch.setattr(bl, "USE", use)
    # negative lattice coordinates: the byte of i & 255 is two's complement
    kw = dict(kind="simplex", fractal=fractal, octaves=octaves, scale=24.0, seed=5,
              offset=(-30.25, -7.5, -2.0)[: len(shape)])
    a = noise_grid(shape, **kw)
    b = noise_grid(shape, dtype=np.float64, **kw)
    assert a.dtype == np.float32
    assert np.abs(a.astype(np.float64) - b).max() < gk32.TOLERANCE
    assert b.std() > 0.05


@pytest.mark.usefixtures("_compiled")
@pytest.mark.parametrize("use", [True, False], ids=["bytelanes", "tables"])
@pytest.mark.parametrize("shape", [(20, 300), (4, 10, 333)], ids=["2d", "3d"])
@pytest.mark.parametrize("tileable", [False, True])
def test_both_float32_improved_roads_within_tolerance(monkeypatch, use, shape, tileable):
    # 6 octaves from 4 samples a cell down: the first by cells, the finer ones by samples
    # (the byte-lane road where it is taken); negative lattice coordinates and periods
    monkeypatch.setattr(bl, "USE", use)
    kw = dict(kind="improved", octaves=6, scale=75.0, seed=3, tileable=tileable,
              offset=(-41.5, -7.25, -3.0)[: len(shape)])
    a = noise_grid(shape, **kw)
    b = noise_grid(shape, dtype=np.float64, **kw)
    assert np.abs(a.astype(np.float64) - b).max() < gk32.TOLERANCE
    assert b.std() > 0.05


@pytest.mark.usefixtures("_compiled")
@pytest.mark.parametrize("use", [True, False], ids=["permutes", "selects"])
@pytest.mark.parametrize("kind", ["value", "perlin", "improved"])
@pytest.mark.parametrize("shape", [(6, 500), (3, 5, 333)], ids=["2d", "3d"])
def test_both_cell_roads_within_tolerance(monkeypatch, use, kind, shape):
    # 25, 12.5, 6.25, 3.1 samples a cell: the cell road (permutes down to two samples a
    # cell, select chains down to about four), then samples; rows of several blocks
    # with a partial last vector
    monkeypatch.setattr(bl, "USE", use)
    kw = dict(kind=kind, octaves=5, scale=20.0, seed=8, offset=(-3.3, 1.7, -0.4)[: len(shape)])
    a = noise_grid(shape, **kw)
    b = noise_grid(shape, dtype=np.float64, **kw)
    assert np.abs(a.astype(np.float64) - b).max() < gk32.TOLERANCE
    assert b.std() > 0.05


@pytest.mark.usefixtures("_compiled")
@pytest.mark.parametrize("use", [True, False], ids=["bytelanes", "tables"])
@pytest.mark.parametrize(
    "shape,kw",
    [((2, 3, 6, 70), dict(kind="value", octaves=3)),
     ((2, 3, 6, 70), dict(kind="improved", octaves=2, offset=(-5.5, 2.0, -1.0, 3.25))),
     ((2, 3, 6, 70), dict(kind="perlin", octaves=2, tileable=True)),
     ((2, 3, 6, 70), dict(kind="simplex", octaves=3, fractal="ridged")),
     ((24, 70), dict(kind="simplex", octaves=2, tileable=True)),
     ((3, 10, 40), dict(kind="simplex", octaves=2, warp=0.6)),
     ((20, 50), dict(kind="improved", octaves=2, warp=0.7))],
    ids=["4d-value", "4d-improved", "4d-perlin", "4d-simplex", "torus", "warp3d", "warp2d"],
)
def test_both_point_roads_within_tolerance(monkeypatch, use, shape, kw):
    # the _points32 road (4D grids, the torus of tileable simplex, domain warping)
    monkeypatch.setattr(bl, "USE", use)
    kw = dict(kw, scale=7.0, seed=2)
    a = noise_grid(shape, **kw)
    b = noise_grid(shape, dtype=np.float64, **kw)
    assert np.abs(a.astype(np.float64) - b).max() < gk32.TOLERANCE
    assert b.std() > 0.05


# ------------------------------------------------------- the vector width (bl.Wide)
def _axpy(a, b):
    for i in range(a.shape[0]):
        a[i] = a[i] * b[i] + np.float32(1.5)


def _axpy_rows(a, b):
    for r in prange(a.shape[0]):
        for i in range(a.shape[1]):
            a[r, i] = a[r, i] * b[r, i] + np.float32(1.5)


def _fresh(fn, shape, **opts):
    kernel = njit(fastmath=True, **opts)(fn)  # a fresh dispatcher: compiled here, uncached
    a = np.ones(shape, np.float32)
    kernel(a, a)
    assert a.flat[0] == np.float32(2.5)
    return kernel, kernel.signatures[0]


_PREFER = '"prefer-vector-width"="512"'


def test_wide_kernels_ask_llvm_for_512_bit_vectors():
    wide, sig = _fresh(_axpy, 64, pipeline_class=bl.Wide)
    plain, psig = _fresh(_axpy, 64)
    assert _PREFER in wide.inspect_llvm(sig)
    assert _PREFER not in plain.inspect_llvm(psig)


def test_sylva_vector_width_256_leaves_llvms_width(monkeypatch):
    monkeypatch.setenv("SYLVA_VECTOR_WIDTH", "256")
    wide, sig = _fresh(_axpy, 64, pipeline_class=bl.Wide)
    assert _PREFER not in wide.inspect_llvm(sig)


@pytest.mark.skipif(not bl.AVX512, reason="the CPU has no AVX-512")
def test_wide_loops_run_in_zmm_registers_serial_and_in_prange_bodies():
    # on Intel's AVX-512 models LLVM's own choice is ymm (256 bits) for these loops
    for fn, shape, opts in ((_axpy, 64, {}), (_axpy_rows, (4, 64), {"parallel": True})):
        wide, sig = _fresh(fn, shape, pipeline_class=bl.Wide, **opts)
        assert "zmm" in wide.inspect_asm(sig), fn.__name__


_OTHER_CPU = """
import sys
import numpy as np
sys.path.insert(0, sys.argv[1])
from sylva.texture import _bytelanes as bl
from tests.texture import test_bytelanes as t
assert not bl.VBMI and not bl.AVX512, (bl.VBMI, bl.AVX512)
perm, perm12, tab = t._tables(5)
rows = t._rows(5, 3)
t._hash_caller(3)(tab, rows)  # compiled for haswell: scalar loads, no byte permutes
for corner, ref in enumerate(t._reference(3, perm, perm12, rows)):
    np.testing.assert_array_equal(rows[4 + corner], ref)
print("ok")
"""


def test_a_build_for_a_cpu_without_avx512_emits_none_of_its_instructions(tmp_path):
    # NUMBA_CPU_NAME / NUMBA_CPU_FEATURES build numba's code for another CPU (a cache for
    # other machines, an AVX2 build measured here): the intrinsics follow those features,
    # not the host's (an AVX-512 intrinsic in a haswell build fails to compile)
    import llvmlite.binding as llvm

    feats = [("-" if k.startswith(("avx512", "avx10", "evex512", "amx")) else
              "+" if v else "-") + k for k, v in llvm.get_host_cpu_features().items()]  # fmt: skip
    root = Path(__file__).resolve().parents[2]
    env = dict(os.environ, NUMBA_CPU_NAME="haswell", NUMBA_CPU_FEATURES=",".join(feats),
               NUMBA_CACHE_DIR=str(tmp_path), SYLVA_BYTELANES="0",
               PYTHONPATH=str(Path(bl.__file__).parents[2]))  # fmt: skip
    run = subprocess.run([sys.executable, "-c", _OTHER_CPU, str(root)], env=env, cwd=root,
                         capture_output=True, text=True, timeout=300)  # fmt: skip
    assert run.returncode == 0 and run.stdout.strip() == "ok", run.stderr[-2000:]

"""Float32 SIMD paths for noise on regular grids (private; see :mod:`sylva.texture.noise`).

The float32 road of :func:`sylva.texture.noise_grid` (``dtype=np.float32``, the default):
the same lattices, hashes and gradients as the float64 road of :mod:`._gridkernels`, but
float32 arithmetic throughout, every octave fused into one pass per row (the output row
is the accumulator), and one branch-free loop per row and octave that LLVM vectorises to
the machine's widest registers (16 float32 lanes with AVX-512, 8 with AVX2; the kernels
compile with :class:`._bytelanes.Wide`, since LLVM's Intel AVX-512 models would keep
them at 256 bits): gradients come
from bit masks or selects instead of tables, floors are float floors, fast-math lets LLVM
fuse multiply-adds.  The permutation tables stay (so that the values are the float64
road's within rounding); where the CPU has AVX-512 VBMI their lookups go 64 at a time in
byte lanes (:mod:`._bytelanes`, the ``hashed`` / ``lanes`` flag of the work buffers),
elsewhere in scalar passes (LLVM emits no vector gathers for znver4, and explicit
``vpgatherdd`` measured no faster than scalar loads), so the lattice noises look up less.
Where an octave has about four samples a lattice cell or more along x (``KMAX``; two,
``KPERM``, with AVX-512 permutes), value, classic and improved noise go by *cells*:
each cell of a row is hashed once (scalar; and kept for the next rows in the same lattice
rows, ``y0, y1, z0, z1``, which only reduce it anew), its noise along the row reduced to four
coefficients, ``lerp(u, p0 x + q0, p1 (x - 1) + q1)`` (SIMD across cells), and the
samples take their cell's coefficients by select chains over ``KMAX`` cells (SIMD; one
set-up of the chains for each run of whole 16-lane vectors inside those cells, as a literal
trip count of 16 is unrolled to scalar code), or with AVX-512 by one permute per
coefficient row for each 16-lane vector (:func:`_cell_eval16`).  Finer octaves keep the
per-sample road: on rows longer than 128 samples (3D value noise: 256) row tables of the
corner hashes (for every ``perm[x]``: 2D, and 3D improved and value noise — two lookups a
sample instead of fourteen chained ones; 3D improved noise 1.4-1.7x over 6 octaves on
znver3), then SIMD; improved noise's corner gradient indices travel packed, four (2D) or
eight (3D) nibbles in one int32.  Its gradient selects test ``h & 13 == 12`` for "h is
12 or 14": the ``|`` of two compares made LLVM pack and unpack masks (the 3D corner pass
4.4 -> 2.5 ns a sample).  Integer work inside the SIMD loops is int32 throughout (numba
widens ``int32 & 15`` to int64, which cuts the lanes to 4).
Simplex noise is :mod:`._simplex32` (its corners hashed in byte lanes where the CPU has
AVX-512 VBMI, else one packed table word a sample; 3D located in float64).

Covered here, 2D and 3D, every fractal sum (fBm, turbulence, ridged) and integer lattice
periods (``tileable``): value, classic Perlin (its 256 gradients stored into the block by
the scalar hash pass), improved Perlin, simplex, and Worley F1..F3 and their combinations
(:mod:`._worley32`, which also takes 4D Worley F1..F3 by rows).  4D lattice grids (and 3D
grids with ``time``) go by rows too (:mod:`._lattice4_32`), as 4D simplex does
(``_simplex32.rows4s``); tileable simplex (its 4D torus) and domain warping take the
float32 road of :mod:`._points32` (warped 2D and 3D grids by rows, :mod:`._warp32`).  The rest
takes the float64 road and is rounded once: Worley's cell id and Poisson process on 2D and 3D grids,
and its orders above F3.  A work item's rows go in one call (:func:`_lat_rows`,
``_simplex32._simplex_rows``, ``_worley32._worley_rows``: a call per row cost more than a
short row's work); the texture graph runs its lattice and simplex generators through them a
block of rows at a time, its Worley generators row by row (``_worley32.row_worley32``;
:func:`row_lattice32` and ``row_simplex32`` are the one-row forms).

Results differ from the float64 road by float32 rounding only: the difference is below
``TOLERANCE`` (absolute, on values normalised to about [-1, 1]); see
``tests/texture/test_grid32.py``.
"""

from __future__ import annotations

import math
import os

import numpy as np
from numba import njit, prange, uint64

from .. import _jit
from . import _bytelanes as _bl
from . import _kernels as k
from ._gridkernels import BLOCK, axis_tables

#: bound on the absolute difference from the float64 road (values about [-1, 1]): value,
#: classic and improved noise and Worley differ by ~3e-7 (their lattice tables and feature
#: points are computed in float64);
#: 2D simplex, located in float32 coordinates near the origin (their rounding moves a
#: value by up to ~3.5e-7 per cell of distance times the octave's amplitude; a row's octaves
#: spend at most 256 of that, ~1e-4, the rest locate in float64: ``_simplex32._s2_near``),
#: by up to ~7e-5 over 6 octaves; 3D simplex is located in float64 (its kernel, r² = 0.6,
#: jumps across simplex faces, so the simplex must be the float64 road's) and differs by
#: ~5e-7
TOLERANCE = 2e-4
#: work items of a grid (``prange``; numba hands each thread an equal share of them): each
#: allocates its row and block buffers once, so a few dozen rather than one per
#: 8 rows (a 16 x 256 x 256 grid made 4,608 allocations)
CHUNKS = 64

_F = np.float32
ZERO = _F(0.0)
ONE = _F(1.0)
HALF = _F(0.5)
F2 = _F(k.F2)
G2 = _F(k.G2)
G2X2 = _F(2.0 * k.G2 - 1.0)  # x2 = x0 - 1 + 2 G2
F3 = _F(k.F3)
G3 = _F(k.G3)
G3X2 = _F(2.0 * k.G3)
G3X3 = _F(3.0 * k.G3 - 1.0)
SIX = _F(6.0)
FIFTEEN = _F(15.0)
TEN = _F(10.0)
THREE = _F(3.0)
TWO = _F(2.0)
R2 = _F(0.5)
R3 = _F(0.6)
S2 = _F(70.0)
S3 = _F(32.0)

_OPTS = dict(cache=True, fastmath=True, error_model="numpy", pipeline_class=_bl.Wide)
_OPTS64 = dict(cache=True, error_model="numpy", pipeline_class=_bl.Wide)  # no fast-math
_i32 = np.int32
I0, I1, I2, I4, I8, I12, I13, I15 = (np.int32(v) for v in (0, 1, 2, 4, 8, 12, 13, 15))
_C28, _C30, _C31 = np.int32(28), np.int32(30), np.int32(31)
_SIGN = np.int32(-(2**31))  # the float32 sign bit


@njit(inline="always", **_OPTS)
def _lerp(t, a, b):
    return a + t * (b - a)


@njit(inline="always", **_OPTS)
def _g16(h, x, y, z):
    """Improved noise's gradient ``GRAD16[h & 15] . (x, y, z)`` by selects (Perlin's own
    ``grad``; no table).  Every integer operation is int32 (:func:`_i32`): numba widens
    ``int32 & 15`` to int64, and LLVM then ran the whole loop 4 lanes wide instead of 16."""
    h = _i32(h & I15)
    u = y if _bl.shl32(h, _C28) < I0 else x  # bit 3 by its sign: one blend
    v = y if h < I4 else (x if _i32(h & I13) == I12 else z)  # h is 12 or 14
    # the signs, bits 0 and 1, xor-ed into the float bits (no negation and select)
    return _bl.xorf(u, _bl.shl32(h, _C31)) + _bl.xorf(v, _i32(_bl.shl32(h, _C30) & _SIGN))


@njit(inline="always", **_OPTS)
def _g16_2(h, x, y):
    """:func:`_g16` with z = 0."""
    h = _i32(h & I15)
    u = y if _bl.shl32(h, _C28) < I0 else x
    v = y if h < I4 else (x if _i32(h & I13) == I12 else ZERO)
    return _bl.xorf(u, _bl.shl32(h, _C31)) + _bl.xorf(v, _i32(_bl.shl32(h, _C30) & _SIGN))


@njit(**_OPTS)
def _combine_block(mode, row, weight, base, cnt, nb, amp, gain, first):
    """Add octave values ``nb[:cnt]`` into ``row[base:base + cnt]`` (fBm, turbulence or
    ridged, as :func:`._gridkernels._combine_block`); ``first``: the first octave, which
    sets ``row`` (and ridged's ``weight``) instead, as if they held 0 (and 1) — no pass to
    clear them."""
    b = uint64(base)
    if mode == k.FBM:
        if first:
            for q in range(cnt):
                row[b + uint64(q)] = amp * nb[q]
        else:
            for q in range(cnt):
                row[b + uint64(q)] += amp * nb[q]
    elif mode == k.TURBULENCE:
        if first:
            for q in range(cnt):
                row[b + uint64(q)] = amp * abs(nb[q])
        else:
            for q in range(cnt):
                row[b + uint64(q)] += amp * abs(nb[q])
    elif first:
        for q in range(cnt):
            i = b + uint64(q)
            s = ONE - abs(nb[q])
            s *= s
            weight[i] = min(max(s * gain, ZERO), ONE)
            row[i] = amp * s
    else:
        for q in range(cnt):
            i = b + uint64(q)
            s = ONE - abs(nb[q])
            s *= s
            s *= weight[i]
            weight[i] = min(max(s * gain, ZERO), ONE)
            row[i] += amp * s


@njit(inline="always", **_OPTS)
def _finish(mode, row, norm):
    if mode == k.RIDGED:
        for i in range(row.shape[0]):
            row[i] *= norm


@njit(**_OPTS)
def _lat_hash(kind, ndim, base, cnt, a0, a1, perm, vals, grad, y0, y1, z0, z1, hb, vb, gb):
    """Scalar pass: the corner hashes of samples ``base..base + cnt`` (improved noise: the
    corners' gradient indices into ``hb[c]``, in 2D packed, corner ``c``'s ``perm[...] & 15``
    in bits ``4c .. 4c + 3`` of ``hb[0]``, one store a sample; value noise: lattice values
    into ``vb``; classic Perlin noise: the gradients into ``gb``)."""
    b0 = uint64(base)
    if kind == k.PERLIN:
        for q in range(cnt):
            i = b0 + uint64(q)
            a = uint64(a0[i])
            b = uint64(a1[i])
            if ndim == 2:
                h0 = uint64(perm[a + y0])
                h1 = uint64(perm[b + y0])
                h2 = uint64(perm[a + y1])
                h3 = uint64(perm[b + y1])
                gb[0, 0, q] = grad[h0, 0]
                gb[1, 0, q] = grad[h0, 1]
                gb[0, 1, q] = grad[h1, 0]
                gb[1, 1, q] = grad[h1, 1]
                gb[0, 2, q] = grad[h2, 0]
                gb[1, 2, q] = grad[h2, 1]
                gb[0, 3, q] = grad[h3, 0]
                gb[1, 3, q] = grad[h3, 1]
            else:
                aa = uint64(perm[a + y0])
                ba = uint64(perm[b + y0])
                ab = uint64(perm[a + y1])
                bb = uint64(perm[b + y1])
                for c in range(8):
                    h = aa if c % 4 == 0 else (ba if c % 4 == 1 else (ab if c % 4 == 2 else bb))
                    g = uint64(perm[h + (z1 if c >= 4 else z0)])
                    gb[0, c, q] = grad[g, 0]
                    gb[1, c, q] = grad[g, 1]
                    gb[2, c, q] = grad[g, 2]
        return
    for q in range(cnt):
        i = b0 + uint64(q)
        a = uint64(a0[i])
        b = uint64(a1[i])
        if ndim == 2:
            h0 = perm[a + y0]
            h1 = perm[b + y0]
            h2 = perm[a + y1]
            h3 = perm[b + y1]
            if kind == k.IMPROVED:  # the corners' 4-bit gradient indices in one word
                hb[0, q] = ((perm[uint64(h0)] & 15) | ((perm[uint64(h1)] & 15) << 4)
                            | ((perm[uint64(h2)] & 15) << 8) | ((perm[uint64(h3)] & 15) << 12))
            else:
                vb[0, q] = vals[uint64(h0)]
                vb[1, q] = vals[uint64(h1)]
                vb[2, q] = vals[uint64(h2)]
                vb[3, q] = vals[uint64(h3)]
        else:
            aa = uint64(perm[a + y0])
            ba = uint64(perm[b + y0])
            ab = uint64(perm[a + y1])
            bb = uint64(perm[b + y1])
            if kind == k.IMPROVED:  # 3D: packing measured slower (8 more ALU ops a sample)
                hb[0, q] = perm[aa + z0]
                hb[1, q] = perm[ba + z0]
                hb[2, q] = perm[ab + z0]
                hb[3, q] = perm[bb + z0]
                hb[4, q] = perm[aa + z1]
                hb[5, q] = perm[ba + z1]
                hb[6, q] = perm[ab + z1]
                hb[7, q] = perm[bb + z1]
            else:
                vb[0, q] = vals[uint64(perm[aa + z0])]
                vb[1, q] = vals[uint64(perm[ba + z0])]
                vb[2, q] = vals[uint64(perm[ab + z0])]
                vb[3, q] = vals[uint64(perm[bb + z0])]
                vb[4, q] = vals[uint64(perm[aa + z1])]
                vb[5, q] = vals[uint64(perm[ba + z1])]
                vb[6, q] = vals[uint64(perm[ab + z1])]
                vb[7, q] = vals[uint64(perm[bb + z1])]


@njit(**_OPTS)
def _lat_hash_b(base, cnt, a0, a1, bt, lb, y0, y1, z0, z1):
    """:func:`_lat_hash` of 3D improved noise in byte lanes: the samples' ``perm[x0]``,
    ``perm[x1]`` into byte rows 0 and 1 of ``lb`` (SIMD), then the eight corners' hashes
    into rows 2..9 (:func:`._bytelanes.lattice3_hash`)."""
    b0 = uint64(base)
    for q in range(cnt):
        lb[0, q] = np.uint8(a0[b0 + uint64(q)])
        lb[1, q] = np.uint8(a1[b0 + uint64(q)])
    p = bt.ctypes.data
    rs = uint64(lb.shape[1])
    r0 = lb.ctypes.data
    for o in range(0, cnt, _bl.LANES):
        _bl.lattice3_hash(p, r0 + uint64(o), rs, y0, y1, z0, z1)


@njit(**_OPTS)
def _lat_eval_b3(base, cnt, fx, cu, y, v, z, w, lb, nb):
    """:func:`_lat_eval` of 3D improved noise from the byte rows 2..9 of ``lb`` (its own
    copy of that one loop: :func:`_lat_eval` for a byte table would compile all six)."""
    b0 = uint64(base)
    for q in range(cnt):
        i = b0 + uint64(q)
        x = fx[i]
        u = cu[i]
        nb[q] = _imp3(lb[2, q], lb[3, q], lb[4, q], lb[5, q], lb[6, q], lb[7, q], lb[8, q],
                      lb[9, q], x, y, z, u, v, w)


@njit(**_OPTS)
def _lat_hash2_b(base, cnt, a0, a1, bt, lb, y0, y1, hb):
    """:func:`_lat_hash` of 2D improved noise in byte lanes
    (:func:`._bytelanes.lattice2_hash`), the four nibbles into ``hb[0]``'s word."""
    b0 = uint64(base)
    for q in range(cnt):
        lb[0, q] = np.uint8(a0[b0 + uint64(q)])
        lb[1, q] = np.uint8(a1[b0 + uint64(q)])
    p = bt.ctypes.data
    rs = uint64(lb.shape[1])
    r0 = lb.ctypes.data
    for o in range(0, cnt, _bl.LANES):
        _bl.lattice2_hash(p, r0 + uint64(o), rs, y0, y1)
    for q in range(cnt):
        hb[0, q] = _i32(lb[2, q]) | _i32(_i32(lb[3, q]) << I8)


@njit(**_OPTS)
def _row_tables(kind, perm, vals, grad, y0, y1, th, tv, tg):
    """The 2D corner hashes of one row and octave for every ``a = perm[x]`` (0..255): a
    row of 2D noise then needs one lookup per corner instead of two."""
    for a in range(256):
        h0 = uint64(perm[uint64(a) + y0])
        h1 = uint64(perm[uint64(a) + y1])
        if kind == k.PERLIN:
            tg[0, 0, a] = grad[h0, 0]
            tg[1, 0, a] = grad[h0, 1]
            tg[0, 1, a] = grad[h1, 0]
            tg[1, 1, a] = grad[h1, 1]
        elif kind == k.IMPROVED:  # corner (x, y0) in bits 0..3, (x, y1) in bits 8..11
            th[0, a] = (perm[h0] & 15) | ((perm[h1] & 15) << 8)
        else:
            tv[0, a] = vals[h0]
            tv[1, a] = vals[h1]


@njit(**_OPTS)
def _row_tables3(kind, perm, vals, y0, y1, z0, z1, th, tv):
    """:func:`_row_tables` of a 3D row of improved or value noise: for every
    ``a = perm[x]`` the hashes of the four corners ``(x, y0 | y1, z0 | z1)`` (improved
    noise: their gradient indices packed in bits 0, 8, 16 and 24 of ``th[0, a]``), so that
    a sample needs two lookups instead of fourteen chained ones (its corners at ``x1`` are
    the next column's at ``x0``)."""
    for a in range(256):
        h0 = uint64(perm[uint64(a) + y0])
        h1 = uint64(perm[uint64(a) + y1])
        c0 = uint64(perm[h0 + z0])  # corner order as _imp3's: y1 is +1, z1 is +2
        c1 = uint64(perm[h1 + z0])
        c2 = uint64(perm[h0 + z1])
        c3 = uint64(perm[h1 + z1])
        if kind == k.IMPROVED:
            th[0, a] = _i32(_i32(c0 & 15) | _i32(c1 & 15) << I8 | _i32(c2 & 15) << np.int32(16)
                            | _i32(c3 & 15) << np.int32(24))
        else:
            tv[0, a] = vals[c0]
            tv[1, a] = vals[c1]
            tv[2, a] = vals[c2]
            tv[3, a] = vals[c3]


@njit(**_OPTS)
def _lat_hash3(kind, base, cnt, a0, a1, th, tv, hb, vb):
    """:func:`_lat_hash` of a 3D row through its :func:`_row_tables3` (improved noise: the
    eight corners' gradient indices packed in one word, corner ``c`` in bits ``4c ..``)."""
    b0 = uint64(base)
    for q in range(cnt):
        i = b0 + uint64(q)
        a = uint64(a0[i])
        b = uint64(a1[i])
        if kind == k.IMPROVED:
            hb[0, q] = th[0, a] | (th[0, b] << I4)
        else:
            for c in range(4):
                vb[2 * c, q] = tv[c, a]
                vb[2 * c + 1, q] = tv[c, b]


@njit(**_OPTS)
def _lat_hash2(kind, base, cnt, a0, a1, th, tv, tg, hb, vb, gb):
    """:func:`_lat_hash` of a 2D row through its :func:`_row_tables`."""
    b0 = uint64(base)
    for q in range(cnt):
        i = b0 + uint64(q)
        a = uint64(a0[i])
        b = uint64(a1[i])
        if kind == k.PERLIN:
            for c in range(2):
                gb[c, 0, q] = tg[c, 0, a]
                gb[c, 1, q] = tg[c, 0, b]
                gb[c, 2, q] = tg[c, 1, a]
                gb[c, 3, q] = tg[c, 1, b]
        elif kind == k.IMPROVED:  # :func:`_lat_hash`'s word: corners x0y0, x1y0, x0y1, x1y1
            hb[0, q] = th[0, a] | (th[0, b] << 4)
        else:
            vb[0, q] = tv[0, a]
            vb[1, q] = tv[0, b]
            vb[2, q] = tv[1, a]
            vb[3, q] = tv[1, b]


@njit(inline="always", **_OPTS)
def _imp3(h0, h1, h2, h3, h4, h5, h6, h7, x, y, z, u, v, w):
    """3D improved noise from its eight corner hashes (corner c: x1 if ``c & 1``, y1 if
    ``c & 2``, z1 if ``c & 4``), the fractions and curve weights (scalars only: an
    inlined helper that took the hash array would cost a reference count a sample)."""
    x_1 = x - ONE
    y_1 = y - ONE
    z_1 = z - ONE
    return _lerp(
        w,
        _lerp(v, _lerp(u, _g16(h0, x, y, z), _g16(h1, x_1, y, z)),
              _lerp(u, _g16(h2, x, y_1, z), _g16(h3, x_1, y_1, z))),
        _lerp(v, _lerp(u, _g16(h4, x, y, z_1), _g16(h5, x_1, y, z_1)),
              _lerp(u, _g16(h6, x, y_1, z_1), _g16(h7, x_1, y_1, z_1))),
    )


@njit(**_OPTS)
def _lat_eval(kind, ndim, base, cnt, fx, cu, y, v, z, w, hb, vb, gb, nb):
    """SIMD pass: blend the corners of samples ``base..base + cnt`` into ``nb``."""
    b0 = uint64(base)
    y_1 = y - ONE
    z_1 = z - ONE
    if kind == k.PERLIN and ndim == 2:
        for q in range(cnt):
            i = b0 + uint64(q)
            x = fx[i]
            u = cu[i]
            x_1 = x - ONE
            n00 = gb[0, 0, q] * x + gb[1, 0, q] * y
            n10 = gb[0, 1, q] * x_1 + gb[1, 1, q] * y
            n01 = gb[0, 2, q] * x + gb[1, 2, q] * y_1
            n11 = gb[0, 3, q] * x_1 + gb[1, 3, q] * y_1
            nb[q] = _lerp(v, _lerp(u, n00, n10), _lerp(u, n01, n11))
    elif kind == k.PERLIN:
        for q in range(cnt):
            i = b0 + uint64(q)
            x = fx[i]
            u = cu[i]
            x_1 = x - ONE
            n0 = gb[0, 0, q] * x + gb[1, 0, q] * y + gb[2, 0, q] * z
            n1 = gb[0, 1, q] * x_1 + gb[1, 1, q] * y + gb[2, 1, q] * z
            n2 = gb[0, 2, q] * x + gb[1, 2, q] * y_1 + gb[2, 2, q] * z
            n3 = gb[0, 3, q] * x_1 + gb[1, 3, q] * y_1 + gb[2, 3, q] * z
            n4 = gb[0, 4, q] * x + gb[1, 4, q] * y + gb[2, 4, q] * z_1
            n5 = gb[0, 5, q] * x_1 + gb[1, 5, q] * y + gb[2, 5, q] * z_1
            n6 = gb[0, 6, q] * x + gb[1, 6, q] * y_1 + gb[2, 6, q] * z_1
            n7 = gb[0, 7, q] * x_1 + gb[1, 7, q] * y_1 + gb[2, 7, q] * z_1
            nb[q] = _lerp(
                w,
                _lerp(v, _lerp(u, n0, n1), _lerp(u, n2, n3)),
                _lerp(v, _lerp(u, n4, n5), _lerp(u, n6, n7)),
            )
    elif kind == k.IMPROVED and ndim == 2:
        for q in range(cnt):
            i = b0 + uint64(q)
            x = fx[i]
            u = cu[i]
            x_1 = x - ONE
            h = hb[0, q]
            n = _lerp(
                v,
                _lerp(u, _g16_2(h, x, y), _g16_2(_i32(h >> I4), x_1, y)),
                _lerp(u, _g16_2(_i32(h >> I8), x, y_1), _g16_2(_i32(h >> I12), x_1, y_1)),
            )
            nb[q] = n
    elif kind == k.IMPROVED:
        for q in range(cnt):
            i = b0 + uint64(q)
            x = fx[i]
            u = cu[i]
            nb[q] = _imp3(hb[0, q], hb[1, q], hb[2, q], hb[3, q], hb[4, q], hb[5, q],
                          hb[6, q], hb[7, q], x, y, z, u, v, w)
    elif ndim == 2:
        for q in range(cnt):
            i = b0 + uint64(q)
            u = cu[i]
            n = _lerp(v, _lerp(u, vb[0, q], vb[1, q]), _lerp(u, vb[2, q], vb[3, q]))
            nb[q] = n
    else:
        for q in range(cnt):
            i = b0 + uint64(q)
            u = cu[i]
            n = _lerp(
                w,
                _lerp(v, _lerp(u, vb[0, q], vb[1, q]), _lerp(u, vb[2, q], vb[3, q])),
                _lerp(v, _lerp(u, vb[4, q], vb[5, q]), _lerp(u, vb[6, q], vb[7, q])),
            )
            nb[q] = n

@njit(**_OPTS)
def _lat_eval_p3(base, cnt, fx, cu, y, v, z, w, hb, nb):
    """:func:`_lat_eval` of 3D improved noise from :func:`_lat_hash3`'s packed words."""
    b0 = uint64(base)
    for q in range(cnt):
        i = b0 + uint64(q)
        h = hb[0, q]
        nb[q] = _imp3(h, _i32(h >> I4), _i32(h >> I8), _i32(h >> I12), _i32(h >> np.int32(16)),
                      _i32(h >> np.int32(20)), _i32(h >> np.int32(24)),
                      _i32(h >> np.int32(28)), fx[i], y, z, cu[i], v, w)


#: the cell road's samples by AVX2 permutes (:func:`._bytelanes.cell_lerp8`) where the CPU
#: has AVX2 but not AVX-512 (with AVX-512 :func:`_cell_eval16` takes 16 at a time): on
#: znver3 single-octave 2D value and improved noise 1.4x, 3D improved 1.3x, 3D value 1.5x
#: (at four samples a cell a run of select chains covered a vector or two);
#: ``SYLVA_PERM8=0`` keeps the select chains (for comparison; read when the kernels compile)
_PERM8 = _bl.AVX2 and not _bl.AVX512 and os.environ.get("SYLVA_PERM8") != "0"

#: samples per vector block of the cell road (one AVX-512 vector, two AVX2 ones)
LANES = 16
#: the cell road takes an octave whose 16-sample blocks span at most this many lattice
#: cells along x (about four samples a cell or more); finer octaves keep the sample road
#: (measured: at two samples a cell the select chains cost more than the lookups saved)
KMAX = 5
#: with 16-lane permutes (:func:`_cell_eval16`) or AVX2's 8-lane ones (:data:`_PERM8`) the
#: cell road takes an octave whose 16-sample blocks span at most this many cells (about two
#: samples a cell or more; on znver3 3D value fBm 1.1x, the rest within the noise)
KPERM = 8
#: no lattice row (the cell road's cache key before its first row)
NOKEY = np.uint64(1 << 32)


@njit(inline="always", **_OPTS)
def _cx16(h, three):
    """Improved noise's gradient ``GRAD16[h & 15]`` as coefficients ``(gx, gy, gz)`` of
    ``(x, y, z)`` (selects; :func:`_g16` is ``gx x + gy y + gz z``; ``gz = 0`` in 2D)."""
    h = _i32(h & I15)
    su = -ONE if _i32(h & I1) != I0 else ONE
    sv = -ONE if _i32(h & I2) != I0 else ONE
    lo = h < I8
    v_y = h < I4
    v_x = _i32(h & I13) == I12  # h is 12 or 14 (one compare: ``|`` of two cost mask packing)
    gx = (su if lo else ZERO) + (sv if (not v_y) & v_x else ZERO)
    gy = (ZERO if lo else su) + (sv if v_y else ZERO)
    gz = sv if three & (not v_y) & (not v_x) else ZERO
    return gx, gy, gz


@njit(**_OPTS)
def _grads16(ndim, cnt, hb, gb):
    """SIMD pass: improved noise's corner gradients ``GRAD16[h]`` into ``gb`` (``h``:
    ``hb[c] & 15``, in 2D the 4-bit fields of :func:`_lat_hash`'s words ``hb[0]``; the
    layout of classic Perlin's, so that one coefficient loop serves both)."""
    if ndim == 3:
        for c in range(8):
            for q in range(cnt):
                gb[0, c, q], gb[1, c, q], gb[2, c, q] = _cx16(hb[c, q], True)
    else:
        for c in range(4):
            sh = _i32(4 * c)
            for q in range(cnt):
                gb[0, c, q], gb[1, c, q], _ = _cx16(_i32(hb[0, q] >> sh), False)


@njit(inline="always", **_OPTS)
def _coef_loop(three, cnt, y, v, z, w, gb, cc):
    # corners c = x bit + 2 y bit + 4 z bit (:func:`_lat_hash`'s order); ``three`` literal
    # at each call, so that each copy is one branch-free loop
    y_1 = y - ONE
    z_1 = z - ONE
    for q in range(cnt):
        for side in range(2):
            c2 = side + 2
            p = _lerp(v, gb[0, side, q], gb[0, c2, q])
            if three:
                c4 = side + 4
                c6 = side + 6
                r = _lerp(v, gb[1, side, q] * y + gb[2, side, q] * z,
                          gb[1, c2, q] * y_1 + gb[2, c2, q] * z)
                p = _lerp(w, p, _lerp(v, gb[0, c4, q], gb[0, c6, q]))
                r = _lerp(w, r, _lerp(v, gb[1, c4, q] * y + gb[2, c4, q] * z_1,
                                      gb[1, c6, q] * y_1 + gb[2, c6, q] * z_1))
            else:
                r = _lerp(v, gb[1, side, q] * y, gb[1, c2, q] * y_1)
            cc[2 * side, q] = p
            cc[2 * side + 1, q] = r


@njit(**_OPTS)
def _cell_coef(kind, ndim, cnt, y, v, z, w, vb, gb, cc):
    """SIMD pass over lattice cells ``0 .. cnt - 1`` of a row (their corner values in
    ``vb`` or gradients in ``gb``, :func:`_lat_hash` and :func:`_grads16`): the noise
    inside a cell along the row is ``lerp(u, p0 x + q0, p1 (x - 1) + q1)``;
    ``cc[:, e] = (p0, q0, p1, q1)`` (value noise: ``p0 = p1 = 0``)."""
    if kind == k.VALUE:
        for q in range(cnt):
            cc[0, q] = ZERO
            cc[2, q] = ZERO
        if ndim == 3:
            for q in range(cnt):
                cc[1, q] = _lerp(w, _lerp(v, vb[0, q], vb[2, q]), _lerp(v, vb[4, q], vb[6, q]))
                cc[3, q] = _lerp(w, _lerp(v, vb[1, q], vb[3, q]), _lerp(v, vb[5, q], vb[7, q]))
        else:
            for q in range(cnt):
                cc[1, q] = _lerp(v, vb[0, q], vb[2, q])
                cc[3, q] = _lerp(v, vb[1, q], vb[3, q])
    elif ndim == 3:
        _coef_loop(True, cnt, y, v, z, w, gb, cc)
    else:
        _coef_loop(False, cnt, y, v, z, w, gb, cc)


@njit(inline="always", **_OPTS)
def _ld(cc, i, ce):
    """Coefficient ``i`` of cells ``ce .. ce + KMAX - 1`` as scalars (loaded before the
    lane loop: selects between loads inside it would become address selects, a gather)."""
    return (cc[i, ce], cc[i, ce + uint64(1)], cc[i, ce + uint64(2)], cc[i, ce + uint64(3)],
            cc[i, ce + uint64(4)])


@njit(inline="always", **_OPTS)
def _pick(lane, c, span):
    """``c[lane]`` by a chain of selects over ``span`` cells (a literal at each call)."""
    a = c[0]
    if span > 1:
        a = c[1] if lane >= np.int32(1) else a
    if span > 2:
        a = c[2] if lane >= np.int32(2) else a
    if span > 3:
        a = c[3] if lane >= np.int32(3) else a
    if span > 4:
        a = c[4] if lane >= np.int32(4) else a
    return a


@njit(inline="always", **_OPTS)
def _cell_lanes(value, span, us, nl, cf, ce, cid, xf, xu, cc, nb, uo):
    """A run of ``nl`` samples from ``us`` into ``nb[uo:uo + nl]``, all of them in the
    ``span`` cells from ``cf`` (:func:`_cell_eval` makes the runs: whole 16-lane vectors,
    the row's last one partial).  The trip count is a variable: LLVM then vectorises the
    loop 16 lanes wide (a literal 16 would be unrolled to scalar code instead)."""
    c1 = _ld(cc, 1, ce)
    c3 = _ld(cc, 3, ce)
    if value:
        for q in range(nl):
            p = us + uint64(q)
            lane = np.int32(cid[p] - cf)  # 32-bit compares: 16 lanes a vector
            nb[uo + uint64(q)] = _lerp(xu[p], _pick(lane, c1, span), _pick(lane, c3, span))
    else:
        c0 = _ld(cc, 0, ce)
        c2 = _ld(cc, 2, ce)
        for q in range(nl):
            p = us + uint64(q)
            lane = np.int32(cid[p] - cf)  # 32-bit compares: 16 lanes a vector
            x = xf[p]
            a = _pick(lane, c0, span) * x + _pick(lane, c1, span)
            b = _pick(lane, c2, span) * (x - ONE) + _pick(lane, c3, span)
            nb[uo + uint64(q)] = _lerp(xu[p], a, b)


@njit(**_OPTS)
def _cell_eval16(base, cnt, cid, xf, xu, cc, e0, nb, ob):
    """:func:`_cell_eval` by 16-lane permutes (:func:`._bytelanes.cell_lerp16`, AVX-512):
    any 16 samples lie in at most 16 cells (``cid`` grows by at most one a sample), so
    every whole vector goes in one step, whatever the cells' width; the row's last
    partial vector sample by sample.  Sample ``p`` goes to ``nb[p - ob]`` (``ob = base``:
    a block buffer; 0: the row itself)."""
    end = base + cnt
    st = uint64(cc.shape[1] * 4)
    c0 = cc.ctypes.data
    pc = cid.ctypes.data
    px = xf.ctypes.data
    pu = xu.ctypes.data
    po = nb.ctypes.data
    s = base
    while s + LANES <= end:
        cf = cid[uint64(s)]
        o = uint64(s) * uint64(4)
        _bl.cell_lerp16(c0 + uint64(cf - e0) * uint64(4), st, pc + o, cf, px + o, pu + o,
                        po + uint64(s - ob) * uint64(4))
        s += LANES
    for p in range(s, end):
        c = uint64(cid[p] - e0)
        x = xf[p]
        a = cc[0, c] * x + cc[1, c]
        b = cc[2, c] * (x - ONE) + cc[3, c]
        nb[p - ob] = _lerp(xu[p], a, b)


@njit(**_OPTS)
def _cell_eval(kind, base, cnt, ob, cid, xf, xu, cc, e0, nb):
    """SIMD pass: samples ``base .. base + cnt`` (``base`` a multiple of :data:`LANES`)
    from their cells' coefficients (``cc``: those of cells ``e0 ..``; ``cid``: each
    column's cell) into ``nb``: runs of whole :data:`LANES`-lane vectors whose samples lie
    in :data:`KMAX` cells, each lane's coefficients by selects over those cells, loaded
    once per run; on AVX2 CPUs without AVX-512 (:data:`_PERM8`) eight samples at a time by
    permutes instead.  Sample ``p`` goes to ``nb[p - ob]`` (as :func:`_cell_eval16`)."""
    end = base + cnt
    s = base
    if _PERM8:  # AVX2 without AVX-512: 8 samples a step by vpermps, any cell width
        st = uint64(cc.shape[1] * 4)
        c0 = cc.ctypes.data
        pc = cid.ctypes.data
        px = xf.ctypes.data
        pu = xu.ctypes.data
        po = nb.ctypes.data
        while s + 8 <= end:
            cf = cid[uint64(s)]
            o = uint64(s) * uint64(4)
            _bl.cell_lerp8(c0 + uint64(cf - e0) * uint64(4), st, pc + o, cf, px + o, pu + o,
                           po + uint64(s - ob) * uint64(4))
            s += 8
        for p in range(s, end):
            c = uint64(cid[p] - e0)
            x = xf[p]
            nb[p - ob] = _lerp(xu[p], cc[0, c] * x + cc[1, c], cc[2, c] * (x - ONE) + cc[3, c])
        return
    while s < end:
        us = uint64(s)
        cf = cid[us]
        # the run of whole vectors whose samples lie in cells cf .. cf + KMAX - 1 (one
        # set-up of the select chains for them all: ~4 vectors a run at 16 samples a cell)
        e = s + LANES
        while e < end and cid[uint64(min(e + LANES, end) - 1)] - cf < KMAX:
            e += LANES
        e = min(e, end)
        # a literal span (the chain unrolls); one copy for every kind (value noise has
        # p0 = p1 = 0) keeps compile time down
        _cell_lanes(False, KMAX, us, e - s, cf, uint64(cf - e0), cid, xf, xu, cc, nb,
                    uint64(s - ob))
        s = e


@njit(inline="always", **_OPTS)
def _pick_row(out, r, r0, jfix, mfix):
    """Row ``r`` of a work item of :func:`_lat_rows` (and ``_simplex32._simplex_rows``): its
    lattice row ``(j, m)`` and the row it fills — ``out[r // ny, r % ny]`` of a grid
    (``jfix == -1``), ``out[0, r - r0]`` of a block of an image ``mfix`` rows high
    (``jfix == -2``), or the one row ``out[0, 0]`` at ``(mfix, jfix)`` (``jfix >= 0``)."""
    if jfix >= 0:
        return jfix, mfix, out[0, 0]
    if jfix == -2:
        return r % mfix, r // mfix, out[0, r - r0]
    ny = out.shape[1]
    return r % ny, r // ny, out[r // ny, r % ny]


@njit(**_OPTS)
def row_lattice32(kind, mode, ndim, xt, yt, zt, j, m, row, weight, amps, perm, vals, grad,
                  gain, work):
    """Row ``(m, j)`` of 2D or 3D value, classic or improved noise, every octave summed
    into ``row`` (float32; ridged sums are left unnormalised); ``work`` is
    :func:`row_work`'s block buffers (the texture graph's row routine)."""
    # typed ints, not constants: numba would compile a copy per literal value
    _lat_rows(kind, mode, ndim, xt, yt, zt, row.reshape((1, 1, row.shape[0])), np.int64(0),
              np.int64(1), j, m, weight, amps, perm, vals, grad, gain, work, ONE)


@njit(**_OPTS)
def _lat_rows(kind, mode, ndim, xt, yt, zt, out, r0, r1, jfix, mfix, weight, amps, perm, vals,
              grad, gain, work, norm):
    """Rows ``r0 .. r1`` of ``out`` (shape (nz, ny, nx); row ``r`` is ``(r // ny, r % ny)``)
    in one call, the tables and buffers taken out of their tuples once (a call per row, its
    dozens of arrays passed field by field, cost ~0.5 µs, more than a 1024-sample row's
    own work); with ``jfix >= 0`` the one row ``out[0, 0]`` at lattice row ``(mfix, jfix)``
    (:func:`row_lattice32`), with ``jfix == -2`` rows ``r0 .. r1`` of an image ``mfix`` rows
    high into ``out[0, :r1 - r0]`` (the texture graph's blocks of rows): both left
    unnormalised.  Rows of a grid (``jfix == -1``) are normalised (ridged)."""
    hb, vb, gb, nb, th, tv, tg, cc, cv, cg, coct, key, lb, bt, btok, lanes = work
    px0, px1, xf, xu, cid, cp0, cp1, kspan = xt
    yi0, yi1, yf, yv = yt
    zi0, zi1, zf, zw = zt
    kmax = KPERM if lanes or _PERM8 else KMAX
    hashed = lanes and kind == k.IMPROVED
    if hashed and btok[0] == 0:
        for a in range(256):
            bt[a] = perm[a]
        btok[0] = 1
    for r in range(r0, r1):
        j, m, row = _pick_row(out, r, r0, jfix, mfix)
        nx = row.shape[0]
        if amps.shape[0] == 0:  # no octave (the first octave sets the row, no clearing pass)
            row[:] = ZERO
        for o in range(px0.shape[0]):
            y0 = uint64(yi0[o, j])
            y1 = uint64(yi1[o, j])
            z0 = uint64(zi0[o, m]) if ndim == 3 else uint64(0)
            z1 = uint64(zi1[o, m]) if ndim == 3 else uint64(0)
            cells = kspan[o] <= kmax  # the cell road: corners hashed once per cell
            # row tables: a row's corner hashes for every perm[x] (a lookup or two a sample
            # instead of two to fourteen chained ones), for rows long enough to repay their
            # 256 entries (measured; classic Perlin's 3D table of gradients never did)
            rowtab = not cells and not hashed and (
                nx > 128 if ndim == 2 or kind == k.IMPROVED else kind == k.VALUE and nx > 256)
            if rowtab and ndim == 2:
                _row_tables(kind, perm, vals, grad, y0, y1, th, tv, tg)
            elif rowtab:
                _row_tables3(kind, perm, vals, y0, y1, z0, z1, th, tv)
            if cells:  # the cell road: every cell of the row at once
                nc = cid[o, nx - 1] + 1
                ci = coct[o]
                if (key[o, 0] != y0 or key[o, 1] != y1 or key[o, 2] != z0
                        or key[o, 3] != z1):  # not the lattice rows of the last row: hash
                    _lat_hash(kind, ndim, 0, nc, cp0[o], cp1[o], perm, vals, grad, y0, y1, z0,
                              z1, hb, cv[ci], cg[ci])
                    if kind == k.IMPROVED:  # gradients from the hashes, as classic Perlin's
                        _grads16(ndim, nc, hb, cg[ci])
                    key[o, 0] = y0
                    key[o, 1] = y1
                    key[o, 2] = z0
                    key[o, 3] = z1
                _cell_coef(kind, ndim, nc, yf[o, j], yv[o, j], zf[o, m], zw[o, m], cv[ci], cg[ci],
                           cc)
                if o == 0 and mode == k.FBM:  # the first fBm octave: straight into the row
                    amp = amps[0]  # (a sample is linear in its cell's coefficients)
                    for e in range(4):
                        for c in range(nc):
                            cc[e, c] *= amp
                    if lanes:
                        _cell_eval16(0, nx, cid[o], xf[o], xu[o], cc, 0, row, 0)
                    else:
                        _cell_eval(kind, 0, nx, 0, cid[o], xf[o], xu[o], cc, 0, row)
                    continue
                for b in range(0, nx, BLOCK):
                    cnt = min(BLOCK, nx - b)
                    if lanes:
                        _cell_eval16(b, cnt, cid[o], xf[o], xu[o], cc, 0, nb, b)
                    else:
                        _cell_eval(kind, b, cnt, b, cid[o], xf[o], xu[o], cc, 0, nb)
                    _combine_block(mode, row, weight, b, cnt, nb, amps[o], gain, o == 0)
                continue
            for base in range(0, nx, BLOCK):  # the sample road: each block's samples hashed
                cnt = min(BLOCK, nx - base)
                if hashed and ndim == 3:  # in byte lanes; the corners' hashes: rows 2..9 of lb
                    _lat_hash_b(base, cnt, px0[o], px1[o], bt, lb, y0, y1, z0, z1)
                    _lat_eval_b3(base, cnt, xf[o], xu[o], yf[o, j], yv[o, j], zf[o, m], zw[o, m],
                                 lb, nb)
                    _combine_block(mode, row, weight, base, cnt, nb, amps[o], gain, o == 0)
                    continue
                if hashed:  # 2D in byte lanes, into hb's packed word
                    _lat_hash2_b(base, cnt, px0[o], px1[o], bt, lb, y0, y1, hb)
                elif rowtab and ndim == 2:
                    _lat_hash2(kind, base, cnt, px0[o], px1[o], th, tv, tg, hb, vb, gb)
                elif rowtab:
                    _lat_hash3(kind, base, cnt, px0[o], px1[o], th, tv, hb, vb)
                    if kind == k.IMPROVED:  # the corners packed in one word
                        _lat_eval_p3(base, cnt, xf[o], xu[o], yf[o, j], yv[o, j], zf[o, m],
                                     zw[o, m], hb, nb)
                        _combine_block(mode, row, weight, base, cnt, nb, amps[o], gain, o == 0)
                        continue
                else:
                    _lat_hash(kind, ndim, base, cnt, px0[o], px1[o], perm, vals, grad, y0, y1, z0,
                              z1, hb, vb, gb)
                _lat_eval(kind, ndim, base, cnt, xf[o], xu[o], yf[o, j], yv[o, j], zf[o, m],
                          zw[o, m], hb, vb, gb, nb)
                _combine_block(mode, row, weight, base, cnt, nb, amps[o], gain, o == 0)
        if jfix == -1:
            _finish(mode, row, norm)


@njit(**_OPTS)
def cell_octaves(xt, kcell):
    """The octaves of the x tables ``xt`` that go by cells (their 16-sample blocks span at
    most ``kcell`` cells): ``coct`` (each octave's ordinal among them, or -1), their count
    and the most cells a row of them has (at least 1)."""
    cid = xt[4]
    kspan = xt[7]
    no, nx = cid.shape
    coct = np.full(no, -1, np.int32)
    ncell = 1
    nco = 0
    for o in range(no):
        if kspan[o] <= kcell and nx > 0:
            coct[o] = nco
            nco += 1
            ncell = max(ncell, cid[o, nx - 1] + 1)
    return coct, nco, ncell


@njit(**_OPTS)
def row_work(xt, hashed):
    """Block buffers of :func:`row_lattice32` for the x tables ``xt`` (one set per work
    item: the cell road keeps each octave's cell corners, ``cv``/``cg``, for the next row
    in the same lattice rows, ``key`` their ``(y0, y1, z0, z1)``); ``hashed``: the
    AVX-512 roads of :mod:`._bytelanes` — improved noise hashes its samples in byte lanes
    (``lb``, and ``bt``: perm as bytes once the first row has filled it) and the cell
    road picks its cells' coefficients by permutes, down to :data:`KPERM`."""
    coct, nco, ncell = cell_octaves(xt, KPERM if hashed or _PERM8 else KMAX)
    no = coct.shape[0]
    nh = max(BLOCK, ncell)
    return (
        np.empty((8, nh), np.int32),
        np.empty((8, BLOCK), np.float32),
        np.empty((3, 8, BLOCK), np.float32),
        np.empty(BLOCK + LANES, np.float32),
        np.empty((2, 256), np.int32),
        np.empty((4, 256), np.float32),
        np.empty((2, 2, 256), np.float32),
        np.zeros((4, ncell + LANES), np.float32),  # read up to 15 past the cells
        np.empty((max(nco, 1), 8, ncell), np.float32),
        np.empty((max(nco, 1), 3, 8, ncell), np.float32),
        coct,
        np.full((no, 4), NOKEY, np.uint64),
        np.zeros((10, BLOCK), np.uint8),  # BLOCK: a multiple of the 64 byte lanes
        np.zeros(256, np.uint8),
        np.zeros(1, np.int32),
        hashed,
    )


@njit(parallel=True, **_OPTS)
def lattice_grid32(kind, mode, ndim, xt, yt, zt, out, amps, perm, vals, grad, norm, gain,
                   hashed):
    """Fill ``out`` (float32, shape (nz, ny, nx)) with 2D (``nz == 1``) or 3D value,
    classic Perlin or improved noise, every octave in one pass per row.

    ``xt = (px0, px1, xf, xu, cid, cp0, cp1, kspan)``: per octave and column ``perm[x0]``,
    ``perm[x1]`` (int32) and the fraction and curve weight (float32), then the cells along
    x (:func:`cell_tables`); ``yt``, ``zt = (i0, i1, f, c)`` the lattice indices,
    fractions and weights of the rows and slices (see :func:`._gridkernels.axis_tables`;
    :func:`lattice_tables32` makes all three).  ``amps`` already carry ``norm`` unless
    ``mode`` is ridged; ``grad``: classic Perlin's gradient table (float32, 256 x 4).  Each
    block of :data:`BLOCK` samples goes in passes: the table lookups (scalar: LLVM rates
    vector gathers too dear on some CPUs), then the arithmetic (SIMD); the rows in
    :data:`CHUNKS` work items.
    """
    nz, ny, nx = out.shape
    nrows = ny * nz
    nch = min(nrows, CHUNKS)
    for c in prange(nch):
        weight = np.empty(nx, np.float32)
        work = row_work(xt, hashed)
        _lat_rows(kind, mode, ndim, xt, yt, zt, out, c * nrows // nch, (c + 1) * nrows // nch,
                  np.int64(-1), np.int64(-1), weight, amps, perm, vals, grad, gain, work, norm)


def lattice_tables32(axis_tab, perm, is_x):
    """Float32 tables of one axis from :func:`._gridkernels.axis_tables`' ``(i0, i1, frac,
    curve)``: for the x axis ``perm`` is applied to the lattice indices up front, and the
    cell tables of :func:`cell_tables` follow."""
    i0, i1, fr, cu = axis_tab
    tabs = (
        np.ascontiguousarray(perm[i0] if is_x else i0, np.int32),
        np.ascontiguousarray(perm[i1] if is_x else i1, np.int32),
        np.ascontiguousarray(fr, np.float32),
        np.ascontiguousarray(cu, np.float32),
    )
    return tabs + cell_tables(i0, i1, tabs[0], tabs[1]) if is_x else tabs


@njit(cache=True, error_model="numpy")  # no fast-math: the float64 road's coordinates
def x_tables32(coords, freqs, offs, pers, interp, perm):
    """``lattice_tables32(axis_tables(coords, freqs, offs, pers, interp), perm, True)`` in
    one compiled pass (the same values: a grid's set-up spent ~70 µs in the NumPy passes
    of :func:`cell_tables` and the conversions, 5 % of a 1024² single-octave grid)."""
    no = freqs.shape[0]
    n = coords.shape[0]
    px0 = np.empty((no, n), np.int32)
    px1 = np.empty((no, n), np.int32)
    fr = np.empty((no, n), np.float32)
    cu = np.empty((no, n), np.float32)
    cid = np.empty((no, n), np.int32)
    cp0 = np.zeros((no, n), np.int32)
    cp1 = np.zeros((no, n), np.int32)
    kspan = np.ones(no, np.int32)
    for o in range(no):
        per = int(pers[o])
        c = -1
        a0 = -1
        a1 = -1
        for i in range(n):
            x = coords[i] * freqs[o] + offs[o]  # as :func:`._gridkernels.axis_tables`
            fx = k._floor(x)
            x -= fx
            b0 = k._wrap(fx, per)
            b1 = k._wrap(fx + 1, per)
            fr[o, i] = _F(x)
            cu[o, i] = _F(k._curve(x, interp))
            px0[o, i] = perm[b0]
            px1[o, i] = perm[b1]
            if i == 0 or b0 != a0 or b1 != a1:  # a new cell along the row
                c += 1
                cp0[o, c] = perm[b0]
                cp1[o, c] = perm[b1]
            a0 = b0
            a1 = b1
            cid[o, i] = c
        for s in range(0, n, LANES):
            kspan[o] = max(kspan[o], cid[o, min(s + LANES, n) - 1] - cid[o, s] + 1)
    return px0, px1, fr, cu, cid, cp0, cp1, kspan


def cell_tables(i0, i1, px0, px1):
    """The cells along x, per octave: ``cid`` (the column's cell ordinal, counting the
    changes of lattice cell along the row), ``cp0, cp1`` (each cell's ``perm[x0]``,
    ``perm[x1]``) and ``kspan`` (the most cells a :data:`LANES`-sample block spans)."""
    no, n = i0.shape
    cid = np.empty((no, n), np.int32)
    cp0 = np.zeros((no, n), np.int32)
    cp1 = np.zeros((no, n), np.int32)
    kspan = np.empty(no, np.int32)
    for o in range(no):
        new = np.ones(n, bool)
        new[1:] = (i0[o, 1:] != i0[o, :-1]) | (i1[o, 1:] != i1[o, :-1])
        c = np.cumsum(new) - 1
        cid[o] = c
        ne = int(c[-1]) + 1 if n else 0
        cp0[o, :ne] = px0[o][new]
        cp1[o, :ne] = px1[o][new]
        firsts = c[::LANES]
        lasts = c[np.minimum(np.arange(0, n, LANES) + LANES - 1, n - 1)]
        kspan[o] = int((lasts - firsts).max()) + 1 if n else 1
    return cid, cp0, cp1, kspan


def grid32(setup, ndim, axes, freqs, amps, offs, pers, mode, norm, gain, torus, full,
           out=None):
    """The float32 road of :func:`.noise.noise_grid` (its arguments as it computes them;
    ``full``: the grid's (nx, ny, nz, nw); ``out``: a float32 buffer of the grid's size that
    2D and 3D lattice and simplex noise fill instead of a new array), shape (nz, ny, nx)
    (4D Worley: (nw, nz, ny, nx)), or None where this module has no kernel
    (:mod:`._points32`'s road, or the float64 road, which then runs and rounds)."""
    lattice = setup.kind in (k.VALUE, k.PERLIN, k.IMPROVED)
    if ndim not in (2, 3) and not (ndim == 4 and (setup.kind == k.WORLEY or lattice)):
        if ndim != 4 or setup.kind != k.SIMPLEX or torus:
            return None
        from ._gridplan import SCALAR_WORK
        from ._simplex32 import grid4s, rows4s

        if _jit.cold(rows4s, math.prod(full), SCALAR_WORK):
            return None  # small work while the kernel is not compiled: the float64 road
        return grid4s(setup, axes, freqs, amps, offs, mode, norm, gain, full)
    if ndim == 4 and lattice:
        from ._gridplan import SCALAR_WORK
        from ._lattice4_32 import grid4, rows4

        if _jit.cold(rows4, math.prod(full), SCALAR_WORK):
            return None  # small work while the kernel is not compiled: the float64 road
        return grid4(setup, axes, freqs, amps, offs, pers, mode, norm, gain, full)
    shape3 = (full[2], full[1], full[0]) if ndim < 4 else (full[3], full[2], full[1], full[0])
    t = setup.tables
    a32 = (amps if mode == k.RIDGED else amps * norm).astype(np.float32)
    if setup.kind in (k.VALUE, k.PERLIN, k.IMPROVED):
        cols = [(np.ascontiguousarray(freqs[:, a]), np.ascontiguousarray(offs[:, a]),
                 np.ascontiguousarray(pers[:, a])) for a in range(ndim)]
        tabs = [x_tables32(axes[0], *cols[0], setup.interp, t.perm)] + [
            lattice_tables32(axis_tables(axes[a], *cols[a], setup.interp), t.perm, False)
            for a in range(1, ndim)
        ]
        out = np.empty(shape3, np.float32) if out is None else out.reshape(shape3)
        lattice_grid32(
            setup.kind,
            mode,
            ndim,
            tabs[0],
            tabs[1],
            tabs[-1],
            out,
            a32,
            t.perm,
            t.values.astype(np.float32),
            t.gradients[ndim - 2].astype(np.float32),
            np.float32(norm),
            np.float32(gain),
            _bl.USE,
        )
        return out
    if setup.kind == k.WORLEY:
        from ._worley32 import supported, worley_grid32

        wp = setup.wpar
        if not supported(wp):
            return None

        out = np.empty(shape3, np.float32)
        worley_grid32(ndim, mode, axes[0], axes[1], axes[2], axes[3], out, freqs, a32, offs,
                      pers, wp, np.float32(norm), np.float32(gain))
        return out
    if setup.kind == k.SIMPLEX and not torus:
        from ._simplex32 import simplex_grid32, simplex_table

        out = np.empty(shape3, np.float32) if out is None else out.reshape(shape3)
        f32 = np.float32
        simplex_grid32(
            ndim,
            mode,
            axes[0],
            axes[0].astype(f32),
            axes[1],
            axes[2],
            out,
            freqs,
            a32,
            offs,
            t.perm,
            simplex_table(t.seed, t.perm, t.perm12),
            f32(norm),
            f32(gain),
            _bl.USE,
        )
        return out
    return None


def warm() -> None:
    """Compile the float32 road's kernels (``sylva warmup``): every kind, 2D and 3D, plain
    and fractal, on tiny grids."""
    from .noise import noise_grid

    for kind in ("value", "perlin", "improved", "simplex", "worley"):
        for shape in ((4, 24), (2, 3, 24)):
            for fractal in ("fbm", "ridged"):
                noise_grid(shape, kind=kind, fractal=fractal, octaves=2, dtype=np.float32)
    for output in ("f1", "f2"):  # both Worley paths: runs of samples, and wide cells
        for scale in (4.0, 1.0):
            noise_grid((2, 24), kind="worley", output=output, scale=scale, dtype=np.float32)

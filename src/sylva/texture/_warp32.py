"""Domain-warped 2D grids by rows: the float32 road of :func:`sylva.texture.noise_grid`
with ``warp`` for 2D value, classic Perlin, improved Perlin and simplex noise (private).

A warped grid's sample is the grid's point moved by ``warp`` times two warp fields (fBm of
the same kind with other seeds; :mod:`._points32` makes them on the grid roads).  Its
lattice cell is then the sample's own, so the row passes of :mod:`._gridkernels32` (a
cell's corners hashed once for a run of samples) do not apply; nor do rows of points
(:mod:`._points32`, every corner's chained lookups scalar, about 28 ns a sample of 2D
improved noise on znver3).  Here each octave of a row goes in three passes per block:

1. *locate* (float64, SIMD): the warped point and octave coordinates as the float64 road
   computes them, their floors, float32 fractions, and the cell's flat address
   ``(i & 255) << 8 | (j & 255)`` (exact ``& 255`` beyond int32, :func:`._simplex32._low8`);
   2D simplex, which has no jump at its faces, locates in float32 (as its grid pass);
2. *gather* (scalar): one load a sample from a table of the cell's four corners, their
   chained lookups precomputed per seed (:func:`lattice2_table`: improved noise's four
   gradient indices in nibbles, value and classic noise's four corner hashes in bytes,
   then their lattice values or gradients; simplex: :func:`._simplex32.simplex_table`);
3. *blend* (float32, SIMD): the corner gradients by selects, the interpolation curve and
   the bilinear blend, or the simplex sum, and the octave's fBm, turbulence or ridged term.

Lattice periods (``tileable``) wrap a cell's far corner by the period, which the tables
do not: a tileable warped grid stays on rows of points.  Results differ from the float64
road by float32 rounding and the fields' float32 rounding times ``warp``: below
``_points32.TOLERANCE``; see ``tests/texture/test_points32.py``.
"""

from __future__ import annotations

import math

import numpy as np
from numba import njit, uint64

from . import _kernels as k
from ._gridkernels32 import (
    _F,
    _OPTS,
    _OPTS64,
    BLOCK,
    I4,
    I8,
    I12,
    ONE,
    ZERO,
    _combine_block,
    _finish,
    _g16_2,
    _i32,
    _lerp,
)
from ._simplex32 import (
    _BIG,
    _N255,
    _gather,
    _low8,
    _s2_cell,
    _s2_eval,
    simplex_table,
    simplex_work,
)

_SIX, _FIFTEEN, _TEN, _THREE, _TWO, _HALF = (_F(v) for v in (6.0, 15.0, 10.0, 3.0, 2.0, 0.5))
_PI = _F(math.pi)
# sin(a) = a (1 + a^2 (S3 + a^2 (S5 + ...))) on |a| <= pi / 2: below 6e-8 off (a^13 / 13!)
_S3, _S5, _S7, _S9, _S11 = (_F((-1) ** n / math.factorial(2 * n + 1)) for n in range(1, 6))
#: the noise kinds of this road
KINDS = (k.VALUE, k.PERLIN, k.IMPROVED, k.SIMPLEX)


@njit(**_OPTS)
def _curves(interp, cnt, bx, by, cu, cv):
    """The interpolation weights of the fractions ``bx, by`` into ``cu, cv`` (float32; as
    :func:`._kernels._curve`): one loop per curve (with the choice inside the loop LLVM
    kept the loop scalar, ~11 ns a sample), the cosine by a polynomial (SIMD; ``cosf``
    was a scalar call, 7 ns a sample)."""
    for src, dst in ((bx, cu), (by, cv)):
        if interp == 3:
            for q in range(cnt):
                t = src[q]
                dst[q] = t * t * t * (t * (t * _SIX - _FIFTEEN) + _TEN)
        elif interp == 2:
            for q in range(cnt):
                t = src[q]
                dst[q] = t * t * (_THREE - _TWO * t)
        elif interp == 1:  # (1 - cos(pi t)) / 2 = (1 + sin(pi (t - 1/2))) / 2, Taylor to s^11
            for q in range(cnt):
                a = _PI * (src[q] - _HALF)
                a2 = a * a
                p = _S11
                p = p * a2 + _S9
                p = p * a2 + _S7
                p = p * a2 + _S5
                p = p * a2 + _S3
                p = p * a2 + ONE
                dst[q] = _HALF + _HALF * (a * p)
        else:
            for q in range(cnt):
                dst[q] = src[q]


@njit(**_OPTS)
def _absmax(a, b):
    """``max(|a|, |b|)`` over two float32 rows (SIMD: fast-math lets LLVM split the max)."""
    m = ZERO
    for i in range(a.shape[0]):
        m = max(m, max(abs(a[i]), abs(b[i])))
    return m


# -- locate ---------------------------------------------------------------------------------
@njit(**_OPTS64)  # no fast-math: the float64 road's warped points and octave coordinates
def _warp_octave(xs, y, d0, d1, base, cnt, warp, fx, ox, fy, oy, cx, cy):
    """2D simplex: the octave coordinates (float32) of samples ``base .. base + cnt`` of a
    row at ``y``: the point ``(xs[i] + warp d0[i], y + warp d1[i])`` (float64, as the
    float64 road moves it) times the octave's frequency plus its offset."""
    b0 = uint64(base)
    for q in range(cnt):
        i = b0 + uint64(q)
        cx[q] = (xs[i] + warp * np.float64(d0[i])) * fx + ox
        cy[q] = (y + warp * np.float64(d1[i])) * fy + oy


@njit(**_OPTS)
def _s2_locate_xy(cx, cy, cnt, bx, by, ba):
    """:func:`._simplex32._s2_locate` at points of their own y."""
    for q in range(cnt):
        x0, y0, fi, fj = _s2_cell(cx[q], cy[q])
        bx[q] = x0
        by[q] = y0
        ba[q] = _i32(_i32(_i32(np.int32(fi) & _N255) << I8) | _i32(np.int32(fj) & _N255))


@njit(**_OPTS64)  # no fast-math: the float64 road's warped points, floors and fractions
def _lat_locate(xs, y, d0, d1, base, cnt, warp, fx, ox, fy, oy, big, bx, by, ba):
    """Lattice noise: the warped points' octave coordinates in float64, their fractions
    (float32) into ``bx, by`` and the cell's table address into ``ba``."""
    b0 = uint64(base)
    for q in range(cnt):
        i = b0 + uint64(q)
        cx = (xs[i] + warp * np.float64(d0[i])) * fx + ox
        cy = (y + warp * np.float64(d1[i])) * fy + oy
        gx = np.floor(cx)
        gy = np.floor(cy)
        bx[q] = _F(cx - gx)
        by[q] = _F(cy - gy)
        ba[q] = _i32(_i32(_low8(gx, big) << I8) | _low8(gy, big))


# -- gather ---------------------------------------------------------------------------------
@njit(**_OPTS)
def _lat_gather(kind, cnt, tab, ba, vals, grad, vb, gb):
    """Value noise: the four corners' lattice values into ``vb``; classic Perlin noise:
    their gradients into ``gb`` (one table word a sample, read as two uint16 halves: one
    table type for every kind, one compile; then the values or gradients)."""
    if kind == k.VALUE:
        for q in range(cnt):
            a = uint64(ba[q]) << uint64(1)
            w = uint64(tab[a]) | (uint64(tab[a + uint64(1)]) << uint64(16))
            vb[0, q] = vals[w & uint64(255)]
            vb[1, q] = vals[(w >> uint64(8)) & uint64(255)]
            vb[2, q] = vals[(w >> uint64(16)) & uint64(255)]
            vb[3, q] = vals[w >> uint64(24)]
    else:
        for q in range(cnt):
            a = uint64(ba[q]) << uint64(1)
            w = uint64(tab[a]) | (uint64(tab[a + uint64(1)]) << uint64(16))
            for c in range(4):
                h = (w >> uint64(8 * c)) & uint64(255)
                gb[0, c, q] = grad[h, 0]
                gb[1, c, q] = grad[h, 1]


# -- blend ----------------------------------------------------------------------------------
@njit(**_OPTS)
def _lat_eval(kind, cnt, bx, by, cu, cv, bw, vb, gb, nb, ob, amp):
    """SIMD pass: the bilinear blend of the corners (improved noise: gradients by selects
    from the packed word ``bw``; value noise: ``vb``; classic Perlin noise: ``gb``) by the
    weights ``cu, cv``, times ``amp`` into ``nb[ob:]``."""
    if kind == k.IMPROVED:
        for q in range(cnt):
            x = bx[q]
            y = by[q]
            h = bw[q]
            u = cu[q]
            v = cv[q]
            x_1 = x - ONE
            y_1 = y - ONE
            n = _lerp(
                v,
                _lerp(u, _g16_2(h, x, y), _g16_2(_i32(h >> I4), x_1, y)),
                _lerp(u, _g16_2(_i32(h >> I8), x, y_1), _g16_2(_i32(h >> I12), x_1, y_1)),
            )
            nb[ob + uint64(q)] = amp * n
    elif kind == k.VALUE:
        for q in range(cnt):
            u = cu[q]
            v = cv[q]
            n = _lerp(v, _lerp(u, vb[0, q], vb[1, q]), _lerp(u, vb[2, q], vb[3, q]))
            nb[ob + uint64(q)] = amp * n
    else:
        for q in range(cnt):
            x = bx[q]
            y = by[q]
            u = cu[q]
            v = cv[q]
            x_1 = x - ONE
            y_1 = y - ONE
            n00 = gb[0, 0, q] * x + gb[1, 0, q] * y
            n10 = gb[0, 1, q] * x_1 + gb[1, 1, q] * y
            n01 = gb[0, 2, q] * x + gb[1, 2, q] * y_1
            n11 = gb[0, 3, q] * x_1 + gb[1, 3, q] * y_1
            nb[ob + uint64(q)] = amp * _lerp(v, _lerp(u, n00, n10), _lerp(u, n01, n11))


# -- rows -----------------------------------------------------------------------------------
@njit(nogil=True, **_OPTS64)  # no fast-math: the warped points in float64
def warp_rows2(r0, r1, kind, mode, interp, xs, ys, d0, d1, warp, out, freqs, amps, offs, perm,
               tab, vals, grad, norm, gain):
    """Rows ``r0 .. r1`` of ``out`` (float32, shape (ny, nx)) of 2D noise of ``kind`` at
    the grid's points warped by the fields ``d0, d1`` (float32, shape (ny, nx)), every
    octave summed into the row (``amps`` carry ``norm`` unless ``mode`` is ridged;
    ``tab``: :func:`lattice2_table`, or for simplex noise
    :func:`._simplex32.simplex_table`)."""
    bx, by, bz, nb, ba, bw, pk, bb, bt, hashed = simplex_work(perm, False)
    cx = np.empty(BLOCK, np.float32)
    cy = np.empty(BLOCK, np.float32)
    vb = np.empty((4, BLOCK), np.float32)
    gb = np.empty((2, 4, BLOCK), np.float32)
    nx = out.shape[1]
    weight = np.empty(nx, np.float32)
    xm = 0.0
    for i in range(nx):
        xm = max(xm, abs(xs[i]))
    for j in range(r0, r1):
        row = out[j]
        e0 = d0[j]
        e1 = d1[j]
        # how far the warped points may reach: beyond int32 the floors take the exact & 255
        reach = abs(warp) * np.float64(_absmax(e0, e1))
        for o in range(freqs.shape[0]):
            fx, ox, fy, oy = freqs[o, 0], offs[o, 0], freqs[o, 1], offs[o, 1]
            big = ((xm + reach) * abs(fx) + abs(ox) >= _BIG
                   or (abs(ys[j]) + reach) * abs(fy) + abs(oy) >= _BIG)
            direct = o == 0 and mode == k.FBM
            amp = amps[o] if direct else ONE
            for base in range(0, nx, BLOCK):
                cnt = min(BLOCK, nx - base)
                dst = row if direct else nb
                ob = uint64(base) if direct else uint64(0)
                if kind == k.SIMPLEX:
                    _warp_octave(xs, ys[j], e0, e1, base, cnt, warp, fx, ox, fy, oy, cx, cy)
                    _s2_locate_xy(cx, cy, cnt, bx, by, ba)
                    _gather(cnt, tab, ba, bw)
                    _s2_eval(cnt, bx, by, bw, dst, ob, amp)
                else:
                    _lat_locate(xs, ys[j], e0, e1, base, cnt, warp, fx, ox, fy, oy, big, bx,
                                by, ba)
                    if kind == k.IMPROVED:
                        _gather(cnt, tab, ba, bw)
                    else:
                        _lat_gather(kind, cnt, tab, ba, vals, grad, vb, gb)
                    _curves(interp, cnt, bx, by, cx, cy)
                    _lat_eval(kind, cnt, bx, by, cx, cy, bw, vb, gb, dst, ob, amp)
                if not direct:
                    _combine_block(mode, row, weight, base, cnt, nb, amps[o], gain, o == 0)
        _finish(mode, row, norm)


def lattice2_table(kind, seed, perm):
    """The four corners of every 2D lattice cell, their chained lookups precomputed (cached
    per seed): ``tab[i * 256 + j]`` (i, j in 0..255) holds corner ``(i + di, j + dj)`` in
    field ``c = di + 2 dj``: improved noise's gradient index ``perm[perm[perm[i + di] + j +
    dj]] & 15`` in nibble c (uint16, 128 KB; the float64 road's chain with z = 0), value and
    classic noise's hash ``perm[perm[i + di] + j + dj]`` in byte c (uint32, 256 KB, as
    uint16 halves, low first: the kernel's one table type).  The
    permutation is doubled, so ``perm[(i + 1) & 255] = perm[i + 1]`` and the far corners
    need no wrap."""
    key = (kind == k.IMPROVED, seed)
    tab = _TABS.get(key)
    if tab is None:
        r = np.arange(257)
        h = perm[perm[r][:, None] + r[None, :]].astype(np.int64)  # h[i, j], i, j in 0..256
        if kind == k.IMPROVED:
            h = perm[h] & 15
            sh, dt = 4, np.uint16
        else:
            sh, dt = 8, np.uint32
        tab = (h[:-1, :-1] | (h[1:, :-1] << sh) | (h[:-1, 1:] << (2 * sh))
               | (h[1:, 1:] << (3 * sh)))
        tab = np.ascontiguousarray(tab.astype(dt).reshape(-1)).view(np.uint16)
        if len(_TABS) > 16:
            _TABS.clear()
        _TABS[key] = tab
    return tab


_TABS: dict = {}


def warp_grid2(setup, axes, fields, warp, freqs, amps, offs, mode, norm, gain):
    """The float32 2D grid (shape (ny, nx)) of ``setup``'s noise at the grid's points
    warped by ``warp`` times ``fields`` (two float32 arrays of the grid's shape)."""
    from ._gridplan import run_blocks

    t = setup.tables
    kind = setup.kind
    a32 = (amps if mode == k.RIDGED else amps * norm).astype(np.float32)
    ny, nx = len(axes[1]), len(axes[0])
    out = np.empty((ny, nx), np.float32)
    d0, d1 = (np.ascontiguousarray(f, np.float32).reshape(ny, nx) for f in fields)
    if kind == k.SIMPLEX:
        tab = simplex_table(t.seed, t.perm, t.perm12)
    else:
        tab = lattice2_table(kind, t.seed, t.perm)
    run_blocks(warp_rows2, ny,
               (kind, mode, setup.interp, np.ascontiguousarray(axes[0], np.float64),
                np.ascontiguousarray(axes[1], np.float64), d0, d1, float(warp), out,
                np.ascontiguousarray(freqs), a32, np.ascontiguousarray(offs), t.perm, tab,
                t.values.astype(np.float32),
                np.ascontiguousarray(t.gradients[0], np.float32), np.float32(norm),
                np.float32(gain)))
    return out

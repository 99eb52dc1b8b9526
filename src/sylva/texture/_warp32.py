"""Domain-warped 2D and 3D grids by rows: the float32 road of
:func:`sylva.texture.noise_grid` with ``warp`` for 2D and 3D value, classic Perlin,
improved Perlin and simplex noise (private).

A warped grid's sample is the grid's point moved by ``warp`` times a warp field per axis (fBm of
the same kind with other seeds; :mod:`._points32` makes them on the grid roads).  Its
lattice cell is then the sample's own, so the row passes of :mod:`._gridkernels32` (a
cell's corners hashed once for a run of samples) do not apply; nor do rows of points
(:mod:`._points32`, every corner's chained lookups scalar, about 28 ns a sample of 2D
improved noise on znver3).  Here each octave of a row goes in three passes per block:

1. *locate* (float64, SIMD): the warped point and octave coordinates as the float64 road
   computes them, their floors, float32 fractions, and the cell's flat address
   ``(i & 255) << 8 | (j & 255)`` (exact ``& 255`` beyond int32, :func:`._simplex32._low8`);
   2D simplex, which has no jump at its faces, locates in float32 (as its grid pass) but
   far from the origin (:func:`._simplex32._s2_near`), and so do the lattice noises, whose
   value is continuous at cell faces (:func:`_lat_near`); 3D simplex in float64;
2. *gather* (scalar): one load a sample from a table of the cell's four (x, y) corners,
   their chained lookups precomputed per seed (:func:`lattice2_table`: 2D improved noise's
   four gradient indices in nibbles, value and classic noise's four corner hashes in bytes,
   then their lattice values or gradients; in 3D the hashes, then the eight corners'
   ``perm[h + k + dk]``, both ``dk`` of a corner in one row of a table by ``h + k``,
   :func:`_z_pairs`; simplex: :func:`._simplex32.simplex_table`, its 3D gather);
3. *blend* (float32, SIMD): the corner gradients by selects, the interpolation curve and
   the bi- or trilinear blend, or the simplex sum, and the octave's fBm, turbulence or
   ridged term.

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
    _imp3,
    _lerp,
)
from ._simplex32 import (
    _BIG,
    _N255,
    _diffs3,
    _gather,
    _low8,
    _s2_cell,
    _s2_cell64,
    _s2_eval,
    _s2_near,
    _s3_cell64,
    _s3_eval,
    _s3_gather,
    simplex_table,
    simplex_work,
)

_SIX, _FIFTEEN, _TEN, _THREE, _TWO, _HALF = (_F(v) for v in (6.0, 15.0, 10.0, 3.0, 2.0, 0.5))
_PI = _F(math.pi)
_C16, _C20, _C24, _C28 = (np.int32(v) for v in (16, 20, 24, 28))
# sin(a) = a (1 + a^2 (S3 + a^2 (S5 + ...))) on |a| <= pi / 2: below 6e-8 off (a^13 / 13!)
_S3, _S5, _S7, _S9, _S11 = (_F((-1) ** n / math.factorial(2 * n + 1)) for n in range(1, 6))
#: the noise kinds of this road
KINDS = (k.VALUE, k.PERLIN, k.IMPROVED, k.SIMPLEX)


@njit(**_OPTS)
def _curves(interp, cnt, bx, by, cu, cv):
    """:func:`_curve_pairs` of two axes."""
    _curve_pairs(interp, cnt, ((bx, cu), (by, cv)))


@njit(**_OPTS)
def _curves3(interp, cnt, bx, by, bz, cu, cv, cw):
    """:func:`_curve_pairs` of three axes."""
    _curve_pairs(interp, cnt, ((bx, cu), (by, cv), (bz, cw)))


@njit(inline="always", **_OPTS)
def _curve_pairs(interp, cnt, pairs):
    """The interpolation weights (float32, as :func:`._kernels._curve`) of the fractions
    ``src`` into ``dst``, for each ``(src, dst)`` of ``pairs``: one loop per curve (with
    the choice inside the loop LLVM kept the loop scalar, ~11 ns a sample), the cosine by
    a polynomial (SIMD; ``cosf`` was a scalar call, 7 ns a sample)."""
    for src, dst in pairs:
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


@njit(**_OPTS64)  # no fast-math: as :func:`_lat_locate`
def _lat_locate3(xs, y, z, d0, d1, d2, base, cnt, warp, f, o, big, bx, by, bz, ba, bk):
    """:func:`_lat_locate` in 3D (``f``, ``o``: the octave's frequencies and offsets):
    the cell's ``i, j`` table address into ``ba``, its ``k & 255`` into ``bk``."""
    b0 = uint64(base)
    for q in range(cnt):
        i = b0 + uint64(q)
        cx = (xs[i] + warp * np.float64(d0[i])) * f[0] + o[0]
        cy = (y + warp * np.float64(d1[i])) * f[1] + o[1]
        cz = (z + warp * np.float64(d2[i])) * f[2] + o[2]
        gx = np.floor(cx)
        gy = np.floor(cy)
        gz = np.floor(cz)
        bx[q] = _F(cx - gx)
        by[q] = _F(cy - gy)
        bz[q] = _F(cz - gz)
        ba[q] = _i32(_i32(_low8(gx, big) << I8) | _low8(gy, big))
        bk[q] = _low8(gz, big)


#: the budget of sum(amplitude x coordinate magnitude in cells) over a row's octaves up to
#: which warped lattice noise locates in float32 (:func:`_lat_near`)
_LAT_REACH = 128.0


@njit(inline="always", cache=True, error_model="numpy")
def _lat_near(spent, amp, cmax):
    """:func:`._simplex32._s2_near` for warped lattice noise, whose value is continuous
    across cell faces (a float32 floor that differs from the float64 one at a face moves
    the value by rounding only): within :data:`_LAT_REACH` an octave's warped points,
    floors and fractions go in float32 (:func:`_lat_locate32`), rounding a coordinate by
    ~3e-7 of its magnitude, beyond it in float64."""
    cost = abs(amp) * cmax
    if spent + cost <= _LAT_REACH:
        return True, spent + cost
    return False, spent


@njit(inline="always", **_OPTS)
def _lat_cell32(c, fr, q):
    """The floor of float32 coordinate ``c`` (its ``& 255``) and its fraction into ``fr``."""
    g = np.floor(c)
    fr[q] = c - g
    return _i32(np.int32(g) & _N255)


@njit(**_OPTS)
def _lat_locate32(xs32, y, d0, d1, base, cnt, warp, fx, ox, fy, oy, bx, by, ba):
    """:func:`_lat_locate` in float32 lanes near the origin (:func:`_lat_near`)."""
    b0 = uint64(base)
    for q in range(cnt):
        i = b0 + uint64(q)
        gx = _lat_cell32((xs32[i] + warp * d0[i]) * fx + ox, bx, q)
        gy = _lat_cell32((y + warp * d1[i]) * fy + oy, by, q)
        ba[q] = _i32(_i32(gx << I8) | gy)


@njit(**_OPTS)
def _lat_locate3_32(xs32, y, z, d0, d1, d2, base, cnt, warp, fx, fy, fz, ox, oy, oz, bx, by,
                    bz, ba, bk):
    """:func:`_lat_locate3` in float32 lanes near the origin (:func:`_lat_near`)."""
    b0 = uint64(base)
    for q in range(cnt):
        i = b0 + uint64(q)
        gx = _lat_cell32((xs32[i] + warp * d0[i]) * fx + ox, bx, q)
        gy = _lat_cell32((y + warp * d1[i]) * fy + oy, by, q)
        bk[q] = _lat_cell32((z + warp * d2[i]) * fz + oz, bz, q)
        ba[q] = _i32(_i32(gx << I8) | gy)


@njit(**_OPTS64)  # no fast-math: the float64 road's simplex (its kernel jumps at faces)
def _s3_locate_w(xs, y, z, d0, d1, d2, base, cnt, warp, f, o, big, bx, by, bz, ba, bd):
    """3D simplex: the warped points' octave coordinates and Gustavson's cell and
    comparisons in float64, packed as :func:`._simplex32._s3_locate` packs them."""
    b0 = uint64(base)
    for q in range(cnt):
        i = b0 + uint64(q)
        cx = (xs[i] + warp * np.float64(d0[i])) * f[0] + o[0]
        cy = (y + warp * np.float64(d1[i])) * f[1] + o[1]
        cz = (z + warp * np.float64(d2[i])) * f[2] + o[2]
        x0, y0, z0, ca, cb, cc, fi, fj, fk = _s3_cell64(cx, cy, cz)
        _diffs3(q, x0, y0, z0, bx, by, bz, bd)
        ba[q] = (_low8(fi, big) << I8) | _low8(fj, big) | (_low8(fk, big) << np.int32(16))


@njit(**_OPTS64)  # no fast-math: the float64 road's warped points
def _s2_locate_w64(xs, y, d0, d1, base, cnt, warp, fx, ox, fy, oy, big, bx, by, ba):
    """2D simplex far from the origin: :func:`_s2_locate_xy` from the warped points'
    float64 octave coordinates (float32 would round them by more than the tolerance,
    :func:`._simplex32._s2_near`)."""
    b0 = uint64(base)
    for q in range(cnt):
        i = b0 + uint64(q)
        x0, y0, fi, fj = _s2_cell64((xs[i] + warp * np.float64(d0[i])) * fx + ox,
                                    (y + warp * np.float64(d1[i])) * fy + oy)
        bx[q] = x0
        by[q] = y0
        ba[q] = _i32(_i32(_low8(fi, big) << I8) | _low8(fj, big))


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


@njit(**_OPTS)
def _lat_gather3(kind, cnt, tab, pz, vz, gz, ba, bk, hb, vb, gb):
    """3D: the four ``(i, j)`` corner hashes from the table word (``tab``, uint32), then
    the eight corners' ``perm[h + k + dk]`` (the float64 road's chain), both ``dk`` of a
    corner from one row of the tables of :func:`_z_pairs`: improved noise's gradient
    indices packed in one word (corner ``c = di + 2 dj + 4 dk`` in bits ``4c``; five loads
    a sample instead of ten, twice as fast), value noise's lattice values into ``vb``,
    classic Perlin noise's gradients into ``gb``."""
    if kind == k.IMPROVED:
        for q in range(cnt):
            w = uint64(tab[uint64(ba[q])])
            z0 = uint64(bk[q])
            m = uint64(0)
            for c in range(4):
                m |= uint64(pz[((w >> uint64(8 * c)) & uint64(255)) + z0]) << uint64(4 * c)
            hb[q] = np.int32(np.int64(m) - ((np.int64(m) >> 31) << 32))
    elif kind == k.VALUE:
        for q in range(cnt):
            w = uint64(tab[uint64(ba[q])])
            z0 = uint64(bk[q])
            for c in range(4):
                h = ((w >> uint64(8 * c)) & uint64(255)) + z0
                vb[c, q] = vz[h, 0]
                vb[c + 4, q] = vz[h, 1]
    else:
        for q in range(cnt):
            w = uint64(tab[uint64(ba[q])])
            z0 = uint64(bk[q])
            for c in range(4):
                h = ((w >> uint64(8 * c)) & uint64(255)) + z0
                for a in range(3):
                    gb[a, c, q] = gz[h, a]
                    gb[a, c + 4, q] = gz[h, a + 3]


@njit(**_OPTS)
def _z_pairs(perm, vals, grad):
    """The tables of a corner hash ``h`` at a cell's two z planes, by ``m = h + k`` (h, k in
    0..255; the permutation is doubled): ``pz[m] = (perm[m] & 15) | (perm[m + 1] & 15) <<
    16`` (improved noise's gradient indices, in the halves where :func:`_lat_gather3`
    packs corners ``c`` and ``c + 4``), ``vz[m] = vals[perm[m]], vals[perm[m + 1]]`` and
    ``gz[m]`` the two gradients ``grad[perm[m]], grad[perm[m + 1]]`` (classic Perlin)."""
    pz = np.empty(512, np.int32)
    vz = np.empty((512, 2), np.float32)
    gz = np.zeros((512, 6), np.float32)
    na = min(3, grad.shape[1])  # 2D: two components (not read)
    for m in range(512):
        g0 = perm[m]
        g1 = perm[(m + 1) & 511]
        pz[m] = np.int32((g0 & 15) | ((g1 & 15) << 16))
        vz[m, 0] = vals[g0]
        vz[m, 1] = vals[g1]
        for a in range(na):
            gz[m, a] = grad[g0, a]
            gz[m, a + 3] = grad[g1, a]
    return pz, vz, gz


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


@njit(**_OPTS)
def _lat_eval3(kind, cnt, bx, by, bz, cu, cv, cw, hb, vb, gb, nb, ob, amp):
    """:func:`_lat_eval` in 3D (trilinear; corner ``c``: x1 if ``c & 1``, y1 if ``c & 2``,
    z1 if ``c & 4``)."""
    if kind == k.IMPROVED:
        for q in range(cnt):
            h = hb[q]
            n = _imp3(h, _i32(h >> I4), _i32(h >> I8), _i32(h >> I12), _i32(h >> _C16),
                      _i32(h >> _C20), _i32(h >> _C24), _i32(h >> _C28), bx[q], by[q], bz[q],
                      cu[q], cv[q], cw[q])
            nb[ob + uint64(q)] = amp * n
    elif kind == k.VALUE:
        for q in range(cnt):
            u = cu[q]
            v = cv[q]
            n = _lerp(cw[q],
                      _lerp(v, _lerp(u, vb[0, q], vb[1, q]), _lerp(u, vb[2, q], vb[3, q])),
                      _lerp(v, _lerp(u, vb[4, q], vb[5, q]), _lerp(u, vb[6, q], vb[7, q])))
            nb[ob + uint64(q)] = amp * n
    else:
        for q in range(cnt):
            x = bx[q]
            y = by[q]
            z = bz[q]
            u = cu[q]
            v = cv[q]
            x_1 = x - ONE
            y_1 = y - ONE
            z_1 = z - ONE
            n0 = gb[0, 0, q] * x + gb[1, 0, q] * y + gb[2, 0, q] * z
            n1 = gb[0, 1, q] * x_1 + gb[1, 1, q] * y + gb[2, 1, q] * z
            n2 = gb[0, 2, q] * x + gb[1, 2, q] * y_1 + gb[2, 2, q] * z
            n3 = gb[0, 3, q] * x_1 + gb[1, 3, q] * y_1 + gb[2, 3, q] * z
            n4 = gb[0, 4, q] * x + gb[1, 4, q] * y + gb[2, 4, q] * z_1
            n5 = gb[0, 5, q] * x_1 + gb[1, 5, q] * y + gb[2, 5, q] * z_1
            n6 = gb[0, 6, q] * x + gb[1, 6, q] * y_1 + gb[2, 6, q] * z_1
            n7 = gb[0, 7, q] * x_1 + gb[1, 7, q] * y_1 + gb[2, 7, q] * z_1
            n = _lerp(cw[q], _lerp(v, _lerp(u, n0, n1), _lerp(u, n2, n3)),
                      _lerp(v, _lerp(u, n4, n5), _lerp(u, n6, n7)))
            nb[ob + uint64(q)] = amp * n


# -- rows -----------------------------------------------------------------------------------
@njit(nogil=True, **_OPTS64)  # no fast-math: the warped points in float64
def warp_rows(r0, r1, ndim, kind, mode, interp, xs, ys, zs, d0, d1, d2, warp, out, freqs,
              amps, offs, perm, tab, vals, grad, norm, gain):
    """Rows ``r0 .. r1`` (row ``r``: slice ``r // ny``, row ``r % ny``) of ``out``
    (float32, shape (nz, ny, nx); 2D: nz = 1) of 2D or 3D noise of ``kind`` at the grid's
    points warped by the fields ``d0, d1, d2`` (float32, ``out``'s shape; 2D: ``d2``
    unused), every octave summed into the row (``amps`` carry ``norm`` unless ``mode`` is
    ridged; ``tab``: :func:`lattice2_table`, or for simplex noise
    :func:`._simplex32.simplex_table`)."""
    bx, by, bz, nb, ba, bw, pk, bb, bt, hashed, bd = simplex_work(perm, False)
    cx = np.empty(BLOCK, np.float32)
    cy = np.empty(BLOCK, np.float32)
    cz = np.empty(BLOCK, np.float32)
    bk = np.empty(BLOCK, np.int32)
    vb = np.empty((8, BLOCK), np.float32)
    gb = np.empty((3, 8, BLOCK), np.float32)
    pz, vz, gz = _z_pairs(perm, vals, grad)
    tab32 = tab.view(np.uint32)
    ny, nx = out.shape[1], out.shape[2]
    weight = np.empty(nx, np.float32)
    xm = 0.0
    for i in range(nx):
        xm = max(xm, abs(xs[i]))
    xs32 = xs.astype(np.float32)
    w32 = _F(warp)
    for r in range(r0, r1):
        m = r // ny
        j = r % ny
        row = out[m, j]
        e0 = d0[m, j]
        e1 = d1[m, j]
        e2 = d2[m, j] if ndim == 3 else e1
        # how far the warped points may reach: beyond int32 the floors take the exact & 255
        reach = abs(warp) * np.float64(max(_absmax(e0, e1), _absmax(e2, e2)))
        spent = 0.0  # of the 2D simplex float32 locate's budget (_s2_near)
        spent_l = 0.0  # of the lattice noises' (_lat_near)
        for o in range(freqs.shape[0]):
            f = freqs[o]
            of = offs[o]
            cx_ = (xm + reach) * abs(f[0]) + abs(of[0])  # the largest coordinates
            cy_ = (abs(ys[j]) + reach) * abs(f[1]) + abs(of[1])
            cz_ = (abs(zs[m]) + reach) * abs(f[2]) + abs(of[2]) if ndim == 3 else 0.0
            big = not max(cx_, cy_, cz_) < _BIG
            near, spent = _s2_near(spent, amps[o], max(cx_, cy_))
            near_l, spent_l = _lat_near(spent_l, amps[o], max(cx_, cy_, cz_))
            f32 = (_F(f[0]), _F(f[1]), _F(f[2]))
            o32 = (_F(of[0]), _F(of[1]), _F(of[2]))
            direct = o == 0 and mode == k.FBM
            amp = amps[o] if direct else ONE
            for base in range(0, nx, BLOCK):
                cnt = min(BLOCK, nx - base)
                dst = row if direct else nb
                ob = uint64(base) if direct else uint64(0)
                if ndim == 3 and kind == k.SIMPLEX:
                    _s3_locate_w(xs, ys[j], zs[m], e0, e1, e2, base, cnt, warp, f, of, big, bx,
                                 by, bz, ba, bd)
                    _s3_gather(cnt, tab, pk, ba, bw)
                    _s3_eval(cnt, bx, by, bz, bd, bw, dst, ob, amp)
                elif ndim == 3:
                    if near_l:
                        _lat_locate3_32(xs32, _F(ys[j]), _F(zs[m]), e0, e1, e2, base, cnt, w32,
                                        f32[0], f32[1], f32[2], o32[0], o32[1], o32[2], bx, by,
                                        bz, ba, bk)
                    else:
                        _lat_locate3(xs, ys[j], zs[m], e0, e1, e2, base, cnt, warp, f, of, big,
                                     bx, by, bz, ba, bk)
                    _lat_gather3(kind, cnt, tab32, pz, vz, gz, ba, bk, bw, vb, gb)
                    _curves3(interp, cnt, bx, by, bz, cx, cy, cz)
                    _lat_eval3(kind, cnt, bx, by, bz, cx, cy, cz, bw, vb, gb, dst, ob, amp)
                elif kind == k.SIMPLEX:
                    if near:
                        _warp_octave(xs, ys[j], e0, e1, base, cnt, warp, f[0], of[0], f[1],
                                     of[1], cx, cy)
                        _s2_locate_xy(cx, cy, cnt, bx, by, ba)
                    else:
                        _s2_locate_w64(xs, ys[j], e0, e1, base, cnt, warp, f[0], of[0], f[1],
                                       of[1], big, bx, by, ba)
                    _gather(cnt, tab, ba, bw)
                    _s2_eval(cnt, bx, by, bw, dst, ob, amp)
                else:
                    if near_l:
                        _lat_locate32(xs32, _F(ys[j]), e0, e1, base, cnt, w32, f32[0], o32[0],
                                      f32[1], o32[1], bx, by, ba)
                    else:
                        _lat_locate(xs, ys[j], e0, e1, base, cnt, warp, f[0], of[0], f[1],
                                    of[1], big, bx, by, ba)
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


def warp_grid(setup, axes, fields, warp, freqs, amps, offs, mode, norm, gain):
    """The float32 2D or 3D grid (shape (ny, nx) or (nz, ny, nx), by ``len(fields)``) of
    ``setup``'s noise at the grid's points warped by ``warp`` times ``fields`` (float32
    arrays of the grid's shape, one per axis)."""
    from ._gridplan import run_blocks

    t = setup.tables
    kind = setup.kind
    ndim = len(fields)
    a32 = (amps if mode == k.RIDGED else amps * norm).astype(np.float32)
    nz = len(axes[2]) if ndim == 3 else 1
    ny, nx = len(axes[1]), len(axes[0])
    out = np.empty((nz, ny, nx), np.float32)
    d = [np.ascontiguousarray(f, np.float32).reshape(nz, ny, nx) for f in fields]
    if kind == k.SIMPLEX:
        tab = simplex_table(t.seed, t.perm, t.perm12)
    else:  # 3D: the (i, j) corner hashes for every kind
        tab = lattice2_table(kind if ndim == 2 else k.VALUE, t.seed, t.perm)
    zs = axes[2] if ndim == 3 else np.zeros(1)
    run_blocks(warp_rows, nz * ny,
               (ndim, kind, mode, setup.interp, np.ascontiguousarray(axes[0], np.float64),
                np.ascontiguousarray(axes[1], np.float64), np.ascontiguousarray(zs, np.float64),
                d[0], d[1], d[-1], float(warp), out, np.ascontiguousarray(freqs), a32,
                np.ascontiguousarray(offs), t.perm, tab, t.values.astype(np.float32),
                np.ascontiguousarray(t.gradients[ndim - 2], np.float32), np.float32(norm),
                np.float32(gain)))
    return out.reshape(out.shape[1:]) if ndim == 2 else out

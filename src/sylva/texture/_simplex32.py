"""Float32 SIMD paths for simplex noise on regular grids (private; the simplex part of
:mod:`._gridkernels32`, whose module docstring describes the float32 road).

Simplex noise hashes its corners in byte lanes where the CPU has AVX-512 VBMI
(:mod:`._bytelanes`: Gustavson's chained lookups for 64 samples in a few byte permutes);
elsewhere it needs one load a sample (2D) or z plane (3D): :func:`simplex_table` packs
the gradient indices of a cell's four (x, y) corners in one word (the chained lookups
precomputed), the SIMD corner pass takes its corners' nibbles out.  3D and 4D locate in
float64 (their kernels jump across simplex faces) and do the rest in float32 lanes; 4D
grids go by rows too (:func:`rows4s`, x along the row).  (Tried and
dropped: locating 3D in float32 lanes from split coordinates, exactly but for the
fractions' rounding and again in float64 near a face — no faster than float64, twice the
operations at twice the lanes.)  :func:`row_simplex32` is also the texture graph's row
routine.
"""

from __future__ import annotations

import numpy as np
from numba import njit, prange, uint64

from . import _bytelanes as _bl
from . import _kernels as k
from ._gridkernels32 import (
    _F,
    _OPTS,
    _OPTS64,
    BLOCK,
    CHUNKS,
    F2,
    G2,
    G2X2,
    G3,
    G3X2,
    G3X3,
    I0,
    I1,
    I2,
    I4,
    I8,
    ONE,
    R2,
    R3,
    S2,
    S3,
    ZERO,
    _combine_block,
    _finish,
    _i32,
    _pick_row,
)

#: the corner passes: fast-math but for reassociation, so that their sums and offsets round
#: the same in every caller LLVM optimises them into (in a texture graph's fused kernel the
#: 2D pass with reassociation rounded 4 of 95 samples 1 ulp off the same graph's Python
#: road, which calls the pass itself; the graph's two roads agree bit for bit)
_OPTS_NR = dict(_OPTS, fastmath={"nnan", "ninf", "nsz", "arcp", "contract", "afn"})
_C28 = np.int32(28)
_C30 = np.int32(30)
_C31 = np.int32(31)
_SIGN = np.int32(-(2**31))
_M1 = np.int32(-1)
_N16 = np.int32(16)
#: coordinates beyond this take the exact ``& 255`` of the float64 road (floor-based)
#: instead of an int32 conversion: ``floor(x + s)`` stays within int32 below it
_BIG = 2.0**29
#: the budget of sum(amplitude x coordinate magnitude in cells) over a row's octaves up to
#: which 2D simplex locates in float32 (:func:`_s2_near`)
_F32_REACH = 256.0


@njit(inline="always", **_OPTS)
def _g12(g, x, y, z):
    """``GRAD3[g] . (x, y, z)`` for g in 0..11 (int32; Gustavson's twelve edge gradients,
    the first twelve of Perlin's improved-noise ``grad``: ``±u ± v`` with u = x for g < 8
    else y, v = y for g < 4 else z): two selects (bit 3 by its sign after a shift), and
    the signs, bits 0 and 1, xor-ed into the float bits (:func:`._bytelanes.xorf`) instead
    of a negation and a select each."""
    u = y if _bl.shl32(g, _C28) < I0 else x
    v = z if g >= I4 else y
    return _bl.xorf(u, _bl.shl32(g, _C31)) + _bl.xorf(v, _i32(_bl.shl32(g, _C30) & _SIGN))


@njit(inline="always", **_OPTS)
def _g12_2(g, x, y):
    """:func:`_g12` with z = 0 (2D simplex: ``GRAD3[g, :2] . (x, y)``)."""
    u = y if _bl.shl32(g, _C28) < I0 else x
    v = ZERO if g >= I4 else y
    return _bl.xorf(u, _bl.shl32(g, _C31)) + _bl.xorf(v, _i32(_bl.shl32(g, _C30) & _SIGN))


#: row stride of :func:`simplex_table` (``tab[i * TAB_STRIDE + m]``)
TAB_STRIDE = 256
_N15 = np.int32(15)
_N255 = np.int32(255)
_N65535 = np.int32(65535)
_ROW = np.int32(0xFF00)  # bits 8..15 of a packed word: the table row i & 255
# rows of the byte-lane work buffer ``bb`` (:func:`simplex_work`): the cell's i, j, k & 255,
# the code of the middle corners' offsets (3D: :func:`_code3`; 2D: the middle corner is
# (1, 0)), the corners' gradient indices (:func:`._bytelanes.simplex3_hash`, ``simplex2_hash``)
_BI, _BJ, _BK, _BC, _BG = 0, 1, 2, 3, 4
_BROWS = 8


@njit(inline="always", **_OPTS)
def _s2_cell(xin, yin):
    """Gustavson's 2D skew and cell (float32): the offsets ``x0, y0`` and the cell's
    floors ``i, j`` (both locate passes)."""
    s = (xin + yin) * F2
    fi = np.floor(xin + s)
    fj = np.floor(yin + s)
    t = (fi + fj) * G2
    return xin - (fi - t), yin - (fj - t), fi, fj


@njit(**_OPTS)
def _s2_locate(xs, base, cnt, fx, ox, yin, bx, by, ba):
    """SIMD pass: skew, find the simplex of samples ``base..base + cnt``, and the flat
    address of its cell's packed corners in :func:`simplex_table` (``ba``)."""
    b0 = uint64(base)
    for q in range(cnt):
        x0, y0, fi, fj = _s2_cell(xs[b0 + uint64(q)] * fx + ox, yin)
        bx[q] = x0
        by[q] = y0
        ba[q] = _i32(_i32(_i32(np.int32(fi) & _N255) << I8) | _i32(np.int32(fj) & _N255))


@njit(**_OPTS)
def _s2_locate_b(xs, base, cnt, fx, ox, yin, bx, by, bb):
    """:func:`_s2_locate` for the byte-lane road: the cell's ``i, j & 255`` and whether
    the middle corner is (1, 0) into the byte rows of ``bb`` (:func:`simplex_work`)."""
    b0 = uint64(base)
    for q in range(cnt):
        x0, y0, fi, fj = _s2_cell(xs[b0 + uint64(q)] * fx + ox, yin)
        bx[q] = x0
        by[q] = y0
        bb[_BI, q] = np.uint8(np.int32(fi))  # the low byte: i & 255 (two's complement)
        bb[_BJ, q] = np.uint8(np.int32(fj))
        bb[_BC, q] = np.uint8(x0 > y0)


@njit(inline="always", cache=True, error_model="numpy")
def _s2_cell64(xin, yin):
    """:func:`_s2_cell` in float64, as :func:`._kernels.simplex2` (coordinates far from
    the origin, where float32 would round them by more than the tolerance)."""
    s = (xin + yin) * k.F2
    fi = np.floor(xin + s)
    fj = np.floor(yin + s)
    t = (fi + fj) * k.G2
    return xin - (fi - t), yin - (fj - t), fi, fj


@njit(**_OPTS64)  # no fast-math: the float64 road's roundings
def _s2_locate64(xs, base, cnt, fx, ox, yin, big, lanes, bx, by, ba, bb):
    """:func:`_s2_locate` (or with ``lanes`` :func:`_s2_locate_b`) in float64 from the
    float64 axis: the octave's coordinates, the skew and the cell as the float64 road's,
    the offsets rounded to float32 once."""
    b0 = uint64(base)
    if lanes:
        for q in range(cnt):
            x0, y0, fi, fj = _s2_cell64(xs[b0 + uint64(q)] * fx + ox, yin)
            bx[q] = x0
            by[q] = y0
            bb[_BI, q] = np.uint8(_low8(fi, big))
            bb[_BJ, q] = np.uint8(_low8(fj, big))
            bb[_BC, q] = np.uint8(x0 > y0)
    else:
        for q in range(cnt):
            x0, y0, fi, fj = _s2_cell64(xs[b0 + uint64(q)] * fx + ox, yin)
            bx[q] = x0
            by[q] = y0
            ba[q] = _i32(_i32(_low8(fi, big) << I8) | _low8(fj, big))


@njit(**_OPTS)
def _s2_hash_b(cnt, bt, bb):
    """The three corners' gradient indices of ``cnt`` samples, 64 at a time in byte lanes
    (:func:`._bytelanes.simplex2_hash`; ``bt``: perm and perm12 as bytes)."""
    p = bt.ctypes.data
    rs = uint64(bb.shape[1])
    r0 = bb.ctypes.data
    for o in range(0, cnt, _bl.LANES):
        _bl.simplex2_hash(p, r0 + uint64(o), rs)


@njit(**_OPTS_NR)
def _s2_eval_b(cnt, bx, by, bb, nb, ob, amp):
    """:func:`_s2_eval` with the corners' gradient indices from the byte rows ``G``."""
    for q in range(cnt):
        x0 = bx[q]
        y0 = by[q]
        i1 = _F(bb[_BC, q])
        x1 = x0 - i1 + G2
        y1 = y0 - (ONE - i1) + G2
        x2 = x0 + G2X2
        y2 = y0 + G2X2
        t0 = max(R2 - x0 * x0 - y0 * y0, ZERO)
        t1 = max(R2 - x1 * x1 - y1 * y1, ZERO)
        t2 = max(R2 - x2 * x2 - y2 * y2, ZERO)
        t0 *= t0
        t1 *= t1
        t2 *= t2
        n = t0 * t0 * _g12_2(_i32(bb[_BG, q]), x0, y0)
        n += t1 * t1 * _g12_2(_i32(bb[_BG + 1, q]), x1, y1)
        n += t2 * t2 * _g12_2(_i32(bb[_BG + 2, q]), x2, y2)
        nb[ob + uint64(q)] = amp * (S2 * n)


@njit(**_OPTS)
def _gather(cnt, tab, ba, bw):
    """Scalar pass: one load a sample, ``bw = tab[ba]`` (LLVM emits no vector gathers for
    this CPU, and ``vpgatherdd`` measured only ~10% faster here)."""
    for q in range(cnt):
        bw[q] = np.int32(tab[uint64(ba[q])])


@njit(inline="always", **_OPTS_NR)
def _s2_corners(x0, y0):
    """The middle and far corners' offsets of a 2D simplex, the three kernel weights t^4
    and the shift of the middle corner's nibble in a packed word (corner (1, 0) is nibble
    2, (0, 1) nibble 1: one variable shift, vpsrlvd)."""
    m = _i32(-np.int32(x0 > y0))  # the middle corner is (1, 0)
    x1 = x0 - _bl.andf(ONE, m) + G2
    y1 = y0 - _bl.andf(ONE, _i32(m ^ _M1)) + G2
    x2 = x0 + G2X2
    y2 = y0 + G2X2
    t0 = max(R2 - x0 * x0 - y0 * y0, ZERO)
    t1 = max(R2 - x1 * x1 - y1 * y1, ZERO)
    t2 = max(R2 - x2 * x2 - y2 * y2, ZERO)
    t0 *= t0
    t1 *= t1
    t2 *= t2
    return x1, y1, x2, y2, t0 * t0, t1 * t1, t2 * t2, _i32(I4 + _i32(m & I4))


@njit(inline="always", **_OPTS_NR)
def _s2_sum(w, x0, y0, x1, y1, x2, y2, t0, t1, t2, sh):
    """The three corner contributions of the packed corners ``w`` (:func:`_s2_corners`'
    offsets and weights), the gradients' dot products by selects (:func:`_g12_2`)."""
    n = t0 * _g12_2(_i32(w & _N15), x0, y0)
    n += t1 * _g12_2(_i32(_bl.srl32(w, sh) & _N15), x1, y1)
    n += t2 * _g12_2(_bl.srl32(w, np.int32(12)), x2, y2)
    return S2 * n


@njit(**_OPTS_NR)
def _s2_eval(cnt, bx, by, bw, nb, ob, amp):
    """SIMD pass: the three corner contributions, gradient indices from the packed cell
    corners (:func:`_s2_corners`, :func:`_s2_sum`), times ``amp`` into ``nb[ob:]`` (the
    block buffer with ``amp`` 1, or the first fBm octave's row)."""
    for q in range(cnt):
        x0 = bx[q]
        y0 = by[q]
        x1, y1, x2, y2, t0, t1, t2, sh = _s2_corners(x0, y0)
        nb[ob + uint64(q)] = amp * _s2_sum(bw[q], x0, y0, x1, y1, x2, y2, t0, t1, t2, sh)


@njit(inline="always", cache=True, error_model="numpy")
def _s3_cell64(xin, yin, zin):
    """Gustavson's skew and cell in float64, as :func:`._kernels.simplex3`: the offsets
    ``x0, y0, z0``, the three comparisons of the six-way choice, the cell ``i, j, k``."""
    s = (xin + yin + zin) * k.F3
    fi = np.floor(xin + s)
    fj = np.floor(yin + s)
    fk = np.floor(zin + s)
    t = (fi + fj + fk) * k.G3
    x0 = xin - (fi - t)
    y0 = yin - (fj - t)
    z0 = zin - (fk - t)
    return x0, y0, z0, x0 >= y0, y0 >= z0, x0 >= z0, fi, fj, fk


@njit(inline="always", cache=True, error_model="numpy")
def _s4_cell64(x, y, z, w):
    """Gustavson's 4D skew and cell in float64, as :func:`._kernels.simplex4`: the offsets
    ``x0 .. w0`` and the cell ``i, j, k, l``."""
    s = (x + y + z + w) * k.F4
    fi = np.floor(x + s)
    fj = np.floor(y + s)
    fk = np.floor(z + s)
    fl = np.floor(w + s)
    t = (fi + fj + fk + fl) * k.G4
    return x - (fi - t), y - (fj - t), z - (fk - t), w - (fl - t), fi, fj, fk, fl


@njit(inline="always", cache=True, error_model="numpy")
def _low8(f, big):
    """``int(f) & 255`` of an integral float64: by an int32 conversion, or where the
    coordinates may leave int32 (``big``) exactly, as the float64 road takes it."""
    if big:
        f = f - 256.0 * np.floor(f * (1.0 / 256.0))
    return _i32(np.int32(f) & _N255)


@njit(**_OPTS64)  # no fast-math: the float64 road's roundings
def _s3_locate(xo, base, cnt, yin, zin, big, bx, by, bz, ba, bd):
    """SIMD pass, in float64 (``xo``: the octave's x coordinates, ``yin``, ``zin``):
    Gustavson's 3D kernel (r² = 0.6) jumps by up to 1e-2 across simplex faces, so the
    simplex must be the one the float64 road picks.  Into float32 rows: the offsets
    ``x0, y0, z0`` (rounded); into ``ba`` one word: ``i & 255`` in bits 8..15, ``j & 255``
    in 0..7 (the cell's :func:`simplex_table` row and column but for ``perm[k]``),
    ``k & 255`` in 16..23; into the rows of ``bd`` the float64 differences ``x0 - y0``,
    ``y0 - z0``, ``x0 - z0`` rounded to float32, whose sign bits are the comparisons
    ``x0 >= y0`` .. of Gustavson's six-way choice exactly (:func:`_diff_sign`)."""
    b0 = uint64(base)
    for q in range(cnt):
        x0, y0, z0, ca, cb, cc, fi, fj, fk = _s3_cell64(xo[b0 + uint64(q)], yin, zin)
        _diffs3(q, x0, y0, z0, bx, by, bz, bd)
        ba[q] = (_low8(fi, big) << I8) | _low8(fj, big) | (_low8(fk, big) << np.int32(16))


@njit(inline="always", cache=True, error_model="numpy")
def _diffs3(q, x0, y0, z0, bx, by, bz, bd):
    """Sample ``q``'s float64 offsets into the float32 rows, and their differences into
    ``bd`` (the comparisons as sign bits: :func:`_diff_sign`)."""
    x0 += 0.0
    y0 += 0.0
    z0 += 0.0
    bx[q] = x0
    by[q] = y0
    bz[q] = z0
    bd[0, q] = x0 - y0
    bd[1, q] = y0 - z0
    bd[2, q] = x0 - z0


@njit(inline="always", **_OPTS)
def _diff_sign(d):
    """-1 where the float64 comparison ``a >= b`` behind ``d = float32(a - b)`` holds, else
    0.  Exact: the difference of two float64 numbers is 0 only where they are equal, and
    rounding it to float32 keeps its sign, a tiny negative one as ``-0.0``; the offsets
    are taken ``+ 0.0`` first, so that two zeros differ by ``+0.0``.  (Packing float64
    comparisons into bits in the locate cost more than its float64 arithmetic.)"""
    return _i32(_bl.signm(d) ^ _M1)


@njit(inline="always", **_OPTS)
def _code3(ca, cb, cc):
    """Corners 1 and 2's offsets ``i1 | j1 << 1 | k1 << 2 | i2 << 3 | j2 << 4 | k2 << 5``
    from the comparisons ``x0 >= y0``, ``y0 >= z0``, ``x0 >= z0``: Gustavson's six-way
    choice, as :func:`_s3_eval` takes it from the comparisons.  Bitwise, not ``and`` / ``or``:
    short-circuits are branches, which LLVM does not vectorise."""
    i = _i32
    return np.uint8(i(ca & cc) | i(cb & (not ca)) << I1 | i(not (cb | cc)) << I2
                    | i(ca | cc) << np.int32(3) | i(cb | (not ca)) << I4
                    | i(not (cb & cc)) << np.int32(5))


@njit(**_OPTS64)  # no fast-math: the float64 road's roundings
def _s3_locate_b(xo, base, cnt, yin, zin, big, bx, by, bz, bb):
    """:func:`_s3_locate` for the byte-lane road: the cell and the code of its corners
    (:func:`_code3`) into the byte rows of ``bb`` instead of one packed word."""
    b0 = uint64(base)
    for q in range(cnt):
        x0, y0, z0, ca, cb, cc, fi, fj, fk = _s3_cell64(xo[b0 + uint64(q)], yin, zin)
        bx[q] = x0
        by[q] = y0
        bz[q] = z0
        bb[_BI, q] = np.uint8(_low8(fi, big))
        bb[_BJ, q] = np.uint8(_low8(fj, big))
        bb[_BK, q] = np.uint8(_low8(fk, big))
        bb[_BC, q] = _code3(ca, cb, cc)


@njit(**_OPTS)
def _s3_gather(cnt, tab, pk, ba, bw):
    """Scalar pass: the packed corners of the cell's two z planes, columns
    ``j + perm[k]`` and ``j + perm[k + 1]`` (mod 256) of row ``i`` of :func:`simplex_table`,
    in one word (plane k + 1 in the high half); ``pk[k]``: ``perm[k] | perm[k + 1] << 16``."""
    for q in range(cnt):
        a = ba[q]
        p = pk[uint64(_i32(a >> _N16) & _N255)]
        row = _i32(a & _ROW)
        c0 = _i32(_i32(a + _i32(p & _N65535)) & _N255)
        c1 = _i32(_i32(a + _i32(p >> _N16)) & _N255)
        bw[q] = _i32(np.int32(tab[uint64(row | c0)])
                     | _i32(np.int32(tab[uint64(row | c1)]) << _N16))


@njit(inline="always", **_OPTS)
def _c3(g, x, y, z):
    """One corner's contribution (before the factor 32)."""
    t = max(R3 - x * x - y * y - z * z, ZERO)
    t *= t
    return t * t * _g12(g, x, y, z)


@njit(**_OPTS_NR)
def _s3_eval(cnt, bx, by, bz, bd, bw, nb, ob, amp):
    """SIMD pass: the four corner contributions (float32, 8 or 16 lanes).  Corners 1 and
    2 from the comparisons (sign bits of ``bd``, :func:`_diff_sign`; Gustavson's six-way
    choice as masks: an offset is ``andf(1, mask)``, a gradient index a variable shift of
    the word ``bw`` by ``16 k + 8 i + 4 j``)."""
    for q in range(cnt):
        ma = _diff_sign(bd[0, q])  # x0 >= y0
        mb = _diff_sign(bd[1, q])  # y0 >= z0
        mc = _diff_sign(bd[2, q])  # x0 >= z0
        na = _i32(ma ^ _M1)
        mi1 = _i32(ma & mc)
        mj1 = _i32(mb & na)
        mk1 = _i32(_i32(mb | mc) ^ _M1)
        mi2 = _i32(ma | mc)
        mj2 = _i32(mb | na)
        mk2 = _i32(_i32(mb & mc) ^ _M1)
        s1 = _i32(_i32(_i32(mi1 & I8) | _i32(mj1 & I4)) | _i32(mk1 & _N16))
        s2 = _i32(_i32(_i32(mi2 & I8) | _i32(mj2 & I4)) | _i32(mk2 & _N16))
        w = bw[q]
        x0 = bx[q]
        y0 = by[q]
        z0 = bz[q]
        f = _bl.andf
        n = _c3(_i32(w & _N15), x0, y0, z0)
        n += _c3(_i32(_bl.srl32(w, s1) & _N15), x0 - f(ONE, mi1) + G3, y0 - f(ONE, mj1) + G3,
                 z0 - f(ONE, mk1) + G3)
        n += _c3(_i32(_bl.srl32(w, s2) & _N15), x0 - f(ONE, mi2) + G3X2,
                 y0 - f(ONE, mj2) + G3X2, z0 - f(ONE, mk2) + G3X2)
        n += _c3(_bl.srl32(w, _C28), x0 + G3X3, y0 + G3X3, z0 + G3X3)
        nb[ob + uint64(q)] = amp * (S3 * n)


@njit(**_OPTS)
def _s3_hash_b(cnt, bt, bb):
    """The corners' gradient indices of ``cnt`` samples, 64 at a time in byte lanes
    (:func:`._bytelanes.simplex3_hash`; ``bt``: perm and perm12 as bytes)."""
    p = bt.ctypes.data
    rs = uint64(bb.shape[1])
    r0 = bb.ctypes.data
    for o in range(0, cnt, _bl.LANES):
        _bl.simplex3_hash(p, r0 + uint64(o), rs)


@njit(inline="always", **_OPTS)
def _obit(c, n):
    return ONE if _i32(c & n) != I0 else ZERO


@njit(**_OPTS_NR)
def _s3_eval_b(cnt, bx, by, bz, bb, nb, ob, amp):
    """:func:`_s3_eval` with the corners' gradient indices from the byte rows ``G`` and
    their offsets from the code row (:func:`_code3`)."""
    for q in range(cnt):
        c = _i32(bb[_BC, q])
        i1, j1, k1 = _obit(c, I1), _obit(c, I2), _obit(c, I4)
        i2, j2, k2 = _obit(c, I8), _obit(c, np.int32(16)), _obit(c, np.int32(32))
        x0 = bx[q]
        y0 = by[q]
        z0 = bz[q]
        n = _c3(_i32(bb[_BG, q]), x0, y0, z0)
        n += _c3(_i32(bb[_BG + 1, q]), x0 - i1 + G3, y0 - j1 + G3, z0 - k1 + G3)
        n += _c3(_i32(bb[_BG + 2, q]), x0 - i2 + G3X2, y0 - j2 + G3X2, z0 - k2 + G3X2)
        n += _c3(_i32(bb[_BG + 3, q]), x0 + G3X3, y0 + G3X3, z0 + G3X3)
        nb[ob + uint64(q)] = amp * (S3 * n)


@njit(**_OPTS64)  # no fast-math: yin, zin as in float64
def row_simplex32(ndim, mode, xs, xs32, ys, zs, j, m, row, weight, freqs, amps, offs, perm,
                  tab, gain, work):
    """Row ``(m, j)`` of 2D or 3D simplex noise, every octave summed into ``row`` (float32;
    ridged sums are left unnormalised); ``work``: :func:`simplex_work` (the texture graph's
    row routine).  Blocks of :data:`BLOCK` samples go in passes: locate (SIMD; 3D in
    float64), one table load a sample and z plane (scalar; 3D with ``hashed``: the chained
    lookups in byte lanes), corner sums (SIMD)."""
    _simplex_rows(ndim, mode, xs, xs32, ys, zs, row.reshape((1, 1, row.shape[0])),
                  np.int64(0), np.int64(1), j, m, weight, freqs, amps, offs, perm, tab, gain,
                  work, ONE)


@njit(**_OPTS64)  # no fast-math: yin, zin as in float64
def _simplex_rows(ndim, mode, xs, xs32, ys, zs, out, r0, r1, jfix, mfix, weight, freqs, amps,
                  offs, perm, tab, gain, work, norm):
    """Rows ``r0 .. r1`` of ``out`` in one call (as :func:`._gridkernels32._lat_rows`: a
    call per row cost more than a short row's work), or with ``jfix >= 0`` the one row
    ``out[0, 0]`` at ``(mfix, jfix)``, or with ``jfix == -2`` a block of image rows (``mfix``
    rows high) into ``out[0, :r1 - r0]``: both left unnormalised."""
    bx, by, bz, nb, ba, bw, pk, bb, bt, hashed, bd = work
    xo, xbig, xmax = _x_octaves(xs, freqs, offs, ndim == 3)  # 3D: each octave's x
    for r in range(r0, r1):
        j, m, row = _pick_row(out, r, r0, jfix, mfix)
        nx = row.shape[0]
        if amps.shape[0] == 0:  # no octave (the first octave sets the row, no clearing pass)
            row[:] = ZERO
        spent = 0.0  # of the float32 locate's budget (2D: _s2_near)
        for o in range(freqs.shape[0]):
            fx = freqs[o, 0]
            ox = offs[o, 0]
            yin = ys[j] * freqs[o, 1] + offs[o, 1]
            zin = zs[m] * freqs[o, 2] + offs[o, 2]
            fx32 = _F(fx)
            ox32 = _F(ox)
            yin32 = _F(yin)
            big = xbig[o] or not (abs(yin) < _BIG and abs(zin) < _BIG)
            near, spent = _s2_near(spent, amps[o], max(xmax[o], abs(yin)))
            # the first fBm octave goes straight into the row (as _combine_block would put it)
            direct = o == 0 and mode == k.FBM
            amp = amps[o] if direct else ONE
            for base in range(0, nx, BLOCK):
                cnt = min(BLOCK, nx - base)
                dst = row if direct else nb
                ob = uint64(base) if direct else uint64(0)
                if ndim == 2 and not near:  # far from the origin: located in float64
                    _s2_locate64(xs, base, cnt, fx, ox, yin, big, hashed, bx, by, ba, bb)
                    if hashed:
                        _s2_hash_b(cnt, bt, bb)
                        _s2_eval_b(cnt, bx, by, bb, dst, ob, amp)
                    else:
                        _gather(cnt, tab, ba, bw)
                        _s2_eval(cnt, bx, by, bw, dst, ob, amp)
                elif ndim == 2 and hashed:
                    _s2_locate_b(xs32, base, cnt, fx32, ox32, yin32, bx, by, bb)
                    _s2_hash_b(cnt, bt, bb)
                    _s2_eval_b(cnt, bx, by, bb, dst, ob, amp)
                elif ndim == 2:
                    _s2_locate(xs32, base, cnt, fx32, ox32, yin32, bx, by, ba)
                    _gather(cnt, tab, ba, bw)
                    _s2_eval(cnt, bx, by, bw, dst, ob, amp)
                elif hashed:
                    _s3_locate_b(xo[o], base, cnt, yin, zin, big, bx, by, bz, bb)
                    _s3_hash_b(cnt, bt, bb)
                    _s3_eval_b(cnt, bx, by, bz, bb, dst, ob, amp)
                else:
                    _s3_locate(xo[o], base, cnt, yin, zin, big, bx, by, bz, ba, bd)
                    _s3_gather(cnt, tab, pk, ba, bw)
                    _s3_eval(cnt, bx, by, bz, bd, bw, dst, ob, amp)
                if not direct:
                    _combine_block(mode, row, weight, base, cnt, nb, amps[o], gain, o == 0)
        if jfix == -1:
            _finish(mode, row, norm)


@njit(**_OPTS64)  # no fast-math: the float64 road's roundings
def _x_octave(xs, fx, ox, xo):
    """``xo = xs * fx + ox`` in float64, as the float64 road takes an octave's x (once a
    call, not once a row)."""
    for q in range(xs.shape[0]):
        xo[q] = xs[q] * fx + ox


@njit(**_OPTS64)  # no fast-math: the float64 road's roundings
def _x_octaves(xs, freqs, offs, need):
    """Every octave's x coordinates (:func:`_x_octave`; none unless ``need``), per octave
    whether one of them is at least :data:`_BIG` (the locates' exact ``& 255``), and the
    largest of them (as a magnitude; 2D: :func:`_s2_near`)."""
    nf = freqs.shape[0]
    xo = np.empty((nf if need else 0, xs.shape[0]))
    xbig = np.zeros(nf, np.bool_)
    xmax = np.zeros(nf)
    for o in range(nf):
        fx = freqs[o, 0]
        ox = offs[o, 0]
        if need:
            _x_octave(xs, fx, ox, xo[o])
        m = 0.0
        for q in range(xs.shape[0]):
            m = max(m, abs(xs[q] * fx + ox))
        xbig[o] = not m < _BIG
        xmax[o] = m
    return xo, xbig, xmax


@njit(inline="always", cache=True, error_model="numpy")
def _s2_near(spent, amp, cmax):
    """Whether a 2D simplex octave of amplitude ``amp`` with coordinates up to ``cmax``
    (cells) may be located in float32, the octaves before it in the row having spent
    ``spent`` of :data:`_F32_REACH`; and the new ``spent``.  Float32 coordinates round by
    about ``cmax`` * 1e-7 of a cell, which moves the octave's value by up to about
    3.5e-7 ``amp cmax`` (measured over 384K samples from 16 to 4,096 cells: 2.6-3.6e-7;
    5.9e-4 at 3,000 cells, 0.02 at 1e5); within the budget the row's float32 octaves
    together stay within ~1e-4 of the float64 road, beyond it an octave locates in float64
    (:func:`_s2_locate64`)."""
    cost = abs(amp) * cmax
    if spent + cost <= _F32_REACH:
        return True, spent + cost
    return False, spent


@njit(cache=True)
def simplex_work(perm, hashed):
    """Block buffers of :func:`row_simplex32`; ``hashed``:
    3D hashes its corners in byte lanes (:mod:`._bytelanes`; ``perm``: the doubled
    permutation) instead of loading the packed corners of :func:`simplex_table`."""
    f = np.float32
    i = np.int32
    bb = np.zeros((_BROWS, BLOCK), np.uint8)  # BLOCK: a multiple of the 64 byte lanes
    bt = np.empty(512, np.uint8)
    pk = np.empty(256, i)  # a cell's two z planes: perm[k] | perm[k + 1] << 16
    for m in range(256):
        bt[m] = perm[m]
        bt[256 + m] = perm[m] % 12
        pk[m] = perm[m] | (perm[m + 1] << 16)
    return (np.empty(BLOCK, f), np.empty(BLOCK, f), np.empty(BLOCK, f), np.empty(BLOCK, f),
            np.empty(BLOCK, i), np.empty(BLOCK, i), pk, bb, bt, hashed,
            np.empty((3, BLOCK + 16), f))  # bd: rows off each other's L1 sets


@njit(parallel=True, **_OPTS64)  # no fast-math: yin, zin as in float64
def simplex_grid32(ndim, mode, xs, xs32, ys, zs, out, freqs, amps, offs, perm, tab, norm, gain,
                   hashed):
    """Fill ``out`` (float32, shape (nz, ny, nx)) with 2D or 3D simplex noise (Gustavson's
    corners, hashes and gradients), every octave in one pass per row.  ``xs, ys, zs``,
    ``freqs``, ``offs`` as for :func:`._gridkernels.simplex_grid` (float64; ``xs32``:
    ``xs`` in float32 for the 2D pass); ``amps`` already carry ``norm`` unless ``mode``
    is ridged; ``tab``: :func:`simplex_table`."""
    nz, ny, nx = out.shape
    nrows = ny * nz
    nch = min(nrows, CHUNKS)
    for c in prange(nch):
        weight = np.empty(nx, np.float32)
        work = simplex_work(perm, hashed)
        _simplex_rows(ndim, mode, xs, xs32, ys, zs, out, c * nrows // nch,
                      (c + 1) * nrows // nch, np.int64(-1), np.int64(-1), weight, freqs, amps,
                      offs, perm, tab, gain, work, norm)


def simplex_table(seed, perm, perm12):
    """The packed corner gradients of simplex noise (cached per seed): ``tab[i * 256 + m]``
    (uint16, i and m in 0..255; 128 KB) holds ``g(i + di, m + dj) = perm12[i + di +
    perm[m + dj]]`` in nibble ``2 di + dj``.  With ``m = j`` in 2D and
    ``m = (j + perm[k]) & 255`` in 3D (the permutation is doubled, so ``perm[m + dj]``
    repeats every 256) one load gives the four corners of a cell's (z) plane:
    Gustavson's chained lookups ``perm12[i + perm[j + perm[k]]]``, as the float64 road's,
    once a sample and plane."""
    tab = _TABS.get(seed)
    if tab is None:
        g = perm12[np.arange(257)[:, None] + perm[np.arange(257)][None, :]]
        g = g.astype(np.int32)
        tab = (g[:-1, :-1] | (g[:-1, 1:] << 4) | (g[1:, :-1] << 8) | (g[1:, 1:] << 12))
        tab = np.ascontiguousarray(tab.astype(np.uint16).reshape(256 * TAB_STRIDE))
        if len(_TABS) > 16:
            _TABS.clear()
        _TABS[seed] = tab
    return tab


_TABS: dict = {}


# -- two 2D simplex fields at once (a warped 2D simplex grid's warp fields) ------------------
# The two fields are fBm at the same points with two seeds: a block is located once, and of
# the corner pass only the gradients differ (the offsets and the kernel weights t^4 are the
# same), so the pair costs about 1.6 fields instead of 2.


@njit(**_OPTS_NR)
def _s2_eval2(cnt, bx, by, bw, bw2, nb, nb2, ob, amp):
    """:func:`_s2_eval` for two seeds' packed corners ``bw``, ``bw2`` into ``nb``, ``nb2``:
    the offsets and weights computed once."""
    for q in range(cnt):
        x0 = bx[q]
        y0 = by[q]
        x1, y1, x2, y2, t0, t1, t2, sh = _s2_corners(x0, y0)
        nb[ob + uint64(q)] = amp * _s2_sum(bw[q], x0, y0, x1, y1, x2, y2, t0, t1, t2, sh)
        nb2[ob + uint64(q)] = amp * _s2_sum(bw2[q], x0, y0, x1, y1, x2, y2, t0, t1, t2, sh)


@njit(nogil=True, **_OPTS64)  # no fast-math: yin, zin as in float64
def simplex_pair_rows32(r0, r1, xs, xs32, ys, zs, out, out2, freqs, amps, offs, perm, perm2,
                        tab, tab2, gain, hashed):
    """Rows ``r0 .. r1`` of two 2D simplex fBm grids ``out``, ``out2`` (float32, shape
    (1, ny, nx)) of the permutations ``perm``, ``perm2`` (``tab``, ``tab2``: their
    :func:`simplex_table`), as :func:`simplex_grid32` makes each with ``mode`` fBm: the
    same locate per block and octave (float32 near the origin, else float64), the two
    seeds' corners gathered (or hashed in byte lanes) one after the other."""
    bx, by, _, nb, ba, bw, _, bb, bt, _, _ = simplex_work(perm, hashed)
    _, _, _, nb2, _, bw2, _, _, bt2, _, _ = simplex_work(perm2, hashed)
    weight = np.empty(0, np.float32)  # fBm has no ridged weights
    _, xbig, xmax = _x_octaves(xs, freqs, offs, False)
    nx = out.shape[2]
    for r in range(r0, r1):
        row = out[0, r]
        row2 = out2[0, r]
        if amps.shape[0] == 0:
            row[:] = ZERO
            row2[:] = ZERO
        spent = 0.0
        for o in range(freqs.shape[0]):
            fx = freqs[o, 0]
            ox = offs[o, 0]
            yin = ys[r] * freqs[o, 1] + offs[o, 1]
            zin = zs[0] * freqs[o, 2] + offs[o, 2]
            fx32 = _F(fx)
            ox32 = _F(ox)
            yin32 = _F(yin)
            big = xbig[o] or not (abs(yin) < _BIG and abs(zin) < _BIG)
            near, spent = _s2_near(spent, amps[o], max(xmax[o], abs(yin)))
            direct = o == 0  # the first octave straight into the rows
            amp = amps[o] if direct else ONE
            for base in range(0, nx, BLOCK):
                cnt = min(BLOCK, nx - base)
                d1 = row if direct else nb
                d2 = row2 if direct else nb2
                ob = uint64(base) if direct else uint64(0)
                if not near:
                    _s2_locate64(xs, base, cnt, fx, ox, yin, big, hashed, bx, by, ba, bb)
                elif hashed:
                    _s2_locate_b(xs32, base, cnt, fx32, ox32, yin32, bx, by, bb)
                else:
                    _s2_locate(xs32, base, cnt, fx32, ox32, yin32, bx, by, ba)
                if hashed:  # the byte rows of the corners, one seed after the other
                    _s2_hash_b(cnt, bt, bb)
                    _s2_eval_b(cnt, bx, by, bb, d1, ob, amp)
                    _s2_hash_b(cnt, bt2, bb)
                    _s2_eval_b(cnt, bx, by, bb, d2, ob, amp)
                else:
                    _gather(cnt, tab, ba, bw)
                    _gather(cnt, tab2, ba, bw2)
                    _s2_eval2(cnt, bx, by, bw, bw2, d1, d2, ob, amp)
                if not direct:
                    _combine_block(k.FBM, row, weight, base, cnt, nb, amps[o], gain, False)
                    _combine_block(k.FBM, row2, weight, base, cnt, nb2, amps[o], gain, False)


def simplex_pair32(setups, axes, freqs, amps, offs, norm, gain, outs=(None, None)):
    """Two 2D simplex fBm grids of the setups ``setups`` (float32, shape (ny, nx)) at the
    grid ``axes`` (float64; x, y, z), as :func:`._gridkernels32.grid32` makes each (into
    the float32 buffers ``outs`` where given): the warp fields of a warped 2D simplex
    grid, by :func:`simplex_pair_rows32` on :func:`._gridplan.run_blocks`' threads."""
    from ._gridplan import run_blocks

    (t, t2) = (s.tables for s in setups)
    ny, nx = len(axes[1]), len(axes[0])
    out, out2 = (np.empty((1, ny, nx), np.float32) if b is None else b.reshape(1, ny, nx)
                 for b in outs)
    run_blocks(simplex_pair_rows32, ny,
               (axes[0], axes[0].astype(np.float32), axes[1], axes[2], out, out2, freqs,
                (amps * norm).astype(np.float32), offs, t.perm, t2.perm,
                simplex_table(t.seed, t.perm, t.perm12), simplex_table(t2.seed, t2.perm,
                                                                       t2.perm12),
                np.float32(gain), _bl.USE))
    return out.reshape(ny, nx), out2.reshape(ny, nx)


# -- 4D simplex noise by rows ---------------------------------------------------------------
# As 3D: x along the row, y, z and w fixed, so a sample is located in float64 (the 4D
# kernel, r² = 0.6, jumps across simplex faces too) and the rest is float32.  The chained
# lookups ``perm[i + perm[j + perm[k + perm[l]]]] & 31`` of the hypercube's sixteen corners
# take six loads a sample (:func:`_s4_gather`: three of :func:`simplex_work`'s pair table,
# one of :func:`simplex4_table` for each of the three (k, l) planes the simplex visits)
# instead of the five corners' twenty chained ones.

_G4 = _F(k.G4)
_G4X2 = _F(2.0 * k.G4)
_G4X3 = _F(3.0 * k.G4)
_G4X4 = _F(4.0 * k.G4 - 1.0)
_R4 = _F(0.6)
_S4 = _F(27.0)
_N31 = np.int32(31)
_C29 = np.int32(29)
_N10 = np.int32(10)
I3 = np.int32(3)
_N5 = np.int32(5)


@njit(inline="always", **_OPTS)
def _g32(h, x, y, z, w):
    """``GRAD4[h] . (x, y, z, w)`` for h in 0..31 (int32; Gustavson's 32 gradients): the
    axis ``h >> 3`` is left out, the other three, in order, take the signs of bits 2, 1, 0
    (xor-ed into the float bits, :func:`._bytelanes.xorf`)."""
    s = _i32(h >> np.int32(3))
    a = y if s == I0 else x
    b = z if s <= I1 else y
    c = z if s == np.int32(3) else w
    sg = _SIGN
    return (_bl.xorf(a, _i32(_bl.shl32(h, _C29) & sg))
            + _bl.xorf(b, _i32(_bl.shl32(h, _C30) & sg)) + _bl.xorf(c, _bl.shl32(h, _C31)))


@njit(**_OPTS64)  # no fast-math: the float64 road's roundings
def _s4_locate(xo, base, cnt, yin, zin, win, big, bx, by, bz, bw, ba, bd):
    """SIMD pass, in float64 as :func:`._kernels.simplex4`: the offsets ``x0 .. w0``
    (float32 rows), the cell ``i, j, k, l & 255`` in one word (``j`` in bits 0..7, ``i``
    in 8..15, ``k`` in 16..23, ``l`` in 24..31: :func:`_s4_gather`'s table row and
    columns) into ``ba``, and for the six comparisons of the rank ordering, ``x0 > y0``,
    ``x0 > z0``, ``x0 > w0``, ``y0 > z0``, ``y0 > w0``, ``z0 > w0``, the float64
    differences ``y0 - x0 .. w0 - z0`` rounded to float32 into the rows of ``bd``: their
    sign bits are the comparisons exactly (rounding keeps a sign, even to ``-0.0``; the
    offsets ``+ 0.0`` so that no difference of two zeros is ``-0.0``), and the corner pass
    takes them in float32 lanes (packing float64 comparisons into bits here cost ~40 % of
    the pass)."""
    b0 = uint64(base)
    for q in range(cnt):
        x0, y0, z0, w0, fi, fj, fk, fl = _s4_cell64(xo[b0 + uint64(q)], yin, zin, win)
        x0 += 0.0
        y0 += 0.0
        z0 += 0.0
        w0 += 0.0
        bx[q] = x0
        by[q] = y0
        bz[q] = z0
        bw[q] = w0
        bd[0, q] = y0 - x0
        bd[1, q] = z0 - x0
        bd[2, q] = w0 - x0
        bd[3, q] = z0 - y0
        bd[4, q] = w0 - y0
        bd[5, q] = w0 - z0
        ba[q] = (_low8(fj, big) | (_low8(fi, big) << I8) | (_low8(fk, big) << np.int32(16))
                 | (_low8(fl, big) << np.int32(24)))


@njit(**_OPTS)
def _s4_gather(cnt, tab, pk, ba, bd, hw):
    """Scalar pass: the gradient indices of the corners of the cell's three ``(k, l)``
    planes the simplex visits, three words a sample: ``hw[0]`` plane ``(0, 0)``, ``hw[1]``
    ``(1, 0)`` where ``z0 > w0`` (z ranks above w, so the simplex offsets k before l;
    the sign of ``bd[5]``, :func:`_s4_locate`) else ``(0, 1)``, ``hw[2]`` ``(1, 1)``; each
    holds corners ``(i1, j1)`` in bits ``5 (2 i1 + j1)`` (:func:`simplex4_table` row
    ``i``, column ``(j + perm[k + k1 + perm[l + l1]]) & 255``; ``pk``:
    :func:`simplex_work`'s ``perm[m] | perm[m + 1] << 16``, 1 KB.  A 256 KB table of the
    four ``perm[..]`` by ``(k, l)``, one load instead of three, measured 0.9x on 4-octave
    fBm: beside ``tab`` it filled this CPU's L2.)"""
    for q in range(cnt):
        a = ba[q]
        row = _i32(a & _ROW)
        kk = _i32(_i32(a >> _N16) & _N255)
        pl = pk[uint64(_i32(a >> np.int32(24)) & _N255)]  # perm[l], perm[l + 1]
        p0 = pk[uint64(_i32(kk + _i32(pl & _N65535)) & _N255)]  # l1 = 0: k1 = 0, 1
        p1 = pk[uint64(_i32(kk + _i32(pl >> _N16)) & _N255)]  # l1 = 1
        mid = _i32(p0 >> _N16) if _bl.signm(bd[5, q]) != I0 else _i32(p1 & _N65535)
        hw[0, q] = tab[uint64(row | _i32(_i32(a + _i32(p0 & _N65535)) & _N255))]
        hw[1, q] = tab[uint64(row | _i32(_i32(a + mid) & _N255))]
        hw[2, q] = tab[uint64(row | _i32(_i32(a + _i32(p1 >> _N16)) & _N255))]


@njit(inline="always", **_OPTS)
def _c4(g, x, y, z, w):
    t = max(_R4 - x * x - y * y - z * z - w * w, ZERO)
    t *= t
    return t * t * _g32(g, x, y, z, w)


@njit(inline="always", **_OPTS)
def _h4(h0, h1, h2, mi, mj, mk, ml):
    """The gradient index of the corner offset by the masks ``mi .. ml`` (-1 or 0): plane
    word ``h0`` where neither k nor l is offset, ``h2`` where both are, else ``h1``
    (:func:`_s4_gather`; loaded: selecting loads of rows would be gathers), field
    ``2 i + j``."""
    v = h2 if _i32(mk & ml) != I0 else (h1 if _i32(mk | ml) != I0 else h0)
    return _i32(_bl.srl32(v, _i32(_i32(mi & _N10) | _i32(mj & _N5))) & _N31)


@njit(inline="always", **_OPTS)
def _mid4(h0, h1, h2, rx, ry, rz, rw, lim, off, x0, y0, z0, w0):
    """Corner ``4 - lim`` (1, 2 or 3): offset by 1 along the axes of rank >= ``lim``."""
    f = _bl.andf
    mi = _i32(-np.int32(rx >= lim))
    mj = _i32(-np.int32(ry >= lim))
    mk = _i32(-np.int32(rz >= lim))
    ml = _i32(-np.int32(rw >= lim))
    return _c4(_h4(h0, h1, h2, mi, mj, mk, ml), x0 - f(ONE, mi) + off, y0 - f(ONE, mj) + off,
               z0 - f(ONE, mk) + off, w0 - f(ONE, ml) + off)


@njit(**_OPTS_NR)
def _s4_eval(cnt, bx, by, bz, bw, bd, hw, nb, ob, amp):
    """SIMD pass: the five corner contributions (float32).  The ranks of ``x0 .. w0`` from
    the comparisons (Gustavson's rank ordering; their masks the sign bits of ``bd``,
    :func:`_s4_locate`), corner ``c`` offset by 1 along the axes of rank at least
    ``4 - c``."""
    for q in range(cnt):
        a = _bl.signm(bd[0, q])  # -1 where x0 > y0
        b = _bl.signm(bd[1, q])  # x0 > z0
        e3 = _bl.signm(bd[2, q])  # x0 > w0
        d = _bl.signm(bd[3, q])  # y0 > z0
        e = _bl.signm(bd[4, q])  # y0 > w0
        g = _bl.signm(bd[5, q])  # z0 > w0
        rx = _i32(-_i32(_i32(a + b) + e3))
        ry = _i32(_i32(_i32(I1 + a) - d) - e)
        rz = _i32(_i32(_i32(I2 + b) + d) - g)
        rw = _i32(_i32(_i32(np.int32(3) + e3) + e) + g)
        x0 = bx[q]
        y0 = by[q]
        z0 = bz[q]
        w0 = bw[q]
        h0 = hw[0, q]
        h1 = hw[1, q]
        h2 = hw[2, q]
        n = _c4(_i32(h0 & _N31), x0, y0, z0, w0)
        n += _mid4(h0, h1, h2, rx, ry, rz, rw, I3, _G4, x0, y0, z0, w0)
        n += _mid4(h0, h1, h2, rx, ry, rz, rw, I2, _G4X2, x0, y0, z0, w0)
        n += _mid4(h0, h1, h2, rx, ry, rz, rw, I1, _G4X3, x0, y0, z0, w0)
        n += _c4(_i32(_bl.srl32(h2, np.int32(15)) & _N31), x0 + _G4X4, y0 + _G4X4,
                 z0 + _G4X4, w0 + _G4X4)
        nb[ob + uint64(q)] = amp * (_S4 * n)


@njit(nogil=True, **_OPTS64)  # no fast-math: y, z, w as in float64
def rows4s(r0, r1, mode, xs, ys, zs, ws, out, freqs, amps, offs, perm, tab, norm, gain):
    """Rows ``r0 .. r1`` of ``out`` (float32, shape (nw, nz, ny, nx); row ``r`` is
    ``(r // (ny nz), r // ny % nz, r % ny)``) of 4D simplex noise, every octave summed
    into the row (as :func:`._lattice4_32.rows4`; ``amps`` carry ``norm`` unless ``mode``
    is ridged; ``tab``: :func:`simplex4_table`)."""
    bx, by, bz, nb, ba, bw1, pk, bb, bt, hashed, _ = simplex_work(perm, False)
    bw = np.empty(BLOCK, np.float32)
    bd = np.empty((6, BLOCK + 16), np.float32)  # rows off each other's L1 sets
    hw = np.empty((3, BLOCK + 16), np.int32)
    nw, nz, ny, nx = out.shape
    weight = np.empty(nx, np.float32)
    nf = freqs.shape[0]
    xo, xbig, _ = _x_octaves(xs, freqs, offs, True)
    for r in range(r0, r1):
        j = r % ny
        m = (r // ny) % nz
        n = r // (ny * nz)
        row = out[n, m, j]
        for o in range(nf):
            yin = ys[j] * freqs[o, 1] + offs[o, 1]
            zin = zs[m] * freqs[o, 2] + offs[o, 2]
            win = ws[n] * freqs[o, 3] + offs[o, 3]
            big = xbig[o] or not (abs(yin) < _BIG and abs(zin) < _BIG and abs(win) < _BIG)
            direct = o == 0 and mode == k.FBM
            amp = amps[o] if direct else ONE
            for base in range(0, nx, BLOCK):
                cnt = min(BLOCK, nx - base)
                dst = row if direct else nb
                ob = uint64(base) if direct else uint64(0)
                _s4_locate(xo[o], base, cnt, yin, zin, win, big, bx, by, bz, bw, ba, bd)
                _s4_gather(cnt, tab, pk, ba, bd, hw)
                _s4_eval(cnt, bx, by, bz, bw, bd, hw, dst, ob, amp)
                if not direct:
                    _combine_block(mode, row, weight, base, cnt, nb, amps[o], gain, o == 0)
        _finish(mode, row, norm)


def simplex4_table(seed, perm):
    """The packed corner gradients of 4D simplex noise (cached per seed):
    ``tab[i * 256 + m]`` (int32, i and m in 0..255; 256 KB) holds
    ``perm[i + di + perm[m + dj]] & 31`` in bits ``5 (2 di + dj)``: with
    ``m = (j + perm[k + k1 + perm[l + l1]]) & 255`` the four corners ``(di, dj)`` of the
    cell's ``(k1, l1)`` plane (the float64 road's chain, :func:`._kernels.simplex4`)."""
    key = ("4d", seed)
    tab = _TABS.get(key)
    if tab is None:
        g = (perm[np.arange(257)[:, None] + perm[np.arange(257)][None, :]] & 31).astype(np.int32)
        tab = g[:-1, :-1] | (g[:-1, 1:] << 5) | (g[1:, :-1] << 10) | (g[1:, 1:] << 15)
        tab = np.ascontiguousarray(tab.astype(np.int32).reshape(256 * TAB_STRIDE))
        if len(_TABS) > 16:
            _TABS.clear()
        _TABS[key] = tab
    return tab


def grid4s(setup, axes, freqs, amps, offs, mode, norm, gain, full):
    """The float32 4D simplex grid (shape (nw, nz, ny, nx); ``full``: (nx, ny, nz, nw)), as
    :func:`._gridkernels32.grid32` takes its arguments."""
    from ._gridplan import run_blocks

    t = setup.tables
    a32 = (amps if mode == k.RIDGED else amps * norm).astype(np.float32)
    out = np.empty((full[3], full[2], full[1], full[0]), np.float32)
    ax = [np.ascontiguousarray(a, np.float64) for a in axes[:4]]
    run_blocks(rows4s, full[1] * full[2] * full[3],
               (mode, *ax, out, np.ascontiguousarray(freqs), a32, np.ascontiguousarray(offs),
                t.perm, simplex4_table(t.seed, t.perm), np.float32(norm), np.float32(gain)))
    return out

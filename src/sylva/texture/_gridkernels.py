"""Fast numba paths for noise on regular grids (private; see :mod:`sylva.texture.noise`).

On a grid every sample of a row shares its y (and z) lattice data, and every sample of a
column its x data, so lattice noises (value, classic and improved Perlin) are evaluated
from per-axis tables of lattice indices, fractions and curve weights built once per octave
(:func:`axis_tables`).  The inner loop is left with hashing, gradients and blending.
Improved Perlin and simplex noise split each block of a row into a scalar pass of table
lookups and SIMD passes of arithmetic; Worley noise goes by runs of samples in one cell
(:func:`._cellkernels.worley_row`).  Rows are shared out to the threads in blocks of
:data:`ROWS`; the kernels write float32 or float64 output directly.

Results equal the point-wise kernels of :mod:`._kernels` and :mod:`._cellkernels` bit for
bit (same operations in the same order; ``tests/texture/test_grid_paths.py``).
"""

from __future__ import annotations

import math

import numpy as np
from numba import njit, prange, uint64

from . import _cellkernels as ck
from . import _kernels as k
from ._kernels import _lerp

ROWS = 8  # rows per parallel work item (enough items to balance the threads)
BLOCK = 256  # samples per block of the split passes (the block buffers stay in L1)


@njit(cache=True, fastmath=False)
def _shape(out32, out64):
    """The grid shape: the grid kernels fill ``out32`` (float32) or ``out64`` (float64),
    whichever is not empty, so that one compiled kernel serves both output types."""
    return out32.shape if out32.size > 0 else out64.shape


@njit(cache=True, inline="always")
def _store(out32, out64, m, j, acc, norm):
    """Row ``(m, j)`` of the output: ``acc * norm`` rounded to the output's type."""
    if out32.size > 0:
        for i in range(acc.shape[0]):
            out32[m, j, i] = acc[i] * norm
    else:
        for i in range(acc.shape[0]):
            out64[m, j, i] = acc[i] * norm


@njit(cache=True, inline="always")
def _combine(mode, acc, weight, i, amp, n, gain):
    if mode == k.FBM:
        acc[i] += amp * n
    elif mode == k.TURBULENCE:
        acc[i] += amp * abs(n)
    else:
        s = 1.0 - abs(n)
        s *= s
        s *= weight[i]
        weight[i] = min(max(s * gain, 0.0), 1.0)
        acc[i] += amp * s


@njit(cache=True, fastmath=False)
def axis_tables(coords, freqs, offs, pers, interp):
    """Lattice tables of one axis: ``(i0, i1, frac, curve)``, each of shape (octaves, n).

    ``freqs``, ``offs`` and ``pers`` (integer periods, 0 = none) hold one value per octave.
    """
    no = freqs.shape[0]
    n = coords.shape[0]
    i0 = np.empty((no, n), np.int32)
    i1 = np.empty((no, n), np.int32)
    fr = np.empty((no, n), np.float64)
    cu = np.empty((no, n), np.float64)
    for o in range(no):
        for i in range(n):
            x = coords[i] * freqs[o] + offs[o]
            fx = k._floor(x)
            x -= fx
            i0[o, i] = k._wrap(fx, int(pers[o]))
            i1[o, i] = k._wrap(fx + 1, int(pers[o]))
            fr[o, i] = x
            cu[o, i] = k._curve(x, interp)
    return i0, i1, fr, cu


@njit(cache=True, inline="always")
def _lattice2(kind, p, vals, g2, x0, x1, y0, y1, x, y, u, v):
    # unsigned indices spare numba's negative-index wrap-around checks
    y0 = uint64(y0)
    y1 = uint64(y1)
    a = uint64(p[uint64(x0)])
    b = uint64(p[uint64(x1)])
    h00 = uint64(p[a + y0])
    h10 = uint64(p[b + y0])
    h01 = uint64(p[a + y1])
    h11 = uint64(p[b + y1])
    if kind == k.PERLIN:
        return _lerp(
            v,
            _lerp(u, g2[h00, 0] * x + g2[h00, 1] * y, g2[h10, 0] * (x - 1.0) + g2[h10, 1] * y),
            _lerp(
                u,
                g2[h01, 0] * x + g2[h01, 1] * (y - 1.0),
                g2[h11, 0] * (x - 1.0) + g2[h11, 1] * (y - 1.0),
            ),
        )
    return _lerp(v, _lerp(u, vals[h00], vals[h10]), _lerp(u, vals[h01], vals[h11]))


@njit(cache=True, inline="always")
def _row_lattice2(kind, mode, xt, yt, j, acc, weight, amps, perm, vals, g2, gain):
    """Row ``j`` of 2D lattice noise, summed into ``acc`` (zeroed; ``weight`` all ones)."""
    xi0, xi1, xf, xu = xt
    yi0, yi1, yf, yv = yt
    no, nx = xi0.shape
    for o in range(no):
        y0 = yi0[o, j]
        y1 = yi1[o, j]
        y = yf[o, j]
        v = yv[o, j]
        amp = amps[o]
        for i in range(nx):
            n = _lattice2(
                kind, perm, vals, g2, xi0[o, i], xi1[o, i], y0, y1, xf[o, i], y, xu[o, i], v
            )
            _combine(mode, acc, weight, i, amp, n, gain)


@njit(cache=True, inline="always")
def _lattice3(kind, p, vals, g3, x0, x1, y0, y1, z0, z1, x, y, z, u, v, w):
    if kind == k.PERLIN:
        return k._gcube(p, g3, x0, x1, y0, y1, z0, z1, x, y, z, u, v, w)
    return k._vcube(p, vals, x0, x1, y0, y1, z0, z1, u, v, w)


@njit(cache=True, inline="always")
def _row_lattice3(kind, mode, xt, yt, zt, j, m, acc, weight, amps, perm, vals, g3, gain):
    """Row ``(m, j)`` of 3D lattice noise, summed into ``acc`` (see :func:`_row_lattice2`)."""
    xi0, xi1, xf, xu = xt
    yi0, yi1, yf, yv = yt
    zi0, zi1, zf, zw = zt
    no, nx = xi0.shape
    for o in range(no):
        y0 = yi0[o, j]
        y1 = yi1[o, j]
        y = yf[o, j]
        v = yv[o, j]
        z0 = zi0[o, m]
        z1 = zi1[o, m]
        z = zf[o, m]
        w = zw[o, m]
        amp = amps[o]
        for i in range(nx):
            n = _lattice3(
                kind,
                perm,
                vals,
                g3,
                xi0[o, i],
                xi1[o, i],
                y0,
                y1,
                z0,
                z1,
                xf[o, i],
                y,
                z,
                xu[o, i],
                v,
                w,
            )
            _combine(mode, acc, weight, i, amp, n, gain)


@njit(cache=True, fastmath=False, parallel=True)
def lattice_grid(kind, mode, ndim, xt, yt, zt, out32, out64, amps, perm, vals, g2, g3, norm, gain):
    """Fill ``out32`` or ``out64`` (see :func:`_shape`; shape (nz, ny, nx)) with 2D
    (``nz == 1``) or 3D lattice noise from the axis tables ``xt, yt, zt``; blocks of
    :data:`ROWS` rows in parallel."""
    nz, ny, nx = _shape(out32, out64)
    nrows = ny * nz
    for c in prange((nrows + ROWS - 1) // ROWS):
        # local buffers: stores into them cannot alias the input tables
        acc = np.empty(nx)
        weight = np.empty(nx)
        hb = np.empty((8, BLOCK), np.int64)
        nb = np.empty(BLOCK)
        for r in range(c * ROWS, min(nrows, (c + 1) * ROWS)):
            j = r % ny
            m = r // ny
            acc[:] = 0.0
            weight[:] = 1.0
            if kind == k.IMPROVED:
                _row_improved(mode, ndim, xt, yt, zt, j, m, acc, weight, amps, perm, gain, hb, nb)
            elif ndim == 2:
                _row_lattice2(kind, mode, xt, yt, j, acc, weight, amps, perm, vals, g2, gain)
            else:
                _row_lattice3(kind, mode, xt, yt, zt, j, m, acc, weight, amps, perm, vals, g3, gain)
            _store(out32, out64, m, j, acc, norm)


# ----------------------------------------------------------------------------- improved
# Improved noise in two passes over a block of samples: (1) hash the cell corners (scalar
# table lookups) into gradient indices, (2) the gradient dot products and the blend (SIMD),
# with the gradient's components of ``GRAD16`` read from bit masks instead of a table, so
# that nothing is left to gather.  Same operations in the same order as
# :func:`._kernels.improved2` / :func:`._kernels.improved3`: the values are bit-identical.
def _bits(component, value):
    return sum(1 << h for h in range(16) if k.GRAD16[h, component] == value)


GXP, GXN, GYP, GYN, GZP, GZN = (_bits(c, v) for c in range(3) for v in (1, -1))


@njit(cache=True, inline="always")
def _gm2(h, x, y):
    """``GRAD16[h, 0] * x + GRAD16[h, 1] * y`` with the components from the bit masks."""
    gx = np.float64(((GXP >> h) & 1) - ((GXN >> h) & 1))
    gy = np.float64(((GYP >> h) & 1) - ((GYN >> h) & 1))
    return gx * x + gy * y


@njit(cache=True, inline="always")
def _gm3(h, x, y, z):
    """``GRAD16[h, 0] * x + GRAD16[h, 1] * y + GRAD16[h, 2] * z`` (see :func:`_gm2`)."""
    gx = np.float64(((GXP >> h) & 1) - ((GXN >> h) & 1))
    gy = np.float64(((GYP >> h) & 1) - ((GYN >> h) & 1))
    gz = np.float64(((GZP >> h) & 1) - ((GZN >> h) & 1))
    return gx * x + gy * y + gz * z


@njit(cache=True, fastmath=False)
def _imp_hash(ndim, base, cnt, xi0, xi1, o, p, y0, y1, z0, z1, hb):
    """Gradient indices (``hash & 15``) of the 4 or 8 cell corners of samples base.. into
    ``hb[:, :cnt]`` (x tables of octave ``o``; the row's y and z lattice indices)."""
    b0 = uint64(base)
    y0 = uint64(y0)
    y1 = uint64(y1)
    z0 = uint64(z0)
    z1 = uint64(z1)
    for q in range(cnt):
        i = b0 + uint64(q)
        a = uint64(p[uint64(xi0[o, i])])
        b = uint64(p[uint64(xi1[o, i])])
        aa = uint64(p[a + y0])
        ab = uint64(p[a + y1])
        ba = uint64(p[b + y0])
        bb = uint64(p[b + y1])
        hb[0, q] = p[aa + z0] & 15
        hb[1, q] = p[ba + z0] & 15
        hb[2, q] = p[ab + z0] & 15
        hb[3, q] = p[bb + z0] & 15
        if ndim == 3:
            hb[4, q] = p[aa + z1] & 15
            hb[5, q] = p[ba + z1] & 15
            hb[6, q] = p[ab + z1] & 15
            hb[7, q] = p[bb + z1] & 15


@njit(cache=True, fastmath=False)
def _imp_eval2(base, cnt, xf, xu, o, y, v, hb, nb):
    b0 = uint64(base)
    for q in range(cnt):
        i = b0 + uint64(q)
        x = xf[o, i]
        u = xu[o, i]
        nb[q] = _lerp(
            v,
            _lerp(u, _gm2(hb[0, q], x, y), _gm2(hb[1, q], x - 1, y)),
            _lerp(u, _gm2(hb[2, q], x, y - 1), _gm2(hb[3, q], x - 1, y - 1)),
        )


@njit(cache=True, fastmath=False)
def _imp_eval3(base, cnt, xf, xu, o, y, z, v, w, hb, nb):
    b0 = uint64(base)
    for q in range(cnt):
        i = b0 + uint64(q)
        x = xf[o, i]
        u = xu[o, i]
        g = _gm3
        nb[q] = _lerp(
            w,
            _lerp(
                v,
                _lerp(u, g(hb[0, q], x, y, z), g(hb[1, q], x - 1, y, z)),
                _lerp(u, g(hb[2, q], x, y - 1, z), g(hb[3, q], x - 1, y - 1, z)),
            ),
            _lerp(
                v,
                _lerp(u, g(hb[4, q], x, y, z - 1), g(hb[5, q], x - 1, y, z - 1)),
                _lerp(u, g(hb[6, q], x, y - 1, z - 1), g(hb[7, q], x - 1, y - 1, z - 1)),
            ),
        )


@njit(cache=True, fastmath=False)
def _row_improved(mode, ndim, xt, yt, zt, j, m, acc, weight, amps, perm, gain, hb, nb):
    """Row ``(m, j)`` of 2D or 3D improved noise summed into ``acc`` (``hb``, ``nb``: block
    buffers)."""
    xi0, xi1, xf, xu = xt
    yi0, yi1, yf, yv = yt
    zi0, zi1, zf, zw = zt
    no, nx = xi0.shape
    for o in range(no):
        z0 = zi0[o, m] if ndim == 3 else 0
        z1 = zi1[o, m] if ndim == 3 else 0
        for base in range(0, nx, BLOCK):
            cnt = min(BLOCK, nx - base)
            _imp_hash(ndim, base, cnt, xi0, xi1, o, perm, yi0[o, j], yi1[o, j], z0, z1, hb)
            if ndim == 2:
                _imp_eval2(base, cnt, xf, xu, o, yf[o, j], yv[o, j], hb, nb)
            else:
                _imp_eval3(base, cnt, xf, xu, o, yf[o, j], zf[o, m], yv[o, j], zw[o, m], hb, nb)
            _combine_block(mode, acc, weight, base, cnt, nb, amps[o], gain)


# ----------------------------------------------------------------------------- simplex
# Gustavson's simplex noise split into three passes over a block of samples, so that the
# arithmetic vectorises: (1) skew and locate the simplex (SIMD), (2) hash the corners into
# gradient indices (scalar table lookups), (3) the corner contributions, with the gradient
# components selected arithmetically from the index (SIMD).  Every pass performs the
# operations of :func:`._kernels.simplex2` / :func:`._kernels.simplex3` in the same order,
# so the values are bit-identical; a gradient component chosen by a select is the same
# +1.0, -1.0 or 0.0 as the table entry.


@njit(cache=True, inline="always")
def _gx(g):
    """``GRAD3[g, 0]`` for g in 0..11."""
    return (-1.0 if g & 1 else 1.0) if g < 8 else 0.0


@njit(cache=True, inline="always")
def _gy(g):
    """``GRAD3[g, 1]`` for g in 0..11."""
    if g < 4:
        return -1.0 if g & 2 else 1.0
    if g < 8:
        return 0.0
    return -1.0 if g & 1 else 1.0


@njit(cache=True, inline="always")
def _gz(g):
    """``GRAD3[g, 2]`` for g in 0..11."""
    return (-1.0 if g & 2 else 1.0) if g >= 4 else 0.0


@njit(cache=True, fastmath=False)
def _s2_locate(xs, base, cnt, fx, ox, yin, bx, by, bi, bj, bc):
    for q in range(cnt):
        xin = xs[uint64(base) + uint64(q)] * fx + ox
        s = (xin + yin) * k.F2
        i = math.floor(xin + s)
        j = math.floor(yin + s)
        t = (i + j) * k.G2
        x0 = xin - (i - t)
        y0 = yin - (j - t)
        bx[q] = x0
        by[q] = y0
        bi[q] = i & 255
        bj[q] = j & 255
        bc[q] = 1 if x0 > y0 else 0


@njit(cache=True, fastmath=False)
def _s2_hash(cnt, bi, bj, bc, perm, perm12, g0, g1, g2):
    one = uint64(1)
    for q in range(cnt):
        ii = uint64(bi[q])
        jj = uint64(bj[q])
        i1 = uint64(bc[q])
        g0[q] = perm12[ii + uint64(perm[jj])]
        g1[q] = perm12[ii + i1 + uint64(perm[jj + one - i1])]
        g2[q] = perm12[ii + one + uint64(perm[jj + one])]


@njit(cache=True, fastmath=False)
def _s2_eval(cnt, bx, by, bc, g0, g1, g2, nb):
    for q in range(cnt):
        x0 = bx[q]
        y0 = by[q]
        i1 = bc[q]
        j1 = 1 - i1
        x1 = x0 - i1 + k.G2
        y1 = y0 - j1 + k.G2
        x2 = x0 - 1.0 + 2.0 * k.G2
        y2 = y0 - 1.0 + 2.0 * k.G2
        t0 = max(0.5 - x0 * x0 - y0 * y0, 0.0)
        t1 = max(0.5 - x1 * x1 - y1 * y1, 0.0)
        t2 = max(0.5 - x2 * x2 - y2 * y2, 0.0)
        t0 *= t0
        t1 *= t1
        t2 *= t2
        a = g0[q]
        b = g1[q]
        c = g2[q]
        n = t0 * t0 * (_gx(a) * x0 + _gy(a) * y0)
        n += t1 * t1 * (_gx(b) * x1 + _gy(b) * y1)
        n += t2 * t2 * (_gx(c) * x2 + _gy(c) * y2)
        nb[q] = 70.0 * n


@njit(cache=True, inline="always")
def _corners3(c):
    """The second and third corner offsets of Gustavson's 3D simplex from the comparison
    bits ``c`` = (x0 >= y0) | (y0 >= z0) << 1 | (x0 >= z0) << 2 (see ``simplex3``)."""
    ca = c & 1
    cb = (c >> 1) & 1
    cc = (c >> 2) & 1
    rx = ca + cc
    ry = 1 - ca + cb
    rz = 2 - cb - cc
    return (
        1 if rx >= 2 else 0,
        1 if ry >= 2 else 0,
        1 if rz >= 2 else 0,
        1 if rx >= 1 else 0,
        1 if ry >= 1 else 0,
        1 if rz >= 1 else 0,
    )


@njit(cache=True, fastmath=False)
def _s3_locate(xs, base, cnt, fx, ox, yin, zin, bx, by, bz, bi, bj, bk, bc):
    for q in range(cnt):
        xin = xs[uint64(base) + uint64(q)] * fx + ox
        s = (xin + yin + zin) * k.F3
        i = math.floor(xin + s)
        j = math.floor(yin + s)
        kk = math.floor(zin + s)
        t = (i + j + kk) * k.G3
        x0 = xin - (i - t)
        y0 = yin - (j - t)
        z0 = zin - (kk - t)
        bx[q] = x0
        by[q] = y0
        bz[q] = z0
        bi[q] = i & 255
        bj[q] = j & 255
        bk[q] = kk & 255
        bc[q] = (1 if x0 >= y0 else 0) | (2 if y0 >= z0 else 0) | (4 if x0 >= z0 else 0)


@njit(cache=True, fastmath=False)
def _s3_hash(cnt, bi, bj, bk, bc, perm, perm12, g0, g1, g2, g3):
    one = uint64(1)
    for q in range(cnt):
        i1, j1, k1, i2, j2, k2 = _corners3(bc[q])
        ii = uint64(bi[q])
        jj = uint64(bj[q])
        kk = uint64(bk[q])
        g0[q] = perm12[ii + uint64(perm[jj + uint64(perm[kk])])]
        h1 = uint64(perm[jj + uint64(j1) + uint64(perm[kk + uint64(k1)])])
        g1[q] = perm12[ii + uint64(i1) + h1]
        h2 = uint64(perm[jj + uint64(j2) + uint64(perm[kk + uint64(k2)])])
        g2[q] = perm12[ii + uint64(i2) + h2]
        g3[q] = perm12[ii + one + uint64(perm[jj + one + uint64(perm[kk + one])])]


@njit(cache=True, fastmath=False)
def _s3_eval(cnt, bx, by, bz, bc, g0, g1, g2, g3, nb):
    for q in range(cnt):
        i1, j1, k1, i2, j2, k2 = _corners3(bc[q])
        x0 = bx[q]
        y0 = by[q]
        z0 = bz[q]
        x1 = x0 - i1 + k.G3
        y1 = y0 - j1 + k.G3
        z1 = z0 - k1 + k.G3
        x2 = x0 - i2 + 2.0 * k.G3
        y2 = y0 - j2 + 2.0 * k.G3
        z2 = z0 - k2 + 2.0 * k.G3
        x3 = x0 - 1.0 + 3.0 * k.G3
        y3 = y0 - 1.0 + 3.0 * k.G3
        z3 = z0 - 1.0 + 3.0 * k.G3
        t0 = max(0.6 - x0 * x0 - y0 * y0 - z0 * z0, 0.0)
        t1 = max(0.6 - x1 * x1 - y1 * y1 - z1 * z1, 0.0)
        t2 = max(0.6 - x2 * x2 - y2 * y2 - z2 * z2, 0.0)
        t3 = max(0.6 - x3 * x3 - y3 * y3 - z3 * z3, 0.0)
        t0 *= t0
        t1 *= t1
        t2 *= t2
        t3 *= t3
        a = g0[q]
        b = g1[q]
        c = g2[q]
        d = g3[q]
        n = t0 * t0 * (_gx(a) * x0 + _gy(a) * y0 + _gz(a) * z0)
        n += t1 * t1 * (_gx(b) * x1 + _gy(b) * y1 + _gz(b) * z1)
        n += t2 * t2 * (_gx(c) * x2 + _gy(c) * y2 + _gz(c) * z2)
        n += t3 * t3 * (_gx(d) * x3 + _gy(d) * y3 + _gz(d) * z3)
        nb[q] = 32.0 * n


@njit(cache=True, fastmath=False)
def _combine_block(mode, acc, weight, base, cnt, nb, amp, gain):
    """Add octave values ``nb[:cnt]`` into ``acc[base:base + cnt]`` (see :func:`_combine`)."""
    # unsigned indices: numba's negative-index wrap-around would keep the loops scalar
    b = uint64(base)
    if mode == k.FBM:
        for q in range(cnt):
            acc[b + uint64(q)] += amp * nb[q]
    elif mode == k.TURBULENCE:
        for q in range(cnt):
            acc[b + uint64(q)] += amp * abs(nb[q])
    else:
        for q in range(cnt):
            i = b + uint64(q)
            s = 1.0 - abs(nb[q])
            s *= s
            s *= weight[i]
            weight[i] = min(max(s * gain, 0.0), 1.0)
            acc[i] += amp * s


@njit(cache=True, fastmath=False, nogil=True)
def simplex_grid(c0, c1, ndim, mode, xs, ys, zs, out32, out64, freqs, amps, offs, perm, perm12,
                 norm, gain):
    """Fill blocks ``c0 .. c1`` of :data:`ROWS` rows of ``out32`` or ``out64`` (see
    :func:`_shape`; shape (nz, ny, nx)) with 2D or 3D simplex noise (a 2D image with time is
    3D with ``nz == 1``); octave ``o`` samples ``noise(freqs[o] * p + offs[o])`` like
    :func:`._sampling.fractal_at`."""
    nz, ny, nx = _shape(out32, out64)
    nrows = ny * nz
    for c in range(c0, c1):
        acc = np.empty(nx)
        weight = np.empty(nx)
        bx = np.empty(BLOCK)
        by = np.empty(BLOCK)
        bz = np.empty(BLOCK)
        nb = np.empty(BLOCK)
        bi = np.empty(BLOCK, np.int64)
        bj = np.empty(BLOCK, np.int64)
        bk = np.empty(BLOCK, np.int64)
        bc = np.empty(BLOCK, np.int64)
        g0 = np.empty(BLOCK, np.int64)
        g1 = np.empty(BLOCK, np.int64)
        g2 = np.empty(BLOCK, np.int64)
        g3 = np.empty(BLOCK, np.int64)
        for r in range(c * ROWS, min(nrows, (c + 1) * ROWS)):
            j = r % ny
            m = r // ny
            acc[:] = 0.0
            weight[:] = 1.0
            for o in range(freqs.shape[0]):
                fx = freqs[o, 0]
                ox = offs[o, 0]
                yo = ys[j] * freqs[o, 1] + offs[o, 1]
                zo = zs[m] * freqs[o, 2] + offs[o, 2]
                for base in range(0, nx, BLOCK):
                    cnt = min(BLOCK, nx - base)
                    if ndim == 2:
                        _s2_locate(xs, base, cnt, fx, ox, yo, bx, by, bi, bj, bc)
                        _s2_hash(cnt, bi, bj, bc, perm, perm12, g0, g1, g2)
                        _s2_eval(cnt, bx, by, bc, g0, g1, g2, nb)
                    else:
                        _s3_locate(xs, base, cnt, fx, ox, yo, zo, bx, by, bz, bi, bj, bk, bc)
                        _s3_hash(cnt, bi, bj, bk, bc, perm, perm12, g0, g1, g2, g3)
                        _s3_eval(cnt, bx, by, bz, bc, g0, g1, g2, g3, nb)
                    _combine_block(mode, acc, weight, base, cnt, nb, amps[o], gain)
            _store(out32, out64, m, j, acc, norm)


# ----------------------------------------------------------------------------- Worley
@njit(cache=True, fastmath=False, nogil=True)
def worley_grid(c0, c1, ndim, mode, xs, ys, zs, out32, out64, freqs, amps, offs, pers, wpar,
                norm, gain):
    """Fill blocks ``c0 .. c1`` of :data:`ROWS` rows of ``out32`` or ``out64`` (see
    :func:`_shape`; shape (nz, ny, nx)) with 2D or 3D
    Worley noise, row by row with :func:`._cellkernels.worley_row` (or
    :func:`._cellkernels.worley_poisson_row` when the density ``wpar[7]`` is positive);
    ``wpar`` = (metric, output, jitter, seed, c1, c2, c3, density) as for
    :func:`._sampling.noise_at`."""
    nz, ny, nx = _shape(out32, out64)
    nrows = ny * nz
    metric = int(wpar[0])
    combo = int(wpar[1])
    jitter = wpar[2]
    seed = int(wpar[3])
    density = wpar[7]
    for c in range(c0, c1):
        acc = np.empty(nx)
        weight = np.empty(nx)
        xb = np.empty(nx)
        f1 = np.empty(nx)
        f2 = np.empty(nx)
        f3 = np.empty(nx)
        best = np.empty(nx, np.int64)
        nb = np.empty(nx)
        win = np.empty((5, 3, 9))
        winh = np.empty((3, 9), np.int64)
        slot = np.empty(3, np.int64)
        for r in range(c * ROWS, min(nrows, (c + 1) * ROWS)):
            j = r % ny
            m = r // ny
            acc[:] = 0.0
            weight[:] = 1.0
            for o in range(freqs.shape[0]):
                if density > 0.0:
                    ck.worley_poisson_row(
                        ndim,
                        xs,
                        freqs[o, 0],
                        offs[o, 0],
                        ys[j] * freqs[o, 1] + offs[o, 1],
                        zs[m] * freqs[o, 2] + offs[o, 2],
                        int(pers[o, 0]),
                        int(pers[o, 1]),
                        int(pers[o, 2]),
                        metric,
                        density,
                        seed,
                        combo,
                        wpar[4],
                        wpar[5],
                        wpar[6],
                        nb,
                    )
                    _combine_block(mode, acc, weight, 0, nx, nb, amps[o], gain)
                    continue
                ck.worley_row(
                    ndim,
                    xs,
                    freqs[o, 0],
                    offs[o, 0],
                    ys[j] * freqs[o, 1] + offs[o, 1],
                    zs[m] * freqs[o, 2] + offs[o, 2],
                    int(pers[o, 0]),
                    int(pers[o, 1]),
                    int(pers[o, 2]),
                    metric,
                    jitter,
                    seed,
                    combo,
                    wpar[4],
                    wpar[5],
                    wpar[6],
                    xb,
                    f1,
                    f2,
                    f3,
                    best,
                    nb,
                    win,
                    winh,
                    slot,
                )
                _combine_block(mode, acc, weight, 0, nx, nb, amps[o], gain)
            _store(out32, out64, m, j, acc, norm)

"""Fast numba paths for noise on regular grids (private; see :mod:`sylva.texture.noise`).

On a grid every sample of a row shares its y (and z) lattice data, and every sample of a
column its x data, so lattice noises (value, classic and improved Perlin) are evaluated
from per-axis tables of lattice indices, fractions and curve weights built once per octave
(:func:`axis_tables`).  The inner loop is left with hashing, gradients and blending.
Simplex gets a row loop without the generic dispatch.  Results equal the point-wise
kernels of :mod:`._kernels` (same operations in the same order).
"""

from __future__ import annotations

import numpy as np
from numba import njit, prange, uint64

from . import _kernels as k
from ._kernels import _lerp

# inlined copies of the simplex kernels for the row loops (the point-wise kernels stay
# separate functions, which keeps the generic dispatcher small and quick to compile)
_simplex2 = njit(inline="always")(k.simplex2.py_func)
_simplex3 = njit(inline="always")(k.simplex3.py_func)


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


@njit(cache=True)
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
def _gi2(h, x, y):
    h = uint64(h) & uint64(15)
    return k.GRAD16[h, 0] * x + k.GRAD16[h, 1] * y


@njit(cache=True, inline="always")
def _gi3(h, x, y, z):
    h = uint64(h) & uint64(15)
    return k.GRAD16[h, 0] * x + k.GRAD16[h, 1] * y + k.GRAD16[h, 2] * z


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
    if kind == k.IMPROVED:
        return _lerp(v, _lerp(u, _gi2(p[h00], x, y), _gi2(p[h10], x - 1, y)),
                     _lerp(u, _gi2(p[h01], x, y - 1), _gi2(p[h11], x - 1, y - 1)))
    if kind == k.PERLIN:
        return _lerp(v, _lerp(u, g2[h00, 0] * x + g2[h00, 1] * y,
                              g2[h10, 0] * (x - 1.0) + g2[h10, 1] * y),
                     _lerp(u, g2[h01, 0] * x + g2[h01, 1] * (y - 1.0),
                           g2[h11, 0] * (x - 1.0) + g2[h11, 1] * (y - 1.0)))
    return _lerp(v, _lerp(u, vals[h00], vals[h10]), _lerp(u, vals[h01], vals[h11]))


@njit(cache=True, inline="always")
def _row_lattice2(kind, mode, xt, yt, j, row, amps, perm, vals, g2, gain):
    """Row ``j`` of 2D lattice noise into ``row``."""
    xi0, xi1, xf, xu = xt
    yi0, yi1, yf, yv = yt
    no, nx = xi0.shape
    weight = np.ones(nx)
    acc = np.zeros(nx)  # a local buffer: stores into it cannot alias the input tables
    for o in range(no):
        y0 = yi0[o, j]
        y1 = yi1[o, j]
        y = yf[o, j]
        v = yv[o, j]
        amp = amps[o]
        for i in range(nx):
            n = _lattice2(kind, perm, vals, g2, xi0[o, i], xi1[o, i], y0, y1, xf[o, i], y,
                          xu[o, i], v)
            _combine(mode, acc, weight, i, amp, n, gain)
    row[:] = acc


@njit(cache=True, inline="always")
def _lattice3(kind, p, vals, g3, x0, x1, y0, y1, z0, z1, x, y, z, u, v, w):
    if kind == k.IMPROVED:
        y0 = uint64(y0)
        y1 = uint64(y1)
        z0 = uint64(z0)
        z1 = uint64(z1)
        a = uint64(p[uint64(x0)])
        b = uint64(p[uint64(x1)])
        aa = uint64(p[a + y0])
        ab = uint64(p[a + y1])
        ba = uint64(p[b + y0])
        bb = uint64(p[b + y1])
        g = _gi3
        return _lerp(
            w,
            _lerp(v, _lerp(u, g(p[aa + z0], x, y, z), g(p[ba + z0], x - 1, y, z)),
                  _lerp(u, g(p[ab + z0], x, y - 1, z), g(p[bb + z0], x - 1, y - 1, z))),
            _lerp(v, _lerp(u, g(p[aa + z1], x, y, z - 1), g(p[ba + z1], x - 1, y, z - 1)),
                  _lerp(u, g(p[ab + z1], x, y - 1, z - 1), g(p[bb + z1], x - 1, y - 1, z - 1))),
        )
    if kind == k.PERLIN:
        return k._gcube(p, g3, x0, x1, y0, y1, z0, z1, x, y, z, u, v, w)
    return k._vcube(p, vals, x0, x1, y0, y1, z0, z1, u, v, w)


@njit(cache=True, inline="always")
def _row_lattice3(kind, mode, xt, yt, zt, j, m, row, amps, perm, vals, g3, gain):
    """Row ``(m, j)`` of 3D lattice noise into ``row``."""
    xi0, xi1, xf, xu = xt
    yi0, yi1, yf, yv = yt
    zi0, zi1, zf, zw = zt
    no, nx = xi0.shape
    weight = np.ones(nx)
    acc = np.zeros(nx)  # a local buffer: stores into it cannot alias the input tables
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
            n = _lattice3(kind, perm, vals, g3, xi0[o, i], xi1[o, i], y0, y1, z0, z1,
                          xf[o, i], y, z, xu[o, i], v, w)
            _combine(mode, acc, weight, i, amp, n, gain)
    row[:] = acc


@njit(cache=True, inline="always")
def _row_simplex(mode, ndim, xs, y, z, row, freqs, amps, offs, perm, perm12, gain):
    """One row of 2D or 3D simplex noise; ``y``/``z`` are the row's base coordinates."""
    nx = xs.shape[0]
    weight = np.ones(nx)
    acc = np.zeros(nx)  # a local buffer: stores into it cannot alias the input tables
    for o in range(freqs.shape[0]):
        fx = freqs[o, 0]
        yo = y * freqs[o, 1] + offs[o, 1]
        zo = z * freqs[o, 2] + offs[o, 2]
        ox = offs[o, 0]
        amp = amps[o]
        if ndim == 2:
            for i in range(nx):
                n = _simplex2(xs[i] * fx + ox, yo, perm, perm12)
                _combine(mode, acc, weight, i, amp, n, gain)
        else:
            for i in range(nx):
                n = _simplex3(xs[i] * fx + ox, yo, zo, perm, perm12)
                _combine(mode, acc, weight, i, amp, n, gain)
    row[:] = acc


LATTICE2, LATTICE3, SIMPLEX = 0, 1, 2


@njit(cache=True, parallel=True)
def fast_grid(path, kind, mode, ndim, xt, yt, zt, xs, ys, zs, out, freqs, amps, offs, perm,
              perm12, vals, g2, g3, norm, gain):
    """Fill ``out[nz, ny, nx]`` row by row (rows in parallel).

    ``path``: LATTICE2 / LATTICE3 use the axis tables ``xt, yt, zt``; SIMPLEX uses the
    coordinates ``xs, ys, zs`` with per-octave ``freqs`` and ``offs``.
    """
    nz, ny, nx = out.shape
    for r in prange(ny * nz):
        j = r % ny
        m = r // ny
        row = np.empty(nx)
        if path == LATTICE2:
            _row_lattice2(kind, mode, xt, yt, j, row, amps, perm, vals, g2, gain)
        elif path == LATTICE3:
            _row_lattice3(kind, mode, xt, yt, zt, j, m, row, amps, perm, vals, g3, gain)
        else:
            _row_simplex(mode, ndim, xs, ys[j], zs[m], row, freqs, amps, offs, perm, perm12,
                         gain)
        for i in range(nx):
            out[m, j, i] = row[i] * norm

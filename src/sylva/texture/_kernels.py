"""Numba kernels behind :mod:`sylva.texture.noise` and :mod:`sylva.texture.cellular`.

Private module: nothing here checks its inputs.  The public layer builds the tables and
per-octave arrays, validates shapes and dtypes, and documents the behaviour.

Every noise is evaluated in float64 (the reference values are double precision); the
result is stored into the output array's dtype (float32 or float64).

Noise kinds (``kind``): 0 value, 1 classic Perlin (1985), 2 improved Perlin (2002),
3 simplex (Gustavson 2012), 4 Worley cellular.
Fractal modes (``mode``): 0 fBm (a single octave is plain noise), 1 turbulence
(sum of |noise|), 2 ridged multifractal (Musgrave).
Interpolation curves (``interp``): 0 linear, 1 cosine, 2 cubic 3t^2-2t^3,
3 quintic 6t^5-15t^4+10t^3.
"""

from __future__ import annotations

import math

import numpy as np
from numba import njit, uint64

VALUE, PERLIN, IMPROVED, SIMPLEX, WORLEY = 0, 1, 2, 3, 4
FBM, TURBULENCE, RIDGED = 0, 1, 2

F2 = 0.5 * (math.sqrt(3.0) - 1.0)
G2 = (3.0 - math.sqrt(3.0)) / 6.0
F3 = 1.0 / 3.0
G3 = 1.0 / 6.0
F4 = (math.sqrt(5.0) - 1.0) / 4.0
G4 = (5.0 - math.sqrt(5.0)) / 20.0
TWO_PI = 2.0 * math.pi

GRAD3 = np.array(
    [[1, 1, 0], [-1, 1, 0], [1, -1, 0], [-1, -1, 0], [1, 0, 1], [-1, 0, 1], [1, 0, -1],
     [-1, 0, -1], [0, 1, 1], [0, -1, 1], [0, 1, -1], [0, -1, -1]],
    dtype=np.float64,
)
GRAD4 = np.array(
    [[0, 1, 1, 1], [0, 1, 1, -1], [0, 1, -1, 1], [0, 1, -1, -1], [0, -1, 1, 1], [0, -1, 1, -1],
     [0, -1, -1, 1], [0, -1, -1, -1], [1, 0, 1, 1], [1, 0, 1, -1], [1, 0, -1, 1], [1, 0, -1, -1],
     [-1, 0, 1, 1], [-1, 0, 1, -1], [-1, 0, -1, 1], [-1, 0, -1, -1], [1, 1, 0, 1], [1, 1, 0, -1],
     [1, -1, 0, 1], [1, -1, 0, -1], [-1, 1, 0, 1], [-1, 1, 0, -1], [-1, -1, 0, 1], [-1, -1, 0, -1],
     [1, 1, 1, 0], [1, 1, -1, 0], [1, -1, 1, 0], [1, -1, -1, 0], [-1, 1, 1, 0], [-1, 1, -1, 0],
     [-1, -1, 1, 0], [-1, -1, -1, 0]],
    dtype=np.float64,
)

# gradient components as separate vectors (faster lookups in the kernels)
G3X = np.ascontiguousarray(GRAD3[:, 0])
G3Y = np.ascontiguousarray(GRAD3[:, 1])
G3Z = np.ascontiguousarray(GRAD3[:, 2])
G4X = np.ascontiguousarray(GRAD4[:, 0])
G4Y = np.ascontiguousarray(GRAD4[:, 1])
G4Z = np.ascontiguousarray(GRAD4[:, 2])
G4W = np.ascontiguousarray(GRAD4[:, 3])


# ----------------------------------------------------------------------------- helpers
@njit(cache=True, inline="always")
def _floor(x):
    return math.floor(x)  # an integer in numba, like Java's fastfloor for finite x


@njit(cache=True, inline="always")
def _wrap(i, period):
    """Lattice coordinate ``i`` reduced by ``period`` (0 = none), then to 0..255."""
    if period > 0:
        i = i % period
    return i & 255


@njit(cache=True, inline="always")
def _curve(t, interp):
    if interp == 3:
        return t * t * t * (t * (t * 6.0 - 15.0) + 10.0)
    if interp == 2:
        return t * t * (3.0 - 2.0 * t)
    if interp == 1:
        return (1.0 - math.cos(math.pi * t)) * 0.5
    return t


@njit(cache=True, inline="always")
def _lerp(t, a, b):
    return a + t * (b - a)


# Perlin's ``grad(hash, x, y, z)`` as a table: entry h holds the coefficients of x, y, z.
# ``(gx*x + gy*y) + gz*z`` equals the reference ``(±u) + (±v)`` exactly, because the
# coefficients are ±1 or 0 and adding a zero product changes no bit of a non-zero sum.
GRAD16 = np.array(
    [[1, 1, 0], [-1, 1, 0], [1, -1, 0], [-1, -1, 0], [1, 0, 1], [-1, 0, 1], [1, 0, -1],
     [-1, 0, -1], [0, 1, 1], [0, -1, 1], [0, 1, -1], [0, -1, -1], [1, 1, 0], [0, -1, 1],
     [-1, 1, 0], [0, -1, -1]],
    dtype=np.float64,
)


@njit(cache=True, inline="always")
def _grad_improved(h, x, y, z):
    h = h & 15
    return GRAD16[h, 0] * x + GRAD16[h, 1] * y + GRAD16[h, 2] * z


@njit(cache=True, inline="always")
def _grad_improved2(h, x, y):
    h = h & 15
    return GRAD16[h, 0] * x + GRAD16[h, 1] * y


# ----------------------------------------------------------------------------- value noise
@njit(cache=True, fastmath=False)
def value2(x, y, px, py, interp, perm, vals):
    fx = _floor(x)
    fy = _floor(y)
    x -= fx
    y -= fy
    x0 = _wrap(fx, px)
    x1 = _wrap(fx + 1, px)
    y0 = _wrap(fy, py)
    y1 = _wrap(fy + 1, py)
    u = _curve(x, interp)
    v = _curve(y, interp)
    a = perm[x0]
    b = perm[x1]
    return _lerp(v, _lerp(u, vals[perm[a + y0]], vals[perm[b + y0]]),
                 _lerp(u, vals[perm[a + y1]], vals[perm[b + y1]]))


@njit(cache=True, inline="always")
def _vcube(perm, vals, h0, h1, y0, y1, z0, z1, u, v, w):
    """Trilinear blend of the lattice values of one cube (``h0``/``h1`` hash x0/x1 so far)."""
    a0 = perm[h0]
    a1 = perm[h1]
    b00 = perm[a0 + y0]
    b10 = perm[a1 + y0]
    b01 = perm[a0 + y1]
    b11 = perm[a1 + y1]
    return _lerp(w, _lerp(v, _lerp(u, vals[perm[b00 + z0]], vals[perm[b10 + z0]]),
                          _lerp(u, vals[perm[b01 + z0]], vals[perm[b11 + z0]])),
                 _lerp(v, _lerp(u, vals[perm[b00 + z1]], vals[perm[b10 + z1]]),
                       _lerp(u, vals[perm[b01 + z1]], vals[perm[b11 + z1]])))


@njit(cache=True, fastmath=False)
def value3(x, y, z, px, py, pz, interp, perm, vals):
    fx = _floor(x)
    fy = _floor(y)
    fz = _floor(z)
    x -= fx
    y -= fy
    z -= fz
    return _vcube(perm, vals, _wrap(fx, px), _wrap(fx + 1, px), _wrap(fy, py),
                  _wrap(fy + 1, py), _wrap(fz, pz), _wrap(fz + 1, pz),
                  _curve(x, interp), _curve(y, interp), _curve(z, interp))


@njit(cache=True, fastmath=False)
def value4(x, y, z, w, px, py, pz, pw, interp, perm, vals):
    fx = _floor(x)
    fy = _floor(y)
    fz = _floor(z)
    fw = _floor(w)
    x -= fx
    y -= fy
    z -= fz
    w -= fw
    x0 = _wrap(fx, px)
    x1 = _wrap(fx + 1, px)
    y0 = _wrap(fy, py)
    y1 = _wrap(fy + 1, py)
    z0 = _wrap(fz, pz)
    z1 = _wrap(fz + 1, pz)
    w0 = _wrap(fw, pw)
    w1 = _wrap(fw + 1, pw)
    u = _curve(x, interp)
    v = _curve(y, interp)
    t = _curve(z, interp)
    # the w axis is hashed first: h = perm[w] + x, then y, then z
    c0 = _vcube(perm, vals, perm[w0] + x0, perm[w0] + x1, y0, y1, z0, z1, u, v, t)
    c1 = _vcube(perm, vals, perm[w1] + x0, perm[w1] + x1, y0, y1, z0, z1, u, v, t)
    return _lerp(_curve(w, interp), c0, c1)


# ----------------------------------------------------------------------------- classic Perlin
@njit(cache=True, fastmath=False)
def perlin2(x, y, px, py, interp, perm, g2):
    fx = _floor(x)
    fy = _floor(y)
    x -= fx
    y -= fy
    x0 = _wrap(fx, px)
    x1 = _wrap(fx + 1, px)
    y0 = _wrap(fy, py)
    y1 = _wrap(fy + 1, py)
    a = perm[x0]
    b = perm[x1]
    h00 = perm[a + y0]
    h10 = perm[b + y0]
    h01 = perm[a + y1]
    h11 = perm[b + y1]
    n00 = g2[h00, 0] * x + g2[h00, 1] * y
    n10 = g2[h10, 0] * (x - 1.0) + g2[h10, 1] * y
    n01 = g2[h01, 0] * x + g2[h01, 1] * (y - 1.0)
    n11 = g2[h11, 0] * (x - 1.0) + g2[h11, 1] * (y - 1.0)
    u = _curve(x, interp)
    v = _curve(y, interp)
    return _lerp(v, _lerp(u, n00, n10), _lerp(u, n01, n11))


@njit(cache=True, inline="always")
def _g3(g, h, x, y, z):
    return g[h, 0] * x + g[h, 1] * y + g[h, 2] * z


@njit(cache=True, inline="always")
def _gcube(perm, g, h0, h1, y0, y1, z0, z1, x, y, z, u, v, w):
    """Trilinear blend of gradient dot products over one cube (classic Perlin, 3D table)."""
    a0 = perm[h0]
    a1 = perm[h1]
    b00 = perm[a0 + y0]
    b10 = perm[a1 + y0]
    b01 = perm[a0 + y1]
    b11 = perm[a1 + y1]
    return _lerp(
        w,
        _lerp(v, _lerp(u, _g3(g, perm[b00 + z0], x, y, z), _g3(g, perm[b10 + z0], x - 1, y, z)),
              _lerp(u, _g3(g, perm[b01 + z0], x, y - 1, z),
                    _g3(g, perm[b11 + z0], x - 1, y - 1, z))),
        _lerp(v, _lerp(u, _g3(g, perm[b00 + z1], x, y, z - 1),
                       _g3(g, perm[b10 + z1], x - 1, y, z - 1)),
              _lerp(u, _g3(g, perm[b01 + z1], x, y - 1, z - 1),
                    _g3(g, perm[b11 + z1], x - 1, y - 1, z - 1))),
    )


@njit(cache=True, fastmath=False)
def perlin3(x, y, z, px, py, pz, interp, perm, g3):
    fx = _floor(x)
    fy = _floor(y)
    fz = _floor(z)
    x -= fx
    y -= fy
    z -= fz
    return _gcube(perm, g3, _wrap(fx, px), _wrap(fx + 1, px), _wrap(fy, py), _wrap(fy + 1, py),
                  _wrap(fz, pz), _wrap(fz + 1, pz), x, y, z,
                  _curve(x, interp), _curve(y, interp), _curve(z, interp))


@njit(cache=True, inline="always")
def _g4(g, h, x, y, z, w):
    return g[h, 0] * x + g[h, 1] * y + g[h, 2] * z + g[h, 3] * w


@njit(cache=True, fastmath=False)
def _gcube4(perm, g, mask, wh, y0, y1, z0, z1, x0, x1, x, y, z, w, u, v, t):
    """One w-slice (a cube) of 4D gradient noise; ``wh = perm[w index]``."""
    a0 = perm[wh + x0]
    a1 = perm[wh + x1]
    b00 = perm[a0 + y0]
    b10 = perm[a1 + y0]
    b01 = perm[a0 + y1]
    b11 = perm[a1 + y1]
    return _lerp(
        t,
        _lerp(v, _lerp(u, _g4(g, perm[b00 + z0] & mask, x, y, z, w),
                       _g4(g, perm[b10 + z0] & mask, x - 1, y, z, w)),
              _lerp(u, _g4(g, perm[b01 + z0] & mask, x, y - 1, z, w),
                    _g4(g, perm[b11 + z0] & mask, x - 1, y - 1, z, w))),
        _lerp(v, _lerp(u, _g4(g, perm[b00 + z1] & mask, x, y, z - 1, w),
                       _g4(g, perm[b10 + z1] & mask, x - 1, y, z - 1, w)),
              _lerp(u, _g4(g, perm[b01 + z1] & mask, x, y - 1, z - 1, w),
                    _g4(g, perm[b11 + z1] & mask, x - 1, y - 1, z - 1, w))),
    )


@njit(cache=True, fastmath=False)
def _grad4d(x, y, z, w, px, py, pz, pw, interp, perm, g, mask):
    fx = _floor(x)
    fy = _floor(y)
    fz = _floor(z)
    fw = _floor(w)
    x -= fx
    y -= fy
    z -= fz
    w -= fw
    x0 = _wrap(fx, px)
    x1 = _wrap(fx + 1, px)
    y0 = _wrap(fy, py)
    y1 = _wrap(fy + 1, py)
    z0 = _wrap(fz, pz)
    z1 = _wrap(fz + 1, pz)
    u = _curve(x, interp)
    v = _curve(y, interp)
    t = _curve(z, interp)
    c0 = _gcube4(perm, g, mask, perm[_wrap(fw, pw)], y0, y1, z0, z1, x0, x1, x, y, z, w, u, v, t)
    c1 = _gcube4(perm, g, mask, perm[_wrap(fw + 1, pw)], y0, y1, z0, z1, x0, x1, x, y, z,
                 w - 1, u, v, t)
    return _lerp(_curve(w, interp), c0, c1)


@njit(cache=True, fastmath=False)
def perlin4(x, y, z, w, px, py, pz, pw, interp, perm, g4):
    return _grad4d(x, y, z, w, px, py, pz, pw, interp, perm, g4, np.int64(255))


# ----------------------------------------------------------------------------- improved Perlin
@njit(cache=True, fastmath=False)
def improved3(x, y, z, px, py, pz, interp, p):
    """Perlin's 2002 reference ``ImprovedNoise.noise`` (bit-exact with the default tables)."""
    fx = _floor(x)
    fy = _floor(y)
    fz = _floor(z)
    x -= fx
    y -= fy
    z -= fz
    x0 = _wrap(fx, px)
    x1 = _wrap(fx + 1, px)
    y0 = _wrap(fy, py)
    y1 = _wrap(fy + 1, py)
    z0 = _wrap(fz, pz)
    z1 = _wrap(fz + 1, pz)
    u = _curve(x, interp)
    v = _curve(y, interp)
    w = _curve(z, interp)
    a = p[x0]
    b = p[x1]
    aa = p[a + y0]
    ab = p[a + y1]
    ba = p[b + y0]
    bb = p[b + y1]
    return _lerp(
        w,
        _lerp(v, _lerp(u, _grad_improved(p[aa + z0], x, y, z),
                       _grad_improved(p[ba + z0], x - 1, y, z)),
              _lerp(u, _grad_improved(p[ab + z0], x, y - 1, z),
                    _grad_improved(p[bb + z0], x - 1, y - 1, z))),
        _lerp(v, _lerp(u, _grad_improved(p[aa + z1], x, y, z - 1),
                       _grad_improved(p[ba + z1], x - 1, y, z - 1)),
              _lerp(u, _grad_improved(p[ab + z1], x, y - 1, z - 1),
                    _grad_improved(p[bb + z1], x - 1, y - 1, z - 1))),
    )


@njit(cache=True, fastmath=False)
def improved2(x, y, px, py, interp, p):
    """``improved3(x, y, 0)`` with the four z=1 corners skipped (their weight is exactly 0)."""
    fx = _floor(x)
    fy = _floor(y)
    x -= fx
    y -= fy
    x0 = _wrap(fx, px)
    x1 = _wrap(fx + 1, px)
    y0 = _wrap(fy, py)
    y1 = _wrap(fy + 1, py)
    u = _curve(x, interp)
    v = _curve(y, interp)
    a = p[x0]
    b = p[x1]
    z0 = 0
    aa = p[a + y0]
    ab = p[a + y1]
    ba = p[b + y0]
    bb = p[b + y1]
    return _lerp(v, _lerp(u, _grad_improved2(p[aa + z0], x, y),
                          _grad_improved2(p[ba + z0], x - 1, y)),
                 _lerp(u, _grad_improved2(p[ab + z0], x, y - 1),
                       _grad_improved2(p[bb + z0], x - 1, y - 1)))


@njit(cache=True, fastmath=False)
def improved4(x, y, z, w, px, py, pz, pw, interp, p, g4):
    """4D extension of improved noise: the 32 hypercube-edge gradients of Gustavson's table
    (``hash & 31``), the hash taken over w first."""
    return _grad4d(x, y, z, w, px, py, pz, pw, interp, p, g4, np.int64(31))


# ----------------------------------------------------------------------------- simplex
@njit(cache=True, fastmath=False)
def simplex2(xin, yin, perm, perm12):
    """Gustavson's SimplexNoise.java (2012) ``noise(x, y)``.

    Same arithmetic in the same order; corners outside the kernel radius contribute
    ``0.0`` through ``max(t, 0)`` instead of a branch, which leaves the sum unchanged.
    """
    s = (xin + yin) * F2
    i = _floor(xin + s)
    j = _floor(yin + s)
    t = (i + j) * G2
    x0 = xin - (i - t)
    y0 = yin - (j - t)
    i1 = 1 if x0 > y0 else 0
    j1 = 1 - i1
    x1 = x0 - i1 + G2
    y1 = y0 - j1 + G2
    x2 = x0 - 1.0 + 2.0 * G2
    y2 = y0 - 1.0 + 2.0 * G2
    # unsigned indices spare numba's negative-index wrap-around checks
    ii = uint64(i & 255)
    jj = uint64(j & 255)
    g0 = uint64(perm12[ii + uint64(perm[jj])])
    g1 = uint64(perm12[ii + uint64(i1) + uint64(perm[jj + uint64(j1)])])
    g2 = uint64(perm12[ii + uint64(1) + uint64(perm[jj + uint64(1)])])
    t0 = max(0.5 - x0 * x0 - y0 * y0, 0.0)
    t1 = max(0.5 - x1 * x1 - y1 * y1, 0.0)
    t2 = max(0.5 - x2 * x2 - y2 * y2, 0.0)
    t0 *= t0
    t1 *= t1
    t2 *= t2
    n = t0 * t0 * (G3X[g0] * x0 + G3Y[g0] * y0)
    n += t1 * t1 * (G3X[g1] * x1 + G3Y[g1] * y1)
    n += t2 * t2 * (G3X[g2] * x2 + G3Y[g2] * y2)
    return 70.0 * n


@njit(cache=True, fastmath=False)
def simplex3(xin, yin, zin, perm, perm12):
    """Gustavson's SimplexNoise.java (2012) ``noise(x, y, z)``."""
    s = (xin + yin + zin) * F3
    i = _floor(xin + s)
    j = _floor(yin + s)
    k = _floor(zin + s)
    t = (i + j + k) * G3
    x0 = xin - (i - t)
    y0 = yin - (j - t)
    z0 = zin - (k - t)
    # Gustavson's six-way choice of the simplex, branch-free: the same three comparisons
    # rank x0, y0, z0 (2 = largest), which picks the same corners in every case, ties too
    ca = 1 if x0 >= y0 else 0
    cb = 1 if y0 >= z0 else 0
    cc = 1 if x0 >= z0 else 0
    rx = ca + cc
    ry = 1 - ca + cb
    rz = 2 - cb - cc
    i1 = 1 if rx >= 2 else 0
    j1 = 1 if ry >= 2 else 0
    k1 = 1 if rz >= 2 else 0
    i2 = 1 if rx >= 1 else 0
    j2 = 1 if ry >= 1 else 0
    k2 = 1 if rz >= 1 else 0
    x1 = x0 - i1 + G3
    y1 = y0 - j1 + G3
    z1 = z0 - k1 + G3
    x2 = x0 - i2 + 2.0 * G3
    y2 = y0 - j2 + 2.0 * G3
    z2 = z0 - k2 + 2.0 * G3
    x3 = x0 - 1.0 + 3.0 * G3
    y3 = y0 - 1.0 + 3.0 * G3
    z3 = z0 - 1.0 + 3.0 * G3
    ii = uint64(i & 255)
    jj = uint64(j & 255)
    kk = uint64(k & 255)
    one = uint64(1)
    g0 = uint64(perm12[ii + uint64(perm[jj + uint64(perm[kk])])])
    h1 = uint64(perm[jj + uint64(j1) + uint64(perm[kk + uint64(k1)])])
    g1 = uint64(perm12[ii + uint64(i1) + h1])
    h2 = uint64(perm[jj + uint64(j2) + uint64(perm[kk + uint64(k2)])])
    g2 = uint64(perm12[ii + uint64(i2) + h2])
    g3 = uint64(perm12[ii + one + uint64(perm[jj + one + uint64(perm[kk + one])])])
    t0 = max(0.6 - x0 * x0 - y0 * y0 - z0 * z0, 0.0)
    t1 = max(0.6 - x1 * x1 - y1 * y1 - z1 * z1, 0.0)
    t2 = max(0.6 - x2 * x2 - y2 * y2 - z2 * z2, 0.0)
    t3 = max(0.6 - x3 * x3 - y3 * y3 - z3 * z3, 0.0)
    t0 *= t0
    t1 *= t1
    t2 *= t2
    t3 *= t3
    n = t0 * t0 * (G3X[g0] * x0 + G3Y[g0] * y0 + G3Z[g0] * z0)
    n += t1 * t1 * (G3X[g1] * x1 + G3Y[g1] * y1 + G3Z[g1] * z1)
    n += t2 * t2 * (G3X[g2] * x2 + G3Y[g2] * y2 + G3Z[g2] * z2)
    n += t3 * t3 * (G3X[g3] * x3 + G3Y[g3] * y3 + G3Z[g3] * z3)
    return 32.0 * n


@njit(cache=True, inline="always")
def _s4corner(x, y, z, w, g):
    t = max(0.6 - x * x - y * y - z * z - w * w, 0.0)
    t *= t
    return t * t * (G4X[g] * x + G4Y[g] * y + G4Z[g] * z + G4W[g] * w)
@njit(cache=True, fastmath=False)
def simplex4(x, y, z, w, perm):
    """Gustavson's SimplexNoise.java (2012, rank ordering) ``noise(x, y, z, w)``."""
    s = (x + y + z + w) * F4
    i = _floor(x + s)
    j = _floor(y + s)
    k = _floor(z + s)
    l = _floor(w + s)
    t = (i + j + k + l) * G4
    x0 = x - (i - t)
    y0 = y - (j - t)
    z0 = z - (k - t)
    w0 = w - (l - t)
    rx = 0
    ry = 0
    rz = 0
    rw = 0
    if x0 > y0:
        rx += 1
    else:
        ry += 1
    if x0 > z0:
        rx += 1
    else:
        rz += 1
    if x0 > w0:
        rx += 1
    else:
        rw += 1
    if y0 > z0:
        ry += 1
    else:
        rz += 1
    if y0 > w0:
        ry += 1
    else:
        rw += 1
    if z0 > w0:
        rz += 1
    else:
        rw += 1
    i1 = 1 if rx >= 3 else 0
    j1 = 1 if ry >= 3 else 0
    k1 = 1 if rz >= 3 else 0
    l1 = 1 if rw >= 3 else 0
    i2 = 1 if rx >= 2 else 0
    j2 = 1 if ry >= 2 else 0
    k2 = 1 if rz >= 2 else 0
    l2 = 1 if rw >= 2 else 0
    i3 = 1 if rx >= 1 else 0
    j3 = 1 if ry >= 1 else 0
    k3 = 1 if rz >= 1 else 0
    l3 = 1 if rw >= 1 else 0
    ii = i & 255
    jj = j & 255
    kk = k & 255
    ll = l & 255
    g0 = perm[ii + perm[jj + perm[kk + perm[ll]]]] % 32
    g1 = perm[ii + i1 + perm[jj + j1 + perm[kk + k1 + perm[ll + l1]]]] % 32
    g2 = perm[ii + i2 + perm[jj + j2 + perm[kk + k2 + perm[ll + l2]]]] % 32
    g3 = perm[ii + i3 + perm[jj + j3 + perm[kk + k3 + perm[ll + l3]]]] % 32
    g4 = perm[ii + 1 + perm[jj + 1 + perm[kk + 1 + perm[ll + 1]]]] % 32
    n = _s4corner(x0, y0, z0, w0, g0)
    n += _s4corner(x0 - i1 + G4, y0 - j1 + G4, z0 - k1 + G4, w0 - l1 + G4, g1)
    n += _s4corner(x0 - i2 + 2.0 * G4, y0 - j2 + 2.0 * G4, z0 - k2 + 2.0 * G4,
                   w0 - l2 + 2.0 * G4, g2)
    n += _s4corner(x0 - i3 + 3.0 * G4, y0 - j3 + 3.0 * G4, z0 - k3 + 3.0 * G4,
                   w0 - l3 + 3.0 * G4, g3)
    n += _s4corner(x0 - 1.0 + 4.0 * G4, y0 - 1.0 + 4.0 * G4, z0 - 1.0 + 4.0 * G4,
                   w0 - 1.0 + 4.0 * G4, g4)
    return 27.0 * n


class _ArrayMath:
    """``math`` as the lattice noises above use it (``floor``, ``cos``, ``pi``), on NumPy
    arrays: with it in place of ``math`` (:data:`_INTERPRETED`), their Python source,
    which is otherwise arithmetic and table indexing, evaluates whole arrays of coordinates
    at once (:func:`sylva.texture._gridplan.fractal_arrays`; value, classic and improved
    Perlin only: simplex branches on each coordinate)."""

    pi = math.pi
    cos = staticmethod(np.cos)

    @staticmethod
    def floor(x):
        return np.floor(x).astype(np.int64)


#: What :func:`sylva._jit.interpreted` puts in this module's copy.
_INTERPRETED = {"math": "_ArrayMath"}

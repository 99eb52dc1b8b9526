"""Numba helpers the generated graph kernels call per sample (private).

Each is the definition written in :data:`._nodes.NODE_TYPES` (libnoise's Curve, Terrace,
Select and Exponent; Mystica's blend modes; piecewise-linear gradients).
"""

from __future__ import annotations

import math

from numba import njit

BLEND = {"normal": 0, "multiply": 1, "screen": 2, "overlay": 3, "difference": 4, "add": 5,
         "subtract": 6, "darken": 7, "lighten": 8, "hard-light": 9, "soft-light": 10}


@njit(cache=True, inline="always")
def cubic(n0, n1, n2, n3, a):
    """libnoise's cubic interpolation of n1..n2 with outer points n0, n3."""
    p = (n3 - n2) - (n0 - n1)
    q = (n0 - n1) - p
    r = n2 - n0
    return p * a * a * a + q * a * a + r * a + n1


@njit(cache=True)
def curve(v, pts):
    """libnoise Curve: ``pts[k] = (input, output)`` sorted by input, at least 4."""
    n = pts.shape[0]
    pos = 0
    while pos < n and v >= pts[pos, 0]:
        pos += 1
    i0 = min(max(pos - 2, 0), n - 1)
    i1 = min(max(pos - 1, 0), n - 1)
    i2 = min(max(pos, 0), n - 1)
    i3 = min(max(pos + 1, 0), n - 1)
    if i1 == i2:
        return pts[i1, 1]
    x0 = pts[i1, 0]
    x1 = pts[i2, 0]
    a = (v - x0) / (x1 - x0)
    return cubic(pts[i0, 1], pts[i1, 1], pts[i2, 1], pts[i3, 1], a)


@njit(cache=True)
def terrace(v, pts, invert):
    """libnoise Terrace: ``pts`` sorted terrace heights (at least 2)."""
    n = pts.shape[0]
    pos = 0
    while pos < n and v >= pts[pos]:
        pos += 1
    i0 = min(max(pos - 1, 0), n - 1)
    i1 = min(max(pos, 0), n - 1)
    if i0 == i1:
        return pts[i1]
    a0 = pts[i0]
    a1 = pts[i1]
    s = (v - a0) / (a1 - a0)
    if invert:
        s = 1.0 - s
        a0, a1 = a1, a0
    s = s * s
    return a0 * (1.0 - s) + a1 * s


@njit(cache=True, inline="always")
def scurve3(a):
    return a * a * (3.0 - 2.0 * a)


@njit(cache=True)
def select(a, b, c, lower, upper, falloff):
    """libnoise Select: ``b`` where ``lower <= c <= upper``, else ``a``; edges blended with
    an s-curve over ``falloff`` (at most half the band)."""
    f = min(falloff, (upper - lower) / 2.0)
    if f > 0.0:
        if c < lower - f:
            return a
        if c < lower + f:
            t = scurve3((c - (lower - f)) / (2.0 * f))
            return a + t * (b - a)
        if c < upper - f:
            return b
        if c < upper + f:
            t = scurve3((c - (upper - f)) / (2.0 * f))
            return b + t * (a - b)
        return a
    if c < lower or c > upper:
        return a
    return b


@njit(cache=True, inline="always")
def exponent(v, e):
    return math.pow(abs((v + 1.0) / 2.0), e) * 2.0 - 1.0


@njit(cache=True, inline="always")
def smoothstep(v):
    s = min(max(v, 0.0), 1.0)
    return s * s * (3.0 - 2.0 * s)


@njit(cache=True)
def gradient(v, vmin, vmax, pos, cols, ch):
    """Channel ``ch`` of the piecewise-linear map ``pos -> cols`` at ``(v - vmin) / (vmax -
    vmin)`` clipped to [0, 1] (NaN maps to 0), as :class:`~sylva.texture.Colormap`."""
    t = (v - vmin) / (vmax - vmin) if vmax > vmin else 0.0
    if t != t:
        t = 0.0
    t = min(max(t, 0.0), 1.0)
    n = pos.shape[0]
    if t <= pos[0]:
        return cols[0, ch]
    for k in range(1, n):
        if t <= pos[k]:
            p0 = pos[k - 1]
            p1 = pos[k]
            if p1 == p0:
                return cols[k, ch]
            return cols[k - 1, ch] + (t - p0) / (p1 - p0) * (cols[k, ch] - cols[k - 1, ch])
    return cols[n - 1, ch]


@njit(cache=True)
def blend(mode, a, b):
    """Mystica's blend mode ``mode`` (see :data:`BLEND`) of base ``a`` and top ``b``."""
    if mode == 0:
        return b
    if mode == 1:
        return a * b
    if mode == 2:
        return 1.0 - (1.0 - a) * (1.0 - b)
    if mode == 3:
        return 2.0 * a * b if a < 0.5 else 1.0 - 2.0 * (1.0 - a) * (1.0 - b)
    if mode == 4:
        return abs(a - b)
    if mode == 5:
        return min(a + b, 1.0)
    if mode == 6:
        return max(a - b, 0.0)
    if mode == 7:
        return min(a, b)
    if mode == 8:
        return max(a, b)
    if mode == 9:
        return 2.0 * a * b if b < 0.5 else 1.0 - 2.0 * (1.0 - a) * (1.0 - b)
    return (1.0 - 2.0 * b) * a * a + 2.0 * b * a
